/*
 * bench_est.c - benchmark cases of the onboard estimator (grip_est.h).
 * Integer-only in the fixed build: every input is a compile-time RC()
 * constant.
 *
 *   est_step_worst   one grip_est_step on the worst-case path: observer
 *                    active, excitation (mu adapts), all three measurement
 *                    updates (yaw rate, ay, ax: the vehicle-speed input is
 *                    valid, which the ax update needs), four tire
 *                    evaluations, braking in a turn with every input valid;
 *                    stiff_est = 1, kx_est = 1 and roll_est = 1 (rear-wheel
 *                    drive; their gates run, their updates do not: braking,
 *                    at the limit)
 *   est_step_learn   one step where the cornering stiffness learns
 *                    (stiff_est = 1, kx_est = 1, a steady turn at 20 m/s, ay
 *                    3 m/s^2, no braking): the stiffness update instead of
 *                    the ax update
 *   est_step_learn_kx one step where the longitudinal slip stiffness learns
 *                    (the same configuration, straight ahead at 20 m/s,
 *                    traction at 1.5 m/s^2, the rear wheels 2 % fast): its
 *                    update
 *   est_step_learn_roll the est_step_learn turn where the roll gradient
 *                    updates as well: its band-pass started with a 3 m/s^2
 *                    step of vx r, its weave gate held open by the case
 *                    (a turn is no weave), so that both learners update
 *   est_step_low     one step at standstill (observer off, no tire calls)
 *
 * Each case is a step of a running estimator (state kept between calls);
 * bench_est_setup() initializes it and drives it into the case's regime.
 * The lead wires bench_est_cases[] into the bench table and calls
 * bench_est_setup() from bench_cases_setup().
 */
#include <string.h>

#include "bench_cases.h"
#include "grip/grip_est.h"
#include "arith.h"
#include "mf_params.h"

extern const bench_case bench_est_cases[];
extern const int bench_est_case_count;
/* a steady left turn at 20 m/s, ay ~3 m/s^2, the steering weaving a little
 * (the regression's excitation) */
static void learn_input(grip_input_sample_t *s, int i)
{
    static const grip_real_t swa[4] = { RC(0.30), RC(0.31), RC(0.32), RC(0.31) };
    static const grip_real_t yaw[4] = { RC(0.148), RC(0.150), RC(0.152), RC(0.150) };
    int k;
    memset(s, 0, sizeof *s);
    s->value[GRIP_IN_WHEEL_SPEED_FL] = RC(19.8);
    s->value[GRIP_IN_WHEEL_SPEED_FR] = RC(20.2);
    s->value[GRIP_IN_WHEEL_SPEED_RL] = RC(19.8);
    s->value[GRIP_IN_WHEEL_SPEED_RR] = RC(20.2);
    s->value[GRIP_IN_STEER_ANGLE] = swa[i & 3];
    s->value[GRIP_IN_YAW_RATE] = yaw[i & 3];
    s->value[GRIP_IN_AX] = RC(0.0);
    s->value[GRIP_IN_AY] = RC(3.0);
    for (k = 0; k <= GRIP_IN_AY; ++k) {
        s->valid[k] = 1;
    }
}

/* straight ahead at 20 m/s in traction, ax 1.5 m/s^2, the driven rear
 * wheels 2 % faster than the front ones, the steering weaving a little */
static void learn_kx_input(grip_input_sample_t *s, int i)
{
    static const grip_real_t swa[4] = { RC(0.00), RC(0.01), RC(0.02), RC(0.01) };
    static const grip_real_t wsr[4] = { RC(20.40), RC(20.41), RC(20.40), RC(20.39) };
    int k;
    memset(s, 0, sizeof *s);
    s->value[GRIP_IN_WHEEL_SPEED_FL] = RC(20.0);
    s->value[GRIP_IN_WHEEL_SPEED_FR] = RC(20.0);
    s->value[GRIP_IN_WHEEL_SPEED_RL] = wsr[i & 3];
    s->value[GRIP_IN_WHEEL_SPEED_RR] = wsr[(i + 1) & 3];
    s->value[GRIP_IN_STEER_ANGLE] = swa[i & 3];
    s->value[GRIP_IN_YAW_RATE] = RC(0.0);
    s->value[GRIP_IN_AX] = RC(1.5);
    s->value[GRIP_IN_AY] = RC(0.0);
    for (k = 0; k <= GRIP_IN_AY; ++k) {
        s->valid[k] = 1;
    }
}

void bench_est_setup(void);

static grip_est_t est_worst;
static grip_est_t est_learn;
static grip_est_t est_learn_kx;
static grip_est_t est_learn_roll;
static grip_est_t est_low;
static grip_input_sample_t in_worst[BENCH_INPUTS];
static grip_input_sample_t in_learn[BENCH_INPUTS];
static grip_input_sample_t in_learn_kx[BENCH_INPUTS];
static grip_input_sample_t in_low;
static volatile uint32_t est_sink;

static const grip_mf_params *est_tire(void)
{
    const grip_mf_params *p = grip_test_tire_params("PacejkaBook_Defaults");
    return (p != 0) ? p : grip_test_tires[0].params;
}

