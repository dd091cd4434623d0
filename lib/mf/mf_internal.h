/*
 * mf_internal.h - building blocks of the Magic Formula code in lib/mf.
 * Internal to lib/: not part of the public API.
 *
 * Every quantity handled here is normalized by the tyre's own load, so that
 * the fixed build stays inside Q15.16 and keeps the same relative
 * resolution at every load (docs/magic-formula-c.md, "Normalization"):
 *   forces        F / Fz           (a friction-like number, |.| < ~5)
 *   moments       M / (Fz * UNLOADED_RADIUS)
 *   lengths       l / UNLOADED_RADIUS (pneumatic trail t, arm s)
 *   stiffnesses   K / Fz           (per radian or per unit slip)
 *   load          Fz / FNOMIN, Fz / Fz0', dfz
 * All of them are QS values in the fixed build.
 */
#ifndef GRIP_MF_INTERNAL_H
#define GRIP_MF_INTERNAL_H

#include <stddef.h>
#include "arith.h"
#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#if GRIP_MF_LANES
#include "f32_kernels.h" /* the kernels' branch-free forms (mfk_*): only where the lanes are built */
#endif

/* Forces the inlining of the combined evaluation into grip_mf_eval,
 * mf_eval_core and mf_eval_core_use: each keeps one frame (no wrapper frame under
 * grip_mf_eval, whose worst-case stack the estimator's step adds to, and
 * the capture of the intermediates compiles away from grip_mf_eval); and
 * of the blocks and small helpers that the plain and the extended variants
 * of mf_eval.c share, so that each variant has the code of one caller
 * (-Os made mf_sin_curve, mf_atan_ratio, mf_mux calls once they had two:
 * +110 Cortex-M0+ instructions per grip_mf_eval). GCC and clang; other
 * compilers inline as they see fit (the stack budget is measured with
 * arm-none-eabi-gcc). */
#if defined(__GNUC__)
#define MF_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define MF_ALWAYS_INLINE inline
#endif

/* Keeps a function out of line (its frame apart from its caller's: see
 * mf_eval_core_use). */
#if defined(__GNUC__)
#define MF_NOINLINE __attribute__((noinline))
#else
#define MF_NOINLINE
#endif

/* Operating point shared by all parts of one evaluation. */
typedef struct {
    grip_real_t fz_ql;   /* Fz [N] (QL), after clamping                        */
    grip_real_t fz;      /* Fz / FNOMIN                                        */
    grip_real_t fzp;     /* Fz / Fz0' with Fz0' = LFZO * FNOMIN                 */
    grip_real_t dfz;     /* (Fz - Fz0') / Fz0'                       (4.E2a)   */
    grip_real_t dfz_lo;  /* what dfz lacks of the exact value (float; 0 fixed) */
    grip_real_t dpi;     /* (p - NOMPRES) / NOMPRES                  (4.E2b)   */
    grip_real_t kappa;   /* longitudinal slip (ISO)                            */
    grip_real_t alpha;   /* alpha* : alpha (MF-Tyre) or tan(alpha) (book)      */
    grip_real_t gamma;   /* gamma* : gamma (MF-Tyre) or sin(gamma)             */
    grip_real_t cosa;    /* cos'(alpha) = |Vcx| / Vc = |cos(alpha)|     (4.E6) */
    grip_real_t smooth;  /* low-speed factor of the shifts, t and Mzr:         */
                         /* 1 - 0.5 (1 + cos(pi Vx / VXLOW)) for |Vx| <= VXLOW */
    grip_real_t lmux_s;  /* LMUX*, LMUY* (4.E7)                                */
    grip_real_t lmuy_s;
    grip_real_t lmux_p;  /* LMUX', LMUY' (4.E8)                                */
    grip_real_t lmuy_p;
    grip_real_t gmux;    /* camber in mu_x (4.E13): gamma (times LGAX in 5.2); */
                         /* the book writes gamma, not gamma*, there too       */
    grip_real_t gx;      /* camber as it enters Fx, Fy, Mz: gamma* (MF 6.x),   */
    grip_real_t gy;      /* gamma* * LGAX / LGAY / LGAZ (MF 5.2)               */
    grip_real_t gz;
    grip_real_t ky_mu;   /* LKY / LMUY* (4.E40, 4.E45)                         */
    const grip_real_t *dp; /* the prepared set's pressure factors (MF_DP_*) at */
                         /* its default pressure; NULL: formed where used, at  */
                         /* dpi (a table in the frame would put 32 B on the    */
                         /* deepest stack path of grip_mf_eval_ext)            */
    int mf52;            /* FITTYP 5, 6, 21                                    */
    int book;            /* GRIP_MF_OPT_BOOK                                   */
} mf_op;

