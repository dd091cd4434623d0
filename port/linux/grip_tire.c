/*
 * grip_tire.c - `grip-tire`: evaluate a tire model on CSV rows.
 *
 *   grip-tire [--model mf] [--tir FILE] [--pure] [--side left|right]
 *             [--sae] [--kappa-braking] [--mz52-svyk-camber] [--outputs LIST]
 *             [--use-mode NNN] [--turn-slip] [--ts-camber]
 *             [--no-status] [--prefix STR] < in.csv > out.csv
 *
 * Reads CSV on standard input whose header names at least the columns
 * kappa, alpha, gamma, fz, p, vx (SI units, radians; any order; other
 * columns are passed through unchanged) and writes every row again with
 * the columns fx, fy, mz and status appended. docs/tools.md is the manual:
 * CSV schema, sign conventions, status values and exit codes. --outputs
 * adds the Magic Formula's extended channels (grip_mf_eval_ext, MFeval's
 * channel names, unit in the column name); a channel that is not available
 * at a row (docs/magic-formula-c.md section 8) is an empty field.
 * --use-mode takes MFeval's three-digit useMode (1xx/2xx limits, xx1/xx2
 * turn slip; x2x is refused) and --turn-slip is xx2; with turn slip the
 * column phit [1/m] is read, and a column omega [rad/s] (the wheel's spin,
 * 0: estimated) is read whenever present.
 *
 * Models are entries of MODELS[] below; a model needs a name, a set-up
 * function (read its parameter file) and an evaluation function on SI
 * doubles. The conversion of SI doubles to the build's grip_real_t formats
 * (float, or Q15.16 / Q23.8 in the fixed build) happens here, so a model's
 * evaluation function sees exactly what an ECU application would pass.
 */
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#include "grip/grip_types.h"
#include "brush_params.h"
#include "channel_rules.h"
#include "csv.h"
#include "tir_reader.h"

/* Exit codes (docs/tools.md). */
#define EXIT_ROWS_FAILED 1   /* some rows malformed or rejected by the model */
#define EXIT_USAGE 2         /* bad command line */
#define EXIT_MODEL 3         /* the model's parameters could not be loaded */
#define EXIT_HEADER 4        /* input not CSV grip-tire reads, or implausible in SI units */
#define EXIT_IO 5            /* reading stdin or writing stdout failed */

/* Status written for a row that could not be read (not a grip_status_t). */
#define ROW_MALFORMED (-100)
/* Status written for a row with a value outside its column's plausible
 * range (channel_rules.h): a unit error, not evaluated. */
#define ROW_IMPLAUSIBLE (-101)

/* Longest input line, bytes (without the line end): rows are read into a
 * fixed buffer, so memory does not grow with the input (/dev/zero, a 1 GiB
 * file without a line end). */
#define TIRE_LINE_MAX 65536

/* Model inputs and outputs, in this order: the six every model needs,
 * then the Magic Formula's turn slip and wheel spin (optional columns, 0
 * when absent). */
enum { IN_KAPPA, IN_ALPHA, IN_GAMMA, IN_FZ, IN_P, IN_VX, N_REQ, IN_PHIT = N_REQ, IN_OMEGA, N_IN };
enum { OUT_FX, OUT_FY, OUT_MZ, N_OUT };

static const char *const IN_NAMES[N_IN] = { "kappa", "alpha", "gamma", "fz", "p", "vx", "phit", "omega" };
static const char *const OUT_NAMES[N_OUT] = { "fx", "fy", "mz" };
/* fixed-point format of each: 1 = QL (forces, pressure), 0 = QS */
static const int IN_QL[N_IN] = { 0, 0, 0, 1, 1, 0, 0, 0 };
static const int OUT_QL[N_OUT] = { 1, 1, 1 };
/* SI unit of each input, as a header may declare it: "fz[N]" */
static const char *const IN_UNITS[N_IN] = { "-", "rad", "rad", "N", "Pa", "m/s", "1/m", "rad/s" };

/* Physical plausibility of the inputs: the table grip-tire shares with the
 * Python tools (channel_rules.h). A value outside its range is a unit
 * error (an angle in degrees), not a point of the model's domain: the
 * model's own valid domain (ALPMIN, FZMAX, ...) is narrower and clamps. */
typedef struct {
    const char *name;
    const char *unit;
    double lo;
    double hi;
    const char *what;
    const char *hint;
    double hint_max;
} channel_rule;

#define CHANNEL_RULE(n, u, l, h, w, hi, hm) { #n, u, l, h, w, hi, hm },
static const channel_rule CHANNEL_RULES[] = { GRIP_CHANNELS(CHANNEL_RULE) };
#undef CHANNEL_RULE
#define N_CHANNEL_RULES ((int)(sizeof CHANNEL_RULES / sizeof CHANNEL_RULES[0]))

/* The Magic Formula's extended channels (--outputs), in the column order
 * of grip_mf_output_ext; names as MFeval's, units in the column name. */
typedef struct {
    const char *name;
    const char *unit;
    uint32_t bit;
    size_t off;
    int ql;
} ext_channel;

#define EXT(n, u, b, f, q) { n, u, b, offsetof(grip_mf_output_ext, f), q }
static const ext_channel EXT_CHANNELS[] = {
    EXT("re", "m", GRIP_MF_EXT_RE, re, 0),
    EXT("omega", "rad/s", GRIP_MF_EXT_OMEGA, omega, 0),
    EXT("rl", "m", GRIP_MF_EXT_RL, rl, 0),
    EXT("rho", "m", GRIP_MF_EXT_RHO, rho, 0),
    EXT("cz", "N/m", GRIP_MF_EXT_CZ, cz, 1),
    EXT("2a", "m", GRIP_MF_EXT_LENGTH, contact_length, 0),
    EXT("2b", "m", GRIP_MF_EXT_WIDTH, contact_width, 0),
    EXT("t", "m", GRIP_MF_EXT_T, t, 0),
    EXT("mzr", "Nm", GRIP_MF_EXT_MZR, mzr, 1),
    EXT("mux", "-", GRIP_MF_EXT_MUX, mux, 0),
    EXT("muy", "-", GRIP_MF_EXT_MUY, muy, 0),
    EXT("kxk", "N", GRIP_MF_EXT_KXK, kxk, 1),
    EXT("kya", "N/rad", GRIP_MF_EXT_KYA, kya, 1),
    EXT("cx", "N/m", GRIP_MF_EXT_CX, cx, 1),
    EXT("cy", "N/m", GRIP_MF_EXT_CY, cy, 1),
    EXT("sigmax", "m", GRIP_MF_EXT_SIGMAX, sigmax, 0),
    EXT("sigmay", "m", GRIP_MF_EXT_SIGMAY, sigmay, 0),
    EXT("mx", "Nm", GRIP_MF_EXT_MX, mx, 1),
    EXT("my", "Nm", GRIP_MF_EXT_MY, my, 1),
};
#define N_EXT ((int)(sizeof EXT_CHANNELS / sizeof EXT_CHANNELS[0]))

