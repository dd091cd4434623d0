/*
 * f32_kernels.h - single-precision atan, atan2, sin, cos, sincos and exp
 * from minimax polynomials (f32_kernels_coefs.h, `grip kernels-f32`), for
 * the float build's arithmetic layer (arith.h, GRIP_FLOAT_KERNELS >= 1).
 *
 * Why: libm's functions are accurate but opaque calls (an x86 call clobbers
 * every vector register; glibc's atanf is ~60 instructions); these are
 * short and inline, so the compiler schedules them with the Magic Formula
 * around them. atan, sin, cos and exp select by arithmetic, selections and
 * table look-ups, not by a branch on the data (gcc -O2 makes atan branch-free;
 * atan2's octant test, sin's and cos's test of |x| <= pi and the rare cases -
 * NaN, the fallbacks - may become well-predicted branches). Polynomials in
 * one of two forms (GRIP_KF_FMA below): Estrin's scheme in plain IEEE single
 * operations (the host build is compiled with -std=c99, which does not
 * contract a*b + c, so the same bits on every IEEE-754 target compiled so),
 * or, on a Cortex-M with a fused multiply-add, Horner's with explicit fmaf.
 *
 * Accuracy, measured against the host's libm at twice this precision by
 * tests/unit/test_f32_kernels.c (and _fma.c, the second form) over the
 * whole float domain (every float for the one-argument functions,
 * docs/numerics.md "Float kernels"):
 *   |k(x) - f(x)| <= bound * max(|f(x)|, FLT_MIN)
 * (relative error; FLT_MIN is the floor where results are subnormal).
 *
 * Domains: atan, atan2 every float (IEEE special cases as C99's atan2f,
 * signed zeros included); atan2_q1 y >= 0, x > 0; sin, cos, sincos use the
 * polynomial for |x| <= GRIP_KF_TRIG_MAX (one exact subtraction for
 * |x| <= pi, the reduction by m pi/2 beyond) and libm's sinf/cosf beyond
 * (and for NaN, inf);
 * exp uses it for GRIP_KF_EXP_MIN <= x <= GRIP_KF_EXP_MAX (normal results)
 * and libm's expf beyond (overflow, subnormal results, NaN, inf).
 *
 * The end of the file holds their branch-free forms for the lane evaluation
 * of the Magic Formula (grip_kf_lane_*), built from the same pieces.
 *
 * Internal to lib/: not part of the public API.
 */
#ifndef GRIP_F32_KERNELS_H
#define GRIP_F32_KERNELS_H

#include <math.h> /* fabsf, copysignf and the libm fallbacks (float build only) */
#include <stdint.h>
#include <string.h>
#include "f32_kernels_coefs.h"

/* |x| up to which sin/cos reduce by m pi/2 themselves: |m| <= 83 < 2^7, so
 * that m times each 17-bit part of pi/2 is exact. */
#define GRIP_KF_TRIG_MAX 128.0f
/* exp's own range: 2^k stays a normal float (-126 <= k <= 127). */
#define GRIP_KF_EXP_MIN (-87.0f)
#define GRIP_KF_EXP_MAX 88.0f
/* The form of the polynomials. 1: Horner's scheme with every step an
 * explicit fmaf (one rounding), for a core that has a single-precision
 * fused multiply-add and runs one instruction after the other (Cortex-M4F,
 * M7, M33): one vfma.f32 per coefficient, no powers of z, and the same bits
 * whether or not the compiler contracts (fmaf is a builtin there; on a host
 * without the instruction, libm's correctly rounded fmaf gives the same
 * bits, which is how tests/unit/test_f32_kernels_fma.c measures this form).
 * 0: Estrin's scheme in separate operations: the same polynomial in a
 * quarter of Horner's dependency chain, which is what limits a Magic Formula
 * evaluation on an out-of-order core (docs/performance.md, "Float
 * kernels"). */
#ifndef GRIP_KF_FMA
#if defined(__ARM_FEATURE_FMA) && defined(__ARM_ARCH_PROFILE) && (__ARM_ARCH_PROFILE == 'M')
#define GRIP_KF_FMA 1
#else
#define GRIP_KF_FMA 0
#endif
#endif
/* 1.5 * 2^23: adding and subtracting it rounds a float of magnitude below
 * 2^22 to an integer (round to nearest even), without a conversion. */
