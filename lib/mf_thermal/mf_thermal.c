/*
 * mf_thermal.c - temperature-dependent Magic Formula with a tire surface
 * temperature state (seed 000, chapter 4). Equations, formats and the time
 * step: include/grip/grip_mf_thermal.h and docs/mf89-thermal.md.
 *
 * Numerics: the Magic Formula runs on values normalized by fz0 (friction-like,
 * QS) and is scaled by the load to N (QL) at the end; q = F Vs is QL [W] and
 * the heating rate q / W a QL / QL ratio in K/s, so neither the power nor W
 * has to fit QS. Magnitudes sqrt(a^2 + b^2) use a scaled hypot, never a QL
 * square.
 */
#include <stddef.h>

#include "grip/grip_mf_thermal.h"
#include "arith.h"

#define THERMAL_MAGIC 0x4d465448u   /* "MFTH" */

/* D sin[C atan{B p - E (B p - atan(B p))}] */
static grip_real_t mf_sin(grip_real_t d, grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t p)
{
    grip_real_t bp = r_mul(b, p);
    grip_real_t arg = r_sub(bp, r_mul(e, r_sub(bp, r_atan(bp))));
    return r_mul(d, r_sin(r_mul(c, r_atan(arg))));
}

/* cos[C atan{B p - E (B p - atan(B p))}] */
static grip_real_t mf_cos(grip_real_t b, grip_real_t c, grip_real_t e, grip_real_t p)
{
    grip_real_t bp = r_mul(b, p);
    grip_real_t arg = r_sub(bp, r_mul(e, r_sub(bp, r_atan(bp))));
    return r_cos(r_mul(c, r_atan(arg)));
}

/* 1 + k (T - T0) >= 0.01 at both ends of [t_min, t_max] (it is linear in T) */
static int temp_factor_ok(grip_real_t k, const grip_mf_thermal_params *p)
{
    grip_real_t lo = r_add(R_ONE, r_mul(k, r_sub(p->t_min, p->t0)));
    grip_real_t hi = r_add(R_ONE, r_mul(k, r_sub(p->t_max, p->t0)));
    return (lo >= RC(0.01)) && (hi >= RC(0.01));
}

static int params_ok(const grip_mf_thermal_params *p)
{
    const grip_real_t v[] = {
        p->fz0, p->t0, p->dx0, p->kx0, p->cx, p->ex, p->shx, p->svx, p->ax, p->bx,
        p->dy0, p->ky0, p->cy, p->ey, p->shy, p->svy, p->ay, p->by,
        p->bxa, p->cxa, p->exa, p->shxa, p->bys, p->cys, p->eys, p->shys, p->svys,
        p->w, p->kappa, p->fz_max, p->alpha_max, p->slip_max, p->v_max, p->t_min, p->t_max,
    };
    size_t i;
    for (i = 0; i < sizeof(v) / sizeof(v[0]); ++i) {
        if (!r_is_finite(v[i])) {
            return 0;
        }
    }
    if (!(p->fz0 >= RCL(100.0) && p->fz0 <= RCL(30000.0))) {
        return 0;
    }
    if (!(p->fz_max > R_ZERO && p->fz_max <= RCL(30000.0) &&
          r_div(p->fz_max, p->fz0) <= RC(100.0))) {
        return 0;
    }
    if (!(p->dx0 > R_ZERO && p->kx0 > R_ZERO && p->dy0 > R_ZERO && p->ky0 > R_ZERO)) {
        return 0;
    }
    /* normalized peak factors and stiffnesses stay inside QS with margin */
    if (!(r_div(p->dx0, p->fz0) <= RC(10.0) && r_div(p->dy0, p->fz0) <= RC(10.0) &&
          r_div(p->kx0, p->fz0) <= RC(1000.0) && r_div(p->ky0, p->fz0) <= RC(1000.0))) {
        return 0;
    }
    if (!(p->cx > R_ZERO && p->cx < RC(2.0) && p->cy > R_ZERO && p->cy < RC(2.0))) {
        return 0;
    }
    if (!(p->cxa > R_ZERO && p->cxa <= R_ONE && p->cys > R_ZERO && p->cys <= R_ONE)) {
        return 0;
    }
    if (!(p->bxa >= R_ZERO && p->bys >= R_ZERO)) {
        return 0;
    }
    if (!(p->w > R_ZERO && r_div(p->fz0, p->w) <= RC(100.0))) {
        return 0;
    }
    if (!(p->kappa >= R_ZERO && p->kappa <= RC(100.0))) {
        return 0;
    }
    if (!(p->alpha_max > R_ZERO && p->alpha_max <= RC(1.5) && p->slip_max > R_ZERO &&
          p->slip_max <= RC(2.0) && p->v_max > R_ZERO && p->v_max <= RC(200.0))) {
        return 0;
    }
    if (!(p->t_min < p->t_max && p->t_min >= RC(-1000.0) && p->t_max <= RC(1000.0) &&
          p->t0 >= RC(-1000.0) && p->t0 <= RC(1000.0))) {
        return 0;
    }
    if (!temp_factor_ok(p->ax, p) || !temp_factor_ok(p->bx, p) || !temp_factor_ok(p->ay, p) ||
        !temp_factor_ok(p->by, p)) {
        return 0;
    }
    return 1;
}

