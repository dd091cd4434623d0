/*
 * mf_equations.h - the equations of the steady-state Magic Formula (MF 5.2 /
 * PAC2002, MF 6.1 / 6.2), each written once, for the two evaluations built
 * from them: the scalar ones of mf_eval.c (both arithmetics, the use modes,
 * the extended outputs' capture) and the lane evaluation of mf_lanes.c (8
 * points side by side, float build, a loop the compiler vectorizes).
 * Internal to lib/mf: not part of the public API.
 *
 * Every block is an always-inline function on grip_real_t through the
 * arithmetic layer's names, per unit load (mf_internal.h), with its
 * equation numbers (Pacejka, Tyre and Vehicle Dynamics, 3rd ed., section
 * 4.3.2, "4.Exx"). Its transcendental functions and guarded quotients are
 * the kernel names of mf_internal.h (mfk_*, mf_*_k), whose form mk selects:
 * NULL in mf_eval.c, the scalar kernels; a lane's range mark in mf_lanes.c,
 * the branch-free kernels. The options are fields of the operating point
 * (op->mf52, op->book, op->dp) and arguments (ts, emax): each caller's
 * values, constants in the lane loop, so that what a lane does not need
 * compiles away there and the loop has no branch.
 *
 * What each caller writes itself is the order of the blocks and what is
 * not an equation of the model: mf_eval.c the input checks, clamps and
 * statuses as branches and early returns, the use modes (turn slip, no
 * limits, the book forms) and the function boundaries that keep the
 * firmware's stack budget; mf_lanes.c the same input handling as masks and
 * selections (a lane cannot return early), and the redo of a marked lane by
 * the scalar path. test_mf_lanes checks that the two stay equal bit for
 * bit (docs/magic-formula-c.md section 7.2).
 */
#ifndef GRIP_MF_EQUATIONS_H
#define GRIP_MF_EQUATIONS_H

#include "mf_internal.h"

/* Coefficients that MF 5.2 does not have (PKY5, PEY5, RBX3, RBY4, QDZ10,
 * QDZ11): zero for FITTYP 5, 6, 21 whatever the set holds. */
#define MF6_ONLY(op, coef) ((op)->mf52 ? R_ZERO : (coef))

/* The factors r_mul_unit (arith.h) may take, within [-1, 1] by
 * construction (a Q15.16 sine or cosine is within +-1: grip_q16_sin clamps
 * its polynomial to 1 before rounding):
 *   op->smooth  1, or 0.5 (1 - cos(pi rl)) with cos in [-1, 1] (mf_low_smooth);
 *   op->cosa    |cos alpha|, or 0;
 *   sines and cosines of a kernel, and the curves made of them: cos(C atan(.))
 *               (the trail), r_cos_atan (1 / sqrt(1 + x^2): in [0, 1] in both
 *               builds, a kernel of its own in the fixed build whose table
 *               never exceeds 1, checked by its generator). */

/* Pure longitudinal slip. */
typedef struct {
    grip_real_t fx0;     /* Fx0 / Fz                                           */
    grip_real_t kxk;     /* Kxk / Fz                                           */
} mf_long;

/* Pure lateral slip at one inclination. */
typedef struct {
    grip_real_t fy0;     /* Fy0 / Fz                                           */
    grip_real_t muy;
    grip_real_t kya;     /* Kya / Fz (per rad)                                 */
    grip_real_t shy;
    grip_real_t svy;     /* SVy / Fz                                           */
    grip_real_t by;
    grip_real_t cy;
} mf_lat;

/* Aligning-moment coefficients (pure slip). */
typedef struct {
    grip_real_t alpha_r; /* alpha_r = alpha* + SHf                   (4.E37)   */
    grip_real_t alpha_t; /* alpha_t = alpha* + SHt                   (4.E34)   */
    grip_real_t dt;      /* Dt / UNLOADED_RADIUS                               */
    grip_real_t bt;
    grip_real_t ct;
    grip_real_t et;
    grip_real_t br;
    grip_real_t dr;      /* Dr / (Fz * UNLOADED_RADIUS)                        */
} mf_trail;

/* The turn slip of one evaluation (mf_ts_begin, mf_ts_moment): the spin
 * and the zeta factors, each times what MFeval multiplies by it (zeta5
 * and zeta6 are formed where they act, mf_trail_coefs_x). */
