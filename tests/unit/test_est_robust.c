/*
 * test_est_robust.c - lib/est robustness: API errors, bad configuration,
 * non-finite / invalid / stale / saturated inputs, standstill, reversing,
 * wheel lock and spin, every wheel locked at speed, steering at lock, long
 * input loss and recovery.
 * Every step's outputs must be finite, flagged as documented in grip_est.h,
 * and the estimator must come back (validity bits set again, beta near the
 * undisturbed run) once the inputs recover.
 *
 * Inputs come from a steady circle at 20 m/s built in this file:
 * yaw rate r = ay / vx, wheel speeds from vx -/+ r * track / 2.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_est.h"
#include "mf_params.h"

#if GRIP_ARITH_FIXED
static grip_real_t qs(double v) { return (grip_real_t)lround(v * 65536.0); }
static grip_real_t ql(double v) { return (grip_real_t)lround(v * 256.0); }
static double dq(grip_real_t v) { return (double)v / 65536.0; }
static double dl(grip_real_t v) { return (double)v / 256.0; }
#else
static grip_real_t qs(double v) { return (grip_real_t)v; }
static grip_real_t ql(double v) { return (grip_real_t)v; }
static double dq(grip_real_t v) { return (double)v; }
static double dl(grip_real_t v) { return (double)v; }
#endif

static const grip_mf_params *tire(void)
{
    return grip_test_tire_params("PacejkaBook_Defaults");
}

/* The consumer's sideslip limit of these tests: 3 deg (beta_sd_max). With
 * mu at its prior (1.0 +- 0.3) beta's bound carries the slip angles of the
 * lowest friction not excluded, the one in use (docs/estimator/integrity.md,
 * "Friction not yet known"): 0.46 deg per m/s^2 of a steady circle, beyond
 * the default 1 deg from 2.2 m/s^2 (test_steady_circle). The tests of other
 * mechanisms (inputs lost and back, reset, bank, ax missing) take beta at
 * the wider limit, so that V_BETA there says what the mechanism did. */
#define TEST_BETA_SD_MAX 0.0524

static void make_est(grip_est_t *e)
{
    grip_est_config_t cfg;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.beta_sd_max = qs(TEST_BETA_SD_MAX);
    assert_int_equal(grip_est_init(e, &cfg), GRIP_OK);
}

/* The wheel speeds, steering-wheel angle swa and yaw rate r of a steady
 * turn at speed v (the default car's half tracks 0.775 / 0.765 m). */
static void turn(grip_input_sample_t *s, double v, double r, double swa)
{
    s->value[GRIP_IN_WHEEL_SPEED_FL] = qs((v - r * 0.775) * cos(swa / 15.5));
    s->value[GRIP_IN_WHEEL_SPEED_FR] = qs((v + r * 0.775) * cos(swa / 15.5));
    s->value[GRIP_IN_WHEEL_SPEED_RL] = qs(v - r * 0.765);
    s->value[GRIP_IN_WHEEL_SPEED_RR] = qs(v + r * 0.765);
    s->value[GRIP_IN_STEER_ANGLE] = qs(swa);
    s->value[GRIP_IN_YAW_RATE] = qs(r);
}

/* A steady circle of the default car at speed v [m/s] and lateral
 * acceleration ay: the steering-wheel angle of the linear bicycle model
 * (l = 2.7 m, stability factor A = 3.7e-4 s^2/m^2 of the estimator's car
 * and tire, steering ratio 15.5), yaw rate ay / v, and the accelerometer's
 * reading of a body rolled by the default roll gradient (0.0088 rad per
 * m/s^2: ay (1 + g 0.0088)), which the estimator removes. (A reading
 * without the roll is 8 % below the kinematics, a persistent deficit that
 * mu's secant takes for low friction: docs/estimator.md, "mu's secant".) */
static void circle(grip_input_sample_t *s, double v, double ay)
{
    double r = (v > 0.1) ? ay / v : 0.0;
    double swa = 15.5 * 2.7 * r / ((v > 0.1) ? v : 1.0) * (1.0 + 3.7e-4 * v * v);
    int i;
    memset(s, 0, sizeof *s);
    turn(s, v, r, swa);
    s->value[GRIP_IN_AX] = qs(0.0);
    s->value[GRIP_IN_AY] = qs(ay * (1.0 + 9.80665 * 0.0088));
    for (i = 0; i < 8; ++i) {
        s->valid[i] = 1;
    }
    for (i = 8; i < GRIP_IN_COUNT; ++i) {
        s->fault[i] = GRIP_SIG_UNMAPPED;
    }
}

static void assert_finite_out(const grip_est_output_t *o)
{
#if !GRIP_ARITH_FIXED
    int i;
    assert_true(isfinite(o->vx) && isfinite(o->vy) && isfinite(o->beta) && isfinite(o->yaw_rate));
    assert_true(isfinite(o->yaw_rate_ref) && isfinite(o->mu) && isfinite(o->mu_conf));
    assert_true(isfinite(o->fy_margin_front) && isfinite(o->yaw_error));
    for (i = 0; i < 4; ++i) {
        assert_true(isfinite(o->kappa[i]) && isfinite(o->alpha[i]) && isfinite(o->fz[i]));
        assert_true(isfinite(o->fx[i]) && isfinite(o->fy[i]) && isfinite(o->mz[i]) && isfinite(o->util[i]));
    }
#endif
    assert_true(dq(o->mu) >= 0.0 && dq(o->mu) <= 1.2 + 1e-4);
    assert_true(dq(o->mu_conf) >= 0.0 && dq(o->mu_conf) <= 1.0 + 1e-4);
    assert_true(fabs(dq(o->beta)) < 1.6);
    assert_true(dl(o->fz[0]) >= 0.0);
}

static void run(grip_est_t *e, grip_input_sample_t *s, int n, grip_est_output_t *o)
{
    int k;
    for (k = 0; k < n; ++k) {
        assert_int_equal(grip_est_step(e, s, o), GRIP_OK);
        assert_finite_out(o);
    }
}

/* A fresh estimator settled for n steps on the steady circle (v, ay);
 * s is left holding that circle's sample. */
static void settle(grip_est_t *e, grip_input_sample_t *s, double v, double ay, int n, grip_est_output_t *o)
{
    make_est(e);
    circle(s, v, ay);
    run(e, s, n, o);
}

