/*
 * test_f32_kernels.c - the float build's polynomial kernels
 * (lib/arith/f32_kernels.h; the form of GRIP_KF_FMA, 0 on the host unless
 * test_f32_kernels_fma.c includes this file with 1) against
 * double-precision libm over the whole
 * float domain; prints the measured maximum error and enforces the bound of
 * each (docs/numerics.md, "Float kernels"), like test_q16.c for the Q15.16
 * kernels.
 *
 * Error: |k(x) - f(x)| / max(|f(x)|, FLT_MIN), f in double (libm's double
 * functions are within 1 ulp of double: 1e-16, far below what is measured).
 * One-argument functions: every float bit pattern with a stride (default
 * 127, a prime, so that every exponent and every low-bit pattern is
 * visited: 34 million points per function), and every float when
 * GRIP_KERNELS_EXHAUSTIVE=1 (2^32 per function: about a minute each).
 * atan2: every pair of a 4096-value set of x and y (every sign, exponents
 * from subnormal to infinity, zeros, NaN), plus 20 million random bit
 * patterns (GRIP_KERNELS_EXHAUSTIVE: 400 million).
 * Special values (NaN, infinities, signed zeros) are compared with C99's
 * rules exactly.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <float.h>
#include <string.h>
#include <cmocka.h>

#include "f32_kernels.h"

/* The bounds enforced: the exhaustively measured maxima (docs/numerics.md,
 * GRIP_KERNELS_EXHAUSTIVE=1), rounded up. sin and cos have two: |x| <= pi
 * (PI_HI; the one-subtraction path, grip_kf_sin_pi, grip_kf_cos_pi) and
 * beyond (the reduction by m pi/2).
 * GRIP_KF_FMA 0, the host's form (Estrin, separate operations): atan
 * 1.313e-7 at 1.00182104, atan2 1.315e-7, sin 1.404e-7 at 1.65542936 and
 * beyond pi 1.686e-7 at 40.8720627, cos 1.414e-7 at 3.05695963 and beyond
 * pi 1.732e-7 at 70.7015381, exp 9.866e-8 at 5.19916725.
 * GRIP_KF_FMA 1, the Cortex-M4F's (Horner with fmaf, the rest contracted;
 * test_f32_kernels_fma.c): atan 1.259e-7 at 1.8279804, atan2 1.315e-7, sin
 * 1.302e-7 at 1.57064819 and beyond pi 1.686e-7 at 40.8720627, cos 1.302e-7
 * at 0.000148236752 and beyond pi 1.732e-7 at 70.7015381, exp 1.011e-7 at
 * -5.19644022. */
#if GRIP_KF_FMA
#define BOUND_ATAN   1.3e-7
#define BOUND_ATAN2  1.4e-7
#define BOUND_SIN_PI 1.4e-7
#define BOUND_COS_PI 1.4e-7
#define BOUND_SIN    1.8e-7
#define BOUND_COS    1.8e-7
#define BOUND_EXP    1.1e-7
#else
#define BOUND_ATAN   1.4e-7
#define BOUND_ATAN2  1.4e-7
#define BOUND_SIN_PI 1.5e-7
#define BOUND_COS_PI 1.5e-7
#define BOUND_SIN    1.8e-7
#define BOUND_COS    1.8e-7
#define BOUND_EXP    1.0e-7
#endif

typedef struct {
    double max_err;
    float worst_x;
    float worst_y;
    uint64_t n;
} stats_t;

static uint32_t stride(void)
{
    const char *e = getenv("GRIP_KERNELS_EXHAUSTIVE");
    return (e != NULL && strcmp(e, "1") == 0) ? 1u : 127u;
}