typedef struct {
    grip_real_t u;       /* R0 phi: the spin (turn slip and camber), limited   */
                         /* to +-MF_TS_U_MAX                                   */
    grip_real_t ut;      /* R0 phit_e: the turn slip as MFeval processes it    */
    grip_real_t one_eg;  /* 1 - eps_gamma, eps_gamma = PECP1 (1 + PECP2 dfz)   */
    grip_real_t gabs;    /* |gamma| (the inclination, not gamma*)              */
    grip_real_t z1;      /* zeta1: Dx, SVx                            (4.105)  */
    grip_real_t z2;      /* zeta2: Dy, SVy, SVyg, DVyk, Dr's LRES term (4.77)  */
    grip_real_t z3;      /* zeta3: Kya                                 (4.79)  */
    grip_real_t shyp;    /* SHyp, the shift that replaces the camber shift of  */
                         /* Fy (MF 6.x)                                (4.80)  */
    grip_real_t cr;      /* Cr = zeta7 of the residual moment          (4.E46) */
    grip_real_t re;      /* in: Re / R0 for the estimate of Omega (mf_ts_radius), */
                         /* 0 when Omega is given or Re cannot be formed       */
    int camber;          /* GRIP_MF_OPT_TS_CAMBER                              */
} mf_ts;

/* ---------------------------------------------------------------- Fx0 */
static MF_ALWAYS_INLINE void mf_long_pure(const grip_mf_params *p, const mf_op *op, const mf_ts *ts,
                                          grip_real_t emax, grip_real_t *mk, int cert, mf_long *out)
{
    grip_real_t dfz = op->dfz;
    grip_real_t shx = r_mul_unit(op->smooth, r_mul_scale(mf_cmac(cert, p->phx1, p->phx2, dfz), p->lhx)); /* 4.E17 */
    grip_real_t kx = r_add(op->kappa, shx);                                          /* 4.E10 */
    grip_real_t cx = r_mul_scale(p->pcx1, p->lcx);                                        /* 4.E11 */
    grip_real_t mux = mf_mux_dp(p, dfz, mf_dp(p, op->dp, op->dpi, MF_DP_PX_MU), op->gmux, op->lmux_s,
                                 cert);                                                          /* 4.E13 */
    grip_real_t dx = (ts != NULL) ? r_mul(mux, ts->z1) : mux;                        /* 4.E12 */
    grip_real_t ex = r_mul_scale(r_mul(mf_cadd(cert, p->pex1,
                                               mf_cmac(cert, mf_cmul(cert, p->pex2, dfz), p->pex3, mf_csq(cert, dfz))),
                                       mf_cmsub(cert, R_ONE, p->pex4, r_sign(kx))),
                                 p->lex);                                                  /* 4.E14 */
    /* Kxk / Fz: the slip stiffness per unit load, so that Bx is formed
     * without dividing two loads (4.E15, 4.E16);
     * PKX1 + PKX2 dfz with dfz beyond single precision: it falls through
     * zero with load in some files (FSAE_Defaults: 50 - 80 dfz), where one
     * rounding of dfz alone moved Fx by 3e-6 Fz (r_lin_ext). */
    grip_real_t kx_per = r_mul(r_mul(r_mul(r_lin_ext(p->pkx1, p->pkx2, dfz, op->dfz_lo), mfk_exp(mf_cmul(cert, p->pkx3, dfz), mk)),
                                     mf_dp(p, op->dp, op->dpi, MF_DP_PX_K)),
                               p->lkx);
    grip_real_t bx = mfk_div_lim(kx_per, r_mul(cx, dx), MF_LIM_B, mk);                    /* 4.E16 */
    grip_real_t svx = r_mul_unit(op->smooth, r_mul_scale(r_mul_scale(mf_cmac(cert, p->pvx1, p->pvx2, dfz), p->lvx), op->lmux_p)); /* 4.E18 */
    if (ts != NULL) {
        svx = r_mul(svx, ts->z1);
    }
    ex = r_min(ex, emax);
    out->fx0 = r_add(mf_sin_curve_k(bx, cx, dx, ex, kx, mk, cert), svx);                        /* 4.E9 */
    out->kxk = kx_per;
}

/* ---------------------------------------------------------------- Fy0 */

/* The factors of the pure lateral force that do not depend on the
 * inclination: formed once per evaluation, shared by Fy0 at gamma* and, for
 * the aligning moment of MF 6.x, Fy0 at gamma = 0. */
typedef struct {
    grip_real_t kyb;     /* PKY1 (1 + PPY1 dpi)                                */
    grip_real_t kyd;     /* 1 + PPY2 dpi                                       */
    grip_real_t mub;     /* (PDY1 + PDY2 dfz)(1 + PPY3 dpi + PPY4 dpi^2)       */
    grip_real_t svb;     /* (PVY1 + PVY2 dfz) LVY LMUY'                        */
    grip_real_t shb;     /* (PHY1 + PHY2 dfz) LHY                              */
    grip_real_t eyb;     /* PEY1 + PEY2 dfz                                    */
    grip_real_t cy;      /* PCY1 LCY                                           */
} mf_lat_common;

