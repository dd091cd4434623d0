/*
 * est_outputs.c - forces and outputs: the yaw and lateral balances (the
 * yaw moment and the lateral force the model lacks, measured by the gyro
 * and the accelerometer, put into the output axle forces), the lateral
 * outputs at the updated state extrapolated over the sensors' latency
 * (slip angles, forces, vy, beta, yaw rate), and the outputs every step
 * gives (the yaw-rate reference, the under/oversteer indication, the front
 * axle's margin). Output corrections only: the filter's states do not take
 * them.
 */
#include "est_internal.h"

/* The yaw balance: the yaw moment the model lacks (the yaw-rate update's
 * correction of the predicted r, taken before the ay update moves r too,
 * as a yaw acceleration against the model's) as a front-axle force
 * Iz dr / l, low-passed. Not while braking or driving (|ax| >= MB_AX): the
 * model's left / right Fx moment errs there too. */
static void yaw_balance(grip_est_t *est, const est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t dmr = R_ZERO;
    if (s->yaw_ok && r_abs(s->ax) < RC(EST_MB_AX)) {
        dmr = sym_clamp(r_mul(r_sub(s->r_upd, r_add(s->r, s->dr)), est->rate), RC(EST_MB_RACC));
    }
    est->yaw_mb = r_add(est->yaw_mb,
                        r_mul(est->mb_a, r_sub(r_div(r_mul(c->iz, dmr), r_add(c->lf, c->lr)), est->yaw_mb)));
}

/* The lateral balance: the lateral force the model still lacks at the
 * updated state (the ay update is weak at the limit, where the model is
 * least trusted), low-passed; target 0 while braking or driving, or
 * without ay. */
static void lateral_balance(grip_est_t *est, const est_ctx_t *s)
{
    grip_real_t sb_t = R_ZERO;
    if (s->ay_ok && r_abs(s->ax) < RC(EST_MB_AX)) {
        grip_real_t ay_pred = r_add(s->ay_m, r_add(r_mul(s->a_vv, r_sub(est->x[0], s->vy)), r_mul(s->a_vr, r_sub(est->x[1], s->r))));
        ay_pred = r_add(ay_pred, r_mul(s->a_vm, r_sub(est->x[2], s->mu)));
        /* within the accelerometer's range: mass x residual then fits QL */
        sb_t = r_mul(est->cfg.mass, sym_clamp(r_sub(s->ay, ay_pred), RC(EST_ACC_MAX)));
    }
    est->lat_sb = r_add(est->lat_sb, r_mul(est->sb_a, r_sub(sb_t, est->lat_sb)));
}

/* The balances, after the yaw-rate and ay updates and before the ax
 * update (the lateral balance takes the state there). */
void est_balances(grip_est_t *est, const est_ctx_t *s)
{
    yaw_balance(est, s);
    lateral_balance(est, s);
}

/* The lateral outputs (vy, beta, yaw_rate, alpha[], fy[], fy_axle) at the updated state, extrapolated over the inertial
 * sensors' latency: vy and r along their derivatives (vyd, racc), the slip
 * angles exactly at that state, the forces to first order along the local
 * slope d Fy / d alpha of the step's tire evaluation (the same slope as the
 * Jacobians: -max(G_MIN, sqrt(1 - u)) Fz/Fz_static C_alpha) times the share
 * of the way the tire's lagged slip angle moves over the latency.
 * The updates' correction of vy (duv: posterior - predicted) moves each
 * lagged slip angle along the kinematic slope first: vy is predicted from
 * the measured ay, so its correction is a re-estimate of where the car is,
 * not motion the tire lags (the Jacobians assume the whole slope). r is
 * predicted from the model's yaw moment: its correction stays in the lag,
 * else a model-vs-gyro fight drifts the lagged angles (docs/estimator.md,
 * "Tire relaxation"). */
