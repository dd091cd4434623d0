/*
 * test_mf89.c - the 1989-style lateral Magic Formula (lib/mf89) against the
 * float64 reference tools/grip_tools/reference/mf89.py (build/golden/mf89.txt, from
 * golden/mf89.py), plus clamping, constraint checker, status codes, NULL and
 * non-finite inputs, and saturation in the DEBUG_SAT build.
 *
 * Tolerances (docs/mf89-thermal.md):
 *   float build: |Fy - Fy_ref| <= 1e-4 * Fz
 *   fixed build: |Fy - Fy_ref| <= 0.005 * peak + 0.03 N, peak = |D| + |Sv| at
 *                that load and camber (0.5 % of the peak force; the 0.03 N
 *                floor is two LSB of the internal kN scale)
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_mf89.h"
#include "grip/grip_q16.h"
#include "golden.h"

#if GRIP_ARITH_FIXED
static grip_real_t to_qs(double x) { return (grip_real_t)llround(x * 65536.0); }
static grip_real_t to_ql(double x) { return (grip_real_t)llround(x * 256.0); }
static double from_ql(grip_real_t v) { return (double)v / 256.0; }
/* 0.03 N: two LSB of the internal kN scale (QS, 1 LSB = 0.0153 N), which
 * dominates only for loads of a few newtons. */
#define TOL_DESC "0.005 * peak + 0.03 N"
static double tolerance(double fz, double peak) { (void)fz; return 0.005 * peak + 0.03; }
#else
static grip_real_t to_qs(double x) { return (grip_real_t)x; }
static grip_real_t to_ql(double x) { return (grip_real_t)x; }
static double from_ql(grip_real_t v) { return (double)v; }
#define TOL_DESC "1e-4 * Fz"
static double tolerance(double fz, double peak) { (void)peak; return 1e-4 * fz; }
#endif

static grip_mf89_params params;
static int params_loaded;

static void load_params(void)
{
    golden_file g;
    int i;
    if (params_loaded) {
        return;
    }
    assert_int_equal(golden_open(&g, "mf89.txt"), 0);
    while (golden_next(&g) > 0) {
        if (strcmp(g.field[0], "P") == 0) {
            assert_true(g.nfields >= 22);
            for (i = 0; i < GRIP_MF89_NCOEF; ++i) {
                params.a[i] = to_qs(golden_num(&g, 1 + i));
            }
            params.fz_max = to_ql(golden_num(&g, 19));
            params.alpha_max = to_qs(golden_num(&g, 20));
            params.gamma_max = to_qs(golden_num(&g, 21));
            params_loaded = 1;
            break;
        }
    }
    golden_close(&g);
    assert_true(params_loaded);
}

/* Every row with the tag: evaluate, compare, count violations. */
static void run_rows(const char *tag, grip_status_t want_status, const char *name)
{
    golden_file g;
    err_stats st;
    long bad = 0;
    double worst_ratio = 0.0;
    double worst_peak = 0.0;   /* max |err| / peak over loads >= 100 N */
    load_params();
    assert_int_equal(golden_open(&g, "mf89.txt"), 0);
    err_init(&st, name, 100.0);
    grip_debug_saturation_reset();
    while (golden_next(&g) > 0) {
        double alpha, fz, gamma, want, peak, got, err, tol;
        grip_real_t fy = 0;
        grip_status_t s;
        if (strcmp(g.field[0], tag) != 0) {
            continue;
        }
        alpha = golden_num(&g, 1);
        fz = golden_num(&g, 2);
        gamma = golden_num(&g, 3);
        want = golden_num(&g, 4);
        peak = golden_num(&g, 5);
        s = grip_mf89_fy(&params, to_qs(alpha), to_ql(fz), to_qs(gamma), &fy);
        if (s != want_status) {
            fail_msg("%s: status %d (%s) at alpha=%g fz=%g gamma=%g, want %d", name, (int)s,
                     grip_status_str(s), alpha, fz, gamma, (int)want_status);
        }
        got = from_ql(fy);
        err = fabs(got - want);
        err_add(&st, got, want, alpha, fz, gamma);
        tol = tolerance(fz > 0.0 ? fz : 0.0, peak);
        if (!(err <= tol)) {
            if (bad < 5) {
                printf("#   beyond: alpha=%.9g fz=%.9g gamma=%.9g got=%.9g want=%.9g tol=%.3g\n", alpha, fz,
                       gamma, got, want, tol);
            }
            bad++;
        }
        if (fz >= 100.0 && err / peak > worst_peak) {
            worst_peak = err / peak;
        }
        if (tol > 0.0 && err / tol > worst_ratio) {
            worst_ratio = err / tol;
        }
    }
    golden_close(&g);
    err_print(&st, "N");
    printf("#   worst |err| / (" TOL_DESC ") = %.3f; max |err| / peak (Fz >= 100 N) = %.2e; "
           "saturations: %u\n", worst_ratio, worst_peak, (unsigned)grip_debug_saturation_count());
    assert_true(st.n > 0);
    if (bad != 0) {
        fail_msg("%s: %ld of %ld vectors beyond " TOL_DESC, name, bad, st.n);
    }
}