static MF_ALWAYS_INLINE void mf_lat_common_init(const grip_mf_params *p, const mf_op *op, int cert, mf_lat_common *c)
{
    grip_real_t dfz = op->dfz;
    c->kyb = mf_dp(p, op->dp, op->dpi, MF_DP_KYB);
    c->kyd = mf_dp(p, op->dp, op->dpi, MF_DP_KYD);
    c->mub = r_mul(mf_cmac(cert, p->pdy1, p->pdy2, dfz), mf_dp(p, op->dp, op->dpi, MF_DP_PY_MU));
    c->svb = r_mul_scale(r_mul_scale(mf_cmac(cert, p->pvy1, p->pvy2, dfz), p->lvy), op->lmuy_p);
    c->shb = r_mul_scale(mf_cmac(cert, p->phy1, p->phy2, dfz), p->lhy);
    c->eyb = mf_cmac(cert, p->pey1, p->pey2, dfz);
    c->cy = r_mul_scale(p->pcy1, p->lcy);                                                              /* 4.E21 */
}

/* The load factor of Kya / Fz (4.E25) at the denominator den = (PKY2 + PKY5
 * gamma^2)(1 + PPY2 dpi): sin(PKY4 atan(Fz / Fz0' / den)) divided by Fz /
 * Fz0' (finite as Fz -> 0, where the sine is ~ PKY4 Fz / Fz0'). With PKY4 = 2
 * (PacejkaBook, FSAE; the MF 5.2 files, which have no PKY4 and read it as
 * 2) sin(2 atan(n / d)) / n = 2 d / (d^2 + n^2), exactly: a division for an
 * atan2 and a sin (the lanes form both and select). */
static MF_ALWAYS_INLINE grip_real_t mf_kya_sin(const grip_mf_params *p, const mf_op *op, grip_real_t den,
                                               grip_real_t *mk, int cert)
{
    grip_real_t k2;
    grip_real_t ks;
    if ((mk == NULL) && (p->pky4 != RC(2.0))) {
        return mfk_div_lim(mfk_sin(mf_cmul(cert, p->pky4, mf_atan_ratio_k(op->fzp, den, mk)), mk), op->fzp, MF_LIM_B, mk);
    }
    k2 = mfk_div_lim(r_mul(RC(2.0), den), r_mac(r_sq(den), op->fzp, op->fzp), MF_LIM_B, mk);
    if (mk == NULL) {
        return k2;
    }
    ks = mfk_div_lim(mfk_sin(mf_cmul(cert, p->pky4, mf_atan_ratio_k(op->fzp, den, mk)), mk), op->fzp, MF_LIM_B, mk);
    return (p->pky4 == RC(2.0)) ? k2 : ks;
}

/* Pure lateral force at inclination g (gamma*, scaled for MF 5.2), with the
 * turn slip of ts when not NULL; emax limits Ey. */
