/*
 * test_tir_reader.c - the host .tir reader (port/linux/tir_reader.c):
 * every shared .tir file parses; spot values and unit conversion; each
 * class of error on a small fixture in tests/data/tir/, with a message that
 * names the file, the line and the key; and, where the Python emitter wrote
 * parameter sets (build/golden/mf_params.c), the C reader's struct equals
 * the emitted one field by field, exactly (both builds: each side rounds the
 * same double once).
 *
 * Shared data: $GRIP_SHARED_DATA, else ../shared/data (relative to the
 * repository root, where the tests run).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "grip/grip_mf.h"
#include "tir_reader.h"
#include "mf_params.h"

#define FIX "tests/data/tir/"

static const char *shared_dir(void)
{
    const char *d = getenv("GRIP_SHARED_DATA");
    return (d != NULL && d[0] != '\0') ? d : "tests/data";
}

static const char *const SHARED_TIR[] = {
    "chrono-tir/335_65R22_5_G275MSA_40psi.tir",
    "chrono-tir/335_65R22_5_G275MSA_60psi.tir",
    "chrono-tir/335_65R22_5_G275MSA_70psi.tir",
    "chrono-tir/335_65R22_5_G275MSA_95psi.tir",
    "chrono-tir/mf_185_80R14.tir",
    "mfeval-tir/FSAE_Defaults.tir",
    "mfeval-tir/MagicFormula52_Paramerters.tir",
    "mfeval-tir/MagicFormula61_Paramerters.tir",
    "mfeval-tir/MagicFormula62_Paramerters.tir",
    "mfeval-tir/PacejkaBook_Defaults.tir",
};
#define N_SHARED (sizeof SHARED_TIR / sizeof SHARED_TIR[0])

/* Tolerance of a read value against the exact SI value: the storage
 * rounding of the build (half an LSB in fixed, half an ulp in float). */
static double storage_tol(double want, int ql)
{
#if GRIP_ARITH_FIXED
    (void)want;
    return ql ? 0.5 / 256.0 : 0.5 / 65536.0;
#else
    (void)ql;
    return fabs(want) * 0x1p-24 + 1e-45;
#endif
}

static double get(const grip_mf_params *p, const char *key)
{
    int i = grip_tir_coef_index(key);
    if (i < 0) {
        fail_msg("no coefficient %s", key);
    }
    return grip_tir_coef_get(p, i);
}

static void check_value(const grip_mf_params *p, const char *key, double want)
{
    int i = grip_tir_coef_index(key);
    double got = get(p, key);
    double tol = storage_tol(want, grip_tir_coef_is_ql(i));
    if (!(fabs(got - want) <= tol)) {
        fail_msg("%s = %.9g, want %.9g (tol %.3g)", key, got, want, tol);
    }
}

/* Line number (1-based) of the first line of `path` containing `text`. */
static unsigned long line_of(const char *path, const char *text)
{
    char buf[1024];
    unsigned long n = 0;
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fail_msg("cannot open fixture %s", path);
    }
    while (fgets(buf, sizeof buf, f) != NULL) {
        n++;
        if (strstr(buf, text) != NULL) {
            fclose(f);
            return n;
        }
    }
    fclose(f);
    fail_msg("fixture %s has no line with '%s'", path, text);
    return 0;
}

static unsigned long line_count(const char *path)
{
    int c;
    unsigned long n = 0;
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fail_msg("cannot open fixture %s", path);
    }
    while ((c = fgetc(f)) != EOF) {
        if (c == '\n') {
            n++;
        }
    }
    fclose(f);
    return n;
}

/* ---- every shared file parses -------------------------------------- */

