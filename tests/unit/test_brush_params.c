/*
 * test_brush_params.c - the parameter-file reader of the brush models
 * (port/linux/brush_params.c) against files written by
 * tools/grip_tools/reference/brush.py (golden folder: brush_params_<model>.txt holds
 * set 0 of brush_<model>.txt; brush_params_<model>_default.txt the Python
 * defaults): values and per-kN unit conversions, defaults, every error
 * message, the dump round trip and the grip-tire evaluation hook.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "brush_params.h"
#include "golden.h"

static const char *const MODELS[4] = { "fiala", "brush", "sakai", "neofiala" };

static void golden_path(char *out, size_t n, const char *file)
{
    const char *dir = getenv("GRIP_GOLDEN_DIR");
    snprintf(out, n, "%s/%s", (dir != NULL) ? dir : "build/golden", file);
}

/* The P row of set 0 in brush_<model>.txt, converted like the C tests do. */
static void first_prow(const char *model, double *vals, int *nvals)
{
    golden_file g;
    char name[64];
    int i;
    snprintf(name, sizeof name, "brush_%s.txt", model);
    assert_int_equal(golden_open(&g, name), 0);
    *nvals = 0;
    while (golden_next(&g) > 0) {
        if (g.field[0][0] == 'P' && (int)golden_num(&g, 1) == 0) {
            for (i = 2; i < g.nfields; ++i) {
                vals[(*nvals)++] = golden_num(&g, i);
            }
            break;
        }
    }
    golden_close(&g);
    assert_true(*nvals > 5);
}

static const void *struct_of(const grip_brush_tool *t)
{
    switch (t->kind) {
    case GRIP_BRUSH_KIND_FIALA: return &t->fiala;
    case GRIP_BRUSH_KIND_BRUSH: return &t->brush;
    case GRIP_BRUSH_KIND_SAKAI: return &t->sakai;
    case GRIP_BRUSH_KIND_NEOFIALA: return &t->neofiala;
    default: return NULL;
    }
}

static size_t struct_size(grip_brush_kind k)
{
    switch (k) {
    case GRIP_BRUSH_KIND_FIALA: return sizeof(grip_fiala_params);
    case GRIP_BRUSH_KIND_BRUSH: return sizeof(grip_brush_params);
    case GRIP_BRUSH_KIND_SAKAI: return sizeof(grip_sakai_params);
    case GRIP_BRUSH_KIND_NEOFIALA: return sizeof(grip_neofiala_params);
    default: return 0;
    }
}

/* Every struct is a sequence of 32-bit fields in C order (grip_real_t or
 * int32_t n); compare field i with the P row (C units). The P row values
 * are on the QS/QL grids, so both builds must hold them exactly. */
