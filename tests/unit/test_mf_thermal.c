/*
 * test_mf_thermal.c - the temperature-dependent Magic Formula with its
 * surface temperature state (lib/mf_thermal) against the float64 reference
 * tools/grip_tools/reference/mf_thermal.py (build/golden/mf_thermal.txt): forces at
 * fixed temperatures over the valid box, and closed-loop time series
 * (fish hook, brake-and-cool, cold tire in combined slip, extreme corner)
 * in which the C state integrates its own temperature. Plus the analytic
 * cooling solution, the equilibrium temperature, stability at the largest
 * step, status codes, NULL, non-finite/extreme inputs, and saturation in
 * the DEBUG_SAT build.
 *
 * Tolerances (docs/mf89-thermal.md), peak = max(|Dx(T)|, |Dy(T)|) Fz/Fz0 + |Sv|:
 *   forces  float: 1e-4 * Fz            fixed: 0.005 * peak + 0.03 N
 *   q       float: 1e-4 * Fz * Vs + 1e-5 |q|   fixed: (0.005 * peak + 0.03 N) * Vs + 0.005 |q|
 *   T       float: 2e-4 * excursion + 0.002 K  fixed: 0.005 * excursion + 0.05 K
 *           (excursion = running max |T_ref - T_init| of the scenario: the
 *           temperature rise inherits the relative error of q)
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_mf_thermal.h"
#include "grip/grip_q16.h"
#include "golden.h"

#if GRIP_ARITH_FIXED
static grip_real_t to_qs(double x) { return (grip_real_t)llround(x * 65536.0); }
static grip_real_t to_ql(double x) { return (grip_real_t)llround(x * 256.0); }
static double from_qs(grip_real_t v) { return (double)v / 65536.0; }
static double from_ql(grip_real_t v) { return (double)v / 256.0; }
#define F_TOL_DESC "0.005 peak + 0.03 N"
static double tol_force(double fz, double peak) { (void)fz; return 0.005 * peak + 0.03; }
static double tol_q(double fz, double peak, double vs, double q)
{
    return tol_force(fz, peak) * vs + 0.005 * fabs(q);
}
#define T_TOL_DESC "0.005 exc + 0.05 K"
static double tol_t(double excursion) { return 0.005 * excursion + 0.05; }
#else
static grip_real_t to_qs(double x) { return (grip_real_t)x; }
static grip_real_t to_ql(double x) { return (grip_real_t)x; }
static double from_qs(grip_real_t v) { return (double)v; }
static double from_ql(grip_real_t v) { return (double)v; }
#define F_TOL_DESC "1e-4 Fz"
static double tol_force(double fz, double peak) { (void)peak; return 1e-4 * fz; }
static double tol_q(double fz, double peak, double vs, double q)
{
    return tol_force(fz, peak) * vs + 1e-5 * fabs(q);
}
#define T_TOL_DESC "2e-4 exc + 0.002 K"
static double tol_t(double excursion) { return 2e-4 * excursion + 0.002; }
#endif

/* Field table in the order of grip_tools.reference.mf_thermal.PARAM_ORDER. */
typedef struct {
    const char *name;
    size_t offset;
    int ql;
} field_desc;

#define FD(n, ql) { #n, offsetof(grip_mf_thermal_params, n), ql }
static const field_desc fields[] = {
    FD(fz0, 1), FD(t0, 0),
    FD(dx0, 1), FD(kx0, 1), FD(cx, 0), FD(ex, 0), FD(shx, 0), FD(svx, 1), FD(ax, 0), FD(bx, 0),
    FD(dy0, 1), FD(ky0, 1), FD(cy, 0), FD(ey, 0), FD(shy, 0), FD(svy, 1), FD(ay, 0), FD(by, 0),
    FD(bxa, 0), FD(cxa, 0), FD(exa, 0), FD(shxa, 0), FD(bys, 0), FD(cys, 0), FD(eys, 0), FD(shys, 0),
    FD(svys, 1), FD(w, 1), FD(kappa, 0),
    FD(fz_max, 1), FD(alpha_max, 0), FD(slip_max, 0), FD(v_max, 0), FD(t_min, 0), FD(t_max, 0),
};
#define NFIELDS ((int)(sizeof(fields) / sizeof(fields[0])))