/* LKYC, LKZC (MF 6.x); 1 (MF 5.2). */
#define MF_KYC(p, op) ((op)->mf52 ? R_ONE : (p)->lkyc)
#define MF_KZC(p, op) ((op)->mf52 ? R_ONE : (p)->lkzc)

/* The pressure factors (4.E13, 4.E15, 4.E25, 4.E23, 4.E30, 4.E43, 4.E47):
 * polynomials in dpi alone, formed where used, or once per set for its
 * default pressure (grip_mf_prepare). Indices of mf_op.dp and
 * grip_mf_prepared.dp. */
#define MF_DP_PX_MU 0    /* 1 + PPX3 dpi + PPX4 dpi^2 (mu_x)                   */
#define MF_DP_PX_K  1    /* 1 + PPX1 dpi + PPX2 dpi^2 (Kxk)                    */
#define MF_DP_KYB   2    /* PKY1 (1 + PPY1 dpi) (Kya)                          */
#define MF_DP_KYD   3    /* 1 + PPY2 dpi (Kya)                                 */
#define MF_DP_PY_MU 4    /* 1 + PPY3 dpi + PPY4 dpi^2 (mu_y)                   */
#define MF_DP_PY_G  5    /* 1 + PPY5 dpi (Kyg0)                                */
#define MF_DP_PZ_T  6    /* 1 - PPZ1 dpi (Dt)                                  */
#define MF_DP_PZ_R  7    /* 1 + PPZ2 dpi (Dr)                                  */

/* The pressure factor idx at dpi: one expression each, used both where
 * the evaluation forms it and by grip_mf_prepare (so a prepared set's
 * factors are an unprepared evaluation's bit for bit). */
static inline grip_real_t mf_dp_form(const grip_mf_params *p, grip_real_t dpi, int idx)
{
    switch (idx) {
    case MF_DP_PX_MU:
        return r_add(R_ONE, r_mac(r_mul(p->ppx3, dpi), p->ppx4, r_sq(dpi)));
    case MF_DP_PX_K:
        return r_add(R_ONE, r_mac(r_mul(p->ppx1, dpi), p->ppx2, r_sq(dpi)));
    case MF_DP_KYB:
        return r_mul(p->pky1, r_mac(R_ONE, p->ppy1, dpi));
    case MF_DP_KYD:
        return r_mac(R_ONE, p->ppy2, dpi);
    case MF_DP_PY_MU:
        return r_add(R_ONE, r_mac(r_mul(p->ppy3, dpi), p->ppy4, r_sq(dpi)));
    case MF_DP_PY_G:
        return r_mac(R_ONE, p->ppy5, dpi);
    case MF_DP_PZ_T:
        return r_msub(R_ONE, p->ppz1, dpi);
    default:
        return r_mac(R_ONE, p->ppz2, dpi);   /* MF_DP_PZ_R */
    }
}

/* The pressure factor idx of an evaluation: the prepared one, or formed. */
static inline grip_real_t mf_dp(const grip_mf_params *p, const grip_real_t *dp, grip_real_t dpi, int idx)
{
    return (dp != NULL) ? dp[idx] : mf_dp_form(p, dpi, idx);
}

/* The use-mode bits of an evaluation (GRIP_MF_OPT_* of the set, switched
 * per call by grip_mf_eval_ext's GRIP_MF_USE_* bits). */
static inline uint32_t mf_mode_use(uint32_t opt, uint32_t use)
{
    uint32_t m = opt;
    if ((use & GRIP_MF_USE_TURN_SLIP) != 0u) {
        m |= GRIP_MF_OPT_TURN_SLIP;
    }
    if ((use & GRIP_MF_USE_NO_TURN_SLIP) != 0u) {
        m &= ~GRIP_MF_OPT_TURN_SLIP;
    }
    if ((use & GRIP_MF_USE_NO_LIMITS) != 0u) {
        m |= GRIP_MF_OPT_NO_LIMITS;
    }
    if ((use & GRIP_MF_USE_LIMITS) != 0u) {
        m &= ~GRIP_MF_OPT_NO_LIMITS;
    }
    return m;
}

