"""cffi build script of the grip binding (API mode): one extension per
arithmetic, grip._grip_f32 (float) and grip._grip_q16 (fixed, Q15.16/Q23.8).

Run by setuptools (tools/setup.py, `cffi_modules`) when the tools are
installed (`pip install ./tools`, or editable by `make setup`); it needs the
C sources of the clone this file sits in: lib/, include/ and port/linux/
beside tools/.

What goes into each extension:
  * every lib/*/*.c, compiled as the Makefile compiles the library
    (LIB_CFLAGS below: -std=c99 -O2, the build's defines, -Iinclude
    -Ilib/arith, -fPIC as for `make shlib`; the Makefile's warning flags
    without -Werror) by the same compiler that builds the extension
    (setuptools' choice: $CC or Python's); tools/setup.py compiles these
    objects itself, so Python's own CFLAGS (-O3, -fwrapv, -DNDEBUG) never
    reach the library code;
  * port/linux/tir_reader.c and brush_params.c, the readers of `grip-tire`
    (host code, CFLAGS_HOST), used only when grip_tools cannot read a file;
  * port/linux/replay_core.c with csv.c, candump.c and vehicle_config.c:
    grip-replay's replay of a log (grip._replay, the fleet's in-process
    backend);
  * the wrapper below (C_SOURCE): loops over N points / samples that call
    the library once per point (the Magic Formula: once per block of points,
    grip_mf_eval_batch), and the conversions SI <-> the build's
    number format (grip_convert.h for inputs, GRIP_QS()/GRIP_QL() for
    parameters).

The cdef of the public structs is generated from the headers themselves
(parse_structs), and so is the fixed-point format of every grip_real_t field
(the `/* QS` or `/* QL` comment that starts its description); the
extension carries that table (grip_py_meta) so that Python converts each
field as the header says. cffi checks every declared offset against the
compiler's.
"""
import glob
import json
import os
import re

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
INCLUDE = os.path.join(REPO, "include")
GRIP_INC = os.path.join(INCLUDE, "grip")
ARITH_INC = os.path.join(REPO, "lib", "arith")
PORT = os.path.join(REPO, "port", "linux")

ARITHS = {"float": ("f32", 0), "fixed": ("q16", 1)}

# The Makefile's flags (WARN_LIB, OPT, DEFS, INC; -fPIC as its pic/ objects),
# -Werror left out: a newer compiler's new warning must not break an install.
WARN_LIB = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Wconversion", "-Wsign-conversion",
            "-Wdouble-promotion", "-Wshadow", "-Wundef", "-Wstrict-prototypes",
            "-Wmissing-prototypes", "-Wvla", "-Wcast-qual", "-Wpointer-arith"]
WARN_HOST = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Wshadow", "-Wundef", "-Wvla",
             "-D_POSIX_C_SOURCE=200809L"]
OPT = ["-O2", "-g"]


def defs(arith):
    return [f"-DGRIP_ARITH_FIXED={ARITHS[arith][1]}", "-DGRIP_DEBUG_SATURATION=0"]


def lib_cflags(arith):
    """Flags of every lib/*/*.c object (the Makefile's CFLAGS_LIB -fPIC)."""
    return WARN_LIB + OPT + defs(arith) + ["-I" + INCLUDE, "-I" + ARITH_INC, "-fPIC"]


# Flags of single lib/ sources, after lib_cflags (the Makefile's
# LANE_CFLAGS for the Magic Formula's lane evaluation).
FILE_CFLAGS = {"lib/mf/mf_lanes.c": ["-fno-math-errno", "-fno-trapping-math"]}


def file_cflags(rel):
    """The extra flags of the lib/ source rel (a path from the clone's root)."""
    return list(FILE_CFLAGS.get(rel.replace(os.sep, "/"), []))


def port_cflags(arith):
    """Flags of the host readers (the Makefile's CFLAGS_HOST, -fPIC)."""
    return WARN_HOST + OPT + defs(arith) + ["-I" + INCLUDE, "-I" + ARITH_INC, "-I" + PORT, "-fPIC"]


def lib_sources():
    """lib/*/*.c in the Makefile's order ($(sort $(wildcard lib/*/*.c)))."""
    return sorted(glob.glob(os.path.join(REPO, "lib", "*", "*.c")))


def port_sources():
    """The host code of the programs that the binding runs: the readers of
    grip-tire and the replay of grip-replay (replay_core.c with the CSV and
    candump readers and the vehicle configuration it calls)."""
    return [os.path.join(PORT, n) for n in ("tir_reader.c", "brush_params.c", "csv.c", "candump.c",
                                            "vehicle_config.c", "replay_core.c")]


def check_tree():
    missing = [p for p in (GRIP_INC, os.path.join(REPO, "lib"), PORT) if not os.path.isdir(p)]
    if missing or not lib_sources():
        raise RuntimeError(
            "the grip binding is compiled from the C sources of the clone it is installed from: "
            f"{', '.join(missing) or 'lib/*/*.c'} not found beside tools/ (install with "
            "`pip install ./tools` from the top of a clone, not from an sdist or a copy of tools/)")


# ---------------------------------------------------------------------------
# The public structs, read from the headers.

