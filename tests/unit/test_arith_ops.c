/*
 * test_arith_ops.c - the arithmetic layer's operations with fewer range
 * tests (lib/arith/arith.h: r_mac, r_msub, r_mul_unit, r_mul_scale) against the
 * two-step forms they replace, in both builds:
 *   - r_mac(c, a, b) and r_msub(c, a, b) give the bits of r_add(c, r_mul(a,
 *     b)) and r_sub(c, r_mul(a, b)) wherever the product does not saturate
 *     on its own, and the exact sum clamped once where it does (fixed);
 *   - r_mul_unit(u, b) gives the bits of r_mul(u, b) for every |u| <= 1;
 *   - r_mul_scale(x, s) gives the bits of r_mul(x, s), s = 1 among them;
 *   - r_atan2_q1(y, x) gives the bits of r_atan2(y, x) for y >= 0, x > 0
 *     (fixed; the float build's forms are tested with the kernels);
 *   - r_div_le1(a, b) gives the bits of r_div(a, b) for 0 <= a <= b,
 *     r_div_nt(a, b) those of r_div(a, b) for b != 0 and |a / b| < 32767, and
 *     r_mac_nt, r_msub_nt, r_mul_nt, r_add_nt those of the checked
 *     operations wherever the result is in range;
 *   - q16_div_lim (mf_div_lim, fixed) gives the values of the composition
 *     of r_abs and r_div it replaces;
 *   - r_quot_m1_lo and r_lin_ext carry dfz's residual (float) or are the
 *     plain forms (fixed);
 *   - a GRIP_DEBUG_SATURATION build flags r_mul_unit called with |u| > 1
 *     (the event "mul_unit") and returns the saturated product, and
 *     r_atan2_q1 outside the first quadrant (the event "atan2_q1").
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdint.h>
#include <cmocka.h>

#include "grip/grip_q16.h"
#include "arith.h"

#define N_PAIRS 400000

static uint64_t lcg = 0x2545F4914F6CDD1Dull;

static uint32_t next_u32(void)
{
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(lcg >> 32);
}

/* A value spread over the whole range, log-uniform in magnitude. */
static grip_real_t any_value(void)
{
    uint32_t r = next_u32();
    int sh = (int)(r % 32u);
#if GRIP_ARITH_FIXED
    int32_t v = (int32_t)(next_u32() >> (uint32_t)sh);
    if (v == INT32_MIN) {
        v = -INT32_MAX;
    }
    return ((r & 0x100u) != 0u) ? -v : v;
#else
    float v = (float)next_u32() / 4294967296.0f * (float)(1u << (uint32_t)sh) / 65536.0f;
    return ((r & 0x100u) != 0u) ? -v : v;
#endif
}

/* A factor within [-1, 1], its ends included. */
static grip_real_t unit_value(void)
{
    uint32_t r = next_u32();
#if GRIP_ARITH_FIXED
    int32_t v = (int32_t)(next_u32() % 65537u);
    return ((r & 1u) != 0u) ? -v : v;
#else
    float v = (r % 7u == 0u) ? 1.0f : (float)next_u32() / 4294967296.0f;
    return ((r & 1u) != 0u) ? -v : v;
#endif
}

