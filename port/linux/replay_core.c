/*
 * replay_core.c - a candump log or an estimator-input CSV file replayed
 * into estimator steps (replay_core.h): the signal table, the sample
 * assembler's loop, the CSV reader with its input rules (input_rules.h),
 * the estimator's setup (vehicle_config.h), the rows and the summary.
 * Moved out of grip_replay.c unchanged so that the Python binding runs the
 * same code as the program; docs/can.md is the program's manual.
 */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_can.h"
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "candump.h"
#include "csv.h"
#include "input_rules.h"
#include "replay_core.h"
#include "tir_reader.h"
#include "vehicle_config.h"

double replay_real_to_si(grip_real_t v, int ql)
{
#if GRIP_ARITH_FIXED
    return (double)v / (ql ? 256.0 : 65536.0);
#else
    (void)ql;
    return (double)v;
#endif
}

/* A warning of the .tir reader ("FILE:LINE: KEY: what"). */
static void print_tir_warning(void *ctx, const char *message)
{
    fprintf((FILE *)ctx, "grip-replay: warning: %s\n", message);
}

/* Called once per estimator step with the time-aligned input sample, before
 * the sample is written. */
static void grip_replay_estimator_step(replay *r, const grip_input_sample_t *sample)
{
    if (!r->est_on) {
        return;
    }
    r->est_status = grip_est_step(&r->est, sample, &r->est_out);
    if (r->est_status < 0) {
        r->est_errors++;
    }
    r->est_valid[0] += (r->est_out.valid & GRIP_EST_V_BETA) != 0u;
    r->est_valid[1] += (r->est_out.valid & GRIP_EST_V_YAW_REF) != 0u;
    r->est_valid[2] += (r->est_out.valid & GRIP_EST_V_MU) != 0u;
}
static int parse_double(const char *s, double lo, double hi, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return errno == 0 && end != s && *end == '\0' && *v >= lo && *v <= hi;
}

static int parse_long(const char *s, long long lo, long long hi, long long *v)
{
    char *end;
    errno = 0;
    *v = strtoll(s, &end, 10);
    return errno == 0 && end != s && *end == '\0' && *v >= lo && *v <= hi;
}

/* Where each option applies; an option outside its mode is a usage error
 * (it would otherwise be ignored without a word). */
enum { SC_ANY, SC_CAN, SC_FILE, SC_LIVE, SC_CSV, SC_EST };

static const struct {
    const char *s;
    const char *l;
    int scope;
} OPTS[] = {
    { "-t", "--table", SC_CAN },      { "-o", "--output", SC_ANY },       { "-s", "--step-ms", SC_ANY },
    { "-k", "--stale", SC_CAN },      { "-w", "--reorder-us", SC_CAN },   { "-j", "--jump-ms", SC_CAN },
    { "", "--time-offset-us", SC_FILE }, { "", "--skip-bad", SC_FILE },   { "", "--reorder", SC_FILE },
    { "", "--all-inputs", SC_ANY },   { "", "--units", SC_ANY },          { "", "--dump", SC_CAN },
    { "-i", "--interface", SC_LIVE }, { "", "--fd", SC_LIVE },            { "-d", "--duration", SC_LIVE },
    { "-n", "--frames", SC_CAN },     { "", "--idle-exit", SC_LIVE },     { "-e", "--estimate", SC_ANY },
    { "", "--estimate-rear", SC_EST }, { "", "--vehicle", SC_EST },      { "", "--vehicle-file", SC_EST },   { "", "--csv", SC_CSV },
    { "", "--ignore-columns", SC_CSV }, { "-q", "--quiet", SC_ANY },
    { "", "--strict", SC_EST },       { "", "--no-range-check", SC_EST },
    { "", "--learned-in", SC_EST },   { "", "--learned-out", SC_EST },
};
#define N_OPTS (sizeof OPTS / sizeof OPTS[0])

