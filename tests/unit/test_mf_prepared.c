/*
 * test_mf_prepared.c - grip_mf_prepare, grip_mf_eval_prepared,
 * grip_mf_eval_pure_prepared, grip_mf_eval_prepared_batch (grip_mf.h,
 * grip_mf_batch.h): the outputs and status of every point bit-identical to
 * grip_mf_eval / grip_mf_eval_pure on the set with the same options, for
 * every shared .tir set (tests/support/mf_params.h) and, on one set, every
 * combination of the plain option bits, over a grid that passes every clamp
 * and holds unloaded, reversing, standstill, default-pressure (p <= 0),
 * given-pressure and, in the float build, non-finite points; a set whose
 * own options differ from the prepared ones; the checks of grip_mf_prepare
 * (the field named, as grip_mf_check_params_detail does); an unprepared
 * set refused. Both builds.
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
static grip_mf_output g_out[NPTS];
static grip_mf_output g_ref[NPTS];
static grip_status_t g_st[NPTS];

/* The grid of mf_grid.h and, in the float build, non-finite points. */
static void fill_points(grip_real_t fnomin, grip_real_t nompres)
{
    mf_grid_fill(g_in, NPTS, fnomin, nompres);
#if !GRIP_ARITH_FIXED
    g_in[17].kappa = NAN;
    g_in[400].fz = INFINITY;
    g_in[1001].vx = -INFINITY;
    g_in[1500].p = NAN;
#endif
}

static int same(const grip_mf_output *a, const grip_mf_output *b)
{
    return memcmp(&a->fx, &b->fx, sizeof a->fx) == 0 && memcmp(&a->fy, &b->fy, sizeof a->fy) == 0 &&
           memcmp(&a->mz, &b->mz, sizeof a->mz) == 0;
}

/* p evaluated with `options` (a copy of p with them), against the prepared
 * set of p under `options`; returns the number of points compared. */
static int check_set(const grip_mf_params *p, uint32_t options, const char *name)
{
    grip_mf_params q = *p;
    grip_mf_prepared prep;
    grip_status_t sum;
    int k;
    int n_clamped = 0;
    int n_default_p = 0;
    int n_ext_valid = 0;
    int m;
    /* every channel, and what the estimator asks for (Re, sigma, K) */
    const uint32_t ext_sets[2] = { GRIP_MF_EXT_ALL, GRIP_MF_EXT_RE | GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY |
                                                        GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA };
    q.options = options;
    assert_int_equal(grip_mf_prepare(p, options, &prep), GRIP_OK);
    fill_points(p->fnomin, p->nompres);
    memset(g_out, 0x5A, sizeof g_out);
    sum = grip_mf_eval_prepared_batch(&prep, NPTS, g_in, g_out, g_st);
    assert_int_equal(sum, grip_mf_eval_batch(&q, NPTS, g_in, g_ref, NULL));
    for (k = 0; k < NPTS; k++) {
        grip_mf_output one;
        grip_mf_output two;
        grip_mf_output pure1;
        grip_mf_output pure2;
        grip_status_t s1 = grip_mf_eval(&q, &g_in[k], &one);
        grip_status_t s2 = grip_mf_eval_prepared(&prep, &g_in[k], &two);
        grip_status_t s3 = grip_mf_eval_pure(&q, &g_in[k], &pure1);
        grip_status_t s4 = grip_mf_eval_pure_prepared(&prep, &g_in[k], &pure2);
        if (s1 != s2 || !same(&one, &two)) {
            fail_msg("%s options 0x%x point %d: prepared combined differs (status %d vs %d)", name,
                     (unsigned)options, k, (int)s2, (int)s1);
        }
        if (s3 != s4 || !same(&pure1, &pure2)) {
            fail_msg("%s options 0x%x point %d: prepared pure differs (status %d vs %d)", name, (unsigned)options,
                     k, (int)s4, (int)s3);
        }
        for (m = 0; m < 2; m++) {
            grip_mf_output_ext e1;
            grip_mf_output_ext e2;
            grip_status_t s5 = grip_mf_eval_ext(&q, &g_in[k], ext_sets[m], &e1);
            grip_status_t s6 = grip_mf_eval_ext_prepared(&prep, &g_in[k], ext_sets[m], &e2);
            if (s5 != s6 || memcmp(&e1, &e2, sizeof e1) != 0) {
                fail_msg("%s options 0x%x point %d outputs 0x%x: prepared extended differs (status %d vs %d)",
                         name, (unsigned)options, k, (unsigned)ext_sets[m], (int)s6, (int)s5);
            }
            n_ext_valid += (s5 >= 0) && (e1.valid != 0u);
        }
        if (g_st[k] != s1 || !same(&g_out[k], &one) || !same(&g_ref[k], &one)) {
            fail_msg("%s options 0x%x point %d: batch differs (status %d, single %d)", name, (unsigned)options, k,
                     (int)g_st[k], (int)s1);
        }
        n_clamped += (s1 == GRIP_WARN_CLAMPED);
        n_default_p += (g_in[k].p <= 0) && (s1 >= 0);
    }
    assert_true(n_clamped > 0);
    assert_true(n_default_p > 0);
    assert_true(n_ext_valid > 0);
    return NPTS;
}

