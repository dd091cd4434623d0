/*
 * mf_ext.c - the extended outputs of the Magic Formula (grip_mf_eval_ext):
 * MFeval's other output channels, from one combined-slip evaluation.
 *
 *   Re, Omega        effective rolling radius (MFeval calculateRe)
 *   Rl, rho, Cz      loaded radius, deflection, vertical stiffness
 *                    (calculateRhoRl61 for MF 5.2 / 6.1, calculateFz62 for
 *                    MF 6.2)
 *   2a, 2b           contact patch (calculateContactPatch)
 *   t, Mzr           trail and residual moment of the combined Mz
 *   mu_x, mu_y       friction coefficients
 *   Kxk, Kya         slip stiffnesses
 *   Cx, Cy, sigma    structural stiffnesses, relaxation lengths
 *                    (calculateRelax)
 *   Mx, My           overturning and rolling resistance moments
 *                    (calculateMx, calculateMy)
 *
 * The equations are in docs/magic-formula.md section 9 and the float64
 * reference tools/grip_tools/reference/mf.py (evaluate_ext); what is
 * specific to this C code (formats, iterations, validity) in
 * docs/magic-formula-c.md section 8. As in mf_eval.c every quantity is
 * normalized (lengths by UNLOADED_RADIUS R0, loads by FNOMIN, moments by
 * Fz R0 or FNOMIN R0) and scaled to SI at the end. The two iterations (the
 * rolling radius and the MF 6.2 loaded radius) have fixed step counts; a
 * result that has not converged is flagged, not returned.
 */
#include "mf_internal.h"

/* Largest magnitude a channel may take: kept below the formats' ends
 * (QL +-8.4e6, QS +-32768) in both builds, so that both flag the same
 * channels. */
#define MF_QL_MAX      RCL(8.0e6)
#define MF_QS_MAX      RC(30000.0)

#define MF_HALF_PI     RC(1.5707963267949)
#define MF_LN10        RC(2.30258509299405)

#define MF_RE_STEPS    3              /* Halley steps of the rolling radius      */
#define MF_RE_TOL      RC(2.0e-4)     /* last step of Re / R0, converged         */
#define MF_RE_MAX      RC(6.0)        /* Re / R0 beyond: not a rolling radius    */
#define MF_RE_TINY     MF_RE_TOL      /* a Halley step below: the next are < 1e-9 */
#define MF_RE_BETA     RC(0.005)      /* |b| / a^3 up to this: Re by its series  */
#define MF_RL62_SCAN   12             /* scan points of the MF 6.2 deflection    */
#define MF_RL62_STEPS  10             /* Illinois steps of the MF 6.2 deflection */
#define MF_RL62_TOL    RC(2.0e-3)     /* |Fz62 - Fz| / FNOMIN at the result      */
#define MF_EXP_MAX     RC(10.0)       /* exp arguments beyond: channel flagged   */

/* x * s, or 0 with *ok cleared where |x| > MF_QS_MAX or the product
 * would leave [-max, max] (a NaN too: the tests are written as "not
 * within"). The product first, then its magnitude: no division, and in the
 * fixed build the exact rounded product (q16_mul_round, before any range
 * test), so that a product beyond the format is flagged, never saturated. */
static inline grip_real_t mf_times(grip_real_t x, grip_real_t s, grip_real_t max, int *ok)
{
#if GRIP_ARITH_FIXED
    int64_t v = q16_mul_round(x, s);
    if ((x > MF_QS_MAX) || (x < -MF_QS_MAX) || (v > (int64_t)max) || (v < -(int64_t)max)) {
        *ok = 0;
        return R_ZERO;
    }
    return (grip_real_t)v;
#else
    grip_real_t v = x * s;
    if (!(fabsf(x) <= MF_QS_MAX) || !(fabsf(v) <= max)) {
        *ok = 0;
        return R_ZERO;
    }
    return v;
#endif
}

static inline grip_real_t mf_times_ql(grip_real_t x, grip_real_t s, int *ok)
{
    return mf_times(x, s, MF_QL_MAX, ok);
}

static inline grip_real_t mf_times_qs(grip_real_t x, grip_real_t s, int *ok)
{
    return mf_times(x, s, MF_QS_MAX, ok);
}

/* a / b limited to +-lim (mf_div_lim); *ok cleared when the limit acts. */
static grip_real_t mf_div_ok(grip_real_t a, grip_real_t b, grip_real_t lim, int *ok)
{
    grip_real_t q = mf_div_lim(a, b, lim);
    if (r_abs(q) >= lim) {
        *ok = 0;
    }
    return q;
}

/* exp(a); *ok cleared (and 0) beyond MF_EXP_MAX. */
static grip_real_t mf_exp_ok(grip_real_t a, int *ok)
{
    if (a > MF_EXP_MAX) {
        *ok = 0;
        return R_ZERO;
    }
    return (a < r_neg(MF_EXP_MAX)) ? R_ZERO : r_exp(a);
}

/* x^e for x > 0 (0 for x <= 0), e * ln(x) clamped to [-20, 10]. */
static grip_real_t mf_pow_pos(grip_real_t x, grip_real_t e)
{
    if (!(x > R_ZERO)) {
        return R_ZERO;
    }
    return r_exp(r_clamp(r_mul(e, r_log(x)), RC(-20.0), MF_EXP_MAX));
}

/* What every channel uses: the operating point of the evaluation. */
typedef struct {
    const grip_mf_params *p;
    const mf_core *c;
    grip_real_t kap;     /* kappa (ISO, clamped, before the low-speed scaling) */
    grip_real_t gam;     /* gamma (ISO, mirrored, clamped; not gamma*)         */
    grip_real_t vx;      /* vx, signed                                         */
    grip_real_t omega;   /* the input's wheel spin [rad/s] (clamped), 0: none  */
    grip_real_t fz;      /* Fz / FNOMIN (0 when unloaded)                      */
    grip_real_t fx0;     /* combined Fx / FNOMIN, Fy / FNOMIN (0 unloaded)     */
    grip_real_t fy0;
    grip_real_t r0czp;   /* R0 Cz0 (1 + PFZ1 dpi) [N], QL                      */
    grip_real_t re_k;    /* FNOMIN / (R0 Cz0 (1 + PFZ1 dpi)), with MF_PF_RE     */
    grip_real_t cz_r0;   /* Cz0 (1 + PFZ1 dpi) R0 / FNOMIN                     */
    grip_real_t c0;      /* Cz0 R0 / FNOMIN (Q_FZ1, MF 5.2's Q_A1 default)     */
    int loaded;
    uint32_t czf;        /* MF_PF_CZ: the above formed; MF_PF_RE: re_k too     */
    /* rolling radius */
    int re_ok;
    grip_real_t r;       /* Re / R0                                            */
    grip_real_t b;       /* Q_V1 u^2, u = (1 + kappa) vx / LONGVL              */
    grip_real_t u;
    grip_real_t romega;  /* Romega / R0 (free radius at the wheel's spin)      */
    grip_real_t wspeed;  /* R0 |Omega| / LONGVL                                */
} ext_ctx;

/* ------------------------------------------------------ rolling radius */

/* One Halley step on f = r^3 - a r^2 - b from r: the new r (in [0.01,
 * MF_RE_MAX]) and the step (1 when f' or the denominator says no
 * convergence: flagged by the caller). */
static MF_ALWAYS_INLINE grip_real_t ext_halley(grip_real_t r, grip_real_t a, grip_real_t b, grip_real_t *step)
{
    grip_real_t f = r_sub(r_mul(r_sq(r), r_sub(r, a)), b);
    grip_real_t d = r_mul(r, r_sub(r_mul(RC(3.0), r), r_mul(RC(2.0), a)));   /* f'  */
    grip_real_t dd = r_sub(r_mul(RC(6.0), r), r_mul(RC(2.0), a));            /* f'' */
    grip_real_t den = r_sub(r_mul(RC(2.0), r_sq(d)), r_mul(f, dd));
    *step = R_ONE;
    if ((den > R_ZERO) && (d > RC(0.0001))) {
        *step = r_div(r_mul(r_mul(RC(2.0), f), d), den);
    }
    return r_clamp(r_sub(r, *step), RC(0.01), MF_RE_MAX);
}

/* a = Q_RE0 - FNOMIN / (Cz R0) (DREFF atan(BREFF Fz/FNOMIN) + FREFF
 * Fz/FNOMIN) (ext_radius), k = FNOMIN / (Cz R0); the terms of the
 * deflection's bracket are certified terms (cert, MF_PF_CERT_EXT). */
static MF_ALWAYS_INLINE grip_real_t ext_re_a(const grip_mf_params *p, grip_real_t k, grip_real_t fz, int cert)
{
    grip_real_t defl = mf_cadd(cert, mf_cmul(cert, p->dreff, r_atan(mf_cmul(cert, p->breff, fz))),
                               mf_cmul(cert, p->freff, fz));
    return r_sub(p->q_re0, r_mul(k, defl));
}

/* Re = Romega(Omega) - FNOMIN / Cz (DREFF atan(BREFF Fz/FNOMIN) + FREFF
 * Fz/FNOMIN), Romega = R0 (Q_RE0 + Q_V1 (Omega R0 / LONGVL)^2), Omega =
 * (1 + kappa) vx / Re. With r = Re / R0 and u = (1 + kappa) vx / LONGVL:
 * r = a + b / r^2, a = Q_RE0 - deflection / R0, b = Q_V1 u^2, which MFeval
 * iterates as written until Re changes by less than 1e-9 m. Here: the root
 * of f = r^3 - a r^2 - b, for |b| <= MF_RE_BETA a^3 (the common speeds)
 * by its series in beta = b / a^3 (no iteration), otherwise by Halley's
 * method (cubic convergence; one
 * division a step) from an upper bound of the root, where f is convex:
 * a + b / a^2 (the root is >= a for b >= 0, so b / r^2 <= b / a^2; b < 0
 * likewise) or, when that is far (b > a^3), a + b^(1/3) (f >= 0 there).
 * Three steps reach 1e-13 relative for a in [0.3, 1.5], b in [0, 30]
 * (the domain's worst, vx = 300 m/s, kappa = 1.5, Q_V1 = 7e-4: b = 1.4);
 * the last step must be below MF_RE_TOL. No root when b < -4 a^3 / 27.
 * Forced inline: with a second caller (mf_rolling_radius) GCC made it a
 * call, +150 x86 instructions per grip_mf_eval_ext. */
