/*
 * arith.h - the one set of arithmetic operations that every model in lib/
 * is written in. In the float build each is plain single-precision float
 * arithmetic; in the fixed build each is a saturating Q-format integer
 * operation (Opus/CELT's arch.h idea). Formats (grip_types.h):
 *   QS = Q15.16 (dimensionless, rad, m, m/s, s), QL = Q23.8 (N, N m, Pa, ...).
 *
 *   r_add/r_sub(a, b)   same format in, same out
 *   r_mul(a_QS, b_Qx)   -> Qx       (QS times anything keeps the other format)
 *   r_mac(c_Qx, a_QS, b_Qx)  -> Qx  c + a b, one rounding and one saturation
 *   r_msub(c_Qx, a_QS, b_Qx) -> Qx  c - a b, likewise
 *   r_mul_unit(u_QS, b_Qx)   -> Qx  u b where |u| <= 1 is known: no range test
 *   r_mul_scale(x_Qx, s_QS)  -> Qx  x s for a scale factor s, most often exactly 1
 *   r_div(a_Qx, b_Qx)   -> QS       (ratio of like quantities is dimensionless)
 *   r_div_keep(a_Qx, b_QS) -> Qx    (quantity divided by a dimensionless value)
 *   r_ql_to_qs / r_qs_to_ql          format change, no-op in float
 *   r_sqrt r_atan r_atan2 r_sin r_cos r_sincos r_exp r_log on QS
 *   (float build: libm's, or grip's polynomial kernels f32_kernels.h as
 *   GRIP_FLOAT_KERNELS selects, grip_config.h)
 *
 * Internal to lib/: not part of the public API.
 */
#ifndef GRIP_ARITH_H
#define GRIP_ARITH_H

#include "grip/grip_types.h"

#if GRIP_ARITH_FIXED
#include "q16_inline.h"
#include "q16_math_inline.h"

#define RC(x)  GRIP_QS(x)   /* QS constant */
#define RCL(x) GRIP_QL(x)   /* QL constant */
#define R_ZERO ((grip_real_t)0)
#define R_ONE  ((grip_real_t)65536)

static inline grip_real_t r_add(grip_real_t a, grip_real_t b) { return q16_add(a, b); }
static inline grip_real_t r_sub(grip_real_t a, grip_real_t b) { return q16_sub(a, b); }
static inline grip_real_t r_mul(grip_real_t a, grip_real_t b) { return q16_mul(a, b); }
/* c + a b, c - a b: the product is not clamped on its own (q16_mac). The
 * bits of r_add(c, r_mul(a, b)), r_sub(c, r_mul(a, b)) wherever that
 * product stays in range; one range test instead of two. */
static inline grip_real_t r_mac(grip_real_t c, grip_real_t a, grip_real_t b) { return q16_mac(c, a, b); }
static inline grip_real_t r_msub(grip_real_t c, grip_real_t a, grip_real_t b) { return q16_msub(c, a, b); }
/* u b for a factor u the caller knows to be within [-1, 1] (a sine, a
 * cosine, the low-speed smooth factor, ...), with that argument in a
 * comment where it is used: the product cannot leave the range of b, so it
 * has no range test (q16_mul_unit; the debug-saturation build checks
 * |u| <= 1). */
static inline grip_real_t r_mul_unit(grip_real_t u, grip_real_t b) { return q16_mul_unit(u, b); }
/* x s for a scale factor s (a lambda of the parameter set, or a factor
 * formed from them) that is exactly 1 in most sets: no product when s = 1
 * (q16_mul_scale; the float build multiplies, one instruction). */
static inline grip_real_t r_mul_scale(grip_real_t x, grip_real_t s) { return q16_mul_scale(x, s); }
/* c + a b, c - a b, a b, a + b without a range test, for operands whose
 * ranges the caller has certified (the Magic Formula's prepared sets,
 * MF_PF_CERT); the debug-saturation build checks the result (q16_mac_nt) */
