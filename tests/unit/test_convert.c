/*
 * test_convert.c - the SI <-> QS/QL conversion helpers of grip_convert.h:
 * round to nearest (halfway away from zero, including the 0.5 - 2^-54 case
 * that "add 0.5 and truncate" gets wrong), both ends of both formats,
 * NaN and infinities, NULL, the float functions against the double ones on
 * a sweep of values, exact Q -> double, nearest Q -> float, and the
 * grip_real_t forms of this build. Runs in both builds.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_convert.h"

#define QS_LSB (1.0 / 65536.0)
#define QL_LSB (1.0 / 256.0)

typedef grip_status_t (*from_double_fn)(double, int32_t *);

static void expect_d(from_double_fn f, double si, int32_t want, grip_status_t want_st)
{
    int32_t q = 12345;
    grip_status_t st = f(si, &q);
    if (q != want || st != want_st) {
        fail_msg("%.17g: got %ld (status %d), want %ld (status %d)", si, (long)q, (int)st,
                 (long)want, (int)want_st);
    }
}

static void test_rounding(void **unused)
{
    (void)unused;
    expect_d(grip_qs_from_double, 0.0, 0, GRIP_OK);
    expect_d(grip_qs_from_double, -0.0, 0, GRIP_OK);
    expect_d(grip_qs_from_double, 1.0, 65536, GRIP_OK);
    expect_d(grip_qs_from_double, -1.0, -65536, GRIP_OK);
    expect_d(grip_qs_from_double, 0.1, 6554, GRIP_OK);      /* 6553.6 */
    expect_d(grip_qs_from_double, -0.1, -6554, GRIP_OK);
    expect_d(grip_qs_from_double, 0.3 * QS_LSB, 0, GRIP_OK);
    expect_d(grip_qs_from_double, 0.7 * QS_LSB, 1, GRIP_OK);
    /* halfway cases: away from zero, not to even */
    expect_d(grip_qs_from_double, 0.5 * QS_LSB, 1, GRIP_OK);
    expect_d(grip_qs_from_double, -0.5 * QS_LSB, -1, GRIP_OK);
    expect_d(grip_qs_from_double, 1.5 * QS_LSB, 2, GRIP_OK);
    expect_d(grip_qs_from_double, 2.5 * QS_LSB, 3, GRIP_OK);
    expect_d(grip_qs_from_double, -2.5 * QS_LSB, -3, GRIP_OK);
    expect_d(grip_ql_from_double, 2.5 * QL_LSB, 3, GRIP_OK);
    expect_d(grip_ql_from_double, -1000.5 * QL_LSB, -1001, GRIP_OK);
    /* just below one half: x + 0.5 rounds up to 1.0 in double, the
     * helpers must not */
    expect_d(grip_qs_from_double, 0.49999999999999994 * QS_LSB, 0, GRIP_OK);
    expect_d(grip_qs_from_double, -0.49999999999999994 * QS_LSB, 0, GRIP_OK);
    /* a large value with a fraction */
    expect_d(grip_qs_from_double, 12345.678, 809086353, GRIP_OK);   /* 809086353.41 */
    expect_d(grip_ql_from_double, 4000.0, 1024000, GRIP_OK);
    expect_d(grip_ql_from_double, -3871.2345, -991036, GRIP_OK);    /* -991036.03 */
    /* subnormal and tiny */
    expect_d(grip_qs_from_double, DBL_MIN, 0, GRIP_OK);
    expect_d(grip_qs_from_double, -4.9e-324, 0, GRIP_OK);
}

static void test_range_ends(void **unused)
{
    const double qs_max = (double)INT32_MAX * QS_LSB;   /* 32767.9999847 */
    const double ql_max = (double)INT32_MAX * QL_LSB;   /* 8388607.996 */
    (void)unused;
    /* the largest values that round into the format */
    expect_d(grip_qs_from_double, qs_max, INT32_MAX, GRIP_OK);
    expect_d(grip_qs_from_double, ((double)INT32_MAX + 0.49) * QS_LSB, INT32_MAX, GRIP_OK);
    expect_d(grip_qs_from_double, -qs_max, -INT32_MAX, GRIP_OK);
    expect_d(grip_qs_from_double, -((double)INT32_MAX + 0.49) * QS_LSB, -INT32_MAX, GRIP_OK);
    expect_d(grip_ql_from_double, ql_max, INT32_MAX, GRIP_OK);
    expect_d(grip_ql_from_double, -ql_max, -INT32_MAX, GRIP_OK);
    /* the smallest that do not: saturated, and said so */
    expect_d(grip_qs_from_double, ((double)INT32_MAX + 0.5) * QS_LSB, INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_qs_from_double, 32768.0, INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_qs_from_double, -((double)INT32_MAX + 0.5) * QS_LSB, -INT32_MAX, GRIP_WARN_CLAMPED);
    /* INT32_MIN is outside the symmetric range of grip_q16.h */
    expect_d(grip_qs_from_double, -32768.0, -INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_ql_from_double, 8388608.0, INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_ql_from_double, -8388608.0, -INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_ql_from_double, 1e9, INT32_MAX, GRIP_WARN_CLAMPED);
    /* scaling overflows to infinity: still a saturation, not an error */
    expect_d(grip_qs_from_double, DBL_MAX, INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_qs_from_double, -DBL_MAX, -INT32_MAX, GRIP_WARN_CLAMPED);
    expect_d(grip_ql_from_double, 1e300, INT32_MAX, GRIP_WARN_CLAMPED);
}