static grip_mf_thermal_params params;
static int params_loaded;

static void load_params(void)
{
    golden_file g;
    int i;
    if (params_loaded) {
        return;
    }
    assert_int_equal((int)sizeof(grip_mf_thermal_params), NFIELDS * (int)sizeof(grip_real_t));
    assert_int_equal(golden_open(&g, "mf_thermal.txt"), 0);
    while (golden_next(&g) > 0) {
        if (strcmp(g.field[0], "P") == 0) {
            assert_int_equal(g.nfields, NFIELDS + 1);
            for (i = 0; i < NFIELDS; ++i) {
                double v = golden_num(&g, 1 + i);
                grip_real_t *dst = (grip_real_t *)(void *)((char *)&params + fields[i].offset);
                *dst = fields[i].ql ? to_ql(v) : to_qs(v);
            }
            params_loaded = 1;
            break;
        }
    }
    golden_close(&g);
    assert_true(params_loaded);
}

static grip_mf_thermal_inputs mk_in(double v, double alpha, double slip, double fz, double t_road)
{
    grip_mf_thermal_inputs in;
    in.v = to_qs(v);
    in.alpha = to_qs(alpha);
    in.slip = to_qs(slip);
    in.fz = to_ql(fz);
    in.t_road = to_qs(t_road);
    return in;
}

static void test_forces_golden(void **state)
{
    golden_file g;
    grip_mf_thermal_state s;
    err_stats ex, ey;
    long bad = 0;
    double worst = 0.0;
    (void)state;
    load_params();
    assert_int_equal(grip_mf_thermal_init(&s, &params, params.t0), GRIP_OK);
    assert_int_equal(golden_open(&g, "mf_thermal.txt"), 0);
    err_init(&ex, "thermal Fx at fixed T", 100.0);
    err_init(&ey, "thermal Fy at fixed T", 100.0);
    grip_debug_saturation_reset();
    while (golden_next(&g) > 0) {
        double a, sl, fz, t, wx, wy, pk, tol, gx, gy;
        grip_mf_thermal_inputs in;
        grip_real_t fx = 0, fy = 0;
        grip_status_t st;
        if (strcmp(g.field[0], "F") != 0) {
            continue;
        }
        a = golden_num(&g, 1);
        sl = golden_num(&g, 2);
        fz = golden_num(&g, 3);
        t = golden_num(&g, 4);
        wx = golden_num(&g, 5);
        wy = golden_num(&g, 6);
        pk = golden_num(&g, 7);
        in = mk_in(0.0, a, sl, fz, 20.0);
        st = grip_mf_thermal_forces(&s, &in, to_qs(t), &fx, &fy);
        if (st != GRIP_OK) {
            fail_msg("status %d at alpha=%g S=%g fz=%g T=%g", (int)st, a, sl, fz, t);
        }
        gx = from_ql(fx);
        gy = from_ql(fy);
        err_add(&ex, gx, wx, a, sl, t);
        err_add(&ey, gy, wy, a, sl, t);
        tol = tol_force(fz, pk);
        if (!(fabs(gx - wx) <= tol && fabs(gy - wy) <= tol)) {
            if (bad < 5) {
                printf("#   beyond: alpha=%.9g S=%.9g fz=%.9g T=%.9g fx %.6g/%.6g fy %.6g/%.6g tol %.3g\n", a,
                       sl, fz, t, gx, wx, gy, wy, tol);
            }
            bad++;
        }
        if (tol > 0.0) {
            double r = fmax(fabs(gx - wx), fabs(gy - wy)) / tol;
            worst = fmax(worst, r);
        }
    }
    golden_close(&g);
    err_print(&ex, "N");
    err_print(&ey, "N");
    printf("#   worst |err| / (" F_TOL_DESC ") = %.3f; saturations: %u\n", worst,
           (unsigned)grip_debug_saturation_count());
    assert_true(ex.n > 1000);
    assert_int_equal(grip_debug_saturation_count(), 0);
    if (bad != 0) {
        fail_msg("%ld of %ld force vectors beyond " F_TOL_DESC, bad, ex.n);
    }
}

