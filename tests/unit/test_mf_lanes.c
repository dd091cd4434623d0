/*
 * test_mf_lanes.c - grip_mf_eval_prepared_lanes, grip_mf_eval_pure_prepared_lanes
 * (grip_mf_batch.h; lib/mf/mf_lanes.c, the second implementation of the
 * prepared evaluation for blocks of points):
 *  - over the golden vectors of every shared .tir file (tests/support/
 *    mf_params.h): the lane results against the float64 reference, with
 *    the float build's golden tolerance (1e-4 Fz, 1e-4 Fz m), the largest
 *    errors printed relative to Fz and Fz R0 next to those of the scalar
 *    path (grip_mf_eval_prepared), and their agreement with it;
 *  - over a grid that passes every clamp, unloaded, standstill, reversing,
 *    default- and given-pressure and non-finite points, every shared set
 *    and the plain option bits: the status of every point equal to the
 *    scalar path's, the outputs bit for bit with GRIP_FLOAT_KERNELS=2
 *    (the scalar path on the same kernels), within LANE_TOL of it at the
 *    other levels (libm: the kernels' own error, carried through the
 *    equations);
 *  - the sets the lanes leave to the scalar loop (GRIP_MF_OPT_BOOK,
 *    LMUV > 0, GRIP_MF_OPT_MZ52_SVYK_CAMBER): bit for bit;
 *  - a point whose kernel arguments leave the kernels' range and one whose
 *    result is not finite: evaluated again by the scalar path (its status);
 *  - every count 1 .. 3 blocks + 1: the padded last block gives each point
 *    what a full block gives it; NULL arguments, n = 0, an unprepared set.
 * The fixed build (GRIP_MF_LANES 0): the scalar loop, bit for bit.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#include "golden.h"
#include "mf_grid.h"
#include "mf_params.h"

#define NPTS 2048
#define MAX_ROWS 32768

/* Lanes against the scalar path at GRIP_FLOAT_KERNELS 0 and 1: |diff| <=
 * LANE_TOL * Fz (forces), LANE_TOL * Fz * R0 (Mz), Fz after clamping:
 * the kernels' error against libm's, carried through the equations
 * (grip_mf_batch.h). Measured (gcc 12, x86-64, glibc): 3.0e-6 over this
 * grid, 5.5e-7 over the golden rows, 1.0e-5 at the worst of the binding's
 * random points (tests/python/binding/test_mf.py: 3.3 FNOMIN, 21 degrees
 * of camber, reversing below VXLOW), where the two paths are bit-identical
 * with GRIP_FLOAT_KERNELS=2. */
#define LANE_TOL 2e-5

static grip_mf_input g_in[MAX_ROWS];
static grip_mf_output g_lane[MAX_ROWS];
static grip_mf_output g_ref[MAX_ROWS];
static grip_status_t g_st[MAX_ROWS];
static grip_status_t g_st_ref[MAX_ROWS];
#if !GRIP_ARITH_FIXED
static double g_want[MAX_ROWS][6];
#endif

static double from_ql(grip_real_t v)
{
    return MF_GRID_FROM_QL(v);
}

static int same(const grip_mf_output *a, const grip_mf_output *b)
{
    return memcmp(&a->fx, &b->fx, sizeof a->fx) == 0 && memcmp(&a->fy, &b->fy, sizeof a->fy) == 0 &&
           memcmp(&a->mz, &b->mz, sizeof a->mz) == 0;
}

/* The scalar path (grip_mf_eval_prepared, _pure_prepared) at every point. */
static void scalar(const grip_mf_prepared *prep, int n, int pure)
{
    int k;
    for (k = 0; k < n; k++) {
        g_st_ref[k] = pure ? grip_mf_eval_pure_prepared(prep, &g_in[k], &g_ref[k])
                           : grip_mf_eval_prepared(prep, &g_in[k], &g_ref[k]);
    }
}