grip_status_t grip_mf_thermal_init(grip_mf_thermal_state *s, const grip_mf_thermal_params *p,
                                   grip_real_t t_init)
{
    grip_status_t st = GRIP_OK;
    if (s == NULL) {
        return GRIP_ERR_NULL;
    }
    s->magic = 0u;
    s->p = NULL;
    s->t = R_ZERO;
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!params_ok(p)) {
        return GRIP_ERR_PARAM;
    }
    if (!r_is_finite(t_init)) {
        return GRIP_ERR_INPUT;
    }
    s->gx_den = mf_cos(p->bxa, p->cxa, p->exa, p->shxa);
    s->gy_den = mf_cos(p->bys, p->cys, p->eys, p->shys);
    if (!(s->gx_den >= RC(0.01) && s->gy_den >= RC(0.01))) {
        return GRIP_ERR_PARAM;
    }
    s->dxn = r_div(p->dx0, p->fz0);
    s->kxn = r_div(p->kx0, p->fz0);
    s->svxn = r_div(p->svx, p->fz0);
    s->dyn = r_div(p->dy0, p->fz0);
    s->kyn = r_div(p->ky0, p->fz0);
    s->svyn = r_div(p->svy, p->fz0);
    s->svysn = r_div(p->svys, p->fz0);
    if (t_init < p->t_min) {
        t_init = p->t_min;
        st = GRIP_WARN_CLAMPED;
    } else if (t_init > p->t_max) {
        t_init = p->t_max;
        st = GRIP_WARN_CLAMPED;
    } /* grip-deviation: MISRA-15.7 temperature in range: no clamping */
    s->p = p;
    s->t = t_init;
    s->magic = THERMAL_MAGIC;
    return st;
}

static grip_real_t clamp_warn(grip_real_t x, grip_real_t lo, grip_real_t hi, grip_status_t *st)
{
    if (x < lo) {
        *st = GRIP_WARN_CLAMPED;
        return lo;
    }
    if (x > hi) {
        *st = GRIP_WARN_CLAMPED;
        return hi;
    }
    return x;
}

/* Validated and clamped copy of the inputs. */
static grip_status_t take_inputs(const grip_mf_thermal_params *p, const grip_mf_thermal_inputs *in,
                                 grip_mf_thermal_inputs *c)
{
    grip_status_t st = GRIP_OK;
    if (!r_is_finite(in->v) || !r_is_finite(in->alpha) || !r_is_finite(in->slip) ||
        !r_is_finite(in->fz) || !r_is_finite(in->t_road)) {
        return GRIP_ERR_INPUT;
    }
    c->v = clamp_warn(in->v, R_ZERO, p->v_max, &st);
    c->alpha = clamp_warn(in->alpha, r_neg(p->alpha_max), p->alpha_max, &st);
    c->slip = clamp_warn(in->slip, r_neg(p->slip_max), p->slip_max, &st);
    c->fz = clamp_warn(in->fz, R_ZERO, p->fz_max, &st);
    c->t_road = clamp_warn(in->t_road, p->t_min, p->t_max, &st);
    return st;
}

