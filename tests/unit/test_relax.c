/*
 * test_relax.c - the relaxation-length transient (lib/relax) against the
 * float64 reference tools/grip_tools/reference/relax.py (build/golden/relax.txt):
 * five scenarios in which the C state integrates its own transient slips.
 * Plus the analytic step response, no overshoot at the longest step,
 * status codes, NULL, non-finite and out-of-range inputs/params.
 *
 * Tolerances (docs/measured-data-loop.md), on kappa' and alpha':
 *   float: |err| <= 1e-4 * max(|want|, 0.01) + 1e-7
 *   fixed: |err| <= 2e-4 + 2 * 2.8e-6 / dt * |x - x'_prev|
 *          2e-4 absolute (13 QS units) for r_exp and rounding per step (the
 *          filter is contractive, so errors do not grow), plus the effect of
 *          representing dt in QS: its half-unit 2^-17 s changes
 *          phi = 1 - exp(-a) by at most a e^-a (2^-17 / dt) <= 2.8e-6 / dt
 *          relative, applied to the step x - x'_prev (factor 2 margin); that
 *          part is carried to the next rows decaying as exp(-|v| dt / sigma),
 *          as the filter carries it. At dt = 1.2 ms it is 0.5 % of the step.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_relax.h"
#include "grip/grip_q16.h"
#include "golden.h"

#if GRIP_ARITH_FIXED
static grip_real_t to_qs(double x) { return (grip_real_t)llround(x * 65536.0); }
static double from_qs(grip_real_t v) { return (double)v / 65536.0; }
static double tol(double want) { (void)want; return 2e-4; }
static double tol_dt(double dt, double jump) { return dt > 0.0 ? 2.0 * 2.8e-6 / dt * fabs(jump) : 0.0; }
#define TOL_DESC "2e-4 abs + 5.6e-6/dt |x - x'_prev|"
#else
static grip_real_t to_qs(double x) { return (grip_real_t)x; }
static double from_qs(grip_real_t v) { return (double)v; }
static double tol(double want) { return 1e-4 * fmax(fabs(want), 0.01) + 1e-7; }
static double tol_dt(double dt, double jump) { (void)dt; (void)jump; return 0.0; }
#define TOL_DESC "1e-4 rel (floor 0.01) + 1e-7"
#endif

static grip_relax_params golden_params(void)
{
    grip_relax_params p;
    p.sigma_kappa = to_qs(0.25);
    p.sigma_alpha = to_qs(0.55);
    p.v_min = to_qs(0.5);
    p.v_max = to_qs(100.0);
    p.kappa_max = to_qs(1.0);
    p.alpha_max = to_qs(0.5);
    return p;
}

static void test_golden(void **unused)
{
    golden_file g;
    err_stats ek, ea;
    grip_relax_params p = golden_params();
    grip_relax_state s;
    int prev_id = -1, bad = 0;
    double pk = 0.0, pa = 0.0, ck = 0.0, ca = 0.0;
    (void)unused;
    grip_debug_saturation_reset();
    assert_int_equal(golden_open(&g, "relax.txt"), 0);
    err_init(&ek, "relax kappa_t", 0.01);
    err_init(&ea, "relax alpha_t", 0.01);
    while (golden_next(&g) >= 8) {
        int id = (int)golden_num(&g, 0);
        double k = golden_num(&g, 2), a = golden_num(&g, 3), v = golden_num(&g, 4), dt = golden_num(&g, 5);
        double wk = golden_num(&g, 6), wa = golden_num(&g, 7);
        grip_real_t kt, at;
        grip_status_t st;
        double gk, ga;
        if (id != prev_id) {
            assert_int_equal(grip_relax_init(&s, &p, 0, 0), GRIP_OK);
            prev_id = id;
            pk = 0.0;
            pa = 0.0;
            ck = 0.0;
            ca = 0.0;
        }
        {
            double vv = fmin(fmax(fabs(v), 0.5), 100.0) * dt;
            ck = exp(-vv / 0.25) * ck + tol_dt(dt, fmax(fmin(k, 1.0), -1.0) - pk);
            ca = exp(-vv / 0.55) * ca + tol_dt(dt, fmax(fmin(a, 0.5), -0.5) - pa);
        }
        st = grip_relax_step(&s, to_qs(k), to_qs(a), to_qs(v), to_qs(dt), &kt, &at);
        assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
        gk = from_qs(kt);
        ga = from_qs(at);
        err_add(&ek, gk, wk, k, v, dt);
        err_add(&ea, ga, wa, a, v, dt);
        if (fabs(gk - wk) > tol(wk) + ck || fabs(ga - wa) > tol(wa) + ca) {
            if (bad < 5) {
                print_message("relax id %d row %lu: kappa_t %.9g want %.9g, alpha_t %.9g want %.9g\n",
                              id, g.lineno, gk, wk, ga, wa);
            }
            ++bad;
        }
        pk = wk;
        pa = wa;
    }
    golden_close(&g);
    print_message("# tolerance: " TOL_DESC "\n");
    err_print(&ek, "-");
    err_print(&ea, "rad");
    print_message("# saturations: %u\n", (unsigned)grip_debug_saturation_count());
    assert_int_equal(grip_debug_saturation_count(), 0);
    assert_true(ek.n > 1000);
    assert_int_equal(bad, 0);
}

/* constant input at constant speed: x'(t) = x (1 - exp(-v t / sigma)) */
static void test_step_response(void **unused)
{
    grip_relax_params p = golden_params();
    grip_relax_state s;
    grip_real_t kt = 0, at = 0;
    double maxe = 0.0;
    int i;
    (void)unused;
    assert_int_equal(grip_relax_init(&s, &p, 0, 0), GRIP_OK);
    for (i = 1; i <= 200; ++i) {
        double t = 0.002 * i;
        double wa = 0.1 * (1.0 - exp(-15.0 * t / 0.55));
        double wk = -0.2 * (1.0 - exp(-15.0 * t / 0.25));
        assert_int_equal(grip_relax_step(&s, to_qs(-0.2), to_qs(0.1), to_qs(-15.0), to_qs(0.002), &kt, &at),
                         GRIP_OK);
        maxe = fmax(maxe, fmax(fabs(from_qs(at) - wa), fabs(from_qs(kt) - wk)));
        assert_true(fabs(from_qs(at) - wa) <= tol(wa) + 1e-5);
        assert_true(fabs(from_qs(kt) - wk) <= tol(wk) + 1e-5);
    }
    print_message("# step response vs closed form: max|err| = %.3g\n", maxe);
}