typedef struct {
    const char *model;
    const char *tir;
    const char *params;
    int pure;
    grip_tir_side side;
    int sae;
    int kappa_braking;
    int mz52_svyk_camber;
    int turn_slip;         /* --turn-slip, --use-mode xx2 */
    int no_limits;         /* --use-mode 2xx */
    int ts_camber;         /* --ts-camber */
    const char *outputs;   /* --outputs LIST, or NULL */
    int n_ext;             /* the extended channels asked for, in order */
    int ext[32];
    int status_column;
    int dump_params;
    const char *prefix;
    unsigned tir_flags;    /* GRIP_TIR_STRICT, GRIP_TIR_NO_RANGE_CHECK */
    int no_unit_check;     /* --no-unit-check: no plausibility check of the inputs */
    int lanes;             /* --lanes: mf through grip_mf_eval_prepared_lanes */
} cli_options;

/* Everything a model keeps between rows. */
typedef struct {
    int pure;
    int lanes;          /* mf: each row through the lane evaluation (prep) */
    grip_mf_prepared prep;
    int sae;            /* brush family: convert SAE <-> ISO-W here */
    int kappa_braking;  /* brush family: kappa given positive in braking */
    double fz_nominal;  /* the tyre's nominal load [N] (FNOMIN), 0 if the model has none */
    union {
        grip_mf_params mf;
        grip_brush_tool brush;
    } u;
} model_ctx;

typedef struct {
    const char *name;
    const char *summary;
    /* Loads the parameters; 0 or -1 with a message in err. */
    int (*setup)(const cli_options *o, model_ctx *m, char *err, size_t errlen);
    /* Evaluates one row: in[] in the build's number format (already
     * converted), out[] likewise. */
    grip_status_t (*eval)(const model_ctx *m, const grip_real_t in[N_IN], grip_real_t out[N_OUT]);
    /* Prints the loaded parameters as "KEY = value" lines (SI). */
    void (*dump)(const model_ctx *m, FILE *f);
} tire_model;

/* ---- Magic Formula ------------------------------------------------ */

/* A warning of the .tir reader ("FILE:LINE: KEY: what"). */
static void print_warning(void *ctx, const char *message)
{
    (void)ctx;
    fprintf(stderr, "grip-tire: warning: %s\n", message);
}

static int mf_setup(const cli_options *o, model_ctx *m, char *err, size_t errlen)
{
    static grip_tir_values vals;   /* the file's values and their lines */
    grip_status_t st;
    if (o->tir == NULL) {
        snprintf(err, errlen, "model 'mf' needs a property file: --tir FILE");
        return -1;
    }
    m->pure = o->pure;
    /* TYRESIDE is taken from the file; --side says where the tyre is
     * mounted (default: as fitted, on the side TYRESIDE names), and the
     * library mirrors the characteristics when the two differ. */
    {
        grip_tir_options to;
        grip_tir_options_init(&to);
        to.side = o->side;
        to.flags = o->tir_flags | (o->pure ? GRIP_TIR_PURE_SLIP : 0u);
        to.warn = print_warning;
        if (grip_tir_parse(o->tir, &to, &vals, err, errlen) != 0 ||
            grip_tir_convert(o->tir, &vals, &m->u.mf, err, errlen) != 0) {
            return -1;
        }
        m->fz_nominal = vals.v[GRIP_TIR_I_fnomin];
    }
    if (o->sae) {
        m->u.mf.options |= GRIP_MF_OPT_SAE;
    }
    if (o->kappa_braking) {
        m->u.mf.options |= GRIP_MF_OPT_KAPPA_BRAKE;
    }
    if (o->mz52_svyk_camber) {
        m->u.mf.options |= GRIP_MF_OPT_MZ52_SVYK_CAMBER;
    }
    if (o->no_limits) {
        m->u.mf.options |= GRIP_MF_OPT_NO_LIMITS;
    }
    if (o->ts_camber) {
        m->u.mf.options |= GRIP_MF_OPT_TS_CAMBER;
    }
    if (o->turn_slip) {
        m->u.mf.options |= GRIP_MF_OPT_TURN_SLIP;
        if (m->u.mf.phyp1 <= (grip_real_t)0 || m->u.mf.qdrp1 <= (grip_real_t)0) {
            snprintf(err, errlen, "%s: turn slip needs the file's [TURNSLIP_COEFFICIENTS] (PHYP1 > 0, 0 < QDRP1 < 2)",
                     o->tir);
            return -1;
        }
    }
    {
        grip_check_detail_t d;
        st = grip_mf_check_params_detail(&m->u.mf, &d);
        if (st != GRIP_OK) {
            /* the struct member is the .tir key in lower case */
            char key[64];
            size_t k;
            for (k = 0; d.field[k] != '\0' && k + 1 < sizeof key; k++) {
                key[k] = (char)((d.field[k] >= 'a' && d.field[k] <= 'z') ? d.field[k] - 'a' + 'A' : d.field[k]);
            }
            key[k] = '\0';
            k = (size_t)grip_tir_coef_index(key);
            snprintf(err, errlen, "%s:%lu: %s: the library rejects the parameter set: %s must be %s (status %d, %s)",
                     o->tir, (grip_tir_coef_index(key) >= 0) ? vals.line[k] : 0ul, key[0] ? key : "-",
                     key[0] ? key : "it", d.rule, (int)st, grip_status_str(st));
            return -1;
        }
    }
    m->lanes = o->lanes;
    if (m->lanes && grip_mf_prepare(&m->u.mf, m->u.mf.options, &m->prep) != GRIP_OK) {
        snprintf(err, errlen, "%s: --lanes: the parameter set does not prepare (grip_mf_prepare)", o->tir);
        return -1;
    }
    return 0;
}