#define GRIP_KF_SHIFTER 12582912.0f
/* 1.5 * 2^24: the same for even integers (the spacing of floats there is 2) */
#define GRIP_KF_SHIFTER2 25165824.0f
/* the smallest normal float, 2^-126 */
#define GRIP_KF_FLT_MIN 1.17549435e-38f

static inline uint32_t grip_kf_bits(float x)
{
    uint32_t u;
    (void)memcpy(&u, &x, sizeof u);
    return u;
}

static inline float grip_kf_float(uint32_t u)
{
    float x;
    (void)memcpy(&x, &u, sizeof x);
    return x;
}

/* atan(t) for t in [0, 1] (also correct for t in [-1, 0]). */
static inline float grip_kf_atan01(float t)
{
    /* Estrin's scheme: the same polynomial in a quarter of Horner's
     * dependency chain (latency, not count, limits a Magic Formula
     * evaluation, which is one long chain) */
    float z = t * t;
#if GRIP_KF_FMA
    float p = fmaf(GRIP_KF_ATAN_7, z, GRIP_KF_ATAN_6);
    p = fmaf(p, z, GRIP_KF_ATAN_5);
    p = fmaf(p, z, GRIP_KF_ATAN_4);
    p = fmaf(p, z, GRIP_KF_ATAN_3);
    p = fmaf(p, z, GRIP_KF_ATAN_2);
    p = fmaf(p, z, GRIP_KF_ATAN_1);
    p = fmaf(p, z, GRIP_KF_ATAN_0);
    return fmaf(t, z * p, t);
#else
    float z2 = z * z;
    float z4 = z2 * z2;
    float p01 = GRIP_KF_ATAN_1 * z + GRIP_KF_ATAN_0;
    float p23 = GRIP_KF_ATAN_3 * z + GRIP_KF_ATAN_2;
    float p45 = GRIP_KF_ATAN_5 * z + GRIP_KF_ATAN_4;
    float p67 = GRIP_KF_ATAN_7 * z + GRIP_KF_ATAN_6;
    float p = (p01 + p23 * z2) + (p45 + p67 * z2) * z4;
    return t + t * (z * p);
#endif
}

/* Offsets and signs of the octant reconstruction: result = c_hi + (s p +
 * c_lo), indexed by (|y| > |x|) + 2 (x < 0); atan uses the first two. */
static const float grip_kf_oct_hi[4] = { 0.0f, GRIP_KF_PIO2_HI, GRIP_KF_PI_HI, GRIP_KF_PIO2_HI };
static const float grip_kf_oct_lo[4] = { 0.0f, GRIP_KF_PIO2_LO, GRIP_KF_PI_LO, GRIP_KF_PIO2_LO };
static const float grip_kf_oct_s[4] = { 1.0f, -1.0f, -1.0f, 1.0f };

/* The result of atan and atan2 from atan(t) = p and the octant's offset
 * hi + lo and sign s, with the sign of y. */
static inline float grip_kf_oct(float p, float hi, float lo, float s, float y)
{
    return copysignf(hi + (s * p + lo), y);
}

/* min(a, 1/a) for a = |x| >= 0 (NaN stays NaN), 1/a computed whatever a
 * (so that no branch depends on the data): + FLT_MIN changes nothing for
 * a >= 1 and keeps 0 from being a divisor; below 1 the quotient is >= 1
 * and the minimum drops it. */
static inline float grip_kf_atan_t(float a)
{
    float inv = 1.0f / (a + GRIP_KF_FLT_MIN);
    return (inv < a) ? inv : a;
}

/* min(ax, ay) / max(ax, ay), 0 / 1 when both are zero (atan2's argument). */
static inline float grip_kf_atan2_t(float ax, float ay)
{
    float mx = (ay > ax) ? ay : ax;
    float mn = (ay > ax) ? ax : ay;
    return mn / ((mx > 0.0f) ? mx : 1.0f);
}

/* pi/2 - p as atan's and atan2's second octant forms it: pi/2 + (-p + lo) */
static inline float grip_kf_pio2_minus(float p)
{
    return GRIP_KF_PIO2_HI + (GRIP_KF_PIO2_LO - p);
}

/* The two octants of atan selected rather than read from grip_kf_oct_*:
 * the same operations (s p + lo is p or lo - p, hi + p is p), so the same
 * bits, without the index arithmetic and the three loads (4 Cortex-M4F
 * instructions of ~40). */
