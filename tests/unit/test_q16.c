/*
 * test_q16.c - every Q15.16 primitive against numpy float64 over its whole
 * int32 input domain (build/golden/q16.txt, from tools/grip_tools/golden/q16.py).
 * Prints the measured maximum error and enforces the documented bound
 * (docs/numerics.md). Runs in both builds: the primitives are integer-only.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_q16.h"
#include "golden.h"

#define LSB (1.0 / 65536.0)

typedef struct {
    const char *name;
    int binary;
    /* bound: |err| <= abs_lsb * LSB + rel_x * |x| + rel_y * |y|
     * (x = first input, y = exact result) */
    double abs_lsb;
    double rel_x;
    double rel_y;
} prim_bound;

static double eval(const char *name, int32_t a, int32_t b)
{
    grip_q16_t r = 0;
    if (strcmp(name, "mul") == 0) r = grip_q16_mul(a, b);
    else if (strcmp(name, "div") == 0) r = grip_q16_div(a, b);
    else if (strcmp(name, "sqrt") == 0) r = grip_q16_sqrt(a);
    else if (strcmp(name, "atan") == 0) r = grip_q16_atan(a);
    else if (strcmp(name, "atan2") == 0) r = grip_q16_atan2(a, b);
    else if (strcmp(name, "sin") == 0) r = grip_q16_sin(a);
    else if (strcmp(name, "cos") == 0) r = grip_q16_cos(a);
    else if (strcmp(name, "exp") == 0) r = grip_q16_exp(a);
    else if (strcmp(name, "log") == 0) r = grip_q16_log(a);
    else fail_msg("unknown primitive %s", name);
    return (double)r * LSB;
}

static void check_primitive(const prim_bound *pb)
{
    golden_file g;
    err_stats st;
    long violations = 0;
    double worst_excess = 0.0;
    assert_int_equal(golden_open(&g, "q16.txt"), 0);
    err_init(&st, pb->name, 1.0);
    while (golden_next(&g) > 0) {
        int32_t a;
        int32_t b;
        double want;
        double got;
        double bound;
        if (strcmp(g.field[0], pb->name) != 0) {
            continue;
        }
        a = (int32_t)golden_num(&g, 1);
        b = (int32_t)golden_num(&g, 2);
        want = golden_num(&g, 3);
        got = eval(pb->name, a, b);
        err_add(&st, got, want, a * LSB, b * LSB, 0.0);
        bound = pb->abs_lsb * LSB + pb->rel_x * fabs(a * LSB) + pb->rel_y * fabs(want);
        if (!(fabs(got - want) <= bound)) {
            violations++;
            if (fabs(got - want) - bound > worst_excess) {
                worst_excess = fabs(got - want) - bound;
            }
        }
    }
    golden_close(&g);
    err_print(&st, "");
    printf("#   = %.3f LSB; bound %.2f LSB + %.1e*|x| + %.1e*|y|\n", st.max_abs / LSB, pb->abs_lsb,
           pb->rel_x, pb->rel_y);
    assert_true(st.n > 1000);
    if (violations != 0) {
        fail_msg("%s: %ld vectors beyond the bound (worst by %.3e)", pb->name, violations, worst_excess);
    }
}

/* The bounds enforced here are the measured figures of docs/numerics.md,
 * rounded up; mul, div and sqrt are correctly rounded (0.5 LSB). */
static const prim_bound bounds[] = {
    { "mul",   1, 0.5, 0.0, 0.0 },
    { "div",   1, 0.5, 0.0, 0.0 },
    { "sqrt",  0, 0.5, 0.0, 0.0 },
    { "atan",  0, 0.505, 0.0, 0.0 },
    { "atan2", 1, 0.505, 0.0, 0.0 },
    { "sin",   0, 0.6, 1.0e-9, 0.0 },
    { "cos",   0, 0.6, 1.0e-9, 0.0 },
    { "exp",   0, 0.6, 0.0, 5.0e-9 },
    { "log",   0, 0.6, 0.0, 0.0 },
};

static void test_mul(void **s) { (void)s; check_primitive(&bounds[0]); }
static void test_div(void **s) { (void)s; check_primitive(&bounds[1]); }
static void test_sqrt(void **s) { (void)s; check_primitive(&bounds[2]); }
static void test_atan(void **s) { (void)s; check_primitive(&bounds[3]); }
static void test_atan2(void **s) { (void)s; check_primitive(&bounds[4]); }
static void test_sin(void **s) { (void)s; check_primitive(&bounds[5]); }
static void test_cos(void **s) { (void)s; check_primitive(&bounds[6]); }
static void test_exp(void **s) { (void)s; check_primitive(&bounds[7]); }
static void test_log(void **s) { (void)s; check_primitive(&bounds[8]); }

/* sincos gives exactly sin and cos: every 4099th raw value of the int32
 * domain (both signs, both ends, the quadrant boundaries on the way). */
static void test_sincos_is_sin_and_cos(void **s)
{
    int64_t v;
    uint32_t n = 0u;
    (void)s;
    for (v = -(int64_t)GRIP_Q16_MAX; v <= (int64_t)GRIP_Q16_MAX; v += 4099) {
        grip_q16_t a = (grip_q16_t)v;
        grip_q16_t sn = 0;
        grip_q16_t cs = 0;
        grip_q16_sincos(a, &sn, &cs);
        if ((sn != grip_q16_sin(a)) || (cs != grip_q16_cos(a))) {
            fail_msg("sincos(%ld) = (%ld, %ld), sin %ld, cos %ld", (long)a, (long)sn, (long)cs,
                     (long)grip_q16_sin(a), (long)grip_q16_cos(a));
        }
        ++n;
    }
    print_message("# sincos: %lu arguments, all equal to sin and cos\n", (unsigned long)n);
}