static grip_status_t mf_eval(const model_ctx *m, const grip_real_t in[N_IN], grip_real_t out[N_OUT])
{
    grip_mf_input x;
    grip_mf_output y;
    grip_status_t st;
    memset(&x, 0, sizeof x);
    x.kappa = in[IN_KAPPA];
    x.alpha = in[IN_ALPHA];
    x.gamma = in[IN_GAMMA];
    x.fz = in[IN_FZ];
    x.p = in[IN_P];
    x.vx = in[IN_VX];
    memset(&y, 0, sizeof y);
    if (m->lanes) {
        /* one point per call: the lane code pads the block with copies of
         * it, and a lane's result does not depend on its neighbours, so the
         * row gets the bits grip.mf.evaluate(..., lanes=True) gives it */
        grip_status_t pst = GRIP_OK;
        (void)(m->pure ? grip_mf_eval_pure_prepared_lanes(&m->prep, 1u, &x, &y, &pst)
                       : grip_mf_eval_prepared_lanes(&m->prep, 1u, &x, &y, &pst));
        st = pst;
    } else {
        st = m->pure ? grip_mf_eval_pure(&m->u.mf, &x, &y) : grip_mf_eval(&m->u.mf, &x, &y);
    }
    out[OUT_FX] = y.fx;
    out[OUT_FY] = y.fy;
    out[OUT_MZ] = y.mz;
    return st;
}

/* mf with --outputs: grip_mf_eval_ext, the forces into out[], the asked
 * channels into ext[] (as doubles, SI) and their validity into ok[]. */
static grip_status_t mf_eval_ext_row(const model_ctx *m, const cli_options *o, const grip_real_t in[N_IN],
                                     grip_real_t out[N_OUT], double ext[], int ok[])
{
    grip_mf_input x;
    grip_mf_spin s;
    grip_mf_output_ext y;
    grip_status_t st;
    uint32_t mask = 0u;
    int i;
    x.kappa = in[IN_KAPPA];
    x.alpha = in[IN_ALPHA];
    x.gamma = in[IN_GAMMA];
    x.fz = in[IN_FZ];
    x.p = in[IN_P];
    x.vx = in[IN_VX];
    s.phit = in[IN_PHIT];
    s.omega = in[IN_OMEGA];
    for (i = 0; i < o->n_ext; i++) {
        mask |= EXT_CHANNELS[o->ext[i]].bit;
    }
    st = grip_mf_eval_ext_spin(&m->u.mf, &x, &s, mask, &y);
    out[OUT_FX] = y.fx;
    out[OUT_FY] = y.fy;
    out[OUT_MZ] = y.mz;
    for (i = 0; i < o->n_ext; i++) {
        const ext_channel *c = &EXT_CHANNELS[o->ext[i]];
        grip_real_t v;
        memcpy(&v, (const char *)&y + c->off, sizeof v);
        ext[i] = grip_tir_from_real(v, c->ql);
        ok[i] = (y.valid & c->bit) != 0u;
    }
    return st;
}

static void mf_dump(const model_ctx *m, FILE *f)
{
    int i;
    fprintf(f, "FITTYP = %d\nTYRESIDE = %d\nOPTIONS = %u\n", (int)m->u.mf.fittyp,
            (int)m->u.mf.tyreside, (unsigned)m->u.mf.options);
    for (i = 0; i < grip_tir_coef_count(); i++) {
        fprintf(f, "%s = %.17g\n", grip_tir_coef_key(i), grip_tir_coef_get(&m->u.mf, i));
    }
}

/* ---- brush family (neofiala, fiala, brush, sakai) -------------------- */

static int brush_setup(const cli_options *o, model_ctx *m, char *err, size_t errlen)
{
    if (o->params == NULL) {
        snprintf(err, errlen, "model '%s' needs a parameter file: --params FILE (docs/brush-models.md)",
                 o->model);
        return -1;
    }
    m->pure = o->pure;
    m->sae = o->sae;
    m->kappa_braking = o->kappa_braking;
    /* the models are mirror-symmetric: --side changes nothing */
    return grip_brush_params_read(o->params, o->model, &m->u.brush, err, errlen);
}

static grip_real_t neg(grip_real_t v)
{
    return (grip_real_t)(-v);
}

static grip_status_t brush_eval(const model_ctx *m, const grip_real_t in[N_IN], grip_real_t out[N_OUT])
{
    /* SAE J670 tyre axes differ from ISO-W in the signs of alpha, Fz, Fy
     * and Mz (docs/magic-formula.md); kappa-braking negates kappa. */
    grip_real_t kappa = m->kappa_braking ? neg(in[IN_KAPPA]) : in[IN_KAPPA];
    grip_real_t alpha = m->sae ? neg(in[IN_ALPHA]) : in[IN_ALPHA];
    grip_real_t fz = m->sae ? neg(in[IN_FZ]) : in[IN_FZ];
    grip_status_t st = grip_brush_tool_eval(&m->u.brush, kappa, alpha, in[IN_GAMMA], fz, in[IN_VX],
                                            &out[OUT_FX], &out[OUT_FY], &out[OUT_MZ]);
    if (m->sae) {
        out[OUT_FY] = neg(out[OUT_FY]);
        out[OUT_MZ] = neg(out[OUT_MZ]);
    }
    return st;
}

static void brush_dump(const model_ctx *m, FILE *f)
{
    grip_brush_params_dump(&m->u.brush, f);
}

static const tire_model MODELS[] = {
    { "mf", "Magic Formula 5.2 / 6.1 / 6.2 from a .tir file (--tir)", mf_setup, mf_eval, mf_dump },
    { "neofiala", "reduced Neo-FIALA brush model, closed form (--params)", brush_setup, brush_eval, brush_dump },
    { "fiala", "classic FIALA lateral force and moment (--params)", brush_setup, brush_eval, brush_dump },
    { "brush", "brush model, adhesive/sliding friction, n-th power pressure (--params)", brush_setup,
      brush_eval, brush_dump },
    { "sakai", "Sakai's combined-slip brush model (--params)", brush_setup, brush_eval, brush_dump },
};
#define N_MODELS (sizeof MODELS / sizeof MODELS[0])

/* ---- command line ------------------------------------------------- */

