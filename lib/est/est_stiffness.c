/*
 * est_stiffness.c - each axle's cornering stiffness learned online
 * (configuration stiff_est = 1; docs/estimator/stiffness.md).
 *
 * The tire file is never the car's tire: a generic file, or one fitted on
 * another car, rim, pressure or wear, is off in stiffness by tens of per
 * cent, and the lateral filter then needs slip angles, hence a sideslip,
 * in the inverse proportion. The tires here work at k alpha, k per axle,
 * with k learned as follows.
 *
 * The accelerometer and the gyro measure the axle forces without any tire
 * model: m ay = Ff + Fr and Iz dr/dt = lf Ff - lr Fr (the tires' aligning
 * moments left out: about 2 % of either axle's force; with the model's in
 * the balance the AV-21 log's sideslip was 0.61 deg RMS against 0.60). The model's inverse at
 * each measured force is the model slip psi = k_hat alpha* (alpha* the
 * angle at which the current model gives that force, to first order along
 * the step's slope); the car's slip angle is psi / k. The difference of the
 * front and rear slip angles does not depend on vy (it is lr r / vx ... the
 * kinematics' l r / vx - delta), so
 *
 *     alpha_f - alpha_r = psi_f / k_f - psi_r / k_r
 *
 * is a measurement of (1 / k_f, 1 / k_r) that owes nothing to the
 * sideslip the filter estimates. In a steady turn the two model slips keep
 * the ratio lr : lf times the axles' model stiffnesses, so steady
 * cornering measures one combination (the understeer gradient); yaw
 * transients (dr/dt) separate the axles. A Kalman filter on the two
 * scales, with the tire file as its prior, moves only along what the data
 * measure and keeps the prior elsewhere. The regression's signals are
 * low-passed alike (the relation is linear, so it holds for the filtered
 * signals) and it updates only where the tire works on the linear part of
 * its curve at moderate speed, braking and driving.
 */
#include <stddef.h>
#include "est_internal.h"

/* k from the filter's state (1 / k in units of STF_S_U) */
static grip_real_t stf_scale(grip_real_t x)
{
    return r_div(R_ONE, r_mul(x, RC(EST_STF_S_U)));
}

/* The stability factor A = m (lr Cr - lf Cf) / (l^2 Cf Cr), Cf, Cr per
 * axle at the scales in use (seed eq. 2.17 with K per tire = C / 2), stored
 * as 100 A: the limit tests' and the yaw-rate reference's car is the one the
 * tires are learned to be (grip_est_init, and after each update). */
void est_stability_factor(grip_est_t *est)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t l = r_add(c->lf, c->lr);
    grip_real_t cf = r_mul(r_mul(RC(2.0), est->c_alpha[0]), est->stf_k[0]);
    grip_real_t cr = r_mul(r_mul(RC(2.0), est->c_alpha[1]), est->stf_k[1]);
    grip_real_t num = r_sub(r_mul(c->lr, cr), r_mul(c->lf, cf));   /* N (QL) */
    grip_real_t a1 = r_div(num, cf);                                /* m */
    grip_real_t b100 = r_div(r_mul(RC(100.0), c->mass), cr);        /* 100 kg rad / N */
    est->k_us = r_div(r_mul(a1, b100), r_mul(l, l));
}