static void test_every_tire(void **s)
{
    int t;
    long n = 0;
    (void)s;
    assert_true(grip_test_tire_count > 0);
    for (t = 0; t < grip_test_tire_count; t++) {
        const grip_mf_params *p = grip_test_tires[t].params;
        n += check_set(p, p->options, grip_test_tires[t].name);
    }
    printf("# %d parameter sets, %ld points, combined, pure, extended and batch: prepared bit-identical to unprepared\n",
           grip_test_tire_count, n);
}

/* Every combination of the plain option bits, on an MF 6.1 and an MF 5.2
 * set. */
static void test_options(void **s)
{
    static const char *const names[] = { "MagicFormula61_Paramerters", "G275MSA_60psi" };
    const uint32_t plain = GRIP_MF_OPT_ALL & ~(GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS);
    int t;
    int combos = 0;
    (void)s;
    for (t = 0; t < 2; t++) {
        const grip_mf_params *p = grip_test_tire_params(names[t]);
        uint32_t o;
        assert_non_null(p);
        for (o = 0u; o <= GRIP_MF_OPT_ALL; o++) {
            if ((o & ~plain) == 0u) {
                (void)check_set(p, o, names[t]);
                combos++;
            }
        }
    }
    printf("# %d option combinations on MF 6.1 and MF 5.2: bit-identical\n", combos);
}

/* LMUV > 0 (friction decaying with slip speed: LMU* per call) and a
 * default pressure outside the domain (dpi clamped at preparation). */
static void test_per_call_friction_and_clamped_pressure(void **s)
{
    grip_mf_params q = *grip_test_tire_params("MagicFormula61_Paramerters");
    (void)s;
    q.lmuv = qs(0.3);
    q.longvl = qs(16.7);
    (void)check_set(&q, q.options, "LMUV 0.3");
    (void)check_set(&q, q.options | GRIP_MF_OPT_BOOK, "LMUV 0.3 book");
    q = *grip_test_tire_params("MagicFormula61_Paramerters");
    q.inflpres = (grip_real_t)(q.nompres * 3);   /* beyond 2 NOMPRES */
    (void)check_set(&q, q.options, "INFLPRES 3 NOMPRES");
    {
        grip_mf_prepared prep;
        grip_mf_output out;
        grip_mf_input in = { qs(0.01), qs(0.02), 0, ql(3000.0), 0, qs(20.0) };
        assert_int_equal(grip_mf_prepare(&q, q.options, &prep), GRIP_OK);
        assert_int_equal(grip_mf_eval_prepared(&prep, &in, &out), GRIP_WARN_CLAMPED);
    }
}

/* The prepared options replace the set's own: a set asking for turn slip
 * (grip_mf_eval refuses it) prepared without it evaluates as the set
 * without it. */
static void test_options_replace_the_sets(void **s)
{
    grip_mf_params q = *grip_test_tire_params("MagicFormula61_Paramerters");
    grip_mf_params plain = q;
    grip_mf_prepared prep;
    grip_mf_output a;
    grip_mf_output b;
    grip_mf_input in = { qs(0.05), qs(-0.04), qs(0.02), ql(4000.0), 0, qs(15.0) };
    (void)s;
    q.options = GRIP_MF_OPT_TURN_SLIP;
    plain.options = GRIP_MF_OPT_RIGHT_SIDE;
    assert_int_equal(grip_mf_eval(&q, &in, &a), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_prepare(&q, GRIP_MF_OPT_RIGHT_SIDE, &prep), GRIP_OK);
    assert_int_equal(grip_mf_eval_prepared(&prep, &in, &a), GRIP_OK);
    assert_int_equal(grip_mf_eval(&plain, &in, &b), GRIP_OK);
    assert_true(same(&a, &b));
    assert_true(a.fy != 0);
}

