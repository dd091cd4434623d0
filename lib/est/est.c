/*
 * est.c - onboard vehicle-state and friction estimator (grip_est.h),
 * written once for both arithmetics. Method and every constant:
 * docs/estimator.md; float64 reference: tools/grip_tools/est_ref.py (the
 * same steps in the same order).
 *
 * Per step: inputs (validity, hold, saturation) -> longitudinal speed
 * (complementary filter) -> vertical loads -> four tire evaluations at the
 * prior state -> analytic Jacobians -> EKF predict (x = [vy, r, mu, gyro bias]) ->
 * scalar updates: yaw rate, ay, (ax when excited) -> lateral outputs at the
 * updated state, extrapolated over the sensor latency -> outputs.
 * No loop depends on data: every loop runs 3 or 4 times.
 */
#include <stddef.h>

#include "est_internal.h"

/* ------------------------------------------------------------------ */
/* small helpers */

static int32_t r_to_int(grip_real_t a)
{
#if GRIP_ARITH_FIXED
    return (a >= 0) ? (int32_t)((a + 32768) >> 16) : -(int32_t)((32768 - a) >> 16);
#else
    return (int32_t)((a >= 0.0f) ? (a + 0.5f) : (a - 0.5f));
#endif
}

static grip_real_t sym_clamp(grip_real_t x, grip_real_t m)
{
    return r_clamp(x, r_neg(m), m);
}

/* x limited to the interval between 0 and f (either sign of f) */
static grip_real_t between_zero(grip_real_t x, grip_real_t f)
{
    return r_clamp(x, r_min(f, R_ZERO), r_max(f, R_ZERO));
}

/* Wheel-speed reference while neither braking nor driving, from the mean
 * of the trusted wheels. When they spread wider than SPREAD_REL |vx| +
 * SPREAD_ABS (a driven wheel slipping in a corner, below the outlier test)
 * the mean moves towards the cluster the odd wheel left: a > 0 (mean below
 * the middle, one wheel high) towards vmin, a < 0 towards vmax, by the
 * weight w that reaches 1 at twice the threshold. Continuous in every
 * input: a switch between the mean and one wheel chattered. */
static grip_real_t spread_reference(grip_real_t v_mean, grip_real_t vmin, grip_real_t vmax, grip_real_t vx_pred)
{
    grip_real_t sp = r_sub(vmax, vmin);
    grip_real_t thr = r_add(r_mul(RC(EST_SPREAD_REL), r_abs(vx_pred)), RC(EST_SPREAD_ABS));
    grip_real_t v = v_mean;
    if (sp > thr) {
        grip_real_t w = r_min(r_div(r_sub(sp, thr), thr), R_ONE);
        grip_real_t a = sym_clamp(r_div(r_mul(RC(4.0), r_sub(r_add(vmax, vmin), r_mul(RC(2.0), v_mean))), sp), R_ONE);
        if (a > R_ZERO) {
            v = r_add(v_mean, r_mul(r_mul(w, a), r_sub(vmin, v_mean)));
        } else {
            v = r_sub(v_mean, r_mul(r_mul(w, a), r_sub(vmax, v_mean)));
        }
    }
    return v;
}

/* One tire evaluation through the axle's model (the tagged union). */
static grip_status_t tire_eval(const grip_est_tire_t *t, const grip_mf_input *in, grip_mf_output *out)
{
    switch (t->kind) {
    case GRIP_EST_TIRE_MF:
        return grip_mf_eval(t->model.mf, in, out);
    default:
        out->fx = R_ZERO;
        out->fy = R_ZERO;
        out->mz = R_ZERO;
        return GRIP_ERR_PARAM;
    }
}

static int in_range(grip_real_t v, grip_real_t lo, grip_real_t hi)
{
    return r_is_finite(v) && v >= lo && v <= hi;
}

/* ------------------------------------------------------------------ */