static grip_status_t lanes(const grip_mf_prepared *prep, int n, int pure)
{
    memset(g_lane, 0x5A, sizeof(g_lane[0]) * (size_t)n);
    return pure ? grip_mf_eval_pure_prepared_lanes(prep, (uint32_t)n, g_in, g_lane, g_st)
                : grip_mf_eval_prepared_lanes(prep, (uint32_t)n, g_in, g_lane, g_st);
}

/* Largest |lane - scalar| / (Fz, Fz R0) over n points (statuses equal,
 * checked); *bits: points whose outputs differ in any bit. */
static double lane_vs_scalar(const grip_mf_prepared *prep, int n, long *bits)
{
    const grip_mf_params *p = prep->p;
    double fz_max = 4.0 * from_ql(p->fnomin);
    double worst = 0.0;
    int k;
    for (k = 0; k < n; k++) {
        double fz = fabs(from_ql(g_in[k].fz));
        double e[3];
        int j;
        assert_int_equal(g_st[k], g_st_ref[k]);
        if (!same(&g_lane[k], &g_ref[k])) {
            (*bits)++;
        }
        fz = (fz < fz_max) ? fz : fz_max;
        e[0] = fabs(from_ql(g_lane[k].fx) - from_ql(g_ref[k].fx)) / fz;
        e[1] = fabs(from_ql(g_lane[k].fy) - from_ql(g_ref[k].fy)) / fz;
        e[2] = fabs(from_ql(g_lane[k].mz) - from_ql(g_ref[k].mz)) / (fz * from_ql(p->unloaded_radius));
        if (g_st[k] < 0 || !(fz > 0.0)) {
            /* errors and unloaded points: zero outputs, both paths */
            assert_true(same(&g_lane[k], &g_ref[k]));
            continue;
        }
        for (j = 0; j < 3; j++) {
            if (!(e[j] <= worst)) {
                worst = e[j];
            }
        }
    }
    return worst;
}

/* The summary: the first error, else a clamp, else OK. */
static grip_status_t summary(int n)
{
    grip_status_t sum = GRIP_OK;
    int k;
    for (k = 0; k < n; k++) {
        if (sum >= 0 && (g_st[k] < 0 || g_st[k] == GRIP_WARN_CLAMPED)) {
            sum = g_st[k];
        }
    }
    return sum;
}

static void fill_grid(const grip_mf_params *p)
{
    mf_grid_fill(g_in, NPTS, p->fnomin, p->nompres);
#if !GRIP_ARITH_FIXED
    g_in[17].kappa = NAN;
    g_in[400].fz = INFINITY;
    g_in[1001].vx = -INFINITY;
    g_in[1500].p = NAN;
    g_in[1501].alpha = INFINITY;
    g_in[1502].gamma = -NAN;
#endif
}

/* p under `options` over the grid, combined and pure: statuses equal to the
 * scalar path's; returns the largest difference (bits: differing points). */
static double grid_set(const grip_mf_params *p, uint32_t options, long *bits)
{
    grip_mf_prepared prep;
    double worst = 0.0;
    int pure;
    assert_int_equal(grip_mf_prepare(p, options, &prep), GRIP_OK);
    fill_grid(p);
    for (pure = 0; pure <= 1; pure++) {
        grip_status_t sum = lanes(&prep, NPTS, pure);
        double w;
        scalar(&prep, NPTS, pure);
        assert_int_equal(sum, summary(NPTS));
        w = lane_vs_scalar(&prep, NPTS, bits);
        worst = (w > worst) ? w : worst;
    }
    return worst;
}