static MF_ALWAYS_INLINE void ext_radius(ext_ctx *e, int cert)
{
    const grip_mf_params *p = e->p;
    int i;
    grip_real_t a;
    grip_real_t b;
    grip_real_t num;
    grip_real_t a3;
    grip_real_t r;
    grip_real_t step = R_ONE;
    e->re_ok = 0;
    if (e->omega != R_ZERO) {
        /* Omega given (MFeval's input column 8): Re = Romega(Omega) -
         * deflection, nothing to iterate. w = Omega R0 / LONGVL, |w| < 181
         * (w^2 in QS); u = w r and b = Q_V1 w^2 r^2 keep Romega = Q_RE0 +
         * b / r^2 and R0 |Omega| / LONGVL = |u| / r of the estimate. */
        grip_real_t w;
        grip_real_t bw;
        if (((e->czf & MF_PF_RE) == 0u) ||
            !(r_mul(r_abs(r_mul(e->omega, p->unloaded_radius)), RC(1.0 / 181.0)) < p->longvl)) {
            return;
        }
        a = ext_re_a(p, e->re_k, e->fz, cert);
        w = r_div(r_mul(e->omega, p->unloaded_radius), p->longvl);
        bw = r_mul(p->q_v1, r_sq(w));
        r = r_add(a, bw);
        /* a radius, positive and finite (Q_V1 < 0 at a high spin, or an
         * infinite Q_V1 in the float build, would make it neither) */
        if (!(a > RC(0.01)) || !(r > RC(0.01)) || !(r <= MF_RE_MAX)) {
            return;
        }
        e->r = r;
        e->u = r_mul(w, r);
        e->b = r_mul(bw, r_sq(r));
        e->re_ok = 1;
        return;
    }
    /* FNOMIN / (Cz R0) < 1000 (MF_PF_RE), and |u| < 181 (u^2 in QS);
     * |num| <= 2.5 * 300 m/s (kappa and vx clamped): no range test */
    num = r_mul_nt(r_add_nt(R_ONE, e->kap), e->vx);
    if (((e->czf & MF_PF_RE) == 0u) ||
        (((e->czf & MF_PF_RE_U) == 0u) && !(r_mul(r_abs(num), RC(1.0 / 181.0)) < p->longvl))) {
        return;
    }
    a = ext_re_a(p, e->re_k, e->fz, cert);
    /* LONGVL > 0 and |u| < 182 (the test above, or LONGVL > 4.2 m/s) */
    e->u = r_div_nt(num, p->longvl);
    b = r_mul(p->q_v1, r_sq(e->u));
    if (!(a > RC(0.01))) {
        return;
    }
    a3 = r_mul(r_sq(a), a);
    if ((a > RC(0.3)) && (r_abs(b) <= r_mul(MF_RE_BETA, a3))) {
        /* r = a (1 + eps), eps (1 + eps)^2 = beta = b / a^3: the root's
         * series, beta - 2 beta^2 + 7 beta^3 - 30 beta^4, whose next term
         * (143 beta^5) is below 5e-10 for |beta| <= MF_RE_BETA */
        grip_real_t beta = r_div_nt(b, a3);   /* a^3 > 0.027, |beta| <= 0.005 */
        /* |beta| <= 0.005 (and a rounding): no term of the series can leave
         * the range, so none has a range test (r_msub_nt: the bits of
         * r_sub(c, r_mul(a, b)) where the product is within it) */
        grip_real_t eps =
            r_mul_nt(beta, r_msub_nt(R_ONE, beta, r_msub_nt(RC(2.0), beta, r_msub_nt(RC(7.0), RC(30.0), beta))));
        r = r_mac(a, a, eps);
        if (!(r <= MF_RE_MAX)) {
            return;
        }
    } else {
        /* 27 b + 4 a^3 < 0: no root (only for b < 0, Q_V1 < 0; with the
         * series, |b| <= a^3 / 200, never) */
        if ((b < R_ZERO) && (r_add(r_mul(RC(27.0), b), r_mul(RC(4.0), a3)) < R_ZERO)) {
            return;
        }
        if (b <= a3) {
            r = r_add(a, r_div(b, r_sq(a)));
        } else {
            r = r_add(a, mf_pow_pos(b, RC(0.333333333333333)));
        }
        if (!(r <= MF_RE_MAX)) {
            return;
        }
        r = ext_halley(r, a, b, &step);
        for (i = 1; i < MF_RE_STEPS; i++) {
            /* after a step below MF_RE_TINY the error is below 1e-9 (cubic
             * convergence): the next steps are skipped, the count of the
             * loop stays fixed */
            if (r_abs(step) > MF_RE_TINY) {
                r = ext_halley(r, a, b, &step);
            }
        }
        /* r is finite: each step clamps it (r_max(NaN, lo) is lo) */
        if (!(r_abs(step) <= MF_RE_TOL)) {
            return;
        }
    }
    e->r = r;
    e->b = b;
    e->re_ok = 1;
}

void mf_ext_cz_form(const grip_mf_params *p, grip_real_t dpi, mf_ext_cz *z)
{
    int ok = 1;
    grip_real_t czp = mf_times_ql(r_add(R_ONE, r_mul(p->pfz1, dpi)), p->vertical_stiffness, &ok);
    z->r0czp = mf_times_ql(p->unloaded_radius, czp, &ok);
    /* |u| = |(1 + kappa) vx| / LONGVL < 181 (u^2 in QS) for every input:
     * |(1 + kappa) vx| <= 2.5 * 300 m/s = 750 m/s */
    z->flags = 0u;
    if (p->longvl > RC(4.2)) {
        z->flags = MF_PF_RE_U;
    }
    z->re_k = R_ZERO;
    if (ok && (p->vertical_stiffness > R_ZERO) && (czp > R_ZERO)) {
        z->flags |= MF_PF_CZ;
        if (r_mul(RC(0.001), p->fnomin) < z->r0czp) {
            z->flags |= MF_PF_RE;
            z->re_k = r_div(p->fnomin, z->r0czp);
        }
    }
}

/* every field zero (a static object): the start of a context */
static const ext_ctx EXT_CTX_ZERO;

grip_real_t mf_rolling_radius(const grip_mf_params *p, grip_real_t kap, grip_real_t vx, grip_real_t fz,
                              grip_real_t dpi)
{
    ext_ctx e = EXT_CTX_ZERO;
    mf_ext_cz z;
    e.p = p;
    e.kap = kap;
    e.vx = vx;
    e.fz = fz;
    e.omega = R_ZERO;
    e.r = R_ZERO;
    mf_ext_cz_form(p, dpi, &z);
    e.r0czp = z.r0czp;
    e.re_k = z.re_k;
    e.czf = z.flags;
    ext_radius(&e, 0);
    return e.re_ok ? e.r : R_ZERO;
}

/* Romega / R0 and R0 |Omega| / LONGVL = |u| / r, for the vertical model. */
static void ext_spin(ext_ctx *e)
{
    e->romega = r_add(e->p->q_re0, r_div(e->b, r_sq(e->r)));
    e->wspeed = r_div(r_abs(e->u), e->r);
}

/* ------------------------------------------- loaded radius, MF 5.2/6.1 */

/* Q_FZ1 = sqrt((Cz0 R0 / FNOMIN)^2 - 4 Q_FZ2), formed without the square
 * of the (possibly large) ratio; *ok cleared when the root is imaginary. */
static grip_real_t ext_qfz1(const grip_mf_params *p, grip_real_t c, int *ok)
{
    grip_real_t t = r_div(mf_div_lim(r_mul(RC(4.0), p->q_fz2), c, RC(1000.0)), c);
    if ((t > R_ONE) || (c > RC(150.0))) {
        *ok = 0;
        return R_ZERO;
    }
    return r_mul(c, r_sqrt(r_sub(R_ONE, t)));
}

/* FNOMIN / R0 [N/m] as QL; *ok cleared beyond the format. */
static grip_real_t ext_fz0_per_r0(const grip_mf_params *p, int *ok)
{
    if (!(p->unloaded_radius > r_div(p->fnomin, MF_QL_MAX))) {
        *ok = 0;
        return R_ZERO;
    }
    return r_div_keep(p->fnomin, p->unloaded_radius);
}

/* MFeval's calculateRhoRl61 (MF 5.2 and 6.1): Fz = (Q_FZ1 x + Q_FZ2 x^2)
 * E FNOMIN with x = rho / R0 and E = (1 + Q_V2 R0 |Omega| / LONGVL -
 * (Q_FCX Fx / FNOMIN)^2 - (Q_FCY Fy / FNOMIN)^2)(1 + PFZ1 dpi); x is the
 * root 2 y / (Q_FZ1 + sqrt(Q_FZ1^2 + 4 Q_FZ2 y)), y = Fz / (FNOMIN E),
 * which stays finite for Q_FZ2 = 0. Cz = Fz / rho = E (Q_FZ1 + Q_FZ2 x)
 * FNOMIN / R0 without dividing by the small x. */