static inline grip_real_t r_mac_nt(grip_real_t c, grip_real_t a, grip_real_t b) { return q16_mac_nt(c, a, b); }
static inline grip_real_t r_msub_nt(grip_real_t c, grip_real_t a, grip_real_t b) { return q16_msub_nt(c, a, b); }
static inline grip_real_t r_mul_nt(grip_real_t a, grip_real_t b) { return q16_mul_nt(a, b); }
static inline grip_real_t r_add_nt(grip_real_t a, grip_real_t b) { return q16_add_nt(a, b); }
/* a / b where the caller knows 0 <= a <= b, b > 0: no zero or range test
 * (q16_div_le1; the debug-saturation build checks the precondition) */
static inline grip_real_t r_div_le1(grip_real_t a, grip_real_t b) { return q16_div_le1(a, b); }
/* a / b where the caller knows b != 0 and |a / b| < 32767: no zero or
 * range test (q16_div_nt; the debug-saturation build checks the
 * precondition) */
static inline grip_real_t r_div_nt(grip_real_t a, grip_real_t b) { return q16_div_nt(a, b); }
static inline grip_real_t r_div(grip_real_t a, grip_real_t b) { return q16_div(a, b); }
static inline grip_real_t r_div_keep(grip_real_t a, grip_real_t b) { return q16_div(a, b); }
static inline grip_real_t r_neg(grip_real_t a) { return q16_neg(a); }
static inline grip_real_t r_abs(grip_real_t a) { return q16_abs(a); }
static inline grip_real_t r_ql_to_qs(grip_real_t a) { return q16_from_ql(a); }
static inline grip_real_t r_qs_to_ql(grip_real_t a) { return q16_to_ql(a); }
static inline grip_real_t r_sqrt(grip_real_t a) { return grip_q16_sqrt(a); }
#if GRIP_Q16_INLINE_KERNELS
/* atan, atan2, sin, cos inline (q16_math_inline.h): grip_q16_*'s code */
static GRIP_Q16_KINLINE grip_real_t r_atan(grip_real_t a) { return q16_atan_k(a); }
static GRIP_Q16_KINLINE grip_real_t r_atan2(grip_real_t y, grip_real_t x) { return q16_atan2_k(y, x); }
/* atan2(y, x) where the caller knows y >= 0 and x > 0 (float build: see
 * there): without the sign tests (q16_atan2_q1_k; the debug-saturation
 * build checks the precondition) */
static GRIP_Q16_KINLINE grip_real_t r_atan2_q1(grip_real_t y, grip_real_t x) { return q16_atan2_q1_k(y, x); }
static GRIP_Q16_KINLINE grip_real_t r_sin(grip_real_t a) { return q16_sin_k(a); }
static GRIP_Q16_KINLINE grip_real_t r_cos(grip_real_t a) { return q16_cos_k(a); }
/* One argument reduction for both (grip_q16_sincos): the same bits as
 * grip_q16_sin and grip_q16_cos. */
static GRIP_Q16_KINLINE void r_sincos(grip_real_t a, grip_real_t *s, grip_real_t *c) { q16_sincos_k(a, s, c); }
#else
/* -Os: the out-of-line kernels of q16.c (the same code) */
static inline grip_real_t r_atan(grip_real_t a) { return grip_q16_atan(a); }
static inline grip_real_t r_atan2(grip_real_t y, grip_real_t x) { return grip_q16_atan2(y, x); }
static inline grip_real_t r_atan2_q1(grip_real_t y, grip_real_t x) { return grip_q16_atan2(y, x); }
static inline grip_real_t r_sin(grip_real_t a) { return grip_q16_sin(a); }
static inline grip_real_t r_cos(grip_real_t a) { return grip_q16_cos(a); }
static inline void r_sincos(grip_real_t a, grip_real_t *s, grip_real_t *c) { grip_q16_sincos(a, s, c); }
#endif
static inline grip_real_t r_exp(grip_real_t a) { return grip_q16_exp(a); }
static inline grip_real_t r_log(grip_real_t a) { return grip_q16_log(a); }
/* Every fixed-point value is finite by construction. */
static inline int r_is_finite(grip_real_t a) { (void)a; return 1; }
/* cos(atan(a)) = 1 / sqrt(1 + a^2) from a kernel of its own
 * (q16_cos_atan_k: no 1 + a^2, which would leave QS for |a| > 181), in
 * [0, 1]; out of line at -Os (grip_q16_i_cos_atan, the same code). */
