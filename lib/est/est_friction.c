/*
 * est_friction.c - the road friction mu: the excitation that lets it adapt,
 * the mu-independent friction-limit test, the low-friction bound at the
 * understeer limit and that bound's withdrawal, the longitudinal (ax)
 * update, and mu's bounds after the updates. The bounds are bounds, not
 * measurements: they add no confidence. The two pieces the tire evaluation
 * needs, mu's lower bound from the friction in use and mu's column of the
 * Jacobians (its secant), are static inline in est_internal.h, so that the
 * tire loop inlines them.
 */
#include <stddef.h>

#include "est_internal.h"

/* Low-friction detection at the understeer limit (docs/estimator.md,
 * "Friction at the understeer limit"): with the yaw rate held below the
 * lagged linear reference by the share dd for lim_n steps (us_steps), the
 * front axle works near its peak. Its friction in use (steady-state share
 * lr / l of ay, load share of ax) over its peak at mu = 1 (each front
 * wheel's peak at its current load) and over the utilization the deficit
 * implies, min(US_UMAX, US_U0 + US_U1 dd), bounds mu from above (a bound on
 * the state, no update: it adds no confidence). Returned only when below
 * US_ZMAX (low friction): on dry the test cannot tell 1.0 from 0.85.
 * 0 = no bound.
 * Withdrawal: with mu held down by the bound and unconfirmed since
 * (us_low), the same test saying "no deficit" in steady cornering (steady:
 * |ax| and |dvy/dt| below B_AX; braking in a turn lowers the deficit while
 * the front is still at its limit, and a spinning car's yaw rate can match
 * the reference with the rear sliding) at about the front friction in use
 * that set the bound (REL_K to 1 / REL_K of it), for lim_n steps, means the
 * deficit was not the tires' (a steering-angle offset fakes one; once it
 * ends nothing else would lift mu, since in the linear range the ay update
 * does not see it): mu goes back to its value before. Far more friction in
 * use than at the bound shows the bound too low, which the friction in use
 * lifts by itself; the value before would overshoot (docs/estimator.md). */
static grip_real_t understeer_bound(grip_est_t *est, const grip_real_t fz[4], grip_real_t ay, grip_real_t ax,
                                    grip_real_t dd, grip_real_t l, int test_ok, int steady)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t fzf = r_add(fz[0], fz[1]);
    grip_real_t fzs = r_max(r_add(fzf, r_add(fz[2], fz[3])), RCL(1.0));
    grip_real_t pkf = R_ZERO, use_f, z = R_ZERO;
    int i;
    if (test_ok && dd >= RC(EST_US_D)) {
        est->us_steps = count_up(est->us_steps);
    } else {
        est->us_steps = 0;
    }
    if (est->p[2][2] <= RC(EST_P_CONF)) {
        est->us_low = 0;
    }
    if (est->us_steps < est->lim_n && !est->us_low) {
        est->rel_steps = 0;
        return R_ZERO;
    }
    for (i = 0; i < 2; ++i) {
        grip_real_t cf = r_add(est->mu0[0], r_mul(est->mu0_k[0], r_sub(r_div(fz[i], est->fz_static[0]), R_ONE)));
        pkf = r_add(pkf, r_mul(cf, fz[i]));
    }
    use_f = r_div(r_sqrt(r_add(r_sq(r_mul(ay, r_div(c->lr, l))), r_sq(r_mul(ax, r_div(fzf, fzs))))),
                  r_max(r_div(pkf, c->mass), RC(0.5)));
    if (est->us_steps >= est->lim_n) {
        z = r_div(use_f, r_min(RC(EST_US_UMAX), r_add(RC(EST_US_U0), r_mul(RC(EST_US_U1), dd))));
        if (z < RC(EST_US_ZMAX)) {
            est->use_b = use_f;
        } else {
            z = R_ZERO;
        }
    }
    if (est->us_low && test_ok && steady && dd > RC(-EST_LIM_REL) && dd < RC(EST_US_D) &&
        use_f >= r_mul(RC(EST_REL_K), est->use_b) && use_f <= r_div(est->use_b, RC(EST_REL_K))) {
        est->rel_steps = count_up(est->rel_steps);
    } else if (est->us_low && test_ok) {
        /* a step out of the band counts one back, not to 0: at a car's own
         * understeer the deficit hovers at US_D (wet step steer after a
         * steering offset: 0.13 - 0.16; mu stayed at the bound) */
        est->rel_steps = (est->rel_steps > 0) ? (est->rel_steps - 1) : 0;
    } else {
        est->rel_steps = 0;
    }
    if (est->rel_steps >= est->lim_n) {
        est->x[2] = r_max(est->x[2], est->mu_pre);
        est->us_low = 0;
        /* the confidence the updates gained at the bound's mu goes with it */
        est->p[2][2] = r_max(est->p[2][2], RC((EST_CONF_S0 / EST_S_MU) * (EST_CONF_S0 / EST_S_MU)));
    }
    return z;
}

/* Excitation (mu may adapt), the friction-limit test and the understeer
 * bound, all at the prior state. */
