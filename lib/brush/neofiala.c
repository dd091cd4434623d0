/*
 * neofiala.c - reduced Neo-FIALA, pure and combined slip (seed 000, 5.1-5.40),
 * and the brush model in braking/driving (2.67-2.92), both on the shared
 * core (brush_core.c). Kinematics, normalization and every choice:
 * docs/brush-models.md; float64 twin: kinematics / neofiala_cf / brush_cf in
 * tools/grip_tools/reference/brush.py.
 */
#include <stddef.h>

#include "brush_internal.h"
#include "../core/check_internal.h"

#define KN RCL(1000.0)

/* ---- Neo-FIALA ------------------------------------------------------- */

/* A_gamma of gamma_e = gamma + A_gamma gamma_e |gamma_e| (5.39-5.40):
 * (2 h w / l^2) Ky c_gamma / G_my; 0 when G_my = 0. */
static grip_real_t camber_a(const grip_neofiala_params *p)
{
    if (!(p->g_my > R_ZERO)) {
        return R_ZERO;
    }
    return r_mul(r_div(r_mul(RC(2.0), r_mul(p->h, p->w)), r_sq(p->l)), r_mul(p->c_gamma, r_div(p->ky, p->g_my)));
}

/* Every real field finite. Float: x - x is 0 for a finite x and NaN for an
 * infinite or NaN one, and a NaN survives the sum, so one comparison tests
 * all 24 fields (two operations a field instead of a test and a branch). */
static int nf_params_finite(const grip_neofiala_params *p)
{
#if GRIP_ARITH_FIXED
    (void)p;
    return 1;
#else
    grip_real_t z = (p->l - p->l) + (p->w - p->w) + (p->kx - p->kx) + (p->ky - p->ky) +
                    (p->mu_s - p->mu_s) + (p->mu_d0 - p->mu_d0) + (p->a_v - p->a_v) + (p->q0 - p->q0) +
                    (p->c_q - p->c_q) + (p->c_qm - p->c_qm) + (p->c_xc - p->c_xc) + (p->xi - p->xi) +
                    (p->eps - p->eps) + (p->g_mz - p->g_mz) + (p->a_x - p->a_x) +
                    (p->c_gamma - p->c_gamma) + (p->h - p->h) + (p->g_my - p->g_my) +
                    (p->fz_min - p->fz_min) + (p->fz_max - p->fz_max) + (p->alpha_max - p->alpha_max) +
                    (p->kappa_max - p->kappa_max) + (p->gamma_max - p->gamma_max) + (p->v_max - p->v_max);
    return (z == 0.0f) ? 1 : 0;
#endif
}

/* The first field of p that is not finite (its name), or NULL. Only on
 * the failure path of nf_params_ok: nf_params_finite is the fast test. */
typedef struct {
    const char *name;
    grip_real_t v;
} nf_field_t;

static const char *nf_first_not_finite(const grip_neofiala_params *p)
{
    const nf_field_t f[] = {
        { "l", p->l }, { "w", p->w }, { "kx", p->kx }, { "ky", p->ky }, { "mu_s", p->mu_s },
        { "mu_d0", p->mu_d0 }, { "a_v", p->a_v }, { "q0", p->q0 }, { "c_q", p->c_q }, { "c_qm", p->c_qm },
        { "c_xc", p->c_xc }, { "xi", p->xi }, { "eps", p->eps }, { "g_mz", p->g_mz }, { "a_x", p->a_x },
        { "c_gamma", p->c_gamma }, { "h", p->h }, { "g_my", p->g_my }, { "fz_min", p->fz_min },
        { "fz_max", p->fz_max }, { "alpha_max", p->alpha_max }, { "kappa_max", p->kappa_max },
        { "gamma_max", p->gamma_max }, { "v_max", p->v_max },
    };
    size_t i;
    for (i = 0; i < sizeof f / sizeof f[0]; ++i) {
        if (!r_is_finite(f[i].v)) {
            return f[i].name;
        }
    }
    return "l";
}

/* The checks of grip_neofiala_check_params; the first failure named in *d
 * (d may be NULL). */