#if GRIP_Q16_INLINE_KERNELS
static GRIP_Q16_KINLINE grip_real_t r_cos_atan(grip_real_t a) { return q16_cos_atan_k(a); }
#else
static inline grip_real_t r_cos_atan(grip_real_t a) { return grip_q16_i_cos_atan(a); }
#endif
/* c0 + c1 x and a / (b1 b2) - 1: see the float build. Q15.16 carries no
 * residual (its resolution is its own tolerance): the plain forms, 0. */
static inline grip_real_t r_lin_ext(grip_real_t c0, grip_real_t c1, grip_real_t x, grip_real_t x_lo)
{
    (void)x_lo;
    return q16_add(c0, q16_mul(c1, x));
}
static inline grip_real_t r_quot_m1_lo(grip_real_t a, grip_real_t b1, grip_real_t b2, grip_real_t q, grip_real_t d)
{
    (void)a; (void)b1; (void)b2; (void)q; (void)d;
    return R_ZERO;
}

#else /* float */
#include <math.h> /* grip-deviation: MISRA-20.1 float build only, inside the arithmetic selection #if */

#define RC(x)  ((grip_real_t)(x))
#define RCL(x) ((grip_real_t)(x))
#define R_ZERO (0.0f)
#define R_ONE  (1.0f)

static inline grip_real_t r_add(grip_real_t a, grip_real_t b) { return a + b; }
static inline grip_real_t r_sub(grip_real_t a, grip_real_t b) { return a - b; }
static inline grip_real_t r_mul(grip_real_t a, grip_real_t b) { return a * b; }
/* the plain operations, in the order the two-step forms had them */
static inline grip_real_t r_mac(grip_real_t c, grip_real_t a, grip_real_t b) { return c + a * b; }
static inline grip_real_t r_msub(grip_real_t c, grip_real_t a, grip_real_t b) { return c - a * b; }
static inline grip_real_t r_mul_unit(grip_real_t u, grip_real_t b) { return u * b; }
static inline grip_real_t r_mul_scale(grip_real_t x, grip_real_t s) { return x * s; }
static inline grip_real_t r_mac_nt(grip_real_t c, grip_real_t a, grip_real_t b) { return c + a * b; }
static inline grip_real_t r_msub_nt(grip_real_t c, grip_real_t a, grip_real_t b) { return c - a * b; }
static inline grip_real_t r_mul_nt(grip_real_t a, grip_real_t b) { return a * b; }
static inline grip_real_t r_add_nt(grip_real_t a, grip_real_t b) { return a + b; }
static inline grip_real_t r_div_le1(grip_real_t a, grip_real_t b) { return a / b; }
static inline grip_real_t r_div_nt(grip_real_t a, grip_real_t b) { return a / b; }
static inline grip_real_t r_div(grip_real_t a, grip_real_t b) { return a / b; }
static inline grip_real_t r_div_keep(grip_real_t a, grip_real_t b) { return a / b; }
static inline grip_real_t r_neg(grip_real_t a) { return -a; }
static inline grip_real_t r_abs(grip_real_t a) { return fabsf(a); }
static inline grip_real_t r_ql_to_qs(grip_real_t a) { return a; }
static inline grip_real_t r_qs_to_ql(grip_real_t a) { return a; }
/* Negative arguments give 0, as in the fixed build, never NaN. */
static inline grip_real_t r_sqrt(grip_real_t a) { return (a > 0.0f) ? sqrtf(a) : 0.0f; }
#if GRIP_FLOAT_KERNELS >= 1
/* grip's polynomial kernels (grip_config.h, GRIP_FLOAT_KERNELS) */
#include "f32_kernels.h" /* grip-deviation: MISRA-20.1 float build only, inside the kernel selection #if */
static inline grip_real_t r_atan(grip_real_t a) { return grip_kf_atan(a); }
static inline grip_real_t r_atan2(grip_real_t y, grip_real_t x) { return grip_kf_atan2(y, x); }
static inline grip_real_t r_atan2_q1(grip_real_t y, grip_real_t x) { return grip_kf_atan2_q1(y, x); }
#else
static inline grip_real_t r_atan(grip_real_t a) { return atanf(a); }
static inline grip_real_t r_atan2(grip_real_t y, grip_real_t x) { return atan2f(y, x); }
/* atan2(y, x) where the caller knows y >= 0 and x > 0 (finite or not, not
 * NaN): atanf of the quotient. fdlibm's atan2f (newlib's) is exactly that
 * in this quadrant - atanf(|y / x|), pi/2 where y / x > 2^60, which atanf
 * gives too - so on newlib the bits are atan2f's, without its tests of the
 * other quadrants and its second call (~40 Cortex-M4F instructions); a
 * correctly rounded atan2f (glibc) may differ from it by the rounding of
 * the quotient, within 1.5 ulp of atan(y / x). */