static void test_mac_msub_as_two_steps(void **s)
{
    long same = 0;
    long fused_only = 0;
    int i;
    (void)s;
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t a = any_value();
        grip_real_t b = any_value();
        grip_real_t c = any_value();
#if GRIP_ARITH_FIXED
        int64_t p = ((int64_t)a * (int64_t)b + 32768) >> 16;      /* round(a b / 2^16) */
        if ((p >= -(int64_t)INT32_MAX) && (p <= (int64_t)INT32_MAX)) {
            assert_int_equal(r_mac(c, a, b), r_add(c, r_mul(a, b)));
            assert_int_equal(r_msub(c, a, b), r_sub(c, r_mul(a, b)));
            ++same;
        } else {
            /* the product alone saturates: the exact sum, clamped once */
            int64_t sp = (int64_t)c + p;
            int64_t sm = (int64_t)c - p;
            int64_t ep = (sp > INT32_MAX) ? INT32_MAX : ((sp < -INT32_MAX) ? -INT32_MAX : sp);
            int64_t em = (sm > INT32_MAX) ? INT32_MAX : ((sm < -INT32_MAX) ? -INT32_MAX : sm);
            assert_int_equal(r_mac(c, a, b), (grip_real_t)ep);
            assert_int_equal(r_msub(c, a, b), (grip_real_t)em);
            ++fused_only;
        }
#else
        /* the plain operations in the same order: the same bits */
        assert_true(r_mac(c, a, b) == r_add(c, r_mul(a, b)));
        assert_true(r_msub(c, a, b) == r_sub(c, r_mul(a, b)));
        ++same;
#endif
    }
    print_message("# mac, msub: %ld triples as the two-step forms, %ld with a saturating product\n", same,
                  fused_only);
#if GRIP_ARITH_FIXED
    /* a product beyond the range whose sum is inside: round(1.5 MAX) - MAX = 2^30 */
    assert_int_equal(r_mac(-INT32_MAX, RC(1.5), INT32_MAX), 1073741824);
#endif
}

static void test_mul_unit_as_mul(void **s)
{
    int i;
    (void)s;
    grip_debug_saturation_reset();
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t u = unit_value();
        grip_real_t b = any_value();
#if GRIP_ARITH_FIXED
        assert_int_equal(r_mul_unit(u, b), r_mul(u, b));
#else
        assert_true(r_mul_unit(u, b) == r_mul(u, b));
#endif
    }
    /* the ends: |u| = 1 at the largest |b| */
    assert_true(r_mul_unit(R_ONE, RC(32767.0)) == RC(32767.0));
    assert_true(r_mul_unit(r_neg(R_ONE), RC(32767.0)) == RC(-32767.0));
    /* within its precondition, never a saturation */
    assert_int_equal(grip_debug_saturation_count(), 0);
    print_message("# mul_unit: %d pairs with |u| <= 1 as r_mul\n", N_PAIRS);
}

static void test_mul_scale_as_mul(void **s)
{
    int i;
    (void)s;
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t x = any_value();
        grip_real_t f = ((i % 4) == 0) ? R_ONE : any_value();
#if GRIP_ARITH_FIXED
        assert_int_equal(r_mul_scale(x, f), r_mul(x, f));
#else
        assert_true(r_mul_scale(x, f) == r_mul(x, f));
#endif
    }
    print_message("# mul_scale: %d pairs (a quarter with s = 1) as r_mul\n", N_PAIRS);
}

/* r_div_le1 (0 <= a <= b, b > 0) and r_div_nt (b != 0, |a / b| < 32767)
 * against r_div, and the certified operations (r_mac_nt ...) against the
 * checked ones where the result is in range */