int replay_parse_args(int argc, char **argv, replay_options *o, FILE *msg)
{
    int i;
    unsigned char given[N_OPTS];
    const char *scope_opt[SC_EST + 1];
    const char *mode;
    size_t k;
    memset(o, 0, sizeof *o);
    memset(given, 0, sizeof given);
    memset((void *)scope_opt, 0, sizeof scope_opt);
    o->step_ms = 10.0;
    o->jump_ms = 1000.0;
    o->stale = 3;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        long long n;
        int takes = 1;
#define IS(s, l) (strcmp(a, s) == 0 || strcmp(a, l) == 0)
        if (IS("-h", "--help")) {
            return 1;
        }
        for (k = 0; k < N_OPTS; k++) {
            if (strcmp(a, OPTS[k].l) == 0 || (OPTS[k].s[0] != '\0' && strcmp(a, OPTS[k].s) == 0)) {
                break;
            }
        }
        if (k < N_OPTS) {
            if (given[k]++) {
                fprintf(msg, "grip-replay: option %s given twice\n", OPTS[k].l);
                return -1;
            }
            if (scope_opt[OPTS[k].scope] == NULL) {
                scope_opt[OPTS[k].scope] = OPTS[k].l;
            }
        }
        if (IS("-q", "--quiet")) {
            o->quiet = 1;
            takes = 0;
        } else if (strcmp(a, "--skip-bad") == 0) {
            o->skip_bad = 1;
            takes = 0;
        } else if (strcmp(a, "--all-inputs") == 0) {
            o->all_inputs = 1;
            takes = 0;
        } else if (strcmp(a, "--no-unit-check") == 0) {
            o->no_unit_check = 1;
            takes = 0;
        } else if (strcmp(a, "--reorder") == 0) {
            o->sort_log = 1;
            takes = 0;
        } else if (strcmp(a, "--units") == 0) {
            o->units = 1;
            takes = 0;
        } else if (strcmp(a, "--fd") == 0) {
            o->want_fd = 1;
            takes = 0;
        } else if (strcmp(a, "--strict") == 0) {
            o->tir_flags |= GRIP_TIR_STRICT;
            takes = 0;
        } else if (strcmp(a, "--no-range-check") == 0) {
            o->tir_flags |= GRIP_TIR_NO_RANGE_CHECK;
            takes = 0;
        } else if (a[0] == '-' && a[1] != '\0' && v == NULL) {
            fprintf(msg, "grip-replay: option %s needs a value\n", a);
            return -1;
        } else if (IS("-t", "--table")) {
            o->table_path = v;
        } else if (IS("-o", "--output")) {
            o->out = v;
        } else if (strcmp(a, "--dump") == 0) {
            o->dump = v;
        } else if (IS("-i", "--interface")) {
            o->iface = v;
        } else if (IS("-e", "--estimate")) {
            o->est_tir = v;
        } else if (strcmp(a, "--estimate-rear") == 0) {
            o->est_tir_rear = v;
        } else if (strcmp(a, "--vehicle") == 0) {
            o->vehicle = v;
        } else if (strcmp(a, "--vehicle-file") == 0) {
            o->vehicle_file = v;
        } else if (strcmp(a, "--learned-in") == 0) {
            o->learned_in = v;
        } else if (strcmp(a, "--learned-out") == 0) {
            o->learned_out = v;
        } else if (strcmp(a, "--csv") == 0) {
            o->csv_in = v;
        } else if (strcmp(a, "--ignore-columns") == 0) {
            o->ignore_cols = v;
        } else if (IS("-s", "--step-ms")) {
            if (!parse_double(v, 0.001, 1000.0, &o->step_ms)) {
                fprintf(msg, "grip-replay: --step-ms must be 0.001..1000, not '%s'\n", v);
                return -1;
            }
            o->step_given = 1;
        } else if (IS("-j", "--jump-ms")) {
            if (!parse_double(v, 0.001, 100000.0, &o->jump_ms)) {
                fprintf(msg, "grip-replay: --jump-ms must be 0.001..100000, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-k", "--stale")) {
            if (!parse_long(v, 1, 1000, &n)) {
                fprintf(msg, "grip-replay: --stale must be 1..1000, not '%s'\n", v);
                return -1;
            }
            o->stale = (long)n;
        } else if (IS("-w", "--reorder-us")) {
            if (!parse_long(v, 0, 10000000, &n)) {
                fprintf(msg, "grip-replay: --reorder-us must be 0..10000000, not '%s'\n", v);
                return -1;
            }
            o->reorder_us = (long)n;
        } else if (strcmp(a, "--time-offset-us") == 0) {
            if (!parse_long(v, -4000000000000000000LL, 4000000000000000000LL, &o->time_offset_us)) {
                fprintf(msg, "grip-replay: --time-offset-us must be an integer, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-d", "--duration")) {
            if (!parse_double(v, 0.0, 1e9, &o->duration_s)) {
                fprintf(msg, "grip-replay: --duration must be >= 0 seconds, not '%s'\n", v);
                return -1;
            }
        } else if (strcmp(a, "--idle-exit") == 0) {
            if (!parse_double(v, 0.0, 1e9, &o->idle_exit_s)) {
                fprintf(msg, "grip-replay: --idle-exit must be >= 0 seconds, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-n", "--frames")) {
            if (!parse_long(v, 1, 4000000000000LL, &n)) {
                fprintf(msg, "grip-replay: --frames must be >= 1, not '%s'\n", v);
                return -1;
            }
            o->max_frames = (unsigned long)n;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(msg, "grip-replay: unknown option %s (try --help)\n", a);
            return -1;
        } else {
            if (o->log != NULL) {
                fprintf(msg, "grip-replay: more than one log file given ('%s' and '%s')\n", o->log, a);
                return -1;
            }
            o->log = a;
            takes = 0;
        }
#undef IS
        i += takes;
    }
    if (o->csv_in != NULL) {
        if (o->log != NULL || o->iface != NULL) {
            fprintf(msg, "grip-replay: --csv replaces the CAN log / interface: give only one source\n");
            return -1;
        }
        if (o->est_tir == NULL) {
            fprintf(msg, "grip-replay: --csv needs the estimator (-e TIR)\n");
            return -1;
        }
        mode = "--csv input";
    } else if ((o->log == NULL) == (o->iface == NULL)) {
        fprintf(msg, "grip-replay: give either a log file or -i IFACE (try --help)\n");
        return -1;
    } else {
        mode = (o->iface != NULL) ? "a live interface (-i)" : "a log file";
    }
    /* options outside their mode */
    {
        const char *bad = NULL;
        const char *where = "";
        if (o->csv_in != NULL) {
            bad = scope_opt[SC_CAN] ? scope_opt[SC_CAN] : scope_opt[SC_FILE] ? scope_opt[SC_FILE] : scope_opt[SC_LIVE];
            where = "CAN input (a log or -i)";
        } else if (scope_opt[SC_CSV] != NULL) {
            bad = scope_opt[SC_CSV];
            where = "--csv input";
        } else if (o->iface != NULL && scope_opt[SC_FILE] != NULL) {
            bad = scope_opt[SC_FILE];
            where = "a log file";
        } else if (o->iface == NULL && scope_opt[SC_LIVE] != NULL) {
            bad = scope_opt[SC_LIVE];
            where = "a live interface (-i)";
        }
        if (bad == NULL && o->est_tir == NULL && scope_opt[SC_EST] != NULL) {
            bad = scope_opt[SC_EST];
            where = "the estimator (-e TIR)";
        }
        if (bad != NULL) {
            fprintf(msg, "grip-replay: option %s is for %s, not %s\n", bad, where, mode);
            return -1;
        }
    }
    return 0;
}

/* ---- signal table ------------------------------------------------------------ */

static grip_can_table_text_t text_table;

static int load_table(const char *path, const grip_can_table_t **table, FILE *out)
{
    static char line[GRIP_CAN_TEXT_LINE_MAX + 1];
    /* the line of each msg and sig line, to name what the consistency
     * check refuses */
    static unsigned long msg_line[GRIP_CAN_MAX_MESSAGES];
    static unsigned long sig_line[GRIP_CAN_MAX_SIGNALS];
    grip_check_detail_t d;
    char err[700];
    const char *why = "";
    csv_reader rd;
    int rc;
    if (path == NULL) {
        *table = &grip_can_table_rav4;
        return 0;
    }
    if (csv_reader_open(&rd, path, line, GRIP_CAN_TEXT_LINE_MAX, 0, err, sizeof err) != 0) {
        fprintf(out, "grip-replay: signal table: %s\n", err);
        return -1;
    }
    grip_can_table_text_init(&text_table);
    while ((rc = csv_read_line(&rd, err, sizeof err)) == 1) {
        uint16_t nm = text_table.table.n_messages;
        uint16_t ns = text_table.table.n_signals;
        if (grip_can_table_text_line(&text_table, line, (uint32_t)rd.len, &why) != GRIP_OK) {
            fprintf(out, "grip-replay: %s:%lu: %s\n", rd.path, rd.lineno, why);
            csv_reader_close(&rd);
            return -1;
        }
        if (text_table.table.n_messages > nm && nm < GRIP_CAN_MAX_MESSAGES) {
            msg_line[nm] = rd.lineno;
        }
        if (text_table.table.n_signals > ns && ns < GRIP_CAN_MAX_SIGNALS) {
            sig_line[ns] = rd.lineno;
        }
    }
    csv_reader_close(&rd);
    if (rc < 0) {
        fprintf(out, "grip-replay: signal table: %s\n", err);
        return -1;
    }
    if (grip_can_table_text_finish_detail(&text_table, table, &why, &d) != GRIP_OK) {
        if (d.rule[0] != '\0') {
            /* the refused message or signal by its line and name */
            const grip_can_table_t *t = &text_table.table;
            int msg = strcmp(d.part, "message") == 0 && d.index >= 0 && d.index < (int32_t)t->n_messages;
            int sig = strcmp(d.part, "signal") == 0 && d.index >= 0 && d.index < (int32_t)t->n_signals;
            if (msg || sig) {
                fprintf(out, "grip-replay: %s:%lu: %s %s: %s: %s (the table's consistency check)\n", path,
                        msg ? msg_line[d.index] : sig_line[d.index], d.part,
                        msg ? t->messages[d.index].name : t->signals[d.index].name, d.field, d.rule);
            } else if (strcmp(d.part, "input") == 0 && d.index >= 0) {
                fprintf(out, "grip-replay: %s: input %s: %s: %s (the table's consistency check)\n", path,
                        grip_input_name((uint32_t)d.index), d.field, d.rule);
            } else {
                fprintf(out, "grip-replay: %s: %s: %s (the table's consistency check)\n", path, d.field,
                        d.rule);
            }
        } else {
            fprintf(out, "grip-replay: %s: %s\n", path, why);
        }
        return -1;
    }
    return 0;
}

/* ---- output -------------------------------------------------------------------- */

static void format_value(char *buf, size_t n, grip_real_t v, uint32_t input)
{
#if GRIP_ARITH_FIXED
    double d = (double)v / (grip_input_is_ql(input) ? 256.0 : 65536.0);
    snprintf(buf, n, "%.17g", d);
#else
    (void)input;
    snprintf(buf, n, "%.*g", REPLAY_DIGITS_INPUT, (double)v);
#endif
}

static void format_time(char *buf, size_t n, int64_t t_us)
{
    int64_t sec = (t_us >= 0) ? t_us / 1000000 : -((-t_us + 999999) / 1000000);
    snprintf(buf, n, "%" PRId64 ".%06" PRId64, sec, t_us - sec * 1000000);
}

/* The estimator's output columns, in order, with their units (--units). */
static const struct {
    const char *name;
    const char *unit;
} EST_COLS[] = {
    { "est_status", "" },   { "est_valid", "" },      { "est_flags", "" },       { "vx", "m_s" },
    { "beta", "rad" },      { "yaw_rate", "rad_s" },  { "yaw_rate_ref", "rad_s" }, { "delta", "rad" },
    { "mu", "" },           { "mu_conf", "" },        { "fy_front", "N" },       { "fy_rear", "N" },
    { "util_front", "" },   { "util_rear", "" },      { "fy_margin_front", "N" }, { "yaw_rate_bias", "rad_s" },
    { "ay_model", "m_s2" },   { "beta_sd", "rad" },     { "mu_sd", "" },           { "vx_sd", "m_s" },
    { "fy_front_sd", "N" },   { "fy_rear_sd", "N" },
};
#define N_EST_COLS (sizeof EST_COLS / sizeof EST_COLS[0])

/* A unit as a column-name suffix: "/" and "^" dropped, "rad/s" -> "rad_s",
 * "m/s^2" -> "m_s2", "N m" -> "Nm". */
static const char *unit_suffix(const char *unit)
{
    static const char *const map[][2] = {
        { "m/s", "m_s" }, { "rad", "rad" }, { "rad/s", "rad_s" }, { "m/s^2", "m_s2" }, { "Pa", "Pa" }, { "N m", "Nm" },
    };
    size_t k;
    for (k = 0; k < sizeof map / sizeof map[0]; k++) {
        if (strcmp(unit, map[k][0]) == 0) {
            return map[k][1];
        }
    }
    return "";
}

/* Base name of input i's columns: its name, with "_in" where the estimator
 * writes a column of the same name (yaw_rate: the measured input is
 * yaw_rate_in, the estimate yaw_rate). */
static void input_base(const replay *r, uint32_t i, char *buf, size_t n)
{
    const char *name = grip_input_name(i);
    size_t k;
    snprintf(buf, n, "%s", name);
    if (r->est_on) {
        for (k = 0; k < N_EST_COLS; k++) {
            if (strcmp(EST_COLS[k].name, name) == 0) {
                snprintf(buf, n, "%s_in", name);
            }
        }
    }
}

#define MAX_OUT_COLS (2 + 2 * GRIP_IN_COUNT + 20)

/* Writes the header; -1 if two columns would have the same name (a reader
 * keyed by name would lose one). */
int replay_write_header(replay *r)
{
    static char names[MAX_OUT_COLS][48];
    size_t nc = 0;
    size_t a;
    size_t b;
    uint32_t i;
    snprintf(names[nc++], sizeof names[0], "t_s");
    snprintf(names[nc++], sizeof names[0], "step");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        char base[40];
        if (!r->write_input[i]) {
            continue;
        }
        input_base(r, i, base, sizeof base);
        if (r->opt->units) {
            snprintf(names[nc++], sizeof names[0], "%s_%s", base, unit_suffix(grip_input_unit(i)));
        } else {
            snprintf(names[nc++], sizeof names[0], "%s", base);
        }
        snprintf(names[nc++], sizeof names[0], "%s_fault", base);
    }
    if (r->est_on) {
        for (a = 0; a < N_EST_COLS; a++) {
            if (r->opt->units && EST_COLS[a].unit[0] != '\0') {
                snprintf(names[nc++], sizeof names[0], "%s_%s", EST_COLS[a].name, EST_COLS[a].unit);
            } else {
                snprintf(names[nc++], sizeof names[0], "%s", EST_COLS[a].name);
            }
        }
    }
    for (a = 0; a < nc; a++) {
        for (b = a + 1; b < nc; b++) {
            if (strcmp(names[a], names[b]) == 0) {
                fprintf(r->msg, "grip-replay: internal error: output columns %lu and %lu are both named %s\n",
                        (unsigned long)a + 1ul, (unsigned long)b + 1ul, names[a]);
                return -1;
            }
        }
    }
    if (r->row != NULL) {
        return 0;   /* the caller names the columns */
    }
    for (a = 0; a < nc; a++) {
        fprintf(r->csv, "%s%s", a ? "," : "", names[a]);
    }
    fprintf(r->csv, "\n");
    return 0;
}

void replay_est_values(const replay *r, double v[REPLAY_EST_REALS])
{
    const grip_est_output_t *e = &r->est_out;
    /* the tire model's lateral acceleration sum Fy / m (body frame: the
     * front wheels' forces turned by the road-wheel angle), the
     * quantity the estimator's ay measurement update predicts */
    double d = replay_real_to_si(e->delta, 0);
    double fyb = 0.0;
    uint32_t i;
    for (i = 0; i < 4u; i++) {
        double fx = replay_real_to_si(e->fx[i], 1);
        double fy = replay_real_to_si(e->fy[i], 1);
        fyb += (i < 2u) ? fx * sin(d) + fy * cos(d) : fy;
    }
    v[0] = replay_real_to_si(e->vx, 0);
    v[1] = replay_real_to_si(e->beta, 0);
    v[2] = replay_real_to_si(e->yaw_rate, 0);
    v[3] = replay_real_to_si(e->yaw_rate_ref, 0);
    v[4] = replay_real_to_si(e->delta, 0);
    v[5] = replay_real_to_si(e->mu, 0);
    v[6] = replay_real_to_si(e->mu_conf, 0);
    v[7] = replay_real_to_si(e->fy_axle[0], 1);
    v[8] = replay_real_to_si(e->fy_axle[1], 1);
    v[9] = replay_real_to_si(e->util_axle[0], 0);
    v[10] = replay_real_to_si(e->util_axle[1], 0);
    v[11] = replay_real_to_si(e->fy_margin_front, 1);
    v[12] = replay_real_to_si(e->yaw_rate_bias, 0);
    v[13] = ((e->valid & GRIP_EST_V_AXLE) != 0u && r->mass_si > 0.0) ? fyb / r->mass_si : NAN;
    v[14] = replay_real_to_si(e->beta_sd, 0);
    v[15] = replay_real_to_si(e->mu_sd, 0);
    v[16] = replay_real_to_si(e->vx_sd, 0);
    v[17] = replay_real_to_si(e->fy_axle_sd[0], 1);
    v[18] = replay_real_to_si(e->fy_axle_sd[1], 1);
}

double replay_input_value(grip_real_t v, uint32_t input)
{
#if GRIP_ARITH_FIXED
    return (double)v / (grip_input_is_ql(input) ? 256.0 : 65536.0);   /* %.17g: exact */
#else
    (void)input;
    return replay_as_printed((double)v, REPLAY_DIGITS_INPUT);
#endif
}

double replay_time_value(int64_t t_us)
{
    char buf[32];
    if (t_us >= 0 && t_us < ((int64_t)1 << 53)) {
        /* the text is t_us / 10^6 exactly; one IEEE division of exact
         * operands is that value correctly rounded, as strtod gives it */
        return (double)t_us / 1e6;
    }
    format_time(buf, sizeof buf, t_us);
    return strtod(buf, NULL);
}

/* 10^0 .. 10^22: every one exact in a double */
static const double POW10[23] = { 1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22 };

static double as_printed_text(double v, int digits)
{
    char buf[40];
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    return strtod(buf, NULL);
}

/* %.*g rounds |v| to M * 10^k, M an integer of `digits` digits (the exact
 * binary value, rounded to nearest); strtod returns the double nearest to
 * M * 10^k. Without text: y = |v| / 10^k is one rounding away from the
 * exact quotient (10^|k| exact for |k| <= 22), so M = round(y) unless y's
 * fraction is within that error of one half (then the text path decides),
 * and M * 10^k (or M / 10^-k) of exact operands is one correctly rounded
 * operation: strtod's result. A value rounding up to 10^digits gives the
 * same M * 10^k as the printed "1e..." form. */
double replay_as_printed(double v, int digits)
{
    double a = fabs(v);
    double y;
    double m;
    double lo;
    double hi;
    int e;
    int k;
    int i;
    if (a == 0.0 || !isfinite(v) || digits < 1 || digits > 15) {
        return (a == 0.0) ? v : as_printed_text(v, digits);
    }
    lo = POW10[digits - 1];
    hi = POW10[digits];
    e = (int)floor(log10(a));
    y = 0.0;
    for (i = 0; i < 3; i++) {   /* log10 may be one off near a power of ten */
        k = e - digits + 1;
        if (k > 22 || k < -22) {
            return as_printed_text(v, digits);
        }
        y = (k >= 0) ? a / POW10[k] : a * POW10[-k];
        if (y < lo) {
            e--;
        } else if (y >= hi) {
            e++;
        } else {
            break;
        }
    }
    if (i == 3) {
        return as_printed_text(v, digits);
    }
    m = floor(y);
    if (fabs((y - m) - 0.5) <= y * 0x1p-50) {
        return as_printed_text(v, digits);
    }
    m = floor(y + 0.5);
    y = (k >= 0) ? m * POW10[k] : m / POW10[-k];
    return (v < 0.0) ? -y : y;
}

static void emit(replay *r, const grip_input_sample_t *s)
{
    char t[32];
    char v[40];
    uint32_t i;
    grip_replay_estimator_step(r, s);
    if (r->row != NULL) {
        r->row(r->row_ctx, r, s);
        r->rows++;
        return;
    }
    format_time(t, sizeof t, s->t_us);
    fprintf(r->csv, "%s,%" PRIu32, t, s->step);
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        if (!r->write_input[i]) {
            continue;
        }
        v[0] = '\0';
        if (s->valid[i]) {
            format_value(v, sizeof v, s->value[i], i);
        }
        fprintf(r->csv, ",%s,%s", v, grip_sig_fault_str(s->fault[i]));
    }
    if (r->est_on) {
        const grip_est_output_t *e = &r->est_out;
        double ev[REPLAY_EST_REALS];
        replay_est_values(r, ev);
        fprintf(r->csv, ",%d,%" PRIu32 ",%" PRIu32, (int)r->est_status, e->valid, e->flags);
        for (i = 0; i < (uint32_t)REPLAY_EST_REALS; i++) {
            if (isnan(ev[i])) {
                fputc(',', r->csv);   /* ay_model without the axle forces: an empty cell */
            } else {
                fprintf(r->csv, ",%.*g", REPLAY_DIGITS_EST, ev[i]);
            }
        }
    }
    if (fprintf(r->csv, "\n") < 0) {
        r->write_failed = 1;
    }
    r->rows++;
}

