/*
 * fiala_sakai.c - the two brush models with closed-form adhesion boundaries
 * (parabolic pressure): classic FIALA, normalized (seed 000, 2.54-2.66), and
 * Sakai's combined-slip model (2.93-2.125). Derivations and the re-derived
 * signs: docs/brush-models.md; float64 twins: fiala_cf, sakai_cf in
 * tools/grip_tools/reference/brush.py. No loops.
 */
#include <stddef.h>

#include "brush_internal.h"
#include "../core/check_internal.h"

/* ---- FIALA ----------------------------------------------------------- */

/* The checks of grip_fiala_check_params; the first failure named in *d
 * (d may be NULL). */
static int fiala_params_ok(const grip_fiala_params *p, grip_check_detail_t *d)
{
    if (!r_is_finite(p->ky)) {
        return check_fail(d, "", -1, "ky", "finite");
    }
    if (!r_is_finite(p->mu)) {
        return check_fail(d, "", -1, "mu", "finite");
    }
    if (!r_is_finite(p->l)) {
        return check_fail(d, "", -1, "l", "finite");
    }
    if (!r_is_finite(p->fz_min)) {
        return check_fail(d, "", -1, "fz_min", "finite");
    }
    if (!r_is_finite(p->fz_max)) {
        return check_fail(d, "", -1, "fz_max", "finite");
    }
    if (!r_is_finite(p->alpha_max)) {
        return check_fail(d, "", -1, "alpha_max", "finite");
    }
    if (!(p->ky > R_ZERO)) {
        return check_fail(d, "", -1, "ky", "> 0 N/rad");
    }
    if (!(p->mu > R_ZERO && p->mu <= RC(3.0))) {
        return check_fail(d, "", -1, "mu", "in (0, 3]");
    }
    if (!(p->l > R_ZERO && p->l <= RC(2.0))) {
        return check_fail(d, "", -1, "l", "in (0, 2] m");
    }
    if (!(p->fz_min > R_ZERO)) {
        return check_fail(d, "", -1, "fz_min", "> 0 N");
    }
    if (!(p->fz_min <= p->fz_max && p->fz_max <= RCL(100000.0))) {
        return check_fail(d, "", -1, "fz_max", "in [fz_min, 1e5] N");
    }
    if (!(r_div(p->ky, r_mul(p->mu, p->fz_min)) <= RC(1000.0))) {
        return check_fail(d, "", -1, "ky", "ky / (mu fz_min) <= 1000");
    }
    if (!(p->alpha_max > R_ZERO && p->alpha_max <= RC(1.0))) {
        return check_fail(d, "", -1, "alpha_max", "in (0, 1] rad");
    }
    return 1;
}

grip_status_t grip_fiala_check_params_detail(const grip_fiala_params *p, grip_check_detail_t *detail)
{
    check_clear(detail);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    return fiala_params_ok(p, detail) ? GRIP_OK : GRIP_ERR_PARAM;
}

grip_status_t grip_fiala_check_params(const grip_fiala_params *p)
{
    return grip_fiala_check_params_detail(p, NULL);
}

grip_status_t grip_fiala_eval(const grip_fiala_params *p, grip_real_t alpha, grip_real_t fz,
                              grip_brush_out *out)
{
    grip_status_t st = GRIP_OK;
    grip_real_t f0;
    grip_real_t phi;
    grip_real_t fyn;
    grip_real_t mzn;
    grip_real_t s;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    brush_out_zero(out);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!r_is_finite(alpha) || !r_is_finite(fz)) {
        return GRIP_ERR_INPUT;
    }
    if (!fiala_params_ok(p, NULL)) {
        return GRIP_ERR_PARAM;
    }
    if (!(fz > R_ZERO)) {
        return GRIP_ERR_INPUT;
    }
    alpha = brush_clamp_sym(alpha, p->alpha_max, &st);
    fz = brush_clamp(fz, p->fz_min, p->fz_max, &st);
    f0 = r_mul(p->mu, fz);
    s = (alpha < R_ZERO) ? r_neg(R_ONE) : R_ONE;
    /* phi = Ky |tan alpha| / (mu Fz) (2.64) */
    phi = r_mul(r_abs(r_mul(r_div(p->ky, f0), alpha)), brush_core_tanc(alpha));
    if (phi < RC(3.0)) {
        /* (2.65) phi - phi^2/3 + phi^3/27 = 1 - r^3 and (2.66) phi/6 - phi^2/6 +
         * phi^3/18 - phi^4/162 = (phi/6) r^3 with r = 1 - phi/3 = l_h/l: the
         * factored forms have no cancellation near phi = 3 */
        grip_real_t r = r_sub(R_ONE, r_mul(phi, RC(1.0 / 3.0)));
        grip_real_t r3 = r_mul(r_sq(r), r);
        fyn = r_sub(R_ONE, r3);
        mzn = r_mul(r_mul(phi, RC(1.0 / 6.0)), r3);
        out->rh = r;
    } else {
        fyn = R_ONE;                                  /* full sliding */
        mzn = R_ZERO;
        out->rh = R_ZERO;
    }
    out->fy = r_mul(r_neg(r_mul(s, fyn)), f0);
    out->mz = r_mul(r_mul(s, mzn), r_mul(p->l, f0));
    return st;
}