/* Conventions of one evaluation. */
typedef struct {
    int zero;            /* Fz <= 0: all outputs are zero                      */
    int mirror;          /* mirror alpha, gamma, Fy, Mz                        */
    int sae;             /* SAE J670 output signs                              */
} mf_io;

/* Bounds of the guarded quotients (only reached by degenerate parameter
 * sets, e.g. a cornering stiffness of zero; never inside the valid range of
 * the shipped .tir files, which DEBUG_SAT tests check). */
#define MF_LIM_B     RC(1000.0)   /* stiffness factors B                        */
#define MF_LIM_SHIFT RC(10.0)     /* shifts expressed in radians (SHy, SVy/Kya) */
#define MF_LIM_G     RC(100.0)    /* combined-slip weights G / G0               */
#define MF_LIM_RATIO RC(1000.0)   /* other ratios of scale factors              */

#define MF_PI        RC(3.14159265358979)
#define MF_2_OVER_PI RC(0.636619772367581)

/* The operations of the coefficient terms: a coefficient of the set times
 * the load (dfz), the inclination (gamma* or gamma) or a sign, up to their
 * squares, and sums of such terms (docs/numerics.md, "Certified
 * operations"). cert, a constant in every caller: 1 in the evaluation of a
 * prepared set whose certificate holds (MF_PF_CERT), where the terms cannot
 * leave Q15.16 and so need no range test (r_mac_nt ...: the same bits), 0
 * elsewhere (the checked operations). The float build has one form. */
/* Whether the evaluations of a certified prepared set have copies of
 * their own with the certified operations (cert = 1): the fixed build where
 * it optimizes for speed (the Cortex-M0+ firmware at -Os keeps one copy,
 * the checked one; the float build has one form). */
#if GRIP_ARITH_FIXED
#if GRIP_Q16_INLINE_KERNELS
#define MF_CERT_PATH 1
#else
#define MF_CERT_PATH 0
#endif
#else
#define MF_CERT_PATH 0
#endif

#if GRIP_ARITH_FIXED
static MF_ALWAYS_INLINE grip_real_t mf_cmac(int cert, grip_real_t c, grip_real_t a, grip_real_t b) /* grip-deviation: MISRA-5.5 the float build's macro of this name: the #if's other branch */
{
    return cert ? r_mac_nt(c, a, b) : r_mac(c, a, b);
}

static MF_ALWAYS_INLINE grip_real_t mf_cmsub(int cert, grip_real_t c, grip_real_t a, grip_real_t b) /* grip-deviation: MISRA-5.5 the float build's macro of this name: the #if's other branch */
{
    return cert ? r_msub_nt(c, a, b) : r_msub(c, a, b);
}

static MF_ALWAYS_INLINE grip_real_t mf_cmul(int cert, grip_real_t a, grip_real_t b) /* grip-deviation: MISRA-5.5 the float build's macro of this name: the #if's other branch */
{
    return cert ? r_mul_nt(a, b) : r_mul(a, b);
}

static MF_ALWAYS_INLINE grip_real_t mf_cadd(int cert, grip_real_t a, grip_real_t b) /* grip-deviation: MISRA-5.5 the float build's macro of this name: the #if's other branch */
{
    return cert ? r_add_nt(a, b) : r_add(a, b);
}

static MF_ALWAYS_INLINE grip_real_t mf_csq(int cert, grip_real_t a) /* grip-deviation: MISRA-5.5 the float build's macro of this name: the #if's other branch */
{
    return cert ? r_mul_nt(a, a) : r_sq(a);
}
#else
/* one form in the float build; macros, as inline functions with the
 * unused cert they put 8 B more on the Cortex-M4F stack of the prepared
 * evaluation (tests/firmware/check.sh) */
#define mf_cmac(cert, c, a, b) ((void)(cert), r_mac((c), (a), (b)))
#define mf_cmsub(cert, c, a, b) ((void)(cert), r_msub((c), (a), (b)))
#define mf_cmul(cert, a, b) ((void)(cert), r_mul((a), (b)))
#define mf_cadd(cert, a, b) ((void)(cert), r_add((a), (b)))
#define mf_csq(cert, a) ((void)(cert), r_sq(a))
#endif

