/*
 * test_calib.c - the sensor calibration stage (lib/calib) against the
 * float64 reference tools/grip_tools/reference/calib.py (build/golden/calib.txt,
 * golden/calib.py), plus configuration checks, NULL / state errors,
 * non-finite inputs, in-place use, pass-through and age.
 *
 * Tolerances (docs/calibration.md):
 *   valid mask: identical on every row (both builds).
 *   float: |err| <= 1e-6 + 4e-7 |want|: the raw value rounded to float
 *          (2^-24 relative), then one subtraction and one multiplication
 *          (2^-24 each), about 3 x 6e-8 of the magnitudes involved, with a
 *          factor 2 for gains up to 2 (measured: 3.9e-6 abs, 1.0e-6 rel).
 *   fixed: bit-exact to the reference's Q15.16 model (calib_ref.correct with
 *          q=True: r_sub, then r_mul rounding half up), 0 LSB.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_calib.h"
#include "golden.h"

#if GRIP_ARITH_FIXED
static grip_real_t to_qs(double x) { return (grip_real_t)llround(x * 65536.0); }
static double from_qs(grip_real_t v) { return (double)v / 65536.0; }
#else
static grip_real_t to_qs(double x) { return (grip_real_t)x; }
static double from_qs(grip_real_t v) { return (double)v; }
#endif

#define N GRIP_CALIB_N

static void test_golden(void **state)
{
    golden_file g;
    grip_calib_config_t cfg;
    grip_calib_t c;
    grip_input_sample_t in, out;
    err_stats e;
    long rows = 0, mask_diff = 0, exact_diff = 0, tol_fail = 0;
    int n, i;
    (void)state;
    assert_int_equal(golden_open(&g, "calib.txt"), 0);
    n = golden_next(&g);
    assert_int_equal(n, 3 * N);
    for (i = 0; i < N; ++i) {
        cfg.offset[i] = to_qs(golden_num(&g, i));
        cfg.gain[i] = to_qs(golden_num(&g, N + i));
        cfg.delay[i] = (uint32_t)golden_num(&g, 2 * N + i);
    }
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_OK);
    err_init(&e, "calibrated value", 0.01);
    memset(&in, 0, sizeof in);
    while ((n = golden_next(&g)) > 0) {
        unsigned long m_in, m_out;
        assert_int_equal(n, 1 + N + 1 + N + 1 + N);
        in.t_us = (int64_t)golden_num(&g, 0);
        m_in = (unsigned long)golden_num(&g, 1 + N);
        m_out = (unsigned long)golden_num(&g, 2 + 2 * N);
        for (i = 0; i < N; ++i) {
            in.value[i] = to_qs(golden_num(&g, 1 + i));
            in.valid[i] = (uint8_t)((m_in >> i) & 1u);
            in.fault[i] = in.valid[i] ? GRIP_SIG_OK : GRIP_SIG_MISSING;
        }
        assert_int_equal(grip_calib_apply(&c, &in, &out), GRIP_OK);
        for (i = 0; i < N; ++i) {
            double want = golden_num(&g, 2 + N + i);
            double got = from_qs(out.value[i]);
            if (out.valid[i] != (uint8_t)((m_out >> i) & 1u)) {
                mask_diff += 1;
            }
            if (!out.valid[i]) {
                assert_true(out.value[i] == 0);
                assert_int_not_equal(out.fault[i], GRIP_SIG_OK);
                continue;
            }
            err_add(&e, got, want, (double)in.t_us * 1e-6, i, 0);
#if GRIP_ARITH_FIXED
            if ((double)out.value[i] != golden_num(&g, 3 + 2 * N + i)) {
                exact_diff += 1;
            }
#else
            if (fabs(got - want) > 1e-6 + 4e-7 * fabs(want)) {
                tol_fail += 1;
            }
#endif
        }
        rows += 1;
    }
    golden_close(&g);
    printf("# calib.txt (%s build): %ld rows, valid mask differs on %ld values, "
           "fixed values not bit-exact: %ld, beyond float tolerance: %ld\n",
           GRIP_ARITH_NAME, rows, mask_diff, exact_diff, tol_fail);
    err_print(&e, "SI");
    assert_true(rows == 600);
    assert_int_equal(mask_diff, 0);
    assert_int_equal(exact_diff, 0);
    assert_int_equal(tol_fail, 0);
}

static void test_config_checks(void **state)
{
    grip_calib_config_t cfg;
    grip_calib_t c;
    grip_input_sample_t s;
    (void)state;
    assert_int_equal(grip_calib_config_identity(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    assert_int_equal(grip_calib_init(NULL, &cfg), GRIP_ERR_NULL);
    assert_int_equal(grip_calib_init(&c, NULL), GRIP_ERR_NULL);
    cfg.offset[5] = to_qs(10.5);
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
    /* unusable after a failed init */
    assert_int_equal(grip_input_sample_clear(&s), GRIP_OK);
    s.valid[5] = 1;
    s.value[5] = to_qs(0.1);
    assert_int_equal(grip_calib_apply(&c, &s, &s), GRIP_ERR_STATE);
    assert_int_equal(s.valid[5], 0);
    assert_true(s.value[5] == 0);
    assert_int_equal(grip_calib_reset(&c), GRIP_ERR_STATE);
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    cfg.gain[0] = to_qs(0.4);
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
    cfg.gain[0] = to_qs(2.5);
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    cfg.delay[8] = GRIP_CALIB_DELAY_MAX + 1u;
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
    cfg.delay[8] = GRIP_CALIB_DELAY_MAX;
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_OK);
#if !GRIP_ARITH_FIXED
    cfg.offset[1] = NAN;
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
    cfg.offset[1] = 0.0f;
    cfg.gain[2] = INFINITY;
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_ERR_PARAM);
#endif
    assert_int_equal(grip_calib_apply(NULL, &s, &s), GRIP_ERR_NULL);
    assert_int_equal(grip_calib_apply(&c, NULL, &s), GRIP_ERR_NULL);
    assert_int_equal(grip_calib_apply(&c, &s, NULL), GRIP_ERR_NULL);
}