static MF_ALWAYS_INLINE void mf_lat_body(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c,
                                         grip_real_t g, const mf_ts *ts, grip_real_t emax, grip_real_t *mk,
                                         int cert, mf_lat *out)
{
    grip_real_t dfz = op->dfz;
    grip_real_t g2 = mf_csq(cert, g);
    /* Cornering stiffness (4.E25); the arctangent of a quotient whose
     * denominator PKY2 + PKY5 gamma^2 may pass through zero. */
    grip_real_t den = r_mul(mf_cmac(cert, p->pky2, MF6_ONLY(op, p->pky5), g2), c->kyd);
    /* Kya / Fz = PKY1 (Fz0' / Fz) sin(PKY4 atan(...)) (...) (mf_kya_sin) */
    grip_real_t kya = r_mul_scale(r_mul(r_mul(c->kyb, mf_cmsub(cert, R_ONE, p->pky3, r_abs(g))), mf_kya_sin(p, op, den, mk, cert)),
                                  p->lky);
    grip_real_t muy = r_mul_scale(r_mul(c->mub, mf_cmsub(cert, R_ONE, p->pdy3, g2)), op->lmuy_s);         /* 4.E23 */
    grip_real_t dy = muy;                                                                         /* 4.E22 */
    grip_real_t svyg = r_mul_scale(r_mul_scale(mf_cmul(cert, mf_cmac(cert, p->pvy3, p->pvy4, dfz), g), MF_KYC(p, op)),
                                   op->lmuy_p); /* 4.E28 */
    grip_real_t svb = c->svb;
    grip_real_t svy;
    grip_real_t shy = c->shb;
    grip_real_t ay;
    grip_real_t cy = c->cy;
    grip_real_t ey;
    grip_real_t by;
    if (ts != NULL) {
        /* turn slip: Kya times zeta3, Dy, SVy (with SVyg) times zeta2 */
        kya = r_mul(kya, ts->z3);
        dy = r_mul(dy, ts->z2);
        svyg = r_mul(svyg, ts->z2);
        svb = r_mul(svb, ts->z2);
    }
    svy = r_add(svb, svyg);                                                                       /* 4.E29 */
    if (op->mf52) {
        /* MF 5.2: camber shift PHY3 * gamma_y (MFeval keeps it with turn
         * slip: SHyp does not enter the MF 5.2 shift). */
        shy = r_mac(shy, p->phy3, g);
    } else if (ts != NULL) {
        /* 4.E27 with zeta0 = 0, zeta4 = 1 + SHyp - SVyg / Kya' (4.84): the
         * turn-slip shift replaces the camber shift */
        shy = r_add(shy, r_sub(ts->shyp, mfk_div_lim(svyg, kya, MF_LIM_SHIFT, mk)));
    } else {
        /* MF 6.x: the camber shift follows from the camber stiffness Kyg0
         * (4.E30) and SVyg (4.E27). */
        grip_real_t kyg0 = r_mul_scale(r_mul(mf_cmac(cert, p->pky6, p->pky7, dfz), mf_dp(p, op->dp, op->dpi, MF_DP_PY_G)), MF_KYC(p, op));
        shy = r_add(shy, mfk_div_lim(r_sub(r_mul(kyg0, g), svyg), kya, MF_LIM_SHIFT, mk));
    }
    /* Low speed: the shifts fade out with the speed. */
    shy = r_mul_unit(op->smooth, shy);
    svy = r_mul_unit(op->smooth, svy);
    ay = r_add(op->alpha, shy);                                                                   /* 4.E20 */
    ey = r_mul_scale(r_mul(c->eyb,
                           mf_cmsub(cert, mf_cmac(cert, R_ONE, MF6_ONLY(op, p->pey5), g2),
                                    mf_cmac(cert, p->pey3, p->pey4, g), mf_sign1(ay))),
                     p->ley);                                                                           /* 4.E24 */
    ey = r_min(ey, emax);
    by = mfk_div_lim(kya, r_mul(cy, dy), MF_LIM_B, mk);                                                /* 4.E26 */
    out->fy0 = r_add(mf_sin_curve_k(by, cy, dy, ey, ay, mk, cert), svy);                                      /* 4.E19 */
    out->muy = muy;
    out->kya = kya;
    out->shy = shy;
    out->svy = svy;
    out->by = by;
    out->cy = cy;
}

/* ------------------------------------------------- Mz0 coefficients */
static MF_ALWAYS_INLINE void mf_trail_body(const grip_mf_params *p, const mf_op *op, const mf_lat *lat,
                                           grip_real_t emax, grip_real_t *mk, int cert, mf_trail *out)
{
    grip_real_t dfz = op->dfz;
    grip_real_t g = op->gz;
    grip_real_t ga = r_abs(g);
    grip_real_t ky_mu = op->ky_mu;                                          /* LKY / LMUY* */
    grip_real_t sht = mf_cmac(cert, mf_cmac(cert, p->qhz1, p->qhz2, dfz), mf_cmac(cert, p->qhz3, p->qhz4, dfz), g);
    /* grip-deviation: clang-analyzer-core.CallAndMessage false positive: the evaluations write every field of *lat (mf_lat_pure) before the trail (the analyzer stops following mf_lat_body) */
    grip_real_t shf = r_add(lat->shy, mfk_div_lim(lat->svy, lat->kya, MF_LIM_SHIFT, mk));              /* 4.E38 */
    grip_real_t dt_cam;
    grip_real_t bt_cam;
    grip_real_t dt;
    grip_real_t bt;
    grip_real_t et;
    grip_real_t dr_cam;
    grip_real_t dr;
    if (op->book && !op->mf52) {
        /* Book 6.1: |gamma*| in Dt (4.E43) and QBZ5 |gamma*| + QBZ6 gamma*^2 in Bt (4.E40). */
        dt_cam = mf_cadd(cert, R_ONE, mf_cmac(cert, mf_cmul(cert, p->qdz3, ga), p->qdz4, mf_csq(cert, g)));
        bt_cam = mf_cadd(cert, R_ONE, mf_cmac(cert, mf_cmul(cert, p->qbz5, ga), p->qbz6, mf_csq(cert, g)));
    } else {
        /* MF-Tyre (and MF 5.2): QDZ3 gamma, QBZ4 gamma + QBZ5 |gamma|. */
        dt_cam = mf_cadd(cert, R_ONE, mf_cmac(cert, mf_cmul(cert, p->qdz3, g), p->qdz4, mf_csq(cert, g)));
        bt_cam = mf_cadd(cert, R_ONE, mf_cmac(cert, mf_cmul(cert, p->qbz4, g), p->qbz5, ga));
    }
    /* Dt / R0 = (Fz / Fz0') (QDZ1 + QDZ2 dfz)(1 - PPZ1 dpi) (...) LTR  (4.E42-43) */
    dt = r_mul_scale(r_mul(r_mul(r_mul(op->fzp, mf_cmac(cert, p->qdz1, p->qdz2, dfz)), mf_dp(p, op->dp, op->dpi, MF_DP_PZ_T)),
                           dt_cam),
                     p->ltr);
    bt = r_mul_scale(r_mul(mf_cadd(cert, p->qbz1, mf_cmac(cert, mf_cmul(cert, p->qbz2, dfz), p->qbz3, mf_csq(cert, dfz))),
                           bt_cam),
                     ky_mu);
    out->alpha_t = r_add(op->alpha, sht);                                                        /* 4.E34 */
    out->alpha_r = r_add(op->alpha, shf);                                                        /* 4.E37 */
    out->ct = p->qcz1;                                                                           /* 4.E41 */
    et = r_mul(mf_cadd(cert, p->qez1, mf_cmac(cert, mf_cmul(cert, p->qez2, dfz), p->qez3, mf_csq(cert, dfz))),
               r_mac(R_ONE, r_mul(mf_cmac(cert, p->qez4, p->qez5, g), MF_2_OVER_PI),
                     mfk_atan(r_mul(r_mul(bt, out->ct), out->alpha_t), mk)));            /* 4.E44 */
    out->et = r_min(et, emax);
    out->dt = dt;
    out->bt = bt;
    out->br = r_mac(r_mul_scale(p->qbz9, ky_mu), r_mul(p->qbz10, lat->by), lat->cy);            /* 4.E45 */
    /* Dr / (Fz R0)                                                         (4.E47) */
    dr_cam = r_mul_scale(r_mul(r_mac(r_mul(mf_cmac(cert, p->qdz8, p->qdz9, dfz), mf_dp(p, op->dp, op->dpi, MF_DP_PZ_R)),
                                     mf_cmac(cert, MF6_ONLY(op, p->qdz10), MF6_ONLY(op, p->qdz11), dfz), ga),
                               g),
                         MF_KZC(p, op));
    dr = r_mul_scale(r_mac(dr_cam, mf_cmac(cert, p->qdz6, p->qdz7, dfz), p->lres), op->lmuy_s);
    /* sgn(Vcx) cos'(alpha), with |Vx| for Vx (see mf_prepare). */
    out->dr = r_mul_unit(op->cosa, dr);
}