static void lateral_outputs(grip_est_t *est, grip_est_output_t *out, const est_ctx_t *s, grip_real_t vx,
                            grip_real_t vyd, grip_real_t racc, grip_real_t duv)
{
    grip_real_t lat = est->cfg.latency;
    grip_real_t vy = sym_clamp(r_add(est->x[0], r_mul(lat, vyd)), r_add(r_mul(RC(EST_VY_K), r_abs(vx)), R_ONE));
    grip_real_t r = sym_clamp(r_add(est->x[1], r_mul(lat, racc)), RC(EST_YAW_MAX));
    /* the outputs' road-wheel angle (steering latency), to first order about
     * the state's (a few mrad) */
    grip_real_t cd_o = r_sub(s->cd, r_mul(s->sd, est->delta_o_d)), sd_o = r_add(s->sd, r_mul(s->cd, est->delta_o_d));
    int i;
    for (i = 0; i < 4; ++i) {
        int axle = i >> 1;
        grip_real_t cdi = axle ? s->cr : cd_o, sdi = axle ? s->sr : sd_o;
        /* the wheel kinematics of the tire evaluation (est_tires.c), written
         * out again rather than shared through a helper with out-parameters,
         * which cost 24 B of M0+ stack */
        grip_real_t vcx = r_sub(vx, r_mul(r, est->yw[i]));
        grip_real_t vcy = r_add(vy, r_mul(r, est->xw[i]));
        grip_real_t vxw, vyw, alpha, fzr = R_ZERO, g, dfda, den, t;
        vxw = r_add(r_mul(cdi, vcx), r_mul(sdi, vcy));
        vyw = r_sub(r_mul(cdi, vcy), r_mul(sdi, vcx));
        den = r_max(r_abs(vxw), RC(EST_V_OFF));
        t = r_div(vyw, den);
        alpha = r_atan(t);
        /* d alpha = c2 cdi duv / den, c2 = 1 / (1 + t^2) */
        est->alpha_t[i] = r_add(est->alpha_t[i],
                                r_div(r_div(r_mul(cdi, duv), r_add(R_ONE, r_sq(sym_clamp(t, RC(100.0))))), den));
        if (out->fz[i] > RCL(50.0)) {
            fzr = r_div(out->fz[i], est->fz_static[axle]);
        }
        g = r_max(RC(EST_G_MIN), r_sqrt(r_sub(R_ONE, r_min(out->util[i], R_ONE))));
        dfda = r_neg(r_mul(g, r_mul(r_mul(fzr, est->c_alpha[axle]), est->stf_k[axle])));
        /* the tire's lagged slip angle (the step's tire worked at out->alpha[i])
         * moves towards the kinematic one over the latency's distance */
        out->fy[i] = r_add(out->fy[i],
                           r_mul(dfda, r_sub(r_add(est->alpha_t[i],
                                                   r_mul(relax_share(r_mul(r_abs(vxw), lat), wheel_sigma(est, axle, out->fz[i])),
                                                         r_sub(alpha, est->alpha_t[i]))),
                                             out->alpha[i])));
        /* ... and along d Fy / d mu with the updates' change of mu */
        out->fy[i] = r_add(out->fy[i], r_mul(est->fy_dmu[i], r_sub(est->x[2], est->mu_lin)));
        out->alpha[i] = alpha;
    }
    /* the yaw balance: +df on the front axle, -df on the rear (the lateral
     * sum unchanged, the moment l df), and the lateral balance in the axles'
     * static shares (no moment), shared by load; the axle's force stays
     * within its friction */
    for (i = 0; i < 2; ++i) {
        int w0 = i + i, w1 = i + i + 1; /* the axle's left and right wheel */
        grip_real_t fza = r_max(r_add(out->fz[w0], out->fz[w1]), RCL(1.0));
        grip_real_t cap = r_mul(r_mul(est->x[2], est->mu0[i]), fza);
        grip_real_t fa = r_add(out->fy[w0], out->fy[w1]);
        grip_real_t sb_f = r_mul(est->sb_share_f, est->lat_sb);
        grip_real_t df = r_add(est->yaw_mb, sb_f);
        if (i == 1) {
            df = r_sub(r_sub(est->lat_sb, sb_f), est->yaw_mb);
        }
        df = r_clamp(df, r_sub(r_neg(cap), fa), r_sub(cap, fa));
        out->fy[w0] = r_add(out->fy[w0], r_mul(df, r_div(out->fz[w0], fza)));
        out->fy[w1] = r_add(out->fy[w1], r_mul(df, r_div(out->fz[w1], fza)));
    }
    out->fy_axle[0] = r_add(out->fy[0], out->fy[1]);
    out->fy_axle[1] = r_add(out->fy[2], out->fy[3]);
    out->vy = vy;
    out->beta = r_atan(r_div(vy, r_max(out->vx, RC(EST_V_OFF))));
    out->yaw_rate = r;
}