static void test_api_errors(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    (void)state;
    circle(&s, 20.0, 2.0);
    assert_int_equal(grip_est_config_default(NULL, tire()), GRIP_ERR_NULL);
    assert_int_equal(grip_est_init(NULL, &cfg), GRIP_ERR_NULL);
    assert_int_equal(grip_est_init(&e, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_est_step(&e, &s, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_est_reset(NULL), GRIP_ERR_NULL);
    memset(&e, 0, sizeof e);
    assert_int_equal(grip_est_step(&e, &s, &o), GRIP_ERR_STATE);
    assert_int_equal(o.valid, 0u);
    assert_int_equal(grip_est_reset(&e), GRIP_ERR_STATE);
    /* bad configurations */
    grip_est_config_default(&cfg, tire());
    cfg.mass = 0;
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    assert_int_equal(grip_est_step(&e, &s, &o), GRIP_ERR_STATE);
    grip_est_config_default(&cfg, tire());
    cfg.rate_hz = 10u;
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    grip_est_config_default(&cfg, tire());
    cfg.tire[1].kind = GRIP_EST_TIRE_BRUSH;   /* not wired yet */
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    grip_est_config_default(&cfg, NULL);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
#if !GRIP_ARITH_FIXED
    grip_est_config_default(&cfg, tire());
    cfg.lf = NAN;
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
#endif
    make_est(&e);
    assert_int_equal(grip_est_step(&e, NULL, &o), GRIP_ERR_NULL);
    assert_int_equal(o.valid, 0u);
}

/* CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, initial value and
 * final XOR all ones): the blob's checksum, to make a changed blob's good */
static uint32_t crc32_ieee(const uint8_t *p, uint32_t n)
{
    uint32_t c = 0xFFFFFFFFu, i;
    int k;
    for (i = 0u; i < n; ++i) {
        c ^= p[i];
        for (k = 0; k < 8; ++k) {
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
        }
    }
    return ~c;
}

/* The learned blob (grip_est_learned_get / _set): NULL and state errors;
 * a round trip moves the scales (cornering and longitudinal, with the
 * radius mismatch) and the roll gradient; a reset keeps them; a blob with
 * one bit changed, another version (the roll gradient's predecessor,
 * version 2, among them), a state out of range, another car's or another
 * drive split's fingerprint is refused and the estimator keeps what it
 * had. */
static void test_learned_blob(void **state)
{
    grip_est_t a, b;
    grip_est_config_t cfg;
    grip_est_learned_t blob, bad, got;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.stiff_est = 1u;
    cfg.kx_est = 1u;
    cfg.roll_est = 1u;
    cfg.drive_front = qs(0.0);
    assert_int_equal(grip_est_init(&a, &cfg), GRIP_OK);
    assert_int_equal(grip_est_init(&b, &cfg), GRIP_OK);
    assert_true(dq(a.kx) == 1.0 && a.kx_updates == 0u);
    assert_int_equal(grip_est_learned_get(NULL, &blob), GRIP_ERR_NULL);
    assert_int_equal(grip_est_learned_get(&a, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_est_learned_set(NULL, &blob), GRIP_ERR_NULL);
    assert_int_equal(grip_est_learned_set(&a, NULL), GRIP_ERR_NULL);
    /* a state as if learned: 1 / k = 0.8 and 0.7 (k 1.25, 1.43) */
    a.stf_x[0] = qs(0.8 / 0.05);
    a.stf_x[1] = qs(0.7 / 0.05);
    /* ... and 1 / kx = 0.75 (kx 1.33), a mismatch of 4 per mille */
    a.kx_x[0] = qs(0.75 / 0.05);
    a.kx_x[1] = qs(4.0);
    a.kx_p[0] = qs(2.0);
    a.kx_p[1] = qs(-0.5);
    a.kx_p[2] = qs(3.0);
    a.kx_updates = 321u;
    /* ... and a roll gradient of 0.015 rad/(m/s^2) (units of 0.001) */
    a.rg_x = qs(15.0);
    a.rg_p = qs(2.0);
    a.rg_updates = 99u;
    assert_int_equal(grip_est_learned_get(&a, &blob), GRIP_OK);
    assert_int_equal(blob.magic, GRIP_EST_LEARNED_MAGIC);
    assert_int_equal(grip_est_learned_set(&b, &blob), GRIP_OK);
    assert_true(b.stf_x[0] == a.stf_x[0] && b.stf_x[1] == a.stf_x[1]);
    assert_true(b.kx_x[0] == a.kx_x[0] && b.kx_x[1] == a.kx_x[1] && b.kx_p[1] == a.kx_p[1]);
    assert_true(b.kx_updates == 321u);
    assert_true(dq(b.kx) > 1.32 && dq(b.kx) < 1.34);
    /* the vx bound's slip per m/s^2 follows kx */
    assert_true(fabs(dq(b.slip_acc) * dq(b.kx) - dq(a.slip_acc)) < 1e-3 * dq(a.slip_acc));
    assert_true(dq(b.stf_k[0]) > 1.24 && dq(b.stf_k[0]) < 1.26);
    assert_true(dq(b.stf_k[1]) > 1.42 && dq(b.stf_k[1]) < 1.44);
    /* the roll gradient, and the ay the filter uses with it */
    assert_true(b.rg_updates == 99u && b.rg_x == a.rg_x && b.rg_p == a.rg_p);
    assert_true(fabs(dq(b.rg_k) - 0.015) < 1e-4);
    assert_true(fabs(dq(b.ay_fac) - 1.0 / (1.0 + 9.80665 * 0.015)) < 1e-4);
    /* reset keeps what was learned: the same blob before and after */
    assert_int_equal(grip_est_learned_get(&b, &bad), GRIP_OK);
    assert_int_equal(grip_est_reset(&b), GRIP_OK);
    assert_int_equal(grip_est_learned_get(&b, &got), GRIP_OK);
    assert_memory_equal(&got, &bad, sizeof got);
    assert_int_equal(grip_est_init(&b, &cfg), GRIP_OK);
    bad = blob;
    ((unsigned char *)&bad.x[0])[1] ^= 0x04u;            /* one bit of the state */
    assert_int_equal(grip_est_learned_set(&b, &bad), GRIP_ERR_PARAM);
    bad = blob;
    bad.version += 2u;
    assert_int_equal(grip_est_learned_set(&b, &bad), GRIP_ERR_PARAM);
    /* a blob of the format before the roll gradient (version 2, this
     * build), its checksum made good: refused */
    bad = blob;
    bad.version = blob.version - 2u * (GRIP_EST_LEARNED_VERSION - 2u);
    assert_int_equal(bad.version / 2u, 2u);
    bad.crc = crc32_ieee((const uint8_t *)&bad, (uint32_t)offsetof(grip_est_learned_t, crc));
    assert_int_equal(grip_est_learned_set(&b, &bad), GRIP_ERR_PARAM);
    assert_true(dq(b.stf_k[0]) == 1.0 && dq(b.stf_k[1]) == 1.0);
    assert_true(b.rg_updates == 0u && b.rg_k == cfg.roll_gradient);
    assert_true(dq(b.kx) == 1.0 && b.kx_updates == 0u);
    {
        /* kx beyond its range (1 / kx = 3: kx 0.33 < 0.4), checksum made good */
        grip_est_t c = a;
        c.kx_x[0] = qs(3.0 / 0.05);
        assert_int_equal(grip_est_learned_get(&c, &bad), GRIP_OK);
        assert_int_equal(grip_est_learned_set(&b, &bad), GRIP_ERR_PARAM);
        assert_true(dq(b.kx) == 1.0);
        /* a roll gradient beyond its range (0.035 > 0.03) */
        c = a;
        c.rg_x = qs(35.0);
        assert_int_equal(grip_est_learned_get(&c, &bad), GRIP_OK);
        assert_int_equal(grip_est_learned_set(&b, &bad), GRIP_ERR_PARAM);
        assert_true(b.rg_updates == 0u && b.rg_k == cfg.roll_gradient);
    }
    {
        /* a blob with nothing learned of kx takes a learned kx back to 1 */
        grip_est_t c;
        grip_est_learned_t fresh;
        assert_int_equal(grip_est_init(&c, &cfg), GRIP_OK);
        assert_int_equal(grip_est_learned_get(&c, &fresh), GRIP_OK);
        assert_int_equal(grip_est_learned_set(&b, &blob), GRIP_OK);
        assert_true(dq(b.kx) > 1.32);
        assert_int_equal(grip_est_learned_set(&b, &fresh), GRIP_OK);
        assert_true(dq(b.kx) == 1.0 && b.kx_updates == 0u && b.slip_acc == c.slip_acc);
        /* ... and the roll gradient back to the configured one */
        assert_true(b.rg_updates == 0u && b.rg_k == c.rg_k && b.ay_fac == c.ay_fac && b.rg_p == c.rg_p);
        /* with roll_est 0 a learned roll gradient is not taken */
        cfg.roll_est = 0u;
        assert_int_equal(grip_est_init(&c, &cfg), GRIP_OK);
        assert_int_equal(grip_est_learned_set(&c, &blob), GRIP_OK);
        assert_true(c.rg_updates == 0u && c.rg_k == cfg.roll_gradient && dq(c.kx) > 1.32);
        cfg.roll_est = 1u;
    }
    cfg.drive_front = qs(1.0);                            /* another drive layout */
    assert_int_equal(grip_est_init(&b, &cfg), GRIP_OK);
    assert_int_equal(grip_est_learned_set(&b, &blob), GRIP_ERR_PARAM);
    cfg.drive_front = qs(0.0);
    cfg.mass = ql(1600.0);                                /* another car */
    assert_int_equal(grip_est_init(&b, &cfg), GRIP_OK);
    assert_int_equal(grip_est_learned_set(&b, &blob), GRIP_ERR_PARAM);
    memset(&b, 0, sizeof b);
    assert_int_equal(grip_est_learned_get(&b, &got), GRIP_ERR_STATE);
    assert_int_equal(grip_est_learned_set(&b, &blob), GRIP_ERR_STATE);
}

/* Steady circle: every output valid; outputs physically sensible. With
 * the default sideslip limit (1 deg) beta is withheld at 4 m/s^2 while mu
 * is at its prior: its bound carries the slip angles of the lowest friction
 * not excluded (est_integrity.c mu_hypothesis), which grows with the
 * friction in use; at 2 m/s^2 it is within the limit. */
static void test_steady_circle(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    double sd4, sd2;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 4.0);
    run(&e, &s, 300, &o);
    sd4 = dq(o.beta_sd);
    assert_false(o.valid & GRIP_EST_V_BETA);
    assert_true(sd4 > dq(cfg.beta_sd_max));
    assert_true(dq(o.mu_sd) > 0.2);                 /* mu not yet known */
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 2.0);
    run(&e, &s, 300, &o);
    sd2 = dq(o.beta_sd);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(sd2 < sd4);
    printf("# circle 20 m/s, default limit %.2f deg: beta_sd %.2f deg at 4 m/s^2 (withheld), %.2f deg at 2 m/s^2\n",
           dq(cfg.beta_sd_max) * 57.2958, sd4 * 57.2958, sd2 * 57.2958);
    /* the rest at the tests' limit */
    settle(&e, &s, 20.0, 4.0, 300, &o);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(o.valid & GRIP_EST_V_YAW_REF);
    assert_true(o.valid & GRIP_EST_V_FZ);
    assert_true(o.valid & GRIP_EST_V_WHEEL(0));
    assert_true(fabs(dq(o.vx) - 20.0) < 0.05);
    /* outer (right) wheels carry more load in a left turn */
    assert_true(dl(o.fz[1]) > dl(o.fz[0]));
    assert_true(dl(o.fz[3]) > dl(o.fz[2]));
    /* the lateral forces carry the car: sum Fy ~ m ay within 10 % */
    assert_true(fabs(dl(o.fy_axle[0]) + dl(o.fy_axle[1]) - 1450.0 * 4.0) < 580.0);
    assert_true(dq(o.fy_margin_front) > 0.0);
    printf("# circle 20 m/s, 4 m/s^2: beta %.3f deg, r_ref %.4f r %.4f, mu %.3f conf %.2f, steer %d\n",
           dq(o.beta) * 57.2958, dq(o.yaw_rate_ref), dq(o.yaw_rate), dq(o.mu), dq(o.mu_conf), (int)o.steer_char);
}

/* A friction source saying mu_road +- 0.02 twice a second, for 5 s of s. */
static void friction_source(grip_est_t *e, grip_input_sample_t *s, double mu_road, grip_est_output_t *o)
{
    int k;
    for (k = 0; k < 10; ++k) {
        assert_int_equal(grip_est_measure_friction(e, qs(mu_road), qs(0.02)), GRIP_OK);
        run(e, s, 50, o);
    }
}

/* grip_est_measure_friction: refusals leave the state as it was; on the
 * 3.5 m/s^2 circle, where beta is withheld while mu is at its prior (the
 * friction in use, 0.36, cannot be excluded: test_steady_circle), a source
 * saying dry (0.95 +- 0.02, twice a second) excludes it: beta valid at the
 * default 1 deg limit, mu near the source's over the tire's own peak
 * (mu's random walk, EST_Q_MU, widens its deviation by 0.05 in a second, so
 * a source must repeat); mu itself is not flagged valid on the source's
 * word. A source saying ice (0.45 +- 0.02) moves mu down
 * and keeps beta withheld. */
static void test_friction_from_outside(void **state)
{
    grip_est_t e, before;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    double mu_dry, sd_dry, sd_none, mu_ice, sd_ice, mu0;
    (void)state;
    assert_int_equal(grip_est_measure_friction(NULL, qs(0.9), qs(0.05)), GRIP_ERR_NULL);
    memset(&e, 0, sizeof e);
    assert_int_equal(grip_est_measure_friction(&e, qs(0.9), qs(0.05)), GRIP_ERR_STATE);
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 3.5);
    run(&e, &s, 300, &o);
    sd_none = dq(o.beta_sd);
    assert_false(o.valid & GRIP_EST_V_BETA);
    before = e;
    assert_int_equal(grip_est_measure_friction(&e, qs(0.04), qs(0.05)), GRIP_ERR_INPUT);
    assert_int_equal(grip_est_measure_friction(&e, qs(2.01), qs(0.05)), GRIP_ERR_INPUT);
    assert_int_equal(grip_est_measure_friction(&e, qs(0.9), qs(0.009)), GRIP_ERR_INPUT);
    assert_int_equal(grip_est_measure_friction(&e, qs(0.9), qs(1.01)), GRIP_ERR_INPUT);
#if !GRIP_ARITH_FIXED
    assert_int_equal(grip_est_measure_friction(&e, (grip_real_t)NAN, qs(0.05)), GRIP_ERR_INPUT);
    assert_int_equal(grip_est_measure_friction(&e, qs(0.9), (grip_real_t)NAN), GRIP_ERR_INPUT);
#endif
    assert_memory_equal(&e, &before, sizeof e);
    mu0 = 0.5 * (dq(e.mu0[0]) + dq(e.mu0[1]));
    friction_source(&e, &s, 0.95, &o);
    mu_dry = dq(o.mu);
    sd_dry = dq(o.beta_sd);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(sd_none > dq(cfg.beta_sd_max) && sd_dry <= dq(cfg.beta_sd_max));
    /* the source's friction is not flagged as one the tires showed: mu_sd
     * is the filter's (with the source), mu_conf and V_MU the tires' own */
    assert_true(dq(o.mu_sd) < 0.05);
    assert_true(dq(o.mu_conf) < 0.5);
    assert_false(o.valid & GRIP_EST_V_MU);
    assert_true(fabs(mu_dry - 0.95 / mu0) < 0.1);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    run(&e, &s, 300, &o);
    friction_source(&e, &s, 0.45, &o);
    mu_ice = dq(o.mu);
    sd_ice = dq(o.beta_sd);
    assert_false(o.valid & GRIP_EST_V_BETA);
    assert_true(mu_ice < mu_dry - 0.3);
    printf("# circle 20 m/s, 3.5 m/s^2, beta_sd: %.2f deg without a source, %.2f deg with 0.95 +- 0.02 (mu %.3f, "
           "tire peak %.3f), %.2f deg with 0.45 +- 0.02 (mu %.3f)\n",
           sd_none * 57.2958, sd_dry * 57.2958, mu_dry, mu0, sd_ice * 57.2958, mu_ice);
}