static void test_time_series_golden(void **state)
{
    golden_file g;
    grip_mf_thermal_state s;
    err_stats ef, eq, et;
    long bad = 0;
    int scen = -1;
    int nscen = 0;
    double t_init = 0.0;
    double excursion = 0.0;
    double worst_f = 0.0, worst_q = 0.0, worst_t = 0.0;
    double t_max = 0.0;
    (void)state;
    load_params();
    t_max = from_qs(params.t_max);
    assert_int_equal(golden_open(&g, "mf_thermal.txt"), 0);
    err_init(&ef, "thermal series Fx, Fy", 100.0);
    err_init(&eq, "thermal series q", 1000.0);
    err_init(&et, "thermal series T", 1.0);
    grip_debug_saturation_reset();
    while (golden_next(&g) > 0) {
        int k;
        double v, a, sl, fz, tr, dt, tb, wfx, wfy, wq, wvs, wta, pk, tf, tq, tt;
        grip_mf_thermal_inputs in;
        grip_mf_thermal_output out;
        grip_status_t st;
        if (strcmp(g.field[0], "S") != 0) {
            continue;
        }
        k = (int)golden_num(&g, 1);
        v = golden_num(&g, 2);
        a = golden_num(&g, 3);
        sl = golden_num(&g, 4);
        fz = golden_num(&g, 5);
        tr = golden_num(&g, 6);
        dt = golden_num(&g, 7);
        tb = golden_num(&g, 8);
        wfx = golden_num(&g, 9);
        wfy = golden_num(&g, 10);
        wq = golden_num(&g, 11);
        wvs = golden_num(&g, 12);
        wta = golden_num(&g, 13);
        pk = golden_num(&g, 14);
        if (k != scen) {
            /* new scenario: the C state starts from the reference's T_init and
             * then integrates on its own (closed loop) */
            scen = k;
            nscen++;
            t_init = tb;
            excursion = 0.0;
            assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(tb)), GRIP_OK);
        }
        in = mk_in(v, a, sl, fz, tr);
        st = grip_mf_thermal_step(&s, &in, to_qs(dt), &out);
        excursion = fmax(excursion, fabs(wta - t_init));
        if (wta < t_max - 1.0 && st != GRIP_OK) {
            fail_msg("scenario %d: status %d away from the temperature limit", k, (int)st);
        }
        if (st == GRIP_WARN_CLAMPED) {
            assert_true(out.t == params.t_max || out.t == params.t_min);
        } else {
            assert_int_equal(st, GRIP_OK);
        }
        err_add(&ef, from_ql(out.fx), wfx, (double)k, tb, a);
        err_add(&ef, from_ql(out.fy), wfy, (double)k, tb, a);
        err_add(&eq, from_ql(out.q), wq, (double)k, tb, a);
        err_add(&et, from_qs(out.t), wta, (double)k, tb, a);
        tf = tol_force(fz, pk);
        tq = tol_q(fz, pk, wvs, wq);
        tt = tol_t(excursion);
        if (tf > 0.0) {
            worst_f = fmax(worst_f, fmax(fabs(from_ql(out.fx) - wfx), fabs(from_ql(out.fy) - wfy)) / tf);
        }
        if (tq > 0.0) {
            worst_q = fmax(worst_q, fabs(from_ql(out.q) - wq) / tq);
        }
        worst_t = fmax(worst_t, fabs(from_qs(out.t) - wta) / tt);
        if (!(fabs(from_ql(out.fx) - wfx) <= tf && fabs(from_ql(out.fy) - wfy) <= tf &&
              fabs(from_ql(out.q) - wq) <= tq + 1e-9 && fabs(from_qs(out.t) - wta) <= tt)) {
            if (bad < 5) {
                printf("#   beyond: scen %d T %.6g/%.6g fx %.6g/%.6g fy %.6g/%.6g q %.6g/%.6g\n", k,
                       from_qs(out.t), wta, from_ql(out.fx), wfx, from_ql(out.fy), wfy, from_ql(out.q), wq);
            }
            bad++;
        }
        (void)wvs;
    }
    golden_close(&g);
    err_print(&ef, "N");
    err_print(&eq, "W");
    err_print(&et, "K");
    printf("#   worst ratio to tolerance: forces %.3f (" F_TOL_DESC "), q %.3f, T %.3f (" T_TOL_DESC
           "); saturations: %u\n", worst_f, worst_q, worst_t, (unsigned)grip_debug_saturation_count());
    assert_true(nscen >= 4);
    assert_true(et.n > 2000);
    assert_int_equal(grip_debug_saturation_count(), 0);
    if (bad != 0) {
        fail_msg("%ld of %ld steps beyond the tolerances", bad, et.n);
    }
}