static void test_grid_every_set(void **state)
{
    static const uint32_t opts[] = { 0u, GRIP_MF_OPT_SAE, GRIP_MF_OPT_KAPPA_BRAKE, GRIP_MF_OPT_MIRROR,
                                     GRIP_MF_OPT_RIGHT_SIDE, GRIP_MF_OPT_SAE | GRIP_MF_OPT_MIRROR,
                                     GRIP_MF_OPT_SAE | GRIP_MF_OPT_KAPPA_BRAKE | GRIP_MF_OPT_RIGHT_SIDE };
    double worst = 0.0;
    long bits = 0;
    long points = 0;
    int t;
    size_t o;
    (void)state;
    for (t = 0; t < grip_test_tire_count; t++) {
        for (o = 0; o < sizeof opts / sizeof opts[0]; o++) {
            double w = grid_set(grip_test_tires[t].params, opts[o], &bits);
            worst = (w > worst) ? w : worst;
            points += 2 * NPTS;
        }
    }
    printf("# grid: %ld evaluations (%d sets x %d option sets x combined, pure), statuses all equal;"
           " lanes vs scalar: %ld differ in a bit, max |diff| / (Fz, Fz R0) = %.3e (GRIP_FLOAT_KERNELS=%d)\n",
           points, grip_test_tire_count, (int)(sizeof opts / sizeof opts[0]), bits, worst, GRIP_FLOAT_KERNELS);
#if GRIP_MF_LANES && GRIP_FLOAT_KERNELS < 2
    assert_true(worst <= LANE_TOL);
#else
    /* the scalar path on the lanes' kernels, or the scalar loop itself */
    assert_int_equal(bits, 0);
#endif
}

/* What the lanes leave to the scalar loop: bit for bit. */
static void test_scalar_forms(void **state)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    const grip_mf_params *p52 = NULL;
    grip_mf_params q = *p;
    long bits = 0;
    int t;
    (void)state;
    (void)grid_set(p, GRIP_MF_OPT_BOOK, &bits);
    (void)grid_set(p, GRIP_MF_OPT_BOOK | GRIP_MF_OPT_SAE, &bits);
    q.lmuv = MF_GRID_QS(0.5);
    q.longvl = MF_GRID_QS(16.7);
    (void)grid_set(&q, q.options, &bits);
    for (t = 0; t < grip_test_tire_count; t++) {
        int f = grip_test_tires[t].params->fittyp;
        if (f == 5 || f == 6 || f == 21) {
            p52 = grip_test_tires[t].params;
        }
    }
    assert_non_null(p52);
    (void)grid_set(p52, GRIP_MF_OPT_MZ52_SVYK_CAMBER, &bits);
    printf("# sets left to the scalar loop (book, LMUV > 0, MZ52_SVYK_CAMBER): %ld points differ\n", bits);
    assert_int_equal(bits, 0);
}

/* Every count up to 3 blocks + 1: each point as in the whole array. */
static void test_counts(void **state)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    grip_mf_prepared prep;
    grip_mf_output all[3 * GRIP_MF_LANES_N + 1];
    grip_status_t st_all[3 * GRIP_MF_LANES_N + 1];
    int n;
    int m = (int)(3 * GRIP_MF_LANES_N + 1);
    (void)state;
    assert_int_equal(grip_mf_prepare(p, p->options, &prep), GRIP_OK);
    mf_grid_fill(g_in, m, p->fnomin, p->nompres);
    (void)grip_mf_eval_prepared_lanes(&prep, (uint32_t)m, g_in, all, st_all);
    for (n = 1; n <= m; n++) {
        int k;
        grip_status_t sum;
        memset(g_lane, 0x5A, sizeof(g_lane[0]) * (size_t)(m + 1));
        sum = grip_mf_eval_prepared_lanes(&prep, (uint32_t)n, g_in, g_lane, g_st);
        for (k = 0; k < n; k++) {
            assert_true(same(&g_lane[k], &all[k]));
            assert_int_equal(g_st[k], st_all[k]);
        }
        assert_int_equal(sum, summary(n));
        /* nothing written beyond n */
        {
            grip_mf_output fill;
            memset(&fill, 0x5A, sizeof fill);
            assert_memory_equal(&g_lane[n], &fill, sizeof fill);
        }
        /* status may be NULL: the same summary */
        assert_int_equal(grip_mf_eval_prepared_lanes(&prep, (uint32_t)n, g_in, g_ref, NULL), sum);
    }
}