static int ext_vertical61(const ext_ctx *e, grip_real_t *x_out, grip_real_t *cz_n)
{
    const grip_mf_params *p = e->p;
    int ok = 1;
    grip_real_t qfz1 = ext_qfz1(p, e->c0, &ok);
    grip_real_t ex = r_mul(r_sub(r_sub(r_add(R_ONE, r_mul(p->q_v2, e->wspeed)), r_sq(r_mul(p->q_fcx, e->fx0))),
                                 r_sq(r_mul(p->q_fcy, e->fy0))),
                           r_add(R_ONE, r_mul(p->pfz1, e->c->op.dpi)));
    grip_real_t y;
    grip_real_t disc;
    grip_real_t x;
    if (!ok || !(ex > RC(0.001))) {
        return 0;
    }
    y = mf_div_ok(e->fz, ex, RC(1000.0), &ok);
    disc = r_add(r_sq(qfz1), r_mul(RC(4.0), r_mul(p->q_fz2, y)));
    if (!ok || !(disc >= R_ZERO)) {
        return 0;
    }
    x = mf_div_ok(r_mul(RC(2.0), y), r_add(qfz1, r_sqrt(disc)), RC(100.0), &ok);
    *x_out = r_max(x, R_ZERO);
    *cz_n = r_mul(ex, r_add(qfz1, r_mul(p->q_fz2, *x_out)));
    return ok;
}

/* ------------------------------------------------ loaded radius, MF 6.2 */

/* What MF 6.2's vertical force needs besides the deflection. */
typedef struct {
    grip_real_t qfz1;
    grip_real_t tan_g;   /* |tan(gamma)|                                       */
    grip_real_t rtw8;    /* (1.075 - 0.5 ASPECT_RATIO) WIDTH / (8 R0)           */
    grip_real_t den;     /* Q_CAM1 Romega + Q_CAM2 Romega^2 [-]                 */
    grip_real_t base;    /* 1 + Q_V2 R0 |Omega| / LONGVL - (Q_FCX Fx/FNOMIN)^2  */
    grip_real_t press;   /* 1 + PFZ1 dpi                                        */
} fz62_ctx;

/* MFeval's calculateFz62 (MF-Tyre 6.2 manual) at the free-rolling
 * deflection d (R0 units; Rl = Romega - d), minus Fz: returned / FNOMIN,
 * with the total deflection x = rho / R0 and the correction factor.
 * fcorr is kept above -8 and its Fy term below 16 in magnitude: far below
 * the root only the sign of the result matters, and no product leaves QS. */
static grip_real_t ext_fz62(const ext_ctx *e, const fz62_ctx *z, grip_real_t d, grip_real_t *x_out,
                            grip_real_t *fcorr_out)
{
    const grip_mf_params *p = e->p;
    grip_real_t r0 = p->unloaded_radius;
    grip_real_t rl = r_sub(e->romega, d);                             /* Rl / R0 */
    grip_real_t ul = mf_div_lim(rl, e->romega, RC(10.0));             /* Rl / Romega */
    grip_real_t x = d;
    grip_real_t sfyg;
    grip_real_t fyt;
    grip_real_t fcorr;
    /* camber deflection; MFeval turns its 0/0 (gamma = 0, or no Q_CAM1,
     * Q_CAM2) into 0 for the whole term */
    if ((e->gam != R_ZERO) && (z->den != R_ZERO)) {
        grip_real_t rlm = r_mul(rl, r0);
        grip_real_t num = r_mul(rlm, r_add(p->q_cam1, r_mul(p->q_cam2, rlm)));
        grip_real_t ratio = mf_div_lim(num, z->den, RC(100.0));
        x = r_add(x, r_sub(r_mul(r_mul(r_sq(ratio), z->rtw8), z->tan_g), r_mul(r_mul(p->q_cam3, d), r_abs(e->gam))));
    }
    x = r_max(x, R_ZERO);
    /* (Q_FYS1 + Q_FYS2 Rl/Romega + Q_FYS3 (Rl/Romega)^2) gamma / FNOMIN */
    sfyg = r_div(r_mul(e->gam, r_add(p->q_fys1, r_add(r_mul(ul, p->q_fys2), r_mul(r_sq(ul), p->q_fys3)))), p->fnomin);
    fyt = r_mul(r_mul(mf_pow_pos(x, p->q_fcy2), p->q_fcy), r_sub(e->fy0, sfyg));
    if (p->q_fcy2 == R_ZERO) {
        fyt = (x > R_ZERO) ? r_mul(p->q_fcy, r_sub(e->fy0, sfyg)) : R_ZERO;
    }
    fyt = r_clamp(fyt, RC(-16.0), RC(16.0));
    fcorr = r_max(r_mul(r_sub(z->base, r_sq(fyt)), z->press), RC(-8.0));
    *x_out = x;
    *fcorr_out = fcorr;
    return r_sub(r_mul(r_mul(fcorr, x), r_add(z->qfz1, r_mul(p->q_fz2, x))), e->fz);
}

/* The MF 6.2 loaded radius: the smallest free-rolling deflection d in
 * [0, R0] with Fz62 = Fz (MFeval: fminsearch of (Fz62 - Fz)^2 from Rl =
 * 0.3 m). d = 0 when even the unloaded radius carries Fz (the camber
 * deflection at a small load; MFeval's minimum is there too). Otherwise the
 * first sign change on MF_RL62_SCAN points d = (k / 12)^2 R0, then
 * MF_RL62_STEPS Illinois steps inside it (regula falsi that halves the
 * retained end's value, so both ends move); flagged unless |Fz62 - Fz| <=
 * MF_RL62_TOL FNOMIN at the result. */
static int ext_vertical62(const ext_ctx *e, grip_real_t *d_out, grip_real_t *x_out, grip_real_t *cz_n)
{
    const grip_mf_params *p = e->p;
    fz62_ctx z;
    int ok = 1;
    int found = 0;
    int side = 0;
    int i;
    grip_real_t lo = R_ZERO;
    grip_real_t hi = R_ONE;
    grip_real_t glo;
    grip_real_t ghi = R_ONE;
    grip_real_t d = R_ZERO;
    grip_real_t gd;
    grip_real_t x;
    grip_real_t fcorr;
    grip_real_t rom = r_mul(e->romega, p->unloaded_radius);          /* Romega [m] */
    grip_real_t cg = r_cos(e->gam);
    z.qfz1 = ext_qfz1(p, e->c0, &ok);
    z.tan_g = mf_div_lim(r_abs(r_sin(e->gam)), r_abs(cg), RC(100.0));
    z.rtw8 = r_mul(r_mul(r_sub(RC(1.075), r_mul(RC(0.5), p->aspect_ratio)),
                         mf_div_lim(p->width, p->unloaded_radius, RC(100.0))),
                   RC(0.125));
    z.den = r_mul(rom, r_add(p->q_cam1, r_mul(p->q_cam2, rom)));
    z.base = r_sub(r_add(R_ONE, r_mul(p->q_v2, e->wspeed)), r_sq(r_mul(p->q_fcx, e->fx0)));
    z.press = r_add(R_ONE, r_mul(p->pfz1, e->c->op.dpi));
    if (!ok) {
        return 0;
    }
    glo = ext_fz62(e, &z, R_ZERO, &x, &fcorr);
    if (glo >= R_ZERO) {
        /* the unloaded radius already carries Fz: Cz = Fz / rho */
        *d_out = R_ZERO;
        *x_out = x;
        *cz_n = (x > R_ZERO) ? mf_div_ok(e->fz, x, RC(1000.0), &ok) : R_ZERO;
        return ok;
    }
    for (i = 1; i <= MF_RL62_SCAN; i++) {
        if (!found) {
            grip_real_t q = r_div(r_from_int(i), r_from_int(MF_RL62_SCAN));
            grip_real_t dk = r_sq(q);
            grip_real_t gk = ext_fz62(e, &z, dk, &x, &fcorr);
            if (gk > R_ZERO) {
                found = 1;
                hi = dk;
                ghi = gk;
            } else {
                lo = dk;
                glo = gk;
            }
        }
    }
    if (!found) {
        return 0;
    }
    gd = glo;
    d = lo;
    for (i = 0; i < MF_RL62_STEPS; i++) {
        /* glo <= 0 < ghi: the ratio first, whose product with the
         * (small) interval keeps its resolution */
        d = r_clamp(r_sub(lo, r_mul(mf_div_lim(glo, r_sub(ghi, glo), R_ONE), r_sub(hi, lo))), lo, hi);
        gd = ext_fz62(e, &z, d, &x, &fcorr);
        if (gd > R_ZERO) {
            hi = d;
            ghi = gd;
            if (side > 0) {
                glo = r_mul(RC(0.5), glo);
            }
            side = 1;
        } else {
            lo = d;
            glo = gd;
            if (side < 0) {
                ghi = r_mul(RC(0.5), ghi);
            }
            side = -1;
        }
    }
    if (!(r_abs(gd) <= MF_RL62_TOL)) {
        return 0;
    }
    (void)ext_fz62(e, &z, d, &x, &fcorr);
    *d_out = d;
    *x_out = x;
    /* at the root Fz = fcorr x (Q_FZ1 + Q_FZ2 x) FNOMIN: Cz = Fz / rho */
    *cz_n = r_mul(fcorr, r_add(z.qfz1, r_mul(p->q_fz2, x)));
    return 1;
}