/* The outputs: with the observer the lateral ones at the updated state,
 * vx among them (at the outputs' time too, like vy and r: its prediction's
 * rate at the updated state; a spin slows it by ~6 m/s^2); without it vx
 * and the yaw rate as measured, vy and beta 0. Then the steering angle, mu
 * and the gyro bias, the yaw-rate reference with the under/oversteer
 * indication, and with the observer the front axle's lateral margin. */
void est_outputs(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t vx = s->vx, yaw = s->yaw, delta = s->delta;
    grip_real_t mu = est->x[2];
    if (est->active) {
        out->vx = r_add(vx, r_mul(c->latency, vx_rate(est, s->ax, est->x[1], est->x[0], s->g_x)));
        grip_real_t vyd = r_sub(r_add(s->ay_ok ? s->ay : s->ay_m, s->g_y), r_mul(est->x[1], vx));
        lateral_outputs(est, out, s, vx, vyd, s->racc, r_sub(est->x[0], r_add(s->vy, s->dvy)));
        /* vy, beta: the kinematic vy (est_integrity.c; the filter's where
         * that is the better) over the latency, along its own rate */
        out->vy = sym_clamp(r_add(est->vy_k, r_mul(c->latency, vyd)), RC(EST_WS_MAX));
        out->beta = r_atan(r_div(out->vy, r_max(out->vx, RC(EST_V_OFF))));
        out->vy_sd = s->vy_sd;
        out->beta_sd = s->beta_sd;
    } else {
        out->vx = vx;
        out->yaw_rate = yaw;
    }
    if (s->yaw_ok) {
        s->valid |= GRIP_EST_V_YAW;
    }
    out->delta = delta;
    out->mu = mu;
    out->yaw_rate_bias = r_mul(RC(EST_S_B), est->x[3]);
    /* yaw-rate reference: steady-state bicycle (eq. 2.14 with 2.17), limited
     * to what the road can carry: |r| <= mu mu0 g / vx */
    if ((s->valid & GRIP_EST_V_VX) && s->steer_ok && vx >= RC(EST_V_ON)) {
        grip_real_t l = r_add(c->lf, c->lr);
        grip_real_t av2 = r_mul(RC(0.01), r_mul(r_mul(est->k_us, vx), vx));
        grip_real_t den = r_max(r_mul(l, r_add(R_ONE, av2)), r_mul(RC(0.1), l));
        grip_real_t rr = r_div(r_mul(vx, r_sub(delta, s->delta_r)), den);
        grip_real_t lim = r_div(r_mul(r_mul(mu, r_min(est->mu0[0], est->mu0[1])), RC(EST_G)), vx);
        out->yaw_rate_ref = sym_clamp(rr, lim);
        s->valid |= GRIP_EST_V_YAW_REF;
        if (s->yaw_ok) {
            grip_real_t d, thr, sgn;
            out->yaw_error = r_sub(yaw, out->yaw_rate_ref);
            sgn = (r_abs(out->yaw_rate_ref) > RC(0.01)) ? r_sign(out->yaw_rate_ref) : r_sign(yaw);
            d = r_mul(sgn, r_sub(out->yaw_rate_ref, yaw));
            thr = r_add(RC(0.03), r_mul(RC(0.1), r_abs(out->yaw_rate_ref)));
            out->steer_char = (d > thr) ? 1 : ((r_neg(d) > thr) ? -1 : 0); /* grip-deviation: MISRA-10.6 tool: ?: of constants is not composite (8.10.3) */
            s->valid |= GRIP_EST_V_STEER;
        }
    }
    if (est->active) {
        out->fy_margin_front = r_sub(r_mul(r_mul(mu, est->mu0[0]), r_add(out->fz[0], out->fz[1])), r_abs(out->fy_axle[0]));
        if (s->valid & GRIP_EST_V_BETA) {
            s->valid |= GRIP_EST_V_MARGIN;
        }
    }
}