/* ---- Sakai ----------------------------------------------------------- */

/* The checks of grip_sakai_check_params; the first failure named in *d
 * (d may be NULL). */
static int sakai_params_ok(const grip_sakai_params *p, grip_check_detail_t *d)
{
    if (!r_is_finite(p->k)) {
        return check_fail(d, "", -1, "k", "finite");
    }
    if (!r_is_finite(p->g_y)) {
        return check_fail(d, "", -1, "g_y", "finite");
    }
    if (!r_is_finite(p->mu_s)) {
        return check_fail(d, "", -1, "mu_s", "finite");
    }
    if (!r_is_finite(p->mu_d)) {
        return check_fail(d, "", -1, "mu_d", "finite");
    }
    if (!r_is_finite(p->l)) {
        return check_fail(d, "", -1, "l", "finite");
    }
    if (!r_is_finite(p->fz_min)) {
        return check_fail(d, "", -1, "fz_min", "finite");
    }
    if (!r_is_finite(p->fz_max)) {
        return check_fail(d, "", -1, "fz_max", "finite");
    }
    if (!r_is_finite(p->alpha_max)) {
        return check_fail(d, "", -1, "alpha_max", "finite");
    }
    if (!r_is_finite(p->kappa_max)) {
        return check_fail(d, "", -1, "kappa_max", "finite");
    }
    if (!(p->k > R_ZERO)) {
        return check_fail(d, "", -1, "k", "> 0 N");
    }
    if (!(p->g_y > R_ZERO)) {
        return check_fail(d, "", -1, "g_y", "> 0 N/m");
    }
    if (!(p->l > R_ZERO && p->l <= RC(2.0))) {
        return check_fail(d, "", -1, "l", "in (0, 2] m");
    }
    if (!(p->mu_d > R_ZERO)) {
        return check_fail(d, "", -1, "mu_d", "> 0");
    }
    if (!(p->mu_d <= p->mu_s && p->mu_s <= RC(3.0))) {
        return check_fail(d, "", -1, "mu_s", "in [mu_d, 3]");
    }
    if (!(p->fz_min > R_ZERO)) {
        return check_fail(d, "", -1, "fz_min", "> 0 N");
    }
    if (!(p->fz_min <= p->fz_max && p->fz_max <= RCL(100000.0))) {
        return check_fail(d, "", -1, "fz_max", "in [fz_min, 1e5] N");
    }
    if (!(r_div(p->k, r_mul(p->mu_s, p->fz_min)) <= RC(1000.0))) {
        return check_fail(d, "", -1, "k", "k / (mu_s fz_min) <= 1000");
    }
    if (!(r_div(r_mul(p->mu_s, p->fz_max), r_mul(p->l, p->g_y)) <= RC(4.0))) {
        return check_fail(d, "", -1, "g_y", "mu_s fz_max / (l g_y) <= 4");
    }
    if (!(p->alpha_max > R_ZERO && p->alpha_max <= RC(1.0))) {
        return check_fail(d, "", -1, "alpha_max", "in (0, 1] rad");
    }
    if (!(p->kappa_max > R_ZERO && p->kappa_max <= RC(10.0))) {
        return check_fail(d, "", -1, "kappa_max", "in (0, 10]");
    }
    return 1;
}

grip_status_t grip_sakai_check_params_detail(const grip_sakai_params *p, grip_check_detail_t *detail)
{
    check_clear(detail);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    return sakai_params_ok(p, detail) ? GRIP_OK : GRIP_ERR_PARAM;
}

grip_status_t grip_sakai_check_params(const grip_sakai_params *p)
{
    return grip_sakai_check_params_detail(p, NULL);
}

