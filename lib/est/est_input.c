/*
 * est_input.c - input conditioning, the first stage of grip_est_step: each
 * ESC input taken with its range and held over short gaps (flags say what
 * is missing), the road-wheel angle after the steering's lag and latency,
 * the inertial inputs less the gyro bias and the body roll, and gravity
 * along the body axes on a configured road plane.
 */
#include "est_internal.h"

/* Reads one QS input with its range; holds the last valid value for
 * hold_steps. Returns 1 when a (fresh or held) value is usable. */
static int take_input(grip_est_t *e, const grip_input_sample_t *in, int id, int slot, grip_real_t lim,
                      uint32_t *flags)
{
    int ok = 0;
    if (in->valid[id]) {
        grip_real_t v = in->value[id];
        if (r_is_finite(v)) {
            if (r_abs(v) < lim) {
                ok = 1;
                e->hold[slot] = v;
                e->age[slot] = 0;
            } else {
                *flags |= GRIP_EST_F_SATURATED;
            }
        }
    }
    if (!ok) {
        e->age[slot] = count_up(e->age[slot]);
    }
    return e->age[slot] <= e->hold_steps;
}

/* The road-wheel angle at the state's time (s->delta, cd, sd), and the
 * outputs' offset from it (est->delta_o_d). */
static void road_wheel_angle(grip_est_t *est, est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    int steer_ok = s->steer_ok;
    grip_real_t delta = r_div(est->hold[H_STEER], c->steer_ratio);
    if (r_abs(delta) > RC(EST_DELTA_MAX)) {
        s->flags |= GRIP_EST_F_STEER_LIMIT;
        delta = sym_clamp(delta, RC(EST_DELTA_MAX));
    }
    if (!steer_ok) {
        delta = R_ZERO;
    }
    /* the road wheels lag the steering signal by cfg.steer_lag (first order):
     * the slip angles and the yaw reference take the lagged angle */
    if (steer_ok && (est->steer_k < R_ONE)) {
        est->delta_f = r_add(est->delta_f, r_mul(est->steer_k, r_sub(r_mul(RC(1024.0), delta), est->delta_f)));
        delta = r_mul(est->delta_f, RC(1.0 / 1024.0));
    } else {
        est->delta_f = r_mul(RC(1024.0), delta);
    }
    /* steering latency (cfg.steer_latency against cfg.latency): the state
     * lives at the inertial data's time, the outputs now; the angle moves
     * along its last step's change to both */
    {
        grip_real_t d_step = (steer_ok && est->delta_prev_ok) ? r_sub(delta, est->delta_prev) : R_ZERO;
        grip_real_t delta_s = sym_clamp(r_add(delta, r_mul(est->st_k_in, d_step)), RC(EST_DELTA_MAX));
        est->delta_prev = delta;
        est->delta_prev_ok = steer_ok;
        est->delta_o_d = r_sub(sym_clamp(r_add(delta, r_mul(est->st_k_out, d_step)), RC(EST_DELTA_MAX)), delta_s);
        delta = delta_s;
    }
    s->delta = delta;
    s->cd = r_cos(delta);
    s->sd = r_sin(delta);
}

/* Road plane: gravity along the body axes at the heading since reset. */
static void road_plane(grip_est_t *est, est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    s->g_x = R_ZERO;
    s->g_y = est->road_gy;
    if (est->plane) {
        grip_real_t cp = r_cos(est->psi), sp = r_sin(est->psi);
        grip_real_t sx = r_add(r_mul(c->tan_grade, cp), r_mul(c->tan_bank, sp));
        grip_real_t sy = r_sub(r_mul(c->tan_bank, cp), r_mul(c->tan_grade, sp));
        s->g_x = r_neg(r_div(r_mul(RC(EST_G), sx), r_sqrt(r_add(R_ONE, r_sq(sx)))));
        s->g_y = r_sub(s->g_y, r_div(r_mul(RC(EST_G), sy), r_sqrt(r_add(R_ONE, r_sq(sy)))));
        est->psi = r_add(est->psi, r_div(s->yaw, est->rate));
        if (est->psi > RC(3.14159265358979)) {
            est->psi = r_sub(est->psi, RC(6.28318530717959));
        } else if (est->psi < RC(-3.14159265358979)) {
            est->psi = r_add(est->psi, RC(6.28318530717959));
        } /* grip-deviation: MISRA-15.7 within (-pi, pi]: nothing to do */
    }
}

/* The step's period from the input times against 1 / rate_hz: F_RATE
 * beyond EST_RATE_TOL of it, or with time going backwards. No check
 * without times (t_us 0) or on a repeated time. */
