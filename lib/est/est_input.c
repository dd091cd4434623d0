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
    s->g_y = R_ZERO;
    if (est->plane) {
        grip_real_t cp = r_cos(est->psi), sp = r_sin(est->psi);
        grip_real_t sx = r_add(r_mul(c->tan_grade, cp), r_mul(c->tan_bank, sp));
        grip_real_t sy = r_sub(r_mul(c->tan_bank, cp), r_mul(c->tan_grade, sp));
        s->g_x = r_neg(r_div(r_mul(RC(EST_G), sx), r_sqrt(r_add(R_ONE, r_sq(sx)))));
        s->g_y = r_neg(r_div(r_mul(RC(EST_G), sy), r_sqrt(r_add(R_ONE, r_sq(sy)))));
        est->psi = r_add(est->psi, r_div(s->yaw, est->rate));
        if (est->psi > RC(3.14159265358979)) {
            est->psi = r_sub(est->psi, RC(6.28318530717959));
        } else if (est->psi < RC(-3.14159265358979)) {
            est->psi = r_add(est->psi, RC(6.28318530717959));
        } /* grip-deviation: MISRA-15.7 within (-pi, pi]: nothing to do */
    }
}

void est_take_inputs(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s)
{
    const grip_est_config_t *c = &est->cfg;
    s->flags = 0u;
    s->valid = 0u;
    s->steer_ok = (uint8_t)take_input(est, in, GRIP_IN_STEER_ANGLE, H_STEER,
                                      r_mul(c->steer_ratio, RC(EST_DELTA_MAX * 2.0)), &s->flags);
    s->yaw_ok = (uint8_t)take_input(est, in, GRIP_IN_YAW_RATE, H_YAW, RC(EST_YAW_MAX), &s->flags);
    s->ax_ok = (uint8_t)take_input(est, in, GRIP_IN_AX, H_AX, RC(EST_ACC_MAX), &s->flags);
    s->ay_ok = (uint8_t)take_input(est, in, GRIP_IN_AY, H_AY, RC(EST_ACC_MAX), &s->flags);
    s->vs_ok = take_input(est, in, GRIP_IN_VEHICLE_SPEED, H_VS, RC(EST_WS_MAX), &s->flags) &&
               est->age[H_VS] == 0;
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
    /* yaw rate with the estimated gyro bias (state x[3]) removed */
    s->yaw = s->yaw_ok ? r_sub(est->hold[H_YAW], r_mul(RC(EST_S_B), est->x[3])) : R_ZERO;
    s->ax = s->ax_ok ? est->hold[H_AX] : R_ZERO;
    /* the accelerometer rolls with the body: ay_meas = ay cos(phi) + g sin(phi),
     * phi = roll_gradient * ay, so ay = ay_meas / (1 + g roll_gradient) */
    s->ay = s->ay_ok ? r_mul(est->ay_fac, est->hold[H_AY]) : R_ZERO;
    road_plane(est, s);
}