int est_stiffness(grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t rdot, l, ff, fr, af, ar, hf, hr, y, a = est->stf_a;
    int ok;
    if (!c->stiff_est) {
        return 0;
    }
    /* a random walk: what is not measured returns towards the prior (the
     * variances grow, so the floor and the correlation's bound hold) */
    est->stf_p[0] = r_min(r_add(est->stf_p[0], est->stf_q), RC(EST_STF_P_MAX));
    est->stf_p[2] = r_min(r_add(est->stf_p[2], est->stf_q), RC(EST_STF_P_MAX));
    /* the yaw acceleration from the last step's yaw rate, when that step
     * learned too (else 0, and the low-pass starts from this step) */
    rdot = (est->stf_n > 0) ? r_mul(r_sub(s->yaw, est->stf_yaw), est->rate) : R_ZERO; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
    est->stf_yaw = s->yaw;
    ok = est->active && s->yaw_ok && s->ay_ok && s->steer_ok && ((s->flags & GRIP_EST_F_STEER_LIMIT) == 0u) && /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
         s->vx >= RC(EST_STF_V) && r_abs(s->ax) < RC(EST_STF_AX) && s->umax_est < RC(EST_STF_U) && !s->lock &&
         !s->spin && !s->dead_reck && !s->at_limit && est_yaw_linear(est, s->yaw, s->vx, RC(EST_STF_D)) &&
         s->slope[0] >= RCL(EST_STF_SLOPE) &&
         s->slope[1] >= RCL(EST_STF_SLOPE) && r_abs(rdot) < RC(EST_STF_RACC);
    if (!ok) {
        est->stf_n = 0;
        return 0;
    }
    /* the axle forces the sensors measure (N), and each one's model slip:
     * the axle's mean lagged angle moved along the step's slope by the
     * model's force error, times the scale the model works at */
    l = r_add(c->lf, c->lr);
    ff = r_div(r_add(r_mul(r_mul(c->mass, c->lr), s->ay), r_mul(c->iz, rdot)), l);
    fr = r_div(r_sub(r_mul(r_mul(c->mass, c->lf), s->ay), r_mul(c->iz, rdot)), l);
    af = r_mul(RC(0.5), r_add(est->alpha_t[0], est->alpha_t[1]));
    ar = r_mul(RC(0.5), r_add(est->alpha_t[2], est->alpha_t[3]));
    hf = r_mul(est->stf_k[0], r_add(af, r_div(r_sub(out->fy_axle[0], ff), s->slope[0])));
    hr = r_mul(est->stf_k[1], r_add(ar, r_div(r_sub(out->fy_axle[1], fr), s->slope[1])));
    y = r_sub(af, ar);
    /* low-passed alike, in crad; the first step of a run starts them */
    if (est->stf_n == 0) {
        a = R_ONE;
    }
    est->stf_z = r_add(est->stf_z, r_mul(a, r_sub(r_mul(y, RC(1.0 / EST_STF_S_Y)), est->stf_z)));
    est->stf_h[0] = r_add(est->stf_h[0], r_mul(a, r_sub(r_mul(hf, RC(1.0 / EST_STF_S_Y)), est->stf_h[0])));
    est->stf_h[1] = r_add(est->stf_h[1], r_mul(a, r_sub(r_mul(hr, RC(1.0 / EST_STF_S_Y)), est->stf_h[1])));
    est->stf_n = count_up(est->stf_n);
    if (est->stf_n < est->stf_n_min || r_add(r_abs(est->stf_h[0]), r_abs(est->stf_h[1])) < RC(EST_STF_H_MIN)) {
        return 0; /* the low-pass not settled on these conditions, or no excitation */
    }
    {
        grip_real_t h0 = r_mul(est->stf_h[0], RC(EST_STF_S_U));
        grip_real_t h1 = r_neg(r_mul(est->stf_h[1], RC(EST_STF_S_U)));
        grip_real_t nu = r_sub(est->stf_z, r_add(r_mul(h0, est->stf_x[0]), r_mul(h1, est->stf_x[1])));
        grip_real_t ph0 = r_add(r_mul(est->stf_p[0], h0), r_mul(est->stf_p[1], h1));
        grip_real_t ph1 = r_add(r_mul(est->stf_p[1], h0), r_mul(est->stf_p[2], h1));
        grip_real_t sv = r_add(r_add(r_mul(h0, ph0), r_mul(h1, ph1)), est->stf_r);
        grip_real_t k0 = r_div(ph0, sv), k1 = r_div(ph1, sv);
        est->stf_x[0] = r_clamp(r_add(est->stf_x[0], r_mul(k0, nu)), RC(EST_STF_X_LO), RC(EST_STF_X_HI));
        est->stf_x[1] = r_clamp(r_add(est->stf_x[1], r_mul(k1, nu)), RC(EST_STF_X_LO), RC(EST_STF_X_HI));
        est->stf_p[0] = r_sub(est->stf_p[0], r_mul(k0, ph0));
        est->stf_p[1] = r_sub(est->stf_p[1], r_mul(k0, ph1));
        est->stf_p[2] = r_sub(est->stf_p[2], r_mul(k1, ph1));
        /* within the floor, the prior and a correlation below 1 */
        cov2_condition(est->stf_p, RC(EST_STF_P_MIN), RC(EST_STF_P_MAX), RC(EST_STF_P_MIN), RC(EST_STF_P_MAX));
        est->stf_k[0] = stf_scale(est->stf_x[0]);
        est->stf_k[1] = stf_scale(est->stf_x[1]);
        est_stability_factor(est);
        est->stf_updates = (est->stf_updates < 0x7fffffffu) ? est->stf_updates + 1u : est->stf_updates;
    }
    return 1;
}