# Structs declared in full (Python reads or writes their fields) and the
# headers they come from; the state structs stay opaque.
FULL_STRUCTS = [
    ("grip_signals.h", "grip_input_sample_t"),
    ("grip_brush.h", "grip_brush_out"),
    ("grip_brush.h", "grip_fiala_params"),
    ("grip_brush.h", "grip_brush_params"),
    ("grip_brush.h", "grip_sakai_params"),
    ("grip_brush.h", "grip_neofiala_params"),
    ("grip_est.h", "grip_est_config_t"),
    ("grip_est.h", "grip_est_output_t"),
    ("grip_est.h", "grip_est_learned_t"),
    ("grip_monitor.h", "grip_monitor_config_t"),
    ("grip_monitor.h", "grip_monitor_report_t"),
    ("grip_calib.h", "grip_calib_config_t"),
]
# grip_real_t fields whose format depends on the input id (grip_input_is_ql)
PER_INPUT = {("grip_input_sample_t", "value")}
C_TYPES = {"grip_real_t", "int32_t", "uint32_t", "uint8_t", "int64_t", "grip_est_tire_t"}


def _read(name):
    with open(os.path.join(GRIP_INC, name)) as f:
        return f.read()


def int_constants():
    """Integer #defines and enum values of the headers (array dimensions)."""
    out = {}
    for path in sorted(glob.glob(os.path.join(GRIP_INC, "*.h"))):
        with open(path) as f:
            text = f.read()
        for m in re.finditer(r"^#define\s+(GRIP_\w+)\s+\(?(\d+)u?\)?\s*(?:/\*.*)?$", text, re.M):
            out[m.group(1)] = int(m.group(2))
        for m in re.finditer(r"^\s+(GRIP_\w+)\s*=\s*(-?\d+)\s*,?", text, re.M):
            out.setdefault(m.group(1), int(m.group(2)))
    return out


def parse_struct(text, name, consts):
    """[(field, ctype, dims, fmt, unit)] of `typedef struct { ... } name;`;
    fmt is "QS"/"QL" for grip_real_t fields (the comment after the field
    starts with it), "input" for the sample values, None otherwise; unit is
    the word or [bracket] that follows it ("kg", "[1/kN]")."""
    end = re.search(r"^\} " + re.escape(name) + r";", text, re.M)
    start = text.rfind("typedef struct {\n", 0, end.start()) if end is not None else -1
    if start < 0:
        raise RuntimeError(f"struct {name} not found in the headers")
    body = text[start + len("typedef struct {\n"):end.start()]
    comments = []

    def keep(mc):
        comments.append(mc.group(0))
        return f" @C{len(comments) - 1}@ "

    body = re.sub(r"/\*.*?\*/", keep, body, flags=re.S)
    fields = []
    decl = re.compile(r"(?:@C\d+@\s*)*([A-Za-z_]\w*)\s+([^;@]+?)\s*;\s*(?:@C(\d+)@)?")
    for d in decl.finditer(body):
        ctype, names, cidx = d.group(1), d.group(2), d.group(3)
        if ctype not in C_TYPES:
            raise RuntimeError(f"{name}: field type {ctype} not known to the binding's cdef")
        fmt = None
        unit = ""
        if (name, names.split("[")[0].strip()) in PER_INPUT:
            fmt = "input"
        elif ctype == "grip_real_t":
            c = comments[int(cidx)] if cidx is not None else ""
            f = re.match(r"/\*\s*(QS|QL)\b[ \t]*(\[[^\]]*\]|[^\s,]+)?", c)
            if f is None:
                raise RuntimeError(f"{name}: grip_real_t field '{names}' has no QS/QL comment")
            fmt = f.group(1)
            unit = f.group(2) or ""
        for one in names.split(","):
            nm = re.match(r"\s*(\w+)\s*((?:\[[^\]]+\])*)\s*$", one)
            if nm is None:
                raise RuntimeError(f"{name}: cannot read declaration '{one}'")
            dims = []
            for dim in re.findall(r"\[([^\]]+)\]", nm.group(2)):
                dim = dim.strip()
                dims.append(int(dim) if dim.isdigit() else consts[dim])
            fields.append((nm.group(1), ctype, dims, fmt, unit))
    return fields


def struct_table():
    consts = int_constants()
    return {name: parse_struct(_read(h), name, consts) for h, name in FULL_STRUCTS}


def cdef_structs(table):
    out = []
    for _, name in FULL_STRUCTS:
        lines = ["typedef struct {"]
        for field, ctype, dims, _fmt, _unit in table[name]:
            lines.append(f"    {ctype} {field}{''.join(f'[{d}]' for d in dims)};")
        lines.append(f"}} {name};")
        out.append("\n".join(lines))
    return "\n".join(out)


# ---------------------------------------------------------------------------
# cdef: what Python sees. GRIP_TYPED names (grip_mf_eval -> _f32/_q16) are
# written plain; the headers' macros map them when the wrapper compiles.