/* With no heat input (V = 0) the exact step reproduces the analytic cooling
 * T(t) = T_R + (T0 - T_R) exp(-kappa t) for any step size. */
static void test_cooling_is_exact(void **state)
{
    const double dts[] = { 0.01, 0.1, 1.0, 10.0 };
    size_t j;
    double kappa, worst = 0.0;
    (void)state;
    load_params();
    kappa = from_qs(params.kappa);
    for (j = 0; j < sizeof(dts) / sizeof(dts[0]); ++j) {
        grip_mf_thermal_state s;
        grip_mf_thermal_output out;
        grip_mf_thermal_inputs in = mk_in(0.0, 0.05, 0.1, 4600.0, 20.0);
        double dt = from_qs(to_qs(dts[j]));
        double t0 = 90.0;
        int n = (int)(20.0 / dt + 0.5);
        int i;
        assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(t0)), GRIP_OK);
        for (i = 1; i <= n; ++i) {
            double want;
            assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(dt), &out), GRIP_OK);
            assert_true(out.q == 0);
            want = 20.0 + (t0 - 20.0) * exp(-kappa * dt * i);
            worst = fmax(worst, fabs(from_qs(out.t) - want));
        }
    }
    printf("#   cooling vs analytic solution (dt 0.01..10 s, 20 s): max |err| = %.3e K\n", worst);
#if GRIP_ARITH_FIXED
    assert_true(worst <= 0.02);
#else
    assert_true(worst <= 1e-3);
#endif
}

/* Constant inputs: T converges to T_R + q / (kappa W), stable even at the
 * largest step and a large kappa. The step is exact for constant q; q(T) is
 * lagged by one step, so a large step may overshoot by up to about
 * |dq/dT| / (kappa W) of the rise, and |dq/dT| <= q max(|a_i|, |b_i|) / f_min
 * (f_min = 0.9, the smallest temperature factor near 25 degC). */
static void test_equilibrium_and_stability(void **state)
{
    grip_mf_thermal_params p;
    grip_mf_thermal_state s;
    grip_mf_thermal_output out;
    grip_mf_thermal_inputs in = mk_in(20.0, 0.05, 0.05, 4600.0, 25.0);
    double t_eq, q, w, kappa, t_hi = -1e9;
    int i;
    (void)state;
    load_params();
    p = params;
    p.kappa = to_qs(2.0);
    assert_int_equal(grip_mf_thermal_init(&s, &p, to_qs(25.0)), GRIP_OK);
    for (i = 0; i < 200; ++i) {
        assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(10.0), &out), GRIP_OK);
        assert_true(from_qs(out.t) > 25.0);
        t_hi = fmax(t_hi, from_qs(out.t));
    }
    q = from_ql(out.q);
    w = from_ql(p.w);
    kappa = from_qs(p.kappa);
    t_eq = 25.0 + q / (kappa * w);
    printf("#   equilibrium: T = %.4f degC, T_R + q/(kappa W) = %.4f degC (q = %.1f W)\n", from_qs(out.t), t_eq, q);
    printf("#   largest overshoot above equilibrium: %.4f K of a %.4f K rise\n", t_hi - t_eq, t_eq - 25.0);
    assert_true(q > 100.0);
    assert_true(fabs(from_qs(out.t) - t_eq) <= 0.01 * (t_eq - 25.0) + 0.01);
    {
        double cmax = fmax(fmax(fabs(from_qs(p.ax)), fabs(from_qs(p.bx))),
                           fmax(fabs(from_qs(p.ay)), fabs(from_qs(p.by))));
        double bound = cmax / 0.9 * q / (kappa * w) * (t_eq - 25.0);
        printf("#   overshoot bound |dq/dT| / (kappa W) * rise = %.4f K\n", bound);
        assert_true(t_hi - t_eq <= bound + 0.001);
    }
}

