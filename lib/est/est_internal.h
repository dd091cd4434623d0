/*
 * est_internal.h - what the estimator's files (lib/est) share: one step's
 * working values (est_ctx_t), the stages grip_est_step (est_step.c) runs in
 * that order, the Kalman filter's scalar update, and the small helpers of
 * several stages. The helpers are static inline so that each stage inlines
 * them: a call per use would cost instructions the M4F budget does not
 * have. Tuning constants: est_tuning.h. Method: docs/estimator.md; float64
 * reference with the same steps in the same order:
 * tools/grip_tools/reference/est.py.
 */
#ifndef GRIP_EST_INTERNAL_H
#define GRIP_EST_INTERNAL_H

#include "grip/grip_est.h"
#include "arith.h"
#include "est_tuning.h"

#define EST_MAGIC 0x45535431u  /* "EST1" */

/* Keeps a function out of its caller's stack frame: its locals then take
 * stack only while it runs, not under the Magic Formula evaluations (the
 * M0+ worst-case stack is within a few words of its 1024 B budget). GCC and
 * clang; other compilers inline as they see fit (the stack budget is
 * measured with arm-none-eabi-gcc). */
#if defined(__GNUC__)
#define EST_NOINLINE __attribute__((noinline))
#else
#define EST_NOINLINE
#endif

/* slots of the held inputs (grip_est_t.hold, .age) */
enum { H_STEER = 0, H_YAW = 1, H_AX = 2, H_AY = 3, H_VS = 4, H_REAR = 5 };

/* One step's working values, handed from stage to stage (grip_est_step
 * owns it; each group is written by the stage named and read after it).
 * It is on the stack under the Magic Formula evaluations, so it holds only
 * what crosses stages, and its flags are bytes. */
typedef struct {
    /* input conditioning (est_input.c) */
    uint32_t flags;             /* GRIP_EST_F_* so far */
    uint32_t valid;             /* GRIP_EST_V_* so far */
    grip_real_t delta;          /* QS rad road-wheel angle at the state's time */
    grip_real_t cd, sd;         /* QS its cosine and sine */
    grip_real_t delta_r;        /* QS rad rear road-wheel angle (0 without rear steering) */
    grip_real_t cr, sr;         /* QS its cosine and sine */
    grip_real_t yaw;            /* QS rad/s yaw rate less the gyro bias; 0 when missing */
    grip_real_t ax, ay;         /* QS m/s^2; ay less the body roll's gravity; 0 when missing */
    grip_real_t g_x, g_y;       /* QS m/s^2 gravity along the body axes on the road plane */
    /* longitudinal speed (est_speed.c) */
    grip_real_t vx;             /* QS m/s the state's longitudinal speed */
    /* lateral observer on / off (est_lateral.c): the prior state */
    grip_real_t vy, r, mu;      /* QS the state the tires are evaluated at */
    /* tire model at the prior state (est_tires.c) */
    grip_real_t ay_m, ax_m;     /* QS m/s^2 the model's accelerations */
    grip_real_t racc;           /* QS rad/s^2 the model's yaw acceleration */
    grip_real_t a_vv, a_vr, a_vm; /* QS d ay_m / d(vy, r, mu) */
    grip_real_t a_rv, a_rr, a_rm; /* QS d racc / d(vy, r, mu) */
    grip_real_t jax_mu;         /* QL d(sum Fbx) / d mu */
    grip_real_t umax;           /* QS largest utilization the slips would cause at mu = 1 (excitation) */
    grip_real_t umax_x;         /* QS ... from the slip ratios alone */
    grip_real_t kappa_sum;      /* QS sum of the slip ratios */
    grip_real_t umax_est;       /* QS largest utilization of the model at the estimated mu */
    /* friction (est_friction.c) */
    grip_real_t mu_us;          /* QS upper bound of mu from the understeer limit; 0: none */
    /* lateral filter (est_lateral.c) */
    grip_real_t dvy, dr;        /* QS the predict's change of vy and r */
    grip_real_t r_upd;          /* QS rad/s r after the yaw-rate update (the yaw balance's) */
    grip_real_t nis_ay;         /* QS normalized innovation squared of the ay update */
    /* bounds (est_integrity.c) */
    grip_real_t vy_sd, beta_sd; /* QS m/s, rad the outputs' standard deviations */
    grip_real_t beta_sd_f;      /* QS rad beta's without mu's share (the axle forces') */
    grip_real_t slope[2];       /* QL N/rad the axles' |d Fy / d alpha| summed (est_tires) */
    /* flags (1: true), by the same stages */
    uint8_t steer_ok, yaw_ok, ax_ok, ay_ok; /* fresh, or held within the hold time */
    uint8_t vs_ok;              /* vehicle speed fresh in this step */
    uint8_t ws_ok[4];           /* wheel speed valid and within range */
    uint8_t wheels_ok;          /* every wheel speed valid */
    uint8_t lock, spin;         /* a wheel far below / above the vehicle */
    uint8_t at_rest;            /* at rest by the wheels and the prediction: the gyro reads its bias */
    uint8_t dead_reck;          /* vx integrates ax: every wheel locked or spinning */
    uint8_t kappa_slip;         /* a wheel at |kappa| >= LOCK_K */
    uint8_t excited;            /* mu may adapt in this step */
    uint8_t at_limit;           /* the mu-independent friction-limit test holds */
    uint8_t b_ok;               /* the gyro bias may adapt in this step */
    uint8_t ay_upd;             /* the ay update ran (nis_ay set) */
    uint8_t disagree;           /* the filter's and the kinematic vy disagree */
} est_ctx_t;