/* sqrt(a^2 + b^2) for a and b in one common format (QS or QL), without
 * squaring them: max(|a|,|b|) sqrt(1 + r^2), r = min/max <= 1, so small
 * components are not lost to underflow and large ones do not overflow. */
static grip_real_t r_hypot(grip_real_t a, grip_real_t b)
{
    grip_real_t m = r_max(r_abs(a), r_abs(b));
    grip_real_t n = r_min(r_abs(a), r_abs(b));
    grip_real_t r;
    if (m == R_ZERO) {
        return R_ZERO;
    }
    r = r_div(n, m);
    return r_mul(r_sqrt(r_add(R_ONE, r_sq(r))), m);
}

/* Combined-slip forces [N, QL] at temperature t. The Magic Formula runs on
 * values normalized by fz0 (QS); the result is scaled by fz itself
 * (F = fz * (F0 / fz0) * G), so small loads keep their full resolution. */
static void forces_at(const grip_mf_thermal_state *s, const grip_mf_thermal_inputs *c, grip_real_t t,
                      grip_real_t *fx, grip_real_t *fy)
{
    const grip_mf_thermal_params *p = s->p;
    grip_real_t dt = r_sub(t, p->t0);
    grip_real_t d;
    grip_real_t b;
    grip_real_t f0;
    grip_real_t g;

    /* longitudinal: (4.11)-(4.14), weighting (2.139)-(2.141) */
    d = r_mul(s->dxn, r_add(R_ONE, r_mul(p->ax, dt)));
    b = r_div(r_mul(s->kxn, r_add(R_ONE, r_mul(p->bx, dt))), r_mul(p->cx, d));
    f0 = r_add(mf_sin(d, b, p->cx, p->ex, r_add(c->slip, p->shx)), s->svxn);
    g = r_div(mf_cos(p->bxa, p->cxa, p->exa, r_add(c->alpha, p->shxa)), s->gx_den);
    *fx = r_mul(r_mul(g, f0), c->fz);

    /* lateral: (4.11)-(4.14), weighting (2.142)-(2.144) */
    d = r_mul(s->dyn, r_add(R_ONE, r_mul(p->ay, dt)));
    b = r_div(r_mul(s->kyn, r_add(R_ONE, r_mul(p->by, dt))), r_mul(p->cy, d));
    f0 = r_add(mf_sin(d, b, p->cy, p->ey, r_add(c->alpha, p->shy)), s->svyn);
    g = r_div(mf_cos(p->bys, p->cys, p->eys, r_add(c->slip, p->shys)), s->gy_den);
    *fy = r_mul(r_add(r_mul(g, f0), s->svysn), c->fz);
}

grip_status_t grip_mf_thermal_forces(const grip_mf_thermal_state *s, const grip_mf_thermal_inputs *in,
                                     grip_real_t t, grip_real_t *fx, grip_real_t *fy)
{
    grip_mf_thermal_inputs c;
    grip_status_t st;
    if (fx != NULL) {
        *fx = R_ZERO;
    }
    if (fy != NULL) {
        *fy = R_ZERO;
    }
    if (s == NULL || in == NULL || fx == NULL || fy == NULL) {
        return GRIP_ERR_NULL;
    }
    if (s->magic != THERMAL_MAGIC || s->p == NULL) {
        return GRIP_ERR_STATE;
    }
    if (!r_is_finite(t)) {
        return GRIP_ERR_INPUT;
    }
    st = take_inputs(s->p, in, &c);
    if (st < 0) {
        return st;
    }
    t = clamp_warn(t, s->p->t_min, s->p->t_max, &st);
    forces_at(s, &c, t, fx, fy);
    return st;
}

/* (1 - exp(-x)) / x for x >= 0: Taylor series (Horner) up to x^7 for
 * x <= 1, where the direct form would lose precision to cancellation
 * (truncation <= x^8/9! < 2.8e-6); the direct form beyond. */