/* a / b, limited to +-lim (the sign of a / b, b = -0 counting as positive);
 * 0 / 0 = 0; a NaN stays NaN. Fixed build: no division (and so no
 * saturation) where the quotient would leave [-lim, lim], including
 * b == 0. Float build: the quotient first, and the tests only where it is
 * not within [-lim, lim] (an infinity or NaN included): one division and
 * one comparison on the common path instead of two divisions and three
 * comparisons (the lane form, mfk_div_lim, is the same selection without
 * branches). A quotient within the limit is the same division, a zero one
 * with its sign (0 / -2 = -0, where a test of a = 0 first gave +0); beyond
 * it the signed limit (fl(|a| / lim) and fl(|a / b|) order |b| and lim
 * alike but at a quotient within one rounding of lim, where either result
 * is lim to that rounding). */
static inline grip_real_t mf_div_lim(grip_real_t a, grip_real_t b, grip_real_t lim)
{
#if GRIP_ARITH_FIXED
    /* |b| <= |a| / lim as a product, and the quotient without q16_div's
     * zero and range tests (q16_div_lim: the values of r_abs, r_div) */
    return q16_div_lim(a, b, lim);
#else
    grip_real_t q = a / b;
    if (fabsf(q) <= lim) {
        return q;
    }
    if ((a == 0.0f) || (q != q)) {
        return (a == 0.0f) ? 0.0f : q;       /* 0 / 0 = 0; NaN in, NaN out */
    }
    return ((a < 0.0f) != (b < 0.0f)) ? -lim : lim;
#endif
}

/* sqrt(a^2 + b^2) without forming the squares of large values. */
static inline grip_real_t mf_hypot(grip_real_t a, grip_real_t b)
{
    grip_real_t x = r_abs(a);
    grip_real_t y = r_abs(b);
    grip_real_t t;
    if (x < y) {
        t = x;
        x = y;
        y = t;
    }
    if (x == R_ZERO) {
        return R_ZERO;
    }
    /* 0 <= y <= x, x > 0: t in [0, 1] and 1 + t^2 in [1, 2], neither
     * needs a range test (r_div_le1; r_mac_nt, whose result the
     * debug-saturation build checks) */
    t = r_div_le1(y, x);
    return r_mul(r_sqrt(r_mac_nt(R_ONE, t, t)), x);
}

/* ------------------------------------------------------------------------
 * The kernels the equations are written with (mf_equations.h), in two
 * forms chosen by mk, a constant in every caller (so that the test compiles
 * away):
 *  - mk NULL: the arithmetic layer's functions (r_atan ..., libm or grip's
 *    kernels as GRIP_FLOAT_KERNELS selects, the Q15.16 kernels in the fixed
 *    build) and mf_div_lim, mf_hypot, which branch where the result is known
 *    without a division (and in the fixed build never divide by zero): the
 *    scalar evaluations of mf_eval.c;
 *  - mk the address of a lane's range mark (where GRIP_MF_LANES is 1: the
 *    float build on a SIMD target, grip_mf_batch.h): the
 *    branch-free forms of f32_kernels.h (grip_kf_lane_*), which mark *mk
 *    where an argument leaves their range, and the guarded operations with
 *    every case formed and one selected: the lane evaluation of mf_lanes.c,
 *    a loop the compiler vectorizes.
 * Where *mk stays <= 0 the two forms give the same bits when the scalar
 * path runs on grip's kernels (GRIP_FLOAT_KERNELS=2; test_mf_lanes).
 */
static MF_ALWAYS_INLINE grip_real_t mfk_atan(grip_real_t x, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        return grip_kf_lane_atan(x);
    }
#endif
    (void)mk;
    return r_atan(x);
}

static MF_ALWAYS_INLINE grip_real_t mfk_atan2(grip_real_t y, grip_real_t x, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        return grip_kf_lane_atan2(y, x, mk);
    }
#endif
    (void)mk;
    return r_atan2(y, x);
}

static MF_ALWAYS_INLINE grip_real_t mfk_sin(grip_real_t x, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        return grip_kf_lane_sin(x, mk);
    }
#endif
    (void)mk;
    return r_sin(x);
}

static MF_ALWAYS_INLINE grip_real_t mfk_cos(grip_real_t x, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        return grip_kf_lane_cos(x, mk);
    }
#endif
    (void)mk;
    return r_cos(x);
}

/* sin and cos of one angle: one argument reduction in the scalar path */
static MF_ALWAYS_INLINE void mfk_sincos(grip_real_t x, grip_real_t *s, grip_real_t *c, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        *s = grip_kf_lane_sin(x, mk);
        *c = grip_kf_lane_cos(x, mk);
        return;
    }