/* A fresh estimator with the consumer's limits vx_max [m/s], fy_max [N], 300
 * steps of s. */
static void run_with_limits(grip_est_t *e, grip_est_config_t *cfg, grip_input_sample_t *s, double vx_max,
                            double fy_max, grip_est_output_t *o)
{
    cfg->vx_sd_max = qs(vx_max);
    cfg->fy_sd_max = ql(fy_max);
    assert_int_equal(grip_est_init(e, cfg), GRIP_OK);
    run(e, s, 300, o);
}

/* The consumer's limits of vx's and the axle forces' deviations: 0 (the
 * default) sets none; a limit below the deviation withholds V_VX, or V_AXLE
 * and V_MARGIN (not V_BETA); a negative one is refused. */
static void test_consumer_limits(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    double vx_sd, fy_sd;
    (void)state;
    settle(&e, &s, 20.0, 4.0, 300, &o);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_true(o.valid & GRIP_EST_V_AXLE);
    assert_true(o.valid & GRIP_EST_V_MARGIN);
    vx_sd = dq(o.vx_sd);
    fy_sd = (dl(o.fy_axle_sd[0]) > dl(o.fy_axle_sd[1])) ? dl(o.fy_axle_sd[0]) : dl(o.fy_axle_sd[1]);
    assert_true(vx_sd > 0.05 && vx_sd < 1.0);
    assert_true(fy_sd > 10.0);
    printf("# circle 20 m/s, 4 m/s^2: vx_sd %.3f m/s, fy_axle_sd %.0f / %.0f N\n", vx_sd, dl(o.fy_axle_sd[0]),
           dl(o.fy_axle_sd[1]));
    /* limits above the deviations: as without; below them: withheld, the
     * sideslip not */
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.beta_sd_max = qs(TEST_BETA_SD_MAX);
    run_with_limits(&e, &cfg, &s, 2.0 * vx_sd, 2.0 * fy_sd, &o);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_true(o.valid & GRIP_EST_V_AXLE);
    run_with_limits(&e, &cfg, &s, 0.5 * vx_sd, 0.5 * fy_sd, &o);
    assert_false(o.valid & GRIP_EST_V_VX);
    assert_false(o.valid & GRIP_EST_V_AXLE);
    assert_false(o.valid & GRIP_EST_V_MARGIN);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(o.vx_sd > 0 && o.fy_axle_sd[0] > 0);
    /* refused */
    cfg.vx_sd_max = qs(-0.1);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    cfg.vx_sd_max = 0;
    cfg.fy_sd_max = ql(-1.0);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
}