static void check_rate(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s)
{
    int64_t t = in->t_us;
    if (t == 0) {
        est->t_prev = 0;
        return;
    }
    if (est->t_prev != 0 && t != est->t_prev) {
        int64_t d = t - est->t_prev;
        int64_t per = (int64_t)(1000000u / est->cfg.rate_hz);
        int64_t e = d - per;
        if (d < 0 || (e < 0 ? -e : e) * EST_RATE_TOL_DIV > per) {
            s->flags |= GRIP_EST_F_RATE;
        }
    }
    est->t_prev = t;
}

/* The rear road-wheel angle (0 without one), its cosine and sine from
 * their Taylor series: within EST_DELTA_R_MAX the error is below 5e-8 */
static void rear_wheel_angle(grip_est_t *est, est_ctx_t *s, int rear_ok)
{
    grip_real_t d = rear_ok ? est->hold[H_REAR] : R_ZERO;
    grip_real_t d2;
    if (r_abs(d) > RC(EST_DELTA_R_MAX)) {
        s->flags |= GRIP_EST_F_STEER_LIMIT;
        d = sym_clamp(d, RC(EST_DELTA_R_MAX));
    }
    s->delta_r = d;
    s->cr = R_ONE;
    s->sr = R_ZERO;
    if (d != R_ZERO) {
        d2 = r_sq(d);
        s->cr = r_add(R_ONE, r_mul(d2, r_add(RC(-0.5), r_mul(d2, RC(1.0 / 24.0)))));
        s->sr = r_mul(d, r_add(R_ONE, r_mul(d2, r_add(RC(-1.0 / 6.0), r_mul(d2, RC(1.0 / 120.0))))));
    }
}

void est_take_inputs(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    int rear_ok;
    s->flags = 0u;
    s->valid = 0u;
    check_rate(est, in, s);
    s->steer_ok = (uint8_t)take_input(est, in, GRIP_IN_STEER_ANGLE, H_STEER,
                                      r_mul(c->steer_ratio, RC(EST_DELTA_MAX * 2.0)), &s->flags);
    s->yaw_ok = (uint8_t)take_input(est, in, GRIP_IN_YAW_RATE, H_YAW, RC(EST_YAW_MAX), &s->flags);
    s->ax_ok = (uint8_t)take_input(est, in, GRIP_IN_AX, H_AX, RC(EST_ACC_MAX), &s->flags);
    s->ay_ok = (uint8_t)take_input(est, in, GRIP_IN_AY, H_AY, RC(EST_ACC_MAX), &s->flags);
    s->vs_ok = take_input(est, in, GRIP_IN_VEHICLE_SPEED, H_VS, RC(EST_WS_MAX), &s->flags) &&
               est->age[H_VS] == 0;
    /* the rear road-wheel angle: taken when given; required (its loss stops
     * the lateral observer like the steering's) with cfg.rear_steer */
    rear_ok = 0;
    if (in->valid[GRIP_IN_REAR_STEER_ANGLE] || c->rear_steer || est->age[H_REAR] <= est->hold_steps) {
        /* a car without rear steering skips the call (the M4F step budget) */
        rear_ok = take_input(est, in, GRIP_IN_REAR_STEER_ANGLE, H_REAR, RC(2.0 * EST_DELTA_R_MAX), &s->flags);
    }
    if (c->rear_steer && !rear_ok) {
        s->flags |= GRIP_EST_F_NO_REAR_STEER;
        s->steer_ok = 0u;
    }
    if (!s->steer_ok) {
        s->flags |= GRIP_EST_F_NO_STEER;
    }
    if (!s->yaw_ok) {
        s->flags |= GRIP_EST_F_NO_YAW;
    }
    if (!s->ax_ok) {
        s->flags |= GRIP_EST_F_NO_AX;
    }
    if (!s->ay_ok) {
        s->flags |= GRIP_EST_F_NO_AY;
    }
    road_wheel_angle(est, s);
    rear_wheel_angle(est, s, rear_ok);
    /* yaw rate with the estimated gyro bias (state x[3]) removed */
    s->yaw = s->yaw_ok ? r_sub(est->hold[H_YAW], r_mul(RC(EST_S_B), est->x[3])) : R_ZERO;
    /* and pitches: ax_meas = ax cos(theta) + g sin(theta), theta =
     * pitch_gradient * ax */
    s->ax = s->ax_ok ? r_mul(est->ax_fac, est->hold[H_AX]) : R_ZERO;
    /* the accelerometer rolls with the body: ay_meas = ay cos(phi) + g sin(phi),
     * phi = roll_gradient * ay, so ay = ay_meas / (1 + g roll_gradient) */
    s->ay = s->ay_ok ? r_mul(est->ay_fac, est->hold[H_AY]) : R_ZERO;
    road_plane(est, s);
}
