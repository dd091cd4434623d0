/*
 * monitor.c - ESC sensor-plausibility monitor (grip_monitor.h), written once
 * for both arithmetics. Float64 reference: tools/grip_tools/reference/monitor.py
 * (the same steps in the same order, the same constants); method and the
 * measurement behind every constant: docs/faults.md.
 *
 * Per step: input status, spike follower, noise -> wheel-speed median ->
 * wheel check -> yaw vs rear wheels -> consensus yaw rate, steadiness ->
 * ay vs r vx -> ax vs d(v)/dt -> steering vs bicycle model -> vehicle
 * speed -> frozen -> debounce, latch, heal, drop.
 * Every loop runs GRIP_MON_N (9) or 4 times.
 */
#include <stddef.h>
#include "grip/grip_monitor.h"
#include "arith.h"
#include "../core/check_internal.h"

#define MON_MAGIC 0x4d4f4e31u   /* "MON1" */
#define MON_BIG 1000000

#define IN_STEER GRIP_IN_STEER_ANGLE
#define IN_YAW GRIP_IN_YAW_RATE
#define IN_AX GRIP_IN_AX
#define IN_AY GRIP_IN_AY
#define IN_VS GRIP_IN_VEHICLE_SPEED

/* ---- constants (reference/monitor.py; docs/faults.md) ---- */
#define MON_WS_MAX 120.0
#define MON_YAW_MAX 2.5
#define MON_ACC_MAX 15.0
#define MON_DELTA_MAX 0.7
#define MON_G 9.80665
/*                                 wheel x4                      steer  yaw    ax     ay     vspeed */
static const grip_real_t RATE_[GRIP_MON_N] = { RC(500.0), RC(500.0), RC(500.0), RC(500.0), RC(25.0), RC(6.0),
                                               RC(300.0), RC(300.0), RC(30.0) };
static const grip_real_t JUMP_ABS_[GRIP_MON_N] = { RC(0.3), RC(0.3), RC(0.3), RC(0.3), RC(0.05), RC(0.03),
                                                   RC(0.5), RC(0.5), RC(0.3) };
static const grip_real_t NOISE_MAX_[GRIP_MON_N] = { RC(0.8), RC(0.8), RC(0.8), RC(0.8), RC(0.06), RC(0.06),
                                                    RC(1.0), RC(1.0), RC(0.6) };
static const int32_t FROZEN_MS_[GRIP_MON_N] = { 100, 100, 100, 100, 300, 100, 100, 100, 100 };
static const grip_real_t FROZEN_MOVE_[GRIP_MON_N] = { RC(0.5), RC(0.5), RC(0.5), RC(0.5), RC(0.05), RC(0.05),
                                                      RC(0.8), RC(0.8), RC(0.5) };
#define SPIKE_INC 10
#define SPIKE_LATCH 25
#define NOISE_TAU 0.1
#define V_MIN 5.0
#define WH_ABS 0.6
#define WH_REL 0.03
#define WH_AX_MAX 1.5
#define WH_SPIN_AY 2.0
#define CALM_ABS 0.5
#define CALM_REL 0.03
#define YAW_ABS 0.04
#define YAW_REL 0.10
#define YAW_AX_MAX 1.0
#define AY_ABS 0.5
#define AY_REL 0.10
#define AY_DR 0.30
#define AY_DR_CAP 20.0
#define AY_DR_DEAD 0.08
#define AX_TAU 0.1
#define AX_ABS 0.8
#define AX_REL 0.15
#define ST_TAU 0.15
#define ST_ABS 0.04
#define ST_REL 0.20
#define ST_A_MAX 2.0
#define VS_ABS 1.0
#define VS_REL 0.05
#define DR_TAU 0.1
#define DR_MAX 0.15
#define DAX_MAX 3.0
#define BETA_UNST 0.1
#define BETA_CALM 0.025
#define UNST_MS 1000
#define DIFF_MAX 10.0
#define STEADY_MS 500
#define DEB_MS 100
#define HEAL_MS 1000
#define FOLLOW_LOST_MS 100
#define DEGR_N 3
#define DEGR_MS 500

/* ------------------------------------------------------------------ */

static int32_t steps_of(int32_t ms, uint32_t rate_hz)
{
    int32_t n = (int32_t)(((uint32_t)ms * rate_hz + 500u) / 1000u);
    return (n < 1) ? 1 : n;
}

static int in_range(grip_real_t v, grip_real_t lo, grip_real_t hi)
{
    return r_is_finite(v) && v >= lo && v <= hi;
}

