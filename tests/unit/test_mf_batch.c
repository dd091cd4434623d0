/*
 * test_mf_batch.c - grip_mf_eval_batch / grip_mf_eval_pure_batch
 * (grip_mf_batch.h): every point bit-identical to grip_mf_eval /
 * grip_mf_eval_pure with the same status, for every shared .tir set
 * (tests/support/mf_params.h) over a grid that passes every clamp and
 * includes unloaded, reversing, standstill and non-finite points; the
 * summary status; argument checks; the loop bounded by n (nothing beyond
 * out[n - 1] or status[n - 1] is written). Both builds.
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
#include "mf_grid.h"
#include "mf_params.h"

#if GRIP_ARITH_FIXED
static grip_real_t qs(double v) { return (grip_real_t)lround(v * 65536.0); }
static grip_real_t ql(double v) { return (grip_real_t)lround(v * 256.0); }
#else
static grip_real_t qs(double v) { return (grip_real_t)v; }
static grip_real_t ql(double v) { return (grip_real_t)v; }
#endif

#define NPTS 2048

static grip_mf_input g_in[NPTS];
static grip_mf_output g_out[NPTS + 1];
static grip_status_t g_st[NPTS + 1];

/* A deterministic grid (mf_grid.h) and, in the float build, non-finite
 * points, which only fail. */
static void fill_points(grip_real_t fnomin, grip_real_t nompres)
{
    mf_grid_fill(g_in, NPTS, fnomin, nompres);
#if !GRIP_ARITH_FIXED
    /* non-finite inputs: those points only fail */
    g_in[17].kappa = NAN;
    g_in[400].fz = INFINITY;
    g_in[1001].vx = -INFINITY;
#endif
}

