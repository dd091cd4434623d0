/*
 * est_step.c - grip_est_step: the estimator's stages in their order.
 * Inputs -> longitudinal speed -> lateral observer on / off -> vertical
 * loads -> with the observer running: four tire evaluations at the prior
 * state with the Jacobians -> friction tests -> predict (x = [vy, r, mu,
 * gyro bias]) -> scalar updates of the yaw rate and ay -> the balances ->
 * the ax update (when excited) -> bounds; then the checks and the outputs
 * (the lateral ones at the updated state, extrapolated over the sensor
 * latency). No loop depends on data: every loop runs 3 or 4 times.
 */
#include <stddef.h>

#include "est_internal.h"

/* Every output 0 (valid 0): also what the error returns leave. Kept out of
 * the step's frame, which is under the Magic Formula evaluations. */
static EST_NOINLINE void zero_output(grip_est_output_t *out)
{
    int i;
    out->vx = R_ZERO;
    out->vy = R_ZERO;
    out->beta = R_ZERO;
    out->yaw_rate = R_ZERO;
    out->yaw_rate_ref = R_ZERO;
    out->yaw_error = R_ZERO;
    out->delta = R_ZERO;
    for (i = 0; i < 4; ++i) {
        out->kappa[i] = R_ZERO;
        out->alpha[i] = R_ZERO;
        out->fz[i] = R_ZERO;
        out->fx[i] = R_ZERO;
        out->fy[i] = R_ZERO;
        out->mz[i] = R_ZERO;
        out->util[i] = R_ZERO;
    }
    out->fy_axle[0] = R_ZERO;
    out->fy_axle[1] = R_ZERO;
    out->util_axle[0] = R_ZERO;
    out->util_axle[1] = R_ZERO;
    out->mu = R_ZERO;
    out->mu_conf = R_ZERO;
    out->yaw_rate_bias = R_ZERO;
    out->fy_margin_front = R_ZERO;
    out->vy_sd = R_ZERO;
    out->beta_sd = R_ZERO;
    out->yaw_rate_sd = R_ZERO;
    out->mu_sd = R_ZERO;
    out->vx_sd = R_ZERO;
    out->fy_axle_sd[0] = R_ZERO;
    out->fy_axle_sd[1] = R_ZERO;
    out->steer_char = 0;
    out->valid = 0;
    out->flags = 0;
}

grip_status_t grip_est_step(grip_est_t *est, const grip_input_sample_t *in, grip_est_output_t *out)
{
    est_ctx_t s;
    int stf_upd;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    zero_output(out);
    if (est == NULL || in == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }

    est_take_inputs(est, in, &s);
    est_speed(est, in, &s);
    est_observer_switch(est, &s);
    est_tires(est, in, &s, out);
    if (est->active) {
        est->p_mu_start = est->p[2][2];
        est->p_mu_pred = est->p_mu_start;
        est_friction_tests(est, &s, out);
        stf_upd = est_stiffness(est, &s, out);
        est_stiffness_long(est, &s, out, stf_upd);
        est_roll(est, &s);
        est_lateral_update(est, &s, out);
        est_road(est, &s);
        est_balances(est, &s);
        est_friction_update(est, &s);
        est_bound_state(est, &s);
        est_mu_own(est);
    } else {
        est_road(est, &s);
    }
    est_checks(est, &s, out);
    est_outputs(est, &s, out);
    est_bound_outputs(est, &s, out);
    out->valid = s.valid;
    out->flags = s.flags;
    return ((s.flags & GRIP_EST_F_RATE) != 0u) ? GRIP_WARN_RATE : GRIP_OK;
}