/* Trail t / R0 at a (possibly equivalent) trail slip angle a (4.E33, 4.E73). */
static MF_ALWAYS_INLINE grip_real_t mf_trail_at_k(const mf_op *op, const mf_trail *tc, grip_real_t a, grip_real_t *mk,
                                                  int cert)
{
    /* the curve first, then |cos alpha| (the old order: reading op->cosa
     * before the curve's call made gcc pass it apart, and the Cortex-M4F
     * frame of the combined evaluation 8 B larger) */
    grip_real_t t = r_mul_unit(mf_cos_curve_k(tc->bt, tc->ct, tc->et, a, mk, cert), tc->dt);
    return r_mul_unit(op->cosa, t);
}

/* Residual moment Mzr / (Fz R0) at a residual slip angle a, Cr = 1 (4.E36). */
static MF_ALWAYS_INLINE grip_real_t mf_residual_at_k(const mf_trail *tc, grip_real_t a)
{
    return r_mul_unit(r_cos_atan(r_mul(tc->br, a)), tc->dr);
}

/* The cosine curve of a combined-slip weighting function: with C = 1
 * (PacejkaBook, FSAE: RCY1 = 1), cos(atan(u)) = 1 / sqrt(1 + u^2)
 * (r_cos_atan: one square root and a division for an atan and a cos);
 * otherwise mf_cos_curve. The lanes select between the two. */
static MF_ALWAYS_INLINE grip_real_t mf_g_curve_k(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                                 grip_real_t *mk, int cert)
{
    if (mk != NULL) {
        grip_real_t u = mf_shape_in_k(b, e, x, mk);
        grip_real_t g1 = r_cos_atan(u);
        grip_real_t gc = mfk_cos(r_mul(c, mfk_atan(u, mk)), mk);
        return (c == R_ONE) ? g1 : gc;
    }
    if (c == R_ONE) {
        return r_cos_atan(mf_shape_in_k(b, e, x, NULL));
    }
    return cert ? mf_cos_curve_c(b, c, e, x) : mf_cos_curve(b, c, e, x);
}