/* ---- the learned blob ---- */

/* CRC-32 (IEEE 802.3, reflected, bitwise: a fixed 8 rounds per byte) */
static uint32_t crc32_bytes(const uint8_t *b, uint32_t n, uint32_t crc)
{
    uint32_t i;
    int k;
    for (i = 0u; i < n; ++i) {
        crc ^= (uint32_t)b[i];
        for (k = 0; k < 8; ++k) {
            crc = ((crc & 1u) != 0u) ? ((crc >> 1) ^ 0xEDB88320u) : (crc >> 1);
        }
    }
    return crc;
}

/* The fingerprint of what the scales apply to: the axles' cornering and
 * slip stiffnesses and loads at init, the axle distances, the mass and the
 * drive split */
static uint32_t stf_config_crc(const grip_est_t *est)
{
    grip_real_t v[10];
    v[0] = est->c_alpha[0];
    v[1] = est->c_alpha[1];
    v[2] = est->fz_static[0];
    v[3] = est->fz_static[1];
    v[4] = est->cfg.lf;
    v[5] = est->cfg.lr;
    v[6] = est->cfg.mass;
    v[7] = est->c_kappa[0];
    v[8] = est->c_kappa[1];
    v[9] = est->cfg.drive_front;
    return ~crc32_bytes((const uint8_t *)v, (uint32_t)sizeof v, 0xFFFFFFFFu);
}

static uint32_t blob_version(void)
{
#if GRIP_ARITH_FIXED
    return GRIP_EST_LEARNED_VERSION * 2u + 1u;
#else
    return GRIP_EST_LEARNED_VERSION * 2u;
#endif
}

static uint32_t blob_crc(const grip_est_learned_t *b)
{
    return ~crc32_bytes((const uint8_t *)b, (uint32_t)offsetof(grip_est_learned_t, crc), 0xFFFFFFFFu);
}