/* ---- helpers of several stages ---- */

static inline grip_real_t sym_clamp(grip_real_t x, grip_real_t m)
{
    return r_clamp(x, r_neg(m), m);
}

/* A two-state filter's covariance {P00, P01, P11} (the learned stiffness
 * scales): each variance within [lo, hi] of its own, the correlation below
 * 0.99 (conditioning after an update) */
static inline void cov2_condition(grip_real_t p[3], grip_real_t lo0, grip_real_t hi0, grip_real_t lo1,
                                  grip_real_t hi1)
{
    p[0] = r_clamp(p[0], lo0, hi0);
    p[2] = r_clamp(p[2], lo1, hi1);
    p[1] = sym_clamp(p[1], r_mul(RC(0.99), r_sqrt(r_mul(p[0], p[2]))));
}

/* The same covariance from outside (a restored blob): 1 when each variance
 * lies within its bounds and P01^2 <= P00 P11; the negated comparisons
 * also refuse NaN in the float build */
static inline int cov2_in_range(const grip_real_t p[3], grip_real_t lo0, grip_real_t hi0, grip_real_t lo1,
                                grip_real_t hi1)
{
    return (p[0] >= lo0 && p[0] <= hi0) && (p[2] >= lo1 && p[2] <= hi1) &&
           (r_mul(p[1], p[1]) <= r_mul(p[0], p[2]));
}

/* A step counter, saturating so that it never wraps */
static inline int32_t count_up(int32_t n)
{
    return (n < 1000000) ? n + 1 : n;
}

/* One tire evaluation through the axle's model (the tagged union). */
static inline grip_status_t tire_eval(const grip_est_tire_t *t, const grip_mf_input *in, grip_mf_output *out)
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

/* The step's tire evaluation of an axle: its prepared MF set (est_init.c),
 * the same outputs as tire_eval, bit for bit, without the per-call checks
 * of the set. */
static inline grip_status_t tire_eval_axle(const grip_est_t *est, int axle, const grip_mf_input *in,
                                           grip_mf_output *out)
{
    switch (est->cfg.tire[axle].kind) {
    case GRIP_EST_TIRE_MF:
        return grip_mf_eval_prepared(&est->tire_prep[axle], in, out);
    default:
        out->fx = R_ZERO;
        out->fy = R_ZERO;
        out->mz = R_ZERO;
        return GRIP_ERR_PARAM;
    }
}

/* vx's rate of change in the body frame: the measured ax less its learned
 * offset, plus r vy, plus gravity's component along the road's grade
 * (vx's prediction over a step, and vx at the outputs' time) */