static int same_bits(grip_real_t a, grip_real_t b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void check_set(const grip_mf_params *p, int pure, const char *name)
{
    grip_status_t want_sum = GRIP_OK;
    grip_status_t sum;
    int first_error = 1;
    int k;
    int n_err = 0;
    int n_warn = 0;
    fill_points(p->fnomin, p->nompres);
    memset(g_out, 0x5A, sizeof g_out);
    memset(g_st, 0x5A, sizeof g_st);
    sum = pure ? grip_mf_eval_pure_batch(p, NPTS, g_in, g_out, g_st) : grip_mf_eval_batch(p, NPTS, g_in, g_out, g_st);
    for (k = 0; k < NPTS; k++) {
        grip_mf_output one;
        grip_status_t st = pure ? grip_mf_eval_pure(p, &g_in[k], &one) : grip_mf_eval(p, &g_in[k], &one);
        if (st != g_st[k] || !same_bits(one.fx, g_out[k].fx) || !same_bits(one.fy, g_out[k].fy) ||
            !same_bits(one.mz, g_out[k].mz)) {
            fail_msg("%s %s point %d: batch differs from the single evaluation (status %d vs %d)", name,
                     pure ? "pure" : "combined", k, (int)g_st[k], (int)st);
        }
        if (st < 0) {
            n_err++;
            if (first_error) {
                want_sum = st;
                first_error = 0;
            }
        } else if (st == GRIP_WARN_CLAMPED) {
            n_warn++;
            if (want_sum >= 0) {
                want_sum = GRIP_WARN_CLAMPED;
            }
        }
    }
    assert_int_equal(sum, want_sum);
    /* nothing beyond n written */
    {
        unsigned char sentinel[sizeof g_out[0]];
        memset(sentinel, 0x5A, sizeof sentinel);
        assert_memory_equal(&g_out[NPTS], sentinel, sizeof g_out[0]);
        memset(sentinel, 0x5A, sizeof g_st[0]);
        assert_memory_equal(&g_st[NPTS], sentinel, sizeof g_st[0]);
    }
    assert_true(n_warn > 0);   /* the grid passes the clamps */
#if !GRIP_ARITH_FIXED
    assert_true(n_err >= 3);
    assert_int_equal(g_st[17], GRIP_ERR_INPUT);
    assert_int_equal(g_st[400], GRIP_ERR_INPUT);
    assert_int_equal(g_st[1001], GRIP_ERR_INPUT);
#else
    (void)n_err;
#endif
}

static void test_every_tire_bit_identical(void **s)
{
    int t;
    (void)s;
    assert_true(grip_test_tire_count > 0);
    for (t = 0; t < grip_test_tire_count; t++) {
        check_set(grip_test_tires[t].params, 0, grip_test_tires[t].name);
        check_set(grip_test_tires[t].params, 1, grip_test_tires[t].name);
    }
    printf("# %d parameter sets x %d points, combined and pure: bit-identical to the single calls\n",
           grip_test_tire_count, NPTS);
}

/* Every option bit (one set), also bit-identical. */
/* A set with a use mode of grip_mf_eval_ext (turn slip, no limits): every
 * point GRIP_ERR_PARAM with zero outputs, as the single calls. */
static void check_refused(const grip_mf_params *p, int pure)
{
    int k;
    fill_points(p->fnomin, p->nompres);
    memset(g_out, 0x5A, sizeof g_out);
    memset(g_st, 0x5A, sizeof g_st);
    assert_int_equal(pure ? grip_mf_eval_pure_batch(p, NPTS, g_in, g_out, g_st)
                          : grip_mf_eval_batch(p, NPTS, g_in, g_out, g_st),
                     GRIP_ERR_PARAM);
    for (k = 0; k < NPTS; k++) {
        grip_mf_output one;
        assert_int_equal(pure ? grip_mf_eval_pure(p, &g_in[k], &one) : grip_mf_eval(p, &g_in[k], &one),
                         GRIP_ERR_PARAM);
        assert_int_equal(g_st[k], GRIP_ERR_PARAM);
        assert_true(g_out[k].fx == 0 && g_out[k].fy == 0 && g_out[k].mz == 0);
    }
}

static void test_options(void **s)
{
    grip_mf_params q = *grip_test_tires[0].params;
    uint32_t o;
    (void)s;
    for (o = 0u; o <= GRIP_MF_OPT_ALL; o++) {
        q.options = o;
        if ((o & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) != 0u) {
            check_refused(&q, 0);
            check_refused(&q, 1);
        } else {
            check_set(&q, 0, "options");
        }
    }
}

static void test_arguments(void **s)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    grip_mf_params bad = *p;
    grip_mf_input in[4];
    grip_mf_output out[4];
    grip_status_t st[4];
    int k;
    (void)s;
    fill_points(p->fnomin, p->nompres);
    memcpy(in, &g_in[20], sizeof in);
    /* n == 0: nothing is read or written, NULL allowed */
    assert_int_equal(grip_mf_eval_batch(NULL, 0u, NULL, NULL, NULL), GRIP_OK);
    assert_int_equal(grip_mf_eval_pure_batch(NULL, 0u, NULL, NULL, NULL), GRIP_OK);
    /* NULL pointers */
    memset(out, 0x5A, sizeof out);
    assert_int_equal(grip_mf_eval_batch(NULL, 4u, in, out, st), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_batch(p, 4u, NULL, out, st), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_batch(p, 4u, in, NULL, st), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_pure_batch(p, 4u, in, NULL, st), GRIP_ERR_NULL);
    /* status may be NULL: the summary alone, the same outputs */
    {
        grip_mf_output out2[4];
        grip_status_t sum = grip_mf_eval_batch(p, 4u, in, out, st);
        assert_int_equal(grip_mf_eval_batch(p, 4u, in, out2, NULL), sum);
        assert_memory_equal(out, out2, sizeof out);
    }
    /* an unusable set: every point GRIP_ERR_PARAM with zero outputs */
    bad.fittyp = 7;
    memset(out, 0x5A, sizeof out);
    assert_int_equal(grip_mf_eval_batch(&bad, 4u, in, out, st), GRIP_ERR_PARAM);
    for (k = 0; k < 4; k++) {
        assert_int_equal(st[k], GRIP_ERR_PARAM);
        assert_true(out[k].fx == 0 && out[k].fy == 0 && out[k].mz == 0);
    }
    assert_int_equal(grip_mf_eval_pure_batch(&bad, 4u, in, out, NULL), GRIP_ERR_PARAM);
}

/* The four wheels of one step: the use the batch is meant for on an ECU. */
static void test_four_wheels(void **s)
{
    const grip_mf_params *p = grip_test_tires[0].params;
    grip_mf_input in[4];
    grip_mf_output out[4];
    grip_status_t st[4];
    int k;
    (void)s;
    for (k = 0; k < 4; k++) {
        in[k].kappa = qs(0.01 * (k + 1));
        in[k].alpha = qs(0.02 * (k - 1.5));
        in[k].gamma = qs(-0.01);
        in[k].fz = ql(3500.0 + 250.0 * k);
        in[k].p = 0;
        in[k].vx = qs(25.0);
    }
    assert_int_equal(grip_mf_eval_batch(p, 4u, in, out, st), GRIP_OK);
    for (k = 0; k < 4; k++) {
        grip_mf_output one;
        assert_int_equal(grip_mf_eval(p, &in[k], &one), GRIP_OK);
        assert_int_equal(st[k], GRIP_OK);
        assert_memory_equal(&one, &out[k], sizeof one);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_tire_bit_identical),
        cmocka_unit_test(test_options),
        cmocka_unit_test(test_arguments),
        cmocka_unit_test(test_four_wheels),
    };
    return cmocka_run_group_tests_name("mf_batch", tests, NULL, NULL);
}
