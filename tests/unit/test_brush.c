/*
 * test_brush.c - the brush-model family (include/grip/grip_brush.h) against
 * the float64 closed forms of tools/grip_tools/reference/brush.py (golden vectors
 * brush_*.txt from tools/grip_tools/golden/brush.py; those closed forms equal
 * the quadrature reference to 1e-9, tests/python/reference/test_brush.py).
 *
 * Errors are normalized: forces by mu_s Fz, moments by mu_s Fz l (Fz after
 * clamping). Bounds (docs/brush-models.md, "Accuracy"):
 *   float: 1e-4 (the budget), fixed: the documented budget below.
 * Every golden test prints its maximum errors (err_print). In a
 * DEBUG_SAT=1 build no fixed-point operation may saturate on the valid rows.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_brush.h"
#include "grip/grip_q16.h"
#include "golden.h"

#if GRIP_ARITH_FIXED
/* Fixed build: documented and enforced error budget (normalized). */
#define TOL_F 1.0e-3
#define TOL_M 1.0e-3
#else
#define TOL_F 1.0e-4
#define TOL_M 1.0e-4
#endif

#define MAX_SETS 32

static grip_real_t qs(double v)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)lround(v * 65536.0);
#else
    return (grip_real_t)v;
#endif
}

static grip_real_t ql(double v)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)lround(v * 256.0);
#else
    return (grip_real_t)v;
#endif
}

static double dqs(grip_real_t v)
{
#if GRIP_ARITH_FIXED
    return (double)v / 65536.0;
#else
    return (double)v;
#endif
}

static double dql(grip_real_t v)
{
#if GRIP_ARITH_FIXED
    return (double)v / 256.0;
#else
    return (double)v;
#endif
}

