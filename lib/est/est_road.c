/*
 * est_road.c - the road's bank as an estimated quantity: gravity along the
 * body's y axis beyond the configured road plane (est->road_gy, m/s^2).
 *
 * The accelerometer reads specific force, the acceleration less gravity:
 * on a road banked by phi (left edge up positive) and graded by theta the
 * lateral channel reads ay = dvy/dt + r vx + g cos(theta) sin(phi), and the
 * tires carry that specific force alone (sum Fy = m ay). The kinematics the
 * lateral filter predicts vy with are dvy/dt = ay + g_y - r vx, g_y = -g
 * cos(theta) sin(phi), so g_y = dvy/dt + r vx - ay is measured wherever
 * dvy/dt is known. Below the tires' limit the ay update holds vy to the
 * tire model: a bank the prediction lacks makes vy drift at g_y's error,
 * and the update pulls it back every step by that amount on average. The
 * correction, integrated, is g_y's error (the integral part of a
 * proportional-integral loop whose proportional part is the filter's own
 * gain). The road's bank changes along it, not in time: the integrator's
 * time constant is a distance, EST_ROAD_L / |vx|. Where the model's pull
 * is not a bank's (at the limit, in a yaw transient, short of the linear
 * yaw response, the model declared misfitting) the bank is held, and with
 * a misfit declared it returns to the bank measured at the last standstill
 * (road_g0; the plane before one). At rest the accelerometer reads gravity
 * alone (ay = -g_y). Only with the configuration's bank_est = 1 (off by
 * default: a tire model that misfits the car is learned as bank, AV-21
 * log). docs/estimator/road.md derives it and gives the measurements
 * (taking g_y = r vx - ay at the limit, dvy/dt = 0, failed: a car sliding
 * at its limit changes vy at a steady yaw rate).
 */
#include "est_internal.h"

void est_road(grip_est_t *est, const est_ctx_t *s)
{
    grip_real_t gy = est->road_gy;
    if (!est->cfg.bank_est) {
        return; /* the configured plane only: road_gy stays 0 */
    }
    if (est->active) {
        /* the yaw acceleration, low-passed over EST_ROAD_T_DR */
        grip_real_t k_ds = r_div(RC(1.0 / EST_ROAD_T_DR), est->rate);
        est->road_dr = r_add(est->road_dr, r_mul(k_ds, r_sub(r_mul(r_sub(s->r_upd, est->road_r), est->rate), est->road_dr)));
        est->road_r = s->r_upd;
        if (s->ay_upd && s->yaw_ok && !s->lock && !s->spin && !s->dead_reck && s->vx >= RC(EST_V_EXC) &&
            r_abs(est->road_dr) < RC(EST_ROAD_RACC)) {
            /* the car within EST_ROAD_D of its linear yaw response: a car
             * nearing its limit on a friction the model does not know yet
             * pulls vy the same way */
            if (s->umax_est < RC(EST_ROAD_U) && !s->at_limit && est_yaw_linear(est, s->yaw, s->vx, RC(EST_ROAD_D)) &&
                !est->misfit && !est->sat_cap) {
                /* the ay update's correction of vy this step */
                gy = r_add(gy, r_mul(r_mul(s->vx, RC(1.0 / EST_ROAD_L)), r_sub(est->x[0], r_add(s->vy, s->dvy))));
            }
        }
        /* the consistency check (est_checks.c) says the model misfits the
         * car: the bank learned moving may be the misfit's, and at the
         * limit its error runs into vy unchecked (AV-21 log: a bank of
         * 0.43 m/s^2 took beta to 40 deg); it returns over EST_ROAD_L to
         * what the accelerometer measured at the last standstill, which
         * owes nothing to the tire model (to the plane before one) */
        if (est->misfit || est->sat_cap) {
            gy = r_sub(gy, r_mul(r_mul(r_abs(s->vx), r_div(RC(1.0 / EST_ROAD_L), est->rate)), r_sub(gy, est->road_g0)));
        }
    } else {
        est->road_r = s->yaw;
        est->road_dr = R_ZERO;
        if (s->at_rest && s->ay_ok) {
            /* at rest the accelerometer reads gravity alone: ay = -(plane + road_gy) */
            grip_real_t plane = r_sub(s->g_y, gy);
            gy = r_add(gy, r_mul(r_div(RC(1.0 / EST_ROAD_T_REST), est->rate), r_sub(r_neg(r_add(s->ay, plane)), gy)));
            est->road_g0 = sym_clamp(gy, RC(EST_ROAD_GY_MAX));
        }
    }
    est->road_gy = sym_clamp(gy, RC(EST_ROAD_GY_MAX));
}