static void test_div_le1_and_certified(void **s)
{
    int i;
    long n_nt = 0;
    long n_div = 0;
    (void)s;
    grip_debug_saturation_reset();
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t a = r_abs(any_value());
        grip_real_t b = r_abs(any_value());
        grip_real_t c = any_value();
        grip_real_t t;
        if (a > b) {
            t = a;
            a = b;
            b = t;
        }
        if (b == R_ZERO) {
            b = (grip_real_t)1;
        }
#if GRIP_ARITH_FIXED
        assert_int_equal(r_div_le1(a, b), r_div(a, b));
        /* +-b / c, c != 0 and |b| < 32767 |c| (its sign and c's: every case) */
        if ((c != 0) && ((int64_t)b < ((c < 0) ? -(int64_t)c : (int64_t)c) * 32767)) {
            assert_int_equal(r_div_nt(b, c), r_div(b, c));
            assert_int_equal(r_div_nt(r_neg(b), c), r_div(r_neg(b), c));
            ++n_div;
        }
        {
            int64_t m = (int64_t)c + (((int64_t)a * b + 32768) >> 16);
            int64_t p = ((int64_t)a * b + 32768) >> 16;
            if (m >= -INT32_MAX && m <= INT32_MAX) {
                assert_int_equal(r_mac_nt(c, a, b), r_mac(c, a, b));
                ++n_nt;
            }
            if (p <= INT32_MAX) {
                assert_int_equal(r_mul_nt(a, b), r_mul(a, b));
            }
            if ((int64_t)c - p >= -INT32_MAX && (int64_t)c - p <= INT32_MAX) {
                assert_int_equal(r_msub_nt(c, a, b), r_msub(c, a, b));
            }
            if ((int64_t)c + a >= -INT32_MAX && (int64_t)c + a <= INT32_MAX) {
                assert_int_equal(r_add_nt(c, a), r_add(c, a));
            }
        }
#else
        assert_true(r_div_le1(a, b) == r_div(a, b));
        assert_true(r_div_nt(a, b) == r_div(a, b));
        assert_true(r_mac_nt(c, a, b) == r_mac(c, a, b));
        ++n_nt;
        ++n_div;
#endif
    }
    assert_int_equal(grip_debug_saturation_count(), 0);
    print_message("# div_le1: %d pairs as r_div; div_nt: %ld as r_div; certified operations: %ld in range as the "
                  "checked ones\n",
                  N_PAIRS, n_div, n_nt);
}

static void test_atan2_q1_as_atan2(void **s)
{
    (void)s;
#if GRIP_ARITH_FIXED
    int i;
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t y = r_abs(any_value());
        grip_real_t x = r_abs(any_value());
        if (x == 0) {
            x = 1;
        }
        assert_int_equal(r_atan2_q1(y, x), r_atan2(y, x));
    }
    assert_int_equal(r_atan2_q1(0, 1), 0);
    assert_int_equal(r_atan2_q1(INT32_MAX, 1), r_atan2(INT32_MAX, 1));
    assert_int_equal(r_atan2_q1(INT32_MAX, INT32_MAX), r_atan2(INT32_MAX, INT32_MAX));
    print_message("# atan2_q1: %d pairs with y >= 0, x > 0 as r_atan2\n", N_PAIRS);
#else
    print_message("# atan2_q1: fixed build only here (float: test_f32_kernels)\n");
#endif
}

/* q16_div_lim (lib/mf's mf_div_lim in the fixed build) against the
 * composition it replaces, for the limits in use: random pairs, pairs at
 * the limit's boundary (|b| = round(|a| / lim) + -1, 0, 1) and INT32_MIN. */
#if GRIP_ARITH_FIXED
static grip_real_t div_lim_ref(grip_real_t a, grip_real_t b, grip_real_t lim)
{
    grip_real_t aa = r_abs(a);
    if (aa == 0) {
        return 0;
    }
    if (r_abs(b) <= r_div(aa, lim)) {
        return ((a < 0) != (b < 0)) ? r_neg(lim) : lim;
    }
    return r_div(a, b);
}
#endif