/* A steady turn of the default car on a road banked by bank [rad] (ISO:
 * left edge up positive) that the configuration does not give: speed v,
 * yaw rate r. The accelerometer reads specific force, the kinematic
 * r v less gravity's pull along the road, g_y = -g sin(bank); the tires
 * carry that specific force, and the steering is the linear bicycle's for
 * it (the understeer term acts on the tire forces, the kinematic term on
 * the path). The body rolls by the default gradient on the specific force. */
static void banked(grip_input_sample_t *s, double v, double r, double bank)
{
    double ay_f = r * v + 9.80665 * sin(bank);
    double swa = 15.5 * (2.7 * r / ((v > 0.1) ? v : 1.0) + 2.7 * 3.7e-4 * ay_f);
    circle(s, v, 0.0);
    turn(s, v, r, swa);
    s->value[GRIP_IN_AY] = qs(ay_f * (1.0 + 9.80665 * 0.0088));
}

/* The linear bicycle's sideslip of the steady turn banked() gives: the rear
 * axle carries lf / l of the specific force, at the estimator's own rear
 * cornering stiffness (2 c_alpha[1] at static load). */
static double banked_beta(const grip_est_t *e, double v, double r, double bank)
{
    double ay_f = r * v + 9.80665 * sin(bank);
    return r * 1.6 / v - 1450.0 * ay_f * (1.1 / 2.7) / (2.0 * fabs(dl(e->c_alpha[1])));
}

/* Runs n steps of sample s and returns the largest |beta - beta_true| over
 * the steps from `from` on that are flagged V_BETA (every one of them must
 * be). */
static double banked_run(grip_est_t *e, grip_input_sample_t *s, int n, int from, double beta_true,
                         grip_est_output_t *o)
{
    double worst = 0.0;
    int k;
    for (k = 0; k < n; ++k) {
        assert_int_equal(grip_est_step(e, s, o), GRIP_OK);
        assert_finite_out(o);
        if (k >= from) {
            assert_true(o->valid & GRIP_EST_V_BETA);
            if (fabs(dq(o->beta) - beta_true) > worst) {
                worst = fabs(dq(o->beta) - beta_true);
            }
        }
    }
    return worst;
}

/* The road's bank is estimated (est_road.c): at rest from the
 * accelerometer, moving from the ay update's correction of vy. Without it
 * the bank's gravity went into vy and the gyro offset: here, where the
 * tire model is the car's, beta 0.07 deg off on the crossfall (0.06 with
 * it) and 0.20 deg on the banked turn (0.115 with it; est_road made a
 * no-op for the figures without); on the independent judge's 8
 * deg banked curve, with a tire model that is not the car's, 2 - 15 deg RMS,
 * flagged valid (docs/estimator/road.md). In a steady turn at constant
 * speed a gyro offset b reads as a bank b vx: the two share the kinematic
 * imbalance (here 0.167 m/s^2, 12 %, went to the offset). */
static void make_bank_est(grip_est_t *e)
{
    grip_est_config_t cfg;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.beta_sd_max = qs(TEST_BETA_SD_MAX);
    cfg.bank_est = 1u;
    assert_int_equal(grip_est_init(e, &cfg), GRIP_OK);
}

static void test_banked_road(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    double worst, bt;
    (void)state;
    /* at rest on a 5 deg crossfall (left edge up), then straight along it
     * at 20 m/s: the tires push up the slope */
    make_est(&e);
    banked(&s, 0.0, 0.0, 0.0873);
    run(&e, &s, 200, &o);
    assert_true(dq(e.road_gy) == 0.0);      /* bank_est 0 (default): the configured plane only */
    make_bank_est(&e);
    run(&e, &s, 200, &o);
    printf("# at rest on 5 deg: road_gy %.3f m/s^2 (gravity -0.853)\n", dq(e.road_gy));
    assert_true(fabs(dq(e.road_gy) + 9.80665 * sin(0.0873)) < 0.05);
    banked(&s, 20.0, 0.0, 0.0873);
    bt = banked_beta(&e, 20.0, 0.0, 0.0873);
    worst = banked_run(&e, &s, 1000, 300, bt, &o);
    printf("# straight on the 5 deg crossfall: beta %.3f deg (bicycle %.3f), worst error %.3f deg\n",
           dq(o.beta) * 57.2958, bt * 57.2958, worst * 57.2958);
    assert_true(worst < 0.1 / 57.2958);
    /* a turn of R = 80 m at 20 m/s banked 8 deg towards its centre (left
     * turn: left edge down), the bank unknown when the car enters it */
    make_bank_est(&e);
    circle(&s, 20.0, 0.0);
    run(&e, &s, 200, &o);
    banked(&s, 20.0, 0.25, -0.1396);
    bt = banked_beta(&e, 20.0, 0.25, -0.1396);
    worst = banked_run(&e, &s, 1500, 500, bt, &o);
    printf("# 8 deg banked turn: beta %.3f deg (bicycle %.3f), worst error after 5 s %.3f deg, road_gy %.3f m/s^2 "
           "(gravity 1.365), gyro offset %.5f rad/s\n", dq(o.beta) * 57.2958, bt * 57.2958, worst * 57.2958,
           dq(e.road_gy), dq(o.yaw_rate_bias));
    assert_true(worst < 0.15 / 57.2958);
    assert_true(fabs(dq(e.road_gy) - 9.80665 * sin(0.1396)) < 0.2);
    assert_true(fabs(dq(e.road_gy) + 20.0 * dq(o.yaw_rate_bias) - 9.80665 * sin(0.1396)) < 0.05);
}

/* Non-finite, saturated, invalid and stale inputs, then recovery. */
static void test_bad_inputs_and_recovery(void **state)
{
    grip_est_t e;
    grip_est_output_t o, ref;
    grip_input_sample_t s, bad;
    int id;
    (void)state;
    settle(&e, &s, 20.0, 3.0, 200, &ref);
    for (id = 0; id < 8; ++id) {
        bad = s;
#if GRIP_ARITH_FIXED
        bad.value[id] = INT32_MAX;          /* saturated / out of range */
#else
        bad.value[id] = (id & 1) ? NAN : INFINITY;
#endif
        run(&e, &bad, 3, &o);               /* shorter than the hold time */
        if (id == GRIP_IN_STEER_ANGLE || id == GRIP_IN_YAW_RATE || id == GRIP_IN_AY) {
            assert_true(o.valid & GRIP_EST_V_BETA);   /* held */
        }
        run(&e, &bad, 20, &o);              /* beyond the hold time */
        if (id == GRIP_IN_STEER_ANGLE) {
            assert_true(o.flags & GRIP_EST_F_NO_STEER);
            assert_false(o.valid & GRIP_EST_V_BETA);
            assert_false(o.valid & GRIP_EST_V_YAW_REF);
        }
        if (id == GRIP_IN_YAW_RATE) {
            assert_true(o.flags & GRIP_EST_F_NO_YAW);
            assert_false(o.valid & GRIP_EST_V_BETA);
        }
        if (id == GRIP_IN_AY) {
            assert_true(o.flags & GRIP_EST_F_NO_AY);
            assert_false(o.valid & GRIP_EST_V_BETA);
            assert_false(o.valid & GRIP_EST_V_FZ);
        }
        if (id < 4) {
            assert_false(o.valid & GRIP_EST_V_WHEEL(id));
            assert_true(o.valid & GRIP_EST_V_VX);     /* three wheels left */
        }
        /* valid flag cleared instead: same handling */
        bad = s;
        bad.valid[id] = 0;
        bad.value[id] = 0;
        bad.fault[id] = GRIP_SIG_STALE;
        run(&e, &bad, 20, &o);
        run(&e, &s, 200, &o);               /* recovery */
        printf("# input %d lost and back: beta %.5f (undisturbed %.5f) rad, mu %.3f, vx %.3f\n", id,
               dq(o.beta), dq(ref.beta), dq(o.mu), dq(o.vx));
        assert_true(o.valid & GRIP_EST_V_BETA);
        assert_true(o.valid & GRIP_EST_V_WHEEL(0));
        assert_true(fabs(dq(o.beta) - dq(ref.beta)) < 0.005);
        assert_true(fabs(dq(o.vx) - 20.0) < 0.1);
    }
    /* every input gone for 2 s: nothing valid but finite, then recovery */
    memset(&bad, 0, sizeof bad);
    run(&e, &bad, 200, &o);
    assert_false(o.valid & GRIP_EST_V_VX);
    assert_false(o.valid & GRIP_EST_V_BETA);
    assert_true(o.flags & GRIP_EST_F_NO_WHEELS);
    run(&e, &s, 300, &o);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(fabs(dq(o.beta) - dq(ref.beta)) < 0.005);
}

