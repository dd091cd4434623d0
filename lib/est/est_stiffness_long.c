/*
 * est_stiffness_long.c - the tires' longitudinal slip stiffness learned
 * online (configuration kx_est = 1 with drive_front known;
 * docs/estimator/stiffness.md, "Longitudinal slip stiffness").
 *
 * The tires here work at kx kappa: the slip stiffness scales by kx, the
 * peak slip by mu / kx, the peak force stays. kx is learned from the slip
 * the wheel speeds show against the slip the model needs for the drive
 * force, a slip-slope estimate written from the force balance:
 *
 * The accelerometer gives the tires' total longitudinal force, F = m ax +
 * drag + rolling resistance, as the ax update's balance has it (ax is the
 * specific force: the grade does not enter). The drive split the car's
 * layout fixes (drive_front, an OEM's datum) shares it between the axles,
 * and each axle's slip is its force over its stiffness, kx c_kappa at its
 * load. The wheel speeds, each turned into the CG's speed (est_speed.c),
 * give the front-minus-rear axle slip without the vx estimate's own error
 * beyond a scale of it:
 *
 *     dk = (v_front - v_rear) / vx
 *        = (1 / kx) (F_f / C_f - F_r / C_r) + d
 *
 * with d the axles' rolling-radius mismatch (tread wear, pressure, load).
 * A Kalman filter on (1 / kx, d) with the tire file and no mismatch as its
 * prior: coasting (F ~ 0) measures d alone, traction with excitation the
 * slope (an AWD whose split follows the axle loads has none). Never while
 * braking (the brake balance moves with EBD and ABS), only on the tire's
 * linear part, straight ahead, at speed. At most one of the two learners
 * updates in a step (the M4F budget): this one waits a step when the
 * cornering stiffness updated.
 */
#include "est_internal.h"

void est_kx_apply(grip_est_t *est)
{
    /* nothing learned: exactly the tire file's (1 / (x S_U) is 0.99994 in
     * Q15.16 at the prior) */
    est->kx = (est->kx_updates > 0u) ? r_div(R_ONE, r_mul(est->kx_x[0], RC(EST_KX_S_U))) : R_ONE;
    est->c_kappa_kx[0] = r_mul(est->c_kappa[0], est->kx);
    est->c_kappa_kx[1] = r_mul(est->c_kappa[1], est->kx);
    est->slip_acc = r_div(est->cfg.mass, r_mul(RC(4.0), r_mul(r_min(est->c_kappa[0], est->c_kappa[1]), est->kx)));
}

/* The regression and the update, once the gates that need no arithmetic
 * hold: kept out of line, so that the step that leaves at those gates (the
 * worst-case step, in a turn at the limit) saves no registers for it.
 * Returns 0 when the remaining gates fail (the run of steps restarts). */