static inline float grip_kf_atan(float x)
{
    float a = fabsf(x);
    float p = grip_kf_atan01(grip_kf_atan_t(a));
    return copysignf((a > 1.0f) ? grip_kf_pio2_minus(p) : p, x);
}

static inline float grip_kf_atan2(float y, float x)
{
    float ax = fabsf(x);
    float ay = fabsf(y);
    uint32_t oct;
    float t;
    float p;
    if ((x != x) || (y != y)) {
        return x + y;                             /* NaN in, NaN out */
    }
    /* octant: + 1 when |y| > |x| (the angle is pi/2 - atan(|x|/|y|)),
     * + 2 when x < 0 or x = -0 (pi - ...) */
    oct = ((ay > ax) ? 1u : 0u) + ((grip_kf_bits(x) >> 30) & 2u);
    t = grip_kf_atan2_t(ax, ay);
    if (t != t) {
        t = 1.0f;                                 /* inf / inf: the diagonal */
    }
    p = grip_kf_atan01(t);
    return grip_kf_oct(p, grip_kf_oct_hi[oct], grip_kf_oct_lo[oct], grip_kf_oct_s[oct], y);
}

/* atan2(y, x) for y >= 0 and x > 0, not NaN (infinities allowed): the bits
 * of grip_kf_atan2 in that quadrant (its octants 0 and 1, with the same
 * operations), without its NaN and sign tests, the octant arithmetic, the
 * table and the sign transfer. */
static inline float grip_kf_atan2_q1(float y, float x)
{
    float t = grip_kf_atan2_t(x, y);
    float p;
    if (t != t) {
        t = 1.0f;                                 /* inf / inf: the diagonal */
    }
    p = grip_kf_atan01(t);
    return (y > x) ? grip_kf_pio2_minus(p) : p;
}

/* sin x and cos x for |x| <= GRIP_KF_TRIG_MAX: x = m pi/2 + r with m even
 * (sin) or odd (cos), |r| <= pi/2 (a little more where x 2/pi rounds), then
 * sin x = (-1)^(m/2) sin r and cos x = (-1)^((m+1)/2) sin r: one odd
 * polynomial, accurate near the zeros of both (r small there). m comes from
 * 1.5 2^24 added and subtracted, which rounds x 2/pi to an even integer. The
 * four parts of pi/2 are positive and have 17 bits, so m times each is
 * exact and the first subtraction is exact wherever r is small (Sterbenz);
 * a zero x has m = 0 and stays a zero of its sign. The sign (neg: negate)
 * is applied to r before the polynomial (sin is odd: the same bits), off
 * the dependency chain, by a selection rather than a table, so that the lane
 * forms below share this function (gcc vectorizes the selection well; a
 * sign selected by the caller and passed in as a factor cost the lane
 * evaluation 13 % more instructions). */

/* P(z) of the sine */
static inline float grip_kf_sin_p(float z)
{
#if GRIP_KF_FMA
    return fmaf(fmaf(fmaf(GRIP_KF_SIN_3, z, GRIP_KF_SIN_2), z, GRIP_KF_SIN_1), z, GRIP_KF_SIN_0);
#else
    return (GRIP_KF_SIN_1 * z + GRIP_KF_SIN_0) + (z * z) * (GRIP_KF_SIN_3 * z + GRIP_KF_SIN_2);
#endif
}

/* r + (r z) p, the last step of the sine */
static inline float grip_kf_sin_fin(float r, float z, float p)
{
#if GRIP_KF_FMA
    return fmaf(r * z, p, r);
#else
    return r + (r * z) * p;
#endif
}

/* r + r^3 P(r^2), sin r for |r| <= pi/2 (a little more: the fit's range);
 * r + (-0) where r = +0, so -0 is not kept (grip_kf_sin_r keeps it) */
static inline float grip_kf_sin_rp(float r)
{
    float z = r * r;
    float p = grip_kf_sin_p(z);
    return grip_kf_sin_fin(r, z, p);
}

/* sin r for |r| <= pi/2 (a little more: the fit's range), negated when neg */
static inline float grip_kf_sin_r(float r, uint32_t neg)
{
    float z = r * r;
    float p = grip_kf_sin_p(z);
    r = r * ((neg != 0u) ? -1.0f : 1.0f);
    /* r + r^3 p, except where z is zero (r = 0, or |r| below 2^-75 where the
     * term is nothing): there r itself, which keeps the sign of a zero */
    return (z == 0.0f) ? r : grip_kf_sin_fin(r, z, p);
}