/* Emits every step due before time now. */
void replay_drain(replay *r, int64_t now)
{
    grip_input_sample_t s;
    while (grip_can_asm_poll(&r->a, now, &s)) {
        emit(r, &s);
    }
}

void replay_feed(replay *r, const grip_can_frame_t *f, const char *ifname)
{
    uint32_t fault = 0;
    int32_t msg;
    if (r->dump != NULL) {
        char line[CANDUMP_LINE_MAX];
        if (candump_format(f, ifname, line, sizeof line) < 0 || fputs(line, r->dump) < 0) {
            r->write_failed = 1;
        }
    }
    r->frames_read++;
    if (!r->have_t || f->t_us > r->last_t) {
        r->last_t = f->t_us;
    }
    if (!r->have_t) {
        r->first_t = f->t_us;
        r->have_t = 1;
    }
    replay_drain(r, f->t_us);
    (void)grip_can_asm_push(&r->a, f, &fault);
    msg = ((f->id & GRIP_CAN_ID_ERR) != 0u) ? -1 : grip_can_find_message(r->table, f->id);
    if (msg >= 0) {
        r->msg_seen[msg]++;
        if (fault == (uint32_t)GRIP_CAN_FRAME_DLC) {
            r->msg_dlc[msg]++;
        }
    }
}