static void test_golden_valid_range(void **state)
{
    (void)state;
    run_rows("V", GRIP_OK, "mf89 Fy valid range");
    /* DEBUG_SAT build: no fixed-point saturation anywhere in the valid range */
    assert_int_equal(grip_debug_saturation_count(), 0);
}

static void test_golden_clamped_inputs(void **state)
{
    (void)state;
    run_rows("C", GRIP_WARN_CLAMPED, "mf89 Fy clamped inputs");
}

static void test_constraint_checker(void **state)
{
    golden_file g;
    int rows = 0;
    int violating = 0;
    (void)state;
    load_params();
    assert_int_equal(golden_open(&g, "mf89.txt"), 0);
    while (golden_next(&g) > 0) {
        grip_mf89_params q = params;
        uint32_t want;
        uint32_t got = 0xffffffffu;
        grip_status_t s;
        int i;
        if (strcmp(g.field[0], "K") != 0) {
            continue;
        }
        want = (uint32_t)golden_num(&g, 2);
        q.gamma_max = to_qs(golden_num(&g, 5));
        for (i = 0; i < GRIP_MF89_NCOEF; ++i) {
            q.a[i] = to_qs(golden_num(&g, 6 + i));
        }
        s = grip_mf89_check_constraints(&q, to_ql(golden_num(&g, 3)), to_ql(golden_num(&g, 4)), &got);
        printf("#   constraints %-14s mask %3u (want %3u) status %d\n", g.field[1], (unsigned)got,
               (unsigned)want, (int)s);
        assert_int_equal(got, want);
        assert_int_equal(s, want == 0u ? GRIP_OK : GRIP_ERR_PARAM);
        rows++;
        violating += (want != 0u);
    }
    golden_close(&g);
    assert_true(rows >= 10);
    assert_true(violating >= rows - 2);
}

static void test_constraint_checker_errors(void **state)
{
    uint32_t m = 123u;
    grip_mf89_params q;
    (void)state;
    load_params();
    assert_int_equal(grip_mf89_check_constraints(&params, to_ql(1000.0), to_ql(10000.0), NULL),
                     GRIP_ERR_NULL);
    assert_int_equal(grip_mf89_check_constraints(NULL, to_ql(1000.0), to_ql(10000.0), &m), GRIP_ERR_NULL);
    assert_int_equal(m, 0u);
    /* bad load ranges */
    assert_int_equal(grip_mf89_check_constraints(&params, to_ql(0.0), to_ql(10000.0), &m), GRIP_ERR_INPUT);
    assert_int_equal(grip_mf89_check_constraints(&params, to_ql(5000.0), to_ql(1000.0), &m),
                     GRIP_ERR_INPUT);
    /* a set that cannot be evaluated is refused before the constraints */
    q = params;
    q.a[4] = 0;
    m = 77u;
    assert_int_equal(grip_mf89_check_constraints(&q, to_ql(1000.0), to_ql(10000.0), &m), GRIP_ERR_PARAM);
    assert_int_equal(m, 0u);
    assert_int_equal(grip_mf89_check_constraints(&params, to_ql(1000.0), to_ql(10000.0), &m), GRIP_OK);
}

