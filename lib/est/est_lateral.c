/*
 * est_lateral.c - the lateral filter: an extended Kalman filter of
 * x = [vy, r, mu, gyro bias] in scaled units (est_tuning.h), started above
 * V_ON and stopped below V_OFF (the gyro bias then adapts at rest), its
 * predict (vy kinematic, r from the tire model's yaw moment, mu and the
 * bias random walks), the scalar updates of the yaw rate and ay in Joseph
 * form, and the bounds of vy, r and the bias.
 */
#include "est_internal.h"

/* state unit of each state: SI, except the gyro bias, which is kept in its
 * scaled unit (0.001 rad/s) so that its small per-step corrections survive
 * Q15.16 (1 LSB = 1.5e-5 rad/s in SI) */
static const grip_real_t est_s[GRIP_EST_NX] = { RC(EST_S_VY), RC(EST_S_R), RC(EST_S_MU), R_ONE };

/* P <- F P F' + Q in scaled units. Only the rows of vy and r of F are
 * given (f, 2 x 4): mu and the gyro bias are random walks (identity rows),
 * so their block of P only gets its process noise; this keeps the
 * temporaries at 2 x 4. Out of line: inlined into the predict it cost the
 * M4F 17 more instructions per step (measured). */
static EST_NOINLINE void kf_predict(grip_est_t *e, grip_real_t f[2][GRIP_EST_NX])
{
    grip_real_t fp[2][GRIP_EST_NX];
    int i, j, k;
    for (i = 0; i < 2; ++i) {
        for (j = 0; j < GRIP_EST_NX; ++j) {
            grip_real_t s = R_ZERO;
            for (k = 0; k < GRIP_EST_NX; ++k) {
                s = r_add(s, r_mul(f[i][k], e->p[k][j]));
            }
            fp[i][j] = s;
        }
    }
    for (i = 0; i < 2; ++i) {
        for (j = i; j < GRIP_EST_NX; ++j) {
            grip_real_t s = fp[i][j];          /* rows 2, 3 of F are identity rows */
            if (j < 2) {
                s = R_ZERO;
                for (k = 0; k < GRIP_EST_NX; ++k) {
                    s = r_add(s, r_mul(fp[i][k], f[j][k]));
                }
            }
            e->p[i][j] = s;
            e->p[j][i] = s;
        }
    }
    for (i = 0; i < GRIP_EST_NX; ++i) {
        e->p[i][i] = r_add(e->p[i][i], e->q[i]);
    }
}

/* Keeps P symmetric positive definite in the presence of rounding: diagonal
 * within [P_MIN, P_MAX], every correlation below 0.99. */
void est_kf_condition(grip_est_t *e)
{
    grip_real_t sd[GRIP_EST_NX];
    int i, j;
    for (i = 0; i < GRIP_EST_NX; ++i) {
        e->p[i][i] = r_clamp(e->p[i][i], RC(EST_P_MIN), RC(EST_P_MAX));
        sd[i] = r_sqrt(e->p[i][i]);
    }
    for (i = 0; i < GRIP_EST_NX; ++i) {
        for (j = i + 1; j < GRIP_EST_NX; ++j) {
            grip_real_t b = r_mul(RC(0.99), r_mul(sd[i], sd[j]));
            grip_real_t v = sym_clamp(e->p[i][j], b);
            e->p[i][j] = v;
            e->p[j][i] = v;
        }
    }
}

/* The variances alone into [P_MIN, P_MAX]: between the predict and the
 * updates of one step (the correlations are bounded once, after the last
 * update, by est_kf_condition: within a step the Joseph form keeps P
 * positive semi-definite, and the bound never acted there on the golden
 * sequences; it took three full conditionings per step, ~460 Cortex-M4F
 * instructions, four square roots each). */
static void kf_clamp_diag(grip_est_t *e)
{
    int i;
    for (i = 0; i < GRIP_EST_NX; ++i) {
        e->p[i][i] = r_clamp(e->p[i][i], RC(EST_P_MIN), RC(EST_P_MAX));
    }
}

/* Scalar measurement update in Joseph form for an arbitrary gain:
 * P' = (I - k h) P (I - k h)' + k r k'
 *    = P - k ph' - ph k' + k (k s)'         with ph = P h', s = h ph + r,
 * where k = ph / s, and k_mu = 0 when mu must not adapt, k_b = 0 when the
 * gyro bias must not (the Joseph form stays exact for that sub-optimal
 * gain). nu: innovation (scaled).
 * Adds k nu (in SI) to the state; keep_p: the covariance is left as it was
 * (a biased measurement that may move the state but not add confidence). Returns the normalized innovation
 * squared nu^2 / s of the (clamped) innovation, in [0, 16]. */
