/*
 * test_check_detail.c - the library's parameter checks name the field that
 * failed (grip_check_detail_t, grip_types.h): grip_mf_check_params_detail,
 * grip_*_check_params_detail of the brush family, grip_est_init_detail and
 * grip_monitor_init_detail. For each: a valid set passes with an empty
 * detail; each broken field is named with its rule; the status is always
 * that of the function without detail (the same checks in the same order),
 * also over a seeded mutation of every field; NULL detail is accepted.
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
#include "grip/grip_est.h"
#include "grip/grip_mf.h"
#include "grip/grip_monitor.h"
#include "brush_params.h"
#include "mf_params.h"

#if GRIP_ARITH_FIXED
static grip_real_t q(double v) { return (grip_real_t)lround(v * 65536.0); }
static grip_real_t ql(double v) { return (grip_real_t)lround(v * 256.0); }
#else
static grip_real_t q(double v) { return (grip_real_t)v; }
static grip_real_t ql(double v) { return (grip_real_t)v; }
#endif

static void expect_detail(const grip_check_detail_t *d, const char *part, int index, const char *field,
                          const char *rule)
{
    print_message("# %s[%d].%s: %s\n", d->part, (int)d->index, d->field, d->rule);
    assert_string_equal(d->part, part);
    assert_int_equal(d->index, index);
    assert_string_equal(d->field, field);
    if (strstr(d->rule, rule) == NULL) {
        fail_msg("rule '%s' lacks '%s'", d->rule, rule);
    }
}

static const grip_mf_params *valid_mf(void)
{
    const grip_mf_params *p = grip_test_tire_params("MagicFormula61_Paramerters");
    if (p == NULL) {
        fail_msg("no emitted parameter set MagicFormula61_Paramerters (make golden)");
    }
    return p;
}

static void test_mf(void **state)
{
    grip_mf_params p;
    grip_check_detail_t d;
    (void)state;
    p = *valid_mf();
    memset(&d, 0x55, sizeof d);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_OK);
    expect_detail(&d, "", -1, "", "");
    assert_int_equal(grip_mf_check_params_detail(NULL, &d), GRIP_ERR_NULL);
    assert_string_equal(d.field, "");
    assert_int_equal(grip_mf_check_params_detail(&p, NULL), GRIP_OK);

    p.fittyp = 52;
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "fittyp", "one of 5, 6, 21");
    p = *valid_mf();
    p.fnomin = ql(2.0e6);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "fnomin", "in (0, 1e6] N");
    p = *valid_mf();
    p.tyreside = 0;
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "tyreside", "+1");
    p = *valid_mf();
    p.options = 0x200u;   /* the first bit above GRIP_MF_OPT_ALL */
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "options", "GRIP_MF_OPT_");
    /* turn slip without its coefficients */
    p = *valid_mf();
    p.options = GRIP_MF_OPT_TURN_SLIP;
    p.phyp1 = q(0.0);
    p.qdrp1 = q(1.0);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "phyp1", "> 0 with GRIP_MF_OPT_TURN_SLIP");
    p.phyp1 = q(1.0);
    p.qdrp1 = q(2.0);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "qdrp1", "in (0, 2)");
    p.qdrp1 = q(1.0);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_OK);
    p = *valid_mf();
    p.lmuv = q(0.5);
    p.longvl = q(0.05);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "longvl", "when LMUV > 0");
    p = *valid_mf();
    p.lmuy = q(-0.1);
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "lmuy", ">= 0");
#if !GRIP_ARITH_FIXED
    p = *valid_mf();
    p.qdz4 = (grip_real_t)NAN;
    assert_int_equal(grip_mf_check_params_detail(&p, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "qdz4", "finite");
#endif
}

/* Every field of each struct set to each of a few hostile values: the
 * detail version gives the status of the plain one, and names a field
 * exactly when it fails. */
static const double HOSTILE[] = { 0.0, -1.0, 1.0e9, -1.0e9, 0.5, 3.5, 1.0e-6 };
#define N_HOSTILE (sizeof HOSTILE / sizeof HOSTILE[0])

static void check_consistent(grip_status_t plain, grip_status_t detail, const grip_check_detail_t *d)
{
    assert_int_equal(plain, detail);
    if (detail == GRIP_OK) {
        assert_string_equal(d->field, "");
    } else {
        assert_true(d->field[0] != '\0');
        assert_true(d->rule[0] != '\0');
    }
}