#endif
    (void)mk;
    r_sincos(x, s, c);
}

static MF_ALWAYS_INLINE grip_real_t mfk_exp(grip_real_t x, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        return grip_kf_lane_exp(x, mk);
    }
#endif
    (void)mk;
    return r_exp(x);
}

/* mf_div_lim */
static MF_ALWAYS_INLINE grip_real_t mfk_div_lim(grip_real_t a, grip_real_t b, grip_real_t lim, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        float q = a / b;
        int within = fabsf(q) <= lim;
        int opp = (a < 0.0f) != (b < 0.0f);
        float beyond = (a == 0.0f) ? 0.0f : ((q != q) ? q : (opp ? -lim : lim));
        return within ? q : beyond;
    }
#endif
    (void)mk;
    return mf_div_lim(a, b, lim);
}

/* mf_hypot */
static MF_ALWAYS_INLINE grip_real_t mfk_hypot(grip_real_t a, grip_real_t b, grip_real_t *mk)
{
#if GRIP_MF_LANES
    if (mk != NULL) {
        float x = fabsf(a);
        float y = fabsf(b);
        int sw = x < y;
        float hi = sw ? y : x;
        float lo = sw ? x : y;
        float r = r_mul(r_sqrt(r_add(R_ONE, r_sq(lo / hi))), hi);
        return (hi == 0.0f) ? 0.0f : r;
    }
#endif
    (void)mk;
    return mf_hypot(a, b);
}

/* The argument of the Magic Formula's outer arctangent: B x - E (B x -
 * atan(B x)). */
static MF_ALWAYS_INLINE grip_real_t mf_shape_in_k(grip_real_t b, grip_real_t e, grip_real_t x, grip_real_t *mk)
{
    grip_real_t bx = r_mul(b, x);
    return r_msub(bx, e, r_sub(bx, mfk_atan(bx, mk)));
}

/* The argument of the Magic Formula: C * atan(B x - E (B x - atan(B x))).
 * C atan(.) is a certified term (cert: a constant, mf_cmul): |C| of each
 * curve (PCX1 LCX, PCY1 LCY, QCZ1, RCX1, RCY1) is within the certificate's
 * box, and |atan| <= pi/2. */
static MF_ALWAYS_INLINE grip_real_t mf_shape_eq(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                                grip_real_t *mk, int cert)
{
    return mf_cmul(cert, c, mfk_atan(mf_shape_in_k(b, e, x, mk), mk));
}

/* The scalar form: a function the compiler may keep out of line (-Os on
 * the Cortex-M0+ does: the curves are called a dozen times per evaluation);
 * _c: the certified one. */
static inline grip_real_t mf_shape(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    return mf_shape_eq(b, c, e, x, NULL, 0);
}

static inline grip_real_t mf_shape_c(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    return mf_shape_eq(b, c, e, x, NULL, 1);
}

static MF_ALWAYS_INLINE grip_real_t mf_shape_k(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                               grip_real_t *mk, int cert)
{
    if (mk != NULL) {
        return mf_shape_eq(b, c, e, x, mk, 0);
    }
    return cert ? mf_shape_c(b, c, e, x) : mf_shape(b, c, e, x);
}

/* D sin(C atan(B x - E (B x - atan(B x)))): the sine version (forces). */
static MF_ALWAYS_INLINE grip_real_t mf_sin_curve_k(grip_real_t b, grip_real_t c, grip_real_t d, grip_real_t e,
                                                   grip_real_t x, grip_real_t *mk, int cert)
{
    return r_mul_unit(mfk_sin(mf_shape_k(b, c, e, x, mk, cert), mk), d);   /* a sine: r_mul_unit */
}

static MF_ALWAYS_INLINE grip_real_t mf_sin_curve(grip_real_t b, grip_real_t c, grip_real_t d, grip_real_t e,
                                       grip_real_t x)
{
    return mf_sin_curve_k(b, c, d, e, x, NULL, 0);
}

/* cos(C atan(B x - E (B x - atan(B x)))): the cosine version (trail and
 * combined-slip weighting functions); a function of its own in the scalar
 * form, as mf_shape. */
static MF_ALWAYS_INLINE grip_real_t mf_cos_curve_eq(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                                    grip_real_t *mk, int cert)
{
    return mfk_cos(mf_shape_k(b, c, e, x, mk, cert), mk);
}

static inline grip_real_t mf_cos_curve(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    return mf_cos_curve_eq(b, c, e, x, NULL, 0);
}