/* Emits the steps up to the newest frame. */
void replay_finish(replay *r)
{
    if (r->have_t && r->a.started) {
        int64_t newest = r->a.newest_t_us > r->last_t ? r->a.newest_t_us : r->last_t;
        replay_drain(r, newest + (int64_t)r->opt->reorder_us + 1);
    }
}

/* ---- summary ------------------------------------------------------------------- */

void replay_summary(const replay *r, const can_sock *sock)
{
    const grip_can_stats_t *st = &r->a.stats;
    char t0[32];
    char t1[32];
    uint32_t i;
    uint32_t decode_errors = st->dlc_errors + st->checksum_errors + st->counter_frozen + st->range_errors +
                             st->qualifier_faults;
    format_time(t0, sizeof t0, r->first_t);
    format_time(t1, sizeof t1, r->last_t);
    fprintf(r->msg, "grip-replay: %s, table %s (%u messages, %u signals), step %g ms, stale after %ld periods\n",
            r->source, r->table->name, (unsigned)r->table->n_messages, (unsigned)r->table->n_signals,
            r->opt->step_ms, r->opt->stale);
    fprintf(r->msg, "  frames         %lu read (%s .. %s s), %" PRIu32 " decoded, %" PRIu32 " other ids, "
            "%" PRIu32 " error frames, %" PRIu32 " remote requests\n",
            r->frames_read, r->have_t ? t0 : "-", r->have_t ? t1 : "-", st->decoded, st->unknown_id,
            st->error_frames, st->rtr_frames);
    fprintf(r->msg, "  decode errors  %" PRIu32 " (dlc %" PRIu32 ", checksum %" PRIu32 ", counter frozen %" PRIu32
            ", out of range %" PRIu32 ", sender fault %" PRIu32 "), counter skips %" PRIu32 "\n",
            decode_errors, st->dlc_errors, st->checksum_errors, st->counter_frozen, st->range_errors,
            st->qualifier_faults, st->counter_skips);
    fprintf(r->msg, "  timing         %" PRIu32 " reordered, %" PRIu32 " late, %" PRIu32 " too old, %" PRIu32
            " timestamp jumps\n", st->reordered, st->late, st->too_old, st->jumps);
    fprintf(r->msg, "  samples        %" PRIu32 " steps written\n", st->samples);
    fprintf(r->msg, "  %-18s %8s %8s %8s %8s %8s\n", "input", "valid", "stale", "missing", "range", "fault");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        const uint32_t *c = st->input_faults[i];
        if (!r->write_input[i]) {
            continue;
        }
        fprintf(r->msg, "  %-18s %8" PRIu32 " %8" PRIu32 " %8" PRIu32 " %8" PRIu32 " %8" PRIu32 "\n",
                grip_input_name(i), c[GRIP_SIG_OK], c[GRIP_SIG_STALE], c[GRIP_SIG_MISSING], c[GRIP_SIG_RANGE],
                c[GRIP_SIG_FAULT]);
    }
    if (sock != NULL) {
        fprintf(r->msg, "  socket         %" PRIu32 " drops (kernel queue overflow), %" PRIu32 " bus-off, %" PRIu32
                " controller errors, %" PRIu32 " truncated reads, %" PRIu32 " interface-down, %" PRIu32
                " without kernel timestamp\n", sock->drops, sock->bus_off, sock->controller_errors, sock->truncated,
                sock->down, sock->no_timestamp);
    } else {
        fprintf(r->msg, "  drops          0 (file replay)\n");
        if (r->opt->sort_log) {
            fprintf(r->msg, "  log order      %lu frames older than one before them (at most %.3f ms), sorted "
                    "(--reorder: %d ms window)\n", r->out_of_order, (double)r->max_back_us / 1000.0,
                    CANDUMP_REORDER_WINDOW_US / 1000);
        } else {
            fprintf(r->msg, "  log order      %lu frames older than one before them (at most %.3f ms, tolerance "
                    "%.3f ms), passed on as they came\n", r->out_of_order, (double)r->max_back_us / 1000.0,
                    (double)r->back_tolerance_us / 1000.0);
        }
    }
    if (r->est_on) {
        fprintf(r->msg, "  estimator      %" PRIu32 " steps, %lu errors; valid: beta %lu, yaw-rate reference %lu, "
                "mu %lu; final mu %.3f (confidence %.2f)\n", st->samples, r->est_errors, r->est_valid[0],
                r->est_valid[1], r->est_valid[2], replay_real_to_si(r->est_out.mu, 0), replay_real_to_si(r->est_out.mu_conf, 0));
    }
}

/* The table's ids never seen, or always of the wrong length: a DBC/map that
 * does not fit the log. Returns -1 if no frame of the table was usable. */
int replay_check_match(const replay *r)
{
    uint32_t i;
    unsigned long usable = 0;
    for (i = 0; i < r->table->n_messages; i++) {
        const grip_can_message_t *m = &r->table->messages[i];
        if (r->msg_seen[i] == 0) {
            fprintf(r->msg, "grip-replay: warning: message %s (0x%03" PRIX32 ") of table %s never appeared\n",
                    m->name, m->id & GRIP_CAN_EFF_MASK, r->table->name);
        } else if (r->msg_dlc[i] == r->msg_seen[i]) {
            fprintf(r->msg, "grip-replay: warning: all %lu frames of %s (0x%03" PRIX32 ") had a length other "
                    "than the table's %u bytes: DBC for another car?\n", r->msg_seen[i], m->name,
                    m->id & GRIP_CAN_EFF_MASK, (unsigned)m->len);
        }
        usable += r->msg_seen[i] - r->msg_dlc[i];
    }
    if (r->frames_read > 0 && usable == 0) {
        fprintf(r->msg, "grip-replay: DBC/map mismatch: none of the %lu frames of %s has an id (and length) of "
                "table %s (", r->frames_read, r->source, r->table->name);
        for (i = 0; i < r->table->n_messages; i++) {
            fprintf(r->msg, "%s0x%03" PRIX32, i ? " " : "", r->table->messages[i].id & GRIP_CAN_EFF_MASK);
        }
        fprintf(r->msg, ")\n");
        return -1;
    }
    return 0;
}

/* ---- sources ------------------------------------------------------------------- */