static void test_standstill_and_reversing(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    (void)state;
    make_est(&e);
    circle(&s, 0.0, 0.0);
    s.value[GRIP_IN_STEER_ANGLE] = qs(2.0);
    run(&e, &s, 100, &o);
    assert_true(o.flags & GRIP_EST_F_STANDSTILL);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_false(o.valid & GRIP_EST_V_BETA);
    assert_true(fabs(dq(o.vx)) < 1e-3);
    assert_true(dl(o.fz[0]) > 3000.0);      /* static loads still given */
    /* an accelerometer bias at standstill must not make the car move */
    s.value[GRIP_IN_AX] = qs(0.3);
    run(&e, &s, 500, &o);
    assert_true(fabs(dq(o.vx)) < 1e-3);
    /* reversing with a signed vehicle speed */
    circle(&s, 2.0, 0.0);
    s.value[GRIP_IN_VEHICLE_SPEED] = qs(-2.0);
    s.valid[GRIP_IN_VEHICLE_SPEED] = 1;
    s.fault[GRIP_IN_VEHICLE_SPEED] = GRIP_SIG_OK;
    run(&e, &s, 200, &o);
    assert_true(o.flags & GRIP_EST_F_REVERSING);
    assert_false(o.valid & GRIP_EST_V_BETA);
    assert_false(o.valid & GRIP_EST_V_YAW_REF);
    assert_true(dq(o.vx) < -1.5);
    /* forward again (straight: the synthetic circle's ax = 0 is not
     * consistent with the side slip the observer builds up while it starts) */
    circle(&s, 20.0, 0.0);
    run(&e, &s, 400, &o);
    assert_false(o.flags & GRIP_EST_F_REVERSING);
    assert_true(o.valid & GRIP_EST_V_BETA);
    assert_true(fabs(dq(o.vx) - 20.0) < 0.2);
}

/* A vehicle-speed input that read 3 m/s while the car ran at 15 m/s, then
 * lost, with the car slowing at 1.5 m/s^2: every wheel is 15 m/s above the
 * speed prediction, but no wheel spins while the car decelerates, so the
 * prediction is what is lost and the wheels are taken (counted as four
 * spinning wheels instead, they would leave vx integrating ax from 3 m/s). */
static void test_speed_recovers_after_reference_fault(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    (void)state;
    make_est(&e);
    circle(&s, 15.0, 0.0);
    s.value[GRIP_IN_AX] = qs(-1.5);
    s.value[GRIP_IN_VEHICLE_SPEED] = qs(3.0);
    s.valid[GRIP_IN_VEHICLE_SPEED] = 1;
    s.fault[GRIP_IN_VEHICLE_SPEED] = GRIP_SIG_OK;
    run(&e, &s, 100, &o);
    printf("# vehicle speed input 3 m/s (wheels 15 m/s, -1.5 m/s^2): vx %.3f m/s\n", dq(o.vx));
    assert_true(dq(o.vx) < 4.0);
    s.valid[GRIP_IN_VEHICLE_SPEED] = 0;
    s.fault[GRIP_IN_VEHICLE_SPEED] = GRIP_SIG_STALE;
    s.value[GRIP_IN_VEHICLE_SPEED] = qs(0.0);
    run(&e, &s, 100, &o);
    printf("# vehicle speed 3 m/s lost at 15 m/s, -1.5 m/s^2: vx %.3f m/s 1 s later\n", dq(o.vx));
    assert_true(fabs(dq(o.vx) - 15.0) < 0.2);
    assert_false(o.flags & (GRIP_EST_F_WHEEL_LOCK | GRIP_EST_F_WHEEL_SPIN));
    assert_true(o.valid & GRIP_EST_V_VX);
}

/* The tires' relaxation length at static load (docs/estimator.md, "Tire
 * relaxation"): C_alpha / LATERAL_STIFFNESS from the file; a file with
 * neither that nor PTY1 / PTY2 gives none (0: no lag). */
static void test_relaxation_length(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_mf_params bare;
    int a;
    (void)state;
    make_est(&e);
    for (a = 0; a < 2; ++a) {
        double want = dl(e.c_alpha[a]) / dl(tire()->lateral_stiffness);
        printf("# relaxation length axle %d: %.4f m (C_alpha / c_lat %.4f m)\n", a, dq(e.sig_a[a]), want);
        assert_true(fabs(dq(e.sig_a[a]) - want) < 1e-4);
        assert_true(dq(e.sig_a[a]) > 0.2 && dq(e.sig_a[a]) < 1.0);
    }
    bare = *tire();
    bare.lateral_stiffness = 0;
    bare.pty1 = 0;
    bare.pty2 = 0;
    assert_int_equal(grip_est_config_default(&cfg, &bare), GRIP_OK);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    assert_true(e.sig_a[0] == 0 && e.sig_a[1] == 0);
}

static void test_wheel_lock_spin_steer_lock(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s, bad;
    (void)state;
    settle(&e, &s, 20.0, 0.0, 100, &o);
    /* braking with the rear left wheel locked: vx follows the fastest wheel */
    bad = s;
    bad.value[GRIP_IN_AX] = qs(-4.0);
    bad.value[GRIP_IN_WHEEL_SPEED_RL] = qs(0.0);
    run(&e, &bad, 50, &o);
    assert_true(o.flags & GRIP_EST_F_WHEEL_LOCK);
    assert_true(dq(o.vx) > 17.0 && dq(o.vx) < 20.5);
    assert_true(dq(o.kappa[2]) < -0.9);
    /* driving with a front wheel spinning: vx follows the slowest wheel */
    bad = s;
    bad.value[GRIP_IN_AX] = qs(2.0);
    bad.value[GRIP_IN_WHEEL_SPEED_FL] = qs(35.0);
    run(&e, &bad, 50, &o);
    assert_true(o.flags & GRIP_EST_F_WHEEL_SPIN);
    assert_true(dq(o.kappa[0]) > 0.3);
    assert_true(dq(o.util[0]) <= 1.5 + 1e-4);
    /* steering at lock (beyond the road-wheel limit) for 3 s on a straight
     * road: no car steers there, so the model's slip angles are not the
     * car's; fitted to them, vy went to 2.3 m/s past both axles' peaks and
     * stayed there after the steering recovered (beta 0.12 rad, misfit) */
    bad = s;
    bad.value[GRIP_IN_STEER_ANGLE] = qs(13.0);
    run(&e, &bad, 300, &o);
    assert_true(o.flags & GRIP_EST_F_STEER_LIMIT);
    assert_true(fabs(dq(o.delta)) <= 0.7 + 1e-4);
    assert_false(o.valid & GRIP_EST_V_BETA);
    print_message("steering at lock for 3 s: beta %.4f rad (flagged invalid)\n", dq(o.beta));
    run(&e, &s, 300, &o);
    assert_false(o.flags & (GRIP_EST_F_WHEEL_LOCK | GRIP_EST_F_WHEEL_SPIN | GRIP_EST_F_STEER_LIMIT));
    assert_true(fabs(dq(o.vx) - 20.0) < 0.3);
    assert_true(o.valid & GRIP_EST_V_BETA);
    print_message("3 s after the steering recovered: beta %.5f rad, misfit %d\n", dq(o.beta), (int)e.misfit);
    assert_true(fabs(dq(o.beta)) < 0.005);
    assert_int_equal(e.misfit, 0);
}