static inline grip_real_t vx_rate(const grip_est_t *est, grip_real_t ax, grip_real_t r, grip_real_t vy, grip_real_t g_x)
{
    return r_add(r_add(r_sub(ax, est->ax_off), r_mul(r, vy)), g_x);
}

/* A wheel's relaxation length: the axle's at static load in proportion to
 * the wheel's load, at least EST_SIG_MIN; 0 where the tire file gives none. */
static inline grip_real_t wheel_sigma(const grip_est_t *est, int axle, grip_real_t fz)
{
    if (est->sig_a[axle] <= R_ZERO) {
        return R_ZERO;
    }
    return r_max(r_mul(est->sig_a[axle], r_div(fz, est->fz_static[axle])), RC(EST_SIG_MIN));
}

/* 1 - exp(-dist / sig): the share of the way the lagged slip angle moves
 * towards the kinematic one over the distance dist; 1 without a relaxation
 * length. The comparison first keeps the exponent within EST_RLX_A_MAX. */
static inline grip_real_t relax_share(grip_real_t dist, grip_real_t sig)
{
    if (sig <= R_ZERO || dist >= r_mul(RC(EST_RLX_A_MAX), sig)) {
        return R_ONE;
    }
    return r_sub(R_ONE, r_exp(r_neg(r_div(dist, sig))));
}

/* The car not short of the linear yaw response by the share d of it (the
 * understeer test's deficit 1 - r / r_lin, est_friction.c, without its
 * division; r_lin low-passed there): a car nearing its limit on a friction
 * the model does not know yet is short of it, whatever mu the filter has.
 * The bank (est_road.c) and the stiffness (est_stiffness.c) learn only
 * while it holds. The reference is the tire file's car (k_us0), not the
 * learned one the limit tests use: a balance learned part of the way (one
 * axle ahead of the other) would otherwise put the car short of it and stop
 * the learning that corrects it. */
static inline int est_yaw_linear(const grip_est_t *est, grip_real_t yaw, grip_real_t vx, grip_real_t d)
{
    grip_real_t v2 = r_mul(RC(0.01), r_mul(vx, vx));
    grip_real_t r_lin = r_div_keep(r_mul(est->r_lin_f, r_max(r_add(R_ONE, r_mul(est->k_us, v2)), RC(0.1))),
                                   r_max(r_add(R_ONE, r_mul(est->k_us0, v2)), RC(0.1)));
    grip_real_t short_by = (r_lin > R_ZERO) ? r_sub(r_lin, yaw) : r_sub(yaw, r_lin);
    return (r_abs(r_lin) <= RC(EST_US_R)) || (short_by < r_mul(d, r_abs(r_lin)));
}

/* ---- friction that the tire evaluation needs (est_tires.c inlines it:
 * the secant runs four times per step) ---- */

/* The friction in use bounds mu from below (a bound on the state, no
 * measurement: it adds no confidence); mu's secant spans no lower (a
 * steering offset's onset took mu 1.0 -> 0.49 in 0.05 s on a dry road with
 * the secant down to MU_MIN). Formed before the tire evaluations. */
static inline void est_friction_floor(grip_est_t *est, const est_ctx_t *s)
{
    grip_real_t ax = s->ax, ay = s->ay, mu = s->mu;
    grip_real_t sig, dmu, mu2;
    est->mu_floor = (s->ax_ok && s->ay_ok) ? r_max(RC(EST_MU_MIN),
                                                   r_min(r_div(r_sqrt(r_add(r_sq(ax), r_sq(ay))),
                                                               r_mul(RC(EST_G), r_max(est->mu0[0], est->mu0[1]))),
                                                         RC(EST_MU_MAX)))
                                           : RC(EST_MU_MIN);
    /* mu's secant (est_mu_secant): its span and the reciprocals are the
     * same for the four wheels, formed once per step */
    sig = r_mul(r_sqrt(est->p[2][2]), RC(EST_S_MU));
    dmu = r_max(r_min(r_mul(RC(EST_SEC_K), sig), r_sub(mu, est->mu_floor)), RC(EST_SEC_MIN));
    mu2 = r_sub(mu, dmu);
    est->sec_inv_mu = r_div(R_ONE, mu);
    est->sec_inv_mu2 = r_div(R_ONE, mu2);
    est->sec_inv_dmu = r_div(R_ONE, dmu);
    est->sec_ratio = r_mul(mu2, est->sec_inv_mu);
}