static int run_file(replay *r)
{
    candump_reader rd;
    candump_order ord;
    grip_can_frame_t f;
    char ifname[CANDUMP_IFNAME_MAX];
    char err[700];
    int64_t tol = CANDUMP_BACK_TOLERANCE_US;
    int rc;
    if (r->opt->reorder_us > tol) {
        tol = r->opt->reorder_us;   /* the assembler places frames up to -w late */
    }
    if (candump_open(&rd, r->opt->log, err, sizeof err) != 0) {
        fprintf(r->msg, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (candump_order_init(&ord, tol, r->opt->sort_log ? CANDUMP_REORDER_WINDOW_US : 0, CANDUMP_REORDER_MAX_FRAMES,
                           err, sizeof err) != 0) {
        fprintf(r->msg, "grip-replay: %s\n", err);
        candump_close(&rd);
        return EXIT_INPUT;
    }
    rd.skip_bad = r->opt->skip_bad;
    while ((rc = candump_next_ordered(&rd, &ord, &f, ifname, err, sizeof err)) == 1) {
        f.t_us += r->opt->time_offset_us;
        replay_feed(r, &f, ifname);
        if (r->opt->max_frames && r->frames_read >= r->opt->max_frames) {
            break;
        }
    }
    r->out_of_order = ord.out_of_order;
    r->max_back_us = ord.max_back_us;
    r->back_tolerance_us = tol;
    if (rd.skipped > 0) {
        fprintf(r->msg, "grip-replay: %lu malformed lines skipped (--skip-bad)\n", rd.skipped);
    }
    candump_order_free(&ord);
    candump_close(&rd);
    if (rc < 0) {
        fprintf(r->msg, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (r->frames_read == 0) {
        fprintf(r->msg, "grip-replay: %s: no CAN frame in the log (%lu lines%s)\n", rd.path, rd.lineno,
                rd.skipped ? ", all skipped as malformed or blank" : ", none a frame");
        return EXIT_INPUT;
    }
    replay_finish(r);
    return 0;
}

/* ---- CSV input (--csv) ----------------------------------------------------------
 * One row per estimator step; docs/estimator.md "Using it" is the schema,
 * docs/guarantees.md what is refused. */

#define CSV_LINE_MAX 8192      /* bytes per line */
#define CSV_MAX_COLS 256       /* columns per line */
#define CSV_MAX_ERRORS 10      /* messages before giving up */
#define CSV_RATE_ROWS 16       /* time steps whose median is the input's sample interval */
#define CSV_RATE_TOL 0.01      /* that median, and the mean over the file, vs --step-ms */
#define CSV_GAP_TOL 0.5        /* any one time step vs --step-ms */

/* the inputs every file must have a column for (empty cells allowed) */
static const uint32_t CSV_REQUIRED[] = {
    GRIP_IN_WHEEL_SPEED_FL, GRIP_IN_WHEEL_SPEED_FR, GRIP_IN_WHEEL_SPEED_RL, GRIP_IN_WHEEL_SPEED_RR,
    GRIP_IN_STEER_ANGLE,    GRIP_IN_YAW_RATE,       GRIP_IN_AX,             GRIP_IN_AY,
};

enum { COL_IGNORED = -1, COL_TIME = -2 };

typedef struct {
    replay *r;
    const char *path;
    unsigned errors;
    char tname[8];   /* the time column's name */
} csv_ctx;

/* strcmp ignoring ASCII letter case */
static int strcasecmp_ascii(const char *a, const char *b)
{
    for (;; a++, b++) {
        int ca = (*a >= 'A' && *a <= 'Z') ? *a - 'A' + 'a' : *a;
        int cb = (*b >= 'A' && *b <= 'Z') ? *b - 'A' + 'a' : *b;
        if (ca != cb || ca == 0) {
            return ca - cb;
        }
    }
}

static void csv_error(csv_ctx *c, const char *fmt, ...)
{
    va_list ap;
    if (c->errors < CSV_MAX_ERRORS) {
        fprintf(c->r->msg, "grip-replay: ");
        va_start(ap, fmt);
        vfprintf(c->r->msg, fmt, ap);
        va_end(ap);
        fprintf(c->r->msg, "\n");
    }
    c->errors++;
}

/* Splits line (modified in place) at commas; returns the number of cells
 * (cells beyond max are counted, not stored). */
static int csv_cells(char *line, char **cell, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        char *c = strchr(p, ',');
        if (n < max) {
            cell[n] = p;
        }
        n++;
        if (c == NULL) {
            break;
        }
        *c = '\0';
        p = c + 1;
    }
    return n;
}

static char *trim(char *s)
{
    size_t n;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t')) {
        s[--n] = '\0';
    }
    return s;
}

/* A decimal number ([+-]digits[.digits][e[+-]digits]) or nan / inf /
 * infinity (any case, optional sign) as a double; 0 if s is anything else
 * (hex, words, trailing text). */
static int cell_number(const char *s, double *v)
{
    const char *p = s;
    int digits = 0;
    char *end;
    if (*p == '+' || *p == '-') {
        p++;
    }
    if (strcasecmp_ascii(p, "nan") == 0 || strcasecmp_ascii(p, "inf") == 0 ||
        strcasecmp_ascii(p, "infinity") == 0) {
        *v = (p[0] == 'n' || p[0] == 'N') ? NAN : (s[0] == '-' ? -INFINITY : INFINITY);
        return 1;
    }
    while (*p >= '0' && *p <= '9') {
        p++;
        digits++;
    }
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') {
            p++;
            digits++;
        }
    }
    if (digits == 0) {
        return 0;
    }
    if (*p == 'e' || *p == 'E') {
        int ed = 0;
        p++;
        if (*p == '+' || *p == '-') {
            p++;
        }
        while (*p >= '0' && *p <= '9') {
            p++;
            ed++;
        }
        if (ed == 0) {
            return 0;
        }
    }
    if (*p != '\0') {
        return 0;
    }
    errno = 0;
    *v = strtod(s, &end);   /* overflow -> +-inf (a range fault), underflow -> ~0 */
    return end == p;
}

/* The SI value v as the build's input format; 0 if not representable. */
static int to_input(double v, uint32_t input, grip_real_t *out)
{
#if GRIP_ARITH_FIXED
    double q = floor(v * (grip_input_is_ql(input) ? 256.0 : 65536.0) + 0.5);
    if (!(q >= -2147483647.0 && q <= 2147483647.0)) {
        return 0;
    }
    *out = (grip_real_t)q;
#else
    (void)input;
    if (!(fabs(v) <= 3.0e38)) {
        return 0;
    }
    *out = (grip_real_t)v;
#endif
    return 1;
}

/* The plausible range of each input in a CSV file (input_rules.h). */
typedef struct {
    double lo;
    double hi;
    const char *hint;
    double hint_max;
} input_rule;

/* indexed by input id; grip_tire.c builds its CHANNEL_RULES the same way */
#define INPUT_RULE(id, lo, hi, hint, hint_max) [id] = { lo, hi, hint, hint_max },
static const input_rule input_rules[GRIP_IN_COUNT] = { GRIP_INPUT_RULES(INPUT_RULE) };
#undef INPUT_RULE

/* 1 if name is in the comma-separated list. */
static int in_list(const char *list, const char *name)
{
    size_t n = strlen(name);
    const char *p = list;
    while (p != NULL && *p != '\0') {
        const char *c = strchr(p, ',');
        size_t len = (c != NULL) ? (size_t)(c - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0) {
            return 1;
        }
        p = (c != NULL) ? c + 1 : NULL;
    }
    return 0;
}

/* Column names the reader knows, for "did you mean". */
static int known_names(const char **names, int max)
{
    static char fault[GRIP_IN_COUNT][48];
    int n = 0;
    uint32_t i;
    names[n++] = "t_s";
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT && n + 2 < max; i++) {
        names[n++] = grip_input_name(i);
        snprintf(fault[i], sizeof fault[i], "%s_fault", grip_input_name(i));
        names[n++] = fault[i];
    }
    names[n++] = "step";
    names[n++] = "comment";
    return n;
}

/* Classifies the header's cells into col[]; reports every problem. */
static void csv_header(csv_ctx *c, char **cell, int ncol, unsigned long line, int *col, int *t_col)
{
    const char *known[2 * GRIP_IN_COUNT + 4];
    int nknown = known_names(known, (int)(sizeof known / sizeof known[0]));
    int have[GRIP_IN_COUNT];
    char missing[400];
    size_t k;
    int j;
    int i;
    *t_col = -1;
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        have[i] = 0;
    }
    for (j = 0; j < ncol; j++) {
        const char *name = cell[j] = trim(cell[j]);
        size_t len = strlen(name);
        int32_t id = (len > 0 && len <= 32) ? grip_input_find(name, (uint32_t)len) : -1;
        col[j] = COL_IGNORED;
        if (len == 0) {
            csv_error(c, "%s:%lu: column %d has no name", c->path, line, j + 1);
            continue;
        }
        if (name[0] == '"' || name[0] == '\'') {
            csv_error(c, "%s:%lu: column %d is quoted (%s): this reader takes no quoting, write the bare name",
                      c->path, line, j + 1, name);
            continue;
        }
        for (i = 0; i < j; i++) {
            if (strcmp(cell[i], name) == 0) {
                break;
            }
        }
        if (i < j) {
            csv_error(c, "%s:%lu: column '%s' appears twice (columns %d and %d)", c->path, line, name, i + 1, j + 1);
            continue;
        }
        if (strcmp(name, "t_s") == 0 || strcmp(name, "t") == 0 || strcmp(name, "time") == 0) {
            if (*t_col >= 0) {
                csv_error(c, "%s:%lu: two time columns: '%s' (column %d) and '%s' (column %d)", c->path, line,
                          cell[*t_col], *t_col + 1, name, j + 1);
                continue;
            }
            *t_col = j;
            col[j] = COL_TIME;
            snprintf(c->tname, sizeof c->tname, "%s", name);
        } else if (id >= 0) {
            col[j] = (int)id;
            have[id] = 1;
        } else if (strcmp(name, "step") == 0 || strcmp(name, "comment") == 0 ||
                   (c->r->opt->ignore_cols != NULL && in_list(c->r->opt->ignore_cols, name))) {
            col[j] = COL_IGNORED;
        } else if (len > 6 && strcmp(name + len - 6, "_fault") == 0 &&
                   grip_input_find(name, (uint32_t)(len - 6)) >= 0) {
            col[j] = COL_IGNORED;   /* grip-replay's own fault columns: the value cell says it */
        } else {
            int d = 0;
            int near = csv_nearest(name, known, nknown, &d);
            if (near >= 0 && d <= 1 + (int)strlen(known[near]) / 4) {
                csv_error(c, "%s:%lu: unknown column '%s' (column %d): did you mean '%s'? (--ignore-columns "
                          "%s to ignore it)", c->path, line, name, j + 1, known[near], name);
            } else {
                char list[600];
                size_t used = 0;
                for (i = 0; i < nknown && used < sizeof list; i++) {
                    used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? " " : "", known[i]);
                }
                csv_error(c, "%s:%lu: unknown column '%s' (column %d); known: %s (--ignore-columns %s to ignore "
                          "it)", c->path, line, name, j + 1, list, name);
            }
        }
    }
    if (*t_col < 0) {
        csv_error(c, "%s:%lu: no time column (t_s) in the header", c->path, line);
    }
    missing[0] = '\0';
    for (k = 0; k < sizeof CSV_REQUIRED / sizeof CSV_REQUIRED[0]; k++) {
        if (!have[CSV_REQUIRED[k]]) {
            size_t u = strlen(missing);
            snprintf(missing + u, sizeof missing - u, "%s%s", u ? ", " : "", grip_input_name(CSV_REQUIRED[k]));
        }
    }
    if (missing[0] != '\0') {
        csv_error(c, "%s:%lu: required column missing: %s (a signal you do not have: give its column with "
                  "empty cells)", c->path, line, missing);
    }
    if (c->r->opt->ignore_cols != NULL) {
        const char *p = c->r->opt->ignore_cols;
        while (p != NULL) {
            const char *e = strchr(p, ',');
            size_t len = (e != NULL) ? (size_t)(e - p) : strlen(p);
            for (j = 0; j < ncol; j++) {
                if (strlen(cell[j]) == len && strncmp(cell[j], p, len) == 0) {
                    break;
                }
            }
            if (j == ncol || len == 0) {
                csv_error(c, "%s:%lu: --ignore-columns names '%.*s', which is not a column of the header",
                          c->path, line, (int)len, p);
            }
            p = (e != NULL) ? e + 1 : NULL;
        }
    }
}