/* dt / tau = 1 / (tau rate), at most 1 */
static grip_real_t lp_factor(grip_real_t tau, grip_real_t rate)
{
    return r_min(r_div(R_ONE, r_mul(tau, rate)), R_ONE);
}

static int32_t inc_sat(int32_t n)
{
    return (n < MON_BIG) ? n + 1 : n;
}

/* ------------------------------------------------------------------ */

grip_status_t grip_monitor_config_default(grip_monitor_config_t *cfg)
{
    if (cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    cfg->lf = RC(1.10);
    cfg->lr = RC(1.60);
    cfg->track_f = RC(1.55);
    cfg->track_r = RC(1.53);
    cfg->steer_ratio = RC(15.5);
    cfg->stab_factor_x100 = RC(0.0367);   /* grip_est_stability_factor of grip_est_config_default, 3 figures (test_monitor.c) */
    cfg->roll_gradient = RC(0.0088);
    cfg->driven = 1u;
    cfg->rate_hz = 100u;
    return GRIP_OK;
}

static grip_status_t check_config(const grip_monitor_config_t *c, grip_check_detail_t *d);

grip_status_t grip_monitor_config_from_est(grip_monitor_config_t *cfg, const grip_est_t *est, uint32_t driven)
{
    grip_monitor_config_t c;
    grip_status_t s;
    if (cfg == NULL || est == NULL) {
        return GRIP_ERR_NULL;
    }
    s = grip_est_stability_factor(est, &c.stab_factor_x100);
    if (s != GRIP_OK) {
        return s;
    }
    c.lf = est->cfg.lf;
    c.lr = est->cfg.lr;
    c.track_f = est->cfg.track_f;
    c.track_r = est->cfg.track_r;
    c.steer_ratio = est->cfg.steer_ratio;
    c.roll_gradient = est->cfg.roll_gradient;
    c.driven = driven;
    c.rate_hz = est->cfg.rate_hz;
    s = check_config(&c, NULL);
    if (s == GRIP_OK) {
        *cfg = c;
    }
    return s;
}

/* A configuration value, its range and the rule's text. */
typedef struct {
    const char *name;
    grip_real_t v;
    grip_real_t lo;
    grip_real_t hi;
    const char *rule;
} mon_range_t;

static grip_status_t check_config(const grip_monitor_config_t *c, grip_check_detail_t *d)
{
    const mon_range_t r[] = {
        { "lf", c->lf, RC(0.05), RC(10.0), "in [0.05, 10] m" },
        { "lr", c->lr, RC(0.05), RC(10.0), "in [0.05, 10] m" },
        { "track_f", c->track_f, RC(0.2), RC(4.0), "in [0.2, 4] m" },
        { "track_r", c->track_r, RC(0.2), RC(4.0), "in [0.2, 4] m" },
        { "steer_ratio", c->steer_ratio, R_ONE, RC(100.0), "in [1, 100]" },
        { "stab_factor_x100", c->stab_factor_x100, RC(-1.0), R_ONE, "in [-1, 1] (100 s^2/m^2)" },
        { "roll_gradient", c->roll_gradient, R_ZERO, RC(0.05), "in [0, 0.05] rad/(m/s^2)" },
    };
    size_t i;
    for (i = 0; i < sizeof r / sizeof r[0]; ++i) {
        if (!in_range(r[i].v, r[i].lo, r[i].hi)) {
            (void)check_fail(d, "", -1, r[i].name, r[i].rule);
            return GRIP_ERR_PARAM;
        }
    }
    if (c->driven < 1u || c->driven > 3u) {
        (void)check_fail(d, "", -1, "driven", "1 (front), 2 (rear) or 3 (both axles)");
        return GRIP_ERR_PARAM;
    }
    if (c->rate_hz < 50u || c->rate_hz > 2000u) {
        (void)check_fail(d, "", -1, "rate_hz", "in 50..2000 Hz");
        return GRIP_ERR_PARAM;
    }
    return GRIP_OK;
}

grip_status_t grip_monitor_reset(grip_monitor_t *mon)
{
    int s;
    if (mon == NULL) {
        return GRIP_ERR_NULL;
    }
    if (mon->magic != MON_MAGIC) {
        return GRIP_ERR_STATE;
    }
    for (s = 0; s < GRIP_MON_N; ++s) {
        mon->fol[s] = R_ZERO;
        mon->x1[s] = R_ZERO;
        mon->x2[s] = R_ZERO;
        mon->noise[s] = R_ZERO;
        mon->frz_val[s] = R_ZERO;
        mon->frz_lo[s] = R_ZERO;
        mon->frz_hi[s] = R_ZERO;
        mon->lost[s] = 0;
        mon->spk[s] = 0;
        mon->frz[s] = 0;
        mon->deb[s] = 0;
        mon->heal[s] = 0;
        mon->have[s] = 0u;
        mon->hist[s] = 0u;
        mon->latch[s] = 0u;
        mon->seen[s] = 0u;
    }
    mon->ax_f = R_ZERO;
    mon->dv_f = R_ZERO;
    mon->v_prev = R_ZERO;
    mon->ax_prev = R_ZERO;
    mon->dax_f = R_ZERO;
    mon->r_lin_f = R_ZERO;
    mon->r_prev = R_ZERO;
    mon->dr_f = R_ZERO;
    mon->dv_prev = R_ZERO;
    mon->ddv_f = R_ZERO;
    mon->ax_steady = 0;
    mon->r_steady = 0;
    mon->unst = 0;
    mon->dv_steady = 0;
    mon->degr = 0;
    mon->v_have = 0u;
    mon->r_have = 0u;
    mon->init_f = 0u;
    mon->pad_ = 0u;
    return GRIP_OK;
}

grip_status_t grip_monitor_init(grip_monitor_t *mon, const grip_monitor_config_t *cfg)
{
    return grip_monitor_init_detail(mon, cfg, NULL);
}

grip_status_t grip_monitor_init_detail(grip_monitor_t *mon, const grip_monitor_config_t *cfg,
                                       grip_check_detail_t *detail)
{
    int s;
    check_clear(detail);
    if (mon == NULL || cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    mon->magic = 0u;
    if (check_config(cfg, detail) != GRIP_OK) {
        return GRIP_ERR_PARAM;
    }
    mon->cfg = *cfg;
    mon->rate = r_from_int((int32_t)cfg->rate_hz);
    mon->ay_fac = r_div(R_ONE, r_add(R_ONE, r_mul(RC(MON_G), cfg->roll_gradient)));
    mon->a_noise = lp_factor(RC(NOISE_TAU), mon->rate);
    mon->a_ax = lp_factor(RC(AX_TAU), mon->rate);
    mon->a_st = lp_factor(RC(ST_TAU), mon->rate);
    mon->a_dr = lp_factor(RC(DR_TAU), mon->rate);
    for (s = 0; s < GRIP_MON_N; ++s) {
        mon->rate_step[s] = r_div(RATE_[s], mon->rate);
        mon->jump[s] = r_add(mon->rate_step[s], JUMP_ABS_[s]);
        mon->n_frozen[s] = steps_of(FROZEN_MS_[s], cfg->rate_hz);
        mon->lim[s] = (s < 4 || s == IN_VS) ? RC(MON_WS_MAX) : RC(MON_ACC_MAX);
    }
    mon->lim[IN_STEER] = r_mul(RC(2.0 * MON_DELTA_MAX), cfg->steer_ratio);
    mon->lim[IN_YAW] = RC(MON_YAW_MAX);
    mon->n_deb = steps_of(DEB_MS, cfg->rate_hz);
    mon->n_heal = steps_of(HEAL_MS, cfg->rate_hz);
    mon->n_lost = steps_of(FOLLOW_LOST_MS, cfg->rate_hz);
    mon->n_steady = steps_of(STEADY_MS, cfg->rate_hz);
    mon->n_unst = steps_of(UNST_MS, cfg->rate_hz);
    mon->n_degr = steps_of(DEGR_MS, cfg->rate_hz);
    mon->magic = MON_MAGIC;
    return grip_monitor_reset(mon);
}

/* ------------------------------------------------------------------ */
/* step pieces */

/* Input status, spike follower and noise filter of signal s; returns 1 if
 * the value is usable as a number this step. */
static int input_check(grip_monitor_t *m, int s, int valid, grip_real_t x, uint32_t *code)
{
    grip_real_t d;
    int ok = 0;
    if (!valid) {
        if (m->seen[s]) {
            *code |= GRIP_MON_C_LOST;
        }
    } else if (!(r_is_finite(x) && r_abs(x) <= m->lim[s])) {
        *code |= GRIP_MON_C_RANGE;
    } else {
        ok = 1;
        m->seen[s] = 1u;
    }
    if (!ok) {
        m->lost[s] = inc_sat(m->lost[s]);
        if (m->lost[s] >= m->n_lost) {
            m->have[s] = 0u;
            m->hist[s] = 0u;
        }
        return 0;
    }
    m->lost[s] = 0;
    if (!m->have[s]) {
        m->fol[s] = x;
        m->have[s] = 1u;
    }
    d = r_sub(x, m->fol[s]);
    if (r_abs(d) > m->jump[s]) {
        m->fol[s] = r_add(m->fol[s], r_clamp(d, r_neg(m->rate_step[s]), m->rate_step[s]));
        m->spk[s] = (m->spk[s] < MON_BIG - SPIKE_INC) ? m->spk[s] + SPIKE_INC : MON_BIG;
        *code |= GRIP_MON_C_SPIKE;
        return 0;
    }
    m->fol[s] = x;
    m->spk[s] = (m->spk[s] > 0) ? m->spk[s] - 1 : 0;
    if (m->hist[s] >= 2u) {
        grip_real_t dd = r_abs(r_add(r_sub(x, r_mul(RC(2.0), m->x1[s])), m->x2[s]));
        m->noise[s] = r_add(m->noise[s], r_mul(m->a_noise, r_sub(dd, m->noise[s])));
    } else {
        m->noise[s] = R_ZERO;
    }
    m->x2[s] = m->x1[s];
    m->x1[s] = x;
    if (m->hist[s] < 2u) {
        m->hist[s] = (uint8_t)(m->hist[s] + 1u);
    }
    return 1;
}

/* |a| <= b: b = abs + rel |ref| */
static int exceeds(grip_real_t e, grip_real_t abs_, grip_real_t rel, grip_real_t ref)
{
    return r_abs(e) > r_add(abs_, r_mul(rel, r_abs(ref)));
}

/* the estimator's previous sideslip is valid, finite and beyond lim */
static int beta_beyond(const grip_est_output_t *est_prev, grip_real_t lim)
{
    return est_prev != NULL && (est_prev->valid & GRIP_EST_V_BETA) != 0u && r_is_finite(est_prev->beta) && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
           r_abs(est_prev->beta) > lim;
}

grip_status_t grip_monitor_step(grip_monitor_t *m, grip_input_sample_t *sample,
                                const grip_est_output_t *est_prev, grip_monitor_report_t *rep)
{
    const grip_monitor_config_t *c;
    grip_real_t x[GRIP_MON_N], vc[4], red[GRIP_MON_N], res[GRIP_MON_N];
    uint32_t code[GRIP_MON_N];
    int ok[GRIP_MON_N], use[GRIP_MON_N], sus[GRIP_MON_N], wh_chk[4];
    grip_real_t delta, cd, r_ws, yw[4], lo, hi, s1, v_ref, spread, vx, ax_m, ay_c, ay_u;
    grip_real_t r_w = R_ZERO, r_c = R_ZERO, rate, l, dl, r_lin, a_tot;
    int s, i, j, n_good, vw_ok, vx_ok, moving, calm, rw_ok, rc_ok, r_steady, wheel_sus;
    uint32_t faulty = 0u, dropped = 0u;
    int detected = 0, degr = 0;

    if (m == NULL || sample == NULL) {
        if (rep != NULL) {
            for (s = 0; s < GRIP_MON_N; ++s) {
                rep->code[s] = 0u;
                rep->resid[s] = R_ZERO;
            }
            rep->faulty = 0u;
            rep->dropped = 0u;
            rep->detected = 0;
            rep->degraded = GRIP_MON_DEGR_SUSPECT | GRIP_MON_DEGR_UNVERIFIED;
        }
        return GRIP_ERR_NULL;
    }
    if (m->magic != MON_MAGIC) {
        /* unusable monitor: pass nothing unchecked on */
        for (s = 0; s < GRIP_MON_N; ++s) {
            sample->valid[s] = 0u;
            sample->value[s] = R_ZERO;
            sample->fault[s] = (uint8_t)GRIP_SIG_FAULT;
            if (rep != NULL) {
                rep->code[s] = 0u;
                rep->resid[s] = R_ZERO;
            }
        }
        if (rep != NULL) {
            rep->faulty = ((uint32_t)1u << GRIP_MON_N) - 1u;
            rep->dropped = rep->faulty;
            rep->detected = 1;
            rep->degraded = GRIP_MON_DEGR_SUSPECT | GRIP_MON_DEGR_UNVERIFIED;
        }
        return GRIP_ERR_STATE;
    }
    c = &m->cfg;
    rate = m->rate;

    /* -- input, spike, noise -- */
    for (s = 0; s < GRIP_MON_N; ++s) {
        code[s] = 0u;
        sus[s] = 0;
        res[s] = R_ZERO;
        x[s] = sample->value[s];
        ok[s] = input_check(m, s, sample->valid[s] != 0u, x[s], &code[s]);
        if (!ok[s]) {
            x[s] = R_ZERO;     /* never used as a number (non-finite stays out) */
        }
    }
    for (s = 0; s < GRIP_MON_N; ++s) {
        use[s] = ok[s] && !m->latch[s];
    }

    /* -- derived quantities -- */
    delta = use[IN_STEER] ? r_clamp(r_div(x[IN_STEER], c->steer_ratio), RC(-MON_DELTA_MAX), RC(MON_DELTA_MAX))
                          : R_ZERO;
    cd = r_cos(delta);
    yw[0] = r_mul(RC(0.5), c->track_f);
    yw[1] = r_neg(yw[0]);
    yw[2] = r_mul(RC(0.5), c->track_r);
    yw[3] = r_neg(yw[2]);
    r_ws = use[IN_YAW] ? x[IN_YAW] : R_ZERO;
    n_good = 0;
    lo = RC(30000.0);
    hi = RC(-30000.0);
    s1 = R_ZERO;
    for (i = 0; i < 4; ++i) {
        vc[i] = R_ZERO;
        wh_chk[i] = 0;
        if (ok[i]) {
            vc[i] = r_add((i < 2) ? r_div(x[i], cd) : x[i], r_mul(r_ws, yw[i]));
        }
        if (use[i]) {
            ++n_good;
            lo = r_min(lo, vc[i]);
            hi = r_max(hi, vc[i]);
            s1 = r_add(s1, vc[i]);
        }
    }
    v_ref = R_ZERO;
    if (n_good == 4) {
        v_ref = r_mul(RC(0.5), r_sub(r_sub(s1, lo), hi));
    } else if (n_good == 3) {
        v_ref = r_sub(r_sub(s1, lo), hi);
    } else if (n_good == 2) {
        v_ref = r_mul(RC(0.5), s1);
    } /* grip-deviation: MISRA-15.7 fewer than two good wheels: no wheel reference (vw_ok is 0) */
    vw_ok = n_good >= 2; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    spread = vw_ok ? r_sub(hi, lo) : R_ZERO;
    vx = v_ref;
    vx_ok = vw_ok;
    if (!vw_ok && est_prev != NULL && (est_prev->valid & GRIP_EST_V_VX) != 0u && r_is_finite(est_prev->vx)) {
        vx = r_clamp(est_prev->vx, RC(-MON_WS_MAX), RC(MON_WS_MAX));
        vx_ok = 1;
    }
    moving = vx_ok && vx >= RC(V_MIN); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    ax_m = use[IN_AX] ? x[IN_AX] : R_ZERO;
    ay_c = ok[IN_AY] ? r_mul(m->ay_fac, x[IN_AY]) : R_ZERO;
    ay_u = use[IN_AY] ? ay_c : R_ZERO;

    /* steadiness of ax */
    if (ok[IN_AX]) {
        grip_real_t d = r_clamp(r_sub(x[IN_AX], m->ax_prev), RC(-DIFF_MAX), RC(DIFF_MAX));
        m->dax_f = r_add(m->dax_f, r_mul(m->a_ax, r_sub(r_mul(d, rate), m->dax_f)));
        m->ax_prev = x[IN_AX];
        m->ax_f = r_add(m->ax_f, r_mul(m->a_ax, r_sub(x[IN_AX], m->ax_f)));
    }
    m->ax_steady = (ok[IN_AX] && r_abs(m->dax_f) < RC(DAX_MAX)) ? inc_sat(m->ax_steady) : 0;

    /* -- wheels: each against the median of the other three -- */
    calm = n_good >= 3 && spread <= r_add(RC(CALM_ABS), r_mul(RC(CALM_REL), vx)); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    if (moving && r_abs(ax_m) < RC(WH_AX_MAX)) {
        for (i = 0; i < 4; ++i) {
            int mcount = 0;
            grip_real_t olo = RC(30000.0), ohi = RC(-30000.0), os = R_ZERO, e;
            if (!ok[i]) {
                continue;
            }
            for (j = 0; j < 4; ++j) {
                if (j != i && use[j]) {
                    ++mcount;
                    olo = r_min(olo, vc[j]);
                    ohi = r_max(ohi, vc[j]);
                    os = r_add(os, vc[j]);
                }
            }
            if (mcount < 3) {
                continue;
            }
            if (r_sub(ohi, olo) > r_add(RC(CALM_ABS), r_mul(RC(CALM_REL), vx))) {
                continue;       /* the others disagree: slip, not a sensor */
            }
            e = r_sub(vc[i], r_sub(r_sub(os, olo), ohi));
            wh_chk[i] = 1;
            res[i] = e;
            if (r_abs(e) > r_add(RC(WH_ABS), r_mul(RC(WH_REL), vx))) {
                /* a driven wheel faster than the others at high |ay| is the
                 * unloaded inner wheel spinning (open differential), not a
                 * sensor; the loaded outer wheel does not spin alone. Inner:
                 * the left wheels (0, 2) in a left turn (ay > 0) */
                int inner = (ay_u > R_ZERO) ? ((i % 2) == 0) : ((i % 2) == 1); /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
                int spin = e > R_ZERO && ((c->driven >> (uint32_t)(i / 2)) & 1u) != 0u && inner && /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
                           r_abs(ay_u) > RC(WH_SPIN_AY);
                if (!spin) {
                    sus[i] = 1;
                }
            }
        }
    }

    /* -- yaw rate against the rear-wheel difference -- */
    wheel_sus = sus[0] || sus[1] || sus[2] || sus[3]; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    /* trusted only without braking / driving and with the wheels agreeing */
    rw_ok = use[2] && use[3] && !wheel_sus && calm && r_abs(ax_m) < RC(YAW_AX_MAX); /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */
    if (rw_ok) {
        r_w = r_div(r_sub(x[3], x[2]), c->track_r);
    }
    if (moving && ok[IN_YAW] && rw_ok) {
        res[IN_YAW] = r_sub(x[IN_YAW], r_w);
        if (exceeds(res[IN_YAW], RC(YAW_ABS), RC(YAW_REL), r_w)) {
            sus[IN_YAW] = 1;
        }
    }
    rc_ok = 1;
    if (use[IN_YAW] && !sus[IN_YAW]) {
        r_c = x[IN_YAW];
    } else if (rw_ok) {
        r_c = r_w;
    } else {
        rc_ok = 0;
    }
    if (rc_ok && m->r_have) {
        grip_real_t d = r_clamp(r_sub(r_c, m->r_prev), RC(-DIFF_MAX), RC(DIFF_MAX));
        m->dr_f = r_add(m->dr_f, r_mul(m->a_dr, r_sub(r_mul(d, rate), m->dr_f)));
    }
    if (rc_ok) {
        m->r_prev = r_c;
        m->r_have = 1u;
    } else {
        m->r_have = 0u;
    }
    m->r_steady = (rc_ok && r_abs(m->dr_f) < RC(DR_MAX)) ? inc_sat(m->r_steady) : 0;
    r_steady = m->r_steady >= m->n_steady; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */

    /* unstable driving (the estimator sees a large sideslip or oversteer):
     * the sideslip rate, ay - r vx, and the bicycle model are then unbounded */
    if (beta_beyond(est_prev, RC(BETA_UNST)) ||
        (est_prev != NULL && (est_prev->valid & GRIP_EST_V_STEER) != 0u && est_prev->steer_char < 0)) {
        m->unst = m->n_unst;
    } else if (m->unst > 0 && !beta_beyond(est_prev, RC(BETA_CALM))) {
        /* the hold's time runs only once the sideslip is back near the
         * linear range: a car still drifting at 2 - 5 deg can swing into
         * the next oversteer, and the hold would lapse in between */
        m->unst -= 1;
    } /* grip-deviation: MISRA-15.7 no hold to start or count down */
    r_steady = r_steady && m->unst == 0; /* grip-deviation: MISRA-10.3 result 0/1 stored in an int flag */

    /* -- ay against r vx (r from the wheels when they give it); no
     * steadiness gate: the threshold widens with the yaw acceleration, as the
     * sideslip rate does in a transient -- */
    if (moving && ok[IN_AY] && rc_ok && m->unst == 0) {
        grip_real_t r_x = rw_ok ? r_w : r_c; /* grip-deviation: MISRA-10.3 tool: cppcheck 2.10 types ?: by its int condition */
        /* the widening counts only the yaw acceleration beyond AY_DR_DEAD
         * (the settling tail of a steering step kept it 0.7 - 1 m/s^2 wide
         * for 0.5 s: docs/faults.md) */
        grip_real_t wide = r_mul(RC(AY_DR),
                                 r_mul(vx, r_min(r_max(r_sub(r_abs(m->dr_f), RC(AY_DR_DEAD)), R_ZERO), RC(AY_DR_CAP))));
        res[IN_AY] = r_sub(ay_c, r_mul(r_x, vx));
        if (exceeds(res[IN_AY], r_add(RC(AY_ABS), wide), RC(AY_REL), ay_c)) {
            sus[IN_AY] = 1;
        }
    }

    /* -- ax against the derivative of the wheel median -- */
    if (vw_ok && m->v_have) {
        grip_real_t d = r_clamp(r_sub(v_ref, m->v_prev), RC(-DIFF_MAX), RC(DIFF_MAX));
        grip_real_t d2;
        m->dv_f = r_add(m->dv_f, r_mul(m->a_ax, r_sub(r_mul(d, rate), m->dv_f)));
        d2 = r_clamp(r_sub(m->dv_f, m->dv_prev), RC(-DIFF_MAX), RC(DIFF_MAX));
        m->ddv_f = r_add(m->ddv_f, r_mul(m->a_ax, r_sub(r_mul(d2, rate), m->ddv_f)));
        m->dv_prev = m->dv_f;
    }
    m->dv_steady = (vw_ok && m->v_have && r_abs(m->ddv_f) < RC(DAX_MAX)) ? inc_sat(m->dv_steady) : 0;
    m->v_prev = v_ref;
    m->v_have = vw_ok ? 1u : 0u;
    /* ax steady (a step fault of ax closes this) or the wheel acceleration
     * steady (closed at a real brake onset, open at an ax step); the yaw
     * rate need not be steady (ax - dv/dt = -r vy stays small) */
    if (moving && ok[IN_AX] && calm && m->unst == 0 &&
        (m->ax_steady >= m->n_steady || m->dv_steady >= m->n_steady)) {
        res[IN_AX] = r_sub(m->ax_f, m->dv_f);
        if (exceeds(res[IN_AX], RC(AX_ABS), RC(AX_REL), m->dv_f)) {
            sus[IN_AX] = 1;
        }
    }

    /* -- steering against the yaw rate (bicycle model, linear range) -- */
    l = r_add(c->lf, c->lr);
    dl = ok[IN_STEER] ? r_clamp(r_div(x[IN_STEER], c->steer_ratio), RC(-MON_DELTA_MAX), RC(MON_DELTA_MAX))
                      : R_ZERO;
    r_lin = R_ZERO;
    if (moving) {
        grip_real_t av2 = r_mul(RC(0.01), r_mul(r_mul(c->stab_factor_x100, vx), vx));
        r_lin = r_div(r_mul(vx, dl), r_mul(l, r_add(R_ONE, av2)));
    }
    if (!m->init_f) {
        m->r_lin_f = r_lin;
        m->init_f = 1u;
    }
    m->r_lin_f = r_add(m->r_lin_f, r_mul(m->a_st, r_sub(r_lin, m->r_lin_f)));
    a_tot = r_sqrt(r_add(r_sq(ax_m), r_sq(ay_u)));
    if (moving && ok[IN_STEER] && rc_ok && r_steady && a_tot < RC(ST_A_MAX)) {
        res[IN_STEER] = r_sub(m->r_lin_f, r_c);
        if (exceeds(res[IN_STEER], RC(ST_ABS), RC(ST_REL), r_c)) {
            sus[IN_STEER] = 1;
        }
    }

    /* -- vehicle speed against the wheels -- */
    if (ok[IN_VS] && n_good >= 2) {
        res[IN_VS] = r_sub(x[IN_VS], v_ref);
        if (exceeds(res[IN_VS], RC(VS_ABS), RC(VS_REL), v_ref)) {
            sus[IN_VS] = 1;
        }
    }

    /* -- frozen: bit-identical while the redundant signal moves -- */
    for (i = 0; i < 4; ++i) {
        red[i] = vx;
    }
    red[IN_STEER] = r_c;
    red[IN_YAW] = rw_ok ? r_w : r_div(ay_u, r_max(vx, RC(V_MIN)));
    red[IN_AX] = m->dv_f;
    red[IN_AY] = r_mul(rw_ok ? r_w : r_c, vx);
    red[IN_VS] = vx;
    for (s = 0; s < GRIP_MON_N; ++s) {
        if (!ok[s] || !moving || (s < 4 && x[s] == R_ZERO)) {
            m->frz[s] = 0;      /* (a locked wheel reads exactly 0) */
            continue;
        }
        if (m->frz[s] > 0 && x[s] == m->frz_val[s]) {
            m->frz[s] = inc_sat(m->frz[s]);
            m->frz_lo[s] = r_min(m->frz_lo[s], red[s]);
            m->frz_hi[s] = r_max(m->frz_hi[s], red[s]);
        } else {
            m->frz[s] = 1;
            m->frz_val[s] = x[s];
            m->frz_lo[s] = red[s];
            m->frz_hi[s] = red[s];
        }
        if (m->frz[s] >= m->n_frozen[s] && r_sub(m->frz_hi[s], m->frz_lo[s]) > FROZEN_MOVE_[s]) {
            code[s] |= GRIP_MON_C_FROZEN;
        }
    }

    /* -- noise, spike latch, debounce, latch, heal, drop -- */
    for (s = 0; s < GRIP_MON_N; ++s) {
        if (ok[s] && m->noise[s] > NOISE_MAX_[s] && (s >= 4 || wh_chk[s])) {
            code[s] |= GRIP_MON_C_NOISE;
        }
        if (m->spk[s] >= SPIKE_LATCH) {
            code[s] |= GRIP_MON_C_SPIKE;
        }
        if (sus[s]) {
            m->deb[s] = (m->deb[s] < m->n_deb) ? m->deb[s] + 1 : m->n_deb;
        } else if (m->deb[s] > 0) {
            m->deb[s] -= 1;
        } /* grip-deviation: MISRA-15.7 no suspicion and the debounce count already 0 */
        if (m->deb[s] >= m->n_deb) {
            code[s] |= GRIP_MON_C_PLAUS;
        }
        if ((code[s] & (GRIP_MON_C_NOISE | GRIP_MON_C_FROZEN | GRIP_MON_C_PLAUS)) != 0u ||
            m->spk[s] >= SPIKE_LATCH) {
            m->latch[s] = 1u;
            m->heal[s] = 0;
        } else if (m->latch[s] && (code[s] & GRIP_MON_C_SPIKE) == 0u && m->deb[s] == 0) {
            m->heal[s] += 1;
            if (m->heal[s] >= m->n_heal) {
                m->latch[s] = 0u;
                m->heal[s] = 0;
            }
        } /* grip-deviation: MISRA-15.7 not latched, or still suspicious: the heal count is kept */
        if (m->latch[s]) {
            faulty |= 1u << (uint32_t)s;
        }
        if (m->latch[s] || code[s] != 0u || m->deb[s] >= DEGR_N) {
            degr = 1;
        }
        if ((m->latch[s] || (code[s] & GRIP_MON_C_SPIKE) != 0u) && sample->valid[s] != 0u) {
            sample->valid[s] = 0u;
            sample->value[s] = R_ZERO;
            sample->fault[s] = (uint8_t)GRIP_SIG_FAULT;
            dropped |= 1u << (uint32_t)s;
        }
        if (code[s] != 0u) {
            detected = 1;
        }
    }
    if (faulty != 0u) {
        detected = 1;
    }
    /* degraded SUSPECT: a signal dropped, lost or latched, or a check
     * accumulating, now or within DEGR_MS; UNVERIFIED: the unstable-driving
     * hold keeps the ay, ax and steering checks off */
    if (degr) {
        m->degr = m->n_degr;
    } else if (m->degr > 0) {
        m->degr -= 1;
    } /* grip-deviation: MISRA-15.7 the degraded hold is already 0 */
    if (rep != NULL) {
        for (s = 0; s < GRIP_MON_N; ++s) {
            rep->code[s] = (uint8_t)code[s];
            rep->resid[s] = res[s];
        }
        rep->faulty = faulty;
        rep->dropped = dropped;
        rep->detected = detected;
        rep->degraded = 0u;
        if (m->degr > 0) {
            rep->degraded |= GRIP_MON_DEGR_SUSPECT;
        }
        if (m->unst > 0) {
            rep->degraded |= GRIP_MON_DEGR_UNVERIFIED;
        }
    }
    return GRIP_OK;
}

grip_status_t grip_monitor_gate(const grip_monitor_report_t *rep, uint32_t honour, grip_est_output_t *out)
{
    if (rep == NULL || out == NULL) {
        return GRIP_ERR_NULL;
    }
    if ((honour & ~(uint32_t)GRIP_MON_GATE_DEFAULT) != 0u) {
        return GRIP_ERR_PARAM;
    }
    if ((rep->degraded & honour) != 0u) {
        out->valid &= ~(uint32_t)GRIP_MON_GATE_CLEARS;
        out->flags |= GRIP_EST_F_INPUT_DEGRADED;
    }
    return GRIP_OK;
}
