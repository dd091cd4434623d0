/*
 * driver.c - the estimator chain of grip_monitor.h in plain C, for
 * tests/python/binding/test_est.py: built there against
 * build/<variant>/libgrip.a and libgrip_port.a (the Makefile's library), it
 * runs the same samples as the Python binding and prints every output
 * field as the bits the library wrote, so the two are compared exactly.
 * Not part of the library.
 *
 *   driver TIR RATE_HZ USE_CALIB USE_MONITOR DRIVEN HONOUR < in > out
 *
 * in:  line 1: the calibration configuration, 27 numbers: offset[9],
 *      gain[9] (the build's grip_real_t as integers: float bits or Q
 *      value), delay[9];
 *      then one line per sample: t_us step value[17] (as integers, as
 *      above) valid[17] fault[17] age_us[17].
 * out: one line per sample: the statuses (calib, monitor, estimator), the
 *      sample after calibration and monitor (value, valid, fault, age_us),
 *      the monitor's report, the estimator's output, the gated valid and
 *      flags; grip_real_t as integers (float: its bits).
 * Per sample, as grip_monitor.h documents:
 *   calib -> monitor (est_prev: the estimator's previous output; none at
 *   the first sample) -> estimator -> gate of a copy.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_calib.h"
#include "grip/grip_est.h"
#include "grip/grip_monitor.h"
#include "tir_reader.h"

static int64_t bits(grip_real_t v)
{
#if GRIP_ARITH_FIXED
    return (int64_t)v;
#else
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return (int64_t)u;
#endif
}

static grip_real_t from_bits(long long x)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)x;
#else
    uint32_t u = (uint32_t)x;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
#endif
}

static void pr(grip_real_t v)
{
    printf(" %" PRId64, bits(v));
}

static void pr_arr(const grip_real_t *v, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        pr(v[i]);
    }
}

int main(int argc, char **argv)
{
    static grip_mf_params tire;
    static grip_est_t est;
    static grip_monitor_t mon;
    static grip_calib_t cal;
    grip_est_config_t ecfg;
    grip_monitor_config_t mcfg;
    grip_calib_config_t ccfg;
    grip_est_output_t last;
    int have_last = 0;
    char err[512];
    int use_cal, use_mon;
    uint32_t honour;
    int i;
    long long x;

    if (argc != 7) {
        fprintf(stderr, "usage: driver TIR RATE_HZ USE_CALIB USE_MONITOR DRIVEN HONOUR < in\n");
        return 2;
    }
    if (grip_tir_read(argv[1], &tire, err, sizeof err) != 0) {
        fprintf(stderr, "driver: %s\n", err);
        return 3;
    }
    use_cal = atoi(argv[3]);
    use_mon = atoi(argv[4]);
    honour = (uint32_t)strtoul(argv[6], NULL, 10);
    if (grip_est_config_default(&ecfg, &tire) != GRIP_OK) {
        return 3;
    }
    ecfg.rate_hz = (uint32_t)atoi(argv[2]);
    if (grip_est_init(&est, &ecfg) != GRIP_OK) {
        fprintf(stderr, "driver: grip_est_init failed\n");
        return 3;
    }
    if (grip_monitor_config_default(&mcfg) != GRIP_OK ||
        grip_monitor_config_from_est(&mcfg, &est, (uint32_t)atoi(argv[5])) != GRIP_OK ||
        grip_monitor_init(&mon, &mcfg) != GRIP_OK) {
        fprintf(stderr, "driver: the monitor's configuration failed\n");
        return 3;
    }
    memset(&ccfg, 0, sizeof ccfg);
    for (i = 0; i < 27; i++) {
        if (scanf("%lld", &x) != 1) {
            fprintf(stderr, "driver: calibration line\n");
            return 4;
        }
        if (i < 9) {
            ccfg.offset[i] = from_bits(x);
        } else if (i < 18) {
            ccfg.gain[i - 9] = from_bits(x);
        } else {
            ccfg.delay[i - 18] = (uint32_t)x;
        }
    }
    if (grip_calib_init(&cal, &ccfg) != GRIP_OK) {
        fprintf(stderr, "driver: grip_calib_init failed\n");
        return 3;
    }
    memset(&last, 0, sizeof last);
    for (;;) {
        grip_input_sample_t in;
        grip_input_sample_t s;
        grip_monitor_report_t rep;
        grip_est_output_t use;
        grip_status_t st_cal = GRIP_OK;
        grip_status_t st_mon = GRIP_OK;
        grip_status_t st_est;
        long long t;
        unsigned long long step;
        memset(&in, 0, sizeof in);
        memset(&rep, 0, sizeof rep);
        if (scanf("%lld %llu", &t, &step) != 2) {
            break;
        }
        in.t_us = (int64_t)t;
        in.step = (uint32_t)step;
        for (i = 0; i < 4 * GRIP_IN_COUNT; i++) {
            if (scanf("%lld", &x) != 1) {
                fprintf(stderr, "driver: short sample line\n");
                return 4;
            }
            if (i < GRIP_IN_COUNT) {
                in.value[i] = from_bits(x);
            } else if (i < 2 * GRIP_IN_COUNT) {
                in.valid[i - GRIP_IN_COUNT] = (uint8_t)x;
            } else if (i < 3 * GRIP_IN_COUNT) {
                in.fault[i - 2 * GRIP_IN_COUNT] = (uint8_t)x;
            } else {
                in.age_us[i - 3 * GRIP_IN_COUNT] = (uint32_t)x;
            }
        }
        s = in;
        if (use_cal) {
            st_cal = grip_calib_apply(&cal, &in, &s);
        }
        if (use_mon) {
            st_mon = grip_monitor_step(&mon, &s, have_last ? &last : NULL, &rep);
        }
        st_est = grip_est_step(&est, &s, &last);
        have_last = 1;
        use = last;
        if (use_mon) {
            (void)grip_monitor_gate(&rep, honour, &use);
        }
        printf("%d %d %d", (int)st_cal, (int)st_mon, (int)st_est);
        pr_arr(s.value, GRIP_IN_COUNT);
        for (i = 0; i < GRIP_IN_COUNT; i++) {
            printf(" %u", (unsigned)s.valid[i]);
        }
        for (i = 0; i < GRIP_IN_COUNT; i++) {
            printf(" %u", (unsigned)s.fault[i]);
        }
        for (i = 0; i < GRIP_IN_COUNT; i++) {
            printf(" %" PRIu32, s.age_us[i]);
        }
        for (i = 0; i < GRIP_MON_N; i++) {
            printf(" %u", (unsigned)rep.code[i]);
        }
        pr_arr(rep.resid, GRIP_MON_N);
        printf(" %" PRIu32 " %" PRIu32 " %d %" PRIu32, rep.faulty, rep.dropped, (int)rep.detected, rep.degraded);
        pr(last.vx);
        pr(last.vy);
        pr(last.beta);
        pr(last.yaw_rate);
        pr(last.yaw_rate_ref);
        pr(last.yaw_error);
        pr(last.delta);
        pr_arr(last.kappa, 4);
        pr_arr(last.alpha, 4);
        pr_arr(last.fz, 4);
        pr_arr(last.fx, 4);
        pr_arr(last.fy, 4);
        pr_arr(last.mz, 4);
        pr_arr(last.util, 4);
        pr_arr(last.fy_axle, 2);
        pr_arr(last.util_axle, 2);
        pr(last.mu);
        pr(last.mu_conf);
        pr(last.yaw_rate_bias);
        pr(last.fy_margin_front);
        printf(" %d %" PRIu32 " %" PRIu32 " %" PRIu32 " %" PRIu32 "\n", (int)last.steer_char, last.valid, last.flags,
               use.valid, use.flags);
    }
    return 0;
}