grip_real_t est_kf_update(grip_est_t *e, const grip_real_t h[GRIP_EST_NX], grip_real_t nu, grip_real_t r,
                          int mu_ok, int b_ok, int keep_p)
{
    grip_real_t ph[GRIP_EST_NX], k[GRIP_EST_NX], ks[GRIP_EST_NX];
    grip_real_t s = r;
    grip_real_t lim, sq;
    int i, j;
    for (i = 0; i < GRIP_EST_NX; ++i) {
        grip_real_t v = R_ZERO;
        for (j = 0; j < GRIP_EST_NX; ++j) {
            v = r_add(v, r_mul(e->p[i][j], h[j]));
        }
        ph[i] = v;
        s = r_add(s, r_mul(h[i], v));
    }
    for (i = 0; i < GRIP_EST_NX; ++i) {
        k[i] = r_div(ph[i], s);
        ks[i] = ph[i];
    }
    if (!mu_ok) {
        k[2] = R_ZERO;
        ks[2] = R_ZERO;
    }
    if (!b_ok) {
        k[3] = R_ZERO;
        ks[3] = R_ZERO;
    }
    sq = r_sqrt(s);
    lim = r_mul(RC(EST_NU_SIGMA), sq);
    nu = sym_clamp(nu, lim);
    for (i = 0; i < GRIP_EST_NX; ++i) {
        e->x[i] = r_add(e->x[i], r_mul(r_mul(k[i], nu), est_s[i]));
    }
    if (!keep_p) {
        for (i = 0; i < GRIP_EST_NX; ++i) {
            for (j = i; j < GRIP_EST_NX; ++j) {
                grip_real_t v = r_sub(e->p[i][j], r_mul(k[i], ph[j]));
                v = r_sub(v, r_mul(ph[i], k[j]));
                v = r_add(v, r_mul(k[i], ks[j]));
                e->p[i][j] = v;
                e->p[j][i] = v;
            }
        }
    }
    /* nu / sqrt(s) rather than nu^2 / s: nu^2 would leave Q15.16 */
    return r_sq(sym_clamp(r_div(nu, sq), RC(EST_NU_SIGMA)));
}

/* load-weighted mean utilization of an axle's two tires */
static grip_real_t axle_utilization(grip_real_t u0, grip_real_t u1, grip_real_t fz0, grip_real_t fz1)
{
    grip_real_t num = r_add(r_mul(r_min(u0, R_ONE), fz0), r_mul(r_min(u1, R_ONE), fz1));
    return r_div(num, r_max(r_add(fz0, fz1), RCL(1.0)));
}

/* how far a utilization is into the band U_R0 .. 1 where the ay noise grows, [0, 1] */
static grip_real_t limit_share(grip_real_t u)
{
    return r_clamp(r_div(r_sub(u, RC(EST_U_R0)), RC(1.0 - EST_U_R0)), R_ZERO, R_ONE);
}

/* Noise of the ay measurement. At the friction limit the tire model is
 * least certain: R grows from utilization U_R0 to 1 by up to R_LIM x with
 * the most-used tire, and by up to R_AXLE x more with an axle's load-weighted
 * mean utilization, i.e. with both tires of an axle at the limit: in a spin
 * the model, past its peak, pulls vy the wrong way, while one tire's
 * utilization alone may be a faulty wheel speed's slip (docs/estimator.md).
 * The utilizations are scaled by k (the caller's: mu / (mu + AY_U_K
 * sigma_mu) at the car's limit, else 1), i.e. taken at a mu that much
 * higher: a mu still too high puts the model at its own limit, and R at
 * the limit would keep the ay update from lowering mu. */
static grip_real_t ay_noise(const grip_est_output_t *out, grip_real_t umax, grip_real_t k)
{
    grip_real_t u_axle = r_max(axle_utilization(r_mul(k, out->util[0]), r_mul(k, out->util[1]), out->fz[0], out->fz[1]),
                               axle_utilization(r_mul(k, out->util[2]), r_mul(k, out->util[3]), out->fz[2], out->fz[3]));
    grip_real_t r = r_add(R_ONE, r_mul(RC(EST_R_LIM), limit_share(r_mul(k, umax))));
    r = r_add(r, r_mul(RC(EST_R_AXLE), limit_share(u_axle)));
    return r_mul(RC(EST_R_AY), r);
}

/* The lateral observer on or off. Stopped, it holds vy at 0 and r at the
 * gyro's, forgets the limit tests and the balances, and lets the gyro bias
 * walk; at rest the gyro reads its bias (the yaw rate is 0). Then the prior
 * state of this step into s. */