void est_friction_tests(grip_est_t *est, est_ctx_t *s, const grip_est_output_t *out)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t vx = s->vx, ax = s->ax, ay = s->ay, yaw = s->yaw;
    int excited = vx >= RC(EST_V_EXC) && s->umax >= RC(EST_EXC_U) && s->ay_ok && s->ax_ok && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
                  r_add(r_abs(ax), r_abs(ay)) >= RC(EST_EXC_A);
    /* friction-limit test, independent of the mu estimate: the yaw
     * rate leaves the (lagged) linear bicycle reference by more than
     * 15 % + 0.03 rad/s for 0.2 s with |a| >= 2 m/s^2 */
    grip_real_t l = r_add(c->lf, c->lr);
    grip_real_t av2 = r_mul(RC(0.01), r_mul(r_mul(est->k_us, vx), vx));
    grip_real_t den = r_max(r_mul(l, r_add(R_ONE, av2)), r_mul(RC(0.1), l));
    grip_real_t r_lin = r_div(r_mul(vx, r_sub(s->delta, s->delta_r)), den);
    grip_real_t a_tot = r_sqrt(r_add(r_sq(ax), r_sq(ay)));
    est->r_lin_f = r_add(est->r_lin_f, r_mul(r_min(r_div(R_ONE, r_mul(RC(EST_LIM_TAU), est->rate)), R_ONE),
                                             r_sub(r_lin, est->r_lin_f)));
    /* both limit tests need speed, the inertial inputs and acceleration */
    int lim_ok = vx >= RC(EST_V_EXC) && s->yaw_ok && s->ax_ok && s->ay_ok && a_tot >= RC(EST_LIM_A); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    if (lim_ok &&
        r_abs(r_sub(yaw, est->r_lin_f)) >= r_add(r_mul(RC(EST_LIM_REL), r_abs(est->r_lin_f)), RC(EST_LIM_ABS))) {
        est->lim_steps = count_up(est->lim_steps);
    } else {
        est->lim_steps = 0;
    }
    s->at_limit = est->lim_steps >= est->lim_n; /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
    /* low-friction detection at the understeer limit (deficit dd of
     * the yaw rate against the lagged reference, same turn direction) */
    {
        grip_real_t dd = (r_abs(est->r_lin_f) > RC(EST_US_R)) ? r_sub(R_ONE, r_div(yaw, est->r_lin_f)) : R_ZERO; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        s->mu_us = understeer_bound(est, out->fz, ay, ax, dd, l,
                                    lim_ok && ((est->r_lin_f > R_ZERO && ay > R_ZERO) ||
                                               (est->r_lin_f < R_ZERO && ay < R_ZERO)),
                                    r_abs(ax) < RC(EST_B_AX) &&
                                        r_abs(r_sub(r_add(ay, s->g_y), r_mul(yaw, vx))) <
                                            r_mul(RC(EST_STEADY_K), c->kin_acc_sd));
    }
    if (s->at_limit) {
        excited = 1;
    }
    s->excited = (uint8_t)excited;
}

/* The longitudinal update, only with an independent speed reference: from
 * the wheel speeds alone, vx is biased by the very slip that carries the
 * information (braking on the simulator's wet road drove mu to its upper
 * bound); and only when the slips push the way the car accelerates: a
 * speed reference that reads a few per cent off the wheel speeds (a
 * speedometer calibration) makes slip of the wrong sign, which would
 * otherwise drive mu down (RAV4 log).
 * A braked wheel at 15 % slip or more (locked, or cycled by an ABS past
 * the tire's peak) works at the road's friction, and its slip is far above
 * what a 0.3 % speed-reference error moves: braking with one is a friction
 * measurement without a speed reference. The free wheels' slips are in the
 * same sum, so it moves mu but adds no confidence: the covariance is kept. */
static void update_ax(grip_est_t *est, const est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t ax = s->ax, m = c->mass;
    grip_real_t h[GRIP_EST_NX];
    int ref_ok = (c->speed_ref_mu != 0u) && s->vs_ok; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    int braked_slip = ax < RC(-EST_AX_TH) && s->kappa_slip; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    if (s->excited && (ref_ok || braked_slip) && s->wheels_ok && s->umax_x >= RC(EST_EXC_U) &&
        r_abs(ax) >= RC(EST_EXC_A) && r_mul(s->kappa_sum, ax) > R_ZERO) {
        grip_real_t ax_pred = r_add(s->ax_m, r_mul(r_div(s->jax_mu, m), r_sub(est->x[2], s->mu)));
        h[0] = R_ZERO;
        h[1] = R_ZERO;
        h[2] = sym_clamp(r_mul(r_div(s->jax_mu, m), RC(EST_S_MU / EST_S_AY)), RC(EST_H_MAX));
        h[3] = R_ZERO;
        (void)est_kf_update(est, h, r_div(r_sub(ax, ax_pred), RC(EST_S_AY)), ref_ok ? RC(EST_R_AX) : RC(EST_R_LOCK), 1, s->b_ok, !ref_ok); /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        est_kf_condition(est);
    }
}

