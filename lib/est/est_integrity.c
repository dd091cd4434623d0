/*
 * est_integrity.c - the error bounds of the lateral outputs
 * (docs/estimator/integrity.md). Two estimates of vy, each with a standard
 * deviation:
 *   filter     the EKF's vy; its deviation is the covariance's together
 *              with the tire model's: a relative force error tire_tol of an
 *              axle's model moves the slip angle the filter infers from
 *              that axle's force by at most tire_tol |alpha| / g, g the
 *              axle's slope factor max(G_MIN, sqrt(1 - u)) (the Jacobians'
 *              form). The ay update fits the axles' force sum, so
 *              the two combine weighted by the axles' slopes: a
 *              saturated axle's error goes to the other's slip angle;
 *              with both near saturation neither fixes vy, and the
 *              covariance does not know it. Nor does it know mu's own
 *              uncertainty where the model tire is linear: the slip
 *              angles at the lowest friction not excluded add their
 *              share (mu_hypothesis).
 *   kinematic  vy integrated from ay + g_y - r vx; an offset
 *              drifts it linearly, so its deviation grows by a rate per
 *              second (accelerometer offset and bank, the gyro offset's
 *              deviation times vx, the roll compensation's error).
 * The kinematic vy moves to the filter's by a share that is 1 while the
 * filter's deviation (without mu's share) is at most half the kinematic
 * one's and 0 once it is the larger (linear between); the outputs take it
 * and its deviation with mu's share (F_BETA_KIN while the kinematic side
 * weighs more). A filter vy beyond
 * EST_DIS_K joint deviations of the kinematic one (share below 1) is not
 * taken: the tire model is fitted where it is wrong (F_BETA_DISAGREE):
 * est_checks withholds V_BETA, the force bits and V_MU. V_BETA further
 * needs beta_sd <= beta_sd_max.
 * Reference: bound_lateral in tools/grip_tools/reference/est.py.
 */
#include "est_internal.h"

/* beta's slip-angle deviation [rad] from mu's own uncertainty, which the
 * covariance does not carry where the model tire is linear: the slip
 * angles the axles' present forces need at the lowest friction the filter
 * cannot exclude, mu_h = max(mu - EST_SEC_K sigma_mu, the friction in
 * use), on each axle's force shape scaled by mu (the filter's own model of
 * a lower mu), less the present ones. The shape's inverse is taken on its
 * chord from the present point to the peak: above a concave shape's
 * inverse and linear in the force (the inverse itself is ill-conditioned
 * on the flat top). vy's error under the hypothesis lies between the two
 * axles' shifts, so the larger counts, over EST_SEC_K: a deviation whose
 * EST_SEC_K multiple covers the hypothesis EST_SEC_K deviations away. */
static grip_real_t mu_hypothesis(const grip_est_t *est, const grip_real_t al_axle[2])
{
    grip_real_t mu = est->x[2];
    grip_real_t mu_h = r_max(r_sub(mu, r_mul(RC(EST_SEC_K * EST_S_MU), r_sqrt(est->p[2][2]))), est->mu_floor);
    grip_real_t inv_mu, gain, d = R_ZERO;
    int a;
    if (mu_h >= mu) {
        return R_ZERO;
    }
    inv_mu = r_div(R_ONE, mu);
    gain = r_sub(r_div(mu, mu_h), R_ONE);   /* the force's relative rise at mu_h */
    for (a = 0; a < 2; ++a) {
        const grip_real_t *row = est->fy_shape[a];
        grip_real_t al = al_axle[a];
        grip_real_t xa = r_min(r_mul(r_mul(al, inv_mu), est->inv_apk[a]), R_ONE);
        grip_real_t ya = r_table_lerp(row, GRIP_EST_SHAPE_N, xa);
        grip_real_t num = r_mul(ya, gain);
        grip_real_t den = r_sub(row[GRIP_EST_SHAPE_N], ya);
        grip_real_t xh = R_ONE;
        if (num < den) {   /* 0 <= num < den: below the peak, a share of the chord */
            xh = r_add(xa, r_mul_unit(r_div(num, den), r_sub(R_ONE, xa)));
        }
        d = r_max(d, r_sub(r_mul(r_mul(est->alpha_pk[a], mu_h), xh), al));
    }
    return r_mul(d, RC(1.0 / EST_SEC_K));
}