static int nf_params_ok(const grip_neofiala_params *p, grip_check_detail_t *d)
{
    grip_real_t fmaxk;
    grip_real_t kmax;
    if (!nf_params_finite(p)) {
        return check_fail(d, "", -1, nf_first_not_finite(p), "finite");
    }
    if (p->n < GRIP_BRUSH_N_MIN || p->n > GRIP_BRUSH_N_MAX) {
        return check_fail(d, "", -1, "n", "in GRIP_BRUSH_N_MIN..GRIP_BRUSH_N_MAX");
    }
    if (!(p->l > R_ZERO && p->l <= RC(2.0))) {
        return check_fail(d, "", -1, "l", "in (0, 2] m");
    }
    if (!(p->w > R_ZERO && p->w <= RC(2.0))) {
        return check_fail(d, "", -1, "w", "in (0, 2] m");
    }
    if (!(p->kx > R_ZERO)) {
        return check_fail(d, "", -1, "kx", "> 0 N");
    }
    if (!(p->ky > R_ZERO)) {
        return check_fail(d, "", -1, "ky", "> 0 N/rad");
    }
    if (!(p->mu_d0 > R_ZERO)) {
        return check_fail(d, "", -1, "mu_d0", "> 0");
    }
    if (!(p->mu_d0 <= p->mu_s && p->mu_s <= RC(3.0))) {
        return check_fail(d, "", -1, "mu_s", "in [mu_d0, 3]");   /* mu_s < mu_d is an error */
    }
    if (!(p->a_v >= R_ZERO && p->a_v <= RC(1.0))) {
        return check_fail(d, "", -1, "a_v", "in [0, 1] s/m");
    }
    if (!(p->fz_min > R_ZERO)) {
        return check_fail(d, "", -1, "fz_min", "> 0 N");
    }
    if (!(p->fz_min <= p->fz_max && p->fz_max <= RCL(100000.0))) {
        return check_fail(d, "", -1, "fz_max", "in [fz_min, 1e5] N");
    }
    kmax = r_max(p->kx, p->ky);
    if (!(r_div(kmax, r_mul(p->mu_s, p->fz_min)) <= RC(1000.0))) {
        return check_fail(d, "", -1, (p->kx >= p->ky) ? "kx" : "ky", "max(kx, ky) / (mu_s fz_min) <= 1000");
    }
    if (!(p->alpha_max > R_ZERO && p->alpha_max <= RC(1.0))) {
        return check_fail(d, "", -1, "alpha_max", "in (0, 1] rad");
    }
    if (!(p->gamma_max >= R_ZERO && p->gamma_max <= RC(0.35))) {
        return check_fail(d, "", -1, "gamma_max", "in [0, 0.35] rad");
    }
    if (!(p->kappa_max > R_ZERO && p->kappa_max <= RC(10.0))) {
        return check_fail(d, "", -1, "kappa_max", "in (0, 10]");
    }
    if (!(p->v_max > R_ZERO && p->v_max <= RC(150.0))) {
        return check_fail(d, "", -1, "v_max", "in (0, 150] m/s");
    }
    fmaxk = r_mul(p->mu_s, r_div(p->fz_max, KN));    /* mu_s Fz_max [kN] */
    if (!(r_abs(p->q0) <= RC(0.5))) {
        return check_fail(d, "", -1, "q0", "|q0| <= 0.5");
    }
    if (!(r_mul(r_abs(p->c_q), fmaxk) <= RC(0.2))) {
        return check_fail(d, "", -1, "c_q", "|c_q| mu_s fz_max <= 0.2 (fz_max in kN)");
    }
    if (!(r_mul(r_mul(r_abs(p->c_qm), fmaxk), p->l) <= RC(0.2))) {
        return check_fail(d, "", -1, "c_qm", "|c_qm| mu_s fz_max l <= 0.2 (fz_max in kN)");
    }
    if (!(r_mul(r_abs(p->c_xc), fmaxk) <= RC(0.1))) {
        return check_fail(d, "", -1, "c_xc", "|c_xc| mu_s fz_max <= 0.1 (fz_max in kN)");
    }
    if (!(r_div(r_mul(r_abs(p->xi), fmaxk), p->l) <= RC(0.1))) {
        return check_fail(d, "", -1, "xi", "|xi| mu_s fz_max / l <= 0.1 (fz_max in kN)");
    }
    if (!(p->eps >= R_ZERO)) {
        return check_fail(d, "", -1, "eps", ">= 0");
    }
    if (!(r_mul(r_mul(p->eps, p->l), r_div(p->ky, KN)) <= RC(1.5))) {
        return check_fail(d, "", -1, "eps", "eps l ky <= 1.5 (ky in kN/rad)");
    }
    if (!(p->g_mz == R_ZERO || (p->g_mz > R_ZERO && r_div(r_mul(p->l, p->ky), p->g_mz) <= RC(1.5)))) {
        return check_fail(d, "", -1, "g_mz", "0, or > 0 with l ky / g_mz <= 1.5");
    }
    if (!(r_div(r_abs(p->a_x), r_mul(p->l, r_mul(p->mu_s, p->fz_min))) <= RC(0.1))) {
        return check_fail(d, "", -1, "a_x", "|a_x| / (l mu_s fz_min) <= 0.1");
    }
    if (!(r_abs(p->c_gamma) <= RC(2.0))) {
        return check_fail(d, "", -1, "c_gamma", "|c_gamma| <= 2");
    }
    if (!(p->h >= R_ZERO)) {
        return check_fail(d, "", -1, "h", ">= 0 m");
    }
    if (!(p->g_my >= R_ZERO)) {
        return check_fail(d, "", -1, "g_my", ">= 0 N/rad");
    }
    if (!(r_mul(RC(4.0), r_mul(r_abs(camber_a(p)), p->gamma_max)) <= RC(0.5))) {
        return check_fail(d, "", -1, "g_my", "4 |A_gamma| gamma_max <= 0.5 (camber coupling, docs/brush-models.md)");
    }
    return 1;
}