/* Rl, rho, Cz into out (valid bits set in *valid). */
static void ext_vertical(ext_ctx *e, uint32_t want, grip_mf_output_ext *out, uint32_t *valid)
{
    const grip_mf_params *p = e->p;
    grip_real_t r0 = p->unloaded_radius;
    grip_real_t d = R_ZERO;
    grip_real_t x = R_ZERO;
    grip_real_t cz_n = R_ZERO;
    int ok = e->re_ok;
    grip_real_t fz0_r0 = ext_fz0_per_r0(p, &ok);
    if (ok) {
        ext_spin(e);
    }
    if (ok && e->loaded) {
        if (p->fittyp == 62) {
            ok = ext_vertical62(e, &d, &x, &cz_n);
        } else {
            ok = ext_vertical61(e, &x, &cz_n);
            d = x;
        }
    }
    if (!ok) {
        return;
    }
    if ((want & GRIP_MF_EXT_RL) != 0u) {
        out->rl = r_mul(r_max(r_sub(e->romega, d), R_ZERO), r0);
        *valid |= GRIP_MF_EXT_RL;
    }
    if ((want & GRIP_MF_EXT_RHO) != 0u) {
        out->rho = r_mul(x, r0);
        *valid |= GRIP_MF_EXT_RHO;
    }
    if ((want & GRIP_MF_EXT_CZ) != 0u) {
        int cok = 1;
        out->cz = e->loaded ? mf_times_ql(cz_n, fz0_r0, &cok) : R_ZERO;
        *valid |= cok ? GRIP_MF_EXT_CZ : 0u;
    }
}

/* ------------------------------------------------------- contact patch */

/* x^(1/3) for x >= 0 */
static grip_real_t mf_cbrt(grip_real_t x)
{
    return (x > R_ZERO) ? r_exp(r_mul(r_log(x), RC(0.333333333333333))) : R_ZERO;
}

/* MFeval's calculateContactPatch. q = Fz / (Cz R0), limited where the
 * approximate loaded radius R0 - Fz / Cz would reach RIM_RADIUS +
 * BOTTOM_OFFST (its bottoming); MF 6.x: a = R0 (Q_RA2 q + Q_RA1 sqrt q),
 * b = WIDTH (Q_RB2 q + Q_RB1 q^(1/3)); MF 5.2: a = R0 (Q_A2 f + Q_A1
 * sqrt f), f = q Cz R0 / FNOMIN (MFeval's defaults of Q_A1, Q_A2 from the
 * vertical stiffness when both are 0), b = WIDTH / 2. q (of order 1e-4 at
 * light loads) is formed as 4096 q, so that its Q15.16 step does not
 * dominate sqrt(q) and q^(1/3): sqrt(q) = sqrt(4096 q) / 64,
 * q^(1/3) = (4096 q)^(1/3) / 16. */
static void ext_patch(const ext_ctx *e, uint32_t want, grip_mf_output_ext *out, uint32_t *valid)
{
    const grip_mf_params *p = e->p;
    grip_real_t r0 = p->unloaded_radius;
    int ok = 0;
    grip_real_t qs = R_ZERO;                                          /* 4096 q */
    grip_real_t qb;
    grip_real_t a = R_ZERO;
    grip_real_t b = R_ZERO;
    if ((e->czf & MF_PF_CZ) != 0u) {
        ok = 1;
    }
    if (ok) {
        qs = mf_div_ok(r_mul(RC(4096.0), r_min(e->fz, RC(7.0))), e->cz_r0, RC(16384.0), &ok);
        qb = r_max(r_sub(R_ONE, mf_div_lim(r_add(p->rim_radius, p->bottom_offst), r0, RC(100.0))), R_ZERO);
        qs = r_min(qs, r_mul(RC(4096.0), qb));
    }
    if (ok) {
        grip_real_t q = r_mul(qs, RC(1.0 / 4096.0));
        grip_real_t sq = r_mul(r_sqrt(qs), RC(1.0 / 64.0));
        if (e->c->op.mf52) {
            grip_real_t qa1 = p->q_a1;
            grip_real_t qa2 = p->q_a2;
            grip_real_t f = r_mul(q, e->cz_r0);
            grip_real_t sf = r_mul(sq, r_sqrt(e->cz_r0));
            if ((qa1 == R_ZERO) && (qa2 == R_ZERO)) {
                grip_real_t y = r_div(r_log(e->c0), MF_LN10);
                qa1 = r_add(r_mul(r_add(r_mul(r_add(r_mul(RC(-0.0388), y), RC(0.2509)), y), RC(-0.6283)), y),
                            RC(0.6279));
                qa2 = r_mul(RC(1.693), r_sq(qa1));
            }
            a = r_mul(r0, r_add(r_mul(qa2, f), r_mul(qa1, sf)));
        } else {
            a = r_mul(r0, r_add(r_mul(p->q_ra2, q), r_mul(p->q_ra1, sq)));
            b = r_mul(p->width, r_add(r_mul(p->q_rb2, q), r_mul(p->q_rb1, r_mul(mf_cbrt(qs), RC(0.0625)))));
        }
    }
    if (ok && ((want & GRIP_MF_EXT_LENGTH) != 0u)) {
        out->contact_length = r_mul(RC(2.0), a);
        *valid |= GRIP_MF_EXT_LENGTH;
    }
    if ((want & GRIP_MF_EXT_WIDTH) != 0u) {
        if (e->c->op.mf52 && (p->width > R_ZERO)) {
            out->contact_width = p->width;
            *valid |= GRIP_MF_EXT_WIDTH;
        } else if (ok && (p->width > R_ZERO)) {
            out->contact_width = r_mul(RC(2.0), b);
            *valid |= GRIP_MF_EXT_WIDTH;
        } else {
            /* WIDTH or VERTICAL_STIFFNESS not given */
        }
    }
}

/* --------------------------------------------- stiffness, relaxation */

/* sin(2 atan(n / d)) = 2 n d / (n^2 + d^2), exactly, without the
 * transcendentals (d = 0: 0, the limit; n = d = 0: 0). */
static grip_real_t ext_sin2atan(grip_real_t n, grip_real_t d)
{
    grip_real_t an = r_abs(n);
    grip_real_t ad = r_abs(d);
    grip_real_t m = r_max(an, ad);
    grip_real_t q;
    if (m == R_ZERO) {
        return R_ZERO;
    }
    q = r_div(r_min(an, ad), m);                                       /* in [0, 1] */
    q = r_div(r_mul(RC(2.0), q), r_add(R_ONE, r_sq(q)));
    return (((n < R_ZERO) != (d < R_ZERO)) && (q != R_ZERO)) ? r_neg(q) : q;
}

/* A relaxation length |K / C| [m] (K, C in the same format), *ok cleared
 * unless it is below 1000 m. Fixed build: the bound as a product of the
 * magnitudes (|K| < 1000 |C|, false for C = 0), then their rounded
 * quotient (q16_div_mag: r_div's value, below 1000.5); float build: the
 * quotient and one comparison (a zero or NaN C gives an infinity or a NaN,
 * which fails it). */
static MF_ALWAYS_INLINE grip_real_t ext_sigma(grip_real_t k, grip_real_t c, int *ok)
{
#if GRIP_ARITH_FIXED
    uint32_t uk = (k < 0) ? (0u - (uint32_t)k) : (uint32_t)k;
    uint32_t uc = (c < 0) ? (0u - (uint32_t)c) : (uint32_t)c;
    if ((uint64_t)uk >= ((uint64_t)uc * 1000u)) {
        *ok = 0;
        return R_ZERO;
    }
    return (grip_real_t)q16_div_mag(uk, uc);
#else
    grip_real_t s = r_div(r_abs(k), r_abs(c));
    if (!(s < RC(1000.0))) {
        *ok = 0;
    }
    return s;
#endif
}

/* A structural stiffness, (1 + c1 dfz + c2 dfz^2)(1 + c3 dpi) c0 [N/m]
 * (QL) for c0 > 0, *ok cleared beyond MF_QL_MAX; cert (MF_PF_CERT_EXT):
 * the terms, their product and the stiffness are within their ranges
 * (mf_cert_ext_ok), no range test. */
static MF_ALWAYS_INLINE grip_real_t ext_cstiff(grip_real_t c1, grip_real_t c2, grip_real_t c3, grip_real_t c0,
                                               grip_real_t dfz, grip_real_t dpi, int *ok, int cert)
{
    grip_real_t f = mf_cmul(cert, mf_cadd(cert, R_ONE, mf_cmac(cert, mf_cmul(cert, c1, dfz), c2, mf_csq(cert, dfz))),
                            mf_cmac(cert, R_ONE, c3, dpi));
    return cert ? r_mul_nt(f, c0) : mf_times_ql(f, c0, ok);
}

/* MFeval's calculateRelax: Cx = LONGITUDINAL_STIFFNESS (1 + PCFX1 dfz +
 * PCFX2 dfz^2)(1 + PCFX3 dpi), Cy likewise; MF 6.x: sigma_x = |Kxk / Cx|,
 * sigma_y = |Kya / Cy|; MF 5.2: sigma_x = (PTX1 + PTX2 dfz) exp(-PTX3 dfz)
 * LSGKP R0 Fz / FNOMIN, sigma_y = PTY1 sin(2 atan(Fz / (PTY2 Fz0'))) (1 -
 * PKY3 |gamma|) R0 LFZO LSGAL. kxk, kya: Kxk, Kya [N] of the evaluation. */