static void expect_refused(const grip_mf_params *p, uint32_t options, const char *field)
{
    grip_mf_prepared prep;
    grip_check_detail_t d;
    grip_mf_output out;
    grip_mf_input in = { qs(0.01), qs(0.02), 0, ql(3000.0), 0, qs(20.0) };
    grip_status_t st;
    memset(&prep, 0x5A, sizeof prep);
    assert_int_equal(grip_mf_prepare_detail(p, options, &prep, &d), GRIP_ERR_PARAM);
    assert_string_equal(d.field, field);
    assert_true(d.rule[0] != '\0');
    assert_int_equal(grip_mf_prepare(p, options, &prep), GRIP_ERR_PARAM);
    /* an evaluation with the refused set fails with zero outputs */
    out.fx = out.fy = out.mz = (grip_real_t)1;
    st = grip_mf_eval_prepared(&prep, &in, &out);
    assert_int_equal(st, GRIP_ERR_PARAM);
    assert_true(out.fx == 0 && out.fy == 0 && out.mz == 0);
    assert_int_equal(grip_mf_eval_pure_prepared(&prep, &in, &out), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_eval_prepared_batch(&prep, 1u, &in, &out, NULL), GRIP_ERR_PARAM);
    {
        grip_mf_output_ext ext;
        ext.fx = (grip_real_t)1;
        ext.valid = 1u;
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, GRIP_MF_EXT_ALL, &ext), GRIP_ERR_PARAM);
        assert_true(ext.fx == 0 && ext.valid == 0u);
    }
}

/* Sets outside the box of the fixed build's certificate (a coefficient of a
 * certified term too large, a load factor LFZO so small that dfz reaches
 * 79, a curve's shape factor C beyond 20000), each with a term that does
 * leave Q15.16: not certified (MF_PF_CERT, 0x400 of lib/mf/mf_internal.h, nor
 * MF_PF_CERT_EXT, 0x800), and the prepared evaluation, on the checked
 * operations, still the unprepared one bit for bit; likewise sets beyond
 * the box of the extended outputs' terms alone; the shipped sets are
 * certified. Both builds (the float build has no certificate). */
static void test_certificate(void **s)
{
    const grip_mf_params *good = grip_test_tire_params("MagicFormula61_Paramerters");
    grip_mf_params p;
    grip_mf_prepared prep;
    int k;
    (void)s;
    for (k = 0; k < 4; k++) {
        p = *good;
        if (k == 0) {
            p.pex1 = qs(30000.0);   /* PEX1 + PEX3 dfz^2 reaches 57000 */
            p.pex3 = qs(3000.0);
        } else if (k == 1) {
            p.rvy6 = qs(-30000.0);  /* RVY6 kappa reaches 45000 */
        } else if (k == 2) {
            p.lfzo = qs(0.05);      /* QBZ3 dfz^2 reaches -62000 */
            p.qbz3 = qs(-10.0);
        } else {
            p.qcz1 = qs(25000.0);   /* the trail's C atan(.) reaches 39000 */
        }
        assert_int_equal(grip_mf_prepare(&p, p.options, &prep), GRIP_OK);
#if GRIP_ARITH_FIXED && !defined(__OPTIMIZE_SIZE__)
        assert_true((prep.flags & 0xC00u) == 0u);
#endif
        (void)check_set(&p, p.options, "uncertified");
    }
    /* beyond the extended outputs' box only (MF_PF_CERT_EXT, 0x800): the
     * combined evaluation certified, the channels checked */
    for (k = 0; k < 3; k++) {
        p = *good;
        if (k == 0) {
            p.breff = qs(10000.0);  /* BREFF Fz / FNOMIN reaches 40000 */
        } else if (k == 1) {
            p.pcfy1 = qs(20.0);     /* Cy (1 + PCFY1 dfz ...) LATERAL_STIFFNESS beyond 8e6 N/m */
        } else {
            p.pcfx2 = qs(-3000.0);  /* PCFX2 dfz^2 reaches -27000, Cx beyond QL */
        }
        assert_int_equal(grip_mf_prepare(&p, p.options, &prep), GRIP_OK);
#if GRIP_ARITH_FIXED && !defined(__OPTIMIZE_SIZE__)
        assert_true((prep.flags & 0xC00u) == 0x400u);
#endif
        (void)check_set(&p, p.options, "uncertified channels");
    }
#if GRIP_ARITH_FIXED && !defined(__OPTIMIZE_SIZE__)
    for (k = 0; k < grip_test_tire_count; k++) {
        assert_int_equal(grip_mf_prepare(grip_test_tires[k].params, 0u, &prep), GRIP_OK);
        assert_true((prep.flags & 0xC00u) == 0xC00u);
    }
#endif
}