grip_status_t grip_est_config_default(grip_est_config_t *cfg, const grip_mf_params *tire)
{
    if (cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    cfg->mass = RCL(1450.0);
    cfg->iz = RCL(2450.0);
    cfg->lf = RC(1.10);
    cfg->lr = RC(1.60);
    cfg->track_f = RC(1.55);
    cfg->track_r = RC(1.53);
    cfg->h_cg = RC(0.55);
    cfg->steer_ratio = RC(15.5);
    cfg->wheel_radius = RC(0.30);
    cfg->roll_split_front = RC(0.60);
    cfg->roll_gradient = RC(0.0088);
    cfg->rate_hz = 100u;
    cfg->speed_ref_mu = 0u;
    cfg->cla = R_ZERO;
    cfg->aero_front = RC(0.5);
    cfg->air_density = RC(1.2);
    cfg->cda = R_ZERO;
    cfg->crr = R_ZERO;
    cfg->tan_bank = R_ZERO;
    cfg->tan_grade = R_ZERO;
    cfg->latency = R_ZERO;
    cfg->steer_lag = R_ZERO;
    cfg->steer_latency = R_ZERO;
    cfg->tire[0].kind = GRIP_EST_TIRE_MF;
    cfg->tire[0].model.mf = tire;
    cfg->tire[1].kind = GRIP_EST_TIRE_MF;
    cfg->tire[1].model.mf = tire;
    return GRIP_OK;
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

/* A step counter, saturating so that it never wraps */
static int32_t count_up(int32_t n)
{
    return (n < 1000000) ? n + 1 : n;
}

/* Peak lateral friction coefficient |Fy| / Fz of a tire at load fz over the
 * sweep alpha = 0.02 .. 0.5 rad (pure side slip, 20 m/s); *slip_pk gets
 * the slip angle of the peak (0.5 if no force). longitudinal: |Fx| / Fz over
 * the braking slips kappa = -0.02 .. -0.5 (pure longitudinal slip), *slip_pk
 * |kappa| there. -1 if a tire call fails. */
static int peak_friction(const grip_est_tire_t *t, grip_real_t fz, int longitudinal, grip_real_t *mu_pk,
                         grip_real_t *slip_pk)
{
    grip_mf_input in;
    grip_mf_output o;
    int k;
    in.gamma = R_ZERO;
    in.fz = fz;
    in.p = R_ZERO;
    in.vx = RC(20.0);
    *mu_pk = R_ZERO;
    *slip_pk = RC(0.5);
    for (k = 1; k <= 25; ++k) {
        grip_real_t s = r_mul(RC(0.02), r_from_int(k));
        grip_real_t u;
        in.kappa = longitudinal ? r_neg(s) : R_ZERO;
        in.alpha = longitudinal ? R_ZERO : s;
        if (tire_eval(t, &in, &o) < 0) {
            return -1;
        }
        u = r_abs(r_div(longitudinal ? o.fx : o.fy, in.fz));
        if (u > *mu_pk) {
            *mu_pk = u;
            *slip_pk = s;
        }
    }
    return 0;
}

/* Lateral relaxation length [m] of the tire at load fz (est_tuning.h):
 * C_alpha / LATERAL_STIFFNESS, else PTY1 sin(2 atan(Fz / (PTY2 Fz0'))) R0
 * LFZO (MF 5.2), else 0 (no lag); at most EST_SIG_MAX. */
static grip_real_t relax_length(const grip_est_tire_t *t, grip_real_t c_alpha, grip_real_t fz)
{
    const grip_mf_params *p;
    grip_real_t fz0;
    if (t->kind != GRIP_EST_TIRE_MF || t->model.mf == NULL) {
        return R_ZERO;
    }
    p = t->model.mf;
    fz0 = r_mul(p->lfzo, p->fnomin);
    if (p->lateral_stiffness > R_ZERO) {
        return r_min(r_div(c_alpha, p->lateral_stiffness), RC(EST_SIG_MAX));
    }
    if (p->pty1 > R_ZERO && p->pty2 > R_ZERO && fz0 > R_ZERO) {
        grip_real_t s = r_sin(r_mul(RC(2.0), r_atan(r_div(fz, r_mul(p->pty2, fz0)))));
        return r_min(r_mul(r_mul(r_mul(p->pty1, s), p->unloaded_radius), p->lfzo), RC(EST_SIG_MAX));
    }
    return R_ZERO;
}

/* A wheel's relaxation length: the axle's at static load in proportion to
 * the wheel's load, at least EST_SIG_MIN; 0 where the tire file gives none. */
static grip_real_t wheel_sigma(const grip_est_t *est, int axle, grip_real_t fz)
{
    if (est->sig_a[axle] <= R_ZERO) {
        return R_ZERO;
    }
    return r_max(r_mul(est->sig_a[axle], r_div(fz, est->fz_static[axle])), RC(EST_SIG_MIN));
}

/* 1 - exp(-dist / sig): the share of the way the lagged slip angle moves
 * towards the kinematic one over the distance dist; 1 without a relaxation
 * length. The comparison first keeps the exponent within EST_RLX_A_MAX. */
static grip_real_t relax_share(grip_real_t dist, grip_real_t sig)
{
    if (sig <= R_ZERO || dist >= r_mul(RC(EST_RLX_A_MAX), sig)) {
        return R_ONE;
    }
    return r_sub(R_ONE, r_exp(r_neg(r_div(dist, sig))));
}

/* d Fy / d mu of one wheel (docs/estimator.md, "mu's secant"): the secant
 * of mu F0(alpha / mu) from mu down to mu - dmu, dmu = SEC_K sigma_mu, on
 * the axle's tabulated force shape: the shape's ratio F(mu - dmu) / F(mu)
 * applied to the wheel's own force fy (its load and combined slip), within
 * [0, fy / mu] like the tangent (F - alpha F') / mu. The tangent is 0 while
 * the model tire is linear, however far a lower mu would take it (the snow
 * onset: mu stayed at its prior while vy took the ay deficit). dmu and
 * 1 / mu are formed per wheel, not held across the wheel loop (the M0+
 * step's frame is within 24 B of the stack budget). */
static grip_real_t mu_secant(const grip_est_t *est, int axle, grip_real_t alpha, grip_real_t fy, grip_real_t mu)
{
    grip_real_t sig = r_mul(r_sqrt(est->p[2][2]), RC(EST_S_MU));
    grip_real_t dmu = r_max(r_min(r_mul(RC(EST_SEC_K), sig), r_sub(mu, est->mu_floor)), RC(EST_SEC_MIN));
    grip_real_t mu2 = r_sub(mu, dmu);
    grip_real_t inv_mu = r_div(R_ONE, mu);
    grip_real_t f1 = r_table_lerp(est->fy_shape[axle], GRIP_EST_SHAPE_N,
                                  r_mul(r_mul(r_abs(alpha), inv_mu), est->inv_apk[axle]));
    grip_real_t q = R_ZERO;
    if (f1 > RC(EST_SHAPE_F_MIN)) {
        grip_real_t f2 = r_table_lerp(est->fy_shape[axle], GRIP_EST_SHAPE_N,
                                      r_mul(r_mul(r_abs(alpha), r_div(R_ONE, mu2)), est->inv_apk[axle]));
        q = r_mul(r_sub(R_ONE, r_mul(r_mul(mu2, inv_mu), r_div(f2, f1))), r_div(R_ONE, dmu));
        q = r_clamp(q, R_ZERO, inv_mu);
    }
    return r_mul(q, fy);
}

/* vx's rate of change in the body frame: the measured ax less its learned
 * offset, plus r vy, plus gravity's component along the road's grade
 * (vx's prediction over a step, and vx at the outputs' time) */
static grip_real_t vx_rate(const grip_est_t *est, grip_real_t ax, grip_real_t r, grip_real_t vy, grip_real_t g_x)
{
    return r_add(r_add(r_sub(ax, est->ax_off), r_mul(r, vy)), g_x);
}

static grip_status_t check_config(const grip_est_config_t *c)
{
    int a;
    if (!in_range(c->mass, RCL(1.0), RCL(60000.0)) || !in_range(c->iz, RCL(1.0), RCL(200000.0)) ||
        !in_range(c->lf, RC(0.05), RC(10.0)) || !in_range(c->lr, RC(0.05), RC(10.0)) ||
        !in_range(c->track_f, RC(0.2), RC(4.0)) || !in_range(c->track_r, RC(0.2), RC(4.0)) ||
        !in_range(c->h_cg, R_ZERO, RC(3.0)) || !in_range(c->steer_ratio, R_ONE, RC(100.0)) ||
        !in_range(c->wheel_radius, RC(0.05), RC(2.0)) ||
        !in_range(c->roll_split_front, R_ZERO, R_ONE) || !in_range(c->roll_gradient, R_ZERO, RC(0.05)) || c->rate_hz < 50u || c->rate_hz > 2000u ||
        c->speed_ref_mu > 1u || !in_range(c->cla, R_ZERO, RC(20.0)) || !in_range(c->aero_front, R_ZERO, R_ONE) ||
        !in_range(c->air_density, RC(0.5), RC(1.5)) || !in_range(c->cda, R_ZERO, RC(5.0)) ||
        !in_range(c->crr, R_ZERO, RC(0.05)) || !in_range(c->tan_bank, RC(-0.5), RC(0.5)) ||
        !in_range(c->tan_grade, RC(-0.5), RC(0.5)) || !in_range(c->latency, R_ZERO, RC(0.1)) ||
        !in_range(c->steer_lag, R_ZERO, RC(0.5)) || !in_range(c->steer_latency, R_ZERO, RC(0.1))) {
        return GRIP_ERR_PARAM;
    }
    for (a = 0; a < 2; ++a) {
        if (c->tire[a].kind != GRIP_EST_TIRE_MF || c->tire[a].model.mf == NULL) {
            return GRIP_ERR_PARAM;
        }
        if (grip_mf_check_params(c->tire[a].model.mf) != GRIP_OK) {
            return GRIP_ERR_PARAM;
        }
    }
    return GRIP_OK;
}

grip_status_t grip_est_reset(grip_est_t *est)
{
    int i, j;
    if (est == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    est->vx = R_ZERO;
    est->x[0] = R_ZERO;
    est->x[1] = R_ZERO;
    est->x[2] = RC(EST_MU_INIT);
    est->x[3] = R_ZERO;
    for (i = 0; i < GRIP_EST_NX; ++i) {
        for (j = 0; j < GRIP_EST_NX; ++j) {
            est->p[i][j] = R_ZERO;
        }
    }
    est->p[0][0] = RC(EST_P0_VY);
    est->p[1][1] = RC(EST_P0_R);
    est->p[2][2] = RC(EST_P0_MU);
    est->p[3][3] = RC(EST_P0_B);
    for (i = 0; i < 5; ++i) {
        est->hold[i] = R_ZERO;
        est->age[i] = 1000000;
    }
    est->no_wheel_steps = 1000000;
    est->dr_steps = 0;
    est->ax_off = R_ZERO;
    est->r_lin_f = R_ZERO;
    est->delta_f = R_ZERO;
    est->delta_prev = R_ZERO;
    est->delta_o_d = R_ZERO;
    est->delta_prev_ok = 0;
    est->lim_steps = 0;
    est->us_steps = 0;
    est->us_low = 0;
    est->rel_steps = 0;
    est->mu_pre = R_ZERO;
    est->use_b = R_ZERO;
    est->nis_f = R_ZERO;
    est->sat_f = R_ZERO;
    est->sat_cap = 0;
    est->misfit = 0;
    for (i = 0; i < 4; ++i) {
        est->alpha_t[i] = R_ZERO;
        est->fy_dmu[i] = R_ZERO;
    }
    est->mu_lin = RC(EST_MU_INIT);
    est->mu_floor = RC(EST_MU_MIN);
    est->rlx_init = 0;
    est->yaw_mb = R_ZERO;
    est->lat_sb = R_ZERO;
    est->active = 0;
    est->vx_init = 0;
    est->psi = R_ZERO;
    return GRIP_OK;
}

grip_status_t grip_est_init(grip_est_t *est, const grip_est_config_t *cfg)
{
    grip_status_t st;
    grip_real_t l, m_g;
    int a, k;
    if (est == NULL || cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    est->magic = 0;
    st = check_config(cfg);
    if (st != GRIP_OK) {
        return st;
    }
    est->cfg = *cfg;
    l = r_add(cfg->lf, cfg->lr);
    m_g = r_mul(RC(EST_G * 0.5), cfg->mass);              /* half the weight [N] */
    est->fz_static[0] = r_mul(r_div(cfg->lr, l), m_g);
    est->fz_static[1] = r_mul(r_div(cfg->lf, l), m_g);
    est->xw[0] = cfg->lf;
    est->xw[1] = cfg->lf;
    est->xw[2] = r_neg(cfg->lr);
    est->xw[3] = r_neg(cfg->lr);
    est->yw[0] = r_mul(RC(0.5), cfg->track_f);
    est->yw[1] = r_neg(est->yw[0]);
    est->yw[2] = r_mul(RC(0.5), cfg->track_r);
    est->yw[3] = r_neg(est->yw[2]);
    for (a = 0; a < 2; ++a) {
        grip_mf_input in;
        grip_mf_output o1, o2;
        grip_real_t best, best2, alpha2, mux_pk;   /* mux_pk: the braking peak, not used */
        in.kappa = R_ZERO;
        in.alpha = RC(0.01);
        in.gamma = R_ZERO;
        in.fz = est->fz_static[a];
        in.p = R_ZERO;
        in.vx = RC(20.0);
        if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
            return GRIP_ERR_PARAM;
        }
        in.alpha = RC(-0.01);
        if (tire_eval(&cfg->tire[a], &in, &o2) < 0) {
            return GRIP_ERR_PARAM;
        }
        est->c_alpha[a] = r_div_keep(r_sub(o2.fy, o1.fy), RC(0.02));
        in.alpha = R_ZERO;
        in.kappa = RC(0.01);
        if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
            return GRIP_ERR_PARAM;
        }
        in.kappa = RC(-0.01);
        if (tire_eval(&cfg->tire[a], &in, &o2) < 0) {
            return GRIP_ERR_PARAM;
        }
        est->c_kappa[a] = r_div_keep(r_sub(o1.fx, o2.fx), RC(0.02));
        /* peak lateral friction coefficient at static load, and its load
         * sensitivity from the same sweep at 1.5 x static load (the
         * understeer-limit friction measurement sums the front wheels' peaks
         * at their current loads); the braking slip of the longitudinal peak
         * (kappa_at_friction) */
        if (peak_friction(&cfg->tire[a], est->fz_static[a], 0, &best, &est->alpha_pk[a]) < 0 ||
            peak_friction(&cfg->tire[a], r_mul(RC(1.5), est->fz_static[a]), 0, &best2, &alpha2) < 0 ||
            peak_friction(&cfg->tire[a], est->fz_static[a], 1, &mux_pk, &est->kappa_pk[a]) < 0) {
            return GRIP_ERR_PARAM;
        }
        est->mu0[a] = best;
        est->mu0_k[a] = r_mul(RC(2.0), r_sub(best2, best));
        if (est->c_alpha[a] <= R_ZERO || est->c_kappa[a] <= R_ZERO || best < RC(0.05)) {
            return GRIP_ERR_PARAM;
        }
        est->sig_a[a] = relax_length(&cfg->tire[a], est->c_alpha[a], est->fz_static[a]);
        /* the lateral force's shape over [0, alpha_pk] for mu's secant */
        est->inv_apk[a] = r_div(R_ONE, est->alpha_pk[a]);
        in.kappa = R_ZERO;
        in.fz = est->fz_static[a];
        for (k = 0; k <= GRIP_EST_SHAPE_N; ++k) {
            in.alpha = r_mul(est->alpha_pk[a], r_div(r_from_int(k), r_from_int(GRIP_EST_SHAPE_N)));
            if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
                return GRIP_ERR_PARAM;
            }
            est->fy_shape[a][k] = r_abs(r_div(o1.fy, in.fz));
        }
    }
    {
        /* stability factor A = m (lr Cr - lf Cf) / (l^2 Cf Cr), Cf, Cr per axle
         * (seed eq. 2.17 with K per tire = C / 2); stored as 100 A */
        grip_real_t cf = r_mul(RC(2.0), est->c_alpha[0]);
        grip_real_t cr = r_mul(RC(2.0), est->c_alpha[1]);
        grip_real_t num = r_sub(r_mul(cfg->lr, cr), r_mul(cfg->lf, cf));   /* N (QL) */
        grip_real_t a1 = r_div(num, cf);                                    /* m */
        grip_real_t b100 = r_div(r_mul(RC(100.0), cfg->mass), cr);          /* 100 kg rad / N */
        est->k_us = r_div(r_mul(a1, b100), r_mul(l, l));
    }
    est->rate = r_from_int((int32_t)cfg->rate_hz);
    est->ay_fac = r_div(R_ONE, r_add(R_ONE, r_mul(RC(EST_G), cfg->roll_gradient)));
    {
        /* road plane (residual/vehicle.py): the normal load factor
         * 1 / sqrt(1 + sx^2 + sy^2) does not depend on the heading */
        grip_real_t sx = cfg->tan_grade, sy = cfg->tan_bank;
        grip_real_t fzn = r_div(R_ONE, r_sqrt(r_add(R_ONE, r_add(r_sq(sx), r_sq(sy)))));
        grip_real_t kq = r_mul(RC(0.25), r_mul(cfg->air_density, cfg->cla));   /* per wheel */
        est->plane = (sx != R_ZERO || sy != R_ZERO) ? 1 : 0; /* grip-deviation: MISRA-10.6 tool: ?: of constants is not composite (8.10.3) */
        for (a = 0; a < 2; ++a) {
            est->fz_base[a] = est->plane ? r_mul(fzn, est->fz_static[a]) : est->fz_static[a];
        }
        est->k_aero[0] = r_mul(kq, cfg->aero_front);
        est->k_aero[1] = r_mul(kq, r_sub(R_ONE, cfg->aero_front));
        est->k_drag = r_mul(RC(0.5), r_mul(cfg->air_density, cfg->cda));
        est->f_roll = r_mul(cfg->crr, r_mul(RC(EST_G), cfg->mass));
    }
    est->q[0] = r_div(RC(EST_Q_VY), est->rate);
    est->q[1] = r_div(RC(EST_Q_R), est->rate);
    est->q[2] = r_div(RC(EST_Q_MU), est->rate);
    est->q[3] = r_div(RC(EST_Q_B), est->rate);
    est->nis_a = r_min(r_div(R_ONE, r_mul(RC(EST_MF_TAU), est->rate)), R_ONE);
    est->mb_a = r_min(r_div(R_ONE, r_mul(est->rate, RC(EST_MB_TAU))), R_ONE);
    est->steer_k = (cfg->steer_lag > R_ZERO) ? r_min(r_div(R_ONE, r_mul(cfg->steer_lag, est->rate)), R_ONE) : R_ONE;
    est->st_k_in = r_mul(r_sub(cfg->steer_latency, cfg->latency), est->rate);
    est->st_k_out = r_mul(cfg->steer_latency, est->rate);
    est->sb_a = r_min(r_div(R_ONE, r_mul(est->rate, RC(EST_SB_TAU))), R_ONE);
    est->sb_share_f = r_div(cfg->lr, r_add(cfg->lf, cfg->lr));
    est->lim_n = r_to_int(r_mul(RC(EST_LIM_T), est->rate));
    est->hold_steps = r_to_int(r_mul(RC(EST_HOLD_T), est->rate));
    est->nowheel_n = r_to_int(r_mul(RC(EST_NOWHEEL_T), est->rate));
    est->dr_n = r_to_int(r_mul(RC(EST_DR_T), est->rate));
    if (est->hold_steps < 1) {
        est->hold_steps = 1;
    }
    est->magic = EST_MAGIC;
    return grip_est_reset(est);
}

/* ------------------------------------------------------------------ */
/* Kalman filter pieces (scaled units, see est_tuning.h) */

/* state unit of each state: SI, except the gyro bias, which is kept in its
 * scaled unit (0.001 rad/s) so that its small per-step corrections survive
 * Q15.16 (1 LSB = 1.5e-5 rad/s in SI) */
static const grip_real_t est_s[GRIP_EST_NX] = { RC(EST_S_VY), RC(EST_S_R), RC(EST_S_MU), R_ONE };

/* P <- F P F' + Q in scaled units. Only the rows of vy and r of F are
 * given (f, 2 x 4): mu and the gyro bias are random walks (identity rows),
 * so their block of P only gets its process noise; this keeps the
 * temporaries at 2 x 4 (stack: the step's frame is the deepest part). */
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
static void kf_condition(grip_est_t *e)
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

/* Scalar measurement update in Joseph form for an arbitrary gain:
 * P' = (I - k h) P (I - k h)' + k r k'
 *    = P - k ph' - ph k' + k (k s)'         with ph = P h', s = h ph + r,
 * where k = ph / s, and k_mu = 0 when mu must not adapt, k_b = 0 when the
 * gyro bias must not (the Joseph form stays exact for that sub-optimal
 * gain). nu: innovation (scaled).
 * Adds k nu (in SI) to the state; keep_p: the covariance is left as it was
 * (a biased measurement that may move the state but not add confidence). Returns the normalized innovation
 * squared nu^2 / s of the (clamped) innovation, in [0, 16]. */
static grip_real_t kf_update(grip_est_t *e, const grip_real_t h[GRIP_EST_NX], grip_real_t nu, grip_real_t r,
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

/* ------------------------------------------------------------------ */

enum { H_STEER = 0, H_YAW = 1, H_AX = 2, H_AY = 3, H_VS = 4 };

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

static void zero_output(grip_est_output_t *out)
{
    int i;
    out->vx = R_ZERO;
    out->vy = R_ZERO;
    out->beta = R_ZERO;
    out->yaw_rate = R_ZERO;
    out->yaw_rate_ref = R_ZERO;
    out->yaw_error = R_ZERO;
    out->delta = R_ZERO;
    for (i = 0; i < 4; ++i) {
        out->kappa[i] = R_ZERO;
        out->alpha[i] = R_ZERO;
        out->fz[i] = R_ZERO;
        out->fx[i] = R_ZERO;
        out->fy[i] = R_ZERO;
        out->mz[i] = R_ZERO;
        out->util[i] = R_ZERO;
    }
    out->fy_axle[0] = R_ZERO;
    out->fy_axle[1] = R_ZERO;
    out->util_axle[0] = R_ZERO;
    out->util_axle[1] = R_ZERO;
    out->mu = R_ZERO;
    out->mu_conf = R_ZERO;
    out->yaw_rate_bias = R_ZERO;
    out->fy_margin_front = R_ZERO;
    out->steer_char = 0;
    out->valid = 0;
    out->flags = 0;
}

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
static EST_NOINLINE void lateral_outputs(grip_est_t *est, grip_est_output_t *out, grip_real_t vx, grip_real_t cd,
                            grip_real_t sd, grip_real_t vyd, grip_real_t racc, grip_real_t duv)
{
    grip_real_t lat = est->cfg.latency;
    grip_real_t vy = sym_clamp(r_add(est->x[0], r_mul(lat, vyd)), r_add(r_mul(RC(EST_VY_K), r_abs(vx)), R_ONE));
    grip_real_t r = sym_clamp(r_add(est->x[1], r_mul(lat, racc)), RC(EST_YAW_MAX));
    /* the outputs' road-wheel angle (steering latency), to first order about
     * the state's (a few mrad) */
    grip_real_t cd_o = r_sub(cd, r_mul(sd, est->delta_o_d)), sd_o = r_add(sd, r_mul(cd, est->delta_o_d));
    int i;
    for (i = 0; i < 4; ++i) {
        int axle = i >> 1;
        grip_real_t cdi = axle ? R_ONE : cd_o, sdi = axle ? R_ZERO : sd_o; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        /* the wheel kinematics of the step's tire loop, written out again: a
         * shared helper with out-parameters cost 24 B of M0+ stack in the
         * step (measured; the budget margin is 32 B) */
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
        dfda = r_neg(r_mul(g, r_mul(fzr, est->c_alpha[axle])));
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

grip_status_t grip_est_step(grip_est_t *est, const grip_input_sample_t *in, grip_est_output_t *out)
{
    static const int8_t side[4] = { 1, -1, 1, -1 };
    const grip_est_config_t *c;
    uint32_t flags = 0, valid = 0;
    int steer_ok, yaw_ok, ax_ok, ay_ok, vs_ok;
    int i, n_ws = 0, active, excited, wheels_ok = 1, lock = 0, spin = 0, stand = 0, at_rest = 0, dead_reck = 0;
    grip_real_t delta, cd, sd, yaw, ax, ay, rate, g_x, g_y;
    grip_real_t ws[4];
    int ws_ok[4];
    grip_real_t vmin = RC(1000.0), vmax = RC(-1000.0), vsum = R_ZERO, v_ref = R_ZERO;
    grip_real_t vx, fz_sum_f;
    grip_real_t mu;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    zero_output(out);
    if (est == NULL || in == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    c = &est->cfg;
    rate = est->rate;

    /* ---- inputs ---- */
    steer_ok = take_input(est, in, GRIP_IN_STEER_ANGLE, H_STEER, r_mul(c->steer_ratio, RC(EST_DELTA_MAX * 2.0)),
                          &flags);
    yaw_ok = take_input(est, in, GRIP_IN_YAW_RATE, H_YAW, RC(EST_YAW_MAX), &flags);
    ax_ok = take_input(est, in, GRIP_IN_AX, H_AX, RC(EST_ACC_MAX), &flags);
    ay_ok = take_input(est, in, GRIP_IN_AY, H_AY, RC(EST_ACC_MAX), &flags);
    vs_ok = take_input(est, in, GRIP_IN_VEHICLE_SPEED, H_VS, RC(EST_WS_MAX), &flags) && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
            est->age[H_VS] == 0;
    if (!steer_ok) {
        flags |= GRIP_EST_F_NO_STEER;
    }
    if (!yaw_ok) {
        flags |= GRIP_EST_F_NO_YAW;
    }
    if (!ax_ok) {
        flags |= GRIP_EST_F_NO_AX;
    }
    if (!ay_ok) {
        flags |= GRIP_EST_F_NO_AY;
    }
    delta = r_div(est->hold[H_STEER], c->steer_ratio);
    if (r_abs(delta) > RC(EST_DELTA_MAX)) {
        flags |= GRIP_EST_F_STEER_LIMIT;
        delta = sym_clamp(delta, RC(EST_DELTA_MAX));
    }
    if (!steer_ok) {
        delta = R_ZERO;
    }
    /* the road wheels lag the steering signal by cfg.steer_lag (first order):
     * the slip angles and the yaw reference below take the lagged angle */
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
        grip_real_t d_step = (steer_ok && est->delta_prev_ok) ? r_sub(delta, est->delta_prev) : R_ZERO; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        grip_real_t delta_s = sym_clamp(r_add(delta, r_mul(est->st_k_in, d_step)), RC(EST_DELTA_MAX));
        est->delta_prev = delta;
        est->delta_prev_ok = steer_ok;
        est->delta_o_d = r_sub(sym_clamp(r_add(delta, r_mul(est->st_k_out, d_step)), RC(EST_DELTA_MAX)), delta_s);
        delta = delta_s;
    }
    cd = r_cos(delta);
    sd = r_sin(delta);
    /* yaw rate with the estimated gyro bias (state x[3]) removed */
    yaw = yaw_ok ? r_sub(est->hold[H_YAW], r_mul(RC(EST_S_B), est->x[3])) : R_ZERO;
    ax = ax_ok ? est->hold[H_AX] : R_ZERO;
    /* the accelerometer rolls with the body: ay_meas = ay cos(phi) + g sin(phi),
     * phi = roll_gradient * ay, so ay = ay_meas / (1 + g roll_gradient) */
    ay = ay_ok ? r_mul(est->ay_fac, est->hold[H_AY]) : R_ZERO;

    /* road plane: gravity along the body axes at the heading since reset */
    g_x = R_ZERO;
    g_y = R_ZERO;
    if (est->plane) {
        grip_real_t cp = r_cos(est->psi), sp = r_sin(est->psi);
        grip_real_t sx = r_add(r_mul(c->tan_grade, cp), r_mul(c->tan_bank, sp));
        grip_real_t sy = r_sub(r_mul(c->tan_bank, cp), r_mul(c->tan_grade, sp));
        g_x = r_neg(r_div(r_mul(RC(EST_G), sx), r_sqrt(r_add(R_ONE, r_sq(sx)))));
        g_y = r_neg(r_div(r_mul(RC(EST_G), sy), r_sqrt(r_add(R_ONE, r_sq(sy)))));
        est->psi = r_add(est->psi, r_div(yaw, rate));
        if (est->psi > RC(3.14159265358979)) {
            est->psi = r_sub(est->psi, RC(6.28318530717959));
        } else if (est->psi < RC(-3.14159265358979)) {
            est->psi = r_add(est->psi, RC(6.28318530717959));
        } /* grip-deviation: MISRA-15.7 within (-pi, pi]: nothing to do */
    }


    /* ---- longitudinal speed ---- */
    {
        grip_real_t r_now = est->active ? est->x[1] : yaw;
        grip_real_t vy_now = est->active ? est->x[0] : R_ZERO;
        grip_real_t vx_pred = r_add(est->vx, r_div(vx_rate(est, ax, r_now, vy_now, g_x), rate));
        grip_real_t k = R_ZERO;
        grip_real_t vcs[4];
        int outl[4], n_good = 0;
        for (i = 0; i < 4; ++i) {
            grip_real_t v = in->value[GRIP_IN_WHEEL_SPEED_FL + i];
            ws_ok[i] = in->valid[GRIP_IN_WHEEL_SPEED_FL + i] && r_is_finite(v) && r_abs(v) < RC(EST_WS_MAX);
            if (in->valid[GRIP_IN_WHEEL_SPEED_FL + i] && !ws_ok[i]) {
                flags |= GRIP_EST_F_SATURATED;
            }
            ws[i] = ws_ok[i] ? v : R_ZERO;
            outl[i] = 0;
            vcs[i] = R_ZERO;
            if (ws_ok[i]) {
                /* speed of the CG the wheel indicates (yaw-corrected, steered) */
                grip_real_t vc = (i < 2) ? r_div_keep(ws[i], cd) : ws[i];
                vc = r_add(vc, r_mul(r_now, est->yw[i]));
                vcs[i] = vc;
                n_ws += 1;
                if (vx_pred > RC(EST_V_ON)) {
                    if (vc < r_sub(r_mul(RC(1.0 - EST_WHEEL_DEV), vx_pred), RC(0.5))) {
                        lock = 1;
                        outl[i] = 1;
                    }
                    if (vc > r_add(r_mul(RC(1.0 + EST_WHEEL_DEV), vx_pred), RC(0.5))) {
                        spin = 1;
                        outl[i] = 1;
                    }
                }
                if (!outl[i]) {
                    n_good += 1;
                }
            } else {
                wheels_ok = 0;
            }
        }
        /* every valid wheel off the prediction on the side the measured
         * acceleration rules out (all above it while the car slows, all below
         * while it speeds up): no wheel spins while the car decelerates and
         * none locks while it accelerates, so the prediction is what is lost
         * (after a speed-reference fault): the wheels are taken */
        if (n_good == 0 && n_ws > 0 && ax_ok &&
            ((spin && !lock && ax <= RC(-EST_DR_AX)) || (lock && !spin && ax >= RC(EST_DR_AX)))) {
            for (i = 0; i < 4; ++i) {
                outl[i] = 0;
            }
            n_good = n_ws;
            lock = 0;
            spin = 0;
        }
        /* the reference uses the wheels that are not locked or spinning
         * (all valid ones when every wheel is) */
        for (i = 0; i < 4; ++i) {
            if (ws_ok[i] && (!outl[i] || n_good == 0)) {
                vmin = r_min(vmin, vcs[i]);
                vmax = r_max(vmax, vcs[i]);
                vsum = r_add(vsum, vcs[i]);
            }
        }
        if (n_good > 0) {
            n_ws = n_good;
        }
        if (lock) {
            flags |= GRIP_EST_F_WHEEL_LOCK;
        }
        if (spin) {
            flags |= GRIP_EST_F_WHEEL_SPIN;
        }
        if (vs_ok) {
            v_ref = est->hold[H_VS];
            k = RC(EST_K_HI);
        } else if (n_ws > 0) {
            static const grip_real_t inv_n[5] = { RC(0.0), RC(1.0), RC(0.5), RC(1.0 / 3.0), RC(0.25) };
            if (ax < RC(-EST_AX_TH)) {
                v_ref = vmax;
            } else if (ax > RC(EST_AX_TH)) {
                v_ref = vmin;
            } else {
                v_ref = spread_reference(r_mul(inv_n[n_ws], vsum), vmin, vmax, vx_pred);
            }
            {
                /* wheels agree with each other: trust them (fully when they also
                 * agree with the prediction, at K_MID when all of them disagree
                 * with it, e.g. after a long loss); otherwise K_LO */
                int agree = r_sub(vmax, vmin) <= r_add(RC(0.5), r_mul(RC(0.05), r_abs(vx_pred))); /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
                int trusted = agree && !lock && !spin; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
                k = agree ? ((lock || spin) ? RC(EST_K_MID) : RC(EST_K_HI)) : RC(EST_K_LO); /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
                /* braking slips every wheel (the brakes act on all four): the
                 * fastest one is still slower than the car */
                if (ax < RC(-EST_AX_TH) && v_ref < vx_pred) {
                    k = r_min(k, RC(EST_K_SLIP));
                    trusted = 0;
                }
                /* the ax offset (unconfigured grade, accelerometer bias) from
                 * the wheels while they are trusted (all agree, none locked or
                 * spinning, not braking below the prediction) */
                if (trusted && vx_pred > RC(EST_V_ON) && ax_ok && est->vx_init) {
                    est->ax_off = sym_clamp(r_sub(est->ax_off, r_mul(r_div(RC(EST_K_OFF), rate), r_sub(v_ref, vx_pred))),
                                            RC(EST_AX_OFF_MAX));
                }
            }
        } /* grip-deviation: MISRA-15.7 no speed reference: k stays 0, vx follows the prediction */
        /* every wheel locked or spinning (every valid wheel is an outlier)
         * while the car still decelerates or accelerates: no wheel tells
         * the speed, integrate ax */
        dead_reck = n_good == 0 && n_ws > 0 && r_abs(ax) >= RC(EST_DR_AX) && ax_ok && !vs_ok; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
        if (dead_reck) {
            k = R_ZERO;
            est->dr_steps = count_up(est->dr_steps);
        } else {
            est->dr_steps = 0;
        }
        if (vs_ok || n_ws > 0) {
            est->no_wheel_steps = 0;
        } else {
            flags |= GRIP_EST_F_NO_WHEELS;
            est->no_wheel_steps = count_up(est->no_wheel_steps);
        }
        if (!est->vx_init) {
            if (vs_ok || n_ws > 0) {
                est->vx = v_ref;
                est->vx_init = 1;
            }
        } else {
            est->vx = r_add(vx_pred, r_mul(r_min(r_div(k, rate), R_ONE), r_sub(v_ref, vx_pred)));
        }
        stand = n_ws > 0 && vmax < RC(EST_V_STAND) && vmin > RC(-EST_V_STAND) && !dead_reck; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
        /* the gyro reads its bias at rest: every wheel at rest and the car
         * (nearly) stopped already by the prediction (wheels locked at speed
         * are not a standstill) */
        at_rest = stand && r_abs(vx_pred) < RC(EST_V_ON); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
        if (stand && !vs_ok) {
            est->vx = R_ZERO;       /* standstill: stops ax-bias drift */
        }
        est->vx = sym_clamp(est->vx, RC(EST_WS_MAX));
    }
    vx = est->vx;
    if (r_abs(vx) < RC(EST_V_STAND)) {
        flags |= GRIP_EST_F_STANDSTILL;
    }
    if (vx < RC(-EST_V_STAND)) {
        flags |= GRIP_EST_F_REVERSING;
    }
    if (est->vx_init && est->no_wheel_steps <= est->nowheel_n && est->dr_steps <= est->dr_n) {
        valid |= GRIP_EST_V_VX;
    }

    /* ---- vertical loads (quasi-static load transfer from ax, ay) ---- */
    {
        grip_real_t l = r_add(c->lf, c->lr);
        grip_real_t dlong = r_mul(r_div(c->h_cg, r_mul(RC(2.0), l)), r_mul(ax, c->mass));   /* per wheel */
        grip_real_t may_h = r_mul(c->h_cg, r_mul(ay, c->mass));                            /* N m */
        grip_real_t dlat_f = r_mul(c->roll_split_front, r_div_keep(may_h, c->track_f));
        grip_real_t dlat_r = r_mul(r_sub(R_ONE, c->roll_split_front), r_div_keep(may_h, c->track_r));
        /* static load on the road plane plus downforce 0.5 rho C_L A vx^2 */
        grip_real_t v2 = r_qs_to_ql(r_sq(vx));
        grip_real_t fz0f = r_add(est->fz_base[0], r_mul(est->k_aero[0], v2));
        grip_real_t fz0r = r_add(est->fz_base[1], r_mul(est->k_aero[1], v2));
        out->fz[0] = r_sub(r_sub(fz0f, dlong), dlat_f);
        out->fz[1] = r_add(r_sub(fz0f, dlong), dlat_f);
        out->fz[2] = r_sub(r_add(fz0r, dlong), dlat_r);
        out->fz[3] = r_add(r_add(fz0r, dlong), dlat_r);
        for (i = 0; i < 4; ++i) {
            out->fz[i] = r_max(out->fz[i], R_ZERO);
        }
        if (ax_ok && ay_ok) {
            valid |= GRIP_EST_V_FZ;
        }
    }
    fz_sum_f = r_add(out->fz[0], out->fz[1]);

    /* ---- lateral observer on / off ---- */
    active = est->active;
    if (active && (vx < RC(EST_V_OFF) || !steer_ok || !(valid & GRIP_EST_V_VX))) {
        active = 0;
    }
    if (!active && vx >= RC(EST_V_ON) && steer_ok && yaw_ok && (valid & GRIP_EST_V_VX)) {
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
        flags |= GRIP_EST_F_RESET;
    }
    est->active = active;
    if (!active) {
        flags |= GRIP_EST_F_LOW_SPEED;
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
        if (at_rest && yaw_ok && wheels_ok && ax_ok && r_abs(ax) < RC(EST_B_AX)) {
            grip_real_t h[GRIP_EST_NX];
            h[0] = R_ZERO;
            h[1] = R_ZERO;
            h[2] = R_ZERO;
            h[3] = RC(EST_S_B / EST_S_R);
            (void)kf_update(est, h, r_div(r_sub(est->hold[H_YAW], r_mul(RC(EST_S_B), est->x[3])), RC(EST_S_R)),
                      RC(EST_R_YAW), 0, 1, 0);
            kf_condition(est);
            est->x[3] = sym_clamp(est->x[3], RC(EST_B_MAX / EST_S_B));
        }
    }
    mu = est->x[2];
    est->mu_lin = mu;

    if (active) {
        grip_real_t jay[3] = { R_ZERO, R_ZERO, R_ZERO };   /* d(sum Fby)/d(vy, r, mu) [QL] */
        grip_real_t jr[3] = { R_ZERO, R_ZERO, R_ZERO };    /* d(sum Mz_body)/d(vy, r, mu) */
        grip_real_t jax_mu = R_ZERO;
        grip_real_t sfx = R_ZERO, sfy = R_ZERO, smz = R_ZERO;
        grip_real_t vy = est->x[0], r = est->x[1];
        grip_real_t umax = R_ZERO, umax_x = R_ZERO, kappa_sum = R_ZERO, umax_est = R_ZERO;
        int at_limit = 0, b_ok, kappa_slip = 0, ref_ok, braked_slip;
        grip_real_t f[2][GRIP_EST_NX];   /* rows vy, r of the transition (mu, bias: identity) */
        grip_real_t ay_m, ax_m, racc, dvy, dr, m = c->mass, nis_ay;
        grip_real_t mu_us = R_ZERO;      /* > 0: upper friction measurement at the understeer limit */
        /* the friction in use bounds mu from below (a bound on the state, no
         * measurement: it adds no confidence); mu's secant spans no lower (a
         * steering offset's onset took mu 1.0 -> 0.49 in 0.05 s on a dry road
         * with the secant down to MU_MIN). |a| is formed again in the limit
         * test below: held across the tire loop it cost 8 B of M0+ stack */
        est->mu_floor = (ax_ok && ay_ok) ? r_max(RC(EST_MU_MIN),
                                                 r_min(r_div(r_sqrt(r_add(r_sq(ax), r_sq(ay))),
                                                             r_mul(RC(EST_G), r_max(est->mu0[0], est->mu0[1]))),
                                                       RC(EST_MU_MAX)))
                                         : RC(EST_MU_MIN);

        for (i = 0; i < 4; ++i) {
            int axle = i >> 1;
            grip_real_t cdi = axle ? R_ONE : cd, sdi = axle ? R_ZERO : sd; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
            grip_real_t vcx = r_sub(vx, r_mul(r, est->yw[i]));
            grip_real_t vcy = r_add(vy, r_mul(r, est->xw[i]));
            grip_real_t vxw = r_add(r_mul(cdi, vcx), r_mul(sdi, vcy));
            grip_real_t vyw = r_sub(r_mul(cdi, vcy), r_mul(sdi, vcx));
            grip_real_t den = r_max(r_abs(vxw), RC(EST_V_OFF));
            grip_real_t t = r_div(vyw, den);
            grip_real_t alpha = r_atan(t);       /* kinematic, then lagged (relaxation) */
            grip_real_t kappa = R_ZERO;
            grip_real_t lever = r_add(r_mul(est->xw[i], cdi), r_mul(est->yw[i], sdi));
            grip_real_t c2, dady, dadr, ca, g, u, dfda, dfdmu, fxn, fyn, fzr;
            grip_mf_input ti;
            grip_mf_output to;
            grip_status_t st;
            if (ws_ok[i]) {
                kappa = r_clamp(r_div(r_sub(ws[i], vxw), den), RC(-1.0), RC(1.5));
            }
            /* the tires work at the lagged slip angle; the Jacobians below keep
             * the kinematic slope (the lag settles within sigma / |vx|, ~20 ms
             * at speed, inside the filter's horizon). The updates' correction
             * of vy was carried into alpha_t at the end of the last step
             * (lateral_outputs); what is lagged here is the rest of the
             * motion since then */
            if (!est->rlx_init) {
                est->alpha_t[i] = alpha;
            }
            alpha = r_add(est->alpha_t[i], r_mul(relax_share(r_div(r_abs(vxw), est->rate), wheel_sigma(est, axle, out->fz[i])),
                                                  r_sub(alpha, est->alpha_t[i])));
            est->alpha_t[i] = alpha;
            ti.kappa = kappa_at_friction(kappa, mu, est->kappa_pk[axle]);
            /* beyond the peak slip angle the model force is held at its peak:
             * the falling branch would make vy and mu unobservable together */
            ti.alpha = sym_clamp(r_div(alpha, mu), est->alpha_pk[axle]);
            if (side[i] < 0) {
                ti.alpha = r_neg(ti.alpha);   /* right wheel: mirror image of the LEFT-fitted tire */
            }
            ti.gamma = R_ZERO;
            ti.fz = out->fz[i];
            ti.p = R_ZERO;
            ti.vx = vxw;
            st = tire_eval(&c->tire[axle], &ti, &to);
            if (st < 0) {
                flags |= GRIP_EST_F_TIRE_ERROR;
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
            out->fx[i] = r_mul(mu, to.fx);
            out->fy[i] = r_mul(mu, to.fy);
            out->mz[i] = r_mul(mu, to.mz);
            if (ws_ok[i] && st >= 0) {
                valid |= GRIP_EST_V_WHEEL(i);
            }
            /* utilization and local slope */
            if (out->fz[i] > RCL(50.0)) {
                fxn = r_div(out->fx[i], out->fz[i]);
                fyn = r_div(out->fy[i], out->fz[i]);
                fzr = r_div(out->fz[i], est->fz_static[axle]);
            } else {
                fxn = R_ZERO;
                fyn = R_ZERO;
                fzr = R_ZERO;
            }
            u = r_div(r_sqrt(r_add(r_sq(fxn), r_sq(fyn))), r_mul(mu, est->mu0[axle]));
            out->util[i] = r_min(u, RC(1.5));
            umax_est = r_max(umax_est, out->util[i]);
            g = r_max(RC(EST_G_MIN), r_sqrt(r_sub(R_ONE, r_min(u, R_ONE))));
            ca = r_mul(fzr, est->c_alpha[axle]);                 /* N/rad at this load */
            {
                /* Excitation: the utilization the slips would cause on the
                 * tire's own friction (mu = 1), never measured against the
                 * estimate itself, which would let a falling mu excite its
                 * own adaptation. */
                grip_real_t cap = r_max(r_mul(est->mu0[axle], out->fz[i]), RCL(50.0));
                grip_real_t ulin_y = r_div(r_mul(r_abs(alpha), r_mul(fzr, est->c_alpha[axle])), cap);
                grip_real_t ulin_x = r_div(r_mul(r_abs(kappa), r_mul(fzr, est->c_kappa[axle])), cap);
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
            dfdmu = mu_secant(est, axle, alpha, out->fy[i], mu);   /* d Fy / d mu [N] */
            est->fy_dmu[i] = dfdmu; /* the output forces move along it with the updates' mu */
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
                grip_real_t dfxdk = r_mul(g, r_mul(fzr, est->c_kappa[axle]));
                grip_real_t dfxdmu = r_div_keep(between_zero(r_sub(out->fx[i], r_mul(kappa, dfxdk)), out->fx[i]), mu);
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
                grip_real_t fxn = r_div(fxa, fzx), fyn = r_div(out->fy_axle[i], fzx);
                out->util_axle[i] = r_min(r_div(r_sqrt(r_add(r_sq(fxn), r_sq(fyn))), r_mul(mu, est->mu0[i])),
                                          RC(1.5));
            }
        }
        ay_m = r_div(sfy, m);
        /* the measured ax also carries the drag and the rolling resistance
         * (vx > 0 here: the lateral observer runs above EST_V_OFF) */
        ax_m = r_div(r_sub(sfx, r_add(r_mul(est->k_drag, r_qs_to_ql(r_sq(vx))), est->f_roll)), m);
        racc = r_div(smz, c->iz);

        excited = vx >= RC(EST_V_EXC) && umax >= RC(EST_EXC_U) && ay_ok && ax_ok && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
                  r_add(r_abs(ax), r_abs(ay)) >= RC(EST_EXC_A);
        {
            /* friction-limit test, independent of the mu estimate: the yaw
             * rate leaves the (lagged) linear bicycle reference by more than
             * 15 % + 0.03 rad/s for 0.2 s with |a| >= 2 m/s^2 */
            grip_real_t l = r_add(c->lf, c->lr);
            grip_real_t av2 = r_mul(RC(0.01), r_mul(r_mul(est->k_us, vx), vx));
            grip_real_t den = r_max(r_mul(l, r_add(R_ONE, av2)), r_mul(RC(0.1), l));
            grip_real_t r_lin = r_div(r_mul(vx, delta), den);
            grip_real_t a_tot = r_sqrt(r_add(r_sq(ax), r_sq(ay)));
            est->r_lin_f = r_add(est->r_lin_f, r_mul(r_min(r_div(R_ONE, r_mul(RC(EST_LIM_TAU), rate)), R_ONE),
                                                     r_sub(r_lin, est->r_lin_f)));
            /* both limit tests need speed, the inertial inputs and acceleration */
            int lim_ok = vx >= RC(EST_V_EXC) && yaw_ok && ax_ok && ay_ok && a_tot >= RC(EST_LIM_A); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
            if (lim_ok &&
                r_abs(r_sub(yaw, est->r_lin_f)) >= r_add(r_mul(RC(EST_LIM_REL), r_abs(est->r_lin_f)), RC(EST_LIM_ABS))) {
                est->lim_steps = count_up(est->lim_steps);
            } else {
                est->lim_steps = 0;
            }
            at_limit = est->lim_steps >= est->lim_n; /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
            /* low-friction detection at the understeer limit (deficit dd of
             * the yaw rate against the lagged reference, same turn direction) */
            {
                grip_real_t dd = (r_abs(est->r_lin_f) > RC(EST_US_R)) ? r_sub(R_ONE, r_div(yaw, est->r_lin_f)) : R_ZERO; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
                mu_us = understeer_bound(est, out->fz, ay, ax, dd, l,
                                         lim_ok && ((est->r_lin_f > R_ZERO && ay > R_ZERO) ||
                                                    (est->r_lin_f < R_ZERO && ay < R_ZERO)),
                                         r_abs(ax) < RC(EST_B_AX) &&
                                             r_abs(r_sub(r_add(ay, g_y), r_mul(yaw, vx))) < RC(EST_B_AX));
            }
            if (at_limit) {
                excited = 1;
            }
        }

        /* ---- predict ---- */
        /* vy: kinematic process vy' = ay - r vx (the tire model enters
         * through the ay measurement, so a flat tire curve at the limit
         * leaves vy to the kinematics instead of to model errors); the
         * model's ay stands in when the accelerometer is missing */
        /* the gyro bias adapts only where the tire model is trusted (linear
         * range, no locked or spinning wheel, no hard braking or driving, no
         * friction-limit indication, no fast yaw transient, where the modelled
         * tire lag errs most); else it would absorb the model's errors */
        b_ok = r_abs(racc) < RC(EST_B_RACC) && umax_est < RC(EST_B_U) && r_abs(ay) < RC(EST_B_A) && r_abs(ax) < RC(EST_B_AX) && !lock && !spin && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
               !at_limit;
        dvy = r_div(r_sub(r_add(ay_ok ? ay : ay_m, g_y), r_mul(r, vx)), rate);
        dr = r_div(racc, rate);
        {
            grip_real_t a_vv = r_div(jay[0], m), a_vr = r_div(jay[1], m), a_vm = r_div(jay[2], m);
            grip_real_t a_rv = r_div(jr[0], c->iz), a_rr = r_div(jr[1], c->iz), a_rm = r_div(jr[2], c->iz);
            grip_real_t ay_pred, h[GRIP_EST_NX];
            if (ay_ok) {
                f[0][0] = R_ONE;
                f[0][1] = r_mul(r_div(r_neg(vx), rate), RC(EST_S_R / EST_S_VY));
                f[0][2] = R_ZERO;
                f[0][3] = R_ZERO;
            } else {
                f[0][0] = r_add(R_ONE, r_div(a_vv, rate));
                f[0][1] = r_mul(r_div(r_sub(a_vr, vx), rate), RC(EST_S_R / EST_S_VY));
                f[0][2] = r_mul(r_div(a_vm, rate), RC(EST_S_MU / EST_S_VY));
                f[0][3] = R_ZERO;
            }
            f[1][0] = r_mul(r_div(a_rv, rate), RC(EST_S_VY / EST_S_R));
            f[1][1] = r_add(R_ONE, r_div(a_rr, rate));
            f[1][2] = r_mul(r_div(a_rm, rate), RC(EST_S_MU / EST_S_R));
            f[1][3] = R_ZERO;
            est->x[0] = r_add(vy, dvy);
            est->x[1] = r_add(r, dr);
            kf_predict(est, f);
            kf_condition(est);
            /* ---- updates ---- (each measurement predicted to first order at
             * the current state from the forces at the prior point vy, r, mu) */
            if (yaw_ok) {
                h[0] = R_ZERO;
                h[1] = R_ONE;
                h[2] = R_ZERO;
                h[3] = RC(EST_S_B / EST_S_R);   /* the gyro reads r + bias */
                /* mu does not adapt on the yaw rate: the yaw moment balance is
                 * the most model-sensitive equation (Iz, lever arms, the
                 * front/rear force split at the limit) and drove mu away
                 * at the limit of the simulator's ramp steer */
                (void)kf_update(est, h, r_div(r_sub(yaw, est->x[1]), RC(EST_S_R)),
                          RC(EST_R_YAW), 0, b_ok, 0);
                kf_condition(est);
            }
            /* the yaw moment the model lacks (the gyro's yaw acceleration
             * against the model's) as a front-axle force Iz dr / l */
            {
                grip_real_t dmr = R_ZERO;
                if (yaw_ok && r_abs(ax) < RC(EST_MB_AX)) {
                    dmr = sym_clamp(r_mul(r_sub(est->x[1], r_add(r, dr)), rate), RC(EST_MB_RACC));
                }
                est->yaw_mb = r_add(est->yaw_mb,
                                    r_mul(est->mb_a, r_sub(r_div(r_mul(c->iz, dmr), r_add(c->lf, c->lr)), est->yaw_mb)));
            }
            /* a road-wheel angle beyond the rack's travel (STEER_LIMIT) is not
             * the car's: the model's slip angles would be fitted to it (at
             * lock on a straight road vy went to 2.3 m/s, past both axles'
             * peaks, and stayed there after the steering recovered) */
            if (ay_ok && ((flags & GRIP_EST_F_STEER_LIMIT) == 0u)) {
                ay_pred = r_add(ay_m, r_add(r_mul(a_vv, r_sub(est->x[0], vy)), r_mul(a_vr, r_sub(est->x[1], r))));
                ay_pred = r_add(ay_pred, r_mul(a_vm, r_sub(est->x[2], mu)));
                h[0] = sym_clamp(r_mul(a_vv, RC(EST_S_VY / EST_S_AY)), RC(EST_H_MAX_VY));
                h[1] = sym_clamp(r_mul(a_vr, RC(EST_S_R / EST_S_AY)), RC(EST_H_MAX));
                h[2] = sym_clamp(r_mul(a_vm, RC(EST_S_MU / EST_S_AY)), RC(EST_H_MAX));
                h[3] = R_ZERO;
                /* the utilization at mu + AY_U_K sigma_mu only while the car's
                 * own yaw response (the mu-independent limit test) says it is
                 * at its limit: elsewhere a model at its own limit is the
                 * model's claim, not evidence (AV-21 log: with a mu cut by the
                 * understeer bound, the updates confirmed it to mu_conf 0.74);
                 * nor while the bound holds mu (a steering offset fakes both
                 * the deficit and the limit test) */
                nis_ay = kf_update(est, h, r_div(r_sub(ay, ay_pred), RC(EST_S_AY)),
                                   ay_noise(out, umax_est,
                                            (at_limit && !est->us_low) ? r_div(mu, r_add(mu, r_mul(RC(EST_AY_U_K * EST_S_MU),
                                                                                 r_sqrt(est->p[2][2]))))
                                                     : R_ONE),
                                   excited, b_ok, 0);
                kf_condition(est);
                {
                    /* model consistency (docs/estimator.md): the low-passed ay
                     * NIS (1 on average for a consistent filter), and the share
                     * of time the model claims saturated tires while the car's
                     * yaw response (the mu-independent limit test) is not at
                     * the limit. A tire model that does not fit is absorbed by
                     * vy and mu, so the NIS alone stays small (AV-21 log). */
                    grip_real_t sat = (vx >= RC(EST_V_EXC) && umax_est >= RC(EST_SAT_U) && !at_limit) ? R_ONE : R_ZERO; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
                    est->nis_f = r_add(est->nis_f, r_mul(est->nis_a, r_sub(nis_ay, est->nis_f)));
                    est->sat_f = r_add(est->sat_f, r_mul(est->nis_a, r_sub(sat, est->sat_f)));
                    if (est->nis_f > RC(EST_NIS_HI) || est->sat_f > RC(EST_SAT_HI)) {
                        est->misfit = 1;
                    } else if (est->nis_f < RC(EST_NIS_LO) && est->sat_f < RC(EST_SAT_LO)) {
                        est->misfit = 0;
                    } /* grip-deviation: MISRA-15.7 between the thresholds the state is kept (hysteresis) */
                    /* the confidence cap below has its own hysteresis: a share
                     * that hovers at SAT_MU would toggle mu's validity */
                    if (est->sat_f > RC(EST_SAT_MU)) {
                        est->sat_cap = 1;
                    } else if (est->sat_f < RC(EST_SAT_MU_LO)) {
                        est->sat_cap = 0;
                    } /* grip-deviation: MISRA-15.7 between the thresholds the state is kept (hysteresis) */
                }
            }
            {
                /* the lateral balance: the lateral force the model still
                 * lacks at the updated state (the ay update is weak at the
                 * limit, where the model is least trusted) */
                grip_real_t sb_t = R_ZERO;
                if (ay_ok && r_abs(ax) < RC(EST_MB_AX)) {
                    ay_pred = r_add(ay_m, r_add(r_mul(a_vv, r_sub(est->x[0], vy)), r_mul(a_vr, r_sub(est->x[1], r))));
                    ay_pred = r_add(ay_pred, r_mul(a_vm, r_sub(est->x[2], mu)));
                    /* within the accelerometer's range: mass x residual then fits QL */
                    sb_t = r_mul(c->mass, sym_clamp(r_sub(ay, ay_pred), RC(EST_ACC_MAX)));
                }
                est->lat_sb = r_add(est->lat_sb, r_mul(est->sb_a, r_sub(sb_t, est->lat_sb)));
            }
            /* longitudinal update only with an independent speed reference:
             * from the wheel speeds alone, vx is biased by the very slip that
             * carries the information (braking on the simulator's wet road
             * drove mu to its upper bound) */
            /* ... and only when the slips push the way the car accelerates:
             * a speed reference that reads a few per cent off the wheel
             * speeds (a speedometer calibration) makes slip of the wrong
             * sign, which would otherwise drive mu down (RAV4 log). */
            /* A braked wheel at 15 % slip or more (locked, or cycled by an
             * ABS past the tire's peak) works at the road's friction, and
             * its slip is far above what a 0.3 % speed-reference error
             * moves: braking with one is a friction measurement without a
             * speed reference. The free wheels' slips are in the same sum,
             * so it moves mu but adds no confidence: the covariance is kept */
            ref_ok = (c->speed_ref_mu != 0u) && vs_ok; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
            braked_slip = ax < RC(-EST_AX_TH) && kappa_slip; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
            if (excited && (ref_ok || braked_slip) && wheels_ok && umax_x >= RC(EST_EXC_U) &&
                r_abs(ax) >= RC(EST_EXC_A) && r_mul(kappa_sum, ax) > R_ZERO) {
                grip_real_t ax_pred = r_add(ax_m, r_mul(r_div(jax_mu, m), r_sub(est->x[2], mu)));
                h[0] = R_ZERO;
                h[1] = R_ZERO;
                h[2] = sym_clamp(r_mul(r_div(jax_mu, m), RC(EST_S_MU / EST_S_AY)), RC(EST_H_MAX));
                h[3] = R_ZERO;
                (void)kf_update(est, h, r_div(r_sub(ax, ax_pred), RC(EST_S_AY)), ref_ok ? RC(EST_R_AX) : RC(EST_R_LOCK), 1, b_ok, !ref_ok); /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
                kf_condition(est);
            }
        }
        /* state bounds; mu: the friction in use from below, the understeer
         * limit's measurement from above. Bounds on the state, not
         * measurements: they add no confidence (a steering-angle offset
         * fakes an understeer deficit, docs/faults.md) */
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
                (void)kf_update(est, h_mu, r_div(r_sub(mu_hi, est->x[2]), RC(EST_S_MU)), R_ZERO, 1, 0, 1);
            }
            est->x[2] = r_clamp(est->x[2], est->mu_floor, mu_hi);
        }
        est->x[0] = sym_clamp(est->x[0], r_add(r_mul(RC(EST_VY_K), r_abs(vx)), R_ONE));
        est->x[1] = sym_clamp(est->x[1], RC(EST_YAW_MAX));
        est->x[3] = sym_clamp(est->x[3], RC(EST_B_MAX / EST_S_B));
        /* with every wheel locked (spinning) the slips leave the tire
         * model's range and the lateral force no longer tells the slip
         * angle: beta is dead reckoning too, flagged; and a tire model
         * that does not fit the car (misfit) does not give a sideslip to
         * stand behind either, nor does a steering angle beyond the rack's
         * travel (no ay update: dead reckoning as well) */
        if (ay_ok && yaw_ok && !dead_reck && !est->misfit && ((flags & GRIP_EST_F_STEER_LIMIT) == 0u)) {
            valid |= GRIP_EST_V_BETA | GRIP_EST_V_AXLE;
        }
        if (!(valid & GRIP_EST_V_BETA)) {
            valid &= ~(GRIP_EST_V_WHEEL(0) | GRIP_EST_V_WHEEL(1) | GRIP_EST_V_WHEEL(2) | GRIP_EST_V_WHEEL(3));
        }
        if (excited) {
            flags |= GRIP_EST_F_EXCITED;
        }
        /* vx at the output's time too, like vy and r: its prediction's
         * rate at the updated state (a spin slows it by ~6 m/s^2) */
        out->vx = r_add(vx, r_mul(c->latency, vx_rate(est, ax, est->x[1], est->x[0], g_x)));
        lateral_outputs(est, out, vx, cd, sd, r_sub(r_add(ay_ok ? ay : ay_m, g_y), r_mul(est->x[1], vx)), racc,
                        r_sub(est->x[0], r_add(vy, dvy)));
    }
    mu = est->x[2];

    /* ---- outputs ---- */
    if (!active) {
        out->vx = vx;
        out->yaw_rate = yaw;   /* vy, beta stay 0; active: vx above, lateral_outputs the rest */
    }
    if (yaw_ok) {
        valid |= GRIP_EST_V_YAW;
    }
    out->delta = delta;
    out->mu = mu;
    out->yaw_rate_bias = r_mul(RC(EST_S_B), est->x[3]);
    {
        grip_real_t sig = r_mul(r_sqrt(est->p[2][2]), RC(EST_S_MU));
        out->mu_conf = r_clamp(r_div(r_sub(RC(EST_CONF_S0), sig), RC(0.1)), R_ZERO, R_ONE);
        if (est->misfit) {
            /* the tire model does not explain the measurements: whatever mu
             * the filter found, it is not the road's */
            flags |= GRIP_EST_F_MODEL_MISFIT;
            out->mu_conf = r_min(out->mu_conf, RC(EST_CONF_MISFIT));
        } else if (est->sat_cap) {
            /* the saturation share on its way to the misfit level: no
             * confidence in mu while that evidence builds up (the check is
             * low-passed over 2 s and declares the misfit late) */
            out->mu_conf = r_min(out->mu_conf, RC(EST_CONF_MISFIT));
        } else {
            /* model consistent */
        }
        if (out->mu_conf >= RC(0.5)) {
            valid |= GRIP_EST_V_MU;
        }
    }
    /* yaw-rate reference: steady-state bicycle (eq. 2.14 with 2.17), limited
     * to what the road can carry: |r| <= mu mu0 g / vx */
    if ((valid & GRIP_EST_V_VX) && steer_ok && vx >= RC(EST_V_ON)) {
        grip_real_t l = r_add(c->lf, c->lr);
        grip_real_t av2 = r_mul(RC(0.01), r_mul(r_mul(est->k_us, vx), vx));
        grip_real_t den = r_max(r_mul(l, r_add(R_ONE, av2)), r_mul(RC(0.1), l));
        grip_real_t rr = r_div(r_mul(vx, delta), den);
        grip_real_t lim = r_div(r_mul(r_mul(mu, r_min(est->mu0[0], est->mu0[1])), RC(EST_G)), vx);
        out->yaw_rate_ref = sym_clamp(rr, lim);
        valid |= GRIP_EST_V_YAW_REF;
        if (yaw_ok) {
            grip_real_t d, thr, sgn;
            out->yaw_error = r_sub(yaw, out->yaw_rate_ref);
            sgn = (r_abs(out->yaw_rate_ref) > RC(0.01)) ? r_sign(out->yaw_rate_ref) : r_sign(yaw);
            d = r_mul(sgn, r_sub(out->yaw_rate_ref, yaw));
            thr = r_add(RC(0.03), r_mul(RC(0.1), r_abs(out->yaw_rate_ref)));
            out->steer_char = (d > thr) ? 1 : ((r_neg(d) > thr) ? -1 : 0); /* grip-deviation: MISRA-10.6 tool: ?: of constants is not composite (8.10.3) */
            valid |= GRIP_EST_V_STEER;
        }
    }
    if (active) {
        out->fy_margin_front = r_sub(r_mul(r_mul(mu, est->mu0[0]), fz_sum_f), r_abs(out->fy_axle[0]));
        if (valid & GRIP_EST_V_BETA) {
            valid |= GRIP_EST_V_MARGIN;
        }
    }
    out->valid = valid;
    out->flags = flags;
    return GRIP_OK;
}

grip_status_t grip_est_stability_factor(const grip_est_t *est, grip_real_t *a_x100)
{
    if (est == NULL || a_x100 == NULL) {
        return GRIP_ERR_NULL;
    }
    if (est->magic != EST_MAGIC) {
        return GRIP_ERR_STATE;
    }
    *a_x100 = est->k_us;
    return GRIP_OK;
}