/* Cornering at 20 m/s, 4 m/s^2, neither braking nor driving hard, with
 * the inner driven front wheel slipping 12 % (below the 15 % outlier test,
 * as in the wet ramp steer at constant speed): the plain mean of the four wheels would read
 * 3 % (0.6 m/s) high and give the free rear wheels -3 % slip; the spread
 * reference takes the three wheels that agree. */
static void test_one_driven_wheel_slipping(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s, slip;
    (void)state;
    settle(&e, &s, 20.0, 4.0, 300, &o);
    slip = s;
    slip.value[GRIP_IN_WHEEL_SPEED_FL] = qs(1.12 * dq(s.value[GRIP_IN_WHEEL_SPEED_FL]));
    run(&e, &slip, 300, &o);
    printf("# inner front wheel 12 %% high: vx %.3f m/s (true 20, wheel mean 20.6), kappa RL %.4f RR %.4f FL %.3f\n",
           dq(o.vx), dq(o.kappa[2]), dq(o.kappa[3]), dq(o.kappa[0]));
    assert_false(o.flags & (GRIP_EST_F_WHEEL_LOCK | GRIP_EST_F_WHEEL_SPIN));
    assert_true(fabs(dq(o.vx) - 20.0) < 0.1);
    assert_true(fabs(dq(o.kappa[2])) < 0.005 && fabs(dq(o.kappa[3])) < 0.005);
    assert_true(dq(o.kappa[0]) > 0.1);
}

/* Every wheel locked at 20 m/s while the car decelerates at 3 m/s^2 (no
 * ABS): vx integrates ax instead of following the wheels to a false
 * standstill; beta loses its valid bit at once, vx after DR_T = 2 s; with
 * ax back at 0 (stopped) the wheels' standstill is taken. */
static void test_all_wheels_locked(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s, bad;
    int i;
    (void)state;
    settle(&e, &s, 20.0, 0.0, 100, &o);
    bad = s;
    bad.value[GRIP_IN_AX] = qs(-3.0);
    for (i = 0; i < 4; ++i) {
        bad.value[GRIP_IN_WHEEL_SPEED_FL + i] = qs(0.0);
    }
    run(&e, &bad, 100, &o);
    printf("# all wheels locked 1 s at -3 m/s^2 from 20 m/s: vx %.3f (17.0)\n", dq(o.vx));
    assert_true(fabs(dq(o.vx) - 17.0) < 0.1);
    assert_true(o.flags & GRIP_EST_F_WHEEL_LOCK);
    assert_false(o.flags & GRIP_EST_F_STANDSTILL);
    assert_true(o.valid & GRIP_EST_V_VX);
    assert_false(o.valid & GRIP_EST_V_BETA);
    run(&e, &bad, 200, &o);
    assert_false(o.valid & GRIP_EST_V_VX);
    bad.value[GRIP_IN_AX] = qs(0.0);
    run(&e, &bad, 20, &o);
    assert_true(o.flags & GRIP_EST_F_STANDSTILL);
    assert_true(fabs(dq(o.vx)) < 1e-3);
    assert_true(o.valid & GRIP_EST_V_VX);
}

/* Reset keeps the configuration and restarts the observer; the instance
 * stays within the 2 KiB state budget. */
static void test_reset_keeps_config(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    (void)state;
    settle(&e, &s, 20.0, 3.0, 100, &o);
    assert_int_equal(grip_est_reset(&e), GRIP_OK);
    run(&e, &s, 1, &o);
    assert_true(o.flags & GRIP_EST_F_RESET);
    run(&e, &s, 100, &o);
    assert_true(o.valid & GRIP_EST_V_BETA);
    printf("# sizeof(grip_est_t) = %u bytes, sizeof(grip_est_output_t) = %u bytes\n",
           (unsigned)sizeof(grip_est_t), (unsigned)sizeof(grip_est_output_t));
    assert_true(sizeof(grip_est_t) <= 2048u);
}

/* Model-consistency check: the same steady circles (inputs from the linear
 * bicycle of the right tire, ay ramped to 7.5 m/s^2 on a dry road) run
 * through the estimator with the right tire and with a deliberately wrong one
 * (friction scale LMUY * MISFIT_LMUY = 0.6: the model tire saturates where
 * the car does not, the case the saturation-share statistic is for). The
 * right tire must never raise GRIP_EST_F_MODEL_MISFIT; the wrong one must
 * raise it, and V_MU must stay cleared from then on.
 * (Not a cornering-stiffness scale such as LKY x 4: with the body roll in
 * the accelerometer's reading, neither the tangent nor the secant form of
 * mu's column flags it in steady circles, since the filter fits it with a
 * different beta; only an accelerometer 8 % below the kinematics made it
 * show. docs/estimator.md, "7. Checks and validity".) */
#ifndef MISFIT_LMUY
#define MISFIT_LMUY 0.6
#endif
#ifndef MISFIT_AY
#define MISFIT_AY 7.5
#endif
/* Steering lag (cfg.steer_lag): the road-wheel angle (out.delta) follows a
 * steering step as a first order of that time constant, also at 1 kHz with
 * the longest lag (the fixed build keeps the lagged angle x 1024, else the
 * per-step change would round away); out-of-range lags are refused. */
static void test_steering_lag(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    double target, at_tau, at_6tau;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.steer_lag = qs(0.6);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    cfg.steer_lag = qs(-0.01);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    cfg.steer_lag = qs(0.5);
    cfg.rate_hz = 1000u;
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 0.0);
    run(&e, &s, 1000, &o);
    assert_true(fabs(dq(o.delta)) < 1e-4);
    circle(&s, 20.0, 3.0);
    target = dq(s.value[GRIP_IN_STEER_ANGLE]) / 15.5;
    run(&e, &s, 500, &o);
    at_tau = dq(o.delta) / target;
    run(&e, &s, 2500, &o);
    at_6tau = dq(o.delta) / target;
    printf("# steering lag 0.5 s at 1 kHz: road-wheel angle %.4f of the step after 0.5 s (first order %.4f), "
           "%.4f after 3 s (%.4f)\n", at_tau, 1.0 - exp(-1.0), at_6tau, 1.0 - exp(-6.0));
    assert_true(fabs(at_tau - (1.0 - exp(-1.0))) < 0.01);
    assert_true(fabs(at_6tau - (1.0 - exp(-6.0))) < 0.01);
    /* without the lag the angle is the signal's at once */
    make_est(&e);
    run(&e, &s, 1, &o);
    assert_true(fabs(dq(o.delta) / target - 1.0) < 1e-3);
}

/* Steering latency (cfg.steer_latency against cfg.latency): on a steering
 * ramp the model's road-wheel angle (out.delta) is the angle at the state's
 * time, the inertial data's: with the steering 10 ms and the inertial data
 * 20 ms old at 100 Hz, the previous step's angle; with both equally old,
 * the signal's own; out-of-range latencies are refused. */
static double steer_ramp_delta(double latency, double steer_latency, double *swa_now, double *swa_prev)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    int k;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.latency = qs(latency);
    cfg.steer_latency = qs(steer_latency);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 0.0);
    run(&e, &s, 200, &o);
    for (k = 1; k <= 50; ++k) {
        *swa_prev = dq(s.value[GRIP_IN_STEER_ANGLE]);
        s.value[GRIP_IN_STEER_ANGLE] = qs(0.002 * k);    /* 0.2 rad/s at the steering wheel */
        *swa_now = dq(s.value[GRIP_IN_STEER_ANGLE]);
        run(&e, &s, 1, &o);
    }
    return dq(o.delta);
}

static void test_steering_latency(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    double now, prev, d_older, d_same, d_none;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.steer_latency = qs(0.11);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    cfg.steer_latency = qs(-0.01);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    d_older = steer_ramp_delta(0.02, 0.01, &now, &prev) * 15.5;
    d_same = steer_ramp_delta(0.02, 0.02, &now, &prev) * 15.5;
    d_none = steer_ramp_delta(0.0, 0.0, &now, &prev) * 15.5;
    printf("# steering ramp, steering-wheel angle now %.5f, a step before %.5f rad: the model's angle x 15.5 "
           "%.5f (inertial data 10 ms older), %.5f (as old), %.5f (no latencies)\n", now, prev, d_older, d_same, d_none);
    assert_true(fabs(d_older - prev) < 2e-4);
    assert_true(fabs(d_same - now) < 2e-4);
    assert_true(fabs(d_none - now) < 2e-4);
}

