/*
 * est_init.c - the estimator's configuration (defaults and checks), init
 * (the axle constants derived once from the tire models at static load:
 * cornering and slip stiffness, peak friction and its load sensitivity,
 * relaxation length, the lateral force shape for mu's secant, the
 * stability factor), reset, and the stability factor's getter.
 */
#include <stddef.h>

#include "est_internal.h"
#include "../core/check_internal.h"

/* the nearest whole number (step counts from times) */
static int32_t r_to_int(grip_real_t a)
{
#if GRIP_ARITH_FIXED
    return (a >= 0) ? (int32_t)((a + 32768) >> 16) : -(int32_t)((32768 - a) >> 16);
#else
    return (int32_t)((a >= 0.0f) ? (a + 0.5f) : (a - 0.5f));
#endif
}

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
    cfg->pitch_gradient = R_ZERO;
    cfg->rate_hz = 100u;
    cfg->speed_ref_mu = 0u;
    cfg->rear_steer = 0u;
    cfg->bank_est = 0u;
    cfg->stiff_est = 0u;
    cfg->kx_est = 0u;
    cfg->roll_est = 0u;
    cfg->drive_front = RC(-1.0);
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
    cfg->tire_tol = RC(0.3);
    cfg->kin_acc_sd = RC(0.10);
    cfg->beta_sd_max = RC(0.0175);
    cfg->vx_sd_max = R_ZERO;
    cfg->fy_sd_max = R_ZERO;
    cfg->tire[0].kind = GRIP_EST_TIRE_MF;
    cfg->tire[0].model.mf = tire;
    cfg->tire[1].kind = GRIP_EST_TIRE_MF;
    cfg->tire[1].model.mf = tire;
    return GRIP_OK;
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

/* The configuration's ranges (grip_est.h) in field order: the first value
 * outside its range named in *d (d may be NULL). */