/* identity: output == input bit for bit; brake inputs pass through; in place */
static void test_identity_passthrough_inplace(void **state)
{
    grip_calib_config_t cfg;
    grip_calib_t c;
    grip_input_sample_t s, o;
    int i, k;
    (void)state;
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_OK);
    for (k = 0; k < 50; ++k) {
        assert_int_equal(grip_input_sample_clear(&s), GRIP_OK);
        s.t_us = (int64_t)k * 10000;
        s.step = (uint32_t)k;
        for (i = 0; i < GRIP_IN_COUNT; ++i) {
            s.valid[i] = (uint8_t)(((k + i) % 7) != 0);
            s.fault[i] = s.valid[i] ? GRIP_SIG_OK : GRIP_SIG_STALE;
            s.value[i] = s.valid[i] ? to_qs(0.37 * (double)(i + 1) - 0.01 * k) : 0;
            s.age_us[i] = (uint32_t)(100 * i);
        }
        assert_int_equal(grip_calib_apply(&c, &s, &o), GRIP_OK);
        assert_memory_equal(&s, &o, sizeof s);
        o = s;
        assert_int_equal(grip_calib_apply(&c, &o, &o), GRIP_OK);   /* in place (second push) */
        for (i = N; i < GRIP_IN_COUNT; ++i) {
            assert_true(o.value[i] == s.value[i]);
            assert_int_equal(o.valid[i], s.valid[i]);
        }
    }
}

/* delay: value, validity and fault come from d steps ago; the age grows by
 * the time since; invalid (missing) until d earlier samples exist */
