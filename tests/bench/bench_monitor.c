/*
 * bench_monitor.c - benchmark case of the sensor-plausibility monitor
 * (grip_monitor.h). Integer-only in the fixed build: every input is a
 * compile-time RC() constant.
 *
 *   monitor_step   one grip_monitor_step on the path that runs every
 *                  check: moving at 22 m/s in a steady left turn (ay 1.8),
 *                  every ESC input valid, the estimator's previous output
 *                  given, the yaw rate and ax steady for longer than 0.5 s
 *                  (the model checks ay, ax and steering run), 16 input
 *                  sets with small variations
 *
 * The state is kept between calls; bench_monitor_setup() initializes the
 * monitor and drives it into that regime. Each call works on a copy of the
 * input sample (the monitor edits the sample in place).
 */
#include <string.h>

#include "bench_cases.h"
#include "grip/grip_monitor.h"
#include "arith.h"

extern const bench_case bench_monitor_cases[];
extern const int bench_monitor_case_count;
void bench_monitor_setup(void);

static grip_monitor_t mon;
static grip_input_sample_t mon_in[BENCH_INPUTS];
static grip_est_output_t mon_est;
static volatile uint32_t mon_sink;

/* steady left turn at 22 m/s, r = 0.08 rad/s, ay = r vx = 1.76 (below the
 * steering check's 2 m/s^2, so every check runs) */
static void mon_input(grip_input_sample_t *s, int i)
{
    static const grip_real_t dv[4] = { RC(0.0), RC(0.01), RC(-0.01), RC(0.02) };
    static const grip_real_t da[4] = { RC(0.0), RC(0.02), RC(-0.02), RC(0.01) };
    memset(s, 0, sizeof *s);
    s->value[GRIP_IN_WHEEL_SPEED_FL] = r_add(RC(21.938), dv[i & 3]);
    s->value[GRIP_IN_WHEEL_SPEED_FR] = r_add(RC(22.062), dv[(i + 1) & 3]);
    s->value[GRIP_IN_WHEEL_SPEED_RL] = r_add(RC(21.939), dv[(i + 2) & 3]);
    s->value[GRIP_IN_WHEEL_SPEED_RR] = r_add(RC(22.061), dv[(i + 3) & 3]);
    s->value[GRIP_IN_STEER_ANGLE] = r_add(RC(0.179), da[(i >> 2) & 3]);
    s->value[GRIP_IN_YAW_RATE] = r_add(RC(0.08), r_mul(RC(0.05), da[i & 3]));
    s->value[GRIP_IN_AX] = da[(i + 1) & 3];
    s->value[GRIP_IN_AY] = r_add(RC(1.91), da[(i + 2) & 3]);
    s->value[GRIP_IN_VEHICLE_SPEED] = RC(22.0);
    memset(s->valid, 1, (size_t)GRIP_IN_VEHICLE_SPEED + 1u);
}

void bench_monitor_setup(void)
{
    grip_monitor_config_t cfg;
    grip_input_sample_t s;
    int i, k;
    (void)grip_monitor_config_default(&cfg);
    (void)grip_monitor_init(&mon, &cfg);
    for (i = 0; i < BENCH_INPUTS; ++i) {
        mon_input(&mon_in[i], i);
    }
    memset(&mon_est, 0, sizeof mon_est);
    mon_est.vx = RC(22.0);
    mon_est.beta = RC(0.01);
    mon_est.valid = GRIP_EST_V_VX | GRIP_EST_V_BETA | GRIP_EST_V_STEER;
    for (k = 0; k < 120; ++k) {
        s = mon_in[k % BENCH_INPUTS];
        (void)grip_monitor_step(&mon, &s, &mon_est, 0);
    }
}

static void b_monitor_step(int i)
{
    grip_input_sample_t s = mon_in[i];
    grip_monitor_report_t rep;
    (void)grip_monitor_step(&mon, &s, &mon_est, &rep);
    mon_sink = rep.faulty ^ (uint32_t)rep.detected ^ rep.dropped;
}

const bench_case bench_monitor_cases[] = {
    { "monitor_step", b_monitor_step },
};
const int bench_monitor_case_count = (int)(sizeof(bench_monitor_cases) / sizeof(bench_monitor_cases[0]));