static grip_status_t check_config(const grip_est_config_t *c, grip_check_detail_t *d)
{
    static const char *const TIRE = "tire";
    const check_range_t r[] = {
        { "mass", c->mass, RCL(1.0), RCL(60000.0), "in [1, 60000] kg" },
        { "iz", c->iz, RCL(1.0), RCL(200000.0), "in [1, 200000] kg m^2" },
        { "lf", c->lf, RC(0.05), RC(10.0), "in [0.05, 10] m" },
        { "lr", c->lr, RC(0.05), RC(10.0), "in [0.05, 10] m" },
        { "track_f", c->track_f, RC(0.2), RC(4.0), "in [0.2, 4] m" },
        { "track_r", c->track_r, RC(0.2), RC(4.0), "in [0.2, 4] m" },
        { "h_cg", c->h_cg, R_ZERO, RC(3.0), "in [0, 3] m" },
        { "steer_ratio", c->steer_ratio, R_ONE, RC(100.0), "in [1, 100]" },
        { "wheel_radius", c->wheel_radius, RC(0.05), RC(2.0), "in [0.05, 2] m" },
        { "roll_split_front", c->roll_split_front, R_ZERO, R_ONE, "in [0, 1]" },
        { "roll_gradient", c->roll_gradient, R_ZERO, RC(0.05), "in [0, 0.05] rad/(m/s^2)" },
        { "pitch_gradient", c->pitch_gradient, R_ZERO, RC(0.05), "in [0, 0.05] rad/(m/s^2)" },
    };
    const check_range_t r2[] = {
        { "drive_front", c->drive_front, RC(-1.0), R_ONE, "in [0, 1], or in [-1, 0) for not known" },
        { "cla", c->cla, R_ZERO, RC(20.0), "in [0, 20] m^2" },
        { "aero_front", c->aero_front, R_ZERO, R_ONE, "in [0, 1]" },
        { "air_density", c->air_density, RC(0.5), RC(1.5), "in [0.5, 1.5] kg/m^3" },
        { "cda", c->cda, R_ZERO, RC(5.0), "in [0, 5] m^2" },
        { "crr", c->crr, R_ZERO, RC(0.05), "in [0, 0.05]" },
        { "tan_bank", c->tan_bank, RC(-0.5), RC(0.5), "in [-0.5, 0.5]" },
        { "tan_grade", c->tan_grade, RC(-0.5), RC(0.5), "in [-0.5, 0.5]" },
        { "latency", c->latency, R_ZERO, RC(0.1), "in [0, 0.1] s" },
        { "steer_lag", c->steer_lag, R_ZERO, RC(0.5), "in [0, 0.5] s" },
        { "steer_latency", c->steer_latency, R_ZERO, RC(0.1), "in [0, 0.1] s" },
        { "tire_tol", c->tire_tol, R_ZERO, RC(2.0), "in [0, 2]" },
        { "kin_acc_sd", c->kin_acc_sd, RC(0.01), RC(2.0), "in [0.01, 2] m/s^2" },
        { "beta_sd_max", c->beta_sd_max, RC(0.001), RC(0.5), "in [0.001, 0.5] rad" },
        { "vx_sd_max", c->vx_sd_max, R_ZERO, RC(50.0), "in [0, 50] m/s (0: no limit)" },
        { "fy_sd_max", c->fy_sd_max, R_ZERO, RCL(1.0e6), "in [0, 1e6] N (0: no limit)" },
    };
    /* the switches: 0 or 1 */
    const struct {
        const char *name;
        uint32_t v;
    } flags[] = {
        { "speed_ref_mu", c->speed_ref_mu }, { "rear_steer", c->rear_steer },
        { "bank_est", c->bank_est },         { "stiff_est", c->stiff_est },
        { "kx_est", c->kx_est },             { "roll_est", c->roll_est },
    };
    size_t k;
    int a;
    if (!check_ranges(r, sizeof r / sizeof r[0], d)) {
        return GRIP_ERR_PARAM;
    }
    if (c->rate_hz < 50u || c->rate_hz > 2000u) {
        (void)check_fail(d, "", -1, "rate_hz", "in 50..2000 Hz");
        return GRIP_ERR_PARAM;
    }
    for (k = 0; k < sizeof flags / sizeof flags[0]; ++k) {
        if (flags[k].v > 1u) {
            (void)check_fail(d, "", -1, flags[k].name, "0 or 1");
            return GRIP_ERR_PARAM;
        }
    }
    if (!check_ranges(r2, sizeof r2 / sizeof r2[0], d)) {
        return GRIP_ERR_PARAM;
    }
    for (a = 0; a < 2; ++a) {
        if (c->tire[a].kind != GRIP_EST_TIRE_MF) {
            (void)check_fail(d, TIRE, a, "kind", "GRIP_EST_TIRE_MF");
            return GRIP_ERR_PARAM;
        }
        if (c->tire[a].model.mf == NULL) {
            (void)check_fail(d, TIRE, a, "model.mf", "a parameter set, not NULL");
            return GRIP_ERR_PARAM;
        }
        if (grip_mf_check_params_detail(c->tire[a].model.mf, d) != GRIP_OK) {
            check_within(d, TIRE, a);
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
    est->p_mu_own = RC(EST_P0_MU);
    est->mu_src = 0;
    est->p_mu_start = RC(EST_P0_MU);
    est->p_mu_pred = RC(EST_P0_MU);
    est->p[3][3] = RC(EST_P0_B);
    est->t_prev = 0;
    for (i = 0; i < 6; ++i) {
        est->hold[i] = R_ZERO;
        est->age[i] = 1000000;
    }
    est->no_wheel_steps = 1000000;
    est->dr_steps = 0;
    est->braking = 0;
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
    est->road_gy = R_ZERO;
    est->road_g0 = R_ZERO;
    est->road_r = R_ZERO;
    est->road_dr = R_ZERO;
    est->vy_k = R_ZERO;
    est->sd_k = RC(EST_SD_CAP);
    est->sd_kmu = RC(EST_SD_CAP);
    est->sd_vx = RC(EST_SD_CAP);
    /* the learned stiffnesses stay (est_stiffness.c, est_stiffness_long.c);
     * their regressions restart */
    est->stf_z = R_ZERO;
    est->stf_h[0] = R_ZERO;
    est->stf_h[1] = R_ZERO;
    est->stf_yaw = R_ZERO;
    est->stf_n = 0;
    est->kx_z = R_ZERO;
    est->kx_h = R_ZERO;
    est->kx_dv = R_ZERO;
    est->kx_n = 0;
    /* the roll gradient stays (est_roll.c); its band-pass restarts */
    est->rg_f[0] = R_ZERO;
    est->rg_f[1] = R_ZERO;
    est->rg_m[0] = R_ZERO;
    est->rg_m[1] = R_ZERO;
    est->rg_vy = R_ZERO;
    est->rg_n = 0;
    est->rg_pos = 1000000;
    est->rg_neg = 1000000;
    return GRIP_OK;
}

grip_status_t grip_est_init(grip_est_t *est, const grip_est_config_t *cfg)
{
    return grip_est_init_detail(est, cfg, NULL);
}

grip_status_t grip_est_init_detail(grip_est_t *est, const grip_est_config_t *cfg, grip_check_detail_t *detail)
{
    static const char *const AT_LOAD = "evaluates at the axle's static load (pure slip, 20 m/s)";
    grip_status_t st;
    grip_real_t l, m_g;
    int a, k;
    check_clear(detail);
    if (est == NULL || cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    est->magic = 0;
    st = check_config(cfg, detail);
    if (st != GRIP_OK) {
        return st;
    }
    est->cfg = *cfg;
    /* Prepared once for the step's evaluations (bit-identical to
     * grip_mf_eval). A set that does not prepare (a use-mode bit, which
     * check_config lets through) leaves the prepared set cleared, and its
     * evaluations return GRIP_ERR_PARAM as grip_mf_eval's would: the
     * static-load evaluations below refuse it. */
    for (a = 0; a < 2; ++a) {
        (void)grip_mf_prepare(cfg->tire[a].model.mf, cfg->tire[a].model.mf->options, &est->tire_prep[a]);
    }
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
        grip_real_t best, best2, alpha2, mux_pk;   /* mux_pk: the braking peak |Fx| / Fz */
        in.kappa = R_ZERO;
        in.alpha = RC(0.01);
        in.gamma = R_ZERO;
        in.fz = est->fz_static[a];
        in.p = R_ZERO;
        in.vx = RC(20.0);
        if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
            (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
            return GRIP_ERR_PARAM;
        }
        in.alpha = RC(-0.01);
        if (tire_eval(&cfg->tire[a], &in, &o2) < 0) {
            (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
            return GRIP_ERR_PARAM;
        }
        est->c_alpha[a] = r_div_keep(r_sub(o2.fy, o1.fy), RC(0.02));
        in.alpha = R_ZERO;
        in.kappa = RC(0.01);
        if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
            (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
            return GRIP_ERR_PARAM;
        }
        in.kappa = RC(-0.01);
        if (tire_eval(&cfg->tire[a], &in, &o2) < 0) {
            (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
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
            (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
            return GRIP_ERR_PARAM;
        }
        est->mu0[a] = best;
        est->mu0_k[a] = r_mul(RC(2.0), r_sub(best2, best));
        if (est->c_alpha[a] <= R_ZERO) {
            (void)check_fail(detail, "tire", a, "model.mf", "a cornering stiffness > 0 at the axle's static load");
            return GRIP_ERR_PARAM;
        }
        if (est->c_kappa[a] <= R_ZERO) {
            (void)check_fail(detail, "tire", a, "model.mf", "a slip stiffness > 0 at the axle's static load");
            return GRIP_ERR_PARAM;
        }
        if (best < RC(0.05)) {
            (void)check_fail(detail, "tire", a, "model.mf", "a peak lateral friction >= 0.05 at the axle's static load");
            return GRIP_ERR_PARAM;
        }
        if (mux_pk < RC(0.05)) {
            (void)check_fail(detail, "tire", a, "model.mf", "a peak braking friction >= 0.05 at the axle's static load");
            return GRIP_ERR_PARAM;
        }
        est->mu_xy[a] = r_div(best, mux_pk);
        est->sig_a[a] = relax_length(&cfg->tire[a], est->c_alpha[a], est->fz_static[a]);
        /* the lateral force's shape over [0, alpha_pk] for mu's secant */
        est->inv_apk[a] = r_div(R_ONE, est->alpha_pk[a]);
        in.kappa = R_ZERO;
        in.fz = est->fz_static[a];
        for (k = 0; k <= GRIP_EST_SHAPE_N; ++k) {
            in.alpha = r_mul(est->alpha_pk[a], r_div(r_from_int(k), r_from_int(GRIP_EST_SHAPE_N)));
            if (tire_eval(&cfg->tire[a], &in, &o1) < 0) {
                (void)check_fail(detail, "tire", a, "model.mf", AT_LOAD);
                return GRIP_ERR_PARAM;
            }
            est->fy_shape[a][k] = r_abs(r_div(o1.fy, in.fz));
        }
    }
    est->rate = r_from_int((int32_t)cfg->rate_hz);
    est->ay_fac = r_div(R_ONE, r_add(R_ONE, r_mul(RC(EST_G), cfg->roll_gradient))); /* the roll gradient in use: est_roll.c */
    est->ax_fac = r_div(R_ONE, r_add(R_ONE, r_mul(RC(EST_G), cfg->pitch_gradient)));
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
    /* the learned cornering stiffness: the tire file's, with the prior's
     * covariance; the model error counted as correlated over STF_TC */
    est->stf_k[0] = R_ONE;
    est->stf_k[1] = R_ONE;
    est_stability_factor(est);
    est->k_us0 = est->k_us;
    est->stf_x[0] = RC(1.0 / EST_STF_S_U);
    est->stf_x[1] = RC(1.0 / EST_STF_S_U);
    est->stf_p[0] = RC(EST_STF_P_MAX);
    est->stf_p[1] = R_ZERO;
    est->stf_p[2] = est->stf_p[0];
    est->stf_updates = 0u;
    est->stf_q = r_div(RC(EST_STF_Q / (EST_STF_S_U * EST_STF_S_U)), est->rate);
    est->stf_a = r_min(r_div(R_ONE, r_mul(RC(EST_STF_T), est->rate)), R_ONE);
    est->stf_r = r_mul(RC((EST_STF_R / EST_STF_S_Y) * (EST_STF_R / EST_STF_S_Y) * EST_STF_TC), est->rate);
    est->stf_n_min = r_to_int(r_mul(RC(3.0 * EST_STF_T), est->rate));
    /* the learned longitudinal slip stiffness: the tire file's, no radius
     * mismatch, the priors' covariance (est_stiffness_long.c) */
    est->kx_x[0] = RC(1.0 / EST_KX_S_U);
    est->kx_x[1] = R_ZERO;
    est->kx_p[0] = RC(EST_KX_P_MAX);
    est->kx_p[1] = R_ZERO;
    est->kx_p[2] = RC(EST_KX_PD_MAX);
    est->kx_updates = 0u;
    est_kx_apply(est); /* kx 1, c_kappa_kx = c_kappa, and vx's deviation: the wheels'
                        * mean slip per m/s^2 of ax, slip_acc = m / (4 c_kappa) */
    est->kx_q = r_div(RC(EST_KX_Q / (EST_KX_S_U * EST_KX_S_U)), est->rate);
    est->kx_qd = r_div(RC(EST_KX_QD / (EST_KX_S_Y * EST_KX_S_Y)), est->rate);
    est->kx_a = r_min(r_div(R_ONE, r_mul(RC(EST_KX_T), est->rate)), R_ONE);
    est->kx_r = r_mul(RC((EST_KX_R / EST_KX_S_Y) * (EST_KX_R / EST_KX_S_Y) * EST_KX_TC), est->rate);
    est->kx_n_min = r_to_int(r_mul(RC(3.0 * EST_KX_T), est->rate));
    /* the roll gradient: the configured one, with the prior's variance
     * (est_roll.c); ay_fac as without it until an update */
    est->rg_k = cfg->roll_gradient;
    est->rg_x = r_mul(cfg->roll_gradient, RC(1.0 / EST_RG_S_U));
    est->rg_p = RC(EST_RG_P_MAX);
    est->rg_updates = 0u;
    est->rg_q = r_div(RC(EST_RG_Q / (EST_RG_S_U * EST_RG_S_U)), est->rate);
    est->rg_r = r_mul(RC(EST_RG_R * EST_RG_R * EST_RG_TC), est->rate);
    est->rg_a1 = r_min(r_div(R_ONE, r_mul(RC(EST_RG_T), est->rate)), R_ONE);
    est->rg_a2 = r_min(r_div(R_ONE, r_mul(RC(EST_RG_TH), est->rate)), R_ONE);
    est->rg_n_min = r_to_int(r_mul(RC(3.0 * EST_RG_T), est->rate));
    est->rg_n_alt = r_to_int(r_mul(RC(EST_RG_T_ALT), est->rate));
    est->magic = EST_MAGIC;
    return grip_est_reset(est);
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