/* braking in a left turn at 19.5 m/s: ay 6..7.5, ax -3 m/s^2, wheels ~10 % slow */
static void worst_input(grip_input_sample_t *s, int i)
{
    static const grip_real_t swa[4] = { RC(1.2), RC(1.5), RC(1.8), RC(2.1) };
    static const grip_real_t ay[4] = { RC(6.0), RC(6.5), RC(7.0), RC(7.5) };
    int k;
    memset(s, 0, sizeof *s);
    s->value[GRIP_IN_WHEEL_SPEED_FL] = RC(17.3);
    s->value[GRIP_IN_WHEEL_SPEED_FR] = RC(18.3);
    s->value[GRIP_IN_WHEEL_SPEED_RL] = RC(17.5);
    s->value[GRIP_IN_WHEEL_SPEED_RR] = RC(18.5);
    s->value[GRIP_IN_STEER_ANGLE] = swa[i & 3];
    s->value[GRIP_IN_YAW_RATE] = RC(0.33);
    s->value[GRIP_IN_AX] = RC(-3.0);
    s->value[GRIP_IN_AY] = ay[(i >> 2) & 3];
    s->value[GRIP_IN_VEHICLE_SPEED] = RC(19.5);   /* enables the ax update */
    for (k = 0; k <= GRIP_IN_VEHICLE_SPEED; ++k) {
        s->valid[k] = 1;
    }
}

void bench_est_setup(void)
{
    grip_est_config_t cfg;
    grip_est_output_t out;
    int i, k;
    (void)grip_est_config_default(&cfg, est_tire());
    (void)grip_est_init(&est_low, &cfg);
    cfg.stiff_est = 1u;
    cfg.kx_est = 1u;
    cfg.roll_est = 1u;
    cfg.drive_front = R_ZERO;
    (void)grip_est_init(&est_worst, &cfg);
    (void)grip_est_init(&est_learn, &cfg);
    (void)grip_est_init(&est_learn_roll, &cfg);
    (void)grip_est_init(&est_learn_kx, &cfg);
    for (i = 0; i < BENCH_INPUTS; ++i) {
        worst_input(&in_worst[i], i);
        learn_input(&in_learn[i], i);
        learn_kx_input(&in_learn_kx[i], i);
    }
    for (k = 0; k < 60; ++k) {
        (void)grip_est_step(&est_worst, &in_worst[k % BENCH_INPUTS], &out);
    }
    for (k = 0; k < 100; ++k) {
        (void)grip_est_step(&est_learn, &in_learn[k % BENCH_INPUTS], &out);
        (void)grip_est_step(&est_learn_kx, &in_learn_kx[k % BENCH_INPUTS], &out);
        (void)grip_est_step(&est_learn_roll, &in_learn[k % BENCH_INPUTS], &out);
    }
    /* the roll gradient's band-pass as after a 3 m/s^2 step of vx r: |bp|
     * stays above EST_RG_H_MIN for seconds */
    est_learn_roll.rg_m[0] = R_ZERO;
    est_learn_roll.rg_m[1] = R_ZERO;
    est_learn_roll.rg_n = est_learn_roll.rg_n_min; /* ... and settled */
    memset(&in_low, 0, sizeof in_low);
    for (k = 0; k < 8; ++k) {
        in_low.valid[k] = 1;
    }
    for (k = 0; k < 10; ++k) {
        (void)grip_est_step(&est_low, &in_low, &out);
    }
}

static int64_t est_clock_us = 1000000;

static void b_est_worst(int i)
{
    grip_est_output_t out;
    /* sample times 10 ms apart, as a CAN sampler gives them: the step's
     * rate check runs (t_us 0 would skip it) */
    est_clock_us += 10000;
    in_worst[i].t_us = est_clock_us;
    (void)grip_est_step(&est_worst, &in_worst[i], &out);
    est_sink = out.valid ^ out.flags;
}

static void b_est_learn(int i)
{
    grip_est_output_t out;
    (void)grip_est_step(&est_learn, &in_learn[i], &out);
    est_sink = out.valid ^ out.flags ^ est_learn.stf_updates;
}

static void b_est_learn_kx(int i)
{
    grip_est_output_t out;
    (void)grip_est_step(&est_learn_kx, &in_learn_kx[i], &out);
    est_sink = out.valid ^ out.flags ^ est_learn_kx.kx_updates;
}

static void b_est_learn_roll(int i)
{
    grip_est_output_t out;
    est_learn_roll.rg_pos = 0; /* the weave gate held open */
    est_learn_roll.rg_neg = 0;
    (void)grip_est_step(&est_learn_roll, &in_learn[i], &out);
    est_sink = out.valid ^ out.flags ^ est_learn_roll.stf_updates ^ est_learn_roll.rg_updates;
}

static void b_est_low(int i)
{
    grip_est_output_t out;
    (void)i;
    (void)grip_est_step(&est_low, &in_low, &out);
    est_sink = out.valid ^ out.flags;
}

const bench_case bench_est_cases[] = {
    { "est_step_worst", b_est_worst },
    { "est_step_learn", b_est_learn },
    { "est_step_learn_kx", b_est_learn_kx },
    { "est_step_learn_roll", b_est_learn_roll },
    { "est_step_low", b_est_low },
};
const int bench_est_case_count = (int)(sizeof(bench_est_cases) / sizeof(bench_est_cases[0]));