/* The filter's vy deviation [m/s]: the covariance's and the tire model's,
 * the axles' slip-angle errors weighted by their slopes; EST_SD_CAP with vy
 * held at its bound. *sd_mu: the same with mu's share (mu_hypothesis). */
static grip_real_t filter_sd(const grip_est_t *est, const est_ctx_t *s, const grip_est_output_t *out,
                             grip_real_t *sd_mu)
{
    grip_real_t e[2], al[2], da, sd_m, sd_f, sd_h, sum;
    int a;
    for (a = 0; a < 2; ++a) {
        grip_real_t u = r_min(out->util_axle[a], R_ONE);
        grip_real_t g = r_max(RC(EST_G_MIN), r_sqrt(r_sub(R_ONE, u)));
        /* the axle's mean slip angle */
        al[a] = r_mul(RC(0.5), r_abs(r_add(out->alpha[a + a], out->alpha[a + a + 1])));
        e[a] = r_min(r_div(r_mul(est->cfg.tire_tol, al[a]), g), RC(EST_SD_CAP));
    }
    /* The ay update fits the axles' force sum with one vy: an axle's force
     * error moves vy by that error over the sum of the slopes, so the
     * slip-angle errors combine as their slope-weighted mean (a saturated
     * axle's weight ~ 0: the other axle fixes vy), not as the smaller. */
    sum = r_add(s->slope[0], s->slope[1]);
    if (sum > R_ZERO) {
        da = r_add(e[1], r_mul_unit(r_div(s->slope[0], sum), r_sub(e[0], e[1])));
    } else {
        da = r_min(e[0], e[1]);
    }
    sd_m = r_min(r_mul(da, r_abs(s->vx)), RC(EST_SD_CAP));
    sd_h = r_min(r_mul(mu_hypothesis(est, al), r_abs(s->vx)), RC(EST_SD_CAP));
    if (r_abs(est->x[0]) >= r_sub(r_add(r_mul(RC(EST_VY_K), r_abs(s->vx)), R_ONE), RC(EST_SD_VY_EDGE))) {
        sd_m = RC(EST_SD_CAP);
    }
    sd_f = r_mul(RC(EST_S_VY), r_sqrt(est->p[0][0]));
    *sd_mu = r_min(r_sqrt(r_add(r_add(r_sq(sd_f), r_sq(sd_m)), r_sq(sd_h))), RC(EST_SD_CAP));
    return r_min(r_sqrt(r_add(r_sq(sd_f), r_sq(sd_m))), RC(EST_SD_CAP));
}