static void usage(FILE *f)
{
    size_t i;
    fprintf(f,
            "usage: grip-tire [--model NAME] [--tir FILE] [--pure] [--side left|right]\n"
            "                 [--sae] [--kappa-braking] [--mz52-svyk-camber] [--outputs LIST]\n"
            "                 [--use-mode NNN] [--turn-slip] [--ts-camber]\n"
            "                 [--no-status] [--prefix STR] [--dump-params] [--strict]\n"
            "                 [--no-range-check] [--no-unit-check] < in.csv > out.csv\n"
            "\n"
            "Reads CSV with the columns kappa,alpha,gamma,fz,p,vx (SI, rad; any order;\n"
            "other columns passed through) and appends fx,fy,mz,status. Build: %s.\n"
            "A header may declare the units (fz[N], alpha[rad]); any other unit is\n"
            "refused. Values that are not plausible in the SI unit are refused: a slip\n"
            "angle beyond 1.5 rad (degrees?), a largest load below FNOMIN/10 (kN?).\n"
            "\n"
            "  --model NAME      tire model (default mf):\n",
            GRIP_ARITH_NAME);
    for (i = 0; i < N_MODELS; i++) {
        fprintf(f, "                      %-8s %s\n", MODELS[i].name, MODELS[i].summary);
    }
    fprintf(f,
            "  --tir FILE        property file of the mf model\n"
            "  --params FILE     parameter file of the brush-family models (key = value, SI;\n"
            "                    docs/brush-models.md)\n"
            "  --pure            pure-slip forces only (no combined-slip weighting)\n"
            "  --lanes           mf: evaluate through the lane batch (grip_mf_eval_prepared_lanes,\n"
            "                    vectorized in the float build; the bits of grip.mf.evaluate(...,\n"
            "                    lanes=True); not with --outputs or the use modes)\n"
            "  --side left|right where the tyre is mounted (default: as fitted, on the\n"
            "                    side TYRESIDE names, never mirrored); a file fitted\n"
            "                    for the other side is mirrored\n"
            "  --sae             inputs and outputs in SAE J670 tyre axes (x forward,\n"
            "                    y right, z down: alpha, fy, mz and fz change sign);\n"
            "                    default ISO-W (x forward, y left, z up)\n"
            "  --kappa-braking   kappa column is positive in braking (kappa_ISO = -kappa)\n"
            "  --outputs LIST    mf: also the extended channels of LIST (comma-separated,\n"
            "                    or 'all'): re omega rl rho cz 2a 2b t mzr mux muy kxk kya\n"
            "                    cx cy sigmax sigmay mx my (MFeval's names), appended as\n"
            "                    name[unit] columns; empty where not available\n"
            "  --mz52-svyk-camber  mf, MF 5.2 files: combined Mz with Fy' = Fy - SVyk of Fy\n"
            "                    (cambered mu_y) instead of MFeval's SVyk with mu_y at\n"
            "                    gamma = 0 (GRIP_MF_OPT_MZ52_SVYK_CAMBER)\n"
            "  --use-mode NNN    mf: MFeval's useMode: 1xx limits (default), 2xx none (no\n"
            "                    low-speed model, no E <= 1); xx1 no turn slip (default),\n"
            "                    xx2 turn slip; x2x (alpha* = tan alpha) is not available\n"
            "  --turn-slip       mf: turn slip (useMode xx2): reads the column phit [1/m]\n"
            "                    (and omega [rad/s] when present; 0 = estimated)\n"
            "  --ts-camber       mf, turn slip: the camber's spin with the sign that keeps\n"
            "                    the camber thrust (docs/magic-formula.md section 10)\n"
            "  --no-status       do not append the status column\n"
            "  --prefix STR      prefix of the appended column names (e.g. model_)\n"
            "  --dump-params     print the loaded parameters (SI, as stored in this\n"
            "                    build) as KEY = value lines and exit\n"
            "  --strict          .tir: every warning is an error (an unknown key, a key\n"
            "                    in another section, an empty value)\n"
            "  --no-range-check  .tir: accept coefficients outside their plausible ranges\n"
            "                    (docs/tools.md); the hard checks stay\n"
            "  --no-unit-check   evaluate inputs outside their plausible ranges (a slip\n"
            "                    angle of 5 rad, loads all below FNOMIN/10) as given\n"
            "\n"
            "exit status: 0 all rows evaluated; 1 some rows malformed or rejected\n"
            "(status < 0); 2 usage; 3 parameters not loaded; 4 input not readable\n"
            "(header, bytes) or its values implausible in SI units (a unit error;\n"
            "status -101 on the rows); 5 I/O error\n");
}

/* --outputs LIST: comma-separated channel names, or "all". */
static int parse_outputs(cli_options *o)
{
    const char *s = o->outputs;
    o->n_ext = 0;
    if (strcmp(s, "all") == 0) {
        int k;
        for (k = 0; k < N_EXT; k++) {
            o->ext[o->n_ext++] = k;
        }
        return 0;
    }
    while (*s != '\0') {
        size_t len = strcspn(s, ",");
        int k;
        int found = -1;
        for (k = 0; k < N_EXT; k++) {
            if (strlen(EXT_CHANNELS[k].name) == len && strncmp(EXT_CHANNELS[k].name, s, len) == 0) {
                found = k;
            }
        }
        if (found < 0) {
            fprintf(stderr, "grip-tire: --outputs: unknown channel '%.*s' (", (int)len, s);
            for (k = 0; k < N_EXT; k++) {
                fprintf(stderr, "%s%s", k ? " " : "", EXT_CHANNELS[k].name);
            }
            fprintf(stderr, ", or all)\n");
            return -1;
        }
        for (k = 0; k < o->n_ext; k++) {
            if (o->ext[k] == found) {
                fprintf(stderr, "grip-tire: --outputs: channel '%s' given twice\n", EXT_CHANNELS[found].name);
                return -1;
            }
        }
        o->ext[o->n_ext++] = found;
        s += len;
        if (*s == ',') {
            s++;
        }
    }
    if (o->n_ext == 0) {
        fprintf(stderr, "grip-tire: --outputs: no channel given\n");
        return -1;
    }
    return 0;
}

