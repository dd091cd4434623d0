/*
 * relax.c - first-order relaxation-length transient of kappa and alpha.
 * Equations and formats: include/grip/grip_relax.h, docs/measured-data-loop.md.
 *
 * Numerics: the decay exponent a = |vx| dt / sigma is formed as a comparison
 * first (|vx| dt >= A_MAX sigma gives a full step, exp(-A_MAX) is below one
 * QS unit), so the division never saturates; then phi = 1 - exp(-a).
 */
#include <stddef.h>

#include "grip/grip_relax.h"
#include "arith.h"

#define RELAX_MAGIC 0x524c4158u   /* "RLAX" */
#define A_MAX 16.0                 /* exp(-16) = 1.1e-7 < 2^-16 */

static int in_range(grip_real_t x, grip_real_t lo, grip_real_t hi)
{
    return r_is_finite(x) && x >= lo && x <= hi;
}

grip_status_t grip_relax_params_check(const grip_relax_params *p)
{
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!in_range(p->sigma_kappa, RC(0.001), RC(100.0)) ||
        !in_range(p->sigma_alpha, RC(0.001), RC(100.0))) {
        return GRIP_ERR_PARAM;
    }
    if (!in_range(p->v_max, RC(0.001), RC(200.0)) || !in_range(p->v_min, R_ZERO, p->v_max)) {
        return GRIP_ERR_PARAM;
    }
    if (!in_range(p->kappa_max, RC(0.001), RC(10.0)) ||
        !in_range(p->alpha_max, RC(0.001), RC(1.5))) {
        return GRIP_ERR_PARAM;
    }
    return GRIP_OK;
}

static grip_real_t clamp_sym(grip_real_t x, grip_real_t lim, int *clamped)
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

grip_status_t grip_relax_init(grip_relax_state *s, const grip_relax_params *p,
                              grip_real_t kappa0, grip_real_t alpha0)
{
    grip_status_t st;
    int clamped = 0;
    if (s == NULL) {
        return GRIP_ERR_NULL;
    }
    s->magic = 0u;
    s->p = NULL;
    s->kappa_t = R_ZERO;
    s->alpha_t = R_ZERO;
    st = grip_relax_params_check(p);
    if (st != GRIP_OK) {
        return st;
    }
    if (!r_is_finite(kappa0) || !r_is_finite(alpha0)) {
        return GRIP_ERR_INPUT;
    }
    s->kappa_t = clamp_sym(kappa0, p->kappa_max, &clamped);
    s->alpha_t = clamp_sym(alpha0, p->alpha_max, &clamped);
    s->p = p;
    s->magic = RELAX_MAGIC;
    return clamped ? GRIP_WARN_CLAMPED : GRIP_OK;
}

/* 1 - exp(-dist / sigma), dist = |vx| dt >= 0 */
static grip_real_t relax_phi(grip_real_t dist, grip_real_t sigma)
{
    if (dist >= r_mul(RC(A_MAX), sigma)) {
        return R_ONE;
    }
    return r_sub(R_ONE, r_exp(r_neg(r_div(dist, sigma))));
}

grip_status_t grip_relax_step(grip_relax_state *s, grip_real_t kappa, grip_real_t alpha,
                              grip_real_t vx, grip_real_t dt,
                              grip_real_t *kappa_t, grip_real_t *alpha_t)
{
    const grip_relax_params *p;
    grip_real_t v, dist;
    int clamped = 0;
    if (kappa_t != NULL) {
        *kappa_t = R_ZERO;
    }
    if (alpha_t != NULL) {
        *alpha_t = R_ZERO;
    }
    if (s == NULL) {
        return GRIP_ERR_NULL;
    }
    if (s->magic != RELAX_MAGIC || s->p == NULL) {
        return GRIP_ERR_STATE;
    }
    p = s->p;
    if (!r_is_finite(kappa) || !r_is_finite(alpha) || !r_is_finite(vx) || !r_is_finite(dt)) {
        return GRIP_ERR_INPUT;
    }
    if (!(dt >= R_ZERO && dt <= RC(GRIP_RELAX_DT_MAX))) {
        return GRIP_ERR_INPUT;
    }
    kappa = clamp_sym(kappa, p->kappa_max, &clamped);
    alpha = clamp_sym(alpha, p->alpha_max, &clamped);
    v = r_abs(vx);
    if (v > p->v_max) {
        v = p->v_max;
        clamped = 1;
    }
    if (v < p->v_min) {
        v = p->v_min;
    }
    dist = r_mul(v, dt);
    s->kappa_t = r_add(s->kappa_t, r_mul(relax_phi(dist, p->sigma_kappa), r_sub(kappa, s->kappa_t)));
    s->alpha_t = r_add(s->alpha_t, r_mul(relax_phi(dist, p->sigma_alpha), r_sub(alpha, s->alpha_t)));
    if (kappa_t != NULL) {
        *kappa_t = s->kappa_t;
    }
    if (alpha_t != NULL) {
        *alpha_t = s->alpha_t;
    }
    return clamped ? GRIP_WARN_CLAMPED : GRIP_OK;
}