void est_integrity(grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    const grip_est_config_t *c = &est->cfg;
    grip_real_t sd_dyn, sd_dmu, ay, sb, rate, grow, vxd, tb, q, w, j;
    s->disagree = 0u;
    s->vy_sd = R_ZERO;
    s->beta_sd = R_ZERO;
    s->beta_sd_f = R_ZERO;
    out->mu_sd = r_mul(RC(EST_S_MU), r_sqrt(est->p[2][2]));
    if (!est->active) {
        out->yaw_rate_sd = R_ZERO;
        est->vy_k = R_ZERO;
        est->sd_k = RC(EST_SD_CAP);
        est->sd_kmu = RC(EST_SD_CAP);
        return;
    }
    out->yaw_rate_sd = r_mul(RC(EST_S_R), r_sqrt(est->p[1][1]));
    sd_dyn = filter_sd(est, s, out, &sd_dmu);
    ay = s->ay_ok ? s->ay : s->ay_m;
    est->vy_k = sym_clamp(r_add(est->vy_k, r_div(r_sub(r_add(ay, s->g_y), r_mul(est->x[1], s->vx)), est->rate)),
                          RC(EST_WS_MAX));
    /* drift rate [m/s^2]: accelerometer offset and bank, the gyro offset's
     * remaining deviation times vx, the roll compensation's error */
    sb = r_mul(RC(EST_S_B), r_sqrt(est->p[3][3]));
    rate = r_add(r_sqrt(r_add(r_sq(c->kin_acc_sd), r_sq(r_mul(s->vx, sb)))),
                 r_mul(r_mul(RC(EST_ROLL_TOL * EST_G), est->rg_k), r_abs(ay)));
    grow = r_div(rate, est->rate);
    est->sd_k = r_min(r_add(est->sd_k, grow), RC(EST_SD_CAP));
    est->sd_kmu = r_min(r_add(est->sd_kmu, grow), RC(EST_SD_CAP));
    /* the filter's share w: 1 while its deviation is at most EST_KIN_Q0 of
     * the kinematic one's, 0 from where it is the larger, linear between
     * (continuous: neither build's last bit picks a branch); the deviation
     * moves by the same share, a convex combination of two bounds being a
     * bound whatever their correlation. The share and the disagreement
     * test weigh the deviations without mu's term (sd_k): the kinematic vy
     * integrates a bank beyond the configured plane as a drift its bound
     * does not hold, and mu's term is largest in the long turns where that
     * drift builds up. The outputs' deviation sd_kmu moves by the same
     * share with mu's term. */
    q = r_min(r_div(sd_dyn, r_max(est->sd_k, RC(EST_SD_MIN))), RC(EST_Q_MAX));
    w = r_clamp(r_mul(r_sub(R_ONE, q), RC(1.0 / (1.0 - EST_KIN_Q0))), R_ZERO, R_ONE);
    j = r_min(r_sqrt(r_add(r_sq(sd_dyn), r_sq(est->sd_k))), RC(EST_SD_CAP));
    if (w < R_ONE && r_abs(r_sub(est->x[0], est->vy_k)) > r_mul(RC(EST_DIS_K), j)) {
        /* the filter's vy outside the joint bound: the tire model is fitted
         * where it is wrong; the kinematic vy carries */
        s->disagree = 1u;
        s->flags |= GRIP_EST_F_BETA_DISAGREE;
    } else {
        est->vy_k = r_add(est->vy_k, r_mul(w, r_sub(est->x[0], est->vy_k)));
        est->sd_k = r_add(est->sd_k, r_mul(w, r_sub(sd_dyn, est->sd_k)));
        est->sd_kmu = r_add(est->sd_kmu, r_mul(w, r_sub(sd_dmu, est->sd_kmu)));
    }
    if (w < RC(0.5)) {
        s->flags |= GRIP_EST_F_BETA_KIN;
    }
    s->vy_sd = est->sd_kmu;
    /* beta's deviation at the state's vy: d atan(vy / vx) / d vy =
     * cos^2(beta) / vx */
    vxd = r_max(s->vx, RC(EST_V_OFF));
    tb = sym_clamp(r_div(est->vy_k, vxd), RC(100.0));
    s->beta_sd = r_div(r_div(s->vy_sd, vxd), r_add(R_ONE, r_sq(tb)));
    /* without mu's share, for the axle forces: a lower mu moves the slip
     * angles at the measured forces, not the forces */
    s->beta_sd_f = r_div(r_div(est->sd_k, vxd), r_add(R_ONE, r_sq(tb)));
}

/* vx's deviation [m/s] through est_speed's complementary filter: the
 * prediction's grows by ax's error (offset and grade: kin_acc_sd, and r
 * times vy's deviation); the reference's is a wheel's rolling-radius
 * tolerance (EST_WS_TOL) and the reference wheels' slip at the measured
 * specific force, m |ax| / (4 c_kappa) at the softer axle's static
 * stiffness (slip_acc = m / (4 c_kappa), est_init); with a lagged slip
 * angle beyond the tire's peak one the tire slides, and the slip grows to
 * EST_SLIP_MAX at twice the peak angle (braking takes the fastest wheel, driving the slowest: their
 * slip is at most the mean); the update moves the deviation towards the
 * reference's by the update's own share kk, a convex combination of two
 * bounds being a bound whatever their correlation. Standstill (vx set to
 * 0 with every wheel below EST_V_STAND): EST_V_STAND. */