grip_status_t grip_neofiala_check_params_detail(const grip_neofiala_params *p, grip_check_detail_t *detail)
{
    check_clear(detail);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    return nf_params_ok(p, detail) ? GRIP_OK : GRIP_ERR_PARAM;
}

grip_status_t grip_neofiala_check_params(const grip_neofiala_params *p)
{
    return grip_neofiala_check_params_detail(p, NULL);
}

#define NF_MAGIC 0x4e464941u   /* "NFIA" */

/* The load-independent constants of a valid set p (every field of *m but
 * p and magic). */
static void nf_derive(const grip_neofiala_params *p, grip_neofiala_model *m)
{
    m->inv1 = brush_core_recip(p->n + 1);
    m->inv2 = brush_core_recip(p->n + 2);
    m->inv3 = brush_core_recip(p->n + 3);
    m->c = r_add(R_ONE, brush_core_recip(p->n));
    m->kyg = (p->g_mz > R_ZERO) ? r_div(r_mul(p->l, p->ky), p->g_mz) : R_ZERO;
    m->eky = r_mul(r_mul(p->eps, p->l), r_div(p->ky, KN));
    m->cam_a = camber_a(p);
}

static grip_status_t nf_eval(const grip_neofiala_params *p, const grip_neofiala_model *d, grip_real_t kappa,
                             grip_real_t alpha, grip_real_t gamma, grip_real_t fz, grip_real_t vx,
                             grip_brush_out *out);

grip_status_t grip_neofiala_prepare(const grip_neofiala_params *p, grip_neofiala_model *m)
{
    if (m == NULL) {
        return GRIP_ERR_NULL;
    }
    m->magic = 0u;
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!nf_params_ok(p, NULL)) {
        return GRIP_ERR_PARAM;
    }
    m->p = *p;
    nf_derive(p, m);
    m->magic = NF_MAGIC;
    return GRIP_OK;
}

grip_status_t grip_neofiala_eval(const grip_neofiala_params *p, grip_real_t kappa,
                                 grip_real_t alpha, grip_real_t gamma, grip_real_t fz,
                                 grip_real_t vx, grip_brush_out *out)
{
    grip_neofiala_model d;                /* only the derived constants are used */
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    brush_out_zero(out);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!nf_params_ok(p, NULL)) {
        return GRIP_ERR_PARAM;
    }
    nf_derive(p, &d);
    return nf_eval(p, &d, kappa, alpha, gamma, fz, vx, out);
}