/* grip_mf_thermal_heat_step: the same temperature step with a heat flux
 * from elsewhere. (1) fed with the q that grip_mf_thermal_step computed, it
 * reproduces that step's temperature exactly (one implementation of 4.6);
 * (2) for constant q it follows the analytic solution
 * T = T_R + q/(kappa W) + (T0 - T_R - q/(kappa W)) exp(-kappa t);
 * (3) bad input: error status, *t_out zero, state unchanged. */
static void test_heat_step(void **state)
{
    grip_mf_thermal_state a, b;
    grip_mf_thermal_output out;
    grip_real_t t_b;
    double kappa, w, q, t0 = 30.0, worst = 0.0;
    int i;
    (void)state;
    load_params();
    assert_int_equal(grip_mf_thermal_init(&a, &params, to_qs(t0)), GRIP_OK);
    assert_int_equal(grip_mf_thermal_init(&b, &params, to_qs(t0)), GRIP_OK);
    for (i = 0; i < 400; ++i) {
        double ph = 0.05 * (double)i;
        grip_mf_thermal_inputs in = mk_in(20.0, 0.08 * sin(ph), 0.1 * cos(0.7 * ph), 4600.0, 20.0);
        grip_status_t sa = grip_mf_thermal_step(&a, &in, to_qs(0.01), &out);
        grip_status_t sb = grip_mf_thermal_heat_step(&b, out.q, in.t_road, to_qs(0.01), &t_b);
        assert_int_equal(sa, sb);
        assert_true(t_b == out.t);
    }
    kappa = from_qs(params.kappa);
    w = from_ql(params.w);
    q = 2000.0;
    assert_int_equal(grip_mf_thermal_init(&b, &params, to_qs(t0)), GRIP_OK);
    for (i = 1; i <= 2000; ++i) {
        double eq = 20.0 + q / (kappa * w);
        double want = eq + (t0 - eq) * exp(-kappa * 0.01 * (double)i);
        grip_status_t st = grip_mf_thermal_heat_step(&b, to_ql(q), to_qs(20.0), to_qs(0.01), &t_b);
        assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
        if (st == GRIP_OK) {
            worst = fmax(worst, fabs(from_qs(t_b) - want));
        }
    }
    printf("#   heat step, constant q = 2 kW vs analytic (20 s): max |err| = %.3e K\n", worst);
#if GRIP_ARITH_FIXED
    assert_true(worst <= 0.02);
#else
    assert_true(worst <= 1e-3);
#endif
    {
        grip_real_t before = b.t;
        grip_mf_thermal_state u;
        memset(&u, 0, sizeof(u));
        assert_int_equal(grip_mf_thermal_heat_step(NULL, 0, 0, to_qs(0.01), &t_b), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_thermal_heat_step(&b, 0, 0, to_qs(0.01), NULL), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_thermal_heat_step(&u, 0, 0, to_qs(0.01), &t_b), GRIP_ERR_STATE);
        assert_int_equal(grip_mf_thermal_heat_step(&b, to_ql(-1.0), 0, to_qs(0.01), &t_b), GRIP_ERR_INPUT);
        assert_true(t_b == 0);
        assert_int_equal(grip_mf_thermal_heat_step(&b, 0, 0, to_qs(-0.01), &t_b), GRIP_ERR_INPUT);
#if !GRIP_ARITH_FIXED
        assert_int_equal(grip_mf_thermal_heat_step(&b, NAN, 0, to_qs(0.01), &t_b), GRIP_ERR_INPUT);
        assert_int_equal(grip_mf_thermal_heat_step(&b, 0, INFINITY, to_qs(0.01), &t_b), GRIP_ERR_INPUT);
#endif
        assert_true(b.t == before);
    }
}