void est_observer_switch(grip_est_t *est, est_ctx_t *s)
{
    grip_real_t vx = s->vx, yaw = s->yaw;
    int i;
    int active = est->active;
    s->ay_upd = 0u;
    if (active && (vx < RC(EST_V_OFF) || !s->steer_ok || !(s->valid & GRIP_EST_V_VX))) {
        active = 0;
    }
    if (!active && vx >= RC(EST_V_ON) && s->steer_ok && s->yaw_ok && (s->valid & GRIP_EST_V_VX)) {
        active = 1;
        int j;
        est->x[0] = R_ZERO;
        est->x[1] = yaw;
        for (i = 0; i < 2; ++i) {
            for (j = 0; j < GRIP_EST_NX; ++j) {
                est->p[i][j] = R_ZERO;
                est->p[j][i] = R_ZERO;
            }
        }
        est->p[0][0] = RC(EST_P0_VY);
        est->p[1][1] = RC(EST_P0_R);
        s->flags |= GRIP_EST_F_RESET;
    }
    est->active = active;
    if (!active) {
        s->flags |= GRIP_EST_F_LOW_SPEED;
        est->rlx_init = 0;
        est->yaw_mb = R_ZERO;
        est->lat_sb = R_ZERO;
        est->x[0] = R_ZERO;
        est->x[1] = yaw;
        est->r_lin_f = yaw;
        est->lim_steps = 0;
        est->us_steps = 0;
        est->us_low = 0;
        est->rel_steps = 0;
        /* gyro bias: random walk; at standstill (every wheel at rest) the
         * yaw rate is zero and the gyro reads its bias */
        est->p[3][3] = r_add(est->p[3][3], est->q[3]);
        if (s->at_rest && s->yaw_ok && s->wheels_ok && s->ax_ok && r_abs(s->ax) < RC(EST_B_AX)) {
            grip_real_t h[GRIP_EST_NX];
            h[0] = R_ZERO;
            h[1] = R_ZERO;
            h[2] = R_ZERO;
            h[3] = RC(EST_S_B / EST_S_R);
            (void)est_kf_update(est, h, r_div(r_sub(est->hold[H_YAW], r_mul(RC(EST_S_B), est->x[3])), RC(EST_S_R)),
                                RC(EST_R_YAW), 0, 1, 0);
            est_kf_condition(est);
            est->x[3] = sym_clamp(est->x[3], RC(EST_B_MAX / EST_S_B));
        }
    }
    s->vy = est->x[0];
    s->r = est->x[1];
    s->mu = est->x[2];
    est->mu_lin = s->mu;
}

/* Predict. vy: kinematic process vy' = ay - r vx (the tire model enters
 * through the ay measurement, so a flat tire curve at the limit leaves vy
 * to the kinematics instead of to model errors); the model's ay stands in
 * when the accelerometer is missing. r from the model's yaw moment. */
static void predict(grip_est_t *est, est_ctx_t *s)
{
    grip_real_t rate = est->rate, vx = s->vx;
    grip_real_t f[2][GRIP_EST_NX];   /* rows vy, r of the transition (mu, bias: identity) */
    /* the gyro bias adapts only where the tire model is trusted (linear
     * range, no locked or spinning wheel, no hard braking or driving, no
     * friction-limit indication, no fast yaw transient, where the modelled
     * tire lag errs most); else it would absorb the model's errors */
    s->b_ok = r_abs(s->racc) < RC(EST_B_RACC) && s->umax_est < RC(EST_B_U) && r_abs(s->ay) < RC(EST_B_A) && r_abs(s->ax) < RC(EST_B_AX) && !s->lock && !s->spin &&
              !s->at_limit;
    s->dvy = r_div(r_sub(r_add(s->ay_ok ? s->ay : s->ay_m, s->g_y), r_mul(s->r, vx)), rate);
    s->dr = r_div(s->racc, rate);
    if (s->ay_ok) {
        f[0][0] = R_ONE;
        f[0][1] = r_mul(r_div(r_neg(vx), rate), RC(EST_S_R / EST_S_VY));
        f[0][2] = R_ZERO;
        f[0][3] = R_ZERO;
    } else {
        f[0][0] = r_add(R_ONE, r_div(s->a_vv, rate));
        f[0][1] = r_mul(r_div(r_sub(s->a_vr, vx), rate), RC(EST_S_R / EST_S_VY));
        f[0][2] = r_mul(r_div(s->a_vm, rate), RC(EST_S_MU / EST_S_VY));
        f[0][3] = R_ZERO;
    }
    f[1][0] = r_mul(r_div(s->a_rv, rate), RC(EST_S_VY / EST_S_R));
    f[1][1] = r_add(R_ONE, r_div(s->a_rr, rate));
    f[1][2] = r_mul(r_div(s->a_rm, rate), RC(EST_S_MU / EST_S_R));
    f[1][3] = R_ZERO;
    est->x[0] = r_add(s->vy, s->dvy);
    est->x[1] = r_add(s->r, s->dr);
    kf_predict(est, f);
    kf_clamp_diag(est);
    est->p_mu_pred = est->p[2][2];
}