/* A combined-slip weighting function G = cos(C atan(B x - E (B x - atan(B
 * x)))) / (the same at x = sh): the curve at the slip x (mf_g_curve_k),
 * normalized by its value at the shift sh (4.E51-52, 4.E59-60). The scalar
 * path (mk NULL) skips the kernels where their result is known exactly:
 * cos(C atan(0)) = 1 at a zero shift (B 0 and atan(0) are zeros, cos of a
 * zero is 1 in every kernel: libm, GRIP_FLOAT_KERNELS, Q15.16; 1 / sqrt(1)
 * with C = 1), cos(0 atan(.)) = 1 when C = 0 (MF 5.2 fits that switch a
 * weighting off), and at x equal to sh (zero slip) the numerator is the
 * normalization itself: the same bits as the curves evaluated, two atan
 * and a cos fewer each. The lanes form both curves (no branch; the same
 * bits). */
static MF_ALWAYS_INLINE grip_real_t mf_g_ratio_k(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t x,
                                                 grip_real_t sh, grip_real_t *mk, int cert)
{
    grip_real_t g;
    grip_real_t g0;
    if (mk != NULL) {
        g = mf_g_curve_k(b, c, e, x, mk, 0);
        g0 = mf_g_curve_k(b, c, e, sh, mk, 0);
    } else if (c == R_ZERO) {
        g = R_ONE;
        g0 = R_ONE;
    } else {
        g0 = (sh == R_ZERO) ? R_ONE : mf_g_curve_k(b, c, e, sh, NULL, cert);
        g = (x == sh) ? g0 : mf_g_curve_k(b, c, e, x, NULL, cert);
    }
    return mfk_div_lim(g, g0, MF_LIM_G, mk);
}

/* Combined-slip weighting function of Fy (4.E59-E65) at inclination g. */
static MF_ALWAYS_INLINE grip_real_t mf_gyk_body(const grip_mf_params *p, const mf_op *op, grip_real_t g,
                                                grip_real_t emax, grip_real_t *mk, int cert)
{
    grip_real_t shyk = mf_cmac(cert, p->rhy1, p->rhy2, op->dfz);                                   /* 4.E65 */
    grip_real_t eyk = r_min(mf_cmac(cert, p->rey1, p->rey2, op->dfz), emax);     /* 4.E64 */
    grip_real_t byk = r_mul_scale(r_mul_unit(r_cos_atan(r_mul(p->rby2, r_sub(op->alpha, p->rby3))),
                                             mf_cmac(cert, p->rby1, MF6_ONLY(op, p->rby4), mf_csq(cert, g))),
                                  p->lyka);                                                             /* 4.E62 */
    grip_real_t ks = r_add(op->kappa, shyk);                                                      /* 4.E61 */
    return mf_g_ratio_k(byk, p->rcy1, eyk, ks, shyk, mk, cert);                                         /* 4.E59-60 */
}

/* ------------------------------------------------- Mz0 and combined slip */

/* Magnitude of the equivalent slip angle of the combined aligning moment
 * (4.E77-78). MF-Tyre: atan(sqrt(tan^2 a + (Kxk/Kya)^2 kappa^2)), written as
 * an atan2 of products so that neither tan(pi/2) nor Kya = 0 divides by
 * zero; book: sqrt(a^2 + (Kxk/Kya)^2 kappa^2). The equations multiply by
 * sgn(a), but both users (the trail's cosine curve at a fixed Et and
 * cos(atan(Br x))) are even in the angle, so only the magnitude matters. The
 * one place where the sign would act, sgn(0) = 0 at a = 0 exactly, makes the
 * equivalent angle jump from atan(|Kxk kappa / Kya|) to 0; grip keeps the
 * continuous value there (docs/magic-formula-c.md). book: op->book; kappa:
 * op->kappa (passed as values: the scalar caller, mf_alpha_eq, then takes
 * them in registers, as IPA-SRA made it do before; passing op put 8 B more
 * on the Cortex-M4F stack of mf_eval_core). */
static MF_ALWAYS_INLINE grip_real_t mf_alpha_eq_k(int book, grip_real_t kappa, grip_real_t a, grip_real_t kxk,
                                                  grip_real_t kya, grip_real_t *mk)
{
    if (book) {
        return mfk_hypot(a, mfk_div_lim(r_mul(kxk, kappa), kya, MF_LIM_RATIO, mk), mk);
    } else {
        grip_real_t sa;
        grip_real_t ca;
        grip_real_t num;
        grip_real_t den;
        mfk_sincos(a, &sa, &ca, mk);
        num = mfk_hypot(r_mul_unit(sa, kya), r_mul_unit(ca, r_mul(kxk, kappa)), mk);
        den = r_abs(r_mul_unit(ca, kya));
        /* num >= 0: where den > 0 the first quadrant's atan2 (arith.h) */
        return ((mk == NULL) && (den > R_ZERO)) ? r_atan2_q1(num, den) : mfk_atan2(num, den, mk);
    }
}

