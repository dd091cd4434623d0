/*
 * test_brush_inputs.c - the brush-model family on bad inputs and parameter
 * sets (clear status, zero and finite outputs, never NaN), extreme finite
 * inputs (finite, bounded outputs), mirror symmetry, and consistency between
 * the models (Neo-FIALA reduces to FIALA and to the brush model when its
 * extra effects are switched off). Runs in both builds.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_brush.h"

#if GRIP_ARITH_FIXED
#define QS(v) ((grip_real_t)lround((v) * 65536.0))
#define QL(v) ((grip_real_t)lround((v) * 256.0))
#define DQS(v) ((double)(v) / 65536.0)
#define DQL(v) ((double)(v) / 256.0)
#define LSB_L (1.0 / 256.0)
#else
#define QS(v) ((grip_real_t)(v))
#define QL(v) ((grip_real_t)(v))
#define DQS(v) ((double)(v))
#define DQL(v) ((double)(v))
#define LSB_L 0.0
#endif

static grip_fiala_params fiala_set(void)
{
    grip_fiala_params p;
    p.ky = QL(60000.0);
    p.mu = QS(1.0);
    p.l = QS(0.2);
    p.fz_min = QL(200.0);
    p.fz_max = QL(10000.0);
    p.alpha_max = QS(0.6);
    return p;
}

static grip_brush_params brush_set(void)
{
    grip_brush_params p;
    p.kx = QL(80000.0);
    p.mu_s = QS(1.1);
    p.mu_d0 = QS(0.9);
    p.a_v = QS(0.005);
    p.n = 4;
    p.fz_min = QL(200.0);
    p.fz_max = QL(10000.0);
    p.kappa_max = QS(1.0);
    p.v_max = QS(60.0);
    return p;
}

static grip_sakai_params sakai_set(void)
{
    grip_sakai_params p;        /* seed Table 2.1 (mu_s, mu_d, l chosen) */
    p.k = QL(57200.0);
    p.g_y = QL(250000.0);
    p.mu_s = QS(1.0);
    p.mu_d = QS(0.8);
    p.l = QS(0.18);
    p.fz_min = QL(200.0);
    p.fz_max = QL(10000.0);
    p.alpha_max = QS(0.6);
    p.kappa_max = QS(1.0);
    return p;
}

static grip_neofiala_params neofiala_set(void)
{
    grip_neofiala_params p;
    memset(&p, 0, sizeof p);
    p.l = QS(0.16);
    p.w = QS(0.19);
    p.kx = QL(95000.0);
    p.ky = QL(72000.0);
    p.mu_s = QS(1.15);
    p.mu_d0 = QS(0.95);
    p.a_v = QS(0.003);
    p.n = 4;
    p.q0 = QS(0.05);
    p.c_q = QS(0.01);       /* 1/kN */
    p.c_xc = QS(0.002);     /* 1/kN */
    p.eps = QS(0.02);       /* 1/(kN m) */
    p.g_mz = QL(15000.0);
    p.a_x = QL(2.0);
    p.c_gamma = QS(0.15);
    p.h = QS(0.02);
    p.g_my = QL(200000.0);
    p.fz_min = QL(500.0);
    p.fz_max = QL(10000.0);
    p.alpha_max = QS(0.6);
    p.kappa_max = QS(1.0);
    p.gamma_max = QS(0.2);
    p.v_max = QS(60.0);
    return p;
}

static void assert_zero_out(const grip_brush_out *o)
{
    assert_true(o->fx == 0 && o->fy == 0 && o->mz == 0);
    assert_true(DQS(o->rh) == 1.0);
}

static void assert_finite_out(const grip_brush_out *o, double fmax, double mmax)
{
    assert_true(isfinite(DQL(o->fx)) && isfinite(DQL(o->fy)) && isfinite(DQL(o->mz)) && isfinite(DQS(o->rh)));
    assert_true(fabs(DQL(o->fx)) <= fmax && fabs(DQL(o->fy)) <= fmax && fabs(DQL(o->mz)) <= mmax);
    assert_true(DQS(o->rh) >= 0.0 && DQS(o->rh) <= 1.0);
}