/* d Fy / d mu of one wheel (docs/estimator.md, "5. Friction"): the secant
 * of mu F0(alpha / mu) from mu down to mu - dmu, dmu = SEC_K sigma_mu, on
 * the axle's tabulated force shape: the shape's ratio F(mu - dmu) / F(mu)
 * applied to the wheel's own force fy (its load and combined slip), within
 * [0, fy / mu] like the tangent (F - alpha F') / mu. The tangent is 0 while
 * the model tire is linear, however far a lower mu would take it (the snow
 * onset: mu stayed at its prior while vy took the ay deficit). */
static inline grip_real_t est_mu_secant(const grip_est_t *est, int axle, grip_real_t alpha, grip_real_t fy)
{
    grip_real_t inv_mu = est->sec_inv_mu;
    grip_real_t f1 = r_table_lerp(est->fy_shape[axle], GRIP_EST_SHAPE_N,
                                  r_mul(r_mul(r_abs(alpha), inv_mu), est->inv_apk[axle]));
    grip_real_t q = R_ZERO;
    if (f1 > RC(EST_SHAPE_F_MIN)) {
        grip_real_t f2 = r_table_lerp(est->fy_shape[axle], GRIP_EST_SHAPE_N,
                                      r_mul(r_mul(r_abs(alpha), est->sec_inv_mu2), est->inv_apk[axle]));
        q = r_mul(r_sub(R_ONE, r_mul(est->sec_ratio, r_div(f2, f1))), est->sec_inv_dmu);
        q = r_clamp(q, R_ZERO, inv_mu);
    }
    return r_mul(q, fy);
}

/* ---- the step's stages, in the order grip_est_step runs them ---- */

/* est_input.c: the ESC inputs taken, range-checked and held; sets
 * s->flags and s->valid first */
void est_take_inputs(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s);

/* est_speed.c: vx from ax and the wheel speeds (or the vehicle speed) */
void est_speed(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s);

/* est_lateral.c: the lateral observer started or stopped (and while
 * stopped, the gyro bias at rest); the prior state into s */
void est_observer_switch(grip_est_t *est, est_ctx_t *s);

/* est_tires.c: the wheels' vertical loads; with the observer running the
 * four tire evaluations at the prior state, the model's accelerations and
 * the Jacobians */
void est_tires(grip_est_t *est, const grip_input_sample_t *in, est_ctx_t *s, grip_est_output_t *out);

/* est_stiffness.c: the axles' cornering-stiffness scales learned (stiff_est).
 * Bounds of its filter in scaled units (est_tuning.h's EST_STF_*): the
 * variance's floor and prior, the state 1 / k's range. */
#define EST_STF_P_MIN ((EST_STF_SD_MIN / EST_STF_S_U) * (EST_STF_SD_MIN / EST_STF_S_U))
#define EST_STF_P_MAX ((EST_STF_P0 / EST_STF_S_U) * (EST_STF_P0 / EST_STF_S_U))
#define EST_STF_X_LO  (1.0 / (EST_STF_K_MAX * EST_STF_S_U))
#define EST_STF_X_HI  (1.0 / (EST_STF_K_MIN * EST_STF_S_U))
int est_stiffness(grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out);
void est_stability_factor(grip_est_t *est);

/* est_stiffness_long.c: the tires' longitudinal slip-stiffness scale learned
 * (kx_est); its Kalman update waits while est_stiffness updated in this step
 * (stf_upd 1: one learner's update per step). Bounds of its filter in scaled
 * units (est_tuning.h's EST_KX_*): the variances' floors and priors, the
 * states' ranges. */