/* Pitch (cfg.pitch_gradient): a straight stop at 6 m/s^2 from 25 m/s whose
 * accelerometer pitches 0.005 rad per m/s^2 (reads 5 % high), its wheels
 * 2 % slow (braking slip: vx follows ax, pulled to the wheels at K_SLIP
 * only). With the gradient configured vx ends within that pull of the
 * truth and nearer it than without, where the ax error integrates;
 * out-of-range gradients are refused. */
/* One sample of a straight stop at speed v: every wheel at wheel_ratio v,
 * the accelerometer reading ax and ay */
static void stop_sample(grip_input_sample_t *s, double v, double wheel_ratio, double ax, double ay)
{
    int i;
    circle(s, v, 0.0);
    for (i = 0; i < 4; ++i) {
        s->value[i] = qs(wheel_ratio * v);
    }
    s->value[GRIP_IN_AX] = qs(ax);
    s->value[GRIP_IN_AY] = qs(ay);
}

static double pitch_stop_error(double pitch_gradient)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    const double kp = 0.005, a = -6.0;
    double v = 25.0;
    int k;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.pitch_gradient = qs(pitch_gradient);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, v, 0.0);
    run(&e, &s, 100, &o);
    for (k = 0; k < 200; ++k) {
        v += a * 0.01;
        stop_sample(&s, v, 0.98, a * (1.0 + 9.80665 * kp), 0.0);
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
        assert_finite_out(&o);
    }
    return dq(o.vx) - v;
}

static void test_pitch_gradient(void **state)
{
    grip_est_t e;
    grip_est_config_t cfg;
    double with_pitch, without;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    assert_true(cfg.pitch_gradient == 0);
    cfg.pitch_gradient = qs(0.06);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    cfg.pitch_gradient = qs(-0.001);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_ERR_PARAM);
    with_pitch = pitch_stop_error(0.005);
    without = pitch_stop_error(0.0);
    printf("# 2 s stop at 6 m/s^2, accelerometer pitching 0.005 rad/(m/s^2): vx error %.3f m/s with the "
           "gradient configured, %.3f m/s without\n", with_pitch, without);
    assert_true(fabs(with_pitch) < 0.5 * fabs(without));
    /* what remains is the K_SLIP pull towards wheels 2 % slow: at most
     * 0.02 v (1 - exp(-0.2 / s * 2 s)), 0.16 m/s at 25 m/s */
    assert_true(fabs(with_pitch) < 0.16);
}

/* A straight ABS stop (every wheel 12 % slow: past the tire's peak slip,
 * where its lateral slope is small) with the accelerometer's ay 0.1 m/s^2
 * off: the filter fits the two axles' forces to that offset. Each axle's
 * deviation carries its static share of m kin_acc_sd (est_bound_outputs),
 * so the forces it reports (true: 0) stay within 3 of it. Returns the
 * smallest fy_axle_sd over that share and the largest |fy_axle| / (3 sd)
 * over the steps with V_AXLE. */
static void abs_stop_axle_bound(double *sd_over_floor, double *err_over_3sd)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    const double a = -8.0, ay_off = 0.1;
    double v = 25.0, floor_n[2];
    int k, ax;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    floor_n[0] = dq(cfg.lr) / (dq(cfg.lf) + dq(cfg.lr)) * dl(cfg.mass) * dq(cfg.kin_acc_sd);
    floor_n[1] = dq(cfg.lf) / (dq(cfg.lf) + dq(cfg.lr)) * dl(cfg.mass) * dq(cfg.kin_acc_sd);
    circle(&s, v, 0.0);
    run(&e, &s, 100, &o);
    *sd_over_floor = 1e9;
    *err_over_3sd = 0.0;
    for (k = 0; k < 200; ++k) {
        v += a * 0.01;
        stop_sample(&s, v, 0.88, a, ay_off);
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
        assert_finite_out(&o);
        if (!e.active) {
            continue;
        }
        for (ax = 0; ax < 2; ++ax) {
            *sd_over_floor = fmin(*sd_over_floor, dl(o.fy_axle_sd[ax]) / floor_n[ax]);
            if (o.valid & GRIP_EST_V_AXLE) {
                *err_over_3sd = fmax(*err_over_3sd, fabs(dl(o.fy_axle[ax])) / (3.0 * dl(o.fy_axle_sd[ax])));
            }
        }
    }
}

static void test_axle_bound_carries_ay_offset(void **state)
{
    double sd_over_floor, err_over_3sd;
    (void)state;
    abs_stop_axle_bound(&sd_over_floor, &err_over_3sd);
    printf("# ABS stop, ay 0.1 m/s^2 off: smallest fy_axle_sd / (share m kin_acc_sd) %.3f, largest |fy_axle| / "
           "(3 fy_axle_sd) where V_AXLE %.3f\n", sd_over_floor, err_over_3sd);
    assert_true(sd_over_floor >= 0.999);
    assert_true(err_over_3sd <= 1.0);
}

/* A steady turn at 20 m/s and 6 m/s^2 with the inner front wheel 0.5 %
 * slow (a lightly loaded wheel: its rolling resistance over a small slip
 * stiffness), for 3 s at the longitudinal acceleration ax (the speed held:
 * the wheels say it). Returns the front wheels' |Fx| sum at the end. */
static double undriven_front_fx(double drive_front, double ax)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    assert_int_equal(grip_est_config_default(&cfg, tire()), GRIP_OK);
    cfg.drive_front = qs(drive_front);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    circle(&s, 20.0, 6.0);
    s.value[GRIP_IN_WHEEL_SPEED_FL] = qs(0.995 * dq(s.value[GRIP_IN_WHEEL_SPEED_FL]));
    s.value[GRIP_IN_AX] = qs(ax);
    run(&e, &s, 300, &o);
    return fabs(dl(o.fx[0])) + fabs(dl(o.fx[1]));
}

/* The front wheels of a rear-driven car carry no torque but their rolling
 * resistance while the car is not braking: they work at zero slip
 * (est_tires.c), whatever their speeds say. Unknown drive layout, or
 * braking: the measured slips (the front brakes act). */
static void test_undriven_wheels_work_at_zero_slip(void **state)
{
    double rear_drive = undriven_front_fx(0.0, 0.0);
    double unknown = undriven_front_fx(-1.0, 0.0);
    double front_drive = undriven_front_fx(1.0, 0.0);
    double braking = undriven_front_fx(0.0, -3.0);
    (void)state;
    printf("# turn at 6 m/s^2, inner front wheel 0.5 %% slow: front |Fx| sum %.1f N rear-driven, %.1f N drive "
           "unknown, %.1f N front-driven, %.1f N rear-driven braking at 3 m/s^2\n",
           rear_drive, unknown, front_drive, braking);
    assert_true(unknown > 100.0);
    assert_true(front_drive > 100.0);
    assert_true(braking > 100.0);
    /* what the tire gives at zero slip and the turn's slip angles (its
     * horizontal and vertical shifts) */
    assert_true(rear_drive < 0.1 * unknown);
}

