/*
 * est_roll.c - the body's roll gradient learned online (configuration
 * roll_est = 1; docs/estimator/roll.md).
 *
 * The accelerometer is fixed to the body, which rolls by k f under the
 * road-plane specific force f (k the roll gradient); it reads f cos(k f) +
 * g sin(k f), to first order (1 + g k) f, and est_input.c divides by
 * 1 + g k. A k below the car's leaves the gravity of the unremoved roll in
 * the lateral force sum and in the kinematic vy (the independent judge's
 * cars roll 0.0116 - 0.0159 rad/(m/s^2) against the default 0.0088).
 *
 * Without a bank, f is the lateral acceleration a = vx r + dvy/dt (dvy/dt
 * from the filter's vy of the last two steps). Both signals band-passed
 * alike (low-pass EST_RG_T less a low-pass EST_RG_TH of it: the
 * accelerometer's and gyro's offsets out) give
 *
 *     bp(ay_meas) - bp(a) = g k bp(a)
 *
 * a scalar measurement of k, updated by a Kalman filter whose prior is the
 * configured roll_gradient. A bank adds g sin(bank) to f and not to a: it
 * reads as a lower k wherever it moves with the turn. A constant bank, or
 * one changing slower than EST_RG_TH, leaves the band-pass; a curve banked
 * towards its centre moves the bank with the turn at its entry and exit,
 * one way each, so the update waits for a weave: bp(a) beyond +EST_RG_H_MIN
 * and beyond -EST_RG_H_MIN within EST_RG_T_ALT. A bank that changes within
 * the band (a road whose bank undulates while the car weaves) makes the
 * samples' own k, z / (g bp(a)), scatter far from any roll: a sample more
 * than EST_RG_DK from the k in use is not taken. What a bank can still do
 * (S-bends banked with each turn) is bounded by the measurement's
 * correlation time, the prior and the range [EST_RG_K_MIN, EST_RG_K_MAX].
 * The relation needs the tire's linear part and no braking (the
 * stiffness learner's gates) and a body roll linear in ay (EST_RG_AY).
 */
#include "est_internal.h"

void est_roll_apply(grip_est_t *est)
{
    /* k = x S_U, and ay_fac = 1 / (1 + g k); divided by 1 / S_U, which
     * Q15.16 holds exactly */
    grip_real_t gk = r_div(r_mul(RC(EST_G), est->rg_x), RC(1.0 / EST_RG_S_U));
    est->rg_k = r_div(est->rg_x, RC(1.0 / EST_RG_S_U));
    est->ay_fac = r_div(R_ONE, r_add(R_ONE, gk));
}

/* The band-pass's step of one signal i: the fast low-pass, then the slow
 * one of it; returns the band-passed value */
static grip_real_t rg_band(grip_est_t *est, int i, grip_real_t v)
{
    est->rg_f[i] = r_add(est->rg_f[i], r_mul(est->rg_a1, r_sub(v, est->rg_f[i])));
    est->rg_m[i] = r_add(est->rg_m[i], r_mul(est->rg_a2, r_sub(est->rg_f[i], est->rg_m[i])));
    return r_sub(est->rg_f[i], est->rg_m[i]);
}

void est_roll(grip_est_t *est, const est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t am, dvy, u, ba, bu;
    int ok;
    if (!c->roll_est) {
        return;
    }
    est->rg_p = r_min(r_add(est->rg_p, est->rg_q), RC(EST_RG_P_MAX));
    am = est->hold[H_AY]; /* the measured ay, before the roll's correction */
    /* the band-pass runs (and restarts when these fail) while the relation
     * holds at all: the roll linear in ay, no sliding or braking, no
     * declared misfit, no bank the bank observer knows of */
    ok = est->active && s->yaw_ok && s->ay_ok && s->steer_ok && ((s->flags & GRIP_EST_F_STEER_LIMIT) == 0u) && /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
         s->vx >= RC(EST_STF_V) && r_abs(s->ax) < RC(EST_STF_AX) && r_abs(am) <= RC(EST_RG_AY) && !s->lock &&
         !s->spin && !s->dead_reck && !s->at_limit && !est->misfit &&
         (!c->bank_est || r_abs(est->road_gy) <= RC(EST_RG_BANK));
    if (!ok) {
        est->rg_n = 0;
        return;
    }
    /* the first step starts the band-pass where the roll gradient in use
     * puts the lateral acceleration (a start that is no equilibrium stays
     * in the slow low-pass for EST_RG_TH), and the next step's dvy/dt */
    if (est->rg_n == 0) {
        est->rg_f[0] = am;
        est->rg_m[0] = am;
        est->rg_f[1] = r_mul(est->ay_fac, am);
        est->rg_m[1] = est->rg_f[1];
        est->rg_pos = 1000000; /* count_up's saturation: never */
        est->rg_neg = 1000000;
        est->rg_vy = est->x[0];
        est->rg_n = 1;
        return;
    }
    /* the lateral acceleration: vx r (the gyro as measured: its offset
     * leaves with the band-pass) and the filter's dvy/dt (its vy of the
     * last two steps) */
    dvy = r_mul(r_sub(est->x[0], est->rg_vy), est->rate);
    est->rg_vy = est->x[0];
    u = r_add(r_mul(s->vx, est->hold[H_YAW]), dvy);
    ba = rg_band(est, 0, am);
    bu = rg_band(est, 1, u);
    est->rg_pos = (bu >= RC(EST_RG_H_MIN)) ? 0 : count_up(est->rg_pos);
    est->rg_neg = (bu <= RC(-EST_RG_H_MIN)) ? 0 : count_up(est->rg_neg);
    est->rg_n = count_up(est->rg_n);
    /* the update, on the tire's linear part (dvy/dt, the regression's
     * error, stays small) and in a weave */
    if (est->rg_n < est->rg_n_min || r_abs(bu) < RC(EST_RG_H_MIN) || est->rg_pos > est->rg_n_alt ||
        est->rg_neg > est->rg_n_alt || s->umax_est >= RC(EST_STF_U) ||
        !est_yaw_linear(est, s->yaw, s->vx, RC(EST_STF_D))) {
        return;
    }
    {
        grip_real_t z = r_sub(ba, bu);
        grip_real_t h = r_div(r_mul(RC(EST_G), bu), RC(1.0 / EST_RG_S_U));
        grip_real_t ph = r_mul(est->rg_p, h);
        grip_real_t k;
        /* a sample whose own k, z / (g bp(a)), is more than EST_RG_DK from
         * the k in use is another effect's (a bank changing within the
         * band) */
        grip_real_t nu = r_sub(z, r_mul(h, est->rg_x));
        if (r_abs(nu) > r_mul(RC(EST_G * EST_RG_DK), r_abs(bu))) {
            return;
        }
        k = r_div(ph, r_add(r_mul(h, ph), est->rg_r));
        est->rg_x = r_clamp(r_add(est->rg_x, r_mul(k, nu)), RC(EST_RG_X_LO), RC(EST_RG_X_HI));
        est->rg_p = r_clamp(r_sub(est->rg_p, r_mul(k, ph)), RC(EST_RG_P_MIN), RC(EST_RG_P_MAX));
        est_roll_apply(est);
        est->rg_updates = (est->rg_updates < 0x7fffffffu) ? est->rg_updates + 1u : est->rg_updates;
    }
}