/* Mz0 = -t0 Fy0 + Mzr0 (4.E31-E36) from the trail t0 at alpha_t and the
 * residual moment Mzr0 at alpha_r (mf_trail_at_k, mf_residual_at_k): Mzr0
 * times cos'(alpha) (Dr carries a cos(alpha) of its own, 4.E47), MF-Tyre's
 * trail times LFZO; fy_ref is Fy0 at gamma = 0 (MF 6.x: camber acts on Mz
 * through Mzr) or Fy0 itself (MF 5.2). */
static MF_ALWAYS_INLINE grip_real_t mf_mz0(const grip_mf_params *p, const mf_op *op, grip_real_t t0, grip_real_t mzr0,
                                           grip_real_t fy_ref)
{
    grip_real_t mz0;
    if (!op->book) {
        t0 = r_mul_scale(t0, p->lfzo);   /* MF-Tyre scales the trail by LFZO */
    }
    mz0 = r_msub(r_mul_unit(op->cosa, mzr0), t0, fy_ref);                           /* 4.E31 */
    return r_mul_unit(op->smooth, mz0);                                              /* low speed */
}

/* Fx's weighting function Gxa (4.E51-E57): Fx = Gxa Fx0. */
static MF_ALWAYS_INLINE grip_real_t mf_gxa(const grip_mf_params *p, const mf_op *op, grip_real_t emax,
                                           grip_real_t *mk, int cert)
{
    grip_real_t bxa = r_mul_scale(r_mul_unit(r_cos_atan(mf_cmul(cert, p->rbx2, op->kappa)),
                                             mf_cmac(cert, p->rbx1, MF6_ONLY(op, p->rbx3), mf_csq(cert, op->gx))),
                                  p->lxal);                                                             /* 4.E54 */
    grip_real_t exa = r_min(mf_cmac(cert, p->rex1, p->rex2, op->dfz), emax);                       /* 4.E56 */
    grip_real_t as = r_add(op->alpha, p->rhx1);                                                    /* 4.E53 */
    return mf_g_ratio_k(bxa, p->rcx1, exa, as, p->rhx1, mk, cert);                                      /* 4.E51-52 */
}

/* The factors of SVyk (4.E66-E67) other than mu_y. */
typedef struct {
    grip_real_t dvy;     /* RVY1 + RVY2 dfz + RVY3 gamma*                      */
    grip_real_t dva;     /* cos(atan(RVY4 alpha*))                             */
    grip_real_t svk;     /* sin(RVY5 atan(RVY6 kappa))                         */
} mf_svyk_f;

static MF_ALWAYS_INLINE void mf_svyk_factors(const grip_mf_params *p, const mf_op *op, grip_real_t *mk, int cert,
                                             mf_svyk_f *f)
{
    f->dvy = mf_cmac(cert, mf_cmac(cert, p->rvy1, p->rvy2, op->dfz), p->rvy3, op->gy);
    f->dva = r_cos_atan(r_mul(p->rvy4, op->alpha));
    f->svk = mfk_sin(mf_cmul(cert, p->rvy5, mfk_atan(mf_cmul(cert, p->rvy6, op->kappa), mk)), mk);
}

/* DVyk = mu_y (RVY1 + RVY2 dfz + RVY3 gamma*) cos(atan(RVY4 alpha*)) (4.E67) */
static MF_ALWAYS_INLINE grip_real_t mf_dvyk(grip_real_t muy, const mf_svyk_f *f)
{
    return r_mul_unit(f->dva, r_mul(muy, f->dvy));
}

/* SVyk = DVyk sin(RVY5 atan(RVY6 kappa)) LVYKA (4.E66), fading at low speed */
static MF_ALWAYS_INLINE grip_real_t mf_svyk(const grip_mf_params *p, const mf_op *op, const mf_svyk_f *f,
                                            grip_real_t dvyk)
{
    return r_mul_unit(op->smooth, r_mul_scale(r_mul_unit(f->svk, dvyk), p->lvyka));
}

/* The moment arm s / R0 of Fx in Mz (4.E76): SSZ1 + SSZ2 Fy / Fz0 + (SSZ3 +
 * SSZ4 dfz) gamma*, LS; MF-Tyre uses FNOMIN for Fz0, the book Fz0'. fy: Fy / Fz. */
static MF_ALWAYS_INLINE grip_real_t mf_sarm(const grip_mf_params *p, const mf_op *op, grip_real_t fy, int cert)
{
    grip_real_t fy_rel = r_mul(fy, op->book ? op->fzp : op->fz);
    return r_mul_scale(r_mac(r_mac(p->ssz1, p->ssz2, fy_rel), mf_cmac(cert, p->ssz3, p->ssz4, op->dfz), op->gz),
                       p->ls);
}

/* The combined trail t and residual moment Mzr as they enter Mz: the book
 * keeps cos'(alpha) in Mzr, MF-Tyre scales the trail by LFZO; both fade at
 * low speed. */