static void test_mf_agrees(void **state)
{
    size_t off;
    size_t h;
    int failed = 0;
    (void)state;
    for (off = offsetof(grip_mf_params, longvl); off + sizeof(grip_real_t) <= sizeof(grip_mf_params);
         off += sizeof(grip_real_t)) {
        for (h = 0; h < N_HOSTILE; h++) {
            grip_mf_params p = *valid_mf();
            grip_check_detail_t d;
            grip_real_t v = ql(HOSTILE[h] > 8.0e6 ? 8.0e6 : (HOSTILE[h] < -8.0e6 ? -8.0e6 : HOSTILE[h]));
            grip_status_t a;
            memcpy((char *)&p + off, &v, sizeof v);
            a = grip_mf_check_params(&p);
            check_consistent(a, grip_mf_check_params_detail(&p, &d), &d);
            failed += (a != GRIP_OK);
        }
    }
    print_message("# %d of the mutated MF sets rejected, each with a field\n", failed);
    assert_true(failed >= 15);
}

static void brush_set(const char *model, grip_brush_tool *t)
{
    char text[64];
    char err[256];
    snprintf(text, sizeof text, "model = %s\n", model);
    if (grip_brush_params_parse(text, "t.txt", NULL, t, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
}

static grip_status_t brush_detail(grip_brush_tool *t, grip_check_detail_t *d, grip_status_t *plain)
{
    switch (t->kind) {
    case GRIP_BRUSH_KIND_FIALA:
        *plain = grip_fiala_check_params(&t->fiala);
        return grip_fiala_check_params_detail(&t->fiala, d);
    case GRIP_BRUSH_KIND_BRUSH:
        *plain = grip_brush_check_params(&t->brush);
        return grip_brush_check_params_detail(&t->brush, d);
    case GRIP_BRUSH_KIND_SAKAI:
        *plain = grip_sakai_check_params(&t->sakai);
        return grip_sakai_check_params_detail(&t->sakai, d);
    default:
        *plain = grip_neofiala_check_params(&t->neofiala);
        return grip_neofiala_check_params_detail(&t->neofiala, d);
    }
}

static void test_brush(void **state)
{
    static const struct {
        const char *model;
        size_t off;
        double v;
        int ql_fmt;
        const char *field;
        const char *rule;
    } C[] = {
        { "fiala", offsetof(grip_fiala_params, mu), 4.0, 0, "mu", "in (0, 3]" },
        { "fiala", offsetof(grip_fiala_params, alpha_max), 1.5, 0, "alpha_max", "in (0, 1] rad" },
        { "brush", offsetof(grip_brush_params, mu_d0), 2.0, 0, "mu_s", "in [mu_d0, 3]" },
        { "brush", offsetof(grip_brush_params, v_max), 200.0, 0, "v_max", "in (0, 150] m/s" },
        { "sakai", offsetof(grip_sakai_params, g_y), 10.0, 1, "g_y", "mu_s fz_max / (l g_y) <= 4" },
        { "sakai", offsetof(grip_sakai_params, kappa_max), 0.0, 0, "kappa_max", "in (0, 10]" },
        { "neofiala", offsetof(grip_neofiala_params, w), 0.0, 0, "w", "in (0, 2] m" },
        { "neofiala", offsetof(grip_neofiala_params, q0), 0.7, 0, "q0", "|q0| <= 0.5" },
        { "neofiala", offsetof(grip_neofiala_params, gamma_max), 0.5, 0, "gamma_max", "in [0, 0.35] rad" },
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof C / sizeof C[0]; i++) {
        grip_brush_tool t;
        grip_check_detail_t d;
        grip_status_t plain;
        grip_real_t v = C[i].ql_fmt ? ql(C[i].v) : q(C[i].v);
        char *base;
        brush_set(C[i].model, &t);
        assert_int_equal(brush_detail(&t, &d, &plain), GRIP_OK);
        assert_string_equal(d.field, "");
        base = (t.kind == GRIP_BRUSH_KIND_FIALA) ? (char *)&t.fiala
             : (t.kind == GRIP_BRUSH_KIND_BRUSH) ? (char *)&t.brush
             : (t.kind == GRIP_BRUSH_KIND_SAKAI) ? (char *)&t.sakai : (char *)&t.neofiala;
        memcpy(base + C[i].off, &v, sizeof v);
        assert_int_equal(brush_detail(&t, &d, &plain), GRIP_ERR_PARAM);
        assert_int_equal(plain, GRIP_ERR_PARAM);
        expect_detail(&d, "", -1, C[i].field, C[i].rule);
    }
    assert_int_equal(grip_fiala_check_params_detail(NULL, NULL), GRIP_ERR_NULL);
}

static void test_brush_agrees(void **state)
{
    static const char *const MODELS[] = { "fiala", "brush", "sakai", "neofiala" };
    size_t m;
    int failed = 0;
    (void)state;
    for (m = 0; m < 4; m++) {
        grip_brush_tool t0;
        size_t size;
        size_t off;
        brush_set(MODELS[m], &t0);
        size = (t0.kind == GRIP_BRUSH_KIND_FIALA) ? sizeof t0.fiala
             : (t0.kind == GRIP_BRUSH_KIND_BRUSH) ? sizeof t0.brush
             : (t0.kind == GRIP_BRUSH_KIND_SAKAI) ? sizeof t0.sakai : sizeof t0.neofiala;
        for (off = 0; off + sizeof(grip_real_t) <= size; off += sizeof(grip_real_t)) {
            size_t h;
            for (h = 0; h < N_HOSTILE; h++) {
                grip_brush_tool t = t0;
                grip_check_detail_t d;
                grip_status_t plain;
                grip_status_t st;
                char *base = (t.kind == GRIP_BRUSH_KIND_FIALA) ? (char *)&t.fiala
                           : (t.kind == GRIP_BRUSH_KIND_BRUSH) ? (char *)&t.brush
                           : (t.kind == GRIP_BRUSH_KIND_SAKAI) ? (char *)&t.sakai : (char *)&t.neofiala;
                grip_real_t v = q(HOSTILE[h] > 30000.0 ? 30000.0 : (HOSTILE[h] < -30000.0 ? -30000.0 : HOSTILE[h]));
                memcpy(base + off, &v, sizeof v);
                st = brush_detail(&t, &d, &plain);
                check_consistent(plain, st, &d);
                failed += (st != GRIP_OK);
            }
        }
    }
    print_message("# %d of the mutated brush-family sets rejected, each with a field\n", failed);
    assert_true(failed > 50);
}

static void test_est(void **state)
{
    grip_est_config_t cfg;
    grip_est_config_t c;
    grip_mf_params bad;
    grip_est_t est;
    grip_check_detail_t d;
    (void)state;
    assert_int_equal(grip_est_config_default(&cfg, valid_mf()), GRIP_OK);
    assert_int_equal(grip_est_init_detail(&est, &cfg, &d), GRIP_OK);
    expect_detail(&d, "", -1, "", "");
    c = cfg;
    c.mass = ql(0.5);
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "mass", "in [1, 60000] kg");
    c = cfg;
    c.rate_hz = 25u;
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "rate_hz", "50..2000");
    c = cfg;
    c.steer_latency = q(0.5);
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "steer_latency", "in [0, 0.1] s");
    assert_int_equal(grip_est_init(&est, &c), GRIP_ERR_PARAM);
    c = cfg;
    c.kx_est = 2u;
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "kx_est", "0 or 1");
    c = cfg;
    c.drive_front = q(1.5);
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "drive_front", "in [0, 1]");
    c = cfg;
    c.tire[1].model.mf = NULL;
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "tire", 1, "model.mf", "not NULL");
    bad = *valid_mf();
    bad.unloaded_radius = q(0.0);
    c = cfg;
    c.tire[0].model.mf = &bad;
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "tire", 0, "unloaded_radius", "> 0 m");
    /* a valid set that gives no cornering stiffness: named as the model */
    bad = *valid_mf();
    bad.pky1 = q(0.0);
    c = cfg;
    c.tire[1].model.mf = &bad;
    assert_int_equal(grip_est_init_detail(&est, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "tire", 1, "model.mf", "cornering stiffness > 0");
    assert_int_equal(grip_est_init_detail(&est, &cfg, NULL), GRIP_OK);
    assert_int_equal(grip_est_init_detail(NULL, &cfg, &d), GRIP_ERR_NULL);
}