/* cos(atan(x)), internal to lib/arith (q16.c) */
grip_q16_t grip_q16_i_cos_atan(grip_q16_t a);

/* atan, sin and cos(atan) on every raw argument of a dense range (atan,
 * cos(atan): |x| < 128, both of their branches; sin: |x| < 16 rad, where the phase's rounding is
 * below 2e-8), against libm in double: the kernel's own error (2.9e-9 and
 * 6.2e-9, docs/numerics.md) on top of the result's rounding. The bound
 * 0.505 LSB leaves 0.005 LSB (7.6e-8) for it. */
static void check_dense(const char *name, int64_t lim, double bound_lsb)
{
    int64_t v;
    double worst = 0.0;
    int64_t worst_at = 0;
    for (v = -lim; v <= lim; ++v) {
        grip_q16_t a = (grip_q16_t)v;
        double x = (double)v * LSB;
        double got = (name[0] == 'a') ? (double)grip_q16_atan(a) * LSB
                     : (name[0] == 'c') ? (double)grip_q16_i_cos_atan(a) * LSB : (double)grip_q16_sin(a) * LSB;
        double want = (name[0] == 'a') ? atan(x) : (name[0] == 'c') ? 1.0 / sqrt(1.0 + x * x) : sin(x);
        double e = fabs(got - want) / LSB;
        if (e > worst) {
            worst = e;
            worst_at = v;
        }
    }
    print_message("# %s on every raw argument in [-%ld, %ld]: max |err| = %.4f LSB at %ld (bound %.3f)\n", name,
                  (long)lim, (long)lim, worst, (long)worst_at, bound_lsb);
    assert_true(worst <= bound_lsb);
}

static void test_atan_dense(void **s) { (void)s; check_dense("atan", (int64_t)1 << 23, 0.505); }
static void test_sin_dense(void **s) { (void)s; check_dense("sin", (int64_t)1 << 20, 0.505); }
/* cos(atan(x)) (lib/arith's r_cos_atan: one kernel, q16_cos_atan_k) on
 * every raw argument with |x| < 128, both of its branches */
static void test_cos_atan_dense(void **s) { (void)s; check_dense("cos_atan", (int64_t)1 << 23, 0.505); }

/* sqrt correctly rounded on every 61st positive raw argument (35 million,
 * both ends included): r^2 - r < a 2^16 <= r^2 + r. */
static void test_sqrt_every_61st(void **s)
{
    int64_t v;
    uint32_t n = 0u;
    (void)s;
    for (v = 1; v <= (int64_t)GRIP_Q16_MAX + 60; v += 61) {
        int64_t a = (v > (int64_t)GRIP_Q16_MAX) ? (int64_t)GRIP_Q16_MAX : v;   /* the end, last */
        uint64_t x = (uint64_t)a << 16;
        uint64_t r = (uint64_t)grip_q16_sqrt((grip_q16_t)a);
        if (!((r * r - r < x) && (x <= r * r + r))) {
            fail_msg("sqrt(%ld) = %lu is not correctly rounded", (long)a, (unsigned long)r);
        }
        ++n;
    }
    print_message("# sqrt: %lu positive arguments, every one correctly rounded\n", (unsigned long)n);
}

/* Saturation never wraps, and a debug-saturation build counts it. */
static void test_saturation_is_reported(void **s)
{
    (void)s;
    grip_debug_saturation_reset();
    assert_int_equal(grip_q16_mul(GRIP_Q16_MAX, 2 * GRIP_Q16_ONE), GRIP_Q16_MAX);
    assert_int_equal(grip_q16_add(GRIP_Q16_MIN, -1), GRIP_Q16_MIN);
    assert_int_equal(grip_q16_div(GRIP_Q16_ONE, 0), GRIP_Q16_MAX);
    assert_int_equal(grip_q16_exp(20 * GRIP_Q16_ONE), GRIP_Q16_MAX);
#if GRIP_DEBUG_SATURATION
    assert_int_equal(grip_debug_saturation_count(), 4);
    assert_string_equal(grip_debug_saturation_first(), "mul");
#else
    assert_int_equal(grip_debug_saturation_count(), 0);
#endif
    grip_debug_saturation_reset();
    (void)grip_q16_mul(3 * GRIP_Q16_ONE, 5 * GRIP_Q16_ONE);
    assert_int_equal(grip_debug_saturation_count(), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mul),   cmocka_unit_test(test_div), cmocka_unit_test(test_sqrt),
        cmocka_unit_test(test_sqrt_every_61st),
        cmocka_unit_test(test_cos_atan_dense),
        cmocka_unit_test(test_atan),  cmocka_unit_test(test_atan2), cmocka_unit_test(test_sin),
        cmocka_unit_test(test_cos),   cmocka_unit_test(test_exp), cmocka_unit_test(test_log),
        cmocka_unit_test(test_atan_dense), cmocka_unit_test(test_sin_dense),
        cmocka_unit_test(test_sincos_is_sin_and_cos), cmocka_unit_test(test_saturation_is_reported),
    };
    return cmocka_run_group_tests_name("q16", tests, NULL, NULL);
}