static inline grip_real_t r_atan2_q1(grip_real_t y, grip_real_t x) { return atanf(y / x); }
#endif
#if GRIP_FLOAT_KERNELS >= 2
static inline grip_real_t r_sin(grip_real_t a) { return grip_kf_sin(a); }
static inline grip_real_t r_cos(grip_real_t a) { return grip_kf_cos(a); }
static inline void r_sincos(grip_real_t a, grip_real_t *s, grip_real_t *c) { grip_kf_sincos(a, s, c); }
static inline grip_real_t r_exp(grip_real_t a) { return grip_kf_exp(a); }
#else
static inline grip_real_t r_sin(grip_real_t a) { return sinf(a); }
static inline grip_real_t r_cos(grip_real_t a) { return cosf(a); }
static inline void r_sincos(grip_real_t a, grip_real_t *s, grip_real_t *c) { *s = sinf(a); *c = cosf(a); }
static inline grip_real_t r_exp(grip_real_t a) { return expf(a); }
#endif
static inline grip_real_t r_log(grip_real_t a) { return (a > 0.0f) ? logf(a) : -1.0e30f; }
static inline int r_is_finite(grip_real_t a) { return isfinite(a) ? 1 : 0; }
/* cos(atan(a)) = 1 / sqrt(1 + a^2), exactly; a^2 = inf gives 0, as the
 * limit. One square root and a division instead of atanf and cosf. */
static inline grip_real_t r_cos_atan(grip_real_t a) { return 1.0f / sqrtf(1.0f + a * a); }

/* A quotient carried beyond single precision, for the few terms whose
 * parts cancel: in c0 + c1 x with c0 ~ -c1 x (a slip stiffness that falls
 * through zero with load, PKX1 + PKX2 dfz) one rounding of x (2^-24 of x)
 * becomes 2^-24 |c1 x| of a result near zero. d = q - 1 where q is the
 * float a / b1 / b2; r_quot_m1_lo is what d lacks of the exact a / (b1 b2)
 * - 1 (to ~2^-48 of it), r_lin_ext is c0 + c1 (x + x_lo) with one rounding
 * of c0 + c1 x. With a fused multiply-add (Cortex-M4F, M7, M33, Arm64) the
 * residuals are exact products: a - q b1 b2 from two fmaf, d's own rounding
 * (only where q < 0.5: for q >= 0.5, q - 1 is exact) by Fast2Sum with -1 as
 * the larger term. Without one (x86-64's baseline, Cortex-R4F/R5F) the
 * same residuals from Dekker's exact product in single precision
 * (r_prod_err), and c0 + c1 x with its product's and its sum's roundings
 * added back; exact while nothing overflows and nothing is contracted,
 * which without a fused multiply-add it cannot be. */