static grip_real_t one_minus_exp_over_x(grip_real_t x)
{
    grip_real_t g;
    if (x > R_ONE) {
        return r_div(r_sub(R_ONE, r_exp(r_neg(x))), x);
    }
    g = r_sub(RC(1.0 / 40320.0), r_mul(x, RC(1.0 / 362880.0)));
    g = r_sub(RC(1.0 / 5040.0), r_mul(x, g));
    g = r_sub(RC(1.0 / 720.0), r_mul(x, g));
    g = r_sub(RC(1.0 / 120.0), r_mul(x, g));
    g = r_sub(RC(1.0 / 24.0), r_mul(x, g));
    g = r_sub(RC(1.0 / 6.0), r_mul(x, g));
    g = r_sub(RC(0.5), r_mul(x, g));
    g = r_sub(R_ONE, r_mul(x, g));
    return g;
}

/* Exact step of (4.6) for q held over dt, T limited to [t_min, t_max]:
 * T += phi (q / W - kappa (T - T_R)), phi = (1 - exp(-kappa dt)) / kappa;
 * q / W is QL / QL -> K/s. The one place the temperature advances. */
static grip_real_t advance(const grip_mf_thermal_params *p, grip_real_t t, grip_real_t q,
                           grip_real_t t_road, grip_real_t dt, grip_status_t *st)
{
    grip_real_t phi = r_mul(dt, one_minus_exp_over_x(r_mul(p->kappa, dt)));
    grip_real_t t_next = r_add(t, r_mul(phi, r_sub(r_div(q, p->w), r_mul(p->kappa, r_sub(t, t_road)))));
    return clamp_warn(t_next, p->t_min, p->t_max, st);
}

grip_status_t grip_mf_thermal_step(grip_mf_thermal_state *s, const grip_mf_thermal_inputs *in,
                                   grip_real_t dt, grip_mf_thermal_output *out)
{
    const grip_mf_thermal_params *p;
    grip_mf_thermal_inputs c;
    grip_status_t st;
    grip_real_t fx;
    grip_real_t fy;
    grip_real_t vs;
    grip_real_t q;
    grip_real_t t_next;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    out->fx = R_ZERO;
    out->fy = R_ZERO;
    out->q = R_ZERO;
    out->vs = R_ZERO;
    out->t = R_ZERO;
    if (s == NULL || in == NULL) {
        return GRIP_ERR_NULL;
    }
    if (s->magic != THERMAL_MAGIC || s->p == NULL) {
        return GRIP_ERR_STATE;
    }
    p = s->p;
    if (!r_is_finite(dt) || dt < R_ZERO || dt > RC(GRIP_MF_THERMAL_DT_MAX)) {
        return GRIP_ERR_INPUT;
    }
    st = take_inputs(p, in, &c);
    if (st < 0) {
        return st;
    }

    forces_at(s, &c, s->t, &fx, &fy);
    /* Vs = V sqrt((S cos alpha)^2 + sin^2 alpha)                 (4.4)-(4.5) */
    vs = r_mul(c.v, r_hypot(r_mul(c.slip, r_cos(c.alpha)), r_sin(c.alpha)));
    /* q = sqrt(Fx^2 + Fy^2) Vs [W, QL]                            (4.2)-(4.3) */
    q = r_mul(vs, r_hypot(fx, fy));
    t_next = advance(p, s->t, q, c.t_road, dt, &st);

    out->fx = fx;
    out->fy = fy;
    out->q = q;
    out->vs = vs;
    out->t = t_next;
    s->t = t_next;
    return st;
}

grip_status_t grip_mf_thermal_heat_step(grip_mf_thermal_state *s, grip_real_t q, grip_real_t t_road,
                                        grip_real_t dt, grip_real_t *t_out)
{
    const grip_mf_thermal_params *p;
    grip_status_t st = GRIP_OK;
    grip_real_t tr;

    if (t_out == NULL) {
        return GRIP_ERR_NULL;
    }
    *t_out = R_ZERO;
    if (s == NULL) {
        return GRIP_ERR_NULL;
    }
    if (s->magic != THERMAL_MAGIC || s->p == NULL) {
        return GRIP_ERR_STATE;
    }
    p = s->p;
    if (!r_is_finite(dt) || dt < R_ZERO || dt > RC(GRIP_MF_THERMAL_DT_MAX) || !r_is_finite(q) ||
        q < R_ZERO || !r_is_finite(t_road)) {
        return GRIP_ERR_INPUT;
    }
    tr = clamp_warn(t_road, p->t_min, p->t_max, &st);
    s->t = advance(p, s->t, q, tr, dt, &st);
    *t_out = s->t;
    return st;
}