static inline grip_real_t mf_cos_curve_c(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    return mf_cos_curve_eq(b, c, e, x, NULL, 1);
}

static MF_ALWAYS_INLINE grip_real_t mf_cos_curve_k(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                                   grip_real_t *mk, int cert)
{
    if (mk != NULL) {
        return mf_cos_curve_eq(b, c, e, x, mk, 0);
    }
    return cert ? mf_cos_curve_c(b, c, e, x) : mf_cos_curve(b, c, e, x);
}

/* atan(num / den) for num >= 0 and any den (den == 0 gives pi/2 for
 * num > 0), without forming the quotient: atan2 was in (pi/2, pi] where
 * den < 0. */
static MF_ALWAYS_INLINE grip_real_t mf_atan_ratio_k(grip_real_t num, grip_real_t den, grip_real_t *mk)
{
    grip_real_t a;
    if ((mk == NULL) && (den > R_ZERO)) {
        return r_atan2_q1(num, den);     /* the first quadrant (arith.h) */
    }
    a = mfk_atan2(num, den, mk);
    return (den < R_ZERO) ? r_sub(a, MF_PI) : a;
}

static MF_ALWAYS_INLINE grip_real_t mf_atan_ratio(grip_real_t num, grip_real_t den)
{
    return mf_atan_ratio_k(num, den, NULL);
}

/* sign with sign(0) = +1 (used where MF-Tyre replaces sign(0) by 1). */
static inline grip_real_t mf_sign1(grip_real_t a)
{
    return (a < R_ZERO) ? r_neg(R_ONE) : R_ONE;
}

/* Structural validity of a parameter set (cheap; done on every call);
 * _plain for grip_mf_eval and grip_mf_eval_pure, which refuse the use-mode
 * bits (turn slip, no limits: grip_mf_eval_ext's). */
int mf_params_usable(const grip_mf_params *p);
int mf_params_usable_plain(const grip_mf_params *p);

/* The option decisions of a prepared set (grip_mf_prepared.flags). */
#define MF_PF_MF52        0x01u  /* FITTYP 5, 6, 21                            */
#define MF_PF_BOOK        0x02u  /* GRIP_MF_OPT_BOOK                           */
#define MF_PF_SAE         0x04u  /* GRIP_MF_OPT_SAE                            */
#define MF_PF_KAPPA_BRAKE 0x08u  /* GRIP_MF_OPT_KAPPA_BRAKE                    */
#define MF_PF_MIRROR      0x10u  /* mirror alpha, gamma, Fy, Mz                */
#define MF_PF_DPI0_CLAMP  0x20u  /* the default pressure is outside the domain */
#define MF_PF_LMU_CONST   0x40u  /* LMUV = 0: LMU*, LMU', LKY / LMUY* constant */
#define MF_PF_CZ          0x80u  /* the vertical stiffness is formed (mf_ext_cz) */
#define MF_PF_RE          0x100u /* and Re's FNOMIN / (R0 Cz) is (mf_ext_cz)     */
#define MF_PF_RE_U        0x200u /* LONGVL > 4.2 m/s: |u| < 181 for every input  */
#define MF_PF_CERT        0x400u /* the coefficient terms cannot leave Q15.16  */
                                 /* (mf_cert_ok, the fixed build at -O2)       */
#define MF_PF_CERT_EXT    0x800u /* and those of the extended outputs' Re, Cx, */
                                 /* Cy, R0 <= 5000 m (mf_cert_ext_ok, mf_ext.c); */
                                 /* float build: R0, Cx, Cy (_ok_f)            */

/* The set has what the turn-slip equations divide by: PHYP1 > 0 (C_Hyp)
 * and 0 < QDRP1 < 2 (C_Drp, sin(pi/2 C_Drp) > 0). */
int mf_turn_slip_usable(const grip_mf_params *p);

/* grip_mf_check_params_detail's checks of p evaluated with the option bits
 * opts in place of p->options, accepting the bits of `accepted` (an option
 * bit outside it fails as "options"); p NULL: GRIP_ERR_NULL, *detail
 * cleared. */
#define mf_check_options GRIP_TYPED(grip_mf_i_check_options)
grip_status_t mf_check_options(const grip_mf_params *p, uint32_t opts, uint32_t accepted,
                               grip_check_detail_t *detail);