static void test_delay_age(void **state)
{
    grip_calib_config_t cfg;
    grip_calib_t c;
    grip_input_sample_t s, o;
    int k;
    const int d = 4;
    (void)state;
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    cfg.delay[GRIP_IN_YAW_RATE] = (uint32_t)d;
    cfg.offset[GRIP_IN_YAW_RATE] = to_qs(0.5);
    cfg.gain[GRIP_IN_YAW_RATE] = to_qs(2.0);
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_OK);
    for (k = 0; k < 40; ++k) {
        assert_int_equal(grip_input_sample_clear(&s), GRIP_OK);
        s.t_us = 1000000 + (int64_t)k * 10000;
        s.valid[GRIP_IN_YAW_RATE] = (uint8_t)(k != 20);
        s.fault[GRIP_IN_YAW_RATE] = (k != 20) ? GRIP_SIG_OK : GRIP_SIG_FAULT;
        s.value[GRIP_IN_YAW_RATE] = (k != 20) ? to_qs(0.01 * k) : 0;
        s.age_us[GRIP_IN_YAW_RATE] = 300u;
        assert_int_equal(grip_calib_apply(&c, &s, &o), GRIP_OK);
        if (k < d) {
            assert_int_equal(o.valid[GRIP_IN_YAW_RATE], 0);
            assert_int_equal(o.fault[GRIP_IN_YAW_RATE], GRIP_SIG_MISSING);
        } else if (k - d == 20) {
            assert_int_equal(o.valid[GRIP_IN_YAW_RATE], 0);
            assert_int_equal(o.fault[GRIP_IN_YAW_RATE], GRIP_SIG_FAULT);
            assert_true(o.value[GRIP_IN_YAW_RATE] == 0);
        } else {
            double want = (0.01 * (k - d) - 0.5) * 2.0;
            assert_int_equal(o.valid[GRIP_IN_YAW_RATE], 1);
            assert_true(fabs(from_qs(o.value[GRIP_IN_YAW_RATE]) - want) < 1e-4);
            assert_int_equal(o.age_us[GRIP_IN_YAW_RATE], 300u + (uint32_t)d * 10000u);
        }
    }
    /* reset empties the ring */
    assert_int_equal(grip_calib_reset(&c), GRIP_OK);
    assert_int_equal(grip_calib_apply(&c, &s, &o), GRIP_OK);
    assert_int_equal(o.valid[GRIP_IN_YAW_RATE], 0);
}

#if !GRIP_ARITH_FIXED
/* a valid but non-finite value, or one whose correction overflows, becomes
 * invalid with GRIP_SIG_RANGE: never NaN / Inf out */
static void test_non_finite(void **state)
{
    grip_calib_config_t cfg;
    grip_calib_t c;
    grip_input_sample_t s, o;
    int i;
    (void)state;
    assert_int_equal(grip_calib_config_identity(&cfg), GRIP_OK);
    cfg.gain[GRIP_IN_AY] = 2.0f;
    assert_int_equal(grip_calib_init(&c, &cfg), GRIP_OK);
    assert_int_equal(grip_input_sample_clear(&s), GRIP_OK);
    for (i = 0; i < N; ++i) {
        s.valid[i] = 1;
        s.fault[i] = GRIP_SIG_OK;
        s.value[i] = 1.0f;
    }
    s.value[GRIP_IN_YAW_RATE] = NAN;
    s.value[GRIP_IN_AX] = -INFINITY;
    s.value[GRIP_IN_AY] = 3.0e38f;      /* x 2 overflows */
    assert_int_equal(grip_calib_apply(&c, &s, &o), GRIP_OK);
    for (i = 0; i < N; ++i) {
        assert_true(isfinite(o.value[i]));
    }
    assert_int_equal(o.valid[GRIP_IN_YAW_RATE], 0);
    assert_int_equal(o.fault[GRIP_IN_YAW_RATE], GRIP_SIG_RANGE);
    assert_int_equal(o.valid[GRIP_IN_AX], 0);
    assert_int_equal(o.valid[GRIP_IN_AY], 0);
    assert_int_equal(o.fault[GRIP_IN_AY], GRIP_SIG_RANGE);
    assert_int_equal(o.valid[GRIP_IN_STEER_ANGLE], 1);
    /* uncalibrated pass-through inputs: a valid non-finite value leaves
     * invalid (found by fuzz_chain), a finite one unchanged */
    s.valid[GRIP_IN_BRAKE_TORQUE_FL] = 1;
    s.value[GRIP_IN_BRAKE_TORQUE_FL] = NAN;
    s.valid[GRIP_IN_BRAKE_PRESSURE_RR] = 1;
    s.value[GRIP_IN_BRAKE_PRESSURE_RR] = 2.5e6f;
    assert_int_equal(grip_calib_apply(&c, &s, &o), GRIP_OK);
    assert_int_equal(o.valid[GRIP_IN_BRAKE_TORQUE_FL], 0);
    assert_int_equal(o.fault[GRIP_IN_BRAKE_TORQUE_FL], GRIP_SIG_RANGE);
    assert_true(o.value[GRIP_IN_BRAKE_TORQUE_FL] == 0.0f);
    assert_int_equal(o.valid[GRIP_IN_BRAKE_PRESSURE_RR], 1);
    assert_true(o.value[GRIP_IN_BRAKE_PRESSURE_RR] == 2.5e6f);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden),
        cmocka_unit_test(test_config_checks),
        cmocka_unit_test(test_identity_passthrough_inplace),
        cmocka_unit_test(test_delay_age),
#if !GRIP_ARITH_FIXED
        cmocka_unit_test(test_non_finite),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