static void test_null_and_status(void **state)
{
    grip_real_t fy = to_ql(123.0);
    (void)state;
    load_params();
    assert_int_equal(grip_mf89_fy(&params, to_qs(0.1), to_ql(4600.0), 0, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_mf89_fy(NULL, to_qs(0.1), to_ql(4600.0), 0, &fy), GRIP_ERR_NULL);
    assert_true(fy == 0);
    assert_int_equal(grip_mf89_check_params(NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_mf89_check_params(&params), GRIP_OK);
    assert_int_equal(grip_mf89_fy(&params, to_qs(0.1), to_ql(4600.0), 0, &fy), GRIP_OK);
    assert_true(from_ql(fy) > 1000.0);
    assert_string_equal(grip_status_str(GRIP_ERR_PARAM), "invalid or unsupported parameter set");
}

/* Parameter sets that cannot be evaluated: GRIP_ERR_PARAM and Fy = 0. */
static void test_invalid_params(void **state)
{
    struct { int idx; double value; } cases[] = {
        { 0, 0.0 },      /* C = 0 */
        { 0, 2.5 },      /* C >= 2 */
        { 4, 0.0 },      /* a4 = 0 */
        { 4, -5.0 },     /* a4 < 0 */
        { 3, 0.0 },      /* BCD = 0 */
        { 2, -1200.0 },  /* D < 0 */
        { 1, -200.0 },   /* D < 0 at fz_max: -200*10 + 1200 */
        { 15, 0.2 },     /* 1 - a15 gamma_max^2 < 0 */
        { 5, 0.2 },      /* 1 - a5 gamma_max < 0 */
    };
    size_t i;
    (void)state;
    load_params();
    for (i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
        grip_mf89_params q = params;
        grip_real_t fy = to_ql(55.0);
        q.a[cases[i].idx] = to_qs(cases[i].value);
        assert_int_equal(grip_mf89_check_params(&q), GRIP_ERR_PARAM);
        assert_int_equal(grip_mf89_fy(&q, to_qs(0.1), to_ql(4600.0), to_qs(0.05), &fy), GRIP_ERR_PARAM);
        assert_true(fy == 0);
    }
    {   /* bad limits */
        grip_mf89_params q = params;
        q.fz_max = 0;
        assert_int_equal(grip_mf89_check_params(&q), GRIP_ERR_PARAM);
        q = params;
        q.alpha_max = to_qs(2.0);
        assert_int_equal(grip_mf89_check_params(&q), GRIP_ERR_PARAM);
        q = params;
        q.gamma_max = 0;
        assert_int_equal(grip_mf89_check_params(&q), GRIP_ERR_PARAM);
    }
#if !GRIP_ARITH_FIXED
    {
        grip_mf89_params q = params;
        grip_real_t fy = 1.0f;
        q.a[7] = NAN;
        assert_int_equal(grip_mf89_fy(&q, 0.1f, 4600.0f, 0.0f, &fy), GRIP_ERR_PARAM);
        assert_true(fy == 0.0f);
        q = params;
        q.fz_max = INFINITY;
        assert_int_equal(grip_mf89_check_params(&q), GRIP_ERR_PARAM);
    }
#endif
}

/* Any input, however extreme, gives a finite bounded force; non-finite
 * inputs are refused with Fy = 0. */
static void test_extreme_inputs_finite(void **state)
{
#if GRIP_ARITH_FIXED
    const grip_real_t vals[] = { INT32_MIN, -INT32_MAX, -65536 * 1000, -1, 0, 1, 65536 * 1000, INT32_MAX };
#else
    const grip_real_t vals[] = { -3.0e38f, -1.0e6f, -1.0f, -1.0e-30f, 0.0f, 1.0e-30f, 1.0f, 1.0e6f, 3.0e38f };
#endif
    const size_t n = sizeof(vals) / sizeof(vals[0]);
    size_t i, j, k;
    double fmax = 0.0;
    (void)state;
    load_params();
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            for (k = 0; k < n; ++k) {
                grip_real_t fy = 0;
                grip_status_t s = grip_mf89_fy(&params, vals[i], vals[j], vals[k], &fy);
                double f = from_ql(fy);
                assert_true(s == GRIP_OK || s == GRIP_WARN_CLAMPED);
                assert_true(isfinite(f));
                if (fabs(f) > fmax) {
                    fmax = fabs(f);
                }
            }
        }
    }
    /* bounded by the peak force at fz_max (~9 kN) plus the camber shift */
    printf("#   extreme inputs: max |Fy| = %.1f N\n", fmax);
    assert_true(fmax < 12000.0);
#if !GRIP_ARITH_FIXED
    {
        grip_real_t fy = 1.0f;
        assert_int_equal(grip_mf89_fy(&params, NAN, 4600.0f, 0.0f, &fy), GRIP_ERR_INPUT);
        assert_true(fy == 0.0f);
        fy = 1.0f;
        assert_int_equal(grip_mf89_fy(&params, 0.1f, INFINITY, 0.0f, &fy), GRIP_ERR_INPUT);
        assert_true(fy == 0.0f);
        fy = 1.0f;
        assert_int_equal(grip_mf89_fy(&params, 0.1f, 4600.0f, -INFINITY, &fy), GRIP_ERR_INPUT);
        assert_true(fy == 0.0f);
    }
#endif
}

