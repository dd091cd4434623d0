/*
 * mf89.c - 1989-style lateral Magic Formula with coefficients a0..a17
 * (seed 000, eqs. 3.1-3.9) and its identification constraints (3.10-3.16).
 * Equations, units and the re-derived signs: include/grip/grip_mf89.h and
 * docs/mf89-thermal.md. Written once in the arith.h operations, so the same
 * source builds the float and the fixed-point library.
 *
 * Numerics: the model runs with Fz in kN (QS) and angles in rad; forces are
 * kN until the final scaling to N (QL). B = BCD / (C D) is evaluated with
 * sin(2 atan u) = 2u / (1 + u^2), u = Fz / a4, so the load cancels and the
 * result stays finite (and exact) down to Fz = 0, where D = 0 gives Fy = Sv = 0.
 */
#include <stddef.h>

#include "grip/grip_mf89.h"
#include "arith.h"

#define RAD2DEG      RC(57.29577951)
#define TWO_RAD2DEG  RC(114.59155903)
#define KN           RCL(1000.0)

static int mf89_params_ok(const grip_mf89_params *p)
{
    const grip_real_t *a = p->a;
    grip_real_t fzmax_kn;
    grip_real_t gmax_deg;
    grip_real_t lin;
    int i;
    for (i = 0; i < GRIP_MF89_NCOEF; ++i) {
        if (!r_is_finite(a[i])) {
            return 0;
        }
    }
    if (!r_is_finite(p->fz_max) || !r_is_finite(p->alpha_max) || !r_is_finite(p->gamma_max)) {
        return 0;
    }
    if (!(p->fz_max > R_ZERO && p->fz_max <= RCL(30000.0))) {
        return 0;
    }
    if (!(p->alpha_max > R_ZERO && p->alpha_max <= RC(1.5))) {
        return 0;
    }
    if (!(p->gamma_max > R_ZERO && p->gamma_max <= RC(0.5))) {
        return 0;
    }
    if (!(a[0] >= RC(0.1) && a[0] < RC(2.0))) {            /* C */
        return 0;
    }
    if (!(a[3] > R_ZERO)) {                                  /* BCD > 0 */
        return 0;
    }
    fzmax_kn = r_div(p->fz_max, KN);
    gmax_deg = r_mul(RAD2DEG, p->gamma_max);
    /* a4 > 0 and u = Fz / a4 <= 128, so 1 + u^2 stays inside QS */
    if (!(a[4] > R_ZERO && r_mul(a[4], RC(128.0)) >= fzmax_kn)) {
        return 0;
    }
    /* D > 0: a1 Fz + a2 >= 1 N/kN at both ends of [0, fz_max] (it is linear) */
    lin = r_add(r_mul(a[1], fzmax_kn), a[2]);
    if (!(a[2] >= RC(1.0) && lin >= RC(1.0))) {
        return 0;
    }
    /* camber factors of D and BCD stay positive over |gamma| <= gamma_max */
    if (!(r_sub(R_ONE, r_mul(a[15], r_sq(gmax_deg))) >= RC(0.01))) {
        return 0;
    }
    if (!(r_sub(R_ONE, r_mul(a[5], gmax_deg)) > R_ZERO)) {
        return 0;
    }
    return 1;
}

grip_status_t grip_mf89_check_params(const grip_mf89_params *p)
{
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    return mf89_params_ok(p) ? GRIP_OK : GRIP_ERR_PARAM;
}

static grip_real_t clamp_sym(grip_real_t x, grip_real_t lim, grip_status_t *st)
{
    if (x > lim) {
        *st = GRIP_WARN_CLAMPED;
        return lim;
    }
    if (x < r_neg(lim)) {
        *st = GRIP_WARN_CLAMPED;
        return r_neg(lim);
    }
    return x;
}