static void test_status_and_null(void **state)
{
    grip_mf_thermal_state s;
    grip_mf_thermal_output out;
    grip_mf_thermal_inputs in = mk_in(20.0, 0.05, 0.05, 4600.0, 25.0);
    grip_real_t fx = 1, fy = 1;
    grip_real_t t_before;
    (void)state;
    load_params();
    memset(&s, 0, sizeof(s));
    assert_int_equal(grip_mf_thermal_init(NULL, &params, 0), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_thermal_init(&s, NULL, 0), GRIP_ERR_NULL);
    /* not initialised */
    out.fx = 1;
    assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(0.01), &out), GRIP_ERR_STATE);
    assert_true(out.fx == 0 && out.t == 0 && out.q == 0);
    assert_int_equal(grip_mf_thermal_forces(&s, &in, 0, &fx, &fy), GRIP_ERR_STATE);
    assert_true(fx == 0 && fy == 0);
    assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(40.0)), GRIP_OK);
    assert_int_equal(grip_mf_thermal_step(NULL, &in, to_qs(0.01), &out), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_thermal_step(&s, NULL, to_qs(0.01), &out), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(0.01), NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_thermal_forces(&s, &in, 0, NULL, &fy), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_thermal_forces(NULL, &in, 0, &fx, &fy), GRIP_ERR_NULL);
    /* bad dt: error, output zero, state unchanged */
    t_before = s.t;
    assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(-0.01), &out), GRIP_ERR_INPUT);
    assert_int_equal(grip_mf_thermal_step(&s, &in, to_qs(10.5), &out), GRIP_ERR_INPUT);
    assert_true(out.fx == 0 && out.fy == 0 && out.t == 0);
    assert_true(s.t == t_before);
    /* dt = 0: forces, no temperature change */
    assert_int_equal(grip_mf_thermal_step(&s, &in, 0, &out), GRIP_OK);
    assert_true(s.t == t_before && out.t == t_before);
    assert_true(from_ql(out.fy) > 1000.0 && from_ql(out.fx) > 500.0);
    /* init clamps t_init */
    assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(500.0)), GRIP_WARN_CLAMPED);
    assert_true(s.t == params.t_max);
    assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(-100.0)), GRIP_WARN_CLAMPED);
    assert_true(s.t == params.t_min);
#if !GRIP_ARITH_FIXED
    assert_int_equal(grip_mf_thermal_init(&s, &params, NAN), GRIP_ERR_INPUT);
    assert_int_equal(grip_mf_thermal_step(&s, &in, 0.01f, &out), GRIP_ERR_STATE);
    assert_int_equal(grip_mf_thermal_init(&s, &params, 30.0f), GRIP_OK);
    t_before = s.t;
    in.alpha = NAN;
    assert_int_equal(grip_mf_thermal_step(&s, &in, 0.01f, &out), GRIP_ERR_INPUT);
    in.alpha = 0.05f;
    in.t_road = INFINITY;
    assert_int_equal(grip_mf_thermal_step(&s, &in, 0.01f, &out), GRIP_ERR_INPUT);
    in.t_road = 25.0f;
    assert_int_equal(grip_mf_thermal_step(&s, &in, NAN, &out), GRIP_ERR_INPUT);
    assert_int_equal(grip_mf_thermal_forces(&s, &in, NAN, &fx, &fy), GRIP_ERR_INPUT);
    assert_true(s.t == t_before);
#endif
}

static void test_invalid_params(void **state)
{
    grip_mf_thermal_state s;
    grip_mf_thermal_params p;
    (void)state;
    load_params();
#define EXPECT_PARAM_ERR(field, value)                                              \
    do {                                                                            \
        p = params;                                                                 \
        p.field = (value);                                                          \
        assert_int_equal(grip_mf_thermal_init(&s, &p, to_qs(30.0)), GRIP_ERR_PARAM); \
        assert_true(s.magic == 0u);                                                 \
    } while (0)
    EXPECT_PARAM_ERR(fz0, 0);
    EXPECT_PARAM_ERR(w, 0);
    EXPECT_PARAM_ERR(w, to_ql(10.0));          /* fz0 / W > 100 */
    EXPECT_PARAM_ERR(kappa, to_qs(-0.1));
    EXPECT_PARAM_ERR(dx0, 0);
    EXPECT_PARAM_ERR(ky0, to_ql(-1000.0));
    EXPECT_PARAM_ERR(cx, 0);
    EXPECT_PARAM_ERR(cy, to_qs(2.0));
    EXPECT_PARAM_ERR(cxa, to_qs(1.2));         /* G could change sign */
    EXPECT_PARAM_ERR(ay, to_qs(-0.02));        /* D(T) < 0 at t_max */
    EXPECT_PARAM_ERR(bx, to_qs(0.05));         /* K(T) < 0 at t_min */
    EXPECT_PARAM_ERR(t_max, to_qs(-40.0));     /* t_max < t_min */
    EXPECT_PARAM_ERR(alpha_max, 0);
    EXPECT_PARAM_ERR(fz_max, to_ql(40000.0));
#if !GRIP_ARITH_FIXED
    EXPECT_PARAM_ERR(ex, NAN);
    EXPECT_PARAM_ERR(t_max, INFINITY);
#endif
#undef EXPECT_PARAM_ERR
}