#define EST_KX_P_MIN  ((EST_KX_SD_MIN / EST_KX_S_U) * (EST_KX_SD_MIN / EST_KX_S_U))
#define EST_KX_P_MAX  ((EST_KX_P0 / EST_KX_S_U) * (EST_KX_P0 / EST_KX_S_U))
#define EST_KX_PD_MIN ((EST_KX_D_SD_MIN / EST_KX_S_Y) * (EST_KX_D_SD_MIN / EST_KX_S_Y))
#define EST_KX_PD_MAX ((EST_KX_D0 / EST_KX_S_Y) * (EST_KX_D0 / EST_KX_S_Y))
#define EST_KX_X_LO   (1.0 / (EST_KX_K_MAX * EST_KX_S_U))
#define EST_KX_X_HI   (1.0 / (EST_KX_K_MIN * EST_KX_S_U))
#define EST_KX_XD_MAX (EST_KX_D_MAX / EST_KX_S_Y)
void est_stiffness_long(grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out, int stf_upd);
/* est_roll.c: the body's roll gradient learned (roll_est). Bounds of its
 * filter in scaled units (est_tuning.h's EST_RG_*) */
#define EST_RG_P_MIN ((EST_RG_SD_MIN / EST_RG_S_U) * (EST_RG_SD_MIN / EST_RG_S_U))
#define EST_RG_P_MAX ((EST_RG_P0 / EST_RG_S_U) * (EST_RG_P0 / EST_RG_S_U))
#define EST_RG_X_LO  (EST_RG_K_MIN / EST_RG_S_U)
#define EST_RG_X_HI  (EST_RG_K_MAX / EST_RG_S_U)
void est_roll(grip_est_t *est, const est_ctx_t *s);
/* est_roll.c: rg_k and ay_fac from the filter's state */
void est_roll_apply(grip_est_t *est);
/* est_stiffness_long.c: est->kx from its state, the slip stiffnesses at
 * that scale (c_kappa_kx) and the vx bound's slip per m/s^2 (slip_acc) */
void est_kx_apply(grip_est_t *est);

/* With the observer running: */
/* est_friction.c: excitation, the friction-limit test, the understeer bound */
void est_friction_tests(grip_est_t *est, est_ctx_t *s, const grip_est_output_t *out);
/* est_lateral.c: predict, then the yaw-rate and ay updates */
void est_lateral_update(grip_est_t *est, est_ctx_t *s, const grip_est_output_t *out);
/* est_outputs.c: the yaw and lateral balances */
void est_balances(grip_est_t *est, const est_ctx_t *s);
/* est_road.c: the road's bank from the ay update's correction of vy (observer
 * running), or from the accelerometer at rest */
void est_road(grip_est_t *est, const est_ctx_t *s);
/* est_friction.c: the ax update, then mu's bounds */
void est_friction_update(grip_est_t *est, const est_ctx_t *s);
/* est_friction.c: mu's variance from the tires alone, after the step's updates */
void est_mu_own(grip_est_t *est);
/* est_lateral.c: the bounds of vy, r and the gyro bias */
void est_bound_state(grip_est_t *est, const est_ctx_t *s);

/* Every step: */
/* est_checks.c: the model-consistency statistics of the ay update, the
 * lateral outputs' validity, mu's confidence */
void est_checks(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out);
/* est_integrity.c (run by est_checks first): the standard deviations of
 * vy (the filter's with the tire model's, the kinematic one's), the
 * kinematic vy, which of the two the outputs take and whether they
 * disagree; the yaw rate's and mu's deviations */
void est_integrity(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out);
/* est_integrity.c, run by est_speed: vx's deviation after the speed update
 * (kk: the update's share of the reference v_ref, 0 without one; stand:
 * the standstill that set vx to 0) */
void est_bound_speed(grip_est_t *est, const est_ctx_t *s, grip_real_t kk, grip_real_t v_ref, int stand);
/* est_integrity.c, after est_outputs: the axle forces' deviations and vx's */
void est_bound_outputs(const grip_est_t *est, est_ctx_t *s, grip_est_output_t *out);
/* est_outputs.c: the outputs (the lateral ones at the updated state) */
void est_outputs(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out);

/* ---- shared by the stages ---- */

/* est_lateral.c: a scalar measurement update, and P kept well conditioned */
grip_real_t est_kf_update(grip_est_t *e, const grip_real_t h[GRIP_EST_NX], grip_real_t nu, grip_real_t r,
                          int mu_ok, int b_ok, int keep_p);
void est_kf_condition(grip_est_t *e);

#endif