static void test_arguments(void **state)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    grip_mf_prepared prep;
    grip_mf_input in[2];
    grip_mf_output out[2];
    grip_status_t st[2];
    (void)state;
    assert_int_equal(grip_mf_prepare(p, p->options, &prep), GRIP_OK);
    mf_grid_fill(in, 2, p->fnomin, p->nompres);
    assert_int_equal(grip_mf_eval_prepared_lanes(NULL, 0u, NULL, NULL, NULL), GRIP_OK);
    assert_int_equal(grip_mf_eval_pure_prepared_lanes(NULL, 0u, NULL, NULL, NULL), GRIP_OK);
    assert_int_equal(grip_mf_eval_prepared_lanes(NULL, 2u, in, out, st), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_prepared_lanes(&prep, 2u, NULL, out, st), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_pure_prepared_lanes(&prep, 2u, in, NULL, st), GRIP_ERR_NULL);
    /* a set that did not prepare: GRIP_ERR_PARAM at every point */
    prep.p = NULL;
    assert_int_equal(grip_mf_eval_prepared_lanes(&prep, 2u, in, out, st), GRIP_ERR_PARAM);
    assert_int_equal(st[0], GRIP_ERR_PARAM);
    assert_int_equal(st[1], GRIP_ERR_PARAM);
    assert_true(out[1].fx == 0 && out[1].fy == 0 && out[1].mz == 0);
}

#if !GRIP_ARITH_FIXED
/* Lanes that the scalar path evaluates again: a kernel argument outside
 * its range (RCX1 = 300: the cosine of Gxa at arguments up to 471, beyond
 * GRIP_KF_TRIG_MAX; a lane that kept its own result there would be off by
 * the order of the force itself, 2 Fz when tried, the cosine of 0 in place
 * of the cosine of the argument; the other points carry the kernels' error
 * times the argument, up to 128), and results that are not finite (a
 * shift of 1e38: GRIP_ERR_DOMAIN, zero outputs, as the scalar path). */
static void test_redo(void **state)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    grip_mf_params q = *p;
    long bits = 0;
    long domain = 0;
    double w;
    int k;
    (void)state;
    q.rcx1 = 300.0f;
    w = grid_set(&q, q.options, &bits);
    printf("# RCX1 = 300 (cosine arguments beyond the kernels' range): max |diff| %.3e, %ld points differ\n", w, bits);
#if GRIP_FLOAT_KERNELS < 2
    assert_true(w <= 1e-4);
#else
    assert_int_equal(bits, 0);
#endif
    q = *p;
    q.pvx1 = 1e38f;
    bits = 0;
    (void)grid_set(&q, q.options, &bits);
    for (k = 0; k < NPTS; k++) {
        domain += (g_st[k] == GRIP_ERR_DOMAIN);
    }
    printf("# PVX1 = 1e38: %ld of %d points GRIP_ERR_DOMAIN as in the scalar path\n", domain, NPTS);
    assert_true(domain > 100);
}

/* Every golden row of every shared set through the lanes against the
 * float64 reference. */