grip_status_t grip_neofiala_eval_model(const grip_neofiala_model *m, grip_real_t kappa,
                                       grip_real_t alpha, grip_real_t gamma, grip_real_t fz,
                                       grip_real_t vx, grip_brush_out *out)
{
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    brush_out_zero(out);
    if (m == NULL) {
        return GRIP_ERR_NULL;
    }
    if (m->magic != NF_MAGIC) {
        return GRIP_ERR_STATE;
    }
    return nf_eval(&m->p, m, kappa, alpha, gamma, fz, vx, out);
}

/* One evaluation of the valid set p with the derived constants of d
 * (nf_derive; d->p and d->magic are not read). out is zeroed already. */
static grip_status_t nf_eval(const grip_neofiala_params *p, const grip_neofiala_model *d, grip_real_t kappa,
                             grip_real_t alpha, grip_real_t gamma, grip_real_t fz, grip_real_t vx,
                             grip_brush_out *out)
{
    grip_status_t st = GRIP_OK;
    brush_problem pb;
    brush_state s;
    grip_real_t f0, f0k, fl, kxn, kyn, tc, ta, ge, teq, syt, sgn, sx, kf, k, dx, dy, h, cth, sth;
    grip_real_t vs, mud, rd;

    if (!r_is_finite(kappa) || !r_is_finite(alpha) || !r_is_finite(gamma) || !r_is_finite(fz) ||
        !r_is_finite(vx)) {
        return GRIP_ERR_INPUT;
    }
    if (!(fz > R_ZERO)) {
        return GRIP_ERR_INPUT;
    }
    alpha = brush_clamp_sym(alpha, p->alpha_max, &st);
    kappa = brush_clamp(kappa, r_neg(R_ONE), p->kappa_max, &st);
    gamma = brush_clamp_sym(gamma, p->gamma_max, &st);
    fz = brush_clamp(fz, p->fz_min, p->fz_max, &st);
    vx = brush_clamp(r_abs(vx), R_ZERO, p->v_max, &st);

    f0 = r_mul(p->mu_s, fz);                       /* QL: mu_s Fz */
    f0k = r_mul(p->mu_s, r_div(fz, KN));           /* QS: mu_s Fz [kN] */
    fl = r_mul(p->l, f0);                          /* QL: mu_s Fz l */
    kxn = r_div(p->kx, f0);
    kyn = r_div(p->ky, f0);
    tc = brush_core_tanc(alpha);
    ta = r_mul(alpha, tc);
    /* gamma_e = 2 gamma / (1 + sqrt(1 - 4 A |gamma|)) (5.39-5.40) */
    ge = (d->cam_a != R_ZERO)
             ? r_div(r_add(gamma, gamma),
                     r_add(R_ONE, r_sqrt(r_sub(R_ONE, r_mul(RC(4.0), r_mul(d->cam_a, r_abs(gamma)))))))
             : gamma;
    /* equivalent slope tan(alpha) + c_gamma gamma_e, and Ky times it formed
     * from (Ky alpha) tan(alpha)/alpha so that small angles keep their
     * relative precision in the fixed build */
    teq = r_add(ta, r_mul(p->c_gamma, ge));
    syt = r_add(r_mul(r_mul(kyn, alpha), tc), r_mul(r_mul(kyn, p->c_gamma), ge));
    sgn = (syt < R_ZERO) ? r_neg(R_ONE) : R_ONE;   /* mirror: lateral excitation >= 0 */
    teq = r_mul(sgn, teq);
    syt = r_abs(syt);
    sx = brush_slip_split(kappa, kxn, &kf, &k);
    /* sliding direction (5.34) from the slip gradients, formed at 64 times
     * their size for the resolution of small slips */
    dx = brush_slip_split(kappa, RC(64.0), &kf, &k);
    dy = r_mul(kf, r_mul(sgn, r_add(r_mul(r_mul(RC(64.0), alpha), tc), r_mul(r_mul(RC(64.0), p->c_gamma), ge))));
    h = brush_core_hypot(dx, dy);
    if (h > R_ZERO) {
        cth = r_div(dx, h);
        sth = r_div(dy, h);
    } else {
        cth = R_ZERO;
        sth = R_ZERO;
    }
    /* sliding friction from the slip speed (5.35): Vs = |vx| sqrt(kappa^2 + tan^2) */
    vs = r_mul(vx, brush_core_hypot(kappa, ta));
    mud = r_max(r_sub(p->mu_d0, r_mul(p->a_v, vs)), R_ZERO);
    rd = r_div(mud, p->mu_s);

    pb.n = p->n;
    pb.inv1 = d->inv1;
    pb.inv2 = d->inv2;
    pb.inv3 = d->inv3;
    pb.c = d->c;
    pb.sx = sx;
    pb.kf = kf;
    pb.k = k;
    pb.teq = teq;
    pb.syt = syt;
    pb.ky = kyn;
    pb.kyg = d->kyg;
    pb.gn = (p->g_mz > R_ZERO) ? r_div(fl, p->g_mz) : R_ZERO;
    pb.eky = d->eky;
    pb.rdcc = r_mul(r_mul(rd, pb.c), cth);
    pb.rdcs = r_mul(r_mul(rd, pb.c), sth);
    pb.axn = r_div(p->a_x, fl);
    pb.cqx = r_mul(p->c_q, f0k);
    pb.cqm = r_mul(r_mul(p->c_qm, f0k), p->l);
    pb.cxc = r_mul(p->c_xc, f0k);
    pb.xin = r_div(r_mul(p->xi, f0k), p->l);
    pb.q0 = p->q0;

    brush_core_solve(&pb, &s);

    out->fx = r_mul(s.fx, f0);
    out->fy = r_mul(r_neg(r_mul(sgn, s.fy)), f0);
    out->mz = r_mul(r_mul(sgn, s.mz), fl);
    out->rh = s.rh;
    return st;
}