static int misfit_run(const grip_mf_params *t, int *first_flag, int *vmu_after, int *vmu_steps, double *mu_end)
{
    grip_est_t e;
    grip_est_config_t cfg;
    grip_est_output_t o;
    grip_input_sample_t s;
    int k, n_flag = 0;
    double sat_max = 0.0, nis_max = 0.0, conf_max = 0.0, mu_min = 2.0;
    *first_flag = -1;
    *vmu_after = 0;
    *vmu_steps = 0;
    assert_int_equal(grip_est_config_default(&cfg, t), GRIP_OK);
    assert_int_equal(grip_est_init(&e, &cfg), GRIP_OK);
    for (k = 0; k < 1600; ++k) {
        double ay = (k < 200) ? 0.5 : ((k < 700) ? 0.5 + (MISFIT_AY - 0.5) * (k - 200) / 500.0 : MISFIT_AY);
        circle(&s, 20.0, ay);
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
        assert_finite_out(&o);
        sat_max = fmax(sat_max, dq(e.sat_f));
        nis_max = fmax(nis_max, dq(e.nis_f));
        conf_max = fmax(conf_max, dq(o.mu_conf));
        mu_min = fmin(mu_min, dq(o.mu));
        if (o.flags & GRIP_EST_F_MODEL_MISFIT) {
            n_flag += 1;
            if (*first_flag < 0) {
                *first_flag = k;
            }
            assert_true(dq(o.mu_conf) < 0.5);
            /* the sideslip and the model forces are not vouched for either */
            assert_false(o.valid & (GRIP_EST_V_BETA | GRIP_EST_V_AXLE | GRIP_EST_V_MARGIN | GRIP_EST_V_WHEEL(0)));
        }
        if (o.valid & GRIP_EST_V_MU) {
            *vmu_steps += 1;
            if (*first_flag >= 0) {
                *vmu_after += 1;
            }
        }
    }
    *mu_end = dq(o.mu);
    printf("#   max sat_f %.2f, max nis_f %.2f, max mu_conf %.2f, min mu %.3f\n", sat_max, nis_max, conf_max, mu_min);
    return n_flag;
}

/* A steady low-speed turn on rolling wheels (no lateral slip at either
 * axle): the exact speeds of the wheel centres along their headings,
 * ws = (vx - r y) cos d + (vy + r x) sin d, and the path's specific force
 * (ax = -r vy, ay = r vx). */
static void kinematic_turn(grip_input_sample_t *s, double vx, double delta)
{
    const double lf = 1.10, lr = 1.60, l = 2.7;
    const double xw[4] = { lf, lf, -lr, -lr }, yw[4] = { 0.775, -0.775, 0.765, -0.765 };
    double r = vx * tan(delta) / l, vy = r * lr;
    int i;
    circle(s, vx, 0.0);
    for (i = 0; i < 4; ++i) {
        double d = (i < 2) ? delta : 0.0;
        s->value[GRIP_IN_WHEEL_SPEED_FL + i] = qs((vx - r * yw[i]) * cos(d) + (vy + r * xw[i]) * sin(d));
    }
    s->value[GRIP_IN_STEER_ANGLE] = qs(delta * 15.5);
    s->value[GRIP_IN_YAW_RATE] = qs(r);
    s->value[GRIP_IN_AX] = qs(-r * vy);
    s->value[GRIP_IN_AY] = qs(r * vx);
}

/* Each wheel speed projected along its own heading with the lateral
 * velocity and yaw terms: ws / cos(delta) put vx 33 % high at a 30 deg
 * road-wheel angle; a wheel steered that far enters the reference only
 * without unsteered ones (a wrong vy would move vx through it). */
static void test_full_lock_turn(void **state)
{
    static const double v[2] = { 1.5, 2.8 };   /* below V_ON: the filter is off, vy = r lr exactly */
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    int j, k;
    (void)state;
    for (j = 0; j < 2; ++j) {
        make_est(&e);
        kinematic_turn(&s, v[j], 30.0 * 3.14159265358979 / 180.0);
        for (k = 0; k < 300; ++k) {
            assert_true(grip_est_step(&e, &s, &o) >= 0);
        }
        printf("# kinematic turn at 30 deg, %.1f m/s: vx %.4f m/s\n", v[j], dq(o.vx));
        assert_true(fabs(dq(o.vx) - v[j]) < 0.02 * v[j]);
    }
}

/* ax missing beyond the hold time: the outputs that rest on it (wheel
 * loads, sideslip, axle forces, mu) lose their validity; vx stays valid
 * (the wheels) */
static void test_missing_ax(void **state)
{
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    int k;
    (void)state;
    make_est(&e);
    circle(&s, 20.0, 4.0);
    for (k = 0; k < 300; ++k) {
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
    }
    assert_true(o.valid & GRIP_EST_V_BETA);
    s.valid[GRIP_IN_AX] = 0;
    s.value[GRIP_IN_AX] = 0;
    for (k = 0; k < 10; ++k) {
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
    }
    assert_true(o.flags & GRIP_EST_F_NO_AX);
    assert_false(o.valid & (GRIP_EST_V_BETA | GRIP_EST_V_MU | GRIP_EST_V_AXLE | GRIP_EST_V_FZ | GRIP_EST_V_MARGIN));
    assert_true(o.valid & GRIP_EST_V_VX);
    s.valid[GRIP_IN_AX] = 1;
    for (k = 0; k < 10; ++k) {
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
    }
    assert_true(o.valid & GRIP_EST_V_BETA);
}

/* The samples' times against rate_hz: 25 Hz data into a 100 Hz
 * configuration warns on every step and reports no sideslip; 100 Hz with
 * a 20 % jitter does not; no times (0) are not checked */
static void test_step_rate(void **state)
{
    static const int64_t per[3] = { 10000, 12000, 40000 };
    static const int warn[3] = { 0, 0, 1 };
    grip_est_t e;
    grip_est_output_t o;
    grip_input_sample_t s;
    int j, k;
    (void)state;
    for (j = 0; j < 3; ++j) {
        grip_status_t st = GRIP_OK;
        make_est(&e);
        circle(&s, 20.0, 2.0);
        for (k = 1; k < 200; ++k) {
            s.t_us = (int64_t)k * per[j];
            st = grip_est_step(&e, &s, &o);
            if (k > 1) {
                assert_int_equal(st, warn[j] ? GRIP_WARN_RATE : GRIP_OK);
            }
        }
        assert_int_equal((o.flags & GRIP_EST_F_RATE) != 0u, warn[j]);
        assert_int_equal((o.valid & GRIP_EST_V_BETA) != 0u, !warn[j]);
    }
    make_est(&e);
    circle(&s, 20.0, 2.0);
    s.t_us = 0;
    for (k = 0; k < 5; ++k) {
        assert_int_equal(grip_est_step(&e, &s, &o), GRIP_OK);
    }
}

static void test_model_misfit(void **state)
{
    static grip_mf_params wrong;
    int first, vmu_after, vmu_steps, n;
    double mu_end;
    (void)state;
    n = misfit_run(tire(), &first, &vmu_after, &vmu_steps, &mu_end);
    printf("# misfit: right tire: %d flagged steps, V_MU in %d steps, mu %.3f\n", n, vmu_steps, mu_end);
    assert_int_equal(n, 0);
    wrong = *tire();
    wrong.lmuy = qs(dq(wrong.lmuy) * MISFIT_LMUY);
    n = misfit_run(&wrong, &first, &vmu_after, &vmu_steps, &mu_end);
    printf("# misfit: LMUY x %.1f: %d flagged steps (first at step %d), V_MU in %d steps (%d after the flag), "
           "mu %.3f\n", MISFIT_LMUY, n, first, vmu_steps, vmu_after, mu_end);
    assert_true(n > 0);
    assert_int_equal(vmu_after, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_api_errors),
        cmocka_unit_test(test_learned_blob),
        cmocka_unit_test(test_steady_circle),
        cmocka_unit_test(test_friction_from_outside),
        cmocka_unit_test(test_consumer_limits),
        cmocka_unit_test(test_banked_road),
        cmocka_unit_test(test_bad_inputs_and_recovery),
        cmocka_unit_test(test_standstill_and_reversing),
        cmocka_unit_test(test_wheel_lock_spin_steer_lock),
        cmocka_unit_test(test_one_driven_wheel_slipping),
        cmocka_unit_test(test_speed_recovers_after_reference_fault),
        cmocka_unit_test(test_relaxation_length),
        cmocka_unit_test(test_all_wheels_locked),
        cmocka_unit_test(test_reset_keeps_config),
        cmocka_unit_test(test_steering_lag),
        cmocka_unit_test(test_steering_latency),
        cmocka_unit_test(test_pitch_gradient),
        cmocka_unit_test(test_axle_bound_carries_ay_offset),
        cmocka_unit_test(test_undriven_wheels_work_at_zero_slip),
        cmocka_unit_test(test_model_misfit),
        cmocka_unit_test(test_full_lock_turn),
        cmocka_unit_test(test_missing_ax),
        cmocka_unit_test(test_step_rate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
