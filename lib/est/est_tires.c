/*
 * est_tires.c - the tire model at the prior state: the wheels' vertical
 * loads (quasi-static load transfer), then with the lateral observer
 * running the four tire evaluations (the lagged slip angles, the learned
 * stiffness scales k and kx, mu's similarity scaling), the model's accelerations and the analytic
 * Jacobians the filter's predict and updates use. These evaluations are the
 * only tire calls of the step.
 */
#include "est_internal.h"

/* x limited to the interval between 0 and f (either sign of f) */
static grip_real_t between_zero(grip_real_t x, grip_real_t f)
{
    return r_clamp(x, r_min(f, R_ZERO), r_max(f, R_ZERO));
}

/* The slip ratio at which the tire model (fitted at friction 1) is
 * evaluated on a road of friction mu: similarity (kappa / mu) up to the
 * stretched peak mu kappa_pk; past it the tire's own sliding branch,
 * shifted to start there (a locked wheel slides at the tire's sliding ratio
 * of the road's friction, not further down a stretched branch); within the
 * model's +-1.5. */
static grip_real_t kappa_at_friction(grip_real_t kappa, grip_real_t mu, grip_real_t kappa_pk)
{
    grip_real_t tk = r_div(kappa, mu);
    if (tk > kappa_pk) {
        tk = r_add(kappa, r_mul(kappa_pk, r_sub(R_ONE, mu)));   /* kappa_pk + (kappa - mu kappa_pk) */
    } else if (tk < r_neg(kappa_pk)) {
        tk = r_sub(kappa, r_mul(kappa_pk, r_sub(R_ONE, mu)));
    } else {
        /* within the stretched peak: similarity */
    }
    return r_clamp(tk, RC(-1.5), RC(1.5));
}

/* A tire's or an axle's utilization on the friction ellipse: Fx against
 * the braking peak (Fx / Fz scaled by mu_xy, the lateral peak over the
 * longitudinal one), Fy against the lateral peak mu_cap = mu mu0 (a tire
 * whose peaks differ saturates in braking at its own Fx peak, not at the
 * lateral one). fz > 0. */
static inline grip_real_t ellipse_util(grip_real_t fx, grip_real_t fy, grip_real_t fz, grip_real_t mu_xy, grip_real_t mu_cap)
{
    grip_real_t fxn = r_div(r_mul(fx, mu_xy), fz);
    grip_real_t fyn = r_div(fy, fz);
    return r_div(r_sqrt(r_add(r_sq(fxn), r_sq(fyn))), mu_cap);
}

/* Quasi-static load transfer from ax and ay on the static loads. Kept out
 * of est_tires' frame, which is under the Magic Formula evaluations. */
static EST_NOINLINE void loads(const grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    const grip_est_config_t *c = &est->cfg;
    int i;
    grip_real_t l = r_add(c->lf, c->lr);
    grip_real_t dlong = r_mul(r_div(c->h_cg, r_mul(RC(2.0), l)), r_mul(s->ax, c->mass));   /* per wheel */
    grip_real_t may_h = r_mul(c->h_cg, r_mul(s->ay, c->mass));                            /* N m */
    grip_real_t dlat_f = r_mul(c->roll_split_front, r_div_keep(may_h, c->track_f));
    grip_real_t dlat_r = r_mul(r_sub(R_ONE, c->roll_split_front), r_div_keep(may_h, c->track_r));
    /* static load on the road plane plus downforce 0.5 rho C_L A vx^2 */
    grip_real_t v2 = r_qs_to_ql(r_sq(s->vx));
    grip_real_t fz0f = r_add(est->fz_base[0], r_mul(est->k_aero[0], v2));
    grip_real_t fz0r = r_add(est->fz_base[1], r_mul(est->k_aero[1], v2));
    out->fz[0] = r_sub(r_sub(fz0f, dlong), dlat_f);
    out->fz[1] = r_add(r_sub(fz0f, dlong), dlat_f);
    out->fz[2] = r_sub(r_add(fz0r, dlong), dlat_r);
    out->fz[3] = r_add(r_add(fz0r, dlong), dlat_r);
    for (i = 0; i < 4; ++i) {
        out->fz[i] = r_max(out->fz[i], R_ZERO);
    }
    if (s->ax_ok && s->ay_ok) {
        s->valid |= GRIP_EST_V_FZ;
    }
}