/* ---- brush model, pure longitudinal slip ------------------------------ */

/* The checks of grip_brush_check_params; the first failure named in *d
 * (d may be NULL). */
static int brush_params_ok(const grip_brush_params *p, grip_check_detail_t *d)
{
    if (!r_is_finite(p->kx)) {
        return check_fail(d, "", -1, "kx", "finite");
    }
    if (!r_is_finite(p->mu_s)) {
        return check_fail(d, "", -1, "mu_s", "finite");
    }
    if (!r_is_finite(p->mu_d0)) {
        return check_fail(d, "", -1, "mu_d0", "finite");
    }
    if (!r_is_finite(p->a_v)) {
        return check_fail(d, "", -1, "a_v", "finite");
    }
    if (!r_is_finite(p->fz_min)) {
        return check_fail(d, "", -1, "fz_min", "finite");
    }
    if (!r_is_finite(p->fz_max)) {
        return check_fail(d, "", -1, "fz_max", "finite");
    }
    if (!r_is_finite(p->kappa_max)) {
        return check_fail(d, "", -1, "kappa_max", "finite");
    }
    if (!r_is_finite(p->v_max)) {
        return check_fail(d, "", -1, "v_max", "finite");
    }
    if (p->n < GRIP_BRUSH_N_MIN || p->n > GRIP_BRUSH_N_MAX) {
        return check_fail(d, "", -1, "n", "in GRIP_BRUSH_N_MIN..GRIP_BRUSH_N_MAX");
    }
    if (!(p->kx > R_ZERO)) {
        return check_fail(d, "", -1, "kx", "> 0 N");
    }
    if (!(p->mu_d0 > R_ZERO)) {
        return check_fail(d, "", -1, "mu_d0", "> 0");
    }
    if (!(p->mu_d0 <= p->mu_s && p->mu_s <= RC(3.0))) {
        return check_fail(d, "", -1, "mu_s", "in [mu_d0, 3]");
    }
    if (!(p->a_v >= R_ZERO && p->a_v <= RC(1.0))) {
        return check_fail(d, "", -1, "a_v", "in [0, 1] s/m");
    }
    if (!(p->fz_min > R_ZERO)) {
        return check_fail(d, "", -1, "fz_min", "> 0 N");
    }
    if (!(p->fz_min <= p->fz_max && p->fz_max <= RCL(100000.0))) {
        return check_fail(d, "", -1, "fz_max", "in [fz_min, 1e5] N");
    }
    if (!(r_div(p->kx, r_mul(p->mu_s, p->fz_min)) <= RC(1000.0))) {
        return check_fail(d, "", -1, "kx", "kx / (mu_s fz_min) <= 1000");
    }
    if (!(p->kappa_max > R_ZERO && p->kappa_max <= RC(10.0))) {
        return check_fail(d, "", -1, "kappa_max", "in (0, 10]");
    }
    if (!(p->v_max > R_ZERO && p->v_max <= RC(150.0))) {
        return check_fail(d, "", -1, "v_max", "in (0, 150] m/s");
    }
    return 1;
}