static void test_not_finite_and_null(void **unused)
{
    int32_t q = 7;
    (void)unused;
    expect_d(grip_qs_from_double, NAN, 0, GRIP_ERR_INPUT);
    expect_d(grip_qs_from_double, -NAN, 0, GRIP_ERR_INPUT);
    expect_d(grip_qs_from_double, INFINITY, 0, GRIP_ERR_INPUT);
    expect_d(grip_qs_from_double, -INFINITY, 0, GRIP_ERR_INPUT);
    expect_d(grip_ql_from_double, NAN, 0, GRIP_ERR_INPUT);
    expect_d(grip_ql_from_double, INFINITY, 0, GRIP_ERR_INPUT);
    expect_d(grip_ql_from_double, -INFINITY, 0, GRIP_ERR_INPUT);
    assert_int_equal(grip_qs_from_float(NAN, &q), GRIP_ERR_INPUT);
    assert_int_equal(q, 0);
    q = 7;
    assert_int_equal(grip_qs_from_float(INFINITY, &q), GRIP_ERR_INPUT);
    assert_int_equal(q, 0);
    q = 7;
    assert_int_equal(grip_ql_from_float(-INFINITY, &q), GRIP_ERR_INPUT);
    assert_int_equal(q, 0);
    assert_int_equal(grip_qs_from_double(1.0, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_ql_from_double(NAN, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_qs_from_float(1.0f, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_ql_from_float(1.0f, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_real_qs_from_si(1.0, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_real_ql_from_si(1.0, NULL), GRIP_ERR_NULL);
}

static void test_float_ends(void **unused)
{
    int32_t q;
    (void)unused;
    /* 32768 - 2^-9 is the largest float below 32768: 2^31 - 128 in QS */
    assert_int_equal(grip_qs_from_float(32767.998046875f, &q), GRIP_OK);
    assert_int_equal(q, 2147483520);
    assert_int_equal(grip_qs_from_float(32768.0f, &q), GRIP_WARN_CLAMPED);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(grip_qs_from_float(-32768.0f, &q), GRIP_WARN_CLAMPED);
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(grip_ql_from_float(8388608.0f, &q), GRIP_WARN_CLAMPED);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(grip_ql_from_float(-FLT_MAX, &q), GRIP_WARN_CLAMPED);
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(grip_qs_from_float(FLT_MAX, &q), GRIP_WARN_CLAMPED);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(grip_qs_from_float(2.5f / 65536.0f, &q), GRIP_OK);
    assert_int_equal(q, 3);
    assert_int_equal(grip_qs_from_float(-2.5f / 65536.0f, &q), GRIP_OK);
    assert_int_equal(q, -3);
    assert_int_equal(grip_qs_from_float(0.1f, &q), GRIP_OK);
    assert_int_equal(q, 6554);
    assert_int_equal(grip_qs_from_float(FLT_MIN, &q), GRIP_OK);
    assert_int_equal(q, 0);
}

/* xorshift32: a reproducible spread of bit patterns */
static uint32_t rng_state = 2463534242u;
static uint32_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

/* Every finite float, over all exponents: the single-precision path gives
 * exactly what the double path gives for the same value. */
static void test_float_matches_double(void **unused)
{
    long n = 0;
    (void)unused;
    for (long i = 0; i < 400000; i++) {
        uint32_t bits = rng();
        float f;
        int32_t qf, qd;
        grip_status_t sf, sd;
        memcpy(&f, &bits, sizeof f);
        if (!isfinite(f)) {
            continue;
        }
        sf = grip_qs_from_float(f, &qf);
        sd = grip_qs_from_double((double)f, &qd);
        if (qf != qd || sf != sd) {
            fail_msg("QS %.9g: float %ld/%d, double %ld/%d", (double)f, (long)qf, (int)sf,
                     (long)qd, (int)sd);
        }
        sf = grip_ql_from_float(f, &qf);
        sd = grip_ql_from_double((double)f, &qd);
        if (qf != qd || sf != sd) {
            fail_msg("QL %.9g: float %ld/%d, double %ld/%d", (double)f, (long)qf, (int)sf,
                     (long)qd, (int)sd);
        }
        n++;
    }
    /* and values near the format range, where the interesting floats are */
    for (long i = 0; i < 200000; i++) {
        float f = (float)((double)(int32_t)rng() * QS_LSB) * (float)((rng() & 1u) ? 1.0f : 1.00001f);
        int32_t qf, qd;
        grip_status_t sf = grip_qs_from_float(f, &qf);
        grip_status_t sd = grip_qs_from_double((double)f, &qd);
        if (qf != qd || sf != sd) {
            fail_msg("QS %.9g: float %ld/%d, double %ld/%d", (double)f, (long)qf, (int)sf,
                     (long)qd, (int)sd);
        }
        n++;
    }
    print_message("# float and double paths agree on %ld values\n", n);
}

static void test_to_si(void **unused)
{
    int32_t q;
    (void)unused;
    assert_true(grip_qs_to_double(65536) == 1.0);
    assert_true(grip_qs_to_double(1) == QS_LSB);
    assert_true(grip_qs_to_double(-INT32_MAX) == -(double)INT32_MAX * QS_LSB);
    assert_true(grip_ql_to_double(INT32_MAX) == (double)INT32_MAX * QL_LSB);
    assert_true(grip_ql_to_double(-256) == -1.0);
    assert_true(grip_qs_to_float(-98304) == -1.5f);
    assert_true(grip_ql_to_float(1) == 0.00390625f);
    /* 2^24 + 1 is not a float: the nearest is 2^24 (to even) */
    assert_true(grip_qs_to_float(16777217) == 256.0f);
    assert_true(grip_qs_to_float(INT32_MAX) == 32768.0f);
    /* round trips, and Q -> float is the nearest float to the exact value */
    for (long i = 0; i < 200000; i++) {
        int32_t v = (int32_t)rng();
        if (v == INT32_MIN) {
            continue;
        }
        assert_int_equal(grip_qs_from_double(grip_qs_to_double(v), &q), GRIP_OK);
        assert_int_equal(q, v);
        assert_int_equal(grip_ql_from_double(grip_ql_to_double(v), &q), GRIP_OK);
        assert_int_equal(q, v);
        assert_true(grip_qs_to_float(v) == (float)grip_qs_to_double(v));
        assert_true(grip_ql_to_float(v) == (float)grip_ql_to_double(v));
    }
}

/* The grip_real_t forms of this build. */
static void test_real_forms(void **unused)
{
    grip_real_t r;
    (void)unused;
    assert_int_equal(grip_real_qs_from_si(0.25, &r), GRIP_OK);
    assert_true(grip_real_qs_to_si(r) == 0.25);
    assert_int_equal(grip_real_ql_from_si(-4000.5, &r), GRIP_OK);
    assert_true(grip_real_ql_to_si(r) == -4000.5);
    assert_int_equal(grip_real_qs_from_si(NAN, &r), GRIP_ERR_INPUT);
    assert_true(grip_real_qs_to_si(r) == 0.0);
    assert_int_equal(grip_real_ql_from_si(-INFINITY, &r), GRIP_ERR_INPUT);
    assert_true(grip_real_ql_to_si(r) == 0.0);
#if GRIP_ARITH_FIXED
    assert_int_equal(grip_real_qs_from_si(0.1, &r), GRIP_OK);
    assert_int_equal(r, 6554);
    assert_int_equal(grip_real_qs_from_si(40000.0, &r), GRIP_WARN_CLAMPED);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(grip_real_ql_from_si(-1e7, &r), GRIP_WARN_CLAMPED);
    assert_int_equal(r, -INT32_MAX);
#else
    assert_int_equal(grip_real_qs_from_si(0.1, &r), GRIP_OK);
    assert_true(r == 0.1f);
    assert_int_equal(grip_real_qs_from_si(40000.0, &r), GRIP_OK);
    assert_true(r == 40000.0f);
    assert_int_equal(grip_real_ql_from_si(1e39, &r), GRIP_WARN_CLAMPED);
    assert_true(r == FLT_MAX);
    assert_int_equal(grip_real_ql_from_si(-1e39, &r), GRIP_WARN_CLAMPED);
    assert_true(r == -FLT_MAX);
    assert_int_equal(grip_real_qs_from_si((double)FLT_MAX, &r), GRIP_OK);
    assert_true(r == FLT_MAX);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rounding),
        cmocka_unit_test(test_range_ends),
        cmocka_unit_test(test_not_finite_and_null),
        cmocka_unit_test(test_float_ends),
        cmocka_unit_test(test_float_matches_double),
        cmocka_unit_test(test_to_si),
        cmocka_unit_test(test_real_forms),
    };
    return cmocka_run_group_tests_name("convert (" GRIP_ARITH_NAME ")", tests, NULL, NULL);
}