static float from_bits(uint32_t u)
{
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static uint32_t to_bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* Same value including the sign of zero, or both NaN. */
static int same(float a, float b)
{
    return (a != a && b != b) || to_bits(a) == to_bits(b);
}

/* Records the error of got against want; special results (want NaN,
 * infinite, or zero) must match exactly (NaN: any NaN; zero: its sign). */
static void add(stats_t *st, float got, double want, float x, float y, const char *name)
{
    double err;
    st->n++;
    if (want != want || isinf((float)want) || want == 0.0) {
        /* NaN, a result beyond FLT_MAX (overflow: inf) or an exact zero */
        if (!same(got, (float)want)) {
            fail_msg("%s(%.9g, %.9g) = %.9g, want %.9g exactly", name, (double)x, (double)y, (double)got, want);
        }
        return;
    }
    err = fabs((double)got - want) / fmax(fabs(want), (double)FLT_MIN);
    if (!(err <= st->max_err)) {
        st->max_err = err;
        st->worst_x = x;
        st->worst_y = y;
    }
}

static void report(const stats_t *st, const char *name, double bound)
{
    printf("# %-6s n=%-11llu max rel err %.3e (%.2f x 2^-23) at x=%.9g y=%.9g; bound %.1e\n", name,
           (unsigned long long)st->n, st->max_err, st->max_err / (double)FLT_EPSILON, (double)st->worst_x,
           (double)st->worst_y, bound);
    if (!(st->max_err <= bound)) {
        fail_msg("%s: max error %.3e beyond the bound %.1e (at %.9g, %.9g)", name, st->max_err, bound,
                 (double)st->worst_x, (double)st->worst_y);
    }
}

typedef float (*kernel1)(float);
typedef double (*ref1)(double);

/* Every float (with the stride) and the edges below; where split > 0 the
 * arguments |x| <= split are reported and bounded apart (bound_in), the
 * rest with bound. */
static void sweep1(const char *name, kernel1 k, ref1 f, double bound, float split, double bound_in,
                   const char *name_in)
{
    stats_t st = { 0.0, 0.0f, 0.0f, 0u };
    stats_t sti = { 0.0, 0.0f, 0.0f, 0u };
    uint64_t u;
    uint64_t step = stride();
    for (u = 0u; u <= 0xFFFFFFFFu; u += step) {
        float x = from_bits((uint32_t)u);
        add((fabsf(x) <= split) ? &sti : &st, k(x), f((double)x), x, 0.0f, name);
    }
    /* the edges of every range the kernels switch at, and their neighbours */
    {
        static const float edges[] = { 0.0f, 1.0f, GRIP_KF_TRIG_MAX, GRIP_KF_EXP_MIN, GRIP_KF_EXP_MAX,
                                       0.785398163f, 1.57079633f, 3.14159265f, 0.34657359f, 88.7228394f,
                                       -103.972076f, -87.3365479f, FLT_MIN, FLT_MAX, INFINITY };
        size_t i;
        for (i = 0; i < sizeof edges / sizeof edges[0]; i++) {
            int d;
            for (d = -64; d <= 64; d++) {
                uint32_t b = to_bits(edges[i]);
                float x = from_bits(b + (uint32_t)d);
                add((fabsf(x) <= split) ? &sti : &st, k(x), f((double)x), x, 0.0f, name);
                add((fabsf(x) <= split) ? &sti : &st, k(-x), f((double)-x), -x, 0.0f, name);
            }
        }
    }
    if (split > 0.0f) {
        report(&sti, name_in, bound_in);
    }
    report(&st, name, bound);
}

static float k_sin_of_sincos(float x)
{
    float s;
    float c;
    grip_kf_sincos(x, &s, &c);
    return s;
}

static float k_cos_of_sincos(float x)
{
    float s;
    float c;
    grip_kf_sincos(x, &s, &c);
    return c;
}

static void test_atan(void **s) { (void)s; sweep1("atan", grip_kf_atan, atan, BOUND_ATAN, 0.0f, 0.0, ""); }
static void test_sin(void **s)
{
    (void)s;
    sweep1("sin", grip_kf_sin, sin, BOUND_SIN, GRIP_KF_PI_HI, BOUND_SIN_PI, "sin|pi");
}
static void test_cos(void **s)
{
    (void)s;
    sweep1("cos", grip_kf_cos, cos, BOUND_COS, GRIP_KF_PI_HI, BOUND_COS_PI, "cos|pi");
}
static void test_exp(void **s) { (void)s; sweep1("exp", grip_kf_exp, exp, BOUND_EXP, 0.0f, 0.0, ""); }

/* sincos gives exactly sin and cos (the same code), every float sampled. */
static void test_sincos(void **s)
{
    uint64_t u;
    uint64_t step = stride() * 7u;
    (void)s;
    for (u = 0u; u <= 0xFFFFFFFFu; u += step) {
        float x = from_bits((uint32_t)u);
        if (!same(k_sin_of_sincos(x), grip_kf_sin(x)) || !same(k_cos_of_sincos(x), grip_kf_cos(x))) {
            fail_msg("sincos(%.9g) differs from sin, cos", (double)x);
        }
    }
}

/* xorshift64*: reproducible random bit patterns */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (uint32_t)((rng_state * 0x2545F4914F6CDD1Dull) >> 32);
}