static double median(double *v, int n)
{
    int i;
    int j;
    for (i = 1; i < n; i++) {   /* insertion sort: n <= CSV_RATE_ROWS */
        double x = v[i];
        for (j = i; j > 0 && v[j - 1] > x; j--) {
            v[j] = v[j - 1];
        }
        v[j] = x;
    }
    return (n % 2) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The input's sample interval (median of its first time steps) against
 * the step; 0, or -1 after reporting. */
static int csv_rate_check(csv_ctx *c, const double *dts, int n, unsigned long first_line, unsigned long last_line)
{
    double tmp[CSV_RATE_ROWS];
    double m;
    double step = c->r->opt->step_ms * 1e-3;
    int i;
    if (n == 0) {
        return 0;
    }
    for (i = 0; i < n; i++) {
        tmp[i] = dts[i];
    }
    m = median(tmp, n);
    if (fabs(m - step) <= CSV_RATE_TOL * step) {
        return 0;
    }
    {
        char where[96];
        double hz = 1.0 / m;
        snprintf(where, sizeof where, "median of the %d time step%s of lines %lu..%lu", n, n > 1 ? "s" : "",
                 first_line, last_line);
        if (fabs(m * 1e-3 - step) <= CSV_RATE_TOL * step || fabs(m * 1e-6 - step) <= CSV_RATE_TOL * step) {
            csv_error(c, "%s: column %s: input sampled every %g s (%s), step is %g ms: is the time in %s? t_s is "
                      "in seconds", c->path, c->tname, m, where, c->r->opt->step_ms,
                      fabs(m * 1e-3 - step) <= CSV_RATE_TOL * step ? "milliseconds" : "microseconds");
        } else if (hz < 50.0 * (1.0 - 5e-4) || hz > 2000.0 * (1.0 + 5e-4)) {
            csv_error(c, "%s: column %s: input sampled every %g ms (%g Hz; %s), step is %g ms, and the estimator "
                      "runs at 50..2000 Hz: resample the input (e.g. to 100 Hz, --step-ms 10)", c->path, c->tname, m * 1e3,
                      hz, where, c->r->opt->step_ms);
        } else if (fabs(hz - floor(hz + 0.5)) <= EST_RATE_TOL * hz) {
            csv_error(c, "%s: column %s: input sampled every %g ms (%s), step is %g ms: pass --step-ms %g", c->path,
                      c->tname, m * 1e3, where, c->r->opt->step_ms, 1000.0 / floor(hz + 0.5));
        } else {
            csv_error(c, "%s: column %s: input sampled every %g ms (%.6g Hz; %s), step is %g ms, and the "
                      "estimator's rate is a whole number of Hz: resample the input (e.g. to 100 Hz, --step-ms 10)",
                      c->path, c->tname, m * 1e3, hz, where, c->r->opt->step_ms);
        }
    }
    return -1;
}

/* One time step (t0 at line l0 -> t1 at line l1) against the step: 0, or -1
 * after reporting. Counts steps off by more than 1 %. */
static int csv_step_check(csv_ctx *c, double t0, unsigned long l0, double t1, unsigned long l1)
{
    double step = c->r->opt->step_ms * 1e-3;
    double dt = t1 - t0;
    if (!(dt > 0.0)) {
        csv_error(c, "%s:%lu: column %s: time %.9g is not after %.9g (line %lu): the rows must be in time order, "
                  "one per step", c->path, l1, c->tname, t1, t0, l0);
        return -1;
    }
    if (fabs(dt - step) > CSV_GAP_TOL * step) {
        csv_error(c, "%s:%lu: column %s: time step %g ms from line %lu (%.9g -> %.9g), --step-ms is %g: a missing "
                  "row or a time jump (the rows must be one per step)", c->path, l1, c->tname, dt * 1e3, l0, t0, t1,
                  c->r->opt->step_ms);
        return -1;
    }
    if (fabs(dt - step) > 0.01 * step) {
        c->r->csv_bad_dt++;
    }
    return 0;
}

/* Parses one data row into *s; 0, or -1 after reporting. */
static int csv_row(csv_ctx *c, char **cell, int ncol, const int *col, int t_col, unsigned long line,
                   grip_input_sample_t *s, double *t)
{
    replay *r = c->r;
    int bad = 0;
    int k;
    (void)grip_input_sample_clear(s);
    *t = 0.0;
    if (t_col >= 0) {
        const char *tc = trim(cell[t_col]);
        if (!cell_number(tc, t) || !isfinite(*t) || fabs(*t) > 9.0e12) {
            csv_error(c, "%s:%lu: column %s: bad time '%s' (seconds, |t| <= 9e12)", c->path, line, c->tname, tc);
            bad = 1;
        }
    }
    s->t_us = (int64_t)floor(*t * 1e6 + 0.5);
    s->step = (uint32_t)r->csv_rows;
    for (k = 0; k < ncol; k++) {
        const char *cv;
        double v;
        uint32_t id;
        if (col[k] < 0) {
            continue;
        }
        id = (uint32_t)col[k];
        cv = trim(cell[k]);
        s->fault[id] = GRIP_SIG_MISSING;
        if (*cv == '\0') {
            continue;
        }
        if (!cell_number(cv, &v)) {
            csv_error(c, "%s:%lu: column %s: not a number '%s'", c->path, line, grip_input_name(id), cv);
            bad = 1;
            continue;
        }
        if (isnan(v)) {
            continue;
        }
        if (isfinite(v) && (v < input_rules[id].lo || v > input_rules[id].hi)) {
            const input_rule *q = &input_rules[id];
            if (!r->opt->no_unit_check) {
                csv_error(c, "%s:%lu: column %s: %g is outside [%g, %g] %s%s; --no-unit-check takes it as a "
                          "range fault", c->path, line, grip_input_name(id), v, q->lo, q->hi, grip_input_unit(id),
                          fabs(v) <= q->hint_max ? q->hint : "");
                bad = 1;
            }
            s->value[id] = 0;
            s->fault[id] = GRIP_SIG_RANGE;
            continue;
        }
        if (!isfinite(v) || !to_input(v, id, &s->value[id])) {
            s->value[id] = 0;
            s->fault[id] = GRIP_SIG_RANGE;
            continue;
        }
        s->valid[id] = 1;
        s->fault[id] = GRIP_SIG_OK;
    }
    return bad ? -1 : 0;
}

static void csv_count(replay *r, const grip_input_sample_t *s)
{
    uint32_t i;
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        r->csv_valid[i] += s->valid[i] != 0u;
        r->csv_range[i] += s->fault[i] == (uint8_t)GRIP_SIG_RANGE;
    }
    r->csv_rows++;
}

/* Emits a row (the header first, once). */
static int csv_emit(replay *r, grip_input_sample_t *s)
{
    if (!r->header_done) {
        if (replay_write_header(r) != 0) {
            return -1;
        }
        r->header_done = 1;
    }
    s->step = (uint32_t)r->csv_rows;
    csv_count(r, s);
    emit(r, s);
    return 0;
}