/* a step far longer than sigma / v lands exactly on the input, no overshoot */
static void test_long_step_no_overshoot(void **unused)
{
    grip_relax_params p = golden_params();
    grip_relax_state s;
    grip_real_t kt, at;
    (void)unused;
    assert_int_equal(grip_relax_init(&s, &p, 0, 0), GRIP_OK);
    assert_int_equal(grip_relax_step(&s, to_qs(0.3), to_qs(-0.4), to_qs(100.0), to_qs(10.0), &kt, &at),
                     GRIP_OK);
    assert_true(fabs(from_qs(kt) - 0.3) < 1e-5);
    assert_true(fabs(from_qs(at) + 0.4) < 1e-5);
    /* dt = 0 changes nothing */
    assert_int_equal(grip_relax_step(&s, 0, 0, to_qs(30.0), 0, &kt, &at), GRIP_OK);
    assert_true(fabs(from_qs(kt) - 0.3) < 1e-5);
}

static void test_status(void **unused)
{
    grip_relax_params p = golden_params(), bad;
    grip_relax_state s;
    grip_real_t kt = to_qs(1.0), at = to_qs(1.0);
    (void)unused;
    assert_int_equal(grip_relax_init(NULL, &p, 0, 0), GRIP_ERR_NULL);
    assert_int_equal(grip_relax_init(&s, NULL, 0, 0), GRIP_ERR_NULL);
    assert_int_equal(grip_relax_step(&s, 0, 0, 0, 0, &kt, &at), GRIP_ERR_STATE);
    assert_true(kt == 0 && at == 0);
    bad = p;
    bad.sigma_alpha = 0;
    assert_int_equal(grip_relax_init(&s, &bad, 0, 0), GRIP_ERR_PARAM);
    bad = p;
    bad.v_min = to_qs(200.0);
    assert_int_equal(grip_relax_params_check(&bad), GRIP_ERR_PARAM);
    bad = p;
    bad.alpha_max = to_qs(2.0);
    assert_int_equal(grip_relax_params_check(&bad), GRIP_ERR_PARAM);
    assert_int_equal(grip_relax_params_check(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_relax_init(&s, &p, to_qs(5.0), 0), GRIP_WARN_CLAMPED);
    assert_true(fabs(from_qs(s.kappa_t) - 1.0) < 1e-6);
    assert_int_equal(grip_relax_init(&s, &p, 0, 0), GRIP_OK);
    assert_int_equal(grip_relax_step(NULL, 0, 0, 0, 0, NULL, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_relax_step(&s, 0, 0, to_qs(10.0), to_qs(-0.1), &kt, &at), GRIP_ERR_INPUT);
    assert_int_equal(grip_relax_step(&s, 0, 0, to_qs(10.0), to_qs(11.0), &kt, &at), GRIP_ERR_INPUT);
    assert_int_equal(grip_relax_step(&s, to_qs(3.0), to_qs(-3.0), to_qs(500.0), to_qs(1.0), &kt, &at),
                     GRIP_WARN_CLAMPED);
    assert_true(fabs(from_qs(kt) - 1.0) < 1e-5 && fabs(from_qs(at) + 0.5) < 1e-5);
#if !GRIP_ARITH_FIXED
    assert_int_equal(grip_relax_step(&s, NAN, 0, 1.0f, 0.01f, &kt, &at), GRIP_ERR_INPUT);
    assert_int_equal(grip_relax_step(&s, 0, 0, INFINITY, 0.01f, &kt, &at), GRIP_ERR_INPUT);
    assert_true(kt == 0.0f && at == 0.0f);
    bad = p;
    bad.sigma_kappa = NAN;
    assert_int_equal(grip_relax_params_check(&bad), GRIP_ERR_PARAM);
#endif
    /* the state survived the errors */
    assert_true(fabs(from_qs(s.kappa_t) - 1.0) < 1e-5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden),
        cmocka_unit_test(test_step_response),
        cmocka_unit_test(test_long_step_no_overshoot),
        cmocka_unit_test(test_status),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