static MF_ALWAYS_INLINE void ext_relax(const ext_ctx *e, grip_real_t kxk, int kxk_ok, grip_real_t kya, int kya_ok,
                                       uint32_t want, grip_mf_output_ext *out, uint32_t *valid, int cert)
{
    const grip_mf_params *p = e->p;
    const mf_ext_op *op = &e->c->op;
    grip_real_t dfz = op->dfz;
    grip_real_t dpi = op->dpi;
    uint32_t need = want;   /* what needs Cx, Cy: them, and MF 6.x's sigma */
    int cxok = 0;
    int cyok = 0;
    grip_real_t cx = R_ZERO;
    grip_real_t cy = R_ZERO;
    if (op->mf52) {
        need &= ~(GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY);
    }
    /* the float build's certificate holds LONGITUDINAL_, LATERAL_STIFFNESS > 0 */
    if (((need & (GRIP_MF_EXT_CX | GRIP_MF_EXT_SIGMAX)) != 0u) &&
        ((!GRIP_ARITH_FIXED && cert) || (p->longitudinal_stiffness > R_ZERO))) {
        cxok = 1;
    }
    if (((need & (GRIP_MF_EXT_CY | GRIP_MF_EXT_SIGMAY)) != 0u) &&
        ((!GRIP_ARITH_FIXED && cert) || (p->lateral_stiffness > R_ZERO))) {
        cyok = 1;
    }
    if (cxok) {
        cx = ext_cstiff(p->pcfx1, p->pcfx2, p->pcfx3, p->longitudinal_stiffness, dfz, dpi, &cxok, cert);
    }
    if (cyok) {
        cy = ext_cstiff(p->pcfy1, p->pcfy2, p->pcfy3, p->lateral_stiffness, dfz, dpi, &cyok, cert);
    }
    grip_real_t sx = R_ZERO;
    grip_real_t sy = R_ZERO;
    int sxok;
    int syok;
    if (cxok && ((want & GRIP_MF_EXT_CX) != 0u)) {
        out->cx = cx;
        *valid |= GRIP_MF_EXT_CX;
    }
    if (cyok && ((want & GRIP_MF_EXT_CY) != 0u)) {
        out->cy = cy;
        *valid |= GRIP_MF_EXT_CY;
    }
    if (op->mf52) {
        grip_real_t r0 = p->unloaded_radius;
        sxok = 1;
        syok = 1;
        sx = r_mul(r_mul(r_mul(r_mul(r_add(p->ptx1, r_mul(p->ptx2, dfz)), mf_exp_ok(r_neg(r_mul(p->ptx3, dfz)), &sxok)),
                               p->lsgkp),
                         r0),
                   e->fz);
        sy = r_mul(r_mul(r_mul(r_mul(r_mul(p->pty1, ext_sin2atan(op->fzp, p->pty2)),
                                     r_sub(R_ONE, r_mul(p->pky3, r_abs(e->gam)))),
                               r0),
                         p->lfzo),
                   p->lsgal);
    } else {
        /* |K / C| below 1000 m (ext_sigma) */
        sxok = 0;
        syok = 0;
        if (cxok && kxk_ok) {
            sxok = 1;
            sx = ext_sigma(kxk, cx, &sxok);
        }
        if (cyok && kya_ok) {
            syok = 1;
            sy = ext_sigma(kya, cy, &syok);
        }
    }
    if (sxok && ((want & GRIP_MF_EXT_SIGMAX) != 0u)) {
        out->sigmax = sx;
        *valid |= GRIP_MF_EXT_SIGMAX;
    }
    if (syok && ((want & GRIP_MF_EXT_SIGMAY) != 0u)) {
        out->sigmay = sy;
        *valid |= GRIP_MF_EXT_SIGMAY;
    }
}

#if MF_CERT_PATH
/* |v| of a Q15.16 or Q23.8 value, as int64 */
static int64_t ext_cert_abs(grip_real_t v)
{
    return (v < 0) ? -(int64_t)v : (int64_t)v;
}

/* A bound of |1 + c1 x + c2 x^2| for |x| <= m (Q16.16): 1 + c (1 + m)^2,
 * c = max(|c1|, |c2|), rounded up (mf_cert_ok's bound); c < 2^31, m <= 16. */
static int64_t ext_cert_poly(grip_real_t c1, grip_real_t c2, int64_t m)
{
    int64_t c = (ext_cert_abs(c1) > ext_cert_abs(c2)) ? ext_cert_abs(c1) : ext_cert_abs(c2);
    int64_t b = ((c * (65536 + m)) + 65535) >> 16;
    b = ((b * (65536 + m)) + 65535) >> 16;
    return b + 65536;
}

/* ext_cstiff's terms for |dfz| <= m, |dpi| <= 1 <= m: the polynomial in
 * dfz and the pressure factor each, and their product, at most 30000 (a
 * few LSB of rounding below 32768), and that times c0 at most 7.99e6 N/m,
 * below MF_QL_MAX by far more than the roundings (so that the checked form,
 * mf_times_ql, keeps its ok). */
static int ext_cert_cstiff(grip_real_t c1, grip_real_t c2, grip_real_t c3, grip_real_t c0, int64_t m)
{
    int64_t lim = (int64_t)30000 << 16;
    int64_t bp = ext_cert_poly(c1, c2, m);
    int64_t bq = 65536 + ext_cert_abs(c3) + 1;   /* 1 + |c3| |dpi|, and a rounding */
    int64_t bf;
    if ((bp > lim) || (bq > lim)) {
        return 0;
    }
    bf = ((bp * bq) + 65535) >> 16;
    if (bf > lim) {
        return 0;
    }
    /* c0 (QL, < 2^31) times bf (<= 30000 << 16): below 2^62 */
    return (((ext_cert_abs(c0) * bf) + 65535) >> 16) <= (int64_t)RCL(7.99e6);
}

int mf_cert_ext_ok(const grip_mf_params *p, int64_t m)
{
    /* Fz / FNOMIN <= GRIP_MF_FZ_MAX_REL (4) and a rounding: 5; the
     * arctangent <= pi / 2 < 5 */
    int64_t f5 = (int64_t)5 << 16;
    int64_t lim = (int64_t)30000 << 16;
    int64_t tb = (ext_cert_abs(p->breff) * f5) >> 16;
    int64_t td = ((ext_cert_abs(p->dreff) + ext_cert_abs(p->freff)) * f5) >> 16;
    /* R0 <= 5000 m: Re = r R0 within QS without a test (r <= MF_RE_MAX) */
    if (((tb + 1) > lim) || ((td + 2) > lim) || (p->unloaded_radius > RC(5000.0))) {
        return 0;
    }
    return ext_cert_cstiff(p->pcfx1, p->pcfx2, p->pcfx3, p->longitudinal_stiffness, m) &&
           ext_cert_cstiff(p->pcfy1, p->pcfy2, p->pcfy3, p->lateral_stiffness, m);
}
#endif

#if !GRIP_ARITH_FIXED
/* The float build's certificate of Cx (c1..c3 PCFX1..3, c0
 * LONGITUDINAL_STIFFNESS) for |dfz| <= m, |dpi| <= 1: c0 > 0, the factors of
 * ext_cstiff and their product at most 29000 in magnitude and that times
 * c0 at most 7.9e6 N/m, so that mf_times_ql's tests (30000, 8e6) hold for
 * every input; the bound is formed from finite coefficients (the set was
 * checked) with a margin far above float's rounding. */
static int ext_cert_cstiff_f(grip_real_t c1, grip_real_t c2, grip_real_t c3, grip_real_t c0, grip_real_t m)
{
    grip_real_t bp = r_add(R_ONE, r_mul(r_add(r_abs(c1), r_mul(r_abs(c2), m)), m));
    grip_real_t bq = r_add(R_ONE, r_abs(c3));
    grip_real_t bf = r_mul(bp, bq);
    return (c0 > R_ZERO) && (bp <= RC(29000.0)) && (bq <= RC(29000.0)) && (bf <= RC(29000.0)) &&
           (r_mul(bf, c0) <= RC(7.9e6));
}

/* The float build's MF_PF_CERT_EXT: R0 <= 5000 m (Re = r R0 with no
 * range test) and Cx, Cy's certificates. */
int mf_cert_ext_ok_f(const grip_mf_params *p, grip_real_t fz_max)
{
    /* dfz in [-1, dfz at fz_max] (mf_load's quotients are monotone in Fz) */
    grip_real_t m = r_max(r_sub(r_div(r_div(fz_max, p->fnomin), p->lfzo), R_ONE), R_ONE);
    /* R0 <= 5000 m: Re = r R0 within QS without a test (r <= MF_RE_MAX) */
    if (!(m <= RC(1.0e4)) || !(p->unloaded_radius <= RC(5000.0))) {
        return 0;
    }
    return ext_cert_cstiff_f(p->pcfx1, p->pcfx2, p->pcfx3, p->longitudinal_stiffness, m) &&
           ext_cert_cstiff_f(p->pcfy1, p->pcfy2, p->pcfy3, p->lateral_stiffness, m);
}
#endif

/* ------------------------------------------------------------ Mx, My */

/* atan(v^2) without forming a square beyond QS. */
static grip_real_t mf_atan_sq(grip_real_t v)
{
    grip_real_t av = r_abs(v);
    if (av <= R_ONE) {
        return r_atan(r_sq(av));
    }
    return r_sub(MF_HALF_PI, r_atan(r_sq(r_div(R_ONE, av))));
}

/* MFeval's low-load factor of Mx and My: Fz is replaced by Fz (Fz /
 * FZMIN)^n below FZMIN (n = 2 in Mx, 1 in My); 1 above, or without FZMIN. */
static grip_real_t ext_low_load(const ext_ctx *e, int squared)
{
    const grip_mf_params *p = e->p;
    grip_real_t f;
    if (!(p->fzmin > R_ZERO) || !(e->c->op.fz_ql < p->fzmin)) {
        return R_ONE;
    }
    f = r_div(e->c->op.fz_ql, p->fzmin);
    return squared ? r_sq(f) : f;
}

/* Mx / (Fz R0): MF-Tyre equation manual (QSX1-QSX14, MFeval's calculateMx):
 * R0 Fz LMX (QSX1 LVMX - QSX2 gamma (1 + PPMX1 dpi) - QSX12 gamma |gamma|
 * + QSX3 Fy/FNOMIN + QSX4 cos(QSX5 atan((QSX6 Fz/FNOMIN)^2)) sin(QSX7 gamma
 * + QSX8 atan(QSX9 Fy/FNOMIN)) + QSX10 atan(QSX11 Fz/FNOMIN) gamma) + R0 Fy
 * LMX (QSX13 + QSX14 |gamma|), Fz with the low-load factor. */