static void test_monitor(void **state)
{
    grip_monitor_config_t cfg;
    grip_monitor_config_t c;
    grip_monitor_t mon;
    grip_check_detail_t d;
    (void)state;
    assert_int_equal(grip_monitor_config_default(&cfg), GRIP_OK);
    assert_int_equal(grip_monitor_init_detail(&mon, &cfg, &d), GRIP_OK);
    expect_detail(&d, "", -1, "", "");
    c = cfg;
    c.stab_factor_x100 = q(2.0);
    assert_int_equal(grip_monitor_init_detail(&mon, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "stab_factor_x100", "in [-1, 1]");
    assert_int_equal(grip_monitor_init(&mon, &c), GRIP_ERR_PARAM);
    c = cfg;
    c.driven = 0u;
    assert_int_equal(grip_monitor_init_detail(&mon, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "driven", "1 (front)");
    c = cfg;
    c.track_r = q(9.0);
    assert_int_equal(grip_monitor_init_detail(&mon, &c, &d), GRIP_ERR_PARAM);
    expect_detail(&d, "", -1, "track_r", "in [0.2, 4] m");
    assert_int_equal(grip_monitor_init_detail(&mon, &cfg, NULL), GRIP_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mf),
        cmocka_unit_test(test_mf_agrees),
        cmocka_unit_test(test_brush),
        cmocka_unit_test(test_brush_agrees),
        cmocka_unit_test(test_est),
        cmocka_unit_test(test_monitor),
    };
    return cmocka_run_group_tests_name("check_detail_" GRIP_ARITH_NAME, tests, NULL, NULL);
}