static int parse_args(int argc, char **argv, cli_options *o)
{
    int i;
    memset(o, 0, sizeof *o);
    o->model = "mf";
    o->side = GRIP_TIR_SIDE_FILE;
    o->status_column = 1;
    o->prefix = "";
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--model") == 0 && i + 1 < argc) {
            o->model = argv[++i];
        } else if (strcmp(a, "--tir") == 0 && i + 1 < argc) {
            o->tir = argv[++i];
        } else if (strcmp(a, "--params") == 0 && i + 1 < argc) {
            o->params = argv[++i];
        } else if (strcmp(a, "--pure") == 0) {
            o->pure = 1;
        } else if (strcmp(a, "--lanes") == 0) {
            o->lanes = 1;
        } else if (strcmp(a, "--side") == 0 && i + 1 < argc) {
            const char *s = argv[++i];
            if (strcmp(s, "left") == 0) {
                o->side = GRIP_TIR_SIDE_LEFT;
            } else if (strcmp(s, "right") == 0) {
                o->side = GRIP_TIR_SIDE_RIGHT;
            } else {
                fprintf(stderr, "grip-tire: --side must be left or right, not '%s'\n", s);
                return -1;
            }
        } else if (strcmp(a, "--sae") == 0) {
            o->sae = 1;
        } else if (strcmp(a, "--kappa-braking") == 0) {
            o->kappa_braking = 1;
        } else if (strcmp(a, "--mz52-svyk-camber") == 0) {
            o->mz52_svyk_camber = 1;
        } else if (strcmp(a, "--turn-slip") == 0) {
            o->turn_slip = 1;
        } else if (strcmp(a, "--ts-camber") == 0) {
            o->ts_camber = 1;
        } else if (strcmp(a, "--use-mode") == 0 && i + 1 < argc) {
            const char *s = argv[++i];
            if (strlen(s) != 3 || (s[0] != '1' && s[0] != '2') || (s[1] != '1' && s[1] != '2') ||
                (s[2] != '1' && s[2] != '2')) {
                fprintf(stderr, "grip-tire: --use-mode: '%s' is not one of MFeval's useModes (1|2)(1|2)(1|2)\n", s);
                return -1;
            }
            if (s[1] == '2') {
                fprintf(stderr, "grip-tire: --use-mode %s: alpha* = tan(alpha) (MFeval's x2x) is not available: "
                                "MFeval mixes gamma and gamma* term by term there; the library's GRIP_MF_OPT_BOOK "
                                "(the book's forms) is the nearest (docs/magic-formula-c.md section 9)\n", s);
                return -1;
            }
            o->no_limits = (s[0] == '2');
            o->turn_slip = (s[2] == '2');
        } else if (strcmp(a, "--outputs") == 0 && i + 1 < argc) {
            o->outputs = argv[++i];
        } else if (strcmp(a, "--no-status") == 0) {
            o->status_column = 0;
        } else if (strcmp(a, "--dump-params") == 0) {
            o->dump_params = 1;
        } else if (strcmp(a, "--strict") == 0) {
            o->tir_flags |= GRIP_TIR_STRICT;
        } else if (strcmp(a, "--no-range-check") == 0) {
            o->tir_flags |= GRIP_TIR_NO_RANGE_CHECK;
        } else if (strcmp(a, "--no-unit-check") == 0) {
            o->no_unit_check = 1;
        } else if (strcmp(a, "--prefix") == 0 && i + 1 < argc) {
            o->prefix = argv[++i];
        } else {
            fprintf(stderr, "grip-tire: unknown or incomplete option '%s' (try --help)\n", a);
            return -1;
        }
    }
    return (o->outputs != NULL) ? parse_outputs(o) : 0;
}

/* ---- CSV processing ------------------------------------------------ */

static int name_eq(const char *a, const char *b)
{
    while (*a != '\0' && *b != '\0') {
        char ca = (*a >= 'A' && *a <= 'Z') ? (char)(*a - 'A' + 'a') : *a;
        char cb = (*b >= 'A' && *b <= 'Z') ? (char)(*b - 'A' + 'a') : *b;
        if (ca != cb) {
            return 0;
        }
        a++;
        b++;
    }
    return *a == *b;
}

/* A header field "name" or "name[unit]" (blanks around either allowed):
 * 1 if its name is `name` (any letter case), with the unit, if declared,
 * in unit[] ("" if not). */
static int column_is(const char *field, const char *name, char *unit, size_t unitlen)
{
    const char *open = strchr(field, '[');
    size_t n = (open != NULL) ? (size_t)(open - field) : strlen(field);
    char base[64];
    unit[0] = '\0';
    while (n > 0 && (field[n - 1] == ' ' || field[n - 1] == '\t')) {
        n--;
    }
    if (n >= sizeof base) {
        return 0;
    }
    memcpy(base, field, n);
    base[n] = '\0';
    if (!name_eq(base, name)) {
        return 0;
    }
    if (open != NULL) {
        const char *u = open + 1;
        const char *close = strchr(u, ']');
        size_t k;
        while (*u == ' ') {
            u++;
        }
        k = (close != NULL) ? (size_t)(close - u) : strlen(u);
        while (k > 0 && u[k - 1] == ' ') {
            k--;
        }
        if (k >= unitlen) {
            k = unitlen - 1;
        }
        memcpy(unit, u, k);
        unit[k] = '\0';
        if (k == 0) {
            unit[0] = '?';   /* "name[]": declared, but no unit */
            unit[1] = '\0';
        }
    }
    return 1;
}

/* The declared unit is the input's SI unit (kappa: "-", "1" or "") */
static int unit_ok(int input, const char *unit)
{
    if (unit[0] == '\0' || strcmp(unit, IN_UNITS[input]) == 0) {
        return 1;
    }
    return input == IN_KAPPA && strcmp(unit, "1") == 0;
}

typedef struct {
    int col[N_IN];        /* column of each input */
    int rule[N_IN];       /* its plausibility rule in CHANNEL_RULES, -1: none */
    int ncols;
} header_map;

/* The column of the i-th asked extended channel: prefix, name, [unit]. */
static void ext_column_name(const cli_options *o, int i, char *name, size_t len)
{
    const ext_channel *c = &EXT_CHANNELS[o->ext[i]];
    snprintf(name, len, "%s%s[%s]", o->prefix, c->name, c->unit);
}