static void test_golden(void **state)
{
    int t;
    int failures = 0;
    (void)state;
    for (t = 0; t < grip_test_tire_count; t++) {
        const grip_test_tire *tt = &grip_test_tires[t];
        const grip_mf_params *p = tt->params;
        double r0 = from_ql(p->unloaded_radius);
        double worst_lane[6] = { 0, 0, 0, 0, 0, 0 };   /* |err| / (Fz, Fz R0) against float64 */
        double worst_scal[6] = { 0, 0, 0, 0, 0, 0 };
        double worst_tol = 0.0;                          /* |err| / the golden tolerance */
        double diff = 0.0;
        long bits = 0;
        grip_mf_prepared prep;
        golden_file g;
        int n = 0;
        int nf;
        int pure;
        assert_int_equal(golden_open(&g, tt->golden), 0);
        while ((nf = golden_next(&g)) > 0) {
            int j;
            assert_int_equal(nf, 12);
            assert_true(n < MAX_ROWS);
            g_in[n].kappa = (grip_real_t)golden_num(&g, 0);
            g_in[n].alpha = (grip_real_t)golden_num(&g, 1);
            g_in[n].gamma = (grip_real_t)golden_num(&g, 2);
            g_in[n].fz = (grip_real_t)golden_num(&g, 3);
            g_in[n].p = (grip_real_t)golden_num(&g, 4);
            g_in[n].vx = (grip_real_t)golden_num(&g, 5);
            for (j = 0; j < 6; j++) {
                g_want[n][j] = golden_num(&g, 6 + j);
            }
            n++;
        }
        golden_close(&g);
        assert_true(n > 100);
        assert_int_equal(grip_mf_prepare(p, p->options, &prep), GRIP_OK);
        for (pure = 1; pure >= 0; pure--) {
            int k;
            double w;
            (void)lanes(&prep, n, pure);
            scalar(&prep, n, pure);
            w = lane_vs_scalar(&prep, n, &bits);
            diff = (w > diff) ? w : diff;
            for (k = 0; k < n; k++) {
                double fz = (double)g_in[k].fz;
                const double *want = &g_want[k][pure ? 0 : 3];
                double got[3];
                double ref[3];
                double scale[3];
                int j;
                got[0] = g_lane[k].fx;
                got[1] = g_lane[k].fy;
                got[2] = g_lane[k].mz;
                ref[0] = g_ref[k].fx;
                ref[1] = g_ref[k].fy;
                ref[2] = g_ref[k].mz;
                scale[0] = scale[1] = fz;
                scale[2] = fz * r0;
                assert_int_equal(g_st[k], GRIP_OK);
                for (j = 0; j < 3; j++) {
                    int o = (pure ? 0 : 3) + j;
                    double e = fabs(got[j] - want[j]);
                    double tol = 1e-4 * fz;   /* test_mf_golden.c's float tolerance (Mz: 1e-4 Fz x 1 m) */
                    if (!(fz > 0.0)) {
                        continue;
                    }
                    if (e / scale[j] > worst_lane[o]) {
                        worst_lane[o] = e / scale[j];
                    }
                    if (fabs(ref[j] - want[j]) / scale[j] > worst_scal[o]) {
                        worst_scal[o] = fabs(ref[j] - want[j]) / scale[j];
                    }
                    if (!(e <= tol)) {
                        if (failures < 5) {
                            printf("# %s row %d %s: got %.9g want %.9g\n", tt->name, k, pure ? "pure" : "combined",
                                   got[j], want[j]);
                        }
                        failures++;
                    }
                    if (e / tol > worst_tol) {
                        worst_tol = e / tol;
                    }
                }
            }
        }
        printf("# %s: %d rows; lanes max |err| vs float64 / Fz (Mz: / Fz R0): Fx0 %.2e Fy0 %.2e Mz0 %.2e "
               "Fx %.2e Fy %.2e Mz %.2e (scalar path: %.2e %.2e %.2e %.2e %.2e %.2e); worst / tolerance %.3f; "
               "lanes vs scalar max %.2e, %ld outputs differ in a bit\n",
               tt->name, n, worst_lane[0], worst_lane[1], worst_lane[2], worst_lane[3], worst_lane[4], worst_lane[5],
               worst_scal[0], worst_scal[1], worst_scal[2], worst_scal[3], worst_scal[4], worst_scal[5], worst_tol,
               diff, bits);
#if GRIP_FLOAT_KERNELS >= 2
        assert_int_equal(bits, 0);
#else
        assert_true(diff <= LANE_TOL);
#endif
    }
    assert_int_equal(failures, 0);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_every_set),
        cmocka_unit_test(test_scalar_forms),
        cmocka_unit_test(test_counts),
        cmocka_unit_test(test_arguments),
#if !GRIP_ARITH_FIXED
        cmocka_unit_test(test_redo),
        cmocka_unit_test(test_golden),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