CDEF_HEAD = """
typedef enum { GRIP_OK, GRIP_WARN_CLAMPED, GRIP_ERR_NULL, GRIP_ERR_PARAM, GRIP_ERR_INPUT,
               GRIP_ERR_STATE, GRIP_ERR_DOMAIN, ... } grip_status_t;
typedef struct { int32_t fittyp; int32_t tyreside; uint32_t options; ...; } grip_mf_params;
typedef struct { int32_t kind; ...; } grip_est_tire_t;
typedef struct { ...; } grip_neofiala_model;
typedef struct { ...; } grip_est_t;
typedef struct { ...; } grip_monitor_t;
typedef struct { ...; } grip_calib_t;

#define GRIP_MF_OPT_BOOK ...
#define GRIP_MF_OPT_KAPPA_BRAKE ...
#define GRIP_MF_OPT_MIRROR ...
#define GRIP_MF_OPT_RIGHT_SIDE ...
#define GRIP_MF_OPT_SAE ...
#define GRIP_EST_TIRE_MF ...
#define GRIP_IN_COUNT ...
#define GRIP_CALIB_N ...
#define GRIP_CALIB_DELAY_MAX ...
#define GRIP_MON_N ...
#define GRIP_MON_GATE_CLEARS ...
#define GRIP_MON_GATE_DEFAULT ...
#define GRIP_MON_DEGR_SUSPECT ...
#define GRIP_MON_DEGR_UNVERIFIED ...
#define GRIP_SIG_OK ...
#define GRIP_SIG_UNMAPPED ...
#define GRIP_SIG_MISSING ...
#define GRIP_SIG_STALE ...
#define GRIP_SIG_RANGE ...
#define GRIP_SIG_FAULT ...
#define GRIP_BRUSH_N_MIN ...
#define GRIP_BRUSH_N_MAX ...
"""

CDEF_TAIL = """
const char *grip_status_str(grip_status_t status);
grip_status_t grip_mf_check_params(const grip_mf_params *p);
grip_status_t grip_fiala_check_params(const grip_fiala_params *p);
grip_status_t grip_brush_check_params(const grip_brush_params *p);
grip_status_t grip_sakai_check_params(const grip_sakai_params *p);
grip_status_t grip_neofiala_check_params(const grip_neofiala_params *p);
grip_status_t grip_neofiala_prepare(const grip_neofiala_params *p, grip_neofiala_model *m);
const char *grip_input_name(uint32_t input);
int grip_input_is_ql(uint32_t input);
const char *grip_input_unit(uint32_t input);
const char *grip_sig_fault_str(uint32_t fault);
grip_status_t grip_est_config_default(grip_est_config_t *cfg, const grip_mf_params *tire);
grip_status_t grip_est_init(grip_est_t *est, const grip_est_config_t *cfg);
grip_status_t grip_est_reset(grip_est_t *est);
grip_status_t grip_est_stability_factor(const grip_est_t *est, grip_real_t *a_x100);
grip_status_t grip_est_learned_get(const grip_est_t *est, grip_est_learned_t *blob);
grip_status_t grip_est_learned_set(grip_est_t *est, const grip_est_learned_t *blob);
grip_status_t grip_est_measure_friction(grip_est_t *est, grip_real_t mu_road, grip_real_t mu_road_sd);
grip_status_t grip_monitor_config_default(grip_monitor_config_t *cfg);
grip_status_t grip_monitor_config_from_est(grip_monitor_config_t *cfg, const grip_est_t *est, uint32_t driven);
grip_status_t grip_monitor_init(grip_monitor_t *mon, const grip_monitor_config_t *cfg);
grip_status_t grip_monitor_reset(grip_monitor_t *mon);
grip_status_t grip_calib_config_identity(grip_calib_config_t *cfg);
grip_status_t grip_calib_init(grip_calib_t *c, const grip_calib_config_t *cfg);
grip_status_t grip_calib_reset(grip_calib_t *c);

const char *grip_py_info(int which);

int grip_py_mf_ncoef(void);
int grip_py_mf_coef(int i, const char **field, const char **key, const char **section, int *ql,
                    double *def, int *required);
int grip_py_param(double si, int ql, grip_real_t *r);
int grip_py_mf_fill(grip_mf_params *p, int32_t fittyp, int32_t tyreside, uint32_t options,
                    const double *v, int n);
double grip_py_mf_get(const grip_mf_params *p, int i);
void grip_py_to_real(size_t n, const double *si, const uint8_t *ql, grip_real_t *out, int32_t *st);
void grip_py_est_set_tire(grip_est_config_t *cfg, int axle, const grip_mf_params *p);
const grip_mf_params *grip_py_est_tire(const grip_est_config_t *cfg, int axle);

int64_t grip_py_mf_eval(const grip_mf_params *p, int pure, int lanes, size_t n,
                        const double *kappa, size_t s_kappa, const double *alpha, size_t s_alpha,
                        const double *gamma, size_t s_gamma, const double *fz, size_t s_fz,
                        const double *pr, size_t s_pr, const double *vx, size_t s_vx,
                        grip_real_t *fx, grip_real_t *fy, grip_real_t *mz, int32_t *status);
int64_t grip_py_brush_eval(int kind, const void *params, size_t n,
                           const double *kappa, size_t s_kappa, const double *alpha, size_t s_alpha,
                           const double *gamma, size_t s_gamma, const double *fz, size_t s_fz,
                           const double *vx, size_t s_vx,
                           grip_real_t *fx, grip_real_t *fy, grip_real_t *mz, grip_real_t *rh,
                           int32_t *status);
int64_t grip_py_est_run(grip_est_t *est, size_t n, const grip_input_sample_t *in,
                        grip_est_output_t *out, int32_t *status);
int64_t grip_py_calib_run(grip_calib_t *c, size_t n, const grip_input_sample_t *in,
                          grip_input_sample_t *out, int32_t *status);
int64_t grip_py_monitor_run(grip_monitor_t *mon, size_t n, grip_input_sample_t *samples,
                            const grip_est_output_t *est_prev, grip_monitor_report_t *rep,
                            int32_t *status);
int64_t grip_py_chain_run(grip_calib_t *cal, grip_monitor_t *mon, grip_est_t *est, uint32_t honour,
                          grip_est_output_t *last, int *have_last, size_t n,
                          const grip_input_sample_t *in, grip_input_sample_t *used,
                          grip_monitor_report_t *rep, grip_est_output_t *own, grip_est_output_t *gated,
                          int32_t *st_cal, int32_t *st_mon, int32_t *st_est);

int grip_py_tir_parse(const char *path, double *v, int n, int32_t *fittyp, int32_t *tyreside, char *err,
                      size_t errlen);
int grip_py_brush_parse(const char *text, const char *name, int *kind, void *params, size_t size, char *err,
                        size_t errlen);

typedef struct {
    double *rows;
    size_t n;
    size_t ncol;
    char *text;
    size_t text_len;
    int capped;
    uint8_t write_input[64];
} grip_py_replay_out;
#define GRIP_PY_REPLAY_EST_REALS ...
int grip_py_replay_run(int argc, char **argv, size_t max_rows, grip_py_replay_out *out);
void grip_py_replay_free(grip_py_replay_out *out);
"""