static void test_shared_files_parse(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_SHARED; i++) {
        char path[1024];
        char err[512];
        grip_mf_params p;
        snprintf(path, sizeof path, "%s/%s", shared_dir(), SHARED_TIR[i]);
        memset(&p, 0, sizeof p);
        if (grip_tir_read(path, &p, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        assert_true(get(&p, "FNOMIN") > 0.0);
        assert_true(get(&p, "UNLOADED_RADIUS") > 0.0);
        print_message("# %s: FITTYP %d, side %+d, FNOMIN %.6g N, R0 %.6g m\n", SHARED_TIR[i],
                      (int)p.fittyp, (int)p.tyreside, get(&p, "FNOMIN"), get(&p, "UNLOADED_RADIUS"));
    }
}

/* Values read from the files by eye, with their storage rounding. */
static void test_shared_spot_values(void **state)
{
    char path[1024];
    char err[512];
    grip_mf_params p;
    (void)state;

    snprintf(path, sizeof path, "%s/mfeval-tir/MagicFormula61_Paramerters.tir", shared_dir());
    assert_int_equal(grip_tir_read(path, &p, err, sizeof err), 0);
    assert_int_equal(p.fittyp, 61);
    assert_int_equal(p.tyreside, -1);          /* TYRESIDE = 'RIGHT' */
    check_value(&p, "FNOMIN", 6752.0);
    check_value(&p, "UNLOADED_RADIUS", 0.393581);
    check_value(&p, "NOMPRES", 260000.0);
    check_value(&p, "LONGITUDINAL_STIFFNESS", 407611.8);
    check_value(&p, "PCY1", 1.51362);

    snprintf(path, sizeof path, "%s/chrono-tir/335_65R22_5_G275MSA_60psi.tir", shared_dir());
    assert_int_equal(grip_tir_read(path, &p, err, sizeof err), 0);
    assert_int_equal(p.fittyp, 5);
    assert_int_equal(p.tyreside, 1);           /* 'UNKNOWN' = left */
    check_value(&p, "FNOMIN", 21674.0);
    check_value(&p, "VERTICAL_STIFFNESS", 5.6519e5);
    check_value(&p, "LONGVL", 16.5);
    check_value(&p, "PKX2", 2.0158e-05);
    /* absent keys take the list's defaults */
    check_value(&p, "LMUV", 0.0);
    check_value(&p, "NOMPRES", 0.0);
}

/* ---- fixtures: valid files --------------------------------------------- */

static void test_minimal_and_side_option(void **state)
{
    char err[512];
    grip_mf_params p;
    grip_tir_options o;
    (void)state;
    grip_tir_options_init(&o);
    assert_int_equal(grip_tir_read(FIX "minimal.tir", &p, err, sizeof err), 0);
    assert_int_equal(p.fittyp, 61);
    assert_int_equal(p.tyreside, -1);
    check_value(&p, "FNOMIN", 4000.0);
    check_value(&p, "PKY1", -15.324);
    check_value(&p, "PKY4", 2.0);     /* default of the list */
    check_value(&p, "LFZO", 1.0);     /* scaling factors default to 1 */
    check_value(&p, "LONGVL", 16.7);
    /* absent coefficients take MFeval's readTIR defaults, not 0: PKY2 = 0
     * would take the cornering stiffness to 0, RBX1 = RCX1 = 0 would
     * remove the combined-slip weighting */
    check_value(&p, "PKY2", 1.0);
    check_value(&p, "PKY6", -1.0);
    check_value(&p, "PDX2", -0.15);
    check_value(&p, "PDY2", -0.15);
    check_value(&p, "RBX1", 20.0);
    check_value(&p, "RBX2", 15.0);
    check_value(&p, "RCX1", 1.0);
    check_value(&p, "RBY1", 10.0);
    check_value(&p, "RCY1", 1.0);
    check_value(&p, "RVY4", 20.0);
    check_value(&p, "QBZ9", 10.0);
    check_value(&p, "QDZ8", -0.05);
    check_value(&p, "FZMAX", 0.0);    /* limits stay "not given" */
    check_value(&p, "PHYP1", 0.0);    /* turn slip stays "not given" */
    /* FITTYP from PROPERTY_FILE_FORMAT when absent */
    assert_int_equal(grip_tir_read(FIX "fittyp_from_format.tir", &p, err, sizeof err), 0);
    assert_int_equal(p.fittyp, 62);
    /* tyreside stays the file's; the mounting side is the option bit, as
     * fitted by default (minimal.tir says RIGHT) */
    assert_int_equal(grip_tir_read(FIX "minimal.tir", &p, err, sizeof err), 0);
    assert_int_equal(p.options, GRIP_MF_OPT_RIGHT_SIDE);
    o.side = GRIP_TIR_SIDE_LEFT;
    assert_int_equal(grip_tir_read_opts(FIX "minimal.tir", &o, &p, err, sizeof err), 0);
    assert_int_equal(p.tyreside, -1);
    assert_int_equal(p.options, 0u);
    o.side = GRIP_TIR_SIDE_RIGHT;
    assert_int_equal(grip_tir_read_opts(FIX "units.tir", &o, &p, err, sizeof err), 0);
    assert_int_equal(p.options, GRIP_MF_OPT_RIGHT_SIDE);
}

static void test_unit_conversion(void **state)
{
    char err[512];
    grip_mf_params p;
    (void)state;
    if (grip_tir_read(FIX "units.tir", &p, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(p.fittyp, 5);
    check_value(&p, "UNLOADED_RADIUS", 0.3135);
    check_value(&p, "WIDTH", 0.205);
    check_value(&p, "FNOMIN", 4000.0);
    check_value(&p, "FZMIN", 100.0);
    check_value(&p, "FZMAX", 10000.0);
    check_value(&p, "VERTICAL_STIFFNESS", 200000.0);
    check_value(&p, "INFLPRES", 220000.0);
    check_value(&p, "LONGVL", 16.7);
    check_value(&p, "VXLOW", 1.0);
    check_value(&p, "ALPMIN", -30.0 * 3.14159265358979323846 / 180.0);
    check_value(&p, "CAMMAX", 6.0 * 3.14159265358979323846 / 180.0);
    check_value(&p, "PHX1", 0.001);   /* dimensionless: not scaled */
    check_value(&p, "PCX1", 1.65);
}

static void test_crlf_and_pressure_unit(void **state)
{
    char err[512];
    grip_mf_params p;
    grip_mf_params q;
    (void)state;
    if (grip_tir_read(FIX "crlf_bar.tir", &p, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    check_value(&p, "INFLPRES", 220000.0);   /* 2.2 bar */
    check_value(&p, "NOMPRES", 220000.0);
    assert_int_equal(grip_tir_read(FIX "minimal.tir", &q, err, sizeof err), 0);
    /* otherwise the same file as minimal.tir */
    assert_memory_equal(&p, &q, sizeof p);
}

/* ---- fixtures: each error class ------------------------------------------ */

typedef struct {
    const char *file;
    const char *key;       /* the key the message must name */
    const char *at;        /* text of the offending line; NULL: last line */
    const char *what;      /* a word the message must contain */
} bad_case;

static const bad_case BAD[] = {
    { "typo_key.tir", "RBX1X", "RBX1X = 12.0", "a misspelling of RBX1? The file does not give RBX1, which would take its default 20" },
    { "missing_fnomin.tir", "FNOMIN", "[VERTICAL]", "missing required key" },
    { "missing_fittyp.tir", "FITTYP", "[MODEL]", "missing required key" },
    { "missing_section.tir", "QBZ1", NULL, "missing required key in [ALIGNING_COEFFICIENTS]" },
    { "bad_fittyp.tir", "FITTYP", "FITTYP = 7", "unsupported" },
    { "nonnumeric.tir", "PCY1", "PCY1 = 1.3x", "not a number" },
    { "quoted_number.tir", "PDY1", "PDY1 = '1.0'", "not a number" },
    { "bad_unit.tir", "LENGTH", "furlong", "cannot be converted" },
    { "fnomin_zero.tir", "FNOMIN", "FNOMIN = 0", "> 0" },
    { "radius_negative.tir", "UNLOADED_RADIUS", "UNLOADED_RADIUS = -", "> 0" },
    { "range_inverted.tir", "FZMAX", "FZMAX = 100", "greater" },
    { "fixed_range.tir", "LATERAL_STIFFNESS", "LATERAL_STIFFNESS = ", "does not fit the fixed-point format QL" },
    { "float_range.tir", "PKY1", "PKY1 = -1.0e39", "does not fit the fixed-point format QS" },
    { "unterminated.tir", "TYRESIDE", "TYRESIDE = 'RIGHT", "unterminated" },
    { "duplicate.tir", "QCZ1", "QCZ1 = 1.2", "duplicate" },
    { "garbage_line.tir", "-", "PKX1 21.687", "expected KEY = value" },
    { "trailing_text.tir", "PDX1", "PDX1 = 1.0 2.0", "after the value" },
    /* the validation layer: plausibility, FITTYP, USE_MODE, empty values, bounds */
    { "range_pdy1.tir", "PDY1", "PDY1 = 30000", "outside the plausible range |v| in [0.05, 10]" },
    { "range_pcy1_zero.tir", "PCY1", "PCY1 = 0", "outside the plausible range [0.1, 5]" },
    { "range_radius_mm.tir", "UNLOADED_RADIUS", "UNLOADED_RADIUS = 313.5", "--no-range-check" },
    { "range_fnomin_kn.tir", "FNOMIN", "FNOMIN = 4", "[20, 1e+06]" },
    { "range_alpmax_deg.tir", "ALPMIN", "ALPMIN = -30", "slip angle range [rad]" },
    { "fittyp_51.tir", "FITTYP", "FITTYP = 51", "unsupported Magic Formula version 51" },
    { "use_mode_turnslip.tir", "USE_MODE", "USE_MODE = 125", "turn slip per call" },
    { "use_mode_negative.tir", "USE_MODE", "USE_MODE = -14", "mirrors the tyre" },
    { "use_mode_fy_only.tir", "USE_MODE", "USE_MODE = 12", "Fy, Mx and Mz only" },
    { "use_mode_uncombined.tir", "USE_MODE", "USE_MODE = 13", "uncombined forces" },
    { "use_mode_digit.tir", "USE_MODE", "USE_MODE = 148", "tens digit 4" },
    { "use_mode_text.tir", "USE_MODE", "USE_MODE = 'combined'", "not an integer" },
    { "empty_required.tir", "FNOMIN", "FNOMIN =", "empty value for a required key" },
    { "long_line.tir", "-", "$ xxxx", "line longer than 4096 bytes" },
    { "nul_byte.tir", "-", "PKX1 = 21", "NUL byte at byte offset" },
};

static void test_error_classes(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < sizeof BAD / sizeof BAD[0]; i++) {
        const bad_case *c = &BAD[i];
        char path[256];
        char err[512];
        char want[512];
        grip_mf_params p;
        grip_mf_params before;
        unsigned long line;
        int rc;
        snprintf(path, sizeof path, FIX "%s", c->file);
        memset(&p, 0xA5, sizeof p);
        before = p;
        err[0] = '\0';
        rc = grip_tir_read(path, &p, err, sizeof err);
        if (rc != -1) {
            fail_msg("%s: accepted, expected an error naming %s", c->file, c->key);
        }
        print_message("# %s -> %s\n", c->file, err);
        /* untouched output */
        assert_memory_equal(&p, &before, sizeof p);
        line = (c->at != NULL) ? line_of(path, c->at) : line_count(path);
        snprintf(want, sizeof want, "%s:%lu: %s: ", path, line, c->key);
        if (strncmp(err, want, strlen(want)) != 0) {
            fail_msg("%s: message '%s' does not start with '%s'", c->file, err, want);
        }
        if (strstr(err, c->what) == NULL) {
            fail_msg("%s: message '%s' does not say '%s'", c->file, err, c->what);
        }
    }
}

static void test_unreadable_file(void **state)
{
    char err[512];
    grip_mf_params p;
    grip_mf_params before;
    (void)state;
    memset(&p, 0x5A, sizeof p);
    before = p;
    assert_int_equal(grip_tir_read(FIX "does_not_exist.tir", &p, err, sizeof err), -1);
    print_message("# %s\n", err);
    assert_non_null(strstr(err, FIX "does_not_exist.tir:0: "));
    assert_non_null(strstr(err, "cannot open"));
    assert_memory_equal(&p, &before, sizeof p);
    /* a directory opens but cannot be read */
    assert_int_equal(grip_tir_read(FIX, &p, err, sizeof err), -1);
    print_message("# %s\n", err);
    assert_memory_equal(&p, &before, sizeof p);
    /* no error buffer: still fails cleanly */
    assert_int_equal(grip_tir_read(FIX "does_not_exist.tir", &p, NULL, 0), -1);
    assert_int_equal(grip_tir_read(NULL, &p, err, sizeof err), -1);
    assert_int_equal(grip_tir_read(FIX "minimal.tir", NULL, err, sizeof err), -1);
}

/* ---- warnings, strict mode, overrides, bounds --------------------------- */

typedef struct {
    int n;
    char last[512];
} warn_log;

static void collect(void *ctx, const char *message)
{
    warn_log *w = ctx;
    w->n++;
    snprintf(w->last, sizeof w->last, "%s", message);
}

static void test_warnings_and_strict(void **state)
{
    static const struct {
        const char *file;
        int n;
        const char *last;   /* words of the last warning */
    } W[] = {
        { "warn_unknown_key.tir", 2, "PKX9: unknown key in [LONGITUDINAL_COEFFICIENTS]: ignored (did you mean PKX1?)" },
        { "warn_misplaced.tir", 3, "LENGTH: grip reads LENGTH from [UNITS], not from the unknown section [HEADER]" },
        { "warn_empty.tir", 4, "ASPECT_RATIO: empty value: the default 0.6 is used" },
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof W / sizeof W[0]; i++) {
        char path[256];
        char err[512];
        grip_tir_options o;
        grip_tir_values v;
        grip_mf_params p;
        grip_mf_params ref;
        warn_log log;
        memset(&log, 0, sizeof log);
        snprintf(path, sizeof path, FIX "%s", W[i].file);
        grip_tir_options_init(&o);
        o.warn = collect;
        o.warn_ctx = &log;
        if (grip_tir_parse(path, &o, &v, err, sizeof err) != 0) {
            fail_msg("%s: %s", W[i].file, err);
        }
        print_message("# %s: %d warnings, last: %s\n", W[i].file, log.n, log.last);
        assert_int_equal(log.n, W[i].n);
        assert_int_equal((int)v.nwarnings, W[i].n);
        assert_non_null(strstr(log.last, W[i].last));
        assert_non_null(strstr(log.last, path));
        /* the values are those of minimal.tir: what is warned about is ignored */
        assert_int_equal(grip_tir_read_opts(path, &o, &p, err, sizeof err), 0);
        assert_int_equal(grip_tir_read(FIX "minimal.tir", &ref, err, sizeof err), 0);
        assert_memory_equal(&p, &ref, sizeof p);
        /* strict: the first warning is the error, the output untouched */
        o.flags = GRIP_TIR_STRICT;
        memset(&p, 0x3C, sizeof p);
        ref = p;
        assert_int_equal(grip_tir_read_opts(path, &o, &p, err, sizeof err), -1);
        print_message("# strict: %s\n", err);
        assert_non_null(strstr(err, "(refused: strict mode)"));
        assert_memory_equal(&p, &ref, sizeof p);
    }
}

static void test_overrides_and_use_mode(void **state)
{
    char err[512];
    grip_tir_options o;
    grip_tir_values v;
    (void)state;
    grip_tir_options_init(&o);
    assert_int_equal(o.side, GRIP_TIR_SIDE_FILE);
    assert_int_equal(o.flags, 0u);
    /* --no-range-check: read as given */
    assert_int_equal(grip_tir_parse(FIX "range_pdy1.tir", &o, &v, err, sizeof err), -1);
    o.flags = GRIP_TIR_NO_RANGE_CHECK;
    assert_int_equal(grip_tir_parse(FIX "range_pdy1.tir", &o, &v, err, sizeof err), 0);
    assert_true(v.v[grip_tir_coef_index("PDY1")] == 30000.0);
    /* the hard checks stay */
    assert_int_equal(grip_tir_parse(FIX "fnomin_zero.tir", &o, &v, err, sizeof err), -1);
    /* USE_MODE 13 for a pure-slip caller */
    o.flags = 0u;
    assert_int_equal(grip_tir_parse(FIX "use_mode_uncombined.tir", &o, &v, err, sizeof err), -1);
    o.flags = GRIP_TIR_PURE_SLIP;
    assert_int_equal(grip_tir_parse(FIX "use_mode_uncombined.tir", &o, &v, err, sizeof err), 0);
    assert_int_equal(v.use_mode, 13);
    assert_true(v.use_mode_line > 0);
    o.flags = 0u;
    assert_int_equal(grip_tir_parse(FIX "use_mode_ok.tir", &o, &v, err, sizeof err), 0);
    assert_int_equal(v.use_mode, 124);
    assert_int_equal(grip_tir_parse(FIX "minimal.tir", &o, &v, err, sizeof err), 0);
    assert_int_equal(v.use_mode, -1);
    assert_int_equal((int)v.use_mode_line, 0);
    assert_int_equal(v.fittyp_file, 61);
    /* FITTYP 52: MF 5.2, evaluated as 21 */
    assert_int_equal(grip_tir_parse(FIX "fittyp_52.tir", &o, &v, err, sizeof err), 0);
    assert_int_equal(v.fittyp, 21);
    assert_int_equal(v.fittyp_file, 52);
    /* unknown flag bits */
    o.flags = 0x80u;
    assert_int_equal(grip_tir_parse(FIX "minimal.tir", &o, &v, err, sizeof err), -1);
    assert_non_null(strstr(err, "unknown option flags"));
}

static void test_shared_files_strict(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < N_SHARED; i++) {
        char path[1024];
        char err[512];
        grip_tir_options o;
        grip_mf_params p;
        grip_mf_params q;
        snprintf(path, sizeof path, "%s/%s", shared_dir(), SHARED_TIR[i]);
        grip_tir_options_init(&o);
        o.flags = GRIP_TIR_STRICT;
        if (grip_tir_read_opts(path, &o, &p, err, sizeof err) != 0) {
            fail_msg("strict: %s", err);
        }
        /* the checks do not change a value */
        o.flags = GRIP_TIR_NO_RANGE_CHECK;
        assert_int_equal(grip_tir_read_opts(path, &o, &q, err, sizeof err), 0);
        assert_memory_equal(&p, &q, sizeof p);
    }
}

/* /dev/zero, a 1 GiB sparse file, a file over 4 MiB: each ends with an
 * error after a bounded read (the memory limit itself: tests/badinput). */
static void test_bounded_reads(void **state)
{
    char err[512];
    grip_mf_params p;
    char path[] = "/tmp/grip_tir_testXXXXXX";
    int fd;
    FILE *f;
    long k;
    (void)state;
    assert_int_equal(grip_tir_read("/dev/zero", &p, err, sizeof err), -1);
    print_message("# %s\n", err);
    assert_non_null(strstr(err, "/dev/zero:1: -: NUL byte at byte offset 0"));
    fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, 1L << 30), 0);
    close(fd);
    assert_int_equal(grip_tir_read(path, &p, err, sizeof err), -1);
    print_message("# %s\n", err);
    assert_non_null(strstr(err, ":0: -: larger than 4194304 bytes: not a .tir file"));
    f = fopen(path, "wb");
    assert_non_null(f);
    fputs("[MODEL]\n", f);
    for (k = 0; k < 5000; k++) {
        fprintf(f, "K%ld = 1\n", k);
    }
    fclose(f);
    assert_int_equal(grip_tir_read(path, &p, err, sizeof err), -1);
    print_message("# %s\n", err);
    assert_non_null(strstr(err, ":4098: -: more than 4096 keys"));
    remove(path);
}

/* ---- the C reader agrees with the Python emitter ---------------------------- */

static void test_matches_emitted_params(void **state)
{
    int t;
    (void)state;
    if (grip_test_tire_count == 0) {
        print_message("# no emitted parameter sets in build/golden/mf_params.c: nothing to compare\n");
        skip();
    }
    for (t = 0; t < grip_test_tire_count; t++) {
        const grip_test_tire *tt = &grip_test_tires[t];
        grip_mf_params p;
        char err[512];
        int i;
        int differ = 0;
        double worst = 0.0;
        const char *worst_key = "-";
        grip_tir_options left;
        grip_tir_options_init(&left);
        left.side = GRIP_TIR_SIDE_LEFT;   /* the golden parameter sets mount every tyre left */
        if (grip_tir_read_opts(tt->tir_path, &left, &p, err, sizeof err) != 0) {
            fail_msg("%s: %s", tt->name, err);
        }
        assert_int_equal(p.fittyp, tt->params->fittyp);
        assert_int_equal(p.tyreside, tt->params->tyreside);
        assert_int_equal(p.options, tt->params->options);
        for (i = 0; i < grip_tir_coef_count(); i++) {
            double a = grip_tir_coef_get(&p, i);
            double b = grip_tir_coef_get(tt->params, i);
            /* both sides round the same double once: (float)v or
             * round(v * 2^n); the emitter's decimal is repr(), which
             * reads back as the same double, so they must be identical */
            int same = (a == b);
            if (fabs(a - b) > worst) {
                worst = fabs(a - b);
                worst_key = grip_tir_coef_key(i);
            }
            if (!same) {
                print_message("#   %s %s: C reader %.9g, emitted %.9g\n", tt->name, grip_tir_coef_key(i), a, b);
                differ++;
            }
        }
        print_message("# %s: %d coefficients, %d differ, max |diff| %.3g (%s)\n", tt->name,
                      grip_tir_coef_count(), differ, worst, worst_key);
        assert_int_equal(differ, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shared_files_parse),
        cmocka_unit_test(test_shared_spot_values),
        cmocka_unit_test(test_minimal_and_side_option),
        cmocka_unit_test(test_unit_conversion),
        cmocka_unit_test(test_crlf_and_pressure_unit),
        cmocka_unit_test(test_error_classes),
        cmocka_unit_test(test_unreadable_file),
        cmocka_unit_test(test_warnings_and_strict),
        cmocka_unit_test(test_overrides_and_use_mode),
        cmocka_unit_test(test_shared_files_strict),
        cmocka_unit_test(test_bounded_reads),
        cmocka_unit_test(test_matches_emitted_params),
    };
    return cmocka_run_group_tests_name("tir_reader_" GRIP_ARITH_NAME, tests, NULL, NULL);
}