/* Re / R0 of MFeval's calculateRe at the operating point (kappa, vx as the
 * model takes them before the low-speed scaling, Fz / FNOMIN, dpi): the
 * fixed point with Omega = (1 + kappa) vx / Re (the spin not given). 0 when
 * it cannot be formed (no VERTICAL_STIFFNESS, no root). */
grip_real_t mf_rolling_radius(const grip_mf_params *p, grip_real_t kap, grip_real_t vx, grip_real_t fz,
                              grip_real_t dpi);

/* The vertical stiffness at a pressure as the extended outputs use it
 * (mf_ext.c): formed per call by mf_ext_cz_form, or once for a prepared
 * set's default pressure (grip_mf_prepared.r0czp, .re_k and the flags
 * MF_PF_CZ, MF_PF_RE), by the same function. */
typedef struct {
    grip_real_t r0czp;   /* R0 Cz0 (1 + PFZ1 dpi) [N], QL                      */
    grip_real_t re_k;    /* FNOMIN / (R0 Cz0 (1 + PFZ1 dpi)) with MF_PF_RE, else 0 */
    uint32_t flags;      /* MF_PF_CZ: VERTICAL_STIFFNESS > 0, Cz0 (1 + PFZ1 dpi) */
                         /* > 0 and both inside QL; MF_PF_RE: that and        */
                         /* FNOMIN / (R0 Cz) < 1000; MF_PF_RE_U               */
} mf_ext_cz;

#define mf_ext_cz_form GRIP_TYPED(grip_mf_i_ext_cz_form)
void mf_ext_cz_form(const grip_mf_params *p, grip_real_t dpi, mf_ext_cz *z);

#if MF_CERT_PATH
/* The certificate of the extended outputs' coefficient terms (MF_PF_CERT_EXT;
 * docs/numerics.md, "Certified operations") of a set whose evaluation's
 * certificate holds with the factor bound m (Q16.16 as int64, >= 1): the
 * terms of Re's deflection (BREFF, DREFF, FREFF times Fz / FNOMIN or an
 * arctangent) and the structural stiffnesses Cx, Cy (PCFX1, PCFX2 times dfz
 * and its square, PCFX3 times dpi; their product, and that times
 * LONGITUDINAL_STIFFNESS within MF_QL_MAX; PCFY* likewise), and R0 <= 5000 m
 * (Re = r R0 within QS with no range test). */
#define mf_cert_ext_ok GRIP_TYPED(grip_mf_i_cert_ext_ok)
int mf_cert_ext_ok(const grip_mf_params *p, int64_t m);
#endif
#if !GRIP_ARITH_FIXED
/* The float build's MF_PF_CERT_EXT: R0 <= 5000 m, and Cx and Cy
 * (ext_cstiff) within their formats' tests (mf_times_ql) for every input of
 * a set whose loads are clamped to fz_max (mf_ext.c); there the channels
 * skip those tests. */
#define mf_cert_ext_ok_f GRIP_TYPED(grip_mf_i_cert_ext_ok_f)
int mf_cert_ext_ok_f(const grip_mf_params *p, grip_real_t fz_max);
#endif

/* mu_x (4.E13) at dfz, dpi, the camber of mu_x and LMUX*. */
static MF_ALWAYS_INLINE grip_real_t mf_mux(const grip_mf_params *p, grip_real_t dfz, grip_real_t dpi, grip_real_t gmux,
                                 grip_real_t lmux_s)
{
    return r_mul_scale(r_mul(r_mul(r_mac(p->pdx1, p->pdx2, dfz),
                                   r_add(R_ONE, r_mac(r_mul(p->ppx3, dpi), p->ppx4, r_sq(dpi)))),
                             r_msub(R_ONE, p->pdx3, r_sq(gmux))),
                       lmux_s);
}

/* The same with its pressure factor already formed (MF_DP_PX_MU). */
static MF_ALWAYS_INLINE grip_real_t mf_mux_dp(const grip_mf_params *p, grip_real_t dfz, grip_real_t px_mu,
                                              grip_real_t gmux, grip_real_t lmux_s, int cert)
{
    return r_mul_scale(r_mul(r_mul(mf_cmac(cert, p->pdx1, p->pdx2, dfz), px_mu),
                             mf_cmsub(cert, R_ONE, p->pdx3, mf_csq(cert, gmux))),
                       lmux_s);
}