static grip_real_t ext_mx(const ext_ctx *e)
{
    const grip_mf_params *p = e->p;
    grip_real_t g = e->gam;
    grip_real_t ga = r_abs(g);
    grip_real_t red = ext_low_load(e, 1);
    grip_real_t fr = r_mul(red, e->fz);
    grip_real_t br = r_sub(r_sub(r_mul(p->qsx1, p->lvmx), r_mul(r_mul(p->qsx2, g), r_add(R_ONE, r_mul(p->ppmx1, e->c->op.dpi)))),
                           r_mul(r_mul(p->qsx12, g), ga));
    br = r_add(br, r_mul(p->qsx3, e->fy0));
    br = r_add(br, r_mul(r_mul(p->qsx4, r_cos(r_mul(p->qsx5, mf_atan_sq(r_mul(p->qsx6, fr))))),
                         r_sin(r_add(r_mul(p->qsx7, g), r_mul(p->qsx8, r_atan(r_mul(p->qsx9, e->fy0)))))));
    br = r_add(br, r_mul(r_mul(p->qsx10, r_atan(r_mul(p->qsx11, fr))), g));
    return r_mul(p->lmx, r_add(r_mul(red, br), r_mul(e->c->fy, r_add(p->qsx13, r_mul(p->qsx14, ga)))));
}

/* My, MFeval's calculateMy. MF 6.x (paper A48): -R0 FNOMIN LMY (QSY1 + QSY2
 * Fx/FNOMIN + QSY3 |vx/LONGVL| + QSY4 (vx/LONGVL)^4 + (QSY5 + QSY6 Fz/FNOMIN)
 * gamma^2) (Fz/FNOMIN)^QSY7 (p/NOMPRES)^QSY8; MF 5.2 (MF-Tyre 5.2 manual):
 * -R0 Fz LMY (QSY1 + ... + QSY4 (vx/LONGVL)^4). Both times the sign of the
 * rolling: -1 for vx < 0, and sin(pi/2 (1 + kappa) |vx| / VXLOW) within
 * |1 + kappa| |vx| <= VXLOW of the locked wheel (-1 below it). Returned as
 * 64 My / (Fz R0): the bracket is of order QSY1 = 0.01, so it is formed
 * times 64 (the coefficients times 64 are exact) to keep its resolution;
 * MF 6.x's (Fz/FNOMIN)^QSY7 / (Fz/FNOMIN) = red (red Fz/FNOMIN)^(QSY7 - 1)
 * with red the low-load factor. */
static grip_real_t ext_my(const ext_ctx *e, int *ok)
{
    const grip_mf_params *p = e->p;
    const mf_ext_op *op = &e->c->op;
    grip_real_t red = ext_low_load(e, 0);
    grip_real_t u = mf_div_ok(r_abs(e->vx), p->longvl, RC(64.0), ok);
    grip_real_t u2 = r_sq(u);
    grip_real_t s = RC(64.0);
    grip_real_t base = r_add(r_add(r_add(r_mul(s, p->qsy1), r_mul(r_mul(s, p->qsy2), e->fx0)), r_mul(r_mul(s, p->qsy3), u)),
                             r_mul(r_mul(r_mul(s, p->qsy4), u2), u2));
    grip_real_t my;
    grip_real_t roll;
    if (op->mf52) {
        my = r_neg(r_mul(r_mul(p->lmy, base), red));
    } else {
        grip_real_t fr = r_mul(red, e->fz);
        base = r_add(base, r_mul(r_add(r_mul(s, p->qsy5), r_mul(r_mul(s, p->qsy6), fr)), r_sq(e->gam)));
        my = r_neg(r_mul(r_mul(r_mul(r_mul(p->lmy, base), red), mf_pow_pos(fr, r_sub(p->qsy7, R_ONE))),
                         mf_pow_pos(r_add(R_ONE, op->dpi), p->qsy8)));
    }
    if (p->vxlow > R_ZERO) {
        roll = r_sin(r_mul(MF_HALF_PI, mf_div_lim(r_mul(r_add(R_ONE, e->kap), r_abs(e->vx)), p->vxlow, R_ONE)));
    } else {
        roll = r_sign(r_add(R_ONE, e->kap));
    }
    my = r_mul(my, roll);
    return (e->vx < R_ZERO) ? r_neg(my) : my;
}

/* ------------------------------------------------------------ public */

uint32_t grip_mf_ext_supported(const grip_mf_params *p)
{
    uint32_t m = GRIP_MF_EXT_ALL;
    if ((p == NULL) || !mf_params_usable(p)) {
        return 0u;
    }
    if (!(p->vertical_stiffness > R_ZERO)) {
        m &= ~(GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ |
               GRIP_MF_EXT_LENGTH);
        if (!((p->fittyp == 5) || (p->fittyp == 6) || (p->fittyp == 21))) {
            m &= ~GRIP_MF_EXT_WIDTH;
        }
    } else {
        int ok = 1;
        grip_real_t c = mf_div_ok(mf_times_ql(p->unloaded_radius, p->vertical_stiffness, &ok), p->fnomin,
                                  RC(1000.0), &ok);
        (void)ext_qfz1(p, c, &ok);
        if (!ok) {
            m &= ~(GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ);
        }
    }
    if (!(p->width > R_ZERO)) {
        m &= ~GRIP_MF_EXT_WIDTH;
    }
    if (!(p->longitudinal_stiffness > R_ZERO)) {
        m &= ~GRIP_MF_EXT_CX;
        if (p->fittyp >= 61) {
            m &= ~GRIP_MF_EXT_SIGMAX;
        }
    }
    if (!(p->lateral_stiffness > R_ZERO)) {
        m &= ~GRIP_MF_EXT_CY;
        if (p->fittyp >= 61) {
            m &= ~GRIP_MF_EXT_SIGMAY;
        }
    }
    return m;
}

/* The channels an evaluation does not always write zero (all but Re:
 * ext_channels_body writes it, and valid, once). */
static MF_ALWAYS_INLINE void ext_zero_channels(grip_mf_output_ext *out)
{
    out->omega = R_ZERO;
    out->rl = R_ZERO;
    out->rho = R_ZERO;
    out->cz = R_ZERO;
    out->contact_length = R_ZERO;
    out->contact_width = R_ZERO;
    out->t = R_ZERO;
    out->mzr = R_ZERO;
    out->mux = R_ZERO;
    out->muy = R_ZERO;
    out->kxk = R_ZERO;
    out->kya = R_ZERO;
    out->cx = R_ZERO;
    out->cy = R_ZERO;
    out->sigmax = R_ZERO;
    out->sigmay = R_ZERO;
    out->mx = R_ZERO;
    out->my = R_ZERO;
}

/* Every output zero, no channel valid: the outputs of an error. Field by
 * field: the compilers make a copy of a zero struct of this size a memset
 * call, ~60 instructions on the Cortex-M4F against 23 stores. */
static void ext_zero(grip_mf_output_ext *out)
{
    out->fx = R_ZERO;
    out->fy = R_ZERO;
    out->mz = R_ZERO;
    out->re = R_ZERO;
    ext_zero_channels(out);
    out->valid = 0u;
}

/* A requested channel that is not finite: 0 and its bit cleared (also when
 * already flagged: a flagged channel may hold a NaN that a NaN coefficient
 * brought before its format check; found by tests/fuzz/fuzz_mf.c). Called
 * by each group of channels for the channels it wrote, so that a request
 * pays for the channels it asked for only. */
static inline void ext_finite(grip_real_t *v, uint32_t bit, uint32_t outputs, uint32_t *valid)
{
    if (((outputs & bit) != 0u) && !r_is_finite(*v)) {
        *v = R_ZERO;
        *valid &= ~bit;
    }
}

/* The channels that need the vertical stiffness (Re ... 2b). */
#define EXT_NEED_CZ                                                                                              \
    (GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ | GRIP_MF_EXT_LENGTH | \
     GRIP_MF_EXT_WIDTH)
/* The channels of the slip stiffnesses and of the relaxation. */
#define EXT_STIFF                                                                                                \
    (GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA | GRIP_MF_EXT_CX | GRIP_MF_EXT_CY | GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY)
/* Everything but Re and the stiffnesses (ext_more). */
#define EXT_MORE (GRIP_MF_EXT_ALL & ~(GRIP_MF_EXT_RE | EXT_STIFF))

/* The inputs as the model saw them, before the low-speed scaling: the
 * conventions and clamps of mf_prepare (mf_eval.c) for kappa, gamma, vx. */
static MF_ALWAYS_INLINE int ext_inputs(uint32_t mode, uint32_t outputs, const grip_mf_input *in, const grip_mf_spin *spin,
                      const mf_io *io, ext_ctx *e)
{
    int clamped = 0;
    int om_clamped = 0;
    grip_real_t kap = ((mode & GRIP_MF_OPT_KAPPA_BRAKE) != 0u) ? r_neg(in->kappa) : in->kappa;
    e->kap = mf_clamp_sym(kap, RC(GRIP_MF_KAPPA_MAX), &clamped);
    e->gam = R_ZERO;
    if (((outputs & EXT_MORE) != 0u) || (e->c->op.mf52 && ((outputs & GRIP_MF_EXT_SIGMAY) != 0u))) {
        /* only the vertical model, Mx, My and MF 5.2's sigma_y use gamma */
        grip_real_t gam = io->mirror ? r_neg(in->gamma) : in->gamma;
        e->gam = mf_clamp_sym(gam, RC(GRIP_MF_GAMMA_MAX), &clamped);
    }
    e->vx = mf_clamp_sym(in->vx, RC(GRIP_MF_VX_MAX), &clamped);
    e->omega = R_ZERO;
    if (spin->omega != R_ZERO) {
        e->omega = mf_clamp_sym(spin->omega, RC(GRIP_MF_OMEGA_MAX), &om_clamped);
    }
    return om_clamped;   /* the others were reported by mf_prepare */
}

/* no turn slip, the spin estimated: grip_mf_eval_ext's */
static const grip_mf_spin SPIN_ZERO;