grip_status_t grip_mf89_fy(const grip_mf89_params *p, grip_real_t alpha, grip_real_t fz,
                           grip_real_t gamma, grip_real_t *fy)
{
    const grip_real_t *a;
    grip_status_t st = GRIP_OK;
    grip_real_t fz_kn;
    grip_real_t g_deg;
    grip_real_t cam15;
    grip_real_t cam5;
    grip_real_t lin_d;
    grip_real_t d_kn;
    grip_real_t u;
    grip_real_t b;
    grip_real_t sh_deg;
    grip_real_t x;
    grip_real_t e;
    grip_real_t bx;
    grip_real_t arg;
    grip_real_t y;
    grip_real_t sv_kn;

    if (fy == NULL) {
        return GRIP_ERR_NULL;
    }
    *fy = R_ZERO;
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!r_is_finite(alpha) || !r_is_finite(fz) || !r_is_finite(gamma)) {
        return GRIP_ERR_INPUT;
    }
    if (!mf89_params_ok(p)) {
        return GRIP_ERR_PARAM;
    }
    a = p->a;
    alpha = clamp_sym(alpha, p->alpha_max, &st);
    gamma = clamp_sym(gamma, p->gamma_max, &st);
    if (fz < R_ZERO) {
        fz = R_ZERO;
        st = GRIP_WARN_CLAMPED;
    } else if (fz > p->fz_max) {
        fz = p->fz_max;
        st = GRIP_WARN_CLAMPED;
    } /* grip-deviation: MISRA-15.7 load in range: no clamping */

    fz_kn = r_div(fz, KN);
    g_deg = r_mul(RAD2DEG, gamma);
    cam15 = r_sub(R_ONE, r_mul(a[15], r_sq(g_deg)));
    cam5 = r_sub(R_ONE, r_mul(a[5], r_abs(g_deg)));

    /* D [kN] = Fz (a1 Fz + a2) / 1000 (1 - a15 gamma^2)           (3.5) */
    lin_d = r_add(r_mul(a[1], fz_kn), a[2]);
    d_kn = r_mul(r_mul(fz_kn, r_div(lin_d, RC(1000.0))), cam15);

    /* B [1/rad] = BCD / (C D) with BCD from (3.6), in per-rad units:
     * 2 a3 (180/pi) (1 - a5|gamma|) / (a4 (1 + u^2) C (a1 Fz + a2) (1 - a15 gamma^2)) */
    u = r_div(fz_kn, a[4]);
    b = r_mul(r_mul(r_div(a[3], lin_d), cam5), TWO_RAD2DEG);
    b = r_div(b, a[4]);
    b = r_div(b, r_add(R_ONE, r_sq(u)));
    b = r_div(b, a[0]);
    b = r_div(b, cam15);

    /* Sh [deg] = (a8 Fz + a9 + a10 gamma) Fz                       (3.8) */
    sh_deg = r_mul(r_add(r_add(r_mul(a[8], fz_kn), a[9]), r_mul(a[10], g_deg)), fz_kn);
    x = r_add(alpha, r_div(sh_deg, RAD2DEG));                      /* (3.3), rad */

    /* E = (a6 Fz + a7) (1 - (a16 gamma + a17) sgn(alpha + Sh))      (3.7) */
    e = r_mul(r_add(r_mul(a[6], fz_kn), a[7]),
              r_sub(R_ONE, r_mul(r_add(r_mul(a[16], g_deg), a[17]), r_sign(x))));

    /* (3.1) */
    bx = r_mul(b, x);
    arg = r_sub(bx, r_mul(e, r_sub(bx, r_atan(bx))));
    y = r_mul(d_kn, r_sin(r_mul(a[0], r_atan(arg))));

    /* Sv [kN] = Fz (a11 Fz + a12 + (a13 Fz + a14) gamma) / 1000     (3.9) */
    sv_kn = r_add(r_add(r_mul(a[11], fz_kn), a[12]), r_mul(r_add(r_mul(a[13], fz_kn), a[14]), g_deg));
    sv_kn = r_mul(fz_kn, r_div(sv_kn, RC(1000.0)));

    *fy = r_mul(r_add(y, sv_kn), KN);                              /* (3.2), QL [N] */
    return st;
}

grip_status_t grip_mf89_check_constraints(const grip_mf89_params *p, grip_real_t fz_lo,
                                          grip_real_t fz_hi, uint32_t *violated)
{
    const grip_real_t *a;
    grip_real_t lo;
    grip_real_t hi;
    grip_real_t gmax;
    grip_real_t fzs[2];
    grip_real_t sv;
    uint32_t m = 0u;
    int i;
    int j;

    if (violated == NULL) {
        return GRIP_ERR_NULL;
    }
    *violated = 0u;
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!r_is_finite(fz_lo) || !r_is_finite(fz_hi) || !(fz_lo > R_ZERO) || !(fz_hi >= fz_lo) ||
        fz_hi > RCL(30000.0)) {
        return GRIP_ERR_INPUT;
    }
    if (!mf89_params_ok(p)) {
        return GRIP_ERR_PARAM;
    }
    a = p->a;
    lo = r_div(fz_lo, KN);
    hi = r_div(fz_hi, KN);
    fzs[0] = lo;
    fzs[1] = hi;
    gmax = r_mul(RAD2DEG, p->gamma_max);

    if (!(a[0] > RC(1.0) && a[0] < RC(1.65))) {
        m |= GRIP_MF89_C_3_10;
    }
    /* E is bilinear in (Fz, gamma): its maximum is at a corner */
    for (i = 0; i < 2; ++i) {
        grip_real_t e0 = r_add(r_mul(a[6], fzs[i]), a[7]);
        for (j = 0; j < 4; ++j) {
            grip_real_t g = (j & 1) ? gmax : r_neg(gmax);
            grip_real_t s = (j & 2) ? R_ONE : r_neg(R_ONE);
            grip_real_t e = r_mul(e0, r_sub(R_ONE, r_mul(r_add(r_mul(a[16], g), a[17]), s)));
            if (!(e < R_ONE)) {
                m |= GRIP_MF89_C_3_11;
            }
        }
    }
    if (a[17] != R_ZERO) {
        m |= GRIP_MF89_C_3_12;
    }
    if (a[8] != R_ZERO || a[9] != R_ZERO || a[11] != R_ZERO || a[12] != R_ZERO) {
        m |= GRIP_MF89_C_3_13;
    }
    if (!(r_mul(r_abs(a[10]), hi) <= RC(0.1))) {
        m |= GRIP_MF89_C_3_14;
    }
    for (i = 0; i < 2; ++i) {
        sv = r_abs(r_add(r_mul(a[13], fzs[i]), a[14]));
        if (!(sv < RC(25.0))) {
            m |= GRIP_MF89_C_3_15;
        }
    }
    if (!(a[15] > R_ZERO)) {
        m |= GRIP_MF89_C_3_16;
    }
    *violated = m;
    return (m == 0u) ? GRIP_OK : GRIP_ERR_PARAM;
}