static void test_values_match_golden(void **s)
{
    int m;
    (void)s;
    for (m = 0; m < 4; ++m) {
        grip_brush_tool t;
        char path[600];
        char file[64];
        char err[512];
        double vals[64];
        int nvals;
        int i;
        const unsigned char *base;
        snprintf(file, sizeof file, "brush_params_%s.txt", MODELS[m]);
        golden_path(path, sizeof path, file);
        if (grip_brush_params_read(path, MODELS[m], &t, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        first_prow(MODELS[m], vals, &nvals);
        assert_int_equal((size_t)nvals * 4u, struct_size(t.kind));
        base = struct_of(&t);
        for (i = 0; i < nvals; ++i) {
            int32_t n;
            grip_real_t r;
            double got;
            memcpy(&n, base + 4 * i, 4);
            memcpy(&r, base + 4 * i, 4);
            if (vals[i] == (double)(int32_t)vals[i] && ((m == 1 && i == 4) || (m == 3 && i == 7))) {
                got = (double)n;                       /* the exponent n */
            } else {
                int ql = 0;
                /* QL fields: forces, stiffnesses, moments, loads */
                if ((m == 0 && (i == 0 || i == 3 || i == 4)) || (m == 1 && (i == 0 || i == 5 || i == 6)) ||
                    (m == 2 && (i == 0 || i == 1 || i == 5 || i == 6)) ||
                    (m == 3 && (i == 2 || i == 3 || i == 14 || i == 15 || i == 18 || i == 19 || i == 20))) {
                    ql = 1;
                }
#if GRIP_ARITH_FIXED
                got = (double)r / (ql ? 256.0 : 65536.0);
#else
                (void)ql;
                got = (double)r;
#endif
            }
#if GRIP_ARITH_FIXED
            assert_true(got == vals[i]);
#else
            assert_true(got == (double)(float)vals[i]);
#endif
        }
        printf("# %s: %d fields read equal the golden P row\n", MODELS[m], nvals);
    }
}

/* The reader's defaults are the Python defaults. */
static void test_defaults(void **s)
{
    int m;
    (void)s;
    for (m = 0; m < 4; ++m) {
        grip_brush_tool a;
        grip_brush_tool b;
        char path[600];
        char file[64];
        char text[64];
        char err[512];
        snprintf(file, sizeof file, "brush_params_%s_default.txt", MODELS[m]);
        golden_path(path, sizeof path, file);
        if (grip_brush_params_read(path, NULL, &a, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        snprintf(text, sizeof text, "model = %s\n", MODELS[m]);
        if (grip_brush_params_parse(text, "min.txt", NULL, &b, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        assert_int_equal(a.kind, b.kind);
        assert_memory_equal(struct_of(&a), struct_of(&b), struct_size(a.kind));
    }
}

static void expect_error(const char *text, const char *expect_model, const char *what)
{
    grip_brush_tool t;
    char err[512];
    err[0] = '\0';
    assert_int_equal(grip_brush_params_parse(text, "t.txt", expect_model, &t, err, sizeof err), -1);
    assert_int_equal(t.kind, GRIP_BRUSH_KIND_NONE);
    if (strstr(err, what) == NULL) {
        fail_msg("message '%s' lacks '%s'", err, what);
    }
}

static void test_errors(void **s)
{
    (void)s;
    expect_error("ky = 1\n", NULL, "t.txt:1: the first entry must be 'model = ...'");
    expect_error("# only a comment\n", NULL, "t.txt:0: no 'model = ...' entry");
    expect_error("model = fiala\nky = abc\n", NULL, "t.txt:2: ky: 'abc' is not a finite number");
    expect_error("model = fiala\nky = 1e999\n", NULL, "t.txt:2: ky:");
    expect_error("model = fiala\nzz = 1\n", NULL, "t.txt:2: zz: unknown key for model fiala");
    expect_error("model = fiala\nky = 1\nky = 2\n", NULL, "t.txt:3: ky: given twice");
    expect_error("model = wheel\n", NULL, "t.txt:1: model: 'wheel' is not one of");
    expect_error("model = fiala\nmodel = sakai\n", NULL, "t.txt:2: model: given twice");
    expect_error("model = sakai\n", "fiala", "t.txt:1: model: the file describes 'sakai', not 'fiala'");
    expect_error("model = fiala\nky\n", NULL, "t.txt:2: expected 'key = value'");
    expect_error("model = brush\nn = 4.5\n", NULL, "t.txt:2: n:");
    /* the library's check names the field (grip_*_check_params_detail), the
     * reader its line (0 with "(its default)" when the file does not give it) */
    expect_error("model = brush\nn = 9\n", NULL, "t.txt:2: n: the library rejects the parameter set: n must be in "
                 "GRIP_BRUSH_N_MIN..GRIP_BRUSH_N_MAX (status -2");
    expect_error("model = neofiala\nmu_s = 0.5\nmu_d0 = 0.9\n", NULL, "t.txt:2: mu_s: the library rejects the "
                 "parameter set: mu_s must be in [mu_d0, 3]");
    expect_error("model = neofiala\nl = 0\n", NULL, "t.txt:2: l: the library rejects the parameter set: l must be in (0, 2] m");
    expect_error("model = neofiala\nw = -0.1\n", NULL, "t.txt:2: w: the library rejects");
    expect_error("model = fiala\nfz_min = 20000\n", NULL, "t.txt:0: fz_max: the library rejects the parameter set: "
                 "fz_max must be in [fz_min, 1e5] N (its default)");
    expect_error("model = sakai\ng_y = 100\n", NULL, "t.txt:2: g_y: the library rejects the parameter set: g_y must be "
                 "mu_s fz_max / (l g_y) <= 4");
#if GRIP_ARITH_FIXED
    expect_error("model = neofiala\nky = 1e12\n", NULL, "t.txt:2: ky: 1e+12 is not representable in the fixed build");
#else
    expect_error("model = neofiala\nky = 1e12\n", NULL, "t.txt:2: ky: the library rejects the parameter set: ky must be "
                 "max(kx, ky) / (mu_s fz_min) <= 1000");
    expect_error("model = neofiala\nky = 1e39\n", NULL, "t.txt:2: ky: 1e+39 is not representable in the float build");
#endif
    {
        grip_brush_tool t;
        char err[256];
        assert_int_equal(grip_brush_params_read("/nonexistent/x.txt", NULL, &t, err, sizeof err), -1);
        assert_non_null(strstr(err, "/nonexistent/x.txt:0: cannot open"));
    }
    assert_int_equal(grip_brush_kind_of("neofiala"), GRIP_BRUSH_KIND_NEOFIALA);
    assert_int_equal(grip_brush_kind_of("mf"), GRIP_BRUSH_KIND_NONE);
}

/* Comments, blanks, CRLF and per-kN units: c_q = 1e-5 1/N is 0.01 1/kN. */
static void test_units_and_syntax(void **s)
{
    grip_brush_tool t;
    char err[256];
    (void)s;
    if (grip_brush_params_parse("# head\r\n\r\nmodel = neofiala   # trailing\r\n  c_q = 1e-5 \r\n eps=2e-5\r\n",
                                "t.txt", "neofiala", &t, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
#if GRIP_ARITH_FIXED
    assert_int_equal(t.neofiala.c_q, (grip_real_t)655);     /* round(0.01 * 65536) */
    assert_int_equal(t.neofiala.eps, (grip_real_t)1311);
#else
    assert_true(t.neofiala.c_q == 0.01f);
    assert_true(t.neofiala.eps == 0.02f);
#endif
}

/* dump -> parse gives the same struct; the hook equals the direct call. */
static void test_dump_and_hook(void **s)
{
    int m;
    (void)s;
    for (m = 0; m < 4; ++m) {
        grip_brush_tool a;
        grip_brush_tool b;
        char path[600];
        char file[64];
        char err[512];
        char *buf = NULL;
        size_t len = 0;
        FILE *f;
        grip_real_t fx;
        grip_real_t fy;
        grip_real_t mz;
        grip_brush_out o;
        grip_status_t st;
        grip_status_t st2;
        snprintf(file, sizeof file, "brush_params_%s.txt", MODELS[m]);
        golden_path(path, sizeof path, file);
        if (grip_brush_params_read(path, NULL, &a, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        f = open_memstream(&buf, &len);
        assert_non_null(f);
        grip_brush_params_dump(&a, f);
        fclose(f);
        if (grip_brush_params_parse(buf, "dump", NULL, &b, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        free(buf);
        assert_memory_equal(struct_of(&a), struct_of(&b), struct_size(a.kind));
#if GRIP_ARITH_FIXED
#define KAP ((grip_real_t)(-3277))
#define ALP ((grip_real_t)(3277))
#define GAM ((grip_real_t)(655))
#define FZ ((grip_real_t)(4000 * 256))
#define VX ((grip_real_t)(20 * 65536))
#else
#define KAP (-0.05f)
#define ALP (0.05f)
#define GAM (0.01f)
#define FZ (4000.0f)
#define VX (20.0f)
#endif
        st = grip_brush_tool_eval(&a, KAP, ALP, GAM, FZ, VX, &fx, &fy, &mz);
        switch (a.kind) {
        case GRIP_BRUSH_KIND_FIALA: st2 = grip_fiala_eval(&a.fiala, ALP, FZ, &o); break;
        case GRIP_BRUSH_KIND_BRUSH: st2 = grip_brush_eval(&a.brush, KAP, FZ, VX, &o); break;
        case GRIP_BRUSH_KIND_SAKAI: st2 = grip_sakai_eval(&a.sakai, KAP, ALP, FZ, &o); break;
        default: st2 = grip_neofiala_eval(&a.neofiala, KAP, ALP, GAM, FZ, VX, &o); break;
        }
        assert_int_equal(st, st2);
        assert_true(fx == o.fx && fy == o.fy && mz == o.mz);
    }
    {
        grip_brush_tool none;
        grip_real_t fx = 1;
        grip_real_t fy = 1;
        grip_real_t mz = 1;
        memset(&none, 0, sizeof none);
        assert_int_equal(grip_brush_tool_eval(&none, 0, 0, 0, FZ, 0, &fx, &fy, &mz), GRIP_ERR_STATE);
        assert_true(fx == 0 && fy == 0 && mz == 0);
        assert_int_equal(grip_brush_tool_eval(NULL, 0, 0, 0, FZ, 0, &fx, &fy, &mz), GRIP_ERR_NULL);
        assert_int_equal(grip_brush_tool_eval(&none, 0, 0, 0, FZ, 0, NULL, &fy, &mz), GRIP_ERR_NULL);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values_match_golden),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_units_and_syntax),
        cmocka_unit_test(test_dump_and_hook),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