/* atan2 of one pair, and where y >= +0 and x > 0 the first-quadrant
 * kernel's result, which must be atan2's bits */
static void add_atan2(stats_t *st, float y, float x)
{
    float r = grip_kf_atan2(y, x);
    add(st, r, atan2((double)y, (double)x), x, y, "atan2");
    if ((to_bits(y) >> 31) == 0u && y == y && x > 0.0f && !same(grip_kf_atan2_q1(y, x), r)) {
        fail_msg("atan2_q1(%.9g, %.9g) = %.9g differs from atan2 %.9g", (double)y, (double)x,
                 (double)grip_kf_atan2_q1(y, x), (double)r);
    }
}

static void test_atan2(void **s)
{
    stats_t st = { 0.0, 0.0f, 0.0f, 0u };
    static float set[4096];
    size_t nset = 0;
    size_t i;
    size_t j;
    uint64_t k;
    uint64_t nrand = (stride() == 1u) ? 400000000u : 20000000u;
    (void)s;
    /* every exponent (with a few mantissas), both signs, zeros, infinities, NaN */
    for (i = 0; i < 256 && nset + 8 <= 4090; i++) {
        uint32_t e = (uint32_t)i << 23;
        set[nset++] = from_bits(e | 0x000000u);
        set[nset++] = from_bits(e | 0x7FFFFFu);
        set[nset++] = from_bits(e | (rnd() & 0x7FFFFFu));
        set[nset++] = from_bits(e | (rnd() & 0x7FFFFFu));
        set[nset] = -set[nset - 4];
        nset++;
        set[nset] = -set[nset - 4];
        nset++;
        set[nset] = -set[nset - 4];
        nset++;
        set[nset] = -set[nset - 4];
        nset++;
    }
    set[nset++] = 0.0f;
    set[nset++] = -0.0f;
    set[nset++] = NAN;
    set[nset++] = 1.0f;
    set[nset++] = -1.0f;
    for (i = 0; i < nset; i++) {
        for (j = 0; j < nset; j++) {
            float y = set[i];
            float x = set[j];
            add_atan2(&st, y, x);
        }
    }
    /* equal and nearly equal magnitudes (the octant boundary) */
    for (k = 0; k < 2000000u; k++) {
        float x = from_bits(rnd() & 0xFFFFFFFFu);
        float y = from_bits(to_bits(x) + (rnd() & 7u) - 3u);
        if (rnd() & 1u) {
            y = -y;
        }
        add_atan2(&st, y, x);
    }
    for (k = 0; k < nrand; k++) {
        float y = from_bits(rnd());
        float x = from_bits(rnd());
        add_atan2(&st, y, x);
    }
    report(&st, "atan2", BOUND_ATAN2);
}