grip_status_t grip_brush_check_params_detail(const grip_brush_params *p, grip_check_detail_t *detail)
{
    check_clear(detail);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    return brush_params_ok(p, detail) ? GRIP_OK : GRIP_ERR_PARAM;
}

grip_status_t grip_brush_check_params(const grip_brush_params *p)
{
    return grip_brush_check_params_detail(p, NULL);
}

/* Below this 1 - rh the sliding speed (2.86) uses 1 - rh = VS_EPS. */
#define VS_EPS RC(0.015625)

grip_status_t grip_brush_eval(const grip_brush_params *p, grip_real_t kappa, grip_real_t fz,
                              grip_real_t vx, grip_brush_out *out)
{
    grip_status_t st = GRIP_OK;
    brush_problem pb;
    brush_state s;
    grip_real_t f0, sx, kf, k, kxn, vs, mud, slide, sg, fxn;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    brush_out_zero(out);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!r_is_finite(kappa) || !r_is_finite(fz) || !r_is_finite(vx)) {
        return GRIP_ERR_INPUT;
    }
    if (!brush_params_ok(p, NULL)) {
        return GRIP_ERR_PARAM;
    }
    if (!(fz > R_ZERO)) {
        return GRIP_ERR_INPUT;
    }
    kappa = brush_clamp(kappa, r_neg(R_ONE), p->kappa_max, &st);
    fz = brush_clamp(fz, p->fz_min, p->fz_max, &st);
    vx = brush_clamp(r_abs(vx), R_ZERO, p->v_max, &st);

    f0 = r_mul(p->mu_s, fz);
    kxn = r_div(p->kx, f0);
    sx = brush_slip_split(kappa, kxn, &kf, &k);

    /* boundary (2.90): 2 Kx S rh = c mu_s Fz D(rh), i.e. the core problem
     * without lateral slip and couplings */
    pb.n = p->n;
    pb.inv1 = brush_core_recip(p->n + 1);
    pb.inv2 = brush_core_recip(p->n + 2);
    pb.inv3 = brush_core_recip(p->n + 3);
    pb.c = r_add(R_ONE, brush_core_recip(p->n));
    pb.sx = sx;
    pb.kf = R_ONE;
    pb.k = R_ONE;
    pb.teq = R_ZERO;
    pb.syt = R_ZERO;
    pb.ky = R_ONE;
    pb.kyg = R_ZERO;
    pb.gn = R_ZERO;
    pb.eky = R_ZERO;
    pb.rdcc = R_ZERO;
    pb.rdcs = R_ZERO;
    pb.axn = R_ZERO;
    pb.cqx = R_ZERO;
    pb.cqm = R_ZERO;
    pb.cxc = R_ZERO;
    pb.xin = R_ZERO;
    pb.q0 = R_ZERO;
    brush_core_solve(&pb, &s);

    /* mu_d = mu_d0 - a_v Vs, Vs = |kappa| V / (1 - rh) (2.85-2.87) */
    vs = r_div(r_mul(r_abs(kappa), vx), r_max(r_sub(R_ONE, s.rh), VS_EPS));
    mud = r_max(r_sub(p->mu_d0, r_mul(p->a_v, vs)), R_ZERO);
    slide = brush_core_slide(s.rh, p->n, pb.inv1);
    sg = r_sign(kappa);
    /* (2.92): Fx = Kx S rh^2 + c mu_d Fz int_rh^1 D */
    fxn = r_add(r_mul(pb.sx, r_sq(s.rh)), r_mul(r_mul(sg, r_div(mud, p->mu_s)), r_mul(pb.c, slide)));
    out->fx = r_mul(fxn, f0);
    out->rh = s.rh;
    return st;
}