/* Physical checks independent of the reference: antisymmetry at zero
 * camber (the constraints make Sh = Sv = 0 and E symmetric), zero force at
 * zero load, camber thrust sign, peak near D. */
static void test_properties(void **state)
{
    double worst = 0.0;
    int i;
    grip_real_t f1 = 0, f2 = 0;
    (void)state;
    load_params();
    for (i = -40; i <= 40; ++i) {
        double a = 0.01 * i;
        grip_real_t fp = 0, fn = 0;
        assert_true(grip_mf89_fy(&params, to_qs(a), to_ql(6000.0), 0, &fp) >= 0);
        assert_true(grip_mf89_fy(&params, to_qs(-a), to_ql(6000.0), 0, &fn) >= 0);
        if (fabs(from_ql(fp) + from_ql(fn)) > worst) {
            worst = fabs(from_ql(fp) + from_ql(fn));
        }
    }
    printf("#   antisymmetry at gamma = 0: max |Fy(a) + Fy(-a)| = %.3g N\n", worst);
    assert_true(worst <= 0.05);
    assert_int_equal(grip_mf89_fy(&params, to_qs(0.2), 0, to_qs(0.1), &f1), GRIP_OK);
    assert_true(f1 == 0);
    /* positive camber gives positive camber thrust at alpha = 0 (a14 > 0) */
    assert_int_equal(grip_mf89_fy(&params, 0, to_ql(4600.0), to_qs(0.07), &f1), GRIP_OK);
    assert_int_equal(grip_mf89_fy(&params, 0, to_ql(4600.0), to_qs(-0.07), &f2), GRIP_OK);
    assert_true(from_ql(f1) > 100.0);
    assert_true(fabs(from_ql(f1) + from_ql(f2)) < 0.05);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_valid_range),
        cmocka_unit_test(test_golden_clamped_inputs),
        cmocka_unit_test(test_constraint_checker),
        cmocka_unit_test(test_constraint_checker_errors),
        cmocka_unit_test(test_null_and_status),
        cmocka_unit_test(test_invalid_params),
        cmocka_unit_test(test_extreme_inputs_finite),
        cmocka_unit_test(test_properties),
    };
    return cmocka_run_group_tests_name("mf89 (" GRIP_ARITH_NAME ")", tests, NULL, NULL);
}