/* Out-of-range inputs are clamped (warning) to the same result as the limit. */
static void test_clamping(void **state)
{
    grip_mf_thermal_state s;
    grip_real_t fx1, fy1, fx2, fy2;
    grip_mf_thermal_inputs over = mk_in(500.0, 2.0, 3.0, 20000.0, 25.0);
    grip_mf_thermal_inputs lim;
    (void)state;
    load_params();
    lim.v = params.v_max;
    lim.alpha = params.alpha_max;
    lim.slip = params.slip_max;
    lim.fz = params.fz_max;
    lim.t_road = to_qs(25.0);
    assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(30.0)), GRIP_OK);
    assert_int_equal(grip_mf_thermal_forces(&s, &over, to_qs(400.0), &fx1, &fy1), GRIP_WARN_CLAMPED);
    assert_int_equal(grip_mf_thermal_forces(&s, &lim, params.t_max, &fx2, &fy2), GRIP_OK);
    assert_true(fx1 == fx2 && fy1 == fy2);
    over = mk_in(-5.0, 0.1, 0.1, -100.0, 25.0);
    assert_int_equal(grip_mf_thermal_forces(&s, &over, to_qs(30.0), &fx1, &fy1), GRIP_WARN_CLAMPED);
    assert_true(fx1 == 0 && fy1 == 0);    /* fz < 0 is a lifted wheel */
}

/* Extreme raw inputs: always finite, T inside [t_min, t_max]. */
static void test_extreme_inputs_finite(void **state)
{
#if GRIP_ARITH_FIXED
    const grip_real_t vals[] = { -INT32_MAX, -65536 * 500, -1, 0, 1, 65536 * 500, INT32_MAX };
#else
    const grip_real_t vals[] = { -3.0e38f, -1.0e4f, -1.0f, 0.0f, 1.0e-30f, 1.0f, 1.0e4f, 3.0e38f };
#endif
    const size_t n = sizeof(vals) / sizeof(vals[0]);
    grip_mf_thermal_state s;
    size_t i, j, k;
    (void)state;
    load_params();
    assert_int_equal(grip_mf_thermal_init(&s, &params, to_qs(30.0)), GRIP_OK);
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            for (k = 0; k < n; ++k) {
                grip_mf_thermal_inputs in;
                grip_mf_thermal_output out;
                grip_status_t st;
                in.v = vals[i];
                in.alpha = vals[j];
                in.slip = vals[k];
                in.fz = vals[(i + k) % n];
                in.t_road = vals[(j + k) % n];
                st = grip_mf_thermal_step(&s, &in, to_qs(0.5), &out);
                assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
                assert_true(isfinite(from_ql(out.fx)) && isfinite(from_ql(out.fy)) &&
                            isfinite(from_ql(out.q)) && isfinite(from_qs(out.t)));
                assert_true(out.t >= params.t_min && out.t <= params.t_max);
                assert_true(fabs(from_ql(out.fx)) < 30000.0 && fabs(from_ql(out.fy)) < 30000.0);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forces_golden),
        cmocka_unit_test(test_time_series_golden),
        cmocka_unit_test(test_cooling_is_exact),
        cmocka_unit_test(test_equilibrium_and_stability),
        cmocka_unit_test(test_heat_step),
        cmocka_unit_test(test_status_and_null),
        cmocka_unit_test(test_invalid_params),
        cmocka_unit_test(test_clamping),
        cmocka_unit_test(test_extreme_inputs_finite),
    };
    return cmocka_run_group_tests_name("mf_thermal (" GRIP_ARITH_NAME ")", tests, NULL, NULL);
}