static int read_header(const char *line, const cli_options *o, header_map *h)
{
    csv_record rec;
    const char *why = NULL;
    size_t len = strlen(line) + 1;
    char *work = malloc(len);
    int i;
    int j;
    int k;
    if (work == NULL) {
        fprintf(stderr, "grip-tire: out of memory\n");
        return -1;
    }
    if (csv_split(line, work, len, &rec, &why) != 0) {
        fprintf(stderr, "grip-tire: <stdin>:1: header: %s\n", why);
        free(work);
        return -1;
    }
    h->ncols = rec.n;
    for (i = 0; i < N_IN; i++) {
        h->col[i] = -1;
        h->rule[i] = -1;
        for (j = 0; j < N_CHANNEL_RULES; j++) {
            if (strcmp(CHANNEL_RULES[j].name, IN_NAMES[i]) == 0) {
                h->rule[i] = j;
            }
        }
        for (j = 0; j < rec.n; j++) {
            char unit[32];
            if (column_is(rec.field[j], IN_NAMES[i], unit, sizeof unit)) {
                if (!unit_ok(i, unit)) {
                    fprintf(stderr,
                            "grip-tire: <stdin>:1: header: column %d '%s': unit [%s], but grip-tire reads %s "
                            "in [%s] (convert the column: nothing is converted here)\n",
                            j + 1, rec.field[j], unit, IN_NAMES[i], IN_UNITS[i]);
                    free(work);
                    return -1;
                }
                if (h->col[i] >= 0) {
                    fprintf(stderr, "grip-tire: <stdin>:1: header: column '%s' appears twice (%d and %d)\n",
                            IN_NAMES[i], h->col[i] + 1, j + 1);
                    free(work);
                    return -1;
                }
                h->col[i] = j;
            }
        }
    }
    for (i = 0; i < N_REQ; i++) {
        if (h->col[i] < 0) {
            fprintf(stderr,
                    "grip-tire: <stdin>:1: header: missing column '%s' (need kappa,alpha,gamma,fz,p,vx)\n",
                    IN_NAMES[i]);
            free(work);
            return -1;
        }
    }
    if (o->turn_slip && h->col[IN_PHIT] < 0) {
        fprintf(stderr, "grip-tire: <stdin>:1: header: missing column 'phit' (turn slip [1/m])\n");
        free(work);
        return -1;
    }
    /* the appended names must not collide with input columns */
    for (k = 0; k < N_OUT + o->n_ext + 1; k++) {
        char name[128];
        if (k == N_OUT + o->n_ext && !o->status_column) {
            break;
        }
        if (k < N_OUT) {
            snprintf(name, sizeof name, "%s%s", o->prefix, OUT_NAMES[k]);
        } else if (k < N_OUT + o->n_ext) {
            ext_column_name(o, k - N_OUT, name, sizeof name);
        } else {
            snprintf(name, sizeof name, "%sstatus", o->prefix);
        }
        for (j = 0; j < rec.n; j++) {
            if (name_eq(rec.field[j], name)) {
                fprintf(stderr,
                        "grip-tire: <stdin>:1: header: input already has a column '%s' "
                        "(use --prefix to name the outputs differently)\n",
                        name);
                free(work);
                return -1;
            }
        }
    }
    free(work);
    return 0;
}

typedef struct {
    unsigned long rows;
    unsigned long malformed;
    unsigned long implausible; /* ROW_IMPLAUSIBLE */
    unsigned long errors;     /* status < 0 */
    unsigned long warnings;   /* status > 0 */
    double fz_max;            /* largest load (ISO, N) of the rows read, and its line */
    unsigned long fz_line;
    double p_max;             /* largest positive pressure [Pa], and its line (0: none) */
    unsigned long p_line;
} run_stats;

/* Messages of implausible rows printed per run; the summary counts the rest. */
#define IMPLAUSIBLE_MESSAGES 10

/* One row's inputs (SI doubles, as given) against the plausibility table:
 * 0, or -1 with the message printed if `print`. */
static int check_row_units(const cli_options *o, const header_map *h, const double in[N_IN],
                           unsigned long lineno, int print)
{
    int i;
    for (i = 0; i < N_IN; i++) {
        const channel_rule *r;
        double v = in[i];
        if (h->rule[i] < 0 || h->col[i] < 0) {
            continue;
        }
        r = &CHANNEL_RULES[h->rule[i]];
        if (i == IN_FZ && o->sae) {
            v = -v;   /* the table's loads are ISO: positive when loaded */
        }
        if (i == IN_P && v <= 0.0) {
            continue;   /* p <= 0: the tyre's nominal pressure (docs/tools.md) */
        }
        if (v < r->lo || v > r->hi) {
            double a = (in[i] < 0.0) ? -in[i] : in[i];
            if (!print) {
                return -1;
            }
            fprintf(stderr,
                    "grip-tire: <stdin>:%lu: column '%s': %g %s is outside the plausible range of the %s "
                    "[%g, %g] %s%s; --no-unit-check evaluates it as given\n",
                    lineno, IN_NAMES[i], in[i], r->unit, r->what, (i == IN_FZ && o->sae) ? -r->hi : r->lo,
                    (i == IN_FZ && o->sae) ? -r->lo : r->hi, r->unit,
                    (r->hint_max > 0.0 && a <= r->hint_max) ? r->hint : "");
            return -1;
        }
    }
    return 0;
}

/* The whole-column rules of channel_rules.h, after the last row: loads
 * all below GRIP_CHANNEL_FZ_KN_N newtons or a tenth of FNOMIN (kN labelled
 * N), pressures all below GRIP_CHANNEL_P_BAR_PA (bar or psi). The rows are
 * written by then; the exit status says the output cannot be used.
 * 0, or -1 with the message printed. */