static void test_null(void **s)
{
    grip_fiala_params pf = fiala_set();
    grip_brush_params pb = brush_set();
    grip_sakai_params ps = sakai_set();
    grip_neofiala_params pn = neofiala_set();
    grip_brush_out o;
    (void)s;
    assert_int_equal(grip_fiala_eval(&pf, QS(0.1), QL(4000.0), NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_brush_eval(&pb, QS(0.1), QL(4000.0), QS(10.0), NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_sakai_eval(&ps, QS(0.1), QS(0.1), QL(4000.0), NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_neofiala_eval(&pn, QS(0.1), QS(0.1), 0, QL(4000.0), QS(10.0), NULL), GRIP_ERR_NULL);
    o.fx = QL(1.0);
    assert_int_equal(grip_fiala_eval(NULL, QS(0.1), QL(4000.0), &o), GRIP_ERR_NULL);
    assert_zero_out(&o);
    o.fx = QL(1.0);
    assert_int_equal(grip_brush_eval(NULL, QS(0.1), QL(4000.0), QS(10.0), &o), GRIP_ERR_NULL);
    assert_zero_out(&o);
    o.fx = QL(1.0);
    assert_int_equal(grip_sakai_eval(NULL, QS(0.1), QS(0.1), QL(4000.0), &o), GRIP_ERR_NULL);
    assert_zero_out(&o);
    o.fx = QL(1.0);
    assert_int_equal(grip_neofiala_eval(NULL, QS(0.1), QS(0.1), 0, QL(4000.0), QS(10.0), &o), GRIP_ERR_NULL);
    assert_zero_out(&o);
    assert_int_equal(grip_fiala_check_params(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_brush_check_params(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_sakai_check_params(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_neofiala_check_params(NULL), GRIP_ERR_NULL);
}

/* Fz <= 0 is an input error with zero outputs (the rule). */
static void test_load_not_positive(void **s)
{
    grip_fiala_params pf = fiala_set();
    grip_brush_params pb = brush_set();
    grip_sakai_params ps = sakai_set();
    grip_neofiala_params pn = neofiala_set();
    const double fzs[3] = { 0.0, -1.0, -5000.0 };
    grip_brush_out o;
    int i;
    (void)s;
    for (i = 0; i < 3; ++i) {
        grip_real_t fz = QL(fzs[i]);
        assert_int_equal(grip_fiala_eval(&pf, QS(0.1), fz, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_brush_eval(&pb, QS(-0.1), fz, QS(10.0), &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_sakai_eval(&ps, QS(-0.1), QS(0.1), fz, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, QS(-0.1), QS(0.1), 0, fz, QS(10.0), &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
    }
}

/* Parameter errors named by the issue: mu_s < mu_d, n out of range, l or
 * w <= 0; and a few more of each model's validity rules. */
static void test_bad_params(void **s)
{
    grip_brush_out o;
    (void)s;
    {
        grip_fiala_params p = fiala_set();
        assert_int_equal(grip_fiala_check_params(&p), GRIP_OK);
        p.l = 0;
        assert_int_equal(grip_fiala_check_params(&p), GRIP_ERR_PARAM);
        assert_int_equal(grip_fiala_eval(&p, QS(0.1), QL(4000.0), &o), GRIP_ERR_PARAM);
        assert_zero_out(&o);
        p = fiala_set();
        p.mu = QS(-0.5);
        assert_int_equal(grip_fiala_check_params(&p), GRIP_ERR_PARAM);
        p = fiala_set();
        p.fz_min = QL(20000.0);          /* fz_min > fz_max */
        assert_int_equal(grip_fiala_check_params(&p), GRIP_ERR_PARAM);
    }
    {
        grip_brush_params p = brush_set();
        const int32_t bad_n[4] = { 1, 0, -3, GRIP_BRUSH_N_MAX + 1 };
        int i;
        assert_int_equal(grip_brush_check_params(&p), GRIP_OK);
        p.mu_d0 = QS(1.2);              /* mu_s < mu_d */
        assert_int_equal(grip_brush_check_params(&p), GRIP_ERR_PARAM);
        assert_int_equal(grip_brush_eval(&p, QS(-0.1), QL(4000.0), QS(10.0), &o), GRIP_ERR_PARAM);
        assert_zero_out(&o);
        for (i = 0; i < 4; ++i) {
            p = brush_set();
            p.n = bad_n[i];
            assert_int_equal(grip_brush_check_params(&p), GRIP_ERR_PARAM);
            assert_int_equal(grip_brush_eval(&p, QS(-0.1), QL(4000.0), QS(10.0), &o), GRIP_ERR_PARAM);
            assert_zero_out(&o);
        }
        p = brush_set();
        p.n = GRIP_BRUSH_N_MAX;
        assert_int_equal(grip_brush_check_params(&p), GRIP_OK);
        p.n = GRIP_BRUSH_N_MIN;
        assert_int_equal(grip_brush_check_params(&p), GRIP_OK);
    }
    {
        grip_sakai_params p = sakai_set();
        assert_int_equal(grip_sakai_check_params(&p), GRIP_OK);
        p.mu_d = QS(1.5);
        assert_int_equal(grip_sakai_check_params(&p), GRIP_ERR_PARAM);
        p = sakai_set();
        p.l = QS(-0.1);
        assert_int_equal(grip_sakai_check_params(&p), GRIP_ERR_PARAM);
        assert_int_equal(grip_sakai_eval(&p, QS(-0.1), QS(0.1), QL(4000.0), &o), GRIP_ERR_PARAM);
        assert_zero_out(&o);
    }
    {
        grip_neofiala_params p = neofiala_set();
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_OK);
        p.mu_d0 = QS(1.3);
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        p = neofiala_set();
        p.n = GRIP_BRUSH_N_MAX + 1;
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        p = neofiala_set();
        p.l = 0;
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        p = neofiala_set();
        p.w = QS(-0.2);
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        assert_int_equal(grip_neofiala_eval(&p, QS(-0.1), QS(0.1), 0, QL(4000.0), QS(10.0), &o), GRIP_ERR_PARAM);
        assert_zero_out(&o);
        p = neofiala_set();
        p.q0 = QS(0.7);                  /* |q0| <= 0.5 */
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        p = neofiala_set();
        p.g_mz = QL(3000.0);             /* Ky l / G_mz = 3.8 > 1.5 */
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
        p = neofiala_set();
        p.eps = QS(0.2);                 /* eps l Ky = 2.3 > 1.5 */
        assert_int_equal(grip_neofiala_check_params(&p), GRIP_ERR_PARAM);
    }
}

#if !GRIP_ARITH_FIXED
/* Non-finite inputs: GRIP_ERR_INPUT, zero outputs, never NaN. */
static void test_non_finite(void **s)
{
    grip_fiala_params pf = fiala_set();
    grip_brush_params pb = brush_set();
    grip_sakai_params ps = sakai_set();
    grip_neofiala_params pn = neofiala_set();
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    grip_brush_out o;
    int i;
    (void)s;
    for (i = 0; i < 3; ++i) {
        float b = bad[i];
        assert_int_equal(grip_fiala_eval(&pf, b, 4000.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_fiala_eval(&pf, 0.1f, b, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_brush_eval(&pb, b, 4000.0f, 10.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_brush_eval(&pb, -0.1f, 4000.0f, b, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_sakai_eval(&ps, b, 0.1f, 4000.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_sakai_eval(&ps, -0.1f, b, 4000.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, b, 0.1f, 0.0f, 4000.0f, 10.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, -0.1f, b, 0.0f, 4000.0f, 10.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, -0.1f, 0.1f, b, 4000.0f, 10.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, -0.1f, 0.1f, 0.0f, b, 10.0f, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        assert_int_equal(grip_neofiala_eval(&pn, -0.1f, 0.1f, 0.0f, 4000.0f, b, &o), GRIP_ERR_INPUT);
        assert_zero_out(&o);
        pn.ky = b;
        assert_int_equal(grip_neofiala_check_params(&pn), GRIP_ERR_PARAM);
        pn = neofiala_set();
    }
}

/* Every real field of a Neo-FIALA set non-finite in turn: the set is
 * rejected by check, prepare and the validating evaluation (the float build
 * tests all 24 fields with one sum of x - x). */
static void test_neofiala_non_finite_fields(void **s)
{
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    grip_neofiala_params pn = neofiala_set();
    grip_real_t *const fields[24] = {
        &pn.l, &pn.w, &pn.kx, &pn.ky, &pn.mu_s, &pn.mu_d0, &pn.a_v, &pn.q0, &pn.c_q, &pn.c_qm, &pn.c_xc,
        &pn.xi, &pn.eps, &pn.g_mz, &pn.a_x, &pn.c_gamma, &pn.h, &pn.g_my, &pn.fz_min, &pn.fz_max,
        &pn.alpha_max, &pn.kappa_max, &pn.gamma_max, &pn.v_max,
    };
    grip_neofiala_model m;
    grip_brush_out o;
    int i;
    int j;
    (void)s;
    assert_int_equal(grip_neofiala_check_params(&pn), GRIP_OK);
    for (j = 0; j < 24; ++j) {
        for (i = 0; i < 3; ++i) {
            grip_real_t keep = *fields[j];
            *fields[j] = bad[i];
            assert_int_equal(grip_neofiala_check_params(&pn), GRIP_ERR_PARAM);
            assert_int_equal(grip_neofiala_prepare(&pn, &m), GRIP_ERR_PARAM);
            assert_int_equal(grip_neofiala_eval_model(&m, -0.1f, 0.1f, 0.0f, 4000.0f, 10.0f, &o), GRIP_ERR_STATE);
            assert_zero_out(&o);
            assert_int_equal(grip_neofiala_eval(&pn, -0.1f, 0.1f, 0.0f, 4000.0f, 10.0f, &o), GRIP_ERR_PARAM);
            assert_zero_out(&o);
            *fields[j] = keep;
        }
    }
    assert_int_equal(grip_neofiala_eval(&pn, -0.1f, 0.1f, 0.0f, 4000.0f, 10.0f, &o), GRIP_OK);
}
#endif

/* Any finite input: OK or clamped, finite outputs bounded by the friction. */
static void test_extreme_finite(void **s)
{
    grip_fiala_params pf = fiala_set();
    grip_brush_params pb = brush_set();
    grip_sakai_params ps = sakai_set();
    grip_neofiala_params pn = neofiala_set();
    const double ks[9] = { -30000.0, -50.0, -1.0, -0.3, 0.0, 0.2, 1.0, 9.0, 30000.0 };
    const double as[7] = { -30000.0, -3.0, -0.5, 0.0, 0.3, 1.5, 30000.0 };
    const double fzs[5] = { 0.00390625, 1.0, 4000.0, 10000.0, 8000000.0 };
    grip_brush_out o;
    int i;
    int j;
    int k;
    (void)s;
    for (i = 0; i < 9; ++i) {
        for (j = 0; j < 7; ++j) {
            for (k = 0; k < 5; ++k) {
                grip_status_t st;
                double fzc = fzs[k] < 500.0 ? 500.0 : (fzs[k] > 10000.0 ? 10000.0 : fzs[k]);
                st = grip_fiala_eval(&pf, QS(as[j]), QL(fzs[k]), &o);
                assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
                assert_finite_out(&o, 1.01 * 1.0 * 10000.0, 1.0 * 10000.0 * 0.2);
                st = grip_brush_eval(&pb, QS(ks[i]), QL(fzs[k]), QS(as[j]), &o);
                assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
                assert_finite_out(&o, 1.01 * 1.1 * 10000.0, 0.0);
                st = grip_sakai_eval(&ps, QS(ks[i]), QS(as[j]), QL(fzs[k]), &o);
                assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
                assert_finite_out(&o, 1.01 * 1.0 * 10000.0, 1.0 * 10000.0 * 0.18);
                st = grip_neofiala_eval(&pn, QS(ks[i]), QS(as[j]), QS(as[(j + 3) % 7]), QL(fzs[k]),
                                        QS(ks[(i + 4) % 9]), &o);
                assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
                assert_finite_out(&o, 1.2 * 1.15 * fzc, 1.15 * fzc * 0.16);
            }
        }
    }
}

/* Mirror image (alpha, gamma) -> (-alpha, -gamma): Fx, rh unchanged, Fy and
 * Mz change sign. Float: the arithmetic is symmetric, 1e-6 relative. Fixed:
 * rounding is half-up (not symmetric), so the images differ by rounding;
 * bound 1e-4 of mu Fz (measured figure printed). */
#if GRIP_ARITH_FIXED
#define MIRROR_TOL 1.0e-4
#else
#define MIRROR_TOL 1.0e-6
#endif
static double mirror_err(const grip_brush_out *a, const grip_brush_out *b, double f0, double l)
{
    double e = fabs(DQL(a->fx) - DQL(b->fx)) / f0;
    e = fmax(e, fabs(DQL(a->fy) + DQL(b->fy)) / f0);
    return fmax(e, fabs(DQL(a->mz) + DQL(b->mz)) / (f0 * l));
}

static void test_mirror(void **s)
{
    grip_fiala_params pf = fiala_set();
    grip_sakai_params ps = sakai_set();
    grip_neofiala_params pn = neofiala_set();
    const double ks[6] = { -1.0, -0.2, -0.03, 0.0, 0.05, 0.5 };
    const double as[5] = { 0.001, 0.02, 0.07, 0.2, 0.5 };
    const double gs[3] = { 0.0, 0.03, -0.1 };
    double worst = 0.0;
    int i;
    int j;
    int k;
    (void)s;
    for (i = 0; i < 6; ++i) {
        for (j = 0; j < 5; ++j) {
            grip_brush_out a;
            grip_brush_out b;
            if (i == 0) {
                assert_int_equal(grip_fiala_eval(&pf, QS(as[j]), QL(4000.0), &a), GRIP_OK);
                assert_int_equal(grip_fiala_eval(&pf, QS(-as[j]), QL(4000.0), &b), GRIP_OK);
                worst = fmax(worst, mirror_err(&a, &b, 4000.0, 0.2));
            }
            assert_int_equal(grip_sakai_eval(&ps, QS(ks[i]), QS(as[j]), QL(4000.0), &a), GRIP_OK);
            assert_int_equal(grip_sakai_eval(&ps, QS(ks[i]), QS(-as[j]), QL(4000.0), &b), GRIP_OK);
            worst = fmax(worst, mirror_err(&a, &b, 4000.0, 0.18));
            for (k = 0; k < 3; ++k) {
                assert_int_equal(grip_neofiala_eval(&pn, QS(ks[i]), QS(as[j]), QS(gs[k]), QL(4000.0), QS(20.0), &a),
                                 GRIP_OK);
                assert_int_equal(grip_neofiala_eval(&pn, QS(ks[i]), QS(-as[j]), QS(-gs[k]), QL(4000.0), QS(20.0),
                                                    &b), GRIP_OK);
                worst = fmax(worst, mirror_err(&a, &b, 1.15 * 4000.0, 0.16));
            }
        }
    }
    printf("# mirror symmetry: max |err| = %.3e mu Fz (bound %.1e)\n", worst, MIRROR_TOL);
    assert_true(worst <= MIRROR_TOL);
}

/* Neo-FIALA with n = 2, q = 0, mu_s = mu_d, no velocity term and no
 * couplings is the FIALA model; in pure longitudinal slip it is the brush
 * model. Both comparisons run the general core against a different code
 * path. Bound: 2e-4 of mu Fz in float (iteration + rounding), 2e-3 fixed. */
static void test_reductions(void **s)
{
    grip_neofiala_params pn;
    grip_fiala_params pf = fiala_set();
    grip_brush_params pb = brush_set();
#if GRIP_ARITH_FIXED
    const double tol = 2.0e-3;
#else
    const double tol = 2.0e-4;
#endif
    double worst = 0.0;
    int i;
    (void)s;
    memset(&pn, 0, sizeof pn);
    pn.l = pf.l;
    pn.w = QS(0.2);
    pn.kx = QL(80000.0);
    pn.ky = pf.ky;
    pn.mu_s = pf.mu;
    pn.mu_d0 = pf.mu;
    pn.n = 2;
    pn.fz_min = pf.fz_min;
    pn.fz_max = pf.fz_max;
    pn.alpha_max = pf.alpha_max;
    pn.kappa_max = QS(1.0);
    pn.gamma_max = QS(0.1);
    pn.v_max = QS(60.0);
    assert_int_equal(grip_neofiala_check_params(&pn), GRIP_OK);
    for (i = -60; i <= 60; ++i) {
        double a = 0.01 * i;
        grip_brush_out x;
        grip_brush_out y;
        double e;
        assert_int_equal(grip_neofiala_eval(&pn, 0, QS(a), 0, QL(4000.0), QS(20.0), &x), GRIP_OK);
        assert_int_equal(grip_fiala_eval(&pf, QS(a), QL(4000.0), &y), GRIP_OK);
        e = fabs(DQL(x.fy) - DQL(y.fy)) / 4000.0;
        e = fmax(e, fabs(DQL(x.mz) - DQL(y.mz)) / (4000.0 * 0.2));
        worst = fmax(worst, e);
        assert_true(e <= tol);
    }
    printf("# Neo-FIALA (n=2, no couplings) vs FIALA: max |err| = %.3e mu Fz\n", worst);
    worst = 0.0;
    pn.kx = pb.kx;
    pn.mu_s = pb.mu_s;
    pn.mu_d0 = pb.mu_d0;
    pn.n = pb.n;
    for (i = -100; i <= 100; ++i) {
        double k = 0.01 * i;
        grip_brush_out x;
        grip_brush_out y;
        double e;
        pb.a_v = 0;
        assert_int_equal(grip_neofiala_eval(&pn, QS(k), 0, 0, QL(4000.0), QS(20.0), &x), GRIP_OK);
        assert_int_equal(grip_brush_eval(&pb, QS(k), QL(4000.0), QS(20.0), &y), GRIP_OK);
        e = fabs(DQL(x.fx) - DQL(y.fx)) / (1.1 * 4000.0);
        worst = fmax(worst, e);
        assert_true(e <= tol);
        assert_true(DQL(x.fy) == 0.0 && DQL(x.mz) == 0.0);
    }
    printf("# Neo-FIALA (pure longitudinal) vs brush: max |err| = %.3e mu Fz\n", worst);
}

/* Physical sanity of the Table 2.1 case: braking force grows from zero,
 * stays below mu_s Fz and ends at the sliding value mu_d Fz when locked;
 * combined slip reduces the lateral force. */
static void test_sakai_table21(void **s)
{
    grip_sakai_params p = sakai_set();
    grip_brush_out o;
    grip_brush_out o2;
    double prev = 0.0;
    int i;
    (void)s;
    for (i = 0; i <= 100; ++i) {
        assert_int_equal(grip_sakai_eval(&p, QS(-0.01 * i), 0, QL(4000.0), &o), GRIP_OK);
        assert_true(DQL(o.fx) <= 0.0);
        assert_true(-DQL(o.fx) <= 1.0 * 4000.0 + 1.0);
        if (i <= 3) {
            assert_true(-DQL(o.fx) >= prev);
        }
        prev = -DQL(o.fx);
    }
    assert_true(fabs(-DQL(o.fx) - 0.8 * 4000.0) < 1.0);
    assert_int_equal(grip_sakai_eval(&p, 0, QS(0.05), QL(4000.0), &o), GRIP_OK);
    assert_int_equal(grip_sakai_eval(&p, QS(-0.05), QS(0.05), QL(4000.0), &o2), GRIP_OK);
    assert_true(DQL(o.fy) < 0.0 && fabs(DQL(o2.fy)) < fabs(DQL(o.fy)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null),
        cmocka_unit_test(test_load_not_positive),
        cmocka_unit_test(test_bad_params),
#if !GRIP_ARITH_FIXED
        cmocka_unit_test(test_non_finite),
        cmocka_unit_test(test_neofiala_non_finite_fields),
#endif
        cmocka_unit_test(test_extreme_finite),
        cmocka_unit_test(test_mirror),
        cmocka_unit_test(test_reductions),
        cmocka_unit_test(test_sakai_table21),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