static void test_div_lim_as_composition(void **s)
{
    (void)s;
#if GRIP_ARITH_FIXED
    static const grip_real_t lims[4] = { R_ONE, RC(10.0), RC(100.0), RC(1000.0) };
    int i;
    int k;
    long n = 0;
    for (k = 0; k < 4; ++k) {
        grip_real_t lim = lims[k];
        for (i = 0; i < N_PAIRS; ++i) {
            grip_real_t a = any_value();
            grip_real_t b = any_value();
            if ((i % 2) == 1) {
                /* at the boundary of the limit */
                grip_real_t q = r_div(r_abs(a), lim);
                int32_t d = (int32_t)(next_u32() % 3u) - 1;
                b = ((q + d) > 0) ? (q + d) : 0;
                if ((next_u32() & 1u) != 0u) {
                    b = -b;
                }
            }
            assert_int_equal(q16_div_lim(a, b, lim), div_lim_ref(a, b, lim));
            ++n;
        }
        assert_int_equal(q16_div_lim(INT32_MIN, 1, lim), div_lim_ref(INT32_MIN, 1, lim));
        assert_int_equal(q16_div_lim(1, INT32_MIN, lim), div_lim_ref(1, INT32_MIN, lim));
        assert_int_equal(q16_div_lim(INT32_MAX, INT32_MIN, lim), div_lim_ref(INT32_MAX, INT32_MIN, lim));
        assert_int_equal(q16_div_lim(INT32_MIN, INT32_MIN, lim), div_lim_ref(INT32_MIN, INT32_MIN, lim));
        assert_int_equal(q16_div_lim(0, 0, lim), 0);
        assert_int_equal(q16_div_lim(5, 0, lim), lim);
        assert_int_equal(q16_div_lim(-5, 0, lim), -lim);
    }
    print_message("# div_lim: %ld pairs (half at the limit's boundary) as the composition\n", n);
#else
    print_message("# div_lim: fixed build only (the float mf_div_lim divides first)\n");
#endif
}

/* r_quot_m1_lo and r_lin_ext (the load term carried beyond single
 * precision): the float build against double arithmetic (on this host the
 * exact products of the non-FMA form, on a core with a fused multiply-add
 * its fmaf form), the fixed build as the plain forms. */
#if !GRIP_ARITH_FIXED
static float unit_float(void)
{
    return (float)(next_u32() >> 8) / 16777216.0f;
}
#endif

static void test_load_term_beyond_single(void **s)
{
    int i;
    (void)s;
#if GRIP_ARITH_FIXED
    for (i = 0; i < N_PAIRS; ++i) {
        grip_real_t c0 = any_value();
        grip_real_t c1 = any_value();
        grip_real_t x = any_value();
        assert_int_equal(r_lin_ext(c0, c1, x, any_value()), r_add(c0, r_mul(c1, x)));
        assert_int_equal(r_quot_m1_lo(x, c0, c1, x, c0), R_ZERO);
    }
    print_message("# load term: %d cases, the plain forms (fixed)\n", N_PAIRS);
#else
    double worst_q = 0.0;
    double worst_l = 0.0;
    for (i = 0; i < N_PAIRS; ++i) {
        /* Fz 0 .. 40 kN, FNOMIN 1 .. 10 kN, LFZO 0.5 .. 2, as mf_load forms q, d */
        float fz = 40000.0f * unit_float();
        float fnomin = 1000.0f + 9000.0f * unit_float();
        float lfzo = 0.5f + 1.5f * unit_float();
        float q = (fz / fnomin) / lfzo;
        float d = q - 1.0f;
        double exact = (double)fz / ((double)fnomin * (double)lfzo) - 1.0;
        double eq = fabs(((double)d + (double)r_quot_m1_lo(fz, fnomin, lfzo, q, d)) - exact) / (1.0 + fabs(exact));
        /* c0 + c1 (x + x_lo), every fourth case with c0 cancelling c1 x */
        float c1 = 200.0f * unit_float() - 100.0f;
        float x = 4.0f * unit_float() - 2.0f;
        float x_lo = (unit_float() - 0.5f) * 1.2e-7f * x;
        float c0 = ((i & 3) == 0) ? -(c1 * x) + (unit_float() - 0.5f) : 200.0f * unit_float() - 100.0f;
        double want = (double)c0 + (double)c1 * ((double)x + (double)x_lo);
        double el = fabs((double)r_lin_ext(c0, c1, x, x_lo) - want) /
                    (fabs(want) * 0x1p-23 + fabs((double)c1 * (double)x) * 0x1p-46 + 1e-30);
        worst_q = (eq > worst_q) ? eq : worst_q;
        worst_l = (el > worst_l) ? el : worst_l;
    }
    print_message("# load term: %d cases, r_quot_m1_lo max |err| / (1 + |dfz|) %.3e (bound 1e-12), "
                  "r_lin_ext max |err| / (2^-23 |result| + 2^-46 |c1 x|) %.3f (bound 1)\n", N_PAIRS, worst_q, worst_l);
    assert_true(worst_q <= 1e-12);
    assert_true(worst_l <= 1.0);
#endif
}