static EST_NOINLINE int kx_regress(grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out, int stf_upd)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t f, ad, fzf, fzr, cf, cr, g, dk, a = est->kx_a;
    int coast;
    /* the tires' total longitudinal force (N) and its share of the mass;
     * the axles' loads */
    f = r_add(r_mul(c->mass, s->ax), r_add(r_mul(est->k_drag, r_qs_to_ql(r_sq(s->vx))), est->f_roll));
    ad = r_div(f, c->mass);
    fzf = r_add(out->fz[0], out->fz[1]);
    fzr = r_add(out->fz[2], out->fz[3]);
    if (ad < RC(-EST_KX_AX_C) || fzf < est->fz_static[0] || fzr < est->fz_static[1]) {
        return 0; /* braking, or an axle unloaded */
    }
    /* each axle's slip stiffness at its load (N per per mille: divided by
     * 1000, which Q15.16 holds exactly, not multiplied by 0.001), the model
     * slip difference of the split force (kx = 1), and the measured one */
    cf = r_div_keep(r_mul(r_div(fzf, est->fz_static[0]), est->c_kappa[0]), RC(1.0 / EST_KX_S_Y));
    cr = r_div_keep(r_mul(r_div(fzr, est->fz_static[1]), est->c_kappa[1]), RC(1.0 / EST_KX_S_Y));
    g = r_sub(r_div(r_mul(c->drive_front, f), cf), r_div(r_mul(r_sub(R_ONE, c->drive_front), f), cr));
    dk = r_div(r_mul(sym_clamp(est->kx_dv, RC(EST_KX_DV_MAX)), RC(1.0 / EST_KX_S_Y)), s->vx);
    /* low-passed alike; the first step of a run starts them */
    if (est->kx_n == 0) {
        a = R_ONE;
    }
    est->kx_z = r_add(est->kx_z, r_mul(a, r_sub(dk, est->kx_z)));
    est->kx_h = r_add(est->kx_h, r_mul(a, r_sub(g, est->kx_h)));
    est->kx_n = count_up(est->kx_n);
    if (est->kx_n < est->kx_n_min || stf_upd) {
        return 1; /* the low-pass not settled, or the cornering stiffness updated in this step */
    }
    coast = r_abs(ad) <= RC(EST_KX_AX_C); /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
    if (!coast && !(ad >= RC(EST_KX_AX_T) && r_abs(est->kx_h) >= RC(EST_KX_H_MIN))) {
        return 1; /* neither coasting nor traction with excitation */
    }
    {
        /* coasting measures the mismatch alone: the small drive slip is
         * taken out at the current kx, and the row has no kx term */
        grip_real_t hs = r_mul(est->kx_h, RC(EST_KX_S_U));
        grip_real_t h0 = coast ? R_ZERO : hs; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        grip_real_t nu = r_sub(est->kx_z, r_add(r_mul(hs, est->kx_x[0]), est->kx_x[1]));
        grip_real_t ph0 = r_add(r_mul(est->kx_p[0], h0), est->kx_p[1]);
        grip_real_t ph1 = r_add(r_mul(est->kx_p[1], h0), est->kx_p[2]);
        grip_real_t sv = r_add(r_add(r_mul(h0, ph0), ph1), est->kx_r);
        grip_real_t k0 = r_div(ph0, sv), k1 = r_div(ph1, sv);
        est->kx_x[0] = r_clamp(r_add(est->kx_x[0], r_mul(k0, nu)), RC(EST_KX_X_LO), RC(EST_KX_X_HI));
        est->kx_x[1] = sym_clamp(r_add(est->kx_x[1], r_mul(k1, nu)), RC(EST_KX_XD_MAX));
        est->kx_p[0] = r_sub(est->kx_p[0], r_mul(k0, ph0));
        est->kx_p[1] = r_sub(est->kx_p[1], r_mul(k0, ph1));
        est->kx_p[2] = r_sub(est->kx_p[2], r_mul(k1, ph1));
        /* within its floors, its priors and a correlation below 1 */
        cov2_condition(est->kx_p, RC(EST_KX_P_MIN), RC(EST_KX_P_MAX), RC(EST_KX_PD_MIN), RC(EST_KX_PD_MAX));
        est->kx_updates = (est->kx_updates < 0x7fffffffu) ? est->kx_updates + 1u : est->kx_updates;
        est_kx_apply(est);
    }
    return 1;
}

void est_stiffness_long(grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out, int stf_upd)
{
    const grip_est_config_t *c = &est->cfg;
    int ok;
    if (!c->kx_est || c->drive_front < R_ZERO) {
        return;
    }
    /* a random walk: what is not measured returns towards the prior */
    est->kx_p[0] = r_min(r_add(est->kx_p[0], est->kx_q), RC(EST_KX_P_MAX));
    est->kx_p[2] = r_min(r_add(est->kx_p[2], est->kx_qd), RC(EST_KX_PD_MAX));
    /* the gates that need no arithmetic first: the linear tire, straight
     * ahead, at speed, every input there */
    ok = r_abs(s->ay) < RC(EST_KX_AY) && s->ax_ok && s->ay_ok && s->yaw_ok && s->steer_ok && s->wheels_ok && /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
         ((s->flags & GRIP_EST_F_STEER_LIMIT) == 0u) && s->vx >= RC(EST_KX_V) && r_abs(s->delta) < RC(EST_KX_STEER) &&
         s->umax_est < RC(EST_KX_U) && !s->lock && !s->spin && !s->dead_reck && !s->at_limit && !s->kappa_slip;
    if (!ok || !kx_regress(est, s, out, stf_upd)) {
        est->kx_n = 0;
    }
}