grip_status_t grip_mf_eval_ext(const grip_mf_params *p, const grip_mf_input *in, uint32_t outputs,
                               grip_mf_output_ext *out)
{
    return grip_mf_eval_ext_spin(p, in, NULL, outputs, out);
}

/* Kxk, Kya [N] and the relaxation's Cx, Cy, sigma_x, sigma_y (want holds
 * at least one of EXT_STIFF). */
static MF_ALWAYS_INLINE void ext_stiff(const ext_ctx *e, uint32_t want, grip_mf_output_ext *out, uint32_t *valid,
                                       int cert)
{
    const mf_core *c = e->c;
    grip_real_t kxk = R_ZERO;
    grip_real_t kya = R_ZERO;
    int kxk_ok = 1;
    int kya_ok = 1;
    /* K = (K / Fz) Fz, valid within +-8e6 N (QL): the product, then its
     * magnitude (mf_times: no division for a bound of K / Fz) */
    if ((want & (GRIP_MF_EXT_KXK | GRIP_MF_EXT_SIGMAX)) != 0u) {
        kxk = mf_times_ql(c->kxk, c->op.fz_ql, &kxk_ok);
        if (kxk_ok && ((want & GRIP_MF_EXT_KXK) != 0u)) {
            out->kxk = kxk;
            *valid |= GRIP_MF_EXT_KXK;
        }
    }
    if ((want & (GRIP_MF_EXT_KYA | GRIP_MF_EXT_SIGMAY)) != 0u) {
        kya = mf_times_ql(c->kya, c->op.fz_ql, &kya_ok);
        if (kya_ok && ((want & GRIP_MF_EXT_KYA) != 0u)) {
            out->kya = kya;
            *valid |= GRIP_MF_EXT_KYA;
        }
    }
    if ((want & (GRIP_MF_EXT_CX | GRIP_MF_EXT_CY | GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY)) != 0u) {
        ext_relax(e, kxk, kxk_ok, kya, kya_ok, want, out, valid, cert);
    }
    /* Kxk, Kya are finite where valid (a NaN or infinite product fails
     * |K| <= 8e6), and so are MF 6.x's sigma (|K| / |C| below 1000);
     * Cx, Cy and MF 5.2's sigma are not when a coefficient is not */
    if ((want & (GRIP_MF_EXT_CX | GRIP_MF_EXT_CY)) != 0u) {
        ext_finite(&out->cx, GRIP_MF_EXT_CX, want, valid);
        ext_finite(&out->cy, GRIP_MF_EXT_CY, want, valid);
    }
    if (c->op.mf52) {
        ext_finite(&out->sigmax, GRIP_MF_EXT_SIGMAX, want, valid);
        ext_finite(&out->sigmay, GRIP_MF_EXT_SIGMAY, want, valid);
    }
}

/* The channels of EXT_MORE (want holds at least one): Omega, the vertical
 * model, the contact patch, t, Mzr, mu_x, mu_y, Mx, My; returns the bits of
 * those formed. A function of its own, so that the common request (Re, the
 * stiffnesses) does not test each of them (and its caller's bits stay in a
 * register). */
static MF_NOINLINE uint32_t ext_more(ext_ctx *e, uint32_t mode, uint32_t want, grip_mf_output_ext *out)
{
    uint32_t valid = 0u;   /* the bits of the channels formed */
    const grip_mf_params *p = e->p;
    const mf_core *c = e->c;
    grip_real_t fzr0 = r_mul(p->unloaded_radius, c->op.fz_ql);          /* Fz R0 [N m] */
    int ok;
    e->loaded = c->io.zero ? 0 : 1;
    e->fx0 = r_mul(c->fx, e->fz);
    e->fy0 = r_mul(c->fy, e->fz);
    if (e->re_ok && ((want & GRIP_MF_EXT_OMEGA) != 0u)) {
        /* (1 + kappa) vx / Re = u LONGVL / Re: below 30000 rad/s; or the
         * input's Omega */
        grip_real_t re = r_mul(e->r, p->unloaded_radius);
        grip_real_t num = r_mul(r_add(R_ONE, e->kap), e->vx);
        if (e->omega != R_ZERO) {
            out->omega = e->omega;
            valid |= GRIP_MF_EXT_OMEGA;
        } else if (r_mul(r_abs(num), RC(1.0 / 30000.0)) < re) {
            out->omega = r_div(num, re);
            valid |= GRIP_MF_EXT_OMEGA;
        } else {
            /* beyond the format: flagged */
        }
    }
    if ((want & (GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ)) != 0u) {
        ext_vertical(e, want, out, &valid);
    }
    if ((want & (GRIP_MF_EXT_LENGTH | GRIP_MF_EXT_WIDTH)) != 0u) {
        ext_patch(e, want, out, &valid);
    }
    if ((want & GRIP_MF_EXT_T) != 0u) {
        out->t = r_mul(c->t, p->unloaded_radius);
        valid |= GRIP_MF_EXT_T;
    }
    if ((want & GRIP_MF_EXT_MZR) != 0u) {
        ok = 1;
        out->mzr = mf_times_ql(c->mzr, fzr0, &ok);
        out->mzr = (c->io.mirror != c->io.sae) ? r_neg(out->mzr) : out->mzr;
        valid |= ok ? GRIP_MF_EXT_MZR : 0u;
    }
    if ((want & GRIP_MF_EXT_MUX) != 0u) {
        out->mux = e->loaded ? mf_mux(p, c->op.dfz, c->op.dpi, c->op.gmux, c->op.lmux_s) : R_ZERO;
        valid |= GRIP_MF_EXT_MUX;
    }
    if ((want & GRIP_MF_EXT_MUY) != 0u) {
        /* MFeval reports |mu_y| in its limits mode (1xx), mu_y in 2xx */
        out->muy = ((mode & GRIP_MF_OPT_NO_LIMITS) != 0u) ? c->muy : r_abs(c->muy);
        valid |= GRIP_MF_EXT_MUY;
    }
    if ((want & GRIP_MF_EXT_MX) != 0u) {
        ok = 1;
        out->mx = e->loaded ? mf_times_ql(ext_mx(e), fzr0, &ok) : R_ZERO;
        out->mx = c->io.mirror ? r_neg(out->mx) : out->mx;
        valid |= ok ? GRIP_MF_EXT_MX : 0u;
    }
    if ((want & GRIP_MF_EXT_MY) != 0u) {
        grip_real_t my = R_ZERO;
        ok = 1;
        if (e->loaded) {
            my = mf_times_ql(ext_my(e, &ok), r_div_keep(fzr0, RC(64.0)), &ok);
        }
        out->my = c->io.sae ? r_neg(my) : my;
        valid |= ok ? GRIP_MF_EXT_MY : 0u;
    }
    ext_finite(&out->omega, GRIP_MF_EXT_OMEGA, want, &valid);
    ext_finite(&out->rl, GRIP_MF_EXT_RL, want, &valid);
    ext_finite(&out->rho, GRIP_MF_EXT_RHO, want, &valid);
    ext_finite(&out->cz, GRIP_MF_EXT_CZ, want, &valid);
    ext_finite(&out->contact_length, GRIP_MF_EXT_LENGTH, want, &valid);
    ext_finite(&out->contact_width, GRIP_MF_EXT_WIDTH, want, &valid);
    ext_finite(&out->t, GRIP_MF_EXT_T, want, &valid);
    ext_finite(&out->mzr, GRIP_MF_EXT_MZR, want, &valid);
    ext_finite(&out->mux, GRIP_MF_EXT_MUX, want, &valid);
    ext_finite(&out->muy, GRIP_MF_EXT_MUY, want, &valid);
    ext_finite(&out->mx, GRIP_MF_EXT_MX, want, &valid);
    ext_finite(&out->my, GRIP_MF_EXT_MY, want, &valid);
    return valid;
}

/* The forces of an extended evaluation (base, its status st) into out and
 * the channels but Re zero (ext_zero_channels: their fields are written
 * once, where the evaluation would not zero them first); whether to go on
 * with the channels (st not an error: the caller zeroes every output
 * otherwise, ext_zero). */
static MF_ALWAYS_INLINE int ext_forces(const grip_mf_output *base, grip_status_t st, grip_mf_output_ext *out)
{
    out->fx = base->fx;
    out->fy = base->fy;
    out->mz = base->mz;
    ext_zero_channels(out);
    return (st >= 0) ? 1 : 0;
}

/* The requested channels of an evaluation whose status st is not an error
 * (c: its intermediates; mode: its use-mode bits; out: the forces written,
 * the channels but Re zero (ext_forces); Re and valid are written here; k: the prepared set of p, or NULL; cert, a
 * constant in each caller: the set's extended certificate holds,
 * MF_PF_CERT_EXT). */