grip_status_t grip_sakai_eval(const grip_sakai_params *p, grip_real_t kappa, grip_real_t alpha,
                              grip_real_t fz, grip_brush_out *out)
{
    grip_status_t st = GRIP_OK;
    grip_real_t f0, kn, rd, a, sl, sgx, sgy, gy, g, cth, sth, rh, r2, om, om2, j0, fx, fy, y0, mzy, mzx, s;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    brush_out_zero(out);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!r_is_finite(kappa) || !r_is_finite(alpha) || !r_is_finite(fz)) {
        return GRIP_ERR_INPUT;
    }
    if (!sakai_params_ok(p, NULL)) {
        return GRIP_ERR_PARAM;
    }
    if (!(fz > R_ZERO)) {
        return GRIP_ERR_INPUT;
    }
    alpha = brush_clamp_sym(alpha, p->alpha_max, &st);
    kappa = brush_clamp(kappa, r_neg(R_ONE), p->kappa_max, &st);
    fz = brush_clamp(fz, p->fz_min, p->fz_max, &st);

    f0 = r_mul(p->mu_s, fz);
    kn = r_div(p->k, f0);
    rd = r_div(p->mu_d, p->mu_s);
    s = (alpha < R_ZERO) ? r_neg(R_ONE) : R_ONE;
    a = r_abs(alpha);
    /* gradients: braking (S cos a, sin a) (2.99-2.100), driving (S, (1-S) tan a)
     * (2.101-2.102); the stresses K g are formed before rounding g */
    if (kappa < R_ZERO) {
        sgx = r_mul(r_mul(kn, kappa), r_cos(a));
        sgy = r_mul(r_mul(kn, a), brush_core_sinc(a));
        gy = r_mul(a, brush_core_sinc(a));
    } else {
        sl = r_add(R_ONE, kappa);
        sgx = r_div(r_mul(kn, kappa), sl);
        gy = r_div(r_mul(a, brush_core_tanc(a)), sl);
        sgy = r_div(r_mul(r_mul(kn, a), brush_core_tanc(a)), sl);
    }
    g = brush_core_hypot(sgx, sgy);                    /* K |g| / (mu_s Fz) */
    if (g > R_ZERO) {
        cth = r_div(sgx, g);                          /* sliding direction (2.116) */
        sth = r_div(sgy, g);
    } else {
        cth = R_ZERO;
        sth = R_ZERO;
    }
    /* friction circle at the boundary (2.113-2.114): rh = 1 - K |g| / (3 mu_s Fz) */
    rh = r_max(r_sub(R_ONE, r_mul(g, RC(1.0 / 3.0))), R_ZERO);
    r2 = r_sq(rh);
    om = r_sub(R_ONE, rh);
    om2 = r_sq(om);
    j0 = r_mul(om2, r_add(R_ONE, r_add(rh, rh)));      /* int_rh^1 6 x (1 - x) */
    fx = r_add(r_mul(sgx, r2), r_mul(r_mul(rd, cth), j0));   /* (2.120), (2.123) */
    fy = r_add(r_mul(sgy, r2), r_mul(r_mul(rd, sth), j0));   /* (2.121), (2.124) */
    y0 = r_mul(fy, r_div(f0, r_mul(p->l, p->g_y)));    /* y0 / l, y0 = Fy / G_y */
    /* lateral stresses, arm x - 1/2 */
    mzy = r_add(r_mul(r_mul(sgy, r2), r_mul(r_sub(r_mul(RC(4.0), rh), RC(3.0)), RC(1.0 / 6.0))),
                r_mul(r_mul(RC(1.5), r_mul(rd, sth)), r_mul(r2, om2)));
    /* longitudinal stresses at the tip's lateral position */
    mzx = r_add(r_mul(sgx, r_add(r_mul(y0, r2), r_mul(RC(2.0 / 3.0), r_mul(gy, r_mul(r2, rh))))),
                r_mul(r_mul(rd, cth),
                      r_add(r_mul(y0, j0),
                            r_mul(r_mul(gy, rh), r_mul(om2, r_mul(RC(0.5), r_add(R_ONE, r_mul(RC(3.0), rh))))))));
    out->fx = r_mul(fx, f0);
    out->fy = r_mul(r_neg(r_mul(s, fy)), f0);
    out->mz = r_mul(r_mul(s, r_add(mzy, mzx)), r_mul(p->l, f0));
    out->rh = rh;
    return st;
}