C_SOURCE = r"""
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_types.h"
#include "grip/grip_version.h"
#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#include "grip/grip_brush.h"
#include "grip/grip_signals.h"
#include "grip/grip_est.h"
#include "grip/grip_monitor.h"
#include "grip/grip_calib.h"
#include "grip/grip_convert.h"
#include "tir_reader.h"
#include "brush_params.h"
#include "replay_core.h"

/* 0: "float" or "fixed", 1: the library version, 2: the struct table
 * (JSON, parsed from the headers at build time), 3: how this extension was
 * built (JSON: compiler, flags, sources). */
static const char *grip_py_info(int which)
{
    switch (which) {
    case 0: return GRIP_ARITH_NAME;
    case 1: return GRIP_VERSION_STRING;
    case 2: return GRIP_PY_META;
    case 3: return GRIP_PY_BUILD;
    default: return "";
    }
}

/* ---- Magic Formula coefficient list (grip_mf_coefs.h) ---------------- */

typedef struct {
    const char *field;
    const char *key;
    const char *section;
    int ql;
    double def;
    int required;
    size_t offset;
} grip_py_coef_t;

#define GRIP_PY_QL_QS 0
#define GRIP_PY_QL_QL 1
#define GRIP_PY_X_DESC(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) \
    { #field, #KEY, #SECTION, GRIP_PY_QL_##FORMAT, (double)(DEFAULT), REQUIRED, offsetof(grip_mf_params, field) },
static const grip_py_coef_t grip_py_coefs[] = { GRIP_MF_COEFFICIENTS(GRIP_PY_X_DESC) };
#undef GRIP_PY_X_DESC
#define GRIP_PY_NCOEF ((int)(sizeof grip_py_coefs / sizeof grip_py_coefs[0]))

static int grip_py_mf_ncoef(void)
{
    return GRIP_PY_NCOEF;
}

static int grip_py_mf_coef(int i, const char **field, const char **key, const char **section, int *ql,
                           double *def, int *required)
{
    if (i < 0 || i >= GRIP_PY_NCOEF) {
        return -1;
    }
    *field = grip_py_coefs[i].field;
    *key = grip_py_coefs[i].key;
    *section = grip_py_coefs[i].section;
    *ql = grip_py_coefs[i].ql;
    *def = grip_py_coefs[i].def;
    *required = grip_py_coefs[i].required;
    return 0;
}

/* ---- conversions ------------------------------------------------------ */

/* A parameter: SI -> grip_real_t with the expression of GRIP_QS()/GRIP_QL()
 * (grip_types.h; what `grip tir2c` emits and grip-tire's reader computes).
 * 0, or -1 when the build cannot hold the value (non-finite; fixed: the
 * result beyond +-INT32_MAX; float: beyond +-FLT_MAX). */
static int grip_py_param(double si, int ql, grip_real_t *r)
{
    if (!(si >= -DBL_MAX && si <= DBL_MAX)) {
        return -1;
    }
#if GRIP_ARITH_FIXED
    {
        double s = si * (ql ? 256.0 : 65536.0) + ((si >= 0) ? 0.5 : -0.5);
        if (!(s > -2147483648.0 && s < 2147483648.0)) {
            return -1;
        }
    }
#else
    if (fabs(si) > (double)FLT_MAX) {
        return -1;
    }
#endif
    *r = ql ? GRIP_QL(si) : GRIP_QS(si);
    return 0;
}

static double grip_py_from_real(grip_real_t r, int ql)
{
    return ql ? grip_real_ql_to_si(r) : grip_real_qs_to_si(r);
}

/* Fills a parameter set field by field (v[i]: SI value of the i-th entry of
 * GRIP_MF_COEFFICIENTS). 0, or -1 - i for the first value the build cannot
 * hold (*p is then untouched). */
static int grip_py_mf_fill(grip_mf_params *p, int32_t fittyp, int32_t tyreside, uint32_t options,
                           const double *v, int n)
{
    grip_mf_params q;
    int i;
    if (n != GRIP_PY_NCOEF) {
        return -1 - n;
    }
    memset(&q, 0, sizeof q);
    q.fittyp = fittyp;
    q.tyreside = tyreside;
    q.options = options;
    for (i = 0; i < n; i++) {
        grip_real_t r;
        if (grip_py_param(v[i], grip_py_coefs[i].ql, &r) != 0) {
            return -1 - i;
        }
        memcpy((char *)&q + grip_py_coefs[i].offset, &r, sizeof r);
    }
    *p = q;
    return 0;
}

static double grip_py_mf_get(const grip_mf_params *p, int i)
{
    grip_real_t r;
    if (i < 0 || i >= GRIP_PY_NCOEF) {
        return 0.0;
    }
    memcpy(&r, (const char *)p + grip_py_coefs[i].offset, sizeof r);
    return grip_py_from_real(r, grip_py_coefs[i].ql);
}

/* Inputs: SI -> grip_real_t with grip_convert.h (round half away from zero
 * in the fixed build). st[k]: its status (GRIP_OK, GRIP_WARN_CLAMPED: not
 * representable, clamped; GRIP_ERR_INPUT: NaN or infinite, 0 written). */
static void grip_py_to_real(size_t n, const double *si, const uint8_t *ql, grip_real_t *out, int32_t *st)
{
    size_t k;
    for (k = 0; k < n; k++) {
        grip_status_t s = ql[k] ? grip_real_ql_from_si(si[k], &out[k]) : grip_real_qs_from_si(si[k], &out[k]);
        st[k] = (int32_t)s;
    }
}

/* One input of a point: GRIP_OK, or GRIP_ERR_INPUT when the build cannot
 * hold it (as grip-tire: not a clamp, the point is not evaluated). */
static grip_status_t grip_py_in(double si, int ql, grip_real_t *r)
{
    grip_status_t s = ql ? grip_real_ql_from_si(si, r) : grip_real_qs_from_si(si, r);
    return (s == GRIP_OK) ? GRIP_OK : GRIP_ERR_INPUT;
}

/* ---- estimator configuration: the tire pointers ------------------------ */

static void grip_py_est_set_tire(grip_est_config_t *cfg, int axle, const grip_mf_params *p)
{
    cfg->tire[axle].kind = (p != NULL) ? GRIP_EST_TIRE_MF : GRIP_EST_TIRE_NONE;
    cfg->tire[axle].model.mf = p;
}

static const grip_mf_params *grip_py_est_tire(const grip_est_config_t *cfg, int axle)
{
    return (cfg->tire[axle].kind == GRIP_EST_TIRE_MF) ? cfg->tire[axle].model.mf : NULL;
}

/* ---- loops: one library call per point -------------------------------- */

/* The Magic Formula over n points: the inputs of a block of points are
 * converted (strided SI doubles -> grip_mf_input), the block is evaluated by
 * one grip_mf_eval_batch / grip_mf_eval_pure_batch call (grip_mf_batch.h;
 * lanes: grip_mf_eval_prepared_lanes / _pure_prepared_lanes),
 * and the outputs are copied out. A point whose input the build cannot hold
 * is not given to the library (GRIP_ERR_INPUT, zero outputs, as grip-tire).
 * The block lives on the stack: no allocation per call. */
#define GRIP_PY_MF_BLOCK 128u

static int64_t grip_py_mf_eval(const grip_mf_params *p, int pure, int lanes, size_t n,
                               const double *kappa, size_t s_kappa, const double *alpha, size_t s_alpha,
                               const double *gamma, size_t s_gamma, const double *fz, size_t s_fz,
                               const double *pr, size_t s_pr, const double *vx, size_t s_vx,
                               grip_real_t *fx, grip_real_t *fy, grip_real_t *mz, int32_t *status)
{
    grip_mf_input in[GRIP_PY_MF_BLOCK];
    grip_mf_output out[GRIP_PY_MF_BLOCK];
    grip_status_t st[GRIP_PY_MF_BLOCK];
    size_t idx[GRIP_PY_MF_BLOCK];
    size_t k0;
    int64_t errors = 0;
    grip_mf_prepared prep;
    /* lanes: the set prepared once per call and each block through
     * grip_mf_eval_prepared_lanes (grip_mf_batch.h); a set that does not
     * prepare takes grip_mf_eval_batch, which reports it per point */
    if (lanes && grip_mf_prepare(p, p->options, &prep) != GRIP_OK) {
        lanes = 0;
    }
    for (k0 = 0; k0 < n; k0 += GRIP_PY_MF_BLOCK) {
        size_t m = (n - k0 < GRIP_PY_MF_BLOCK) ? n - k0 : GRIP_PY_MF_BLOCK;
        uint32_t good = 0;
        size_t j;
        for (j = 0; j < m; j++) {
            size_t k = k0 + j;
            grip_mf_input *x = &in[good];
            if (grip_py_in(kappa[k * s_kappa], 0, &x->kappa) != GRIP_OK ||
                grip_py_in(alpha[k * s_alpha], 0, &x->alpha) != GRIP_OK ||
                grip_py_in(gamma[k * s_gamma], 0, &x->gamma) != GRIP_OK ||
                grip_py_in(fz[k * s_fz], 1, &x->fz) != GRIP_OK ||
                grip_py_in(pr[k * s_pr], 1, &x->p) != GRIP_OK ||
                grip_py_in(vx[k * s_vx], 0, &x->vx) != GRIP_OK) {
                fx[k] = 0;
                fy[k] = 0;
                mz[k] = 0;
                status[k] = (int32_t)GRIP_ERR_INPUT;
                errors++;
            } else {
                idx[good++] = k;
            }
        }
        if (good != 0) {
            if (lanes) {
                if (pure) {
                    (void)grip_mf_eval_pure_prepared_lanes(&prep, good, in, out, st);
                } else {
                    (void)grip_mf_eval_prepared_lanes(&prep, good, in, out, st);
                }
            } else if (pure) {
                (void)grip_mf_eval_pure_batch(p, good, in, out, st);
            } else {
                (void)grip_mf_eval_batch(p, good, in, out, st);
            }
            for (j = 0; j < good; j++) {
                size_t k = idx[j];
                fx[k] = out[j].fx;
                fy[k] = out[j].fy;
                mz[k] = out[j].mz;
                status[k] = (int32_t)st[j];
                errors += (st[j] < 0);
            }
        }
    }
    return errors;
}

/* kind: 1 fiala, 2 brush, 3 sakai, 4 neofiala (params: a prepared
 * grip_neofiala_model) - the numbering of port/linux/brush_params.h. */
static int64_t grip_py_brush_eval(int kind, const void *params, size_t n,
                                  const double *kappa, size_t s_kappa, const double *alpha, size_t s_alpha,
                                  const double *gamma, size_t s_gamma, const double *fz, size_t s_fz,
                                  const double *vx, size_t s_vx,
                                  grip_real_t *fx, grip_real_t *fy, grip_real_t *mz, grip_real_t *rh,
                                  int32_t *status)
{
    size_t k;
    int64_t errors = 0;
    for (k = 0; k < n; k++) {
        grip_real_t ka, al, ga, f, v;
        grip_brush_out o;
        grip_status_t st;
        memset(&o, 0, sizeof o);
        if (grip_py_in(kappa[k * s_kappa], 0, &ka) != GRIP_OK ||
            grip_py_in(alpha[k * s_alpha], 0, &al) != GRIP_OK ||
            grip_py_in(gamma[k * s_gamma], 0, &ga) != GRIP_OK ||
            grip_py_in(fz[k * s_fz], 1, &f) != GRIP_OK ||
            grip_py_in(vx[k * s_vx], 0, &v) != GRIP_OK) {
            st = GRIP_ERR_INPUT;
        } else {
            switch (kind) {
            case GRIP_BRUSH_KIND_FIALA: st = grip_fiala_eval((const grip_fiala_params *)params, al, f, &o); break;
            case GRIP_BRUSH_KIND_BRUSH: st = grip_brush_eval((const grip_brush_params *)params, ka, f, v, &o); break;
            case GRIP_BRUSH_KIND_SAKAI: st = grip_sakai_eval((const grip_sakai_params *)params, ka, al, f, &o); break;
            case GRIP_BRUSH_KIND_NEOFIALA:
                st = grip_neofiala_eval_model((const grip_neofiala_model *)params, ka, al, ga, f, v, &o);
                break;
            default: st = GRIP_ERR_STATE; break;
            }
        }
        fx[k] = o.fx;
        fy[k] = o.fy;
        mz[k] = o.mz;
        rh[k] = o.rh;
        status[k] = (int32_t)st;
        errors += (st < 0);
    }
    return errors;
}

static int64_t grip_py_est_run(grip_est_t *est, size_t n, const grip_input_sample_t *in,
                               grip_est_output_t *out, int32_t *status)
{
    size_t k;
    int64_t errors = 0;
    for (k = 0; k < n; k++) {
        grip_status_t st = grip_est_step(est, &in[k], &out[k]);
        status[k] = (int32_t)st;
        errors += (st < 0);
    }
    return errors;
}

static int64_t grip_py_calib_run(grip_calib_t *c, size_t n, const grip_input_sample_t *in,
                                 grip_input_sample_t *out, int32_t *status)
{
    size_t k;
    int64_t errors = 0;
    for (k = 0; k < n; k++) {
        grip_status_t st = grip_calib_apply(c, &in[k], &out[k]);
        status[k] = (int32_t)st;
        errors += (st < 0);
    }
    return errors;
}

/* est_prev: n outputs (row k is the est_prev of sample k) or NULL. */
static int64_t grip_py_monitor_run(grip_monitor_t *mon, size_t n, grip_input_sample_t *samples,
                                   const grip_est_output_t *est_prev, grip_monitor_report_t *rep,
                                   int32_t *status)
{
    size_t k;
    int64_t errors = 0;
    for (k = 0; k < n; k++) {
        grip_status_t st = grip_monitor_step(mon, &samples[k], (est_prev != NULL) ? &est_prev[k] : NULL, &rep[k]);
        status[k] = (int32_t)st;
        errors += (st < 0);
    }
    return errors;
}

/* The documented chain per sample (grip_calib.h, grip_monitor.h):
 *   calib -> monitor (est_prev: the estimator's own previous output) ->
 *   estimator -> gate of a copy for the consumer.
 * cal, mon may be NULL (stage left out); last / have_last carry the
 * estimator's previous output across calls. */
static int64_t grip_py_chain_run(grip_calib_t *cal, grip_monitor_t *mon, grip_est_t *est, uint32_t honour,
                                 grip_est_output_t *last, int *have_last, size_t n,
                                 const grip_input_sample_t *in, grip_input_sample_t *used,
                                 grip_monitor_report_t *rep, grip_est_output_t *own, grip_est_output_t *gated,
                                 int32_t *st_cal, int32_t *st_mon, int32_t *st_est)
{
    size_t k;
    int64_t errors = 0;
    for (k = 0; k < n; k++) {
        grip_input_sample_t s = in[k];
        grip_status_t st;
        if (cal != NULL) {
            st = grip_calib_apply(cal, &in[k], &s);
            st_cal[k] = (int32_t)st;
            errors += (st < 0);
        }
        if (mon != NULL) {
            st = grip_monitor_step(mon, &s, *have_last ? last : NULL, &rep[k]);
            st_mon[k] = (int32_t)st;
            errors += (st < 0);
        }
        st = grip_est_step(est, &s, last);
        *have_last = 1;
        st_est[k] = (int32_t)st;
        errors += (st < 0);
        own[k] = *last;
        gated[k] = *last;
        if (mon != NULL) {
            (void)grip_monitor_gate(&rep[k], honour, &gated[k]);
        }
        used[k] = s;
    }
    return errors;
}

/* ---- the readers of grip-tire (port/linux), a fallback ------------------ */

/* The file's values in SI doubles (v: GRIP_MF_COEFFICIENTS order), FITTYP
 * and TYRESIDE, validated as grip-tire validates them. 0 or -1 (err). */
static int grip_py_tir_parse(const char *path, double *v, int n, int32_t *fittyp, int32_t *tyreside, char *err,
                             size_t errlen)
{
    grip_tir_values t;
    int i;
    if (n != GRIP_TIR_NCOEF || grip_tir_parse(path, NULL, &t, err, errlen) != 0) {
        return -1;
    }
    for (i = 0; i < n; i++) {
        v[i] = t.v[i];
    }
    *fittyp = t.fittyp;
    *tyreside = t.tyreside;
    return 0;
}

/* A brush-model parameter file's text (name: for messages) parsed by
 * grip-tire's reader into the model's parameter struct (size bytes; for
 * neofiala the grip_neofiala_params, not the prepared model). 0 or -1. */
static int grip_py_brush_parse(const char *text, const char *name, int *kind, void *params, size_t size, char *err,
                               size_t errlen)
{
    grip_brush_tool *t = malloc(sizeof *t);   /* large */
    const void *src = NULL;
    size_t n = 0;
    int rc = -1;
    if (t == NULL) {
        return -1;
    }
    if (grip_brush_params_parse(text, name, NULL, t, err, errlen) == 0) {
        *kind = (int)t->kind;
        switch (t->kind) {
        case GRIP_BRUSH_KIND_FIALA: src = &t->fiala; n = sizeof t->fiala; break;
        case GRIP_BRUSH_KIND_BRUSH: src = &t->brush; n = sizeof t->brush; break;
        case GRIP_BRUSH_KIND_SAKAI: src = &t->sakai; n = sizeof t->sakai; break;
        case GRIP_BRUSH_KIND_NEOFIALA: src = &t->neofiala; n = sizeof t->neofiala; break;
        default: break;
        }
        if (src != NULL && n <= size) {
            memcpy(params, src, n);
            rc = 0;
        }
    }
    free(t);
    return rc;
}
/* ---- grip-replay's replay of a log (port/linux/replay_core.c) ---------- */

/* The rows of one replay: per step t_s, step, (value, fault) of each
 * input the output writes, est_status, est_valid, est_flags and the
 * REPLAY_EST_REALS outputs, as the doubles a reader of grip-replay's text
 * gets (the same formats, read back); NaN = an empty cell. text: every
 * message and the summary, as grip-replay prints them on stderr. */
typedef struct {
    double *rows;
    size_t n;
    size_t ncol;
    char *text;
    size_t text_len;
    int capped;               /* more steps than max_rows: the rest not kept */
    uint8_t write_input[64];
} grip_py_replay_out;

typedef char grip_py_replay_inputs_fit[(GRIP_IN_COUNT <= 64) ? 1 : -1];

#define GRIP_PY_REPLAY_EST_REALS REPLAY_EST_REALS

typedef struct {
    grip_py_replay_out *out;
    size_t cap;
    size_t max_rows;
    int failed;
} grip_py_replay_sink;

static void grip_py_replay_row(void *ctx, const replay *r, const grip_input_sample_t *s)
{
    grip_py_replay_sink *k = (grip_py_replay_sink *)ctx;
    grip_py_replay_out *o = k->out;
    double ev[REPLAY_EST_REALS];
    double *p;
    uint32_t i;
    size_t c = 0;
    if (k->failed) {
        return;
    }
    if (o->ncol == 0) {
        o->ncol = 2 + 3 + REPLAY_EST_REALS;
        for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
            o->ncol += r->write_input[i] ? 2u : 0u;
        }
    }
    if (o->n == k->cap) {
        size_t cap = (k->cap == 0) ? 1024 : 2 * k->cap;
        double *q;
        if (cap > k->max_rows) {
            cap = k->max_rows;
        }
        if (o->n >= cap) {
            k->failed = 1;
            o->capped = 1;
            return;
        }
        q = (double *)realloc(o->rows, cap * o->ncol * sizeof *q);
        if (q == NULL) {
            k->failed = 1;
            o->capped = 1;
            return;
        }
        o->rows = q;
        k->cap = cap;
    }
    p = o->rows + o->n * o->ncol;
    p[c++] = replay_time_value(s->t_us);
    p[c++] = (double)s->step;
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        if (r->write_input[i]) {
            p[c++] = s->valid[i] ? replay_input_value(s->value[i], i) : NAN;
            p[c++] = (double)s->fault[i];
        }
    }
    p[c++] = (double)r->est_status;
    p[c++] = (double)r->est_out.valid;
    p[c++] = (double)r->est_out.flags;
    replay_est_values(r, ev);
    for (i = 0; i < (uint32_t)REPLAY_EST_REALS; i++) {
        p[c++] = isnan(ev[i]) ? NAN : replay_as_printed(ev[i], REPLAY_DIGITS_EST);
    }
    o->n++;
}

/* grip-replay ARGS (argv[0] the program's name) for a log file or --csv
 * file with -e, in this process: the rows into out (at most max_rows),
 * the messages into out->text. Returns grip-replay's exit status. Not
 * reentrant (replay_core's static buffers): the caller holds a lock. */
static int grip_py_replay_run(int argc, char **argv, size_t max_rows, grip_py_replay_out *out)
{
    replay_options o;
    replay *r = NULL;
    grip_py_replay_sink sink;
    FILE *msg;
    int status;
    uint32_t i;
    memset(out, 0, sizeof *out);
    memset(&sink, 0, sizeof sink);
    sink.out = out;
    sink.max_rows = max_rows;
    msg = open_memstream(&out->text, &out->text_len);
    if (msg == NULL) {
        return -1;
    }
    status = replay_parse_args(argc, argv, &o, msg);
    if (status != 0) {
        status = EXIT_USAGE;
    } else if (o.iface != NULL || o.est_tir == NULL || o.out != NULL || o.dump != NULL) {
        fprintf(msg, "grip-replay: the in-process replay takes a log or --csv file with -e, no -i, -o or --dump\n");
        status = EXIT_USAGE;
    } else if ((r = (replay *)calloc(1, sizeof *r)) == NULL) {
        fprintf(msg, "grip-replay: out of memory\n");
        status = EXIT_OUTPUT;
    } else {
        r->opt = &o;
        r->msg = msg;
        status = replay_setup(r);
        if (status == 0) {
            r->source = (o.csv_in != NULL) ? o.csv_in : o.log;
            r->row = grip_py_replay_row;
            r->row_ctx = &sink;
            status = replay_run(r);
            for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
                out->write_input[i] = (uint8_t)(r->write_input[i] != 0);
            }
        }
        free(r);
    }
    fclose(msg);
    return status;
}

static void grip_py_replay_free(grip_py_replay_out *out)
{
    free(out->rows);
    free(out->text);
    out->rows = NULL;
    out->text = NULL;
    out->n = 0;
}
"""