static int check_columns(const model_ctx *m, const run_stats *rs)
{
    int bad = 0;
    double fz_min = GRIP_CHANNEL_FZ_KN_N;
    if (GRIP_CHANNEL_FZ_KN_FNOMIN * m->fz_nominal > fz_min) {
        fz_min = GRIP_CHANNEL_FZ_KN_FNOMIN * m->fz_nominal;
    }
    if (rs->fz_line > 0 && rs->fz_max > 0.0 && rs->fz_max < fz_min) {
        if (m->fz_nominal > 0.0) {
            fprintf(stderr,
                    "grip-tire: <stdin>:%lu: column 'fz': the largest load is %g N, below a tenth of the tyre's "
                    "FNOMIN = %g N: a load in kN labelled N? (--no-unit-check evaluates it as given)\n",
                    rs->fz_line, rs->fz_max, m->fz_nominal);
        } else {
            fprintf(stderr,
                    "grip-tire: <stdin>:%lu: column 'fz': the largest load is %g N, below %g N: a load in kN "
                    "labelled N? (--no-unit-check evaluates it as given)\n",
                    rs->fz_line, rs->fz_max, fz_min);
        }
        bad = 1;
    }
    if (rs->p_line > 0 && rs->p_max < GRIP_CHANNEL_P_BAR_PA) {
        fprintf(stderr,
                "grip-tire: <stdin>:%lu: column 'p': the largest pressure is %g Pa, below %g Pa: bar, psi or kPa "
                "labelled Pa? (0 takes the nominal pressure; --no-unit-check evaluates it as given)\n",
                rs->p_line, rs->p_max, GRIP_CHANNEL_P_BAR_PA);
        bad = 1;
    }
    return bad ? -1 : 0;
}

/* One data row. Writes the output row; returns the status written. */
static int process_row(const tire_model *model, const model_ctx *m, const cli_options *o,
                       const header_map *h, const char *line, unsigned long lineno,
                       char *work, size_t worklen, run_stats *rs, FILE *out)
{
    csv_record rec;
    const char *why = NULL;
    double in[N_IN];
    double res[N_OUT] = { 0.0, 0.0, 0.0 };
    grip_real_t rin[N_IN];
    grip_real_t rout[N_OUT];
    double ext[N_EXT];
    int ext_ok[N_EXT];
    int status;
    int i;

    for (i = 0; i < N_EXT; i++) {
        ext[i] = 0.0;
        ext_ok[i] = 0;
    }

    if (csv_split(line, work, worklen, &rec, &why) != 0) {
        fprintf(stderr, "grip-tire: <stdin>:%lu: malformed row: %s\n", lineno, why);
        status = ROW_MALFORMED;
        goto write;
    }
    if (rec.n != h->ncols) {
        fprintf(stderr, "grip-tire: <stdin>:%lu: malformed row: %d fields, the header has %d\n",
                lineno, rec.n, h->ncols);
        status = ROW_MALFORMED;
        goto write;
    }
    for (i = 0; i < N_IN; i++) {
        const char *f;
        if (h->col[i] < 0) {
            in[i] = 0.0;   /* an optional column that is absent */
            continue;
        }
        f = rec.field[h->col[i]];
        if (csv_number(f, &in[i]) != 0) {
            fprintf(stderr, "grip-tire: <stdin>:%lu: column '%s': '%s' is not a finite number\n",
                    lineno, IN_NAMES[i], f);
            status = ROW_MALFORMED;
            goto write;
        }
    }
    if (!o->no_unit_check) {
        double fz_iso = o->sae ? -in[IN_FZ] : in[IN_FZ];
        if (check_row_units(o, h, in, lineno, rs->implausible < IMPLAUSIBLE_MESSAGES) != 0) {
            status = ROW_IMPLAUSIBLE;
            goto write;
        }
        if (rs->fz_line == 0 || fz_iso > rs->fz_max) {
            rs->fz_max = fz_iso;
            rs->fz_line = lineno;
        }
        if (in[IN_P] > 0.0 && (rs->p_line == 0 || in[IN_P] > rs->p_max)) {
            rs->p_max = in[IN_P];
            rs->p_line = lineno;
        }
    }
    for (i = 0; i < N_IN; i++) {
        if (grip_tir_to_real(in[i], IN_QL[i], &rin[i]) != 0) {
            fprintf(stderr, "grip-tire: <stdin>:%lu: column '%s': %g is not representable in the %s build\n",
                    lineno, IN_NAMES[i], in[i], GRIP_ARITH_NAME);
            status = GRIP_ERR_INPUT;
            goto write;
        }
    }
    if (o->n_ext > 0 || o->turn_slip || o->no_limits) {
        /* the use modes are evaluated by grip_mf_eval_ext only */
        status = (int)mf_eval_ext_row(m, o, rin, rout, ext, ext_ok);
    } else {
        status = (int)model->eval(m, rin, rout);
    }
    for (i = 0; i < N_OUT; i++) {
        res[i] = grip_tir_from_real(rout[i], OUT_QL[i]);
    }
    if (status < 0) {
        fprintf(stderr, "grip-tire: <stdin>:%lu: model '%s': status %d (%s)\n", lineno, model->name,
                status, grip_status_str((grip_status_t)status));
    }
write:
    fputs(line, out);
    if (status == ROW_MALFORMED || status == ROW_IMPLAUSIBLE) {
        for (i = 0; i < N_OUT; i++) {
            fputs(",", out);   /* empty: nothing was computed */
        }
    } else {
        for (i = 0; i < N_OUT; i++) {
            fprintf(out, ",%.9g", res[i] + 0.0);
        }
    }
    for (i = 0; i < o->n_ext; i++) {
        if (status != ROW_MALFORMED && status != ROW_IMPLAUSIBLE && ext_ok[i]) {
            fprintf(out, ",%.9g", ext[i] + 0.0);
        } else {
            fputs(",", out);   /* empty: not available at this row */
        }
    }
    if (o->status_column) {
        fprintf(out, ",%d", status);
    }
    fputc('\n', out);
    return status;
}

/* A row that could not be read at all: its input fields and outputs empty,
 * status ROW_MALFORMED. */
static void write_empty_row(const cli_options *o, const header_map *h, FILE *out)
{
    int i;
    for (i = 1; i < h->ncols; i++) {
        fputc(',', out);
    }
    for (i = 0; i < N_OUT + o->n_ext; i++) {
        fputc(',', out);
    }
    if (o->status_column) {
        fprintf(out, ",%d", ROW_MALFORMED);
    }
    fputc('\n', out);
}

