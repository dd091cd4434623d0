/*
 * est_checks.c - consistency checks and validity: the model-consistency
 * (misfit) statistics of the ay update, which sideslip and axle outputs
 * may be marked valid, and mu's confidence. mu_conf measures only the
 * filter's own variance of mu, i.e. how well the data constrain mu if the
 * tire model is right; the misfit check says whether it is.
 */
#include "est_internal.h"

/* Model consistency (docs/estimator.md), for each ay update: the
 * low-passed ay NIS (1 on average for a consistent filter), and the share
 * of time the model claims saturated tires while the car's yaw response
 * (the mu-independent limit test) is not at the limit. A tire model that
 * does not fit is absorbed by vy and mu, so the NIS alone stays small
 * (AV-21 log). */
static void misfit(grip_est_t *est, const est_ctx_t *s)
{
    grip_real_t sat = (s->vx >= RC(EST_V_EXC) && s->umax_est >= RC(EST_SAT_U) && !s->at_limit) ? R_ONE : R_ZERO;
    est->nis_f = r_add(est->nis_f, r_mul(est->nis_a, r_sub(s->nis_ay, est->nis_f)));
    est->sat_f = r_add(est->sat_f, r_mul(est->nis_a, r_sub(sat, est->sat_f)));
    if (est->nis_f > RC(EST_NIS_HI) || est->sat_f > RC(EST_SAT_HI)) {
        est->misfit = 1;
    } else if (est->nis_f < RC(EST_NIS_LO) && est->sat_f < RC(EST_SAT_LO)) {
        est->misfit = 0;
    } /* grip-deviation: MISRA-15.7 between the thresholds the state is kept (hysteresis) */
    /* the confidence cap (est_confidence) has its own hysteresis: a share
     * that hovers at SAT_MU would toggle mu's validity */
    if (est->sat_f > RC(EST_SAT_MU)) {
        est->sat_cap = 1;
    } else if (est->sat_f < RC(EST_SAT_MU_LO)) {
        est->sat_cap = 0;
    } /* grip-deviation: MISRA-15.7 between the thresholds the state is kept (hysteresis) */
}

/* The sideslip and the axle forces are valid with ay and the yaw rate, but
 * not with every wheel locked (spinning): the slips leave the tire model's
 * range and the lateral force no longer tells the slip angle, so beta is
 * dead reckoning too; nor with a tire model that does not fit the car
 * (misfit), nor with a steering angle beyond the rack's travel (no ay
 * update: dead reckoning as well), nor with the kinematic vy rejecting the
 * filter's (est_integrity.c); the sideslip not either with its deviation
 * beyond the consumer's limit. The per-wheel outputs come from the same
 * model. */
static void lateral_validity(const grip_est_t *est, est_ctx_t *s)
{
    if (s->ay_ok && s->yaw_ok && s->ax_ok && !s->dead_reck && !est->misfit && !s->disagree &&
        ((s->flags & (GRIP_EST_F_STEER_LIMIT | GRIP_EST_F_RATE)) == 0u)) {
        /* the axle forces are the model's at the filter's state and the
         * balances': beta's deviation limit is not theirs */
        s->valid |= GRIP_EST_V_AXLE;
        if (s->beta_sd <= est->cfg.beta_sd_max) {
            s->valid |= GRIP_EST_V_BETA;
        }
    }
    if (!(s->valid & GRIP_EST_V_BETA)) {
        s->valid &= ~(GRIP_EST_V_WHEEL(0) | GRIP_EST_V_WHEEL(1) | GRIP_EST_V_WHEEL(2) | GRIP_EST_V_WHEEL(3));
    }
    if (s->excited) {
        s->flags |= GRIP_EST_F_EXCITED;
    }
}

/* mu's confidence from its variance, capped (and V_MU withheld) while the
 * misfit check or the saturation share's cap holds. */
static void confidence(const grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    /* from the tires alone: a friction measurement from outside is the
     * caller's, not a friction the estimator identified */
    grip_real_t sig = r_mul(r_sqrt(est->mu_src ? est->p_mu_own : est->p[2][2]), RC(EST_S_MU));
    out->mu_conf = r_clamp(r_div(r_sub(RC(EST_CONF_S0), sig), RC(0.1)), R_ZERO, R_ONE);
    if (est->misfit) {
        /* the tire model does not explain the measurements: whatever mu
         * the filter found, it is not the road's */
        s->flags |= GRIP_EST_F_MODEL_MISFIT;
        out->mu_conf = r_min(out->mu_conf, RC(EST_CONF_MISFIT));
    } else if (est->sat_cap) {
        /* the saturation share on its way to the misfit level: no
         * confidence in mu while that evidence builds up (the check is
         * low-passed over 2 s and declares the misfit late) */
        out->mu_conf = r_min(out->mu_conf, RC(EST_CONF_MISFIT));
    } else {
        /* model consistent */
    }
    /* a filter vy the kinematic one rejects: mu absorbed the misfit */
    if (out->mu_conf >= RC(0.5) && s->ax_ok && ((s->flags & GRIP_EST_F_RATE) == 0u) && !s->disagree) {
        s->valid |= GRIP_EST_V_MU;
    }
}

/* The checks of every step, before the outputs (whose front-axle margin is
 * valid with the sideslip): with the observer running the misfit
 * statistics of the step's ay update and the lateral outputs' validity;
 * mu's confidence. */
void est_checks(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    est_integrity(est, s, out);
    if (est->active) {
        if (s->ay_upd) {
            misfit(est, s);
        }
        lateral_validity(est, s);
    }
    confidence(est, s, out);
}