/* C99 special values, exactly */
static void test_special_values(void **s)
{
    const float pi = GRIP_KF_PI_HI;
    const float pio2 = GRIP_KF_PIO2_HI;
    const float pio4 = 0.785398163f;
    (void)s;
    assert_true(same(grip_kf_atan(0.0f), 0.0f));
    assert_true(same(grip_kf_atan(-0.0f), -0.0f));
    assert_true(same(grip_kf_atan(INFINITY), pio2));
    assert_true(same(grip_kf_atan(-INFINITY), -pio2));
    assert_true(isnan(grip_kf_atan(NAN)));
    assert_true(same(grip_kf_atan2(0.0f, 0.0f), 0.0f));
    assert_true(same(grip_kf_atan2(-0.0f, 0.0f), -0.0f));
    assert_true(same(grip_kf_atan2(0.0f, -0.0f), pi));
    assert_true(same(grip_kf_atan2(-0.0f, -0.0f), -pi));
    assert_true(same(grip_kf_atan2(0.0f, -1.0f), pi));
    assert_true(same(grip_kf_atan2(-0.0f, -1.0f), -pi));
    assert_true(same(grip_kf_atan2(1.0f, 0.0f), pio2));
    assert_true(same(grip_kf_atan2(-1.0f, -0.0f), -pio2));
    assert_true(same(grip_kf_atan2(INFINITY, INFINITY), pio4));
    assert_true(same(grip_kf_atan2(-INFINITY, INFINITY), -pio4));
    assert_true(same(grip_kf_atan2(INFINITY, -INFINITY), 2.35619449f));
    assert_true(same(grip_kf_atan2(1.0f, INFINITY), 0.0f));
    assert_true(same(grip_kf_atan2(1.0f, -INFINITY), pi));
    assert_true(same(grip_kf_atan2(-1.0f, -INFINITY), -pi));
    assert_true(same(grip_kf_atan2(INFINITY, 1.0f), pio2));
    assert_true(isnan(grip_kf_atan2(NAN, 1.0f)));
    assert_true(isnan(grip_kf_atan2(1.0f, NAN)));
    assert_true(isnan(grip_kf_atan2(NAN, NAN)));
    assert_true(same(grip_kf_sin(0.0f), 0.0f));
    assert_true(same(grip_kf_sin(-0.0f), -0.0f));
    assert_true(same(grip_kf_cos(0.0f), 1.0f));
    assert_true(same(grip_kf_cos(-0.0f), 1.0f));
    assert_true(isnan(grip_kf_sin(INFINITY)));
    assert_true(isnan(grip_kf_cos(-INFINITY)));
    assert_true(isnan(grip_kf_sin(NAN)));
    assert_true(same(grip_kf_exp(0.0f), 1.0f));
    assert_true(same(grip_kf_exp(-0.0f), 1.0f));
    assert_true(same(grip_kf_exp(-INFINITY), 0.0f));
    assert_true(same(grip_kf_exp(INFINITY), INFINITY));
    assert_true(same(grip_kf_exp(100.0f), INFINITY));
    assert_true(same(grip_kf_exp(-200.0f), 0.0f));
    assert_true(isnan(grip_kf_exp(NAN)));
}

int main(void)
{
#if GRIP_ARITH_FIXED
    /* float-build code: swept once, in the float build (the result does
     * not depend on the build); here only the special values */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_special_values),
    };
    (void)test_atan;
    (void)test_atan2;
    (void)test_sin;
    (void)test_cos;
    (void)test_sincos;
    (void)test_exp;
#else
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_special_values),
        cmocka_unit_test(test_atan),
        cmocka_unit_test(test_atan2),
        cmocka_unit_test(test_sin),
        cmocka_unit_test(test_cos),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_exp),
    };
#endif
#if defined(GRIP_TEST_KF_HOST_FMA)
    /* compiled for a host with the fused multiply-add (test_f32_kernels_fma.c) */
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("fma")) {
        printf("# skip: this host has no fused multiply-add instruction\n");
        return 0;
    }
#endif
    return cmocka_run_group_tests_name(GRIP_KF_FMA ? "f32_kernels_fma" : "f32_kernels", tests, NULL, NULL);
}
