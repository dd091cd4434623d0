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

/* Bounds of the guarded quotients (only reached by degenerate parameter
 * sets, e.g. a cornering stiffness of zero; never inside the valid range of
 * the shipped .tir files, which DEBUG_SAT tests check). */
#define MF_LIM_B     RC(1000.0)   /* stiffness factors B                        */
#define MF_LIM_SHIFT RC(10.0)     /* shifts expressed in radians (SHy, SVy/Kya) */
#define MF_LIM_G     RC(100.0)    /* combined-slip weights G / G0               */
#define MF_LIM_RATIO RC(1000.0)   /* other ratios of scale factors              */

#define MF_PI        RC(3.14159265358979)
#define MF_2_OVER_PI RC(0.636619772367581)

/* a / b, limited to +-lim; no division (and no saturation) when the
 * quotient would leave [-lim, lim], including b == 0. 0 / 0 = 0. */
static inline grip_real_t mf_div_lim(grip_real_t a, grip_real_t b, grip_real_t lim)
{
    grip_real_t aa = r_abs(a);
    if (aa == R_ZERO) {
        return R_ZERO;
    }
    if (r_abs(b) <= r_div(aa, lim)) {
        return ((a < R_ZERO) != (b < R_ZERO)) ? r_neg(lim) : lim;
    }
    return r_div(a, b);
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
    t = r_div(y, x);
    return r_mul(r_sqrt(r_add(R_ONE, r_sq(t))), x);
}

/* atan(num / den) for num >= 0 and any den (den == 0 gives pi/2 for
 * num > 0), without forming the quotient. */
static inline grip_real_t mf_atan_ratio(grip_real_t num, grip_real_t den)
{
    grip_real_t a = r_atan2(num, den);
    if (den < R_ZERO) {
        a = r_sub(a, MF_PI);   /* atan2 was in (pi/2, pi] */
    }
    return a;
}

/* The argument of the Magic Formula: C * atan(B x - E (B x - atan(B x))). */
static inline grip_real_t mf_shape(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    grip_real_t bx = r_mul(b, x);
    grip_real_t arg = r_sub(bx, r_mul(e, r_sub(bx, r_atan(bx))));
    return r_mul(c, r_atan(arg));
}

/* D sin(C atan(B x - E (B x - atan(B x)))): the sine version (forces). */
static inline grip_real_t mf_sin_curve(grip_real_t b, grip_real_t c, grip_real_t d, grip_real_t e,
                                       grip_real_t x)
{
    return r_mul(d, r_sin(mf_shape(b, c, e, x)));
}

/* cos(C atan(B x - E (B x - atan(B x)))): the cosine version (trail and
 * combined-slip weighting functions). */
static inline grip_real_t mf_cos_curve(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x)
{
    return r_cos(mf_shape(b, c, e, x));
}

/* sign with sign(0) = +1 (used where MF-Tyre replaces sign(0) by 1). */
static inline grip_real_t mf_sign1(grip_real_t a)
{
    return (a < R_ZERO) ? r_neg(R_ONE) : R_ONE;
}

/* Structural validity of a parameter set (cheap; done on every call). */
int mf_params_usable(const grip_mf_params *p);

#endif /* GRIP_MF_INTERNAL_H */