/* An undriven axle (drive_front exactly 0 or 1, an OEM datum) while the
 * car is not braking: no torque acts on its wheels but their rolling
 * resistance, so they work at the slip of zero Fx, taken as 0. What their
 * speeds show beyond it is the error of vx, of the wheel's radius and of
 * its projection to the CG: a lightly loaded inner wheel that slows, a few
 * tenths of a percent, is a few hundred N of Fx the tire model would
 * otherwise take out of the axle's lateral friction (docs/estimator.md,
 * stage 3). axle: 0 front, 1 rear. */
static int axle_coasts(const grip_est_t *est, int axle)
{
    grip_real_t undriven = (axle == 0) ? R_ZERO : R_ONE; /* the drive_front that leaves it undriven */
    return (est->braking == 0) && (est->cfg.drive_front == undriven);
}

/* The four tire evaluations at the prior state (s->vy, r, mu): per wheel
 * the slips, the forces and utilization (out), the excitation measures, and
 * the wheel's share of the Jacobians; then the model's accelerations and
 * their Jacobians. */
static void tire_forces(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s, grip_est_output_t *out)
{
    static const int8_t side[4] = { 1, -1, 1, -1 };
    const grip_est_config_t *c = &est->cfg;
    grip_real_t jay[3] = { R_ZERO, R_ZERO, R_ZERO };   /* d(sum Fby)/d(vy, r, mu) [QL] */
    grip_real_t jr[3] = { R_ZERO, R_ZERO, R_ZERO };    /* d(sum Mz_body)/d(vy, r, mu) */
    grip_real_t jax_mu = R_ZERO;
    grip_real_t sfx = R_ZERO, sfy = R_ZERO, smz = R_ZERO;
    grip_real_t umax = R_ZERO, umax_x = R_ZERO, kappa_sum = R_ZERO, umax_est = R_ZERO;
    int i, kappa_slip = 0;

    s->slope[0] = R_ZERO;
    s->slope[1] = R_ZERO;
    for (i = 0; i < 4; ++i) {
        int axle = i >> 1;
        grip_real_t cdi = axle ? s->cr : s->cd, sdi = axle ? s->sr : s->sd;
        grip_real_t vcx = r_sub(s->vx, r_mul(s->r, est->yw[i]));
        grip_real_t vcy = r_add(s->vy, r_mul(s->r, est->xw[i]));
        grip_real_t vxw = r_add(r_mul(cdi, vcx), r_mul(sdi, vcy));
        grip_real_t vyw = r_sub(r_mul(cdi, vcy), r_mul(sdi, vcx));
        grip_real_t den = r_max(r_abs(vxw), RC(EST_V_OFF));
        grip_real_t t = r_div(vyw, den);
        grip_real_t alpha = r_atan(t);       /* kinematic, then lagged (relaxation) */
        grip_real_t kappa = R_ZERO;
        grip_real_t lever = r_add(r_mul(est->xw[i], cdi), r_mul(est->yw[i], sdi));
        grip_real_t c2, dady, dadr, ca, ck, g, u, dfda, dfdmu, fzr, ka;
        grip_mf_input ti;
        grip_mf_output to;
        grip_status_t st;
        if (s->ws_ok[i] && !axle_coasts(est, axle)) {
            kappa = r_clamp(r_div(r_sub(in->value[GRIP_IN_WHEEL_SPEED_FL + i], vxw), den), RC(-1.0), RC(1.5));
        }
        /* the tires work at the lagged slip angle; the Jacobians below keep
         * the kinematic slope (the lag settles within sigma / |vx|, ~20 ms
         * at speed, inside the filter's horizon). The updates' correction
         * of vy was carried into alpha_t at the end of the last step (the
         * lateral outputs, est_outputs.c); what is lagged here is the rest
         * of the motion since then */
        if (!est->rlx_init) {
            est->alpha_t[i] = alpha;
        }
        alpha = r_add(est->alpha_t[i], r_mul(relax_share(r_div(r_abs(vxw), est->rate), wheel_sigma(est, axle, out->fz[i])),
                                              r_sub(alpha, est->alpha_t[i])));
        est->alpha_t[i] = alpha;
        ti.kappa = kappa_at_friction(r_mul(est->kx, kappa), s->mu, est->kappa_pk[axle]); /* at kx kappa */
        /* beyond the peak slip angle the model force is held at its peak:
         * the falling branch would make vy and mu unobservable together */
        ka = r_mul(est->stf_k[axle], alpha);   /* the slip the model works at: k alpha */
        ti.alpha = sym_clamp(r_div(ka, s->mu), est->alpha_pk[axle]);
        if (side[i] < 0) {
            ti.alpha = r_neg(ti.alpha);   /* right wheel: mirror image of the LEFT-fitted tire */
        }
        ti.gamma = R_ZERO;
        ti.fz = out->fz[i];
        ti.p = R_ZERO;
        ti.vx = vxw;
        st = tire_eval_axle(est, axle, &ti, &to);
        if (st < 0) {
            s->flags |= GRIP_EST_F_TIRE_ERROR;
            to.fx = R_ZERO;
            to.fy = R_ZERO;
            to.mz = R_ZERO;
        }
        if (side[i] < 0) {
            to.fy = r_neg(to.fy);
            to.mz = r_neg(to.mz);
        }
        out->kappa[i] = kappa;
        out->alpha[i] = alpha;
        out->fx[i] = r_mul(s->mu, to.fx);
        out->fy[i] = r_mul(s->mu, to.fy);
        out->mz[i] = r_mul(s->mu, to.mz);
        if (s->ws_ok[i] && st >= 0) {
            s->valid |= GRIP_EST_V_WHEEL(i);
        }
        /* utilization and local slope, on the friction ellipse */
        u = R_ZERO;
        fzr = R_ZERO;
        if (out->fz[i] > RCL(50.0)) {
            u = ellipse_util(out->fx[i], out->fy[i], out->fz[i], est->mu_xy[axle], r_mul(s->mu, est->mu0[axle]));
            fzr = r_div(out->fz[i], est->fz_static[axle]);
        }
        out->util[i] = r_min(u, RC(1.5));
        umax_est = r_max(umax_est, out->util[i]);
        g = r_max(RC(EST_G_MIN), r_sqrt(r_sub(R_ONE, r_min(u, R_ONE))));
        ca = r_mul(r_mul(fzr, est->c_alpha[axle]), est->stf_k[axle]); /* N/rad at this load */
        ck = r_mul(fzr, est->c_kappa_kx[axle]);                        /* N at this load, at kx */
        {
            /* Excitation: the utilization the slips would cause on the
             * tire's own friction (mu = 1), never measured against the
             * estimate itself, which would let a falling mu excite its
             * own adaptation. */
            grip_real_t cap = r_max(r_mul(est->mu0[axle], out->fz[i]), RCL(50.0));
            grip_real_t ulin_y = r_div(r_mul(r_abs(alpha), ca), cap);
            grip_real_t ulin_x = r_div(r_mul(r_mul(r_abs(kappa), ck), est->mu_xy[axle]), cap);
            umax = r_max(umax, r_max(ulin_y, ulin_x));
            umax_x = r_max(umax_x, ulin_x);
            kappa_sum = r_add(kappa_sum, kappa);
            if (r_abs(kappa) >= RC(EST_LOCK_K)) {
                kappa_slip = 1;
            }
        }
        c2 = r_div(R_ONE, r_add(R_ONE, r_sq(sym_clamp(t, RC(100.0)))));
        dady = r_div(r_mul(c2, cdi), den);                    /* d alpha / d vy  [s/m] */
        dadr = r_div(r_mul(c2, lever), den);                  /* d alpha / d r   [s]   */
        dfda = r_neg(r_mul(g, ca));                           /* d Fy / d alpha  [N/rad] */
        dfdmu = est_mu_secant(est, axle, ka, out->fy[i]);   /* d Fy / d mu [N] */
        est->fy_dmu[i] = dfdmu; /* the output forces move along it with the updates' mu */
        s->slope[axle] = r_add(s->slope[axle], r_abs(dfda));
        {
            grip_real_t dfy_dvy = r_mul(dady, dfda);
            grip_real_t dfy_dr = r_mul(dadr, dfda);
            jay[0] = r_add(jay[0], r_mul(cdi, dfy_dvy));
            jay[1] = r_add(jay[1], r_mul(cdi, dfy_dr));
            jay[2] = r_add(jay[2], r_mul(cdi, dfdmu));
            jr[0] = r_add(jr[0], r_mul(lever, dfy_dvy));
            jr[1] = r_add(jr[1], r_mul(lever, dfy_dr));
            jr[2] = r_add(jr[2], r_mul(lever, dfdmu));
        }
        {
            /* d Fx / d mu under similarity: (Fx - kappa dFx/dkappa) / mu */
            grip_real_t dfxdk = r_mul(g, ck);
            grip_real_t dfxdmu = r_div_keep(between_zero(r_sub(out->fx[i], r_mul(kappa, dfxdk)), out->fx[i]), s->mu);
            jax_mu = r_add(jax_mu, r_sub(r_mul(cdi, dfxdmu), r_mul(sdi, dfdmu)));
        }
        {
            grip_real_t fbx = r_sub(r_mul(cdi, out->fx[i]), r_mul(sdi, out->fy[i]));
            grip_real_t fby = r_add(r_mul(sdi, out->fx[i]), r_mul(cdi, out->fy[i]));
            sfx = r_add(sfx, fbx);
            sfy = r_add(sfy, fby);
            smz = r_add(smz, r_add(r_sub(r_mul(est->xw[i], fby), r_mul(est->yw[i], fbx)), out->mz[i]));
        }
    }
    est->rlx_init = 1;
    out->fy_axle[0] = r_add(out->fy[0], out->fy[1]);
    out->fy_axle[1] = r_add(out->fy[2], out->fy[3]);
    for (i = 0; i < 2; ++i) {
        grip_real_t fzx = r_add(out->fz[2 * i], out->fz[2 * i + 1]); /* grip-deviation: bugprone-implicit-widening-of-multiplication-result i <= 1 */
        grip_real_t fxa = r_add(out->fx[2 * i], out->fx[2 * i + 1]);
        if (fzx > RCL(100.0)) {
            out->util_axle[i] = r_min(ellipse_util(fxa, out->fy_axle[i], fzx, est->mu_xy[i], r_mul(s->mu, est->mu0[i])), RC(1.5));
        }
    }
    s->ay_m = r_div(sfy, c->mass);
    /* the measured ax also carries the drag and the rolling resistance
     * (vx > 0 here: the lateral observer runs above EST_V_OFF) */
    s->ax_m = r_div(r_sub(sfx, r_add(r_mul(est->k_drag, r_qs_to_ql(r_sq(s->vx))), est->f_roll)), c->mass);
    s->racc = r_div(smz, c->iz);
    s->a_vv = r_div(jay[0], c->mass);
    s->a_vr = r_div(jay[1], c->mass);
    s->a_vm = r_div(jay[2], c->mass);
    s->a_rv = r_div(jr[0], c->iz);
    s->a_rr = r_div(jr[1], c->iz);
    s->a_rm = r_div(jr[2], c->iz);
    s->jax_mu = jax_mu;
    s->umax = umax;
    s->umax_x = umax_x;
    s->kappa_sum = kappa_sum;
    s->umax_est = umax_est;
    s->kappa_slip = (uint8_t)kappa_slip;
}

void est_tires(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s, grip_est_output_t *out)
{
    loads(est, s, out);
    if (est->active) {
        est_friction_floor(est, s);
        tire_forces(est, in, s, out);
    }
}