/* The rows held until the sample interval is known: checks it, then each
 * held time step, then emits them if no error was found. 1 if the rate
 * matches, 0 if not (reported). */
static int csv_release(csv_ctx *c, grip_input_sample_t *held, const double *held_t, const unsigned long *held_line,
                       int nheld)
{
    double dts[CSV_RATE_ROWS];
    int k;
    for (k = 1; k < nheld; k++) {
        dts[k - 1] = held_t[k] - held_t[k - 1];
    }
    if (nheld >= 2 && csv_rate_check(c, dts, nheld - 1, held_line[0], held_line[nheld - 1]) != 0) {
        return 0;
    }
    for (k = 1; k < nheld; k++) {
        (void)csv_step_check(c, held_t[k - 1], held_line[k - 1], held_t[k], held_line[k]);
    }
    for (k = 0; k < nheld && c->errors == 0; k++) {
        if (csv_emit(c->r, &held[k]) != 0) {
            return -1;
        }
    }
    return 1;
}

static int run_csv(replay *r)
{
    static char line[CSV_LINE_MAX + 1];
    static grip_input_sample_t held[CSV_RATE_ROWS + 1];   /* rows held until the rate is checked */
    double held_t[CSV_RATE_ROWS + 1];
    unsigned long held_line[CSV_RATE_ROWS + 1];
    int nheld = 0;
    int rate = 0;   /* 0: rows held, 1: the rate matches, -1: it does not (reported) */
    char *cell[CSV_MAX_COLS];
    int col[CSV_MAX_COLS];
    int ncol = 0;
    int have_header = 0;
    int t_col = -1;
    unsigned long header_line = 0;
    double t_prev = 0.0;
    double t_first = 0.0;
    unsigned long l_prev = 0;
    unsigned long l_first = 0;
    unsigned long nrows = 0;
    char err[700];
    csv_reader rd;
    csv_ctx c;
    int rc = 0;
    int k;
    if (csv_reader_open(&rd, r->opt->csv_in, line, CSV_LINE_MAX, 1, err, sizeof err) != 0) {
        fprintf(r->msg, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    c.r = r;
    c.path = rd.path;
    c.errors = 0;
    snprintf(c.tname, sizeof c.tname, "t_s");
    while (c.errors < CSV_MAX_ERRORS && (rc = csv_read_line(&rd, err, sizeof err)) == 1) {
        grip_input_sample_t s;
        double t;
        int nc;
        if (line[0] == '#' || line[strspn(line, " \t")] == '\0') {
            continue;
        }
        nc = csv_cells(line, cell, CSV_MAX_COLS);
        if (nc > CSV_MAX_COLS) {
            csv_error(&c, "%s:%lu: %d columns, more than %d", c.path, rd.lineno, nc, CSV_MAX_COLS);
            break;
        }
        if (!have_header) {
            ncol = nc;
            header_line = rd.lineno;
            csv_header(&c, cell, nc, rd.lineno, col, &t_col);
            have_header = 1;
            for (k = 0; k < GRIP_IN_COUNT; k++) {
                r->write_input[k] = r->opt->all_inputs;
            }
            for (k = 0; k < ncol; k++) {
                if (col[k] >= 0) {
                    r->write_input[col[k]] = 1;
                }
            }
            continue;
        }
        if (nc != ncol) {
            csv_error(&c, "%s:%lu: %d cells, the header has %d (line %lu)", c.path, rd.lineno, nc, ncol, header_line);
            continue;
        }
        if (csv_row(&c, cell, ncol, col, t_col, rd.lineno, &s, &t) != 0 || t_col < 0) {
            continue;
        }
        if (nrows > 0) {
            if (!(t > t_prev)) {
                (void)csv_step_check(&c, t_prev, l_prev, t, rd.lineno);   /* reports the order */
                continue;
            }
            if (rate == 1) {
                (void)csv_step_check(&c, t_prev, l_prev, t, rd.lineno);
            }
        } else {
            t_first = t;
            l_first = rd.lineno;
        }
        nrows++;
        t_prev = t;
        l_prev = rd.lineno;
        if (rate == 0) {
            held[nheld] = s;
            held_t[nheld] = t;
            held_line[nheld] = rd.lineno;
            if (++nheld == CSV_RATE_ROWS + 1) {
                rate = csv_release(&c, held, held_t, held_line, nheld);
                if (rate < 0) {
                    csv_reader_close(&rd);
                    return EXIT_OUTPUT;
                }
                rate = rate ? 1 : -1;
            }
        } else if (c.errors == 0 && csv_emit(r, &s) != 0) {
            csv_reader_close(&rd);
            return EXIT_OUTPUT;
        }
    }
    csv_reader_close(&rd);
    if (c.errors >= CSV_MAX_ERRORS) {
        fprintf(r->msg, "grip-replay: %s: stopped after %d errors\n", c.path, CSV_MAX_ERRORS);
        return EXIT_INPUT;
    }
    if (rc < 0) {
        fprintf(r->msg, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (!have_header) {
        if (c.errors == 0) {
            fprintf(r->msg, "grip-replay: %s: no header row (%lu lines)\n", c.path, rd.lineno);
        }
        return EXIT_INPUT;
    }
    if (rate == 0 && nheld > 0) {   /* a file of CSV_RATE_ROWS steps or fewer */
        if (csv_release(&c, held, held_t, held_line, nheld) < 0) {
            return EXIT_OUTPUT;
        }
    }
    if (c.errors == 0 && nrows == 0) {
        csv_error(&c, "%s:%lu: no data row after the header", c.path, header_line);
    }
    if (c.errors == 0 && nrows > CSV_RATE_ROWS + 1) {
        double step = r->opt->step_ms * 1e-3;
        double mean = (t_prev - t_first) / (double)(nrows - 1);
        if (fabs(mean - step) > CSV_RATE_TOL * step) {
            csv_error(&c, "%s: column %s: the %lu rows of lines %lu..%lu span %.9g s: a mean time step of %g ms, "
                      "step is %g ms (more than 1 %% off)", c.path, c.tname, nrows, l_first, l_prev, t_prev - t_first,
                      mean * 1e3, r->opt->step_ms);
        }
    }
    return c.errors ? EXIT_INPUT : 0;
}

static void summary_csv(const replay *r)
{
    uint32_t i;
    fprintf(r->msg, "grip-replay: %s (CSV input), step %g ms: %lu rows, %lu with a time step off by > 1 %%\n",
            r->opt->csv_in, r->opt->step_ms, r->csv_rows, r->csv_bad_dt);
    fprintf(r->msg, "  %-18s %8s %8s %8s\n", "input", "valid", "missing", "range");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        if (r->write_input[i]) {
            fprintf(r->msg, "  %-18s %8lu %8lu %8lu\n", grip_input_name(i), r->csv_valid[i],
                    r->csv_rows - r->csv_valid[i] - r->csv_range[i], r->csv_range[i]);
        }
    }
    fprintf(r->msg, "  estimator      %lu steps, %lu errors; valid: beta %lu, yaw-rate reference %lu, "
            "mu %lu; final mu %.3f (confidence %.2f), yaw-rate bias %.5f rad/s\n", r->csv_rows, r->est_errors,
            r->est_valid[0], r->est_valid[1], r->est_valid[2], replay_real_to_si(r->est_out.mu, 0),
            replay_real_to_si(r->est_out.mu_conf, 0), replay_real_to_si(r->est_out.yaw_rate_bias, 0));
}

/* ---- setup ---------------------------------------------------------------------- */

/* ---- the learned blob (--learned-in, --learned-out) ---------------------------- */

/* Restores a grip_est_learned_t blob: exactly its size, and accepted by
 * grip_est_learned_set (this car, tire and arithmetic build, intact). */
static int learned_read(replay *r, const char *path)
{
    grip_est_learned_t blob;
    FILE *f = fopen(path, "rb");
    size_t n;
    int extra;
    if (f == NULL) {
        fprintf(r->msg, "grip-replay: %s: cannot open the learned blob (--learned-in)\n", path);
        return -1;
    }
    n = fread(&blob, 1, sizeof blob, f);
    extra = fgetc(f);
    (void)fclose(f);
    if (n != sizeof blob || extra != EOF) {
        fprintf(r->msg, "grip-replay: %s: a learned blob (--learned-in) is %u bytes, this file has %s%u\n", path,
                (unsigned)sizeof blob, extra != EOF ? "more than " : "", (unsigned)n);
        return -1;
    }
    if (grip_est_learned_set(&r->est, &blob) != GRIP_OK) {
        fprintf(r->msg, "grip-replay: %s: not a learned blob of this car, tire and arithmetic build, or corrupt "
                "(magic, version, configuration fingerprint, ranges or checksum; grip_est_learned_set)\n", path);
        return -1;
    }
    return 0;
}

/* Writes what the estimator learned (grip_est_learned_get) to path */
static int learned_write(replay *r, const char *path)
{
    grip_est_learned_t blob;
    FILE *f;
    if (grip_est_learned_get(&r->est, &blob) != GRIP_OK) {
        fprintf(r->msg, "grip-replay: %s: no learned blob to write (--learned-out)\n", path);
        return -1;
    }
    f = fopen(path, "wb");
    if (f == NULL || fwrite(&blob, 1, sizeof blob, f) != sizeof blob) {
        if (f != NULL) {
            (void)fclose(f);
        }
        fprintf(r->msg, "grip-replay: %s: cannot write the learned blob (--learned-out)\n", path);
        return -1;
    }
    if (fclose(f) != 0) {
        fprintf(r->msg, "grip-replay: %s: cannot write the learned blob (--learned-out)\n", path);
        return -1;
    }
    return 0;
}

/* The tire(s), the vehicle and the estimator (-e); 0 or the exit status. */
static int replay_setup_estimator(replay *r)
{
    const replay_options *o = r->opt;
    grip_status_t st;
    if (o->est_tir != NULL) {
        char err[512];
        grip_est_config_t ecfg;
        double hz = 1000.0 / o->step_ms;
        int rate_hz = (int)(hz + 0.5);
        /* grip_est_config_t.rate_hz: a whole number of Hz in [EST_RATE_MIN,
         * EST_RATE_MAX]; the step must give it within EST_RATE_TOL, or the
         * estimator would integrate with another time step than the data's */
        if (hz < EST_RATE_MIN * (1.0 - EST_RATE_TOL) || hz > EST_RATE_MAX * (1.0 + EST_RATE_TOL)) {
            fprintf(r->msg, "grip-replay: --step-ms %g is %g Hz; the estimator runs at %d..%d Hz (step %g..%g ms): "
                    "resample the input to a rate in that range\n", o->step_ms, hz, EST_RATE_MIN, EST_RATE_MAX,
                    1000.0 / EST_RATE_MAX, 1000.0 / EST_RATE_MIN);
            return EXIT_USAGE;
        }
        if (fabs(hz - rate_hz) > EST_RATE_TOL * hz) {
            fprintf(r->msg, "grip-replay: --step-ms %g is %.6g Hz; the estimator's rate is a whole number of Hz "
                    "(%d would integrate %.3g %% off): use a step of 1000/N ms, e.g. 2, 2.5, 4, 5 or 10\n",
                    o->step_ms, hz, rate_hz, 100.0 * fabs(hz - rate_hz) / hz);
            return EXIT_USAGE;
        }
        {
            /* bounded (4 MiB, 4096-byte lines: /dev/zero and a 1 GiB file end
             * at once) and validated; warnings name the file, line and key */
            grip_tir_options to;
            grip_tir_options_init(&to);
            to.flags = o->tir_flags;
            to.warn = print_tir_warning;
            to.warn_ctx = r->msg;
            if (grip_tir_read_opts(o->est_tir, &to, &r->tire, err, sizeof err) != 0) {
                fprintf(r->msg, "grip-replay: %s\n", err);
                return EXIT_USAGE;
            }
        }
        if (vehicle_preset(o->vehicle, &r->tire, rate_hz, &ecfg) != 0) {
            fprintf(r->msg, "grip-replay: unknown --vehicle '%s' (rav4, av21, generic)\n", o->vehicle);
            return EXIT_USAGE;
        }
        if (o->est_tir_rear != NULL) {
            grip_tir_options to;
            grip_tir_options_init(&to);
            to.flags = o->tir_flags;
            to.warn = print_tir_warning;
            to.warn_ctx = r->msg;
            if (grip_tir_read_opts(o->est_tir_rear, &to, &r->tire_rear, err, sizeof err) != 0) {
                fprintf(r->msg, "grip-replay: %s\n", err);
                return EXIT_USAGE;
            }
            ecfg.tire[1].kind = GRIP_EST_TIRE_MF;
            ecfg.tire[1].model.mf = &r->tire_rear;
        }
        if (o->vehicle_file != NULL) {
            static char rear_path[1024];
            unsigned long rear_line = 0;
            if (vehicle_file_read(o->vehicle_file, &ecfg, rear_path, sizeof rear_path, &rear_line, r->msg) != 0) {
                return EXIT_USAGE;
            }
            if (rear_line != 0) {
                grip_tir_options to;
                if (o->est_tir_rear != NULL) {
                    fprintf(r->msg, "grip-replay: %s:%lu: rear_tire: the rear tire is also given by --estimate-rear\n",
                            o->vehicle_file, rear_line);
                    return EXIT_USAGE;
                }
                grip_tir_options_init(&to);
                to.flags = o->tir_flags;
                to.warn = print_tir_warning;
            to.warn_ctx = r->msg;
                if (grip_tir_read_opts(rear_path, &to, &r->tire_rear, err, sizeof err) != 0) {
                    fprintf(r->msg, "grip-replay: %s:%lu: rear_tire: %s\n", o->vehicle_file, rear_line, err);
                    return EXIT_USAGE;
                }
                ecfg.tire[1].kind = GRIP_EST_TIRE_MF;
                ecfg.tire[1].model.mf = &r->tire_rear;
            }
        }
        r->mass_si = replay_real_to_si(ecfg.mass, 1);
        {
            grip_check_detail_t d;
            char what[96];
            st = grip_est_init_detail(&r->est, &ecfg, &d);
            if (st != GRIP_OK) {
                if (d.part[0] != '\0') {
                    snprintf(what, sizeof what, "%s[%d] (%s axle).%s", d.part, (int)d.index,
                             d.index == 0 ? "front" : "rear", d.field);
                } else {
                    snprintf(what, sizeof what, "%s", d.field[0] ? d.field : "-");
                }
                fprintf(r->msg, "grip-replay: the estimator rejects the vehicle (%s%s%s) with tire %s at %d Hz: "
                        "%s must be %s (%s; grip_est_init's ranges: include/grip/grip_est.h)\n",
                        o->vehicle ? o->vehicle : "rav4", o->vehicle_file ? " + " : "",
                        o->vehicle_file ? o->vehicle_file : "", o->est_tir, rate_hz, what, d.rule, grip_status_str(st));
                return EXIT_USAGE;
            }
        }
        if (o->learned_in != NULL && learned_read(r, o->learned_in) != 0) {
            return EXIT_INPUT;
        }
        r->est_on = 1;
    }
    return 0;
}

int replay_setup(replay *r)
{
    const replay_options *o = r->opt;
    grip_can_asm_config_t cfg;
    grip_status_t st;
    uint32_t i;

    if (o->csv_in != NULL) {
        /* no CAN: inputs straight from the file */
    } else if (load_table(o->table_path, &r->table, r->msg) != 0) {
        return EXIT_TABLE;
    }
    if (o->csv_in != NULL) {
        return replay_setup_estimator(r);
    }
    cfg.step_us = (uint32_t)(o->step_ms * 1000.0 + 0.5);
    cfg.stale_periods = (uint32_t)o->stale;
    cfg.reorder_us = (uint32_t)o->reorder_us;
    cfg.jump_us = (uint32_t)(o->jump_ms * 1000.0 + 0.5);
    st = grip_can_asm_init(&r->a, r->table, &cfg);
    if (st != GRIP_OK) {
        fprintf(r->msg, "grip-replay: bad timing settings for table %s: need step > 0, jump >= step and "
                "<= %u steps, reorder < every message period and < jump (%s)\n", r->table->name,
                GRIP_CAN_MAX_GAP_STEPS, grip_status_str(st));
        return EXIT_USAGE;
    }
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        r->write_input[i] = o->all_inputs || r->a.input_msg[i] != UINT32_MAX;
    }
    return replay_setup_estimator(r);
}

int replay_run(replay *r)
{
    const replay_options *o = r->opt;
    int status;
    if (o->csv_in != NULL) {
        status = run_csv(r);   /* writes the header once it knows the columns */
        if (!o->quiet && status == 0) {   /* on an error, its message is the last word */
            summary_csv(r);
        }
        if (status == 0 && r->est_on && o->learned_out != NULL && learned_write(r, o->learned_out) != 0) {
            status = EXIT_OUTPUT;
        }
        return status;
    }
    if (!r->header_done) {
        if (replay_write_header(r) != 0) {
            return EXIT_OUTPUT;
        }
        r->header_done = 1;
    }
    status = run_file(r);
    if (!o->quiet && status == 0) {
        replay_summary(r, NULL);
    }
    if (status == 0 && replay_check_match(r) != 0) {
        status = EXIT_TABLE;
    }
    if (status == 0 && r->est_on && o->learned_out != NULL && learned_write(r, o->learned_out) != 0) {
        status = EXIT_OUTPUT;
    }
    return status;
}