static inline float grip_kf_sin_poly(float x, float mf, uint32_t neg)
{
    float r = (((x - mf * GRIP_KF_PIO2_1) - mf * GRIP_KF_PIO2_2) - mf * GRIP_KF_PIO2_3) - mf * GRIP_KF_PIO2_4;
    return grip_kf_sin_r(r, neg);
}

/* sin x and cos x for |x| <= pi (a = |x|, x up to PI_HI, pi rounded up to
 * float): one exact subtraction instead of the four-part reduction.
 * sin: r = a where a <= pi/2, else pi - a as (PI_HI - a) + PI_LO, whose
 * subtraction is exact (Sterbenz: PI_HI/2 <= a <= PI_HI); sin x =
 * sign(x) sin r, the sign applied after the polynomial, so that a zero x
 * (r = +0) keeps its sign. cos x = sin(pi/2 - a), (PIO2_HI - a) + PIO2_LO,
 * exact where a >= PIO2_HI/2, i.e. wherever cos x is below 0.71 and its
 * relative accuracy depends on r; below, r >= pi/4 and the rounding of the
 * subtraction moves the result by at most cos(pi/4) 2^-24. r is never -0
 * in either (cos: pi/2 - a is a multiple of a's spacing, PIO2_LO is not),
 * so grip_kf_sin_r's test of a zero is not needed: the same bits without
 * it. The Magic Formula's sines and cosines are mostly of C atan(u),
 * |C atan u| <= |C| pi/2, within pi for |C| <= 2 (every C of the shipped
 * sets but the MF 6.1 / 6.2 examples' PKY4), and of the slip angle
 * (|alpha| <= pi/2). Error bounds: docs/numerics.md. */
static inline float grip_kf_sin_pi(float x, float a)
{
    float r = (a > GRIP_KF_PIO2_HI) ? ((GRIP_KF_PI_HI - a) + GRIP_KF_PI_LO) : a;
    float v = grip_kf_sin_rp(r);
    return ((grip_kf_bits(x) >> 31) != 0u) ? -v : v;   /* -0 too */
}

static inline float grip_kf_cos_pi(float a)
{
    return grip_kf_sin_rp((GRIP_KF_PIO2_HI - a) + GRIP_KF_PIO2_LO);
}

/* m of sin (even) and of cos (odd), and whether the result changes sign:
 * m/2 odd (sin), (m+1)/2 odd (cos) */
static inline float grip_kf_sin_m(float x)
{
    return (x * GRIP_KF_2_OVER_PI + GRIP_KF_SHIFTER2) - GRIP_KF_SHIFTER2;
}

static inline float grip_kf_cos_m(float x)
{
    return (((x * GRIP_KF_2_OVER_PI - 1.0f) + GRIP_KF_SHIFTER2) - GRIP_KF_SHIFTER2) + 1.0f;
}

static inline uint32_t grip_kf_sin_neg(float mf)
{
    return ((uint32_t)(int32_t)mf >> 1) & 1u;
}

static inline uint32_t grip_kf_cos_neg(float mf)
{
    return (((uint32_t)(int32_t)mf >> 1) & 1u) ^ 1u;
}

static inline float grip_kf_sin_k(float x)
{
    float mf = grip_kf_sin_m(x);
    return grip_kf_sin_poly(x, mf, grip_kf_sin_neg(mf));
}

static inline float grip_kf_cos_k(float x)
{
    float mf = grip_kf_cos_m(x);
    return grip_kf_sin_poly(x, mf, grip_kf_cos_neg(mf));
}

/* Beyond pi: the reduction by m pi/2, or libm beyond GRIP_KF_TRIG_MAX. Kept
 * out of line (one copy per file that uses it), so that the path of
 * |x| <= pi, the Magic Formula's, is inlined where it is called: gcc
 * otherwise keeps the whole of sin and cos out of line and every call pays
 * the call and its register saves (Cortex-M4F, prepared MF 6.1 combined:
 * 2,366 -> 2,334 instructions). */