int main(int argc, char **argv)
{
    cli_options o;
    const tire_model *model = NULL;
    static model_ctx m;
    static char linebuf[TIRE_LINE_MAX + 1];
    static char workbuf[TIRE_LINE_MAX + 1];
    char err[1024];
    char rerr[512];
    csv_reader rd;
    header_map h;
    run_stats rs;
    size_t i;
    int k;

    if (parse_args(argc, argv, &o) != 0) {
        return EXIT_USAGE;
    }
    for (i = 0; i < N_MODELS; i++) {
        if (strcmp(MODELS[i].name, o.model) == 0) {
            model = &MODELS[i];
        }
    }
    if (model == NULL) {
        fprintf(stderr, "grip-tire: unknown model '%s'; available:", o.model);
        for (i = 0; i < N_MODELS; i++) {
            fprintf(stderr, " %s", MODELS[i].name);
        }
        fprintf(stderr, "\n");
        return EXIT_USAGE;
    }
    if (o.n_ext > 0 && (strcmp(model->name, "mf") != 0 || o.pure)) {
        fprintf(stderr, "grip-tire: --outputs needs the combined-slip mf model (not --model %s%s)\n", model->name,
                o.pure ? ", --pure" : "");
        return EXIT_USAGE;
    }
    if ((o.turn_slip || o.no_limits || o.ts_camber) && strcmp(model->name, "mf") != 0) {
        fprintf(stderr, "grip-tire: --use-mode, --turn-slip and --ts-camber are options of the mf model (not --model %s)\n",
                model->name);
        return EXIT_USAGE;
    }
    if (o.lanes && (strcmp(model->name, "mf") != 0 || o.n_ext > 0 || o.turn_slip || o.no_limits)) {
        fprintf(stderr, "grip-tire: --lanes evaluates the mf model's forces without use modes (not with --model %s, "
                        "--outputs, --turn-slip or --use-mode 2xx)\n", model->name);
        return EXIT_USAGE;
    }
    if ((o.turn_slip || o.no_limits) && o.pure) {
        fprintf(stderr, "grip-tire: the use modes are evaluated with combined slip only (not with --pure)\n");
        return EXIT_USAGE;
    }
    memset(&m, 0, sizeof m);
    err[0] = '\0';
    if (model->setup(&o, &m, err, sizeof err) != 0) {
        fprintf(stderr, "grip-tire: %s\n", err);
        return EXIT_MODEL;
    }
    if (o.dump_params) {
        model->dump(&m, stdout);
        return (fflush(stdout) == 0) ? 0 : EXIT_IO;
    }

    /* header: the first line that is not blank */
    if (csv_reader_open(&rd, "-", linebuf, TIRE_LINE_MAX, 1, rerr, sizeof rerr) != 0) {
        fprintf(stderr, "grip-tire: %s\n", rerr);
        return EXIT_IO;
    }
    for (;;) {
        int rc = csv_read_line(&rd, rerr, sizeof rerr);
        if (rc == 0) {
            fprintf(stderr, "grip-tire: <stdin>: no header line (empty input)\n");
            return EXIT_HEADER;
        }
        if (rc < 0) {
            fprintf(stderr, "grip-tire: %s (the header)\n", rerr);
            return (rd.error == CSV_ERR_READ) ? EXIT_IO : EXIT_HEADER;
        }
        if (rd.len > 0) {
            break;
        }
    }
    if (read_header(rd.line, &o, &h) != 0) {
        return EXIT_HEADER;
    }
    fputs(rd.line, stdout);
    for (k = 0; k < N_OUT; k++) {
        fprintf(stdout, ",%s%s", o.prefix, OUT_NAMES[k]);
    }
    for (k = 0; k < o.n_ext; k++) {
        char name[128];
        ext_column_name(&o, k, name, sizeof name);
        fprintf(stdout, ",%s", name);
    }
    if (o.status_column) {
        fprintf(stdout, ",%sstatus", o.prefix);
    }
    fputc('\n', stdout);

    memset(&rs, 0, sizeof rs);
    for (;;) {
        int st;
        int rc = csv_read_line(&rd, rerr, sizeof rerr);
        if (rc == 0) {
            break;
        }
        if (rc < 0 && rd.error == CSV_ERR_TEXT) {
            /* a row with a byte that is not text: reported with its line and
             * byte offset, written as a row of empty fields (status -100) so
             * that output row n is still input row n; then on to its end */
            {
                int pre = snprintf(NULL, 0, "%s:%lu: ", rd.path, rd.lineno);
                const char *what = (pre > 0 && (size_t)pre < strlen(rerr)) ? rerr + pre : rerr;
                fprintf(stderr, "grip-tire: %s:%lu: malformed row: %s\n", rd.path, rd.lineno, what);
            }
            write_empty_row(&o, &h, stdout);
            rs.rows++;
            rs.malformed++;
            if (csv_skip_line(&rd, rerr, sizeof rerr) != 0) {
                rc = -1;
            } else {
                continue;
            }
        }
        if (rc < 0) {
            fprintf(stderr, "grip-tire: %s\n", rerr);
            return (rd.error == CSV_ERR_READ) ? EXIT_IO : EXIT_HEADER;
        }
        if (rd.len == 0) {
            continue;   /* blank line: not a row */
        }
        st = process_row(model, &m, &o, &h, rd.line, rd.lineno, workbuf, sizeof workbuf, &rs, stdout);
        rs.rows++;
        if (st == ROW_MALFORMED) {
            rs.malformed++;
        } else if (st == ROW_IMPLAUSIBLE) {
            rs.implausible++;
        } else if (st < 0) {
            rs.errors++;
        } else if (st > 0) {
            rs.warnings++;
        }
    }
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "grip-tire: writing the output failed: %s\n", strerror(errno));
        return EXIT_IO;
    }
    {
        int units_bad = (rs.implausible > 0);
        if (!o.no_unit_check && check_columns(&m, &rs) != 0) {
            units_bad = 1;
        }
        if (rs.malformed > 0 || rs.implausible > 0 || rs.errors > 0 || rs.warnings > 0 || units_bad) {
            fprintf(stderr,
                    "grip-tire: %lu rows: %lu malformed, %lu implausible in SI units%s, %lu rejected by the model, "
                    "%lu with warnings%s\n",
                    rs.rows, rs.malformed, rs.implausible,
                    (rs.implausible > IMPLAUSIBLE_MESSAGES) ? " (the first 10 reported)" : "", rs.errors, rs.warnings,
                    units_bad ? "; the input looks like another unit: the output is not usable" : "");
        }
        if (units_bad) {
            return EXIT_HEADER;
        }
    }
    return (rs.malformed > 0 || rs.errors > 0) ? EXIT_ROWS_FAILED : 0;
}