grip_status_t grip_est_learned_get(const grip_est_t *est, grip_est_learned_t *blob)
{
    if (est == NULL || blob == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    blob->magic = GRIP_EST_LEARNED_MAGIC;
    blob->version = blob_version();
    blob->config_crc = stf_config_crc(est);
    blob->updates = est->stf_updates;
    blob->k[0] = est->stf_k[0];
    blob->k[1] = est->stf_k[1];
    blob->x[0] = est->stf_x[0];
    blob->x[1] = est->stf_x[1];
    blob->p[0] = est->stf_p[0];
    blob->p[1] = est->stf_p[1];
    blob->p[2] = est->stf_p[2];
    blob->kx_updates = est->kx_updates;
    blob->kx = est->kx;
    blob->kx_x[0] = est->kx_x[0];
    blob->kx_x[1] = est->kx_x[1];
    blob->kx_p[0] = est->kx_p[0];
    blob->kx_p[1] = est->kx_p[1];
    blob->kx_p[2] = est->kx_p[2];
    blob->rg_updates = est->rg_updates;
    blob->rg_k = est->rg_k;
    blob->rg_x = est->rg_x;
    blob->rg_p = est->rg_p;
    blob->crc = blob_crc(blob);
    return GRIP_OK;
}

grip_status_t grip_est_learned_set(grip_est_t *est, const grip_est_learned_t *blob)
{
    grip_real_t x_lo = RC(EST_STF_X_LO), x_hi = RC(EST_STF_X_HI);
    grip_real_t p_min = RC(EST_STF_P_MIN), p_max = RC(EST_STF_P_MAX);
    int a;
    if (est == NULL || blob == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    if (blob->magic != GRIP_EST_LEARNED_MAGIC || blob->version != blob_version() || blob->crc != blob_crc(blob) ||
        blob->config_crc != stf_config_crc(est)) {
        return GRIP_ERR_PARAM;
    }
    for (a = 0; a < 2; ++a) {
        /* the negated comparisons also refuse NaN in the float build */
        if (!(blob->x[a] >= x_lo && blob->x[a] <= x_hi)) {
            return GRIP_ERR_PARAM;
        }
    }
    if (!cov2_in_range(blob->p, p_min, p_max, p_min, p_max)) {
        return GRIP_ERR_PARAM;
    }
    if (!(blob->kx_x[0] >= RC(EST_KX_X_LO) && blob->kx_x[0] <= RC(EST_KX_X_HI)) ||
        !(blob->kx_x[1] >= RC(-EST_KX_XD_MAX) && blob->kx_x[1] <= RC(EST_KX_XD_MAX)) ||
        !cov2_in_range(blob->kx_p, RC(EST_KX_P_MIN), RC(EST_KX_P_MAX), RC(EST_KX_PD_MIN), RC(EST_KX_PD_MAX))) {
        return GRIP_ERR_PARAM;
    }
    /* the roll gradient: within the learner's range once learned, else the
     * configuration's range (the prior is the configured roll_gradient) */
    if (!(blob->rg_x >= ((blob->rg_updates > 0u) ? RC(EST_RG_X_LO) : R_ZERO) &&
          blob->rg_x <= ((blob->rg_updates > 0u) ? RC(EST_RG_X_HI) : RC(0.05 / EST_RG_S_U))) ||
        !(blob->rg_p >= RC(EST_RG_P_MIN) && blob->rg_p <= RC(EST_RG_P_MAX))) {
        return GRIP_ERR_PARAM;
    }
    est->stf_x[0] = blob->x[0];
    est->stf_x[1] = blob->x[1];
    est->stf_p[0] = blob->p[0];
    est->stf_p[1] = blob->p[1];
    est->stf_p[2] = blob->p[2];
    est->stf_updates = blob->updates;
    est->stf_k[0] = stf_scale(est->stf_x[0]);
    est->stf_k[1] = stf_scale(est->stf_x[1]);
    est_stability_factor(est);
    est->kx_x[0] = blob->kx_x[0];
    est->kx_x[1] = blob->kx_x[1];
    est->kx_p[0] = blob->kx_p[0];
    est->kx_p[1] = blob->kx_p[1];
    est->kx_p[2] = blob->kx_p[2];
    est->kx_updates = blob->kx_updates;
    est_kx_apply(est);
    /* the roll gradient once one was learned, with roll_est; a blob with
     * nothing learned of it, or roll_est 0, takes it back to the configured
     * one and its prior */
    est->rg_updates = est->cfg.roll_est ? blob->rg_updates : 0u;
    if (est->rg_updates > 0u) {
        est->rg_x = blob->rg_x;
        est->rg_p = blob->rg_p;
        est_roll_apply(est);
    } else {
        est->rg_x = r_mul(est->cfg.roll_gradient, RC(1.0 / EST_RG_S_U));
        est->rg_p = RC(EST_RG_P_MAX);
        est->rg_k = est->cfg.roll_gradient;
        est->ay_fac = r_div(R_ONE, r_add(R_ONE, r_mul(RC(EST_G), est->cfg.roll_gradient)));
    }
    return GRIP_OK;
}