#if defined(__GNUC__)
#define GRIP_KF_OUTLINE __attribute__((noinline))
#else
#define GRIP_KF_OUTLINE
#endif
static GRIP_KF_OUTLINE float grip_kf_sin_far(float x)
{
    if (!(fabsf(x) <= GRIP_KF_TRIG_MAX)) {
        return sinf(x);
    }
    return grip_kf_sin_k(x);
}

static GRIP_KF_OUTLINE float grip_kf_cos_far(float x)
{
    if (!(fabsf(x) <= GRIP_KF_TRIG_MAX)) {
        return cosf(x);
    }
    return grip_kf_cos_k(x);
}

static inline float grip_kf_sin(float x)
{
    float a = fabsf(x);
    return (a <= GRIP_KF_PI_HI) ? grip_kf_sin_pi(x, a) : grip_kf_sin_far(x);
}

static inline float grip_kf_cos(float x)
{
    float a = fabsf(x);
    return (a <= GRIP_KF_PI_HI) ? grip_kf_cos_pi(a) : grip_kf_cos_far(x);
}

/* Both: exactly grip_kf_sin(x) and grip_kf_cos(x). */
static inline void grip_kf_sincos(float x, float *s, float *c)
{
    float a = fabsf(x);
    if (a <= GRIP_KF_PI_HI) {
        *s = grip_kf_sin_pi(x, a);
        *c = grip_kf_cos_pi(a);
        return;
    }
    *s = grip_kf_sin_far(x);
    *c = grip_kf_cos_far(x);
}

/* e^x = 2^k e^r, x = k ln 2 + r, |r| <= ln(2)/2 (a little more where x/ln 2
 * rounds); 2^k from its bits. */
static inline float grip_kf_exp_k(float x)
{
    float kf = (x * GRIP_KF_LOG2E + GRIP_KF_SHIFTER) - GRIP_KF_SHIFTER;
    int32_t k = (int32_t)kf;
    float r = (x - kf * GRIP_KF_LN2_HI) - kf * GRIP_KF_LN2_LO;
    float r2 = r * r;
    float p = (GRIP_KF_EXP_1 * r + GRIP_KF_EXP_0) + r2 * ((GRIP_KF_EXP_3 * r + GRIP_KF_EXP_2) + r2 * GRIP_KF_EXP_4);
    return (1.0f + (r + r * (r * p))) * grip_kf_float((uint32_t)(k + 127) << 23);
}

static inline float grip_kf_exp(float x)
{
    if (!((x >= GRIP_KF_EXP_MIN) && (x <= GRIP_KF_EXP_MAX))) {
        return expf(x);
    }
    return grip_kf_exp_k(x);
}

/* ------------------------------------------------------------------------
 * Branch-free forms, for the lane evaluation of the Magic Formula
 * (lib/mf/mf_lanes.c, through the kernel names of lib/mf/mf_equations.h):
 * built from the same pieces as the kernels above, so the same operations
 * and bits wherever the argument is inside the kernel's own range, but with
 * selections where those index a table and without the libm fallbacks: an
 * argument outside that range, or not finite, marks *bad (grip_kf_lane_mark)
 * and the result is not to be used (the caller evaluates that point again
 * with the scalar kernels). No call, no branch, no table: a loop of them is
 * vectorized by the compiler.
 */

/* The lane forms are inlined whatever the size of their caller: a call left
 * in the lane loop stops its vectorization (gcc 12 kept grip_kf_lane_atan2
 * out of line once the lane evaluation grew, and MF 6.1 per point went
 * from 1,210 to 3,151 x86 instructions). */
#if defined(__GNUC__)
#define GRIP_KF_LANE inline __attribute__((always_inline))
#else
#define GRIP_KF_LANE inline
#endif

/* *bad, starting at -1, becomes > 0 when t > 0 (t: how far an argument is
 * outside its kernel's range, <= 0 inside), NaN when x is not finite (x - x
 * is 0, or NaN for an infinite or NaN x). A number, not a flag: gcc 12 does
 * not vectorize the selections of flags that its jump threading makes of
 * flags set under other selections. */
static GRIP_KF_LANE void grip_kf_lane_mark(float *bad, float t, float x)
{
    *bad = ((t > *bad) ? t : *bad) + (x - x);
}