def c_string(s):
    """A C string literal of s."""
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def meta(table):
    """What the extension tells Python about its structs: per struct the
    fields [name, ctype, dims, fmt]."""
    return json.dumps({name: [list(f) for f in fields] for name, fields in table.items()},
                      separators=(",", ":"))


def make_ffi(arith):
    """The FFI builder of one arithmetic."""
    import cffi
    check_tree()
    suffix, fixed = ARITHS[arith]
    table = struct_table()
    ffi = cffi.FFI()
    real = "int32_t" if fixed else "float"
    ffi.cdef(f"typedef {real} grip_real_t;\n" + CDEF_HEAD + cdef_structs(table) + CDEF_TAIL)
    ffi.set_source(
        f"grip._grip_{suffix}", C_SOURCE,
        include_dirs=[INCLUDE, PORT],
        define_macros=[("GRIP_ARITH_FIXED", str(fixed)), ("GRIP_DEBUG_SATURATION", "0"),
                       ("_POSIX_C_SOURCE", "200809L"),
                       ("GRIP_PY_META", c_string(meta(table))),
                       # replaced by tools/setup.py with the real compiler and
                       # commands once setuptools has chosen the compiler
                       ("GRIP_PY_BUILD", c_string("{}"))],
        libraries=["m"],
        extra_compile_args=["-O2"],
    )
    # tools/setup.py reads these to compile and link the library objects
    ffi.grip_arith = arith
    return ffi


ffi_float = make_ffi("float") if __name__ == "__cffi__" else None
ffi_fixed = make_ffi("fixed") if __name__ == "__cffi__" else None