/* mu's bounds after the updates: the friction in use from below, the
 * understeer limit's measurement from above. Bounds on the state, not
 * measurements: they add no confidence (a steering-angle offset fakes an
 * understeer deficit, docs/faults.md). */
static void bound_mu(grip_est_t *est, const est_ctx_t *s)
{
    grip_real_t mu_us = s->mu_us;
    if (mu_us > R_ZERO && !est->us_low && est->x[2] > r_max(mu_us, est->mu_floor)) {
        est->us_low = 1;
        est->mu_pre = est->x[2];
        if (r_sub(est->x[2], r_max(mu_us, est->mu_floor)) > RC(EST_CUT_CLEAR)) {
            est->yaw_mb = R_ZERO; /* the model's forces jump with a large
                                   * cut: the balances' memory was the
                                   * old model's */
            est->lat_sb = R_ZERO;
        }
    }
    /* the understeer measurement cutting mu is applied as an estimate
     * projection (the constrained Kalman filter): the whole state moves
     * along mu's covariance onto the bound, P kept (a bound adds no
     * confidence); vy and r were fitted with the mu it rejects. Not the
     * friction-in-use bound (docs/estimator.md) */
    {
        static const grip_real_t h_mu[GRIP_EST_NX] = { R_ZERO, R_ZERO, R_ONE, R_ZERO };
        grip_real_t mu_hi = (mu_us > R_ZERO) ? r_max(mu_us, est->mu_floor) : RC(EST_MU_MAX); /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        if (mu_us > R_ZERO && est->x[2] > mu_hi) {
            (void)est_kf_update(est, h_mu, r_div(r_sub(mu_hi, est->x[2]), RC(EST_S_MU)), R_ZERO, 1, 0, 1);
        }
        est->x[2] = r_clamp(est->x[2], est->mu_floor, mu_hi);
    }
}

/* After the lateral updates: the ax update, then mu's bounds. */
void est_friction_update(grip_est_t *est, const est_ctx_t *s)
{
    update_ax(est, s);
    bound_mu(est, s);
}

/* A friction measurement from outside the estimator: a scalar update of mu
 * (Joseph form, the gyro bias held), so mu, its deviation and, through the
 * correlations, vy and r move as the filter's own updates move them. The
 * source states the absolute peak friction |F| / Fz; mu is relative to the
 * tires' own peak, so both are divided by the axles' static peak friction
 * weighted by their static loads. The innovation is clamped as every
 * update's: a source far off moves mu over several calls, not at once. */
grip_status_t grip_est_measure_friction(grip_est_t *est, grip_real_t mu_road, grip_real_t mu_road_sd)
{
    static const grip_real_t h_mu[GRIP_EST_NX] = { R_ZERO, R_ZERO, R_ONE, R_ZERO };
    grip_real_t mu0, q;
    if (est == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    /* the negated comparisons also refuse NaN in the float build */
    if (!(mu_road >= RC(0.05) && mu_road <= RC(2.0)) || !(mu_road_sd >= RC(0.01) && mu_road_sd <= RC(1.0))) {
        return GRIP_ERR_INPUT;
    }
    if (!est->mu_src) {
        est->mu_src = 1;
        est->p_mu_own = est->p[2][2];
    }
    mu0 = r_div(r_add(r_mul(est->mu0[0], est->cfg.lr), r_mul(est->mu0[1], est->cfg.lf)),
                r_add(est->cfg.lf, est->cfg.lr));
    q = r_div(r_div(mu_road_sd, mu0), RC(EST_S_MU));
    (void)est_kf_update(est, h_mu, r_div(r_sub(r_div(mu_road, mu0), est->x[2]), RC(EST_S_MU)), r_sq(q), 1, 0, 0);
    est->x[2] = r_clamp(est->x[2], RC(EST_MU_MIN), RC(EST_MU_MAX));
    return GRIP_OK;
}

/* Once a friction measurement from outside was applied, mu_conf and V_MU
 * rest on mu's variance from the tires alone: it grows as P_mu grows in the
 * step (the predict's random walk, the withdrawal of the understeer bound)
 * and takes the information the step's updates added to P_mu, 1 / P_mu
 * after them less 1 / P_mu after the predict (a scalar view: the
 * correlations with vy and r are not carried); never below P_mu. */
void est_mu_own(grip_est_t *est)
{
    grip_real_t p_end = est->p[2][2], own, info;
    if (!est->mu_src) {
        est->p_mu_own = p_end;
        return;
    }
    own = r_min(r_add(est->p_mu_own, r_max(r_sub(est->p_mu_pred, est->p_mu_start), R_ZERO)), RC(EST_P_MAX));
    info = r_sub(r_div(R_ONE, p_end), r_div(R_ONE, est->p_mu_pred));
    if (info > R_ZERO) {
        own = r_div(R_ONE, r_add(r_div(R_ONE, own), info));
    }
    est->p_mu_own = r_clamp(own, p_end, RC(EST_P_MAX));
}