void est_bound_speed(grip_est_t *est, const est_ctx_t *s, grip_real_t kk, grip_real_t v_ref, int stand)
{
    grip_real_t sd, vyb, acc;
    if (!est->vx_init) {
        est->sd_vx = RC(EST_SD_CAP);
        return;
    }
    vyb = r_min(est->sd_kmu, r_add(r_mul(RC(EST_VY_K), r_abs(est->vx)), R_ONE));
    acc = r_add(est->cfg.kin_acc_sd, r_mul(r_abs(s->yaw), vyb));
    sd = r_min(r_add(est->sd_vx, r_div(acc, est->rate)), RC(EST_SD_CAP));
    if (kk > R_ZERO) {
        grip_real_t slip = r_mul(est->slip_acc, r_min(r_abs(s->ax), RC(EST_ACC_MAX)));
        grip_real_t sref;
        if (est->active) {
            /* a tire beyond its peak slip angle slides: its slip ratio
             * follows the direction of its force, not ax (a spin on snow:
             * every wheel 1 m/s slow at ax ~ 0), up to a peak slip from
             * one to twice the peak angle */
            grip_real_t sl = R_ZERO;
            int i;
            for (i = 0; i < 4; ++i) {
                sl = r_max(sl, r_mul(r_mul(r_abs(est->alpha_t[i]), est->stf_k[i >> 1]), est->inv_apk[i >> 1]));
            }
            slip = r_max(slip, r_mul(RC(EST_SLIP_MAX), r_clamp(r_sub(sl, R_ONE), R_ZERO, R_ONE)));
        }
        sref = r_mul(r_add(RC(EST_WS_TOL), r_min(slip, RC(EST_SLIP_MAX))), r_abs(v_ref));
        sd = r_add(sd, r_mul(kk, r_sub(sref, sd)));
    }
    if (stand) {
        sd = RC(EST_V_STAND);
    }
    est->sd_vx = sd;
}

/* The axle forces' deviations [N]: the tire model's relative error
 * tire_tol of the force, the axle's slope (its wheels' |d Fy / d alpha| of
 * this step's Jacobians) times the slip angle's deviation (beta's, and the
 * yaw rate's lever arm over vx), the force's change with mu (the step's
 * d Fy / d mu) times mu's deviation, and the axle's static share of
 * m kin_acc_sd: the filter fits the two forces to the measured ay, whose
 * offset and uncorrected bank they carry, which the slope term misses where
 * the slope is small (a braked tire near zero slip angle); summed (at least
 * their root sum square, and cheaper). vx's deviation with them. vx_sd_max > 0: V_VX
 * only while vx_sd is within it; fy_sd_max > 0: V_AXLE and V_MARGIN only
 * while both are within it. */
void est_bound_outputs(const grip_est_t *est, est_ctx_t *s, grip_est_output_t *out)
{
    int a;
    grip_real_t q;
    out->vx_sd = est->vx_init ? est->sd_vx : R_ZERO;
    /* the consumer's limits act on the output bits only: the estimator's
     * own use of vx (the lateral observer, the yaw reference) is as before */
    if ((est->cfg.vx_sd_max > R_ZERO) && (est->sd_vx > est->cfg.vx_sd_max)) {
        s->valid &= ~GRIP_EST_V_VX;
    }
    if (!est->active) {
        return;
    }
    q = r_div(out->yaw_rate_sd, r_max(r_abs(out->vx), RC(EST_V_OFF)));
    for (a = 0; a < 2; ++a) {
        int w0 = a + a, w1 = a + a + 1;
        grip_real_t arm = (a == 0) ? est->cfg.lf : est->cfg.lr;
        grip_real_t asd = r_min(r_add(s->beta_sd_f, r_mul(arm, q)), R_ONE);
        grip_real_t share = (a == 0) ? est->sb_share_f : r_sub(R_ONE, est->sb_share_f);
        grip_real_t sd = r_add(r_mul(est->cfg.tire_tol, r_abs(out->fy_axle[a])), r_mul(s->slope[a], asd));
        sd = r_add(sd, r_mul(r_add(r_abs(est->fy_dmu[w0]), r_abs(est->fy_dmu[w1])), out->mu_sd));
        sd = r_add(sd, r_mul(r_mul(share, est->cfg.kin_acc_sd), est->cfg.mass));
        out->fy_axle_sd[a] = sd;
        /* beyond the consumer's limit, when one is set: the axle forces
         * and the front axle's margin are not valid */
        if ((est->cfg.fy_sd_max > R_ZERO) && (sd > est->cfg.fy_sd_max)) {
            s->valid &= ~(GRIP_EST_V_AXLE | GRIP_EST_V_MARGIN);
        }
    }
}