static MF_ALWAYS_INLINE grip_status_t ext_channels_body(const grip_mf_params *p, const grip_mf_prepared *k, mf_core *c,
                                                        grip_status_t st, const grip_mf_input *in,
                                                        const grip_mf_spin *spin, uint32_t mode, uint32_t outputs,
                                                        grip_mf_output_ext *out, int cert)
{
    ext_ctx e;
    uint32_t valid = 0u;
    int ok;
    grip_real_t re = R_ZERO;
    /* the set's extended certificate: the fixed build's a constant of the
     * caller (its certified copy), the float build's the set's flag, read
     * once (mf_cert_ext_ok_f: R0 <= 5000 m, Cx, Cy within their tests) */
#if GRIP_ARITH_FIXED
    int certx = cert;
#else
    int certx = 0;
    (void)cert;
#endif
    e.p = p;
    e.c = c;
    if (k != NULL) {
        /* the prepared evaluation's inputs as it took them (no spin) */
        e.kap = c->kap;
        e.gam = c->gam;
        e.vx = c->vx;
        e.omega = R_ZERO;
#if !GRIP_ARITH_FIXED
        certx = ((k->flags & MF_PF_CERT_EXT) != 0u) ? 1 : 0; /* grip-deviation: MISRA-10.6 tool: ?: of constants is not composite (8.10.3) */
#endif
    } else if (ext_inputs(mode, outputs, in, spin, &c->io, &e) && (st == GRIP_OK)) {
        st = GRIP_WARN_CLAMPED;
    } else {
        /* no spin clamped */
    }
    if (c->io.zero) {
        c->fx = R_ZERO;
        c->fy = R_ZERO;
        c->t = R_ZERO;
        c->mzr = R_ZERO;
        c->kxk = R_ZERO;
        c->kya = R_ZERO;
        c->muy = R_ZERO;
    }
    e.fz = c->op.fz;
    e.czf = 0u;
    e.re_ok = 0;
    if ((outputs & EXT_NEED_CZ) != 0u) {
        /* the vertical stiffness at the pressure, times R0, over FNOMIN:
         * the prepared set's at its default pressure */
        if ((k != NULL) && !(in->p > R_ZERO)) {
            e.r0czp = k->r0czp;
            e.re_k = k->re_k;
            e.czf = k->flags & (MF_PF_CZ | MF_PF_RE | MF_PF_RE_U);
        } else {
            /* z in this branch only: its address passed, it stays in memory */
            mf_ext_cz z;
            mf_ext_cz_form(p, c->op.dpi, &z);
            e.r0czp = z.r0czp;
            e.re_k = z.re_k;
            e.czf = z.flags;
        }
        e.cz_r0 = R_ZERO;
        e.c0 = R_ZERO;
        if ((outputs & (GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ | GRIP_MF_EXT_LENGTH | GRIP_MF_EXT_WIDTH)) !=
            0u) {
            ok = 1;
            e.cz_r0 = mf_div_ok(e.r0czp, p->fnomin, RC(1000.0), &ok);
            e.c0 = mf_div_ok(mf_times_ql(p->unloaded_radius, p->vertical_stiffness, &ok), p->fnomin, RC(1000.0), &ok);
            if (!ok) {
                e.czf = 0u;
            }
        }
    }
    if ((outputs & (GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ)) != 0u) {
        ext_radius(&e, cert);
        if (e.re_ok && ((outputs & GRIP_MF_EXT_RE) != 0u)) {
            ok = 1;
            /* finite: r is (ext_radius), and an R0 of +Inf has no Cz
             * (MF_PF_CZ); r <= MF_RE_MAX, so with R0 <= 5000 m the product
             * is within QS without a test (beyond it 0 when not); the
             * certificate holds R0 <= 5000 m (mf_cert_ext_ok, _ok_f) */
            re = (certx || (p->unloaded_radius <= RC(5000.0))) ? r_mul_nt(e.r, p->unloaded_radius)
                                                                : mf_times_qs(e.r, p->unloaded_radius, &ok);
            valid |= ok ? GRIP_MF_EXT_RE : 0u;
        }
    }
    out->re = re;
    if ((outputs & EXT_STIFF) != 0u) {
        /* the float build's certificate of Cx, Cy (mf_cert_ext_ok_f): their
         * format tests dropped, the same values */
        ext_stiff(&e, outputs, out, &valid, certx);
    }
    if ((outputs & EXT_MORE) != 0u) {
        /* a copy whose address ext_more takes: e's own is never taken, so
         * its fields stay in registers on the paths without ext_more */
        ext_ctx m = e;
        valid |= ext_more(&m, mode, outputs, out);
    }
    out->valid = valid;
    return st;
}

/* The channels' functions. Where the build optimizes for size (the
 * Cortex-M0+ firmware at -Os) one function serves both entry points
 * (ext_channels); elsewhere a prepared set has copies of its own
 * (ext_channels_prep and, where MF_CERT_PATH, the certified
 * ext_channels_prep_c, MF_PF_CERT_EXT), in which k not NULL, no spin and
 * the set's options fold the given-Omega forms away: x86 float 19
 * instructions fewer per prepared call, for 3.5 KB of Cortex-M4F text. */
#if defined(__OPTIMIZE_SIZE__)
#define EXT_PREP_COPY 0
#else
#define EXT_PREP_COPY 1
#endif

#if EXT_PREP_COPY
/* kept out of line, as ext_channels_spin: inlined, its frame would add to
 * the deepest stack path of grip_mf_eval_ext_prepared */
static MF_NOINLINE grip_status_t ext_channels_prep(const grip_mf_prepared *k, mf_core *c, grip_status_t st,
                                                   const grip_mf_input *in, uint32_t outputs, grip_mf_output_ext *out)
{
    return ext_channels_body(k->p, k, c, st, in, &SPIN_ZERO, k->options, outputs, out, 0);
}

#if MF_CERT_PATH
/* (not kept out of line: the copy exists only where the build optimizes
 * for speed, not in the firmware whose stack budget is measured) */
static grip_status_t ext_channels_prep_c(const grip_mf_prepared *k, mf_core *c, grip_status_t st,
                                         const grip_mf_input *in, uint32_t outputs, grip_mf_output_ext *out)
{
    return ext_channels_body(k->p, k, c, st, in, &SPIN_ZERO, k->options, outputs, out, 1);
}
#endif
#else
static grip_status_t ext_channels(const grip_mf_params *p, const grip_mf_prepared *k, mf_core *c, grip_status_t st,
                                  const grip_mf_input *in, const grip_mf_spin *spin, uint32_t mode, uint32_t outputs,
                                  grip_mf_output_ext *out)
{
    return ext_channels_body(p, k, c, st, in, spin, mode, outputs, out, 0);
}
#endif

/* The channels without a prepared set (ext_channels_body), with the eight arguments that
 * grip_mf_eval_ext_spin can pass without a larger frame (its frame is on
 * the deepest stack path of grip_mf_eval_ext; this one is not). */
static MF_NOINLINE grip_status_t ext_channels_spin(const grip_mf_params *p, mf_core *c, const grip_mf_input *in,
                                                  const grip_mf_spin *spin, uint32_t mode, uint32_t outputs,
                                                  grip_status_t st, grip_mf_output_ext *out)
{
#if EXT_PREP_COPY
    return ext_channels_body(p, NULL, c, st, in, spin, mode, outputs, out, 0);
#else
    return ext_channels(p, NULL, c, st, in, spin, mode, outputs, out);
#endif
}

grip_status_t grip_mf_eval_ext_spin(const grip_mf_params *p, const grip_mf_input *in, const grip_mf_spin *spin,
                                    uint32_t outputs, grip_mf_output_ext *out)
{
    mf_core c;
    grip_mf_output base;
    grip_status_t st;
    uint32_t mode;
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    if ((p == NULL) || (in == NULL)) {
        ext_zero(out);
        return GRIP_ERR_NULL;
    }
    if (((outputs & ~(GRIP_MF_EXT_ALL | GRIP_MF_USE_ALL)) != 0u) ||
        ((outputs & (GRIP_MF_USE_TURN_SLIP | GRIP_MF_USE_NO_TURN_SLIP)) ==
         (GRIP_MF_USE_TURN_SLIP | GRIP_MF_USE_NO_TURN_SLIP)) ||
        ((outputs & (GRIP_MF_USE_LIMITS | GRIP_MF_USE_NO_LIMITS)) == (GRIP_MF_USE_LIMITS | GRIP_MF_USE_NO_LIMITS))) {
        ext_zero(out);
        return GRIP_ERR_INPUT;
    }
    if (spin == NULL) {
        spin = &SPIN_ZERO;
    }
    mode = mf_mode_use(p->options, outputs);
    /* the spin and the turn slip (float build: NaN and infinities) */
    if (!r_is_finite(spin->omega) || (((mode & GRIP_MF_OPT_TURN_SLIP) != 0u) && !r_is_finite(spin->phit))) {
        ext_zero(out);
        return GRIP_ERR_INPUT;
    }
    if (((mode | p->options) & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) == 0u) {
        /* no use mode in the set or the call: the plain variant, the cost
         * of before the use modes */
        st = mf_eval_core(p, in, mode, &base, &c);
    } else {
        st = mf_eval_core_use(p, in, spin, mode,
                              (((mode & GRIP_MF_OPT_TURN_SLIP) != 0u) && (spin->omega == R_ZERO))
                                  ? mf_ts_radius(p, in, mode)
                                  : R_ZERO,
                              &base, &c);
    }
    if (!ext_forces(&base, st, out)) {
        ext_zero(out);
        return st;
    }
    return ext_channels_spin(p, &c, in, spin, mode, outputs & GRIP_MF_EXT_ALL, st, out);
}

grip_status_t grip_mf_eval_ext_prepared(const grip_mf_prepared *prep, const grip_mf_input *in, uint32_t outputs,
                                        grip_mf_output_ext *out)
{
    mf_core c;
    grip_mf_output base;
    grip_status_t st;
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    if ((prep == NULL) || (in == NULL)) {
        ext_zero(out);
        return GRIP_ERR_NULL;
    }
    if (prep->p == NULL) {
        ext_zero(out);
        return GRIP_ERR_PARAM;
    }
    /* channels only: the use modes are grip_mf_eval_ext_spin's */
    if ((outputs & ~GRIP_MF_EXT_ALL) != 0u) {
        ext_zero(out);
        return GRIP_ERR_INPUT;
    }
    st = mf_eval_core_prepared(prep, in, &base, &c);
    if (!ext_forces(&base, st, out)) {
        ext_zero(out);
        return st;
    }
#if EXT_PREP_COPY
#if MF_CERT_PATH
    if ((prep->flags & MF_PF_CERT_EXT) != 0u) {
        return ext_channels_prep_c(prep, &c, st, in, outputs, out);
    }
#endif
    return ext_channels_prep(prep, &c, st, in, outputs, out);
#else
    return ext_channels(prep->p, prep, &c, st, in, &SPIN_ZERO, prep->options, outputs, out);
#endif
}