/* The part of the operating point (mf_op) the extended outputs use. */
typedef struct {
    grip_real_t fz_ql;   /* Fz [N] (QL); 0 when unloaded                       */
    grip_real_t fz;      /* Fz / FNOMIN                                        */
    grip_real_t fzp;     /* Fz / Fz0'                                          */
    grip_real_t dfz;
    grip_real_t dpi;
    grip_real_t gmux;    /* camber of mu_x, LMUX* (mu_x by mf_mux)             */
    grip_real_t lmux_s;
    int mf52;
} mf_ext_op;

/* What the extended outputs (mf_ext.c) take from one combined evaluation:
 * the operating point and the model's intermediate results, per unit load
 * (see the top of this file), in the model's frame (ISO-W, mirrored). */
typedef struct {
    mf_ext_op op;
    mf_io io;
    grip_real_t kxk;     /* Kxk / Fz                                           */
    grip_real_t kya;     /* Kya / Fz (at gamma*)                               */
    grip_real_t muy;     /* mu_y (at gamma*)                                   */
    grip_real_t t;       /* combined trail t / R0 (with LFZO, low speed)       */
    grip_real_t mzr;     /* combined residual moment Mzr / (Fz R0)             */
    grip_real_t fx;      /* combined Fx / Fz, Fy / Fz                          */
    grip_real_t fy;
    grip_real_t kap;     /* kappa (ISO, clamped, before the low-speed scaling), */
    grip_real_t gam;     /* gamma (ISO, mirrored, clamped), vx (clamped): the   */
    grip_real_t vx;      /* prepared evaluation's only (mf_eval_core_prepared) */
} mf_core;

/* grip_mf_eval with the use modes of `mode` (GRIP_MF_OPT_* bits, turn slip
 * included), and also the intermediates the extended outputs need into
 * *x (x->op and x->io whenever the status is not an error, also for
 * Fz <= 0, when the op holds Fz = 0; the rest only for Fz > 0), in two
 * variants the caller picks: mf_eval_core when neither mode nor the set
 * has a use mode (turn slip, no limits; the combined evaluation of
 * grip_mf_eval, bit for bit), mf_eval_core_use otherwise. The caller
 * calls them directly (no dispatching function between: its frame would
 * add to grip_mf_eval_ext's deepest stack path). spin: the turn slip and
 * the spin (not NULL); re: with turn slip and no given Omega,
 * mf_ts_radius(p, in, mode); else 0. */
grip_status_t mf_eval_core(const grip_mf_params *p, const grip_mf_input *in, uint32_t mode, grip_mf_output *out,
                           mf_core *x);
grip_status_t mf_eval_core_use(const grip_mf_params *p, const grip_mf_input *in, const grip_mf_spin *spin,
                               uint32_t mode, grip_real_t re, grip_mf_output *out, mf_core *x);
/* mf_eval_core with a prepared set (k->p not NULL, checked by the caller):
 * grip_mf_eval_prepared's evaluation, bit for bit, with the intermediates
 * and also the inputs as the model took them (x->kap, x->gam, x->vx: no
 * use mode, a prepared set has none). */
grip_status_t mf_eval_core_prepared(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                    mf_core *x);

/* Re / R0 at kappa, Vx, Fz and the pressure as mf_prepare takes them (with
 * the sign conventions of mode): the rolling radius of turn slip's estimate
 * of Omega (the spin from camber), 0 when it cannot be formed. The caller
 * of mf_eval_core_use forms it before the evaluation, not within it, so that
 * the iteration's stack does not add to the evaluation's frame (the
 * firmware's stack budget). The inputs are checked by the evaluation (a
 * result of refused inputs is not used). */
grip_real_t mf_ts_radius(const grip_mf_params *p, const grip_mf_input *in, uint32_t mode);

/* grip_mf_eval_prepared (pure: grip_mf_eval_pure_prepared) at every point
 * of in[0..n-1], the loop of grip_mf_eval_prepared_batch (mf_batch.c). */
#define mf_prepared_batch_scalar GRIP_TYPED(grip_mf_i_prepared_batch_scalar)
grip_status_t mf_prepared_batch_scalar(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                       grip_mf_output *out, grip_status_t *status, int pure);

/* x clamped to [-lim, lim]; *clamped set when it was outside. */
static inline grip_real_t mf_clamp_sym(grip_real_t x, grip_real_t lim, int *clamped)
{
    if (x > lim) {
        *clamped = 1;
        return lim;
    }
    if (x < r_neg(lim)) {
        *clamped = 1;
        return r_neg(lim);
    }
    return x;
}


#endif /* GRIP_MF_INTERNAL_H */