/* The yaw rate: the gyro reads r + bias. mu does not adapt on it: the yaw
 * moment balance is the most model-sensitive equation (Iz, lever arms, the
 * front/rear force split at the limit) and drove mu away at the limit of
 * the simulator's ramp steer. */
static void update_yaw(grip_est_t *est, est_ctx_t *s)
{
    grip_real_t h[GRIP_EST_NX];
    if (s->yaw_ok) {
        h[0] = R_ZERO;
        h[1] = R_ONE;
        h[2] = R_ZERO;
        h[3] = RC(EST_S_B / EST_S_R);
        (void)est_kf_update(est, h, r_div(r_sub(s->yaw, est->x[1]), RC(EST_S_R)),
                            RC(EST_R_YAW), 0, s->b_ok, 0);
        kf_clamp_diag(est);
    }
    s->r_upd = est->x[1];
}

/* ay, mu adapting only when excited. A road-wheel angle beyond the rack's
 * travel (STEER_LIMIT) is not the car's: the model's slip angles would be
 * fitted to it (at lock on a straight road vy went to 2.3 m/s, past both
 * axles' peaks, and stayed there after the steering recovered). */
static void update_ay(grip_est_t *est, est_ctx_t *s, const grip_est_output_t *out)
{
    grip_real_t ay_pred, h[GRIP_EST_NX], mu = s->mu;
    if (!s->ay_ok || ((s->flags & GRIP_EST_F_STEER_LIMIT) != 0u)) {
        return;
    }
    ay_pred = r_add(s->ay_m, r_add(r_mul(s->a_vv, r_sub(est->x[0], s->vy)), r_mul(s->a_vr, r_sub(est->x[1], s->r))));
    ay_pred = r_add(ay_pred, r_mul(s->a_vm, r_sub(est->x[2], mu)));
    h[0] = sym_clamp(r_mul(s->a_vv, RC(EST_S_VY / EST_S_AY)), RC(EST_H_MAX_VY));
    h[1] = sym_clamp(r_mul(s->a_vr, RC(EST_S_R / EST_S_AY)), RC(EST_H_MAX));
    h[2] = sym_clamp(r_mul(s->a_vm, RC(EST_S_MU / EST_S_AY)), RC(EST_H_MAX));
    h[3] = R_ZERO;
    /* the utilization at mu + AY_U_K sigma_mu only while the car's
     * own yaw response (the mu-independent limit test) says it is
     * at its limit: elsewhere a model at its own limit is the
     * model's claim, not evidence (AV-21 log: with a mu cut by the
     * understeer bound, the updates confirmed it to mu_conf 0.74);
     * nor while the bound holds mu (a steering offset fakes both
     * the deficit and the limit test) */
    s->nis_ay = est_kf_update(est, h, r_div(r_sub(s->ay, ay_pred), RC(EST_S_AY)),
                              ay_noise(out, s->umax_est,
                                       (s->at_limit && !est->us_low) ? r_div(mu, r_add(mu, r_mul(RC(EST_AY_U_K * EST_S_MU),
                                                                                         r_sqrt(est->p[2][2]))))
                                                                     : R_ONE),
                              s->excited, s->b_ok, 0);
    s->ay_upd = 1u;
}

/* The lateral filter's step: predict, then the updates of the yaw rate and
 * ay (each measurement predicted to first order at the current state from
 * the forces at the prior point vy, r, mu). */
void est_lateral_update(grip_est_t *est, est_ctx_t *s, const grip_est_output_t *out)
{
    predict(est, s);
    update_yaw(est, s);
    update_ay(est, s, out);
    est_kf_condition(est);
}

/* The state's bounds: |vy| by VY_K |vx| + 1 m/s, the yaw rate by the
 * gyro's range, the gyro bias by B_MAX. */
void est_bound_state(grip_est_t *est, const est_ctx_t *s)
{
    est->x[0] = sym_clamp(est->x[0], r_add(r_mul(RC(EST_VY_K), r_abs(s->vx)), R_ONE));
    est->x[1] = sym_clamp(est->x[1], RC(EST_YAW_MAX));
    est->x[3] = sym_clamp(est->x[3], RC(EST_B_MAX / EST_S_B));
}