/* The debug-saturation build checks the preconditions. */
static void test_preconditions_flagged(void **s)
{
    (void)s;
#if GRIP_ARITH_FIXED && GRIP_DEBUG_SATURATION
    grip_debug_saturation_reset();
    /* just beyond 1, a product that still fits: flagged all the same */
    assert_int_equal(r_mul_unit(R_ONE + 1, RC(2.0)), r_mul(R_ONE + 1, RC(2.0)));
    assert_int_equal(grip_debug_saturation_count(), 1);
    assert_string_equal(grip_debug_saturation_first(), "mul_unit");
    /* a product beyond the range: saturated as r_mul's (two events: the
     * precondition and the saturation of the product) */
    assert_int_equal(r_mul_unit(RC(-2.0), RC(30000.0)), -INT32_MAX);
    assert_int_equal(grip_debug_saturation_count(), 3);
    /* atan2_q1 outside the first quadrant: flagged, answered as atan2 */
    grip_debug_saturation_reset();
    assert_int_equal(r_atan2_q1(RC(-1.0), RC(1.0)), r_atan2(RC(-1.0), RC(1.0)));
    assert_int_equal(r_atan2_q1(RC(1.0), 0), r_atan2(RC(1.0), 0));
    assert_int_equal(grip_debug_saturation_count(), 2);
    assert_string_equal(grip_debug_saturation_first(), "atan2_q1");
    /* div_le1 with a > b, or b = 0: flagged, answered as r_div */
    grip_debug_saturation_reset();
    assert_int_equal(r_div_le1(RC(2.0), RC(1.0)), r_div(RC(2.0), RC(1.0)));
    assert_string_equal(grip_debug_saturation_first(), "div_le1");
    /* div_nt by 0, or with a quotient beyond 2^15: flagged, answered as r_div */
    grip_debug_saturation_reset();
    {
        grip_real_t q = r_div_nt(RC(1.0), 0);
        assert_string_equal(grip_debug_saturation_first(), "div_nt");
        assert_int_equal(q, r_div(RC(1.0), 0));
    }
    grip_debug_saturation_reset();
    assert_int_equal(r_div_nt(RC(20000.0), RC(0.5)), INT32_MAX);
    assert_string_equal(grip_debug_saturation_first(), "div_nt");
    /* a certified operation whose result leaves the range: counted as
     * "cert", answered as the checked operation */
    grip_debug_saturation_reset();
    assert_int_equal(r_mac_nt(RC(30000.0), RC(2.0), RC(2000.0)), INT32_MAX);
    assert_int_equal(grip_debug_saturation_count(), 1);
    assert_string_equal(grip_debug_saturation_first(), "cert");
    grip_debug_saturation_reset();
#else
    print_message("# preconditions: checked in the fixed DEBUG_SAT=1 build only\n");
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mac_msub_as_two_steps),
        cmocka_unit_test(test_mul_unit_as_mul),
        cmocka_unit_test(test_preconditions_flagged),
        cmocka_unit_test(test_mul_scale_as_mul),
        cmocka_unit_test(test_atan2_q1_as_atan2),
        cmocka_unit_test(test_div_lim_as_composition),
        cmocka_unit_test(test_div_le1_and_certified),
        cmocka_unit_test(test_load_term_beyond_single),
    };
    return cmocka_run_group_tests_name("arith_ops", tests, NULL, NULL);
}