static MF_ALWAYS_INLINE void mf_mz_scale(const grip_mf_params *p, const mf_op *op, grip_real_t *t, grip_real_t *mzr)
{
    if (op->book) {
        *mzr = r_mul_unit(op->cosa, *mzr);
    } else {
        *t = r_mul_scale(*t, p->lfzo);
    }
    *t = r_mul_unit(op->smooth, *t);
    *mzr = r_mul_unit(op->smooth, *mzr);
}

/* Mz = -t Fy' + Mzr + s Fx (4.E71) */
static MF_ALWAYS_INLINE grip_real_t mf_mz_sum(grip_real_t mzr, grip_real_t t, grip_real_t fy_prime, grip_real_t sarm,
                                              grip_real_t fx)
{
    return r_mac(r_msub(mzr, t, fy_prime), sarm, fx);
}

/* ------------------------------------------------------ operating point */

/* dpi = (p - NOMPRES) / NOMPRES (4.E2b) */
static MF_ALWAYS_INLINE grip_real_t mf_dpi_of(grip_real_t pr, grip_real_t nompres)
{
    return r_div(r_sub(pr, nompres), nompres);
}

/* The load of the operating point from Fz [N] (QL), clamped: Fz / FNOMIN,
 * Fz / Fz0' with Fz0' = LFZO FNOMIN (4.E1) and dfz (4.E2a). */
static MF_ALWAYS_INLINE void mf_load(const grip_mf_params *p, grip_real_t fz, mf_op *op)
{
    op->fz_ql = fz;
    op->fz = r_div(fz, p->fnomin);
    op->fzp = r_div(op->fz, p->lfzo);                                               /* 4.E1 */
    op->dfz = r_sub(op->fzp, R_ONE);                                                /* 4.E2a */
    op->dfz_lo = r_quot_m1_lo(fz, p->fnomin, p->lfzo, op->fzp, op->dfz);
}

/* The low-speed model (VXLOW, as MF-Tyre) at |Vx| <= VXLOW, rl = |Vx| /
 * VXLOW: the factor of the shifts, the trail and the residual moment,
 * 1 - 0.5 (1 + cos(pi rl)) = 0.5 (1 - cos(pi rl)) (kappa fades by rl). */
static MF_ALWAYS_INLINE grip_real_t mf_low_smooth(grip_real_t rl, grip_real_t *mk)
{
    return r_mul_unit(RC(0.5), r_sub(R_ONE, mfk_cos(r_mul(MF_PI, rl), mk)));
}

/* The low-speed model's slip angle: alpha fades by (|Vx| + |Vsy|) / VXLOW
 * while that is below 1, Vsy = tan(alpha) |Vx|, compared and divided after
 * multiplying by |cos alpha| (so alpha = pi/2 needs no tangent): *num =
 * |Vx| (|cos alpha| + |sin alpha|), *den = VXLOW |cos alpha|. */
static MF_ALWAYS_INLINE void mf_low_alpha(grip_real_t avx, grip_real_t sa, grip_real_t ca, grip_real_t vxlow,
                                          grip_real_t *num, grip_real_t *den)
{
    grip_real_t c = r_abs(ca);
    *num = r_mul(avx, r_add(c, r_abs(sa)));
    *den = r_mul_unit(c, vxlow);
}

/* The inclination as it enters each force (op->gamma: gamma*): mu_x with
 * gamma (the book writes gamma, not gamma*, there too) times LGAX in MF 5.2;
 * Fx, Fy, Mz with gamma* (MF 6.x) or gamma* LGAX, LGAY, LGAZ (MF 5.2). */
static MF_ALWAYS_INLINE void mf_cambers(const grip_mf_params *p, grip_real_t gamma, mf_op *op)
{
    op->gmux = op->mf52 ? r_mul(gamma, p->lgax) : gamma;
    if (op->mf52) {
        op->gx = r_mul(op->gamma, p->lgax);
        op->gy = r_mul(op->gamma, p->lgay);
        op->gz = r_mul(op->gamma, p->lgaz);
    } else {
        op->gx = op->gamma;
        op->gy = op->gamma;
        op->gz = op->gamma;
    }
}

/* The normalized results in N and N m, in the model's frame (ISO-W,
 * mirrored): times Fz and Fz R0. */
static MF_ALWAYS_INLINE void mf_scale_out(const grip_mf_params *p, const mf_op *op, grip_real_t fx, grip_real_t fy,
                                          grip_real_t mz, grip_mf_output *out)
{
    grip_real_t mref = r_mul(p->unloaded_radius, op->fz_ql);   /* Fz * R0 [N m] */
    out->fx = r_mul(fx, op->fz_ql);
    out->fy = r_mul(fy, op->fz_ql);
    out->mz = r_mul(mz, mref);
}

#endif /* GRIP_MF_EQUATIONS_H */