#if defined(__ARM_FEATURE_FMA) || defined(__FMA__)
static inline grip_real_t r_quot_m1_lo(grip_real_t a, grip_real_t b1, grip_real_t b2, grip_real_t q, grip_real_t d)
{
    float b = b1 * b2;
    float b_lo = fmaf(b1, b2, -b);           /* b1 b2 = b + b_lo exactly */
    float r = fmaf(-q, b_lo, fmaf(-q, b, a)); /* a - q b1 b2 */
    return (q - (d + 1.0f)) + r / b;
}
static inline grip_real_t r_lin_ext(grip_real_t c0, grip_real_t c1, grip_real_t x, grip_real_t x_lo)
{
    return fmaf(c1, x_lo, fmaf(c1, x, c0));
}
#else
/* a b - p exactly, p = fl(a b): Veltkamp's split of each factor into 12-bit
 * halves, whose products are exact (Dekker). */
static inline float r_prod_err(float a, float b, float p)
{
    float ca = 4097.0f * a;
    float cb = 4097.0f * b;
    float ah = ca - (ca - a);
    float bh = cb - (cb - b);
    float al = a - ah;
    float bl = b - bh;
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}
static inline grip_real_t r_quot_m1_lo(grip_real_t a, grip_real_t b1, grip_real_t b2, grip_real_t q, grip_real_t d)
{
    float b = b1 * b2;
    float b_lo = r_prod_err(b1, b2, b);
    float p = q * b;
    /* a - q b1 b2: q b is within a few roundings of a, so a - p is exact */
    float r = ((a - p) - r_prod_err(q, b, p)) - q * b_lo;
    return (q - (d + 1.0f)) + r / b;
}
static inline grip_real_t r_lin_ext(grip_real_t c0, grip_real_t c1, grip_real_t x, grip_real_t x_lo)
{
    float t = c1 * x;
    float s = c0 + t;
    float v = s - c0;
    float s_lo = (c0 - (s - v)) + (t - v);   /* c0 + t - s exactly (TwoSum) */
    return s + (s_lo + (r_prod_err(c1, x, t) + c1 * x_lo));
}
#endif
#endif

static inline grip_real_t r_min(grip_real_t a, grip_real_t b) { return (a < b) ? a : b; }
static inline grip_real_t r_max(grip_real_t a, grip_real_t b) { return (a > b) ? a : b; }
static inline grip_real_t r_clamp(grip_real_t x, grip_real_t lo, grip_real_t hi)
{
    return r_min(r_max(x, lo), hi);
}
static inline grip_real_t r_sq(grip_real_t a) { return r_mul(a, a); }
/* sign(a) as QS: -1, 0 or +1 */
static inline grip_real_t r_sign(grip_real_t a)
{
    return (a > R_ZERO) ? R_ONE : ((a < R_ZERO) ? r_neg(R_ONE) : R_ZERO);
}

/* a whole number as QS (|n| < 32768 in the fixed build: rates in Hz,
 * counts), exact in both builds */
static inline grip_real_t r_from_int(int32_t n)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)(n * 65536);
#else
    return (grip_real_t)n;
#endif
}

/* Linear interpolation in row[0..m] (m + 1 values at y = k / m) at y,
 * clamped to [0, 1]; the index is the truncated y m (exact in the fixed
 * build: y <= 2^16 and m < 32768). Shared by the brush model's pressure
 * tables and the estimator's force shape. */
static inline grip_real_t r_table_lerp(const grip_real_t *row, int32_t m, grip_real_t y)
{
    grip_real_t t;
    grip_real_t frac;
    int32_t j;
    y = r_clamp(y, R_ZERO, R_ONE);
#if GRIP_ARITH_FIXED
    t = y * m;
    j = t >> 16;
    if (j > m - 1) {
        j = m - 1;
    }
    frac = t - (j << 16);
#else
    t = y * (grip_real_t)m;
    j = (int32_t)t;
    if (j > m - 1) {
        j = m - 1;
    }
    frac = t - (grip_real_t)j;
#endif
    return r_add(row[j], r_mul(frac, r_sub(row[j + 1], row[j])));
}

#endif /* GRIP_ARITH_H */