static void test_bad_sets(void **s)
{
    const grip_mf_params *good = grip_test_tire_params("MagicFormula61_Paramerters");
    grip_mf_params p;
    grip_mf_prepared prep;
    grip_check_detail_t d;
    (void)s;
    expect_refused(good, GRIP_MF_OPT_TURN_SLIP, "options");
    expect_refused(good, GRIP_MF_OPT_NO_LIMITS, "options");
    expect_refused(good, 0x80000000u, "options");
    p = *good;
    p.fnomin = 0;
    expect_refused(&p, 0u, "fnomin");
    p = *good;
    p.fittyp = 7;
    expect_refused(&p, 0u, "fittyp");
    p = *good;
    p.tyreside = 0;
    expect_refused(&p, 0u, "tyreside");
    p = *good;
    p.unloaded_radius = 0;
    expect_refused(&p, 0u, "unloaded_radius");
    p = *good;
    p.lfzo = qs(-1.0);
    expect_refused(&p, 0u, "lfzo");
    p = *good;
    p.lmuv = qs(0.5);
    p.longvl = 0;
    expect_refused(&p, 0u, "longvl");
#if !GRIP_ARITH_FIXED
    /* the per-coefficient finiteness, which grip_mf_eval does not check per call */
    p = *good;
    p.pky1 = NAN;
    expect_refused(&p, 0u, "pky1");
    p = *good;
    p.ssz1 = INFINITY;
    expect_refused(&p, 0u, "ssz1");
#endif
    /* NULL arguments */
    assert_int_equal(grip_mf_prepare_detail(NULL, 0u, &prep, &d), GRIP_ERR_NULL);
    assert_string_equal(d.field, "");
    assert_null(prep.p);
    assert_int_equal(grip_mf_prepare(good, 0u, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_prepare_detail(good, 0u, &prep, NULL), GRIP_OK);
    assert_int_equal(grip_mf_prepare_detail(good, 0u, &prep, &d), GRIP_OK);
    assert_string_equal(d.field, "");
    {
        grip_mf_output out;
        grip_mf_input in = { 0, 0, 0, ql(3000.0), 0, qs(20.0) };
        assert_int_equal(grip_mf_eval_prepared(NULL, &in, &out), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_prepared(&prep, NULL, &out), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_prepared(&prep, &in, NULL), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_pure_prepared(NULL, &in, &out), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_prepared_batch(&prep, 0u, NULL, NULL, NULL), GRIP_OK);
        assert_int_equal(grip_mf_eval_prepared_batch(NULL, 1u, &in, &out, NULL), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_prepared_batch(&prep, 1u, NULL, &out, NULL), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_prepared_batch(&prep, 1u, &in, NULL, NULL), GRIP_ERR_NULL);
    }
    {
        /* the extended outputs: NULLs, and no use mode with a prepared set */
        grip_mf_output_ext ext;
        grip_mf_input in = { qs(0.05), qs(0.02), 0, ql(3000.0), 0, qs(20.0) };
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, GRIP_MF_EXT_ALL, NULL), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_ext_prepared(NULL, &in, GRIP_MF_EXT_ALL, &ext), GRIP_ERR_NULL);
        assert_true(ext.valid == 0u);
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, NULL, GRIP_MF_EXT_ALL, &ext), GRIP_ERR_NULL);
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP, &ext),
                         GRIP_ERR_INPUT);
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, GRIP_MF_EXT_ALL | GRIP_MF_USE_NO_LIMITS, &ext),
                         GRIP_ERR_INPUT);
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, 0x40000000u, &ext), GRIP_ERR_INPUT);
        assert_true(ext.fx == 0 && ext.valid == 0u);
        assert_int_equal(grip_mf_eval_ext_prepared(&prep, &in, GRIP_MF_EXT_RE, &ext), GRIP_OK);
        assert_true(ext.fy != 0 && ext.valid == GRIP_MF_EXT_RE && ext.re > 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_tire),
        cmocka_unit_test(test_options),
        cmocka_unit_test(test_per_call_friction_and_clamped_pressure),
        cmocka_unit_test(test_options_replace_the_sets),
        cmocka_unit_test(test_certificate),
        cmocka_unit_test(test_bad_sets),
    };
    return cmocka_run_group_tests_name("mf_prepared", tests, NULL, NULL);
}