/* grip_kf_atan (every float) */
static GRIP_KF_LANE float grip_kf_lane_atan(float x)
{
    float a = fabsf(x);
    int big = a > 1.0f;
    float p = grip_kf_atan01(grip_kf_atan_t(a));
    return grip_kf_oct(p, big ? GRIP_KF_PIO2_HI : 0.0f, big ? GRIP_KF_PIO2_LO : 0.0f, big ? -1.0f : 1.0f, x);
}

/* grip_kf_atan2 where x and y are finite; else *bad */
static GRIP_KF_LANE float grip_kf_lane_atan2(float y, float x, float *bad)
{
    float ax = fabsf(x);
    float ay = fabsf(y);
    int sw = ay > ax;                        /* octant + 1 */
    int neg = copysignf(1.0f, x) < 0.0f;     /* octant + 2: x < 0 or x = -0 */
    float p = grip_kf_atan01(grip_kf_atan2_t(ax, ay));
    float hi = neg ? (sw ? GRIP_KF_PIO2_HI : GRIP_KF_PI_HI) : (sw ? GRIP_KF_PIO2_HI : 0.0f);
    float lo = neg ? (sw ? GRIP_KF_PIO2_LO : GRIP_KF_PI_LO) : (sw ? GRIP_KF_PIO2_LO : 0.0f);
    float s = (sw != neg) ? -1.0f : 1.0f;
    grip_kf_lane_mark(bad, -1.0f, x + y);
    return grip_kf_oct(p, hi, lo, s, y);
}

/* grip_kf_sin, grip_kf_cos for |x| <= GRIP_KF_TRIG_MAX; else *bad (the
 * argument is replaced by 0 before it is converted to an integer) */
static GRIP_KF_LANE float grip_kf_lane_sin(float x, float *bad)
{
    float a = fabsf(x);
    float xs = (a <= GRIP_KF_TRIG_MAX) ? x : 0.0f;
    float mf = grip_kf_sin_m(xs);
    float r;
    /* both reductions formed, the scalar kernel's selected (|x| <= pi: one
     * subtraction, grip_kf_sin_pi), so that the bits are the scalar's */
    float big = (((xs - mf * GRIP_KF_PIO2_1) - mf * GRIP_KF_PIO2_2) - mf * GRIP_KF_PIO2_3) - mf * GRIP_KF_PIO2_4;
    float small = (a > GRIP_KF_PIO2_HI) ? ((GRIP_KF_PI_HI - a) + GRIP_KF_PI_LO) : a;
    uint32_t neg = (a <= GRIP_KF_PI_HI) ? ((copysignf(1.0f, x) < 0.0f) ? 1u : 0u) : grip_kf_sin_neg(mf);
    r = (a <= GRIP_KF_PI_HI) ? small : big;
    grip_kf_lane_mark(bad, a - GRIP_KF_TRIG_MAX, x);
    return grip_kf_sin_r(r, neg);
}

static GRIP_KF_LANE float grip_kf_lane_cos(float x, float *bad)
{
    float a = fabsf(x);
    float xs = (a <= GRIP_KF_TRIG_MAX) ? x : 0.0f;
    float mf = grip_kf_cos_m(xs);
    float r;
    float big = (((xs - mf * GRIP_KF_PIO2_1) - mf * GRIP_KF_PIO2_2) - mf * GRIP_KF_PIO2_3) - mf * GRIP_KF_PIO2_4;
    float small = (GRIP_KF_PIO2_HI - a) + GRIP_KF_PIO2_LO;
    uint32_t neg = (a <= GRIP_KF_PI_HI) ? 0u : grip_kf_cos_neg(mf);
    r = (a <= GRIP_KF_PI_HI) ? small : big;
    grip_kf_lane_mark(bad, a - GRIP_KF_TRIG_MAX, x);
    return grip_kf_sin_r(r, neg);
}

/* grip_kf_exp for GRIP_KF_EXP_MIN <= x <= GRIP_KF_EXP_MAX; else *bad */
static GRIP_KF_LANE float grip_kf_lane_exp(float x, float *bad)
{
    float lo = GRIP_KF_EXP_MIN - x;
    float hi = x - GRIP_KF_EXP_MAX;
    float xs = ((lo <= 0.0f) & (hi <= 0.0f)) ? x : 0.0f;
    grip_kf_lane_mark(bad, (lo > hi) ? lo : hi, x);
    return grip_kf_exp_k(xs);
}

#endif /* GRIP_F32_KERNELS_H */