static double clampd(double x, double lo, double hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

/* Common bookkeeping of one golden file. */
typedef struct {
    err_stats fx;
    err_stats fy;
    err_stats mz;
    err_stats rh;
    long rows;
    long bad_status;
    long over;
    double worst;
} golden_run;

static void run_init(golden_run *r, const char *model)
{
    static char names[4][64];
    snprintf(names[0], sizeof names[0], "%s Fx/(mu Fz)", model);
    snprintf(names[1], sizeof names[1], "%s Fy/(mu Fz)", model);
    snprintf(names[2], sizeof names[2], "%s Mz/(mu Fz l)", model);
    snprintf(names[3], sizeof names[3], "%s rh", model);
    err_init(&r->fx, names[0], 1.0);
    err_init(&r->fy, names[1], 1.0);
    err_init(&r->mz, names[2], 1.0);
    err_init(&r->rh, names[3], 1.0);
    r->rows = 0;
    r->bad_status = 0;
    r->over = 0;
    r->worst = 0.0;
}

/* Compare one row: got/want in N and N m, normalized by f0 = mu_s Fz. */
static void run_add(golden_run *r, const grip_brush_out *o, const double want[4], double f0, double l,
                    grip_status_t st, grip_status_t want_st, double in0, double in1, double in2)
{
    double gf[3];
    double e;
    gf[0] = dql(o->fx);
    gf[1] = dql(o->fy);
    gf[2] = dql(o->mz);
    err_add(&r->fx, gf[0] / f0, want[0] / f0, in0, in1, in2);
    err_add(&r->fy, gf[1] / f0, want[1] / f0, in0, in1, in2);
    err_add(&r->mz, gf[2] / (f0 * l), want[2] / (f0 * l), in0, in1, in2);
    err_add(&r->rh, dqs(o->rh), want[3], in0, in1, in2);
    r->rows++;
    if (st != want_st) {
        r->bad_status++;
        if (r->bad_status <= 5) {
            printf("# status %d, want %d at inputs %g %g %g\n", (int)st, (int)want_st, in0, in1, in2);
        }
    }
    e = fabs(gf[0] - want[0]) / f0;
    if (fabs(gf[1] - want[1]) / f0 > e) {
        e = fabs(gf[1] - want[1]) / f0;
    }
    if (e > TOL_F || fabs(gf[2] - want[2]) / (f0 * l) > TOL_M || !isfinite(gf[0]) || !isfinite(gf[1]) ||
        !isfinite(gf[2])) {
        r->over++;
        if (r->over <= 5) {
            printf("# over tolerance at inputs %g %g %g: got %g %g %g want %g %g %g\n", in0, in1, in2, gf[0],
                   gf[1], gf[2], want[0], want[1], want[2]);
        }
    }
}

static void run_finish(golden_run *r, long min_rows)
{
    err_print(&r->fx, "");
    err_print(&r->fy, "");
    err_print(&r->mz, "");
    err_print(&r->rh, "");
    printf("#   bound: forces %.1e mu Fz, moment %.1e mu Fz l (%s build)\n", TOL_F, TOL_M, GRIP_ARITH_NAME);
    assert_true(r->rows >= min_rows);
    assert_int_equal(r->bad_status, 0);
    if (r->over != 0) {
        fail_msg("%ld rows beyond the bound", r->over);
    }
}

static void sat_begin(void)
{
    grip_debug_saturation_reset();
}

static void sat_check(const char *what)
{
#if GRIP_DEBUG_SATURATION
    if (grip_debug_saturation_count() != 0) {
        fail_msg("%s: %u fixed-point saturations in the valid range (first: %s)", what,
                 (unsigned)grip_debug_saturation_count(), grip_debug_saturation_first());
    }
    printf("# %s: no saturation in the valid range\n", what);
#else
    (void)what;
#endif
}

/* ---- parameter rows ---- */

static void fill_fiala(const golden_file *g, grip_fiala_params *p)
{
    p->ky = ql(golden_num(g, 2));
    p->mu = qs(golden_num(g, 3));
    p->l = qs(golden_num(g, 4));
    p->fz_min = ql(golden_num(g, 5));
    p->fz_max = ql(golden_num(g, 6));
    p->alpha_max = qs(golden_num(g, 7));
}

static void fill_brush(const golden_file *g, grip_brush_params *p)
{
    p->kx = ql(golden_num(g, 2));
    p->mu_s = qs(golden_num(g, 3));
    p->mu_d0 = qs(golden_num(g, 4));
    p->a_v = qs(golden_num(g, 5));
    p->n = (int32_t)golden_num(g, 6);
    p->fz_min = ql(golden_num(g, 7));
    p->fz_max = ql(golden_num(g, 8));
    p->kappa_max = qs(golden_num(g, 9));
    p->v_max = qs(golden_num(g, 10));
}

static void fill_sakai(const golden_file *g, grip_sakai_params *p)
{
    p->k = ql(golden_num(g, 2));
    p->g_y = ql(golden_num(g, 3));
    p->mu_s = qs(golden_num(g, 4));
    p->mu_d = qs(golden_num(g, 5));
    p->l = qs(golden_num(g, 6));
    p->fz_min = ql(golden_num(g, 7));
    p->fz_max = ql(golden_num(g, 8));
    p->alpha_max = qs(golden_num(g, 9));
    p->kappa_max = qs(golden_num(g, 10));
}

static void fill_neofiala(const golden_file *g, grip_neofiala_params *p)
{
    p->l = qs(golden_num(g, 2));
    p->w = qs(golden_num(g, 3));
    p->kx = ql(golden_num(g, 4));
    p->ky = ql(golden_num(g, 5));
    p->mu_s = qs(golden_num(g, 6));
    p->mu_d0 = qs(golden_num(g, 7));
    p->a_v = qs(golden_num(g, 8));
    p->n = (int32_t)golden_num(g, 9);
    p->q0 = qs(golden_num(g, 10));
    p->c_q = qs(golden_num(g, 11));
    p->c_qm = qs(golden_num(g, 12));
    p->c_xc = qs(golden_num(g, 13));
    p->xi = qs(golden_num(g, 14));
    p->eps = qs(golden_num(g, 15));
    p->g_mz = ql(golden_num(g, 16));
    p->a_x = ql(golden_num(g, 17));
    p->c_gamma = qs(golden_num(g, 18));
    p->h = qs(golden_num(g, 19));
    p->g_my = ql(golden_num(g, 20));
    p->fz_min = ql(golden_num(g, 21));
    p->fz_max = ql(golden_num(g, 22));
    p->alpha_max = qs(golden_num(g, 23));
    p->kappa_max = qs(golden_num(g, 24));
    p->gamma_max = qs(golden_num(g, 25));
    p->v_max = qs(golden_num(g, 26));
}

/* ---- golden tests ---- */

static void test_fiala_golden(void **state)
{
    golden_file g;
    golden_run r;
    grip_fiala_params ps[MAX_SETS];
    (void)state;
    memset(ps, 0, sizeof ps);
    assert_int_equal(golden_open(&g, "brush_fiala.txt"), 0);
    run_init(&r, "fiala");
    sat_begin();
    while (golden_next(&g) > 0) {
        int id = (int)golden_num(&g, 1);
        assert_true(id >= 0 && id < MAX_SETS);
        if (g.field[0][0] == 'P') {
            fill_fiala(&g, &ps[id]);
            assert_int_equal(grip_fiala_check_params(&ps[id]), GRIP_OK);
        } else {
            const grip_fiala_params *p = &ps[id];
            double a = golden_num(&g, 2);
            double fz = golden_num(&g, 3);
            double want[4];
            grip_brush_out o;
            grip_status_t st;
            double fzc = clampd(fz, dql(p->fz_min), dql(p->fz_max));
            int k;
            for (k = 0; k < 4; ++k) {
                want[k] = golden_num(&g, 4 + k);
            }
            st = grip_fiala_eval(p, qs(a), ql(fz), &o);
            run_add(&r, &o, want, dqs(p->mu) * fzc, dqs(p->l), st,
                    (g.field[0][0] == 'V') ? GRIP_OK : GRIP_WARN_CLAMPED, a, fz, 0.0);
            assert_true(dql(o.fx) == 0.0);
        }
    }
    golden_close(&g);
    run_finish(&r, 1000);
    sat_check("fiala");
}

static void test_brush_golden(void **state)
{
    golden_file g;
    golden_run r;
    grip_brush_params ps[MAX_SETS];
    (void)state;
    memset(ps, 0, sizeof ps);
    assert_int_equal(golden_open(&g, "brush_brush.txt"), 0);
    run_init(&r, "brush");
    sat_begin();
    while (golden_next(&g) > 0) {
        int id = (int)golden_num(&g, 1);
        assert_true(id >= 0 && id < MAX_SETS);
        if (g.field[0][0] == 'P') {
            fill_brush(&g, &ps[id]);
            assert_int_equal(grip_brush_check_params(&ps[id]), GRIP_OK);
        } else {
            const grip_brush_params *p = &ps[id];
            double k = golden_num(&g, 2);
            double fz = golden_num(&g, 3);
            double vx = golden_num(&g, 4);
            double want[4];
            grip_brush_out o;
            grip_status_t st;
            double fzc = clampd(fz, dql(p->fz_min), dql(p->fz_max));
            int j;
            for (j = 0; j < 4; ++j) {
                want[j] = golden_num(&g, 5 + j);
            }
            st = grip_brush_eval(p, qs(k), ql(fz), qs(vx), &o);
            run_add(&r, &o, want, dqs(p->mu_s) * fzc, 1.0, st,
                    (g.field[0][0] == 'V') ? GRIP_OK : GRIP_WARN_CLAMPED, k, fz, vx);
        }
    }
    golden_close(&g);
    run_finish(&r, 2500);
    sat_check("brush");
}

static void test_sakai_golden(void **state)
{
    golden_file g;
    golden_run r;
    grip_sakai_params ps[MAX_SETS];
    (void)state;
    memset(ps, 0, sizeof ps);
    assert_int_equal(golden_open(&g, "brush_sakai.txt"), 0);
    run_init(&r, "sakai");
    sat_begin();
    while (golden_next(&g) > 0) {
        int id = (int)golden_num(&g, 1);
        assert_true(id >= 0 && id < MAX_SETS);
        if (g.field[0][0] == 'P') {
            fill_sakai(&g, &ps[id]);
            assert_int_equal(grip_sakai_check_params(&ps[id]), GRIP_OK);
        } else {
            const grip_sakai_params *p = &ps[id];
            double k = golden_num(&g, 2);
            double a = golden_num(&g, 3);
            double fz = golden_num(&g, 4);
            double want[4];
            grip_brush_out o;
            grip_status_t st;
            double fzc = clampd(fz, dql(p->fz_min), dql(p->fz_max));
            int j;
            for (j = 0; j < 4; ++j) {
                want[j] = golden_num(&g, 5 + j);
            }
            st = grip_sakai_eval(p, qs(k), qs(a), ql(fz), &o);
            run_add(&r, &o, want, dqs(p->mu_s) * fzc, dqs(p->l), st,
                    (g.field[0][0] == 'V') ? GRIP_OK : GRIP_WARN_CLAMPED, k, a, fz);
        }
    }
    golden_close(&g);
    run_finish(&r, 1000);
    sat_check("sakai");
}

static void test_neofiala_golden(void **state)
{
    golden_file g;
    golden_run r;
    static grip_neofiala_params ps[MAX_SETS];
    (void)state;
    memset(ps, 0, sizeof ps);
    assert_int_equal(golden_open(&g, "brush_neofiala.txt"), 0);
    run_init(&r, "neofiala");
    sat_begin();
    while (golden_next(&g) > 0) {
        int id = (int)golden_num(&g, 1);
        assert_true(id >= 0 && id < MAX_SETS);
        if (g.field[0][0] == 'P') {
            fill_neofiala(&g, &ps[id]);
            if (grip_neofiala_check_params(&ps[id]) != GRIP_OK) {
                fail_msg("parameter set %d rejected by grip_neofiala_check_params", id);
            }
        } else {
            const grip_neofiala_params *p = &ps[id];
            double k = golden_num(&g, 2);
            double a = golden_num(&g, 3);
            double gm = golden_num(&g, 4);
            double fz = golden_num(&g, 5);
            double vx = golden_num(&g, 6);
            double want[4];
            grip_brush_out o;
            grip_status_t st;
            double fzc = clampd(fz, dql(p->fz_min), dql(p->fz_max));
            int j;
            for (j = 0; j < 4; ++j) {
                want[j] = golden_num(&g, 7 + j);
            }
            st = grip_neofiala_eval(p, qs(k), qs(a), qs(gm), ql(fz), qs(vx), &o);
            run_add(&r, &o, want, dqs(p->mu_s) * fzc, dqs(p->l), st,
                    (g.field[0][0] == 'V') ? GRIP_OK : GRIP_WARN_CLAMPED, k, a, fz);
        }
    }
    golden_close(&g);
    run_finish(&r, 3500);
    sat_check("neofiala");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fiala_golden),
        cmocka_unit_test(test_brush_golden),
        cmocka_unit_test(test_sakai_golden),
        cmocka_unit_test(test_neofiala_golden),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
