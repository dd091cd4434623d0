/* LDFLAGS: -lsocketcan */
/*
 * grip_replay.c - `grip-replay`: CAN frames -> decoded, time-aligned
 * estimator input samples, one CSV row per estimator step.
 *
 *   grip-replay [options] LOG            a candump -l log ("-" = stdin)
 *   grip-replay [options] -i IFACE       a live SocketCAN interface
 *   grip-replay -e TIR [options] --csv FILE   estimator inputs from a CSV file
 *
 * Frames go through the sample assembler of lib/can (grip_can.h): signal
 * table lookup, DLC / checksum / counter / range checks, staleness, and
 * alignment to the estimator's fixed step. Each sample is handed to the
 * estimator hook (grip_replay_estimator_step, below) and written as a CSV
 * row; a summary with frame, decode-error, stale-signal and drop counts
 * goes to stderr. docs/can.md is the manual (options, CSV columns, exit
 * codes). In --csv mode each row of the file is one estimator step
 * (docs/estimator.md, "CSV input"), the CAN path is not used, and the output
 * has the same columns as in CAN mode.
 */
#include <errno.h>
#include <stddef.h>
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "grip/grip_can.h"
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "candump.h"
#include "can_socket.h"
#include "tir_reader.h"

#define EXIT_USAGE 2    /* bad command line */
#define EXIT_TABLE 3    /* signal table unreadable, or it does not match the log (DBC/map mismatch) */
#define EXIT_INPUT 4    /* log unreadable or malformed, interface missing, socket error */
#define EXIT_OUTPUT 5   /* CSV or dump could not be written */

#define RECV_TIMEOUT_MS 50

typedef struct {
    const char *log;
    const char *iface;
    const char *table_path;
    const char *out;
    const char *dump;
    double step_ms;
    double jump_ms;
    double duration_s;
    double idle_exit_s;
    long stale;
    long reorder_us;
    long long time_offset_us;
    unsigned long max_frames;
    const char *est_tir;       /* --estimate: tire of both axles; NULL = inputs only */
    const char *vehicle;       /* --vehicle: configuration preset */
    const char *vehicle_file;  /* --vehicle-file: key = value overrides of the preset */
    const char *csv_in;        /* --csv: estimator inputs from a CSV file instead of CAN */
    int step_given;            /* --step-ms was given */
    int skip_bad;
    int all_inputs;
    int quiet;
    int want_fd;
} options;

typedef struct {
    const options *opt;
    const grip_can_table_t *table;
    grip_can_asm_t a;
    FILE *csv;
    FILE *dump;
    const char *source;
    int write_input[GRIP_IN_COUNT];
    unsigned long frames_read;
    unsigned long rows;
    int64_t first_t;
    int64_t last_t;
    int have_t;
    unsigned long msg_seen[GRIP_CAN_MAX_MESSAGES];
    unsigned long msg_dlc[GRIP_CAN_MAX_MESSAGES];
    int write_failed;
    /* the estimator, when --estimate is given */
    int est_on;
    grip_mf_params tire;
    grip_est_t est;
    grip_est_output_t est_out;
    grip_status_t est_status;
    unsigned long est_errors;
    unsigned long est_valid[3];   /* steps with beta, yaw_rate_ref, mu valid */
    double mass_si;               /* vehicle mass [kg] (model lateral acceleration column) */
    /* --csv mode */
    unsigned long csv_rows;
    unsigned long csv_bad_dt;     /* rows whose time step differs from --step-ms by > 1 % */
    unsigned long csv_valid[GRIP_IN_COUNT];
    unsigned long csv_range[GRIP_IN_COUNT];
} replay;

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

/* ---- estimator ----------------------------------------------------------
 * Vehicle presets for --vehicle.
 * rav4: Toyota RAV4 (XA40, 2013-2018) as the bundled comma2k19 drive; mass
 *   with driver and load, wheelbase and steering ratio as openpilot
 *   configures this car; CG split, height, yaw inertia, track and roll
 *   values are typical-SUV assumptions (docs/estimator.md).
 * av21: Dallara AV-21 (Indy Autonomous Challenge) as in the deep-dynamics
 *   logs: mass 790 kg, lf 1.248 m, lr 1.7328 m from that repository's
 *   vehicle file; steering ratio 1 because its logs carry the ROAD-WHEEL
 *   angle (fed as the steering input); yaw inertia 1000 kg m^2 (the
 *   repository identifies 500-2000), track 1.6 m, CG height 0.30 m, roll
 *   split 0.5 and roll gradient 0.001 rad per m/s^2 are race-car
 *   assumptions (docs/estimator.md); steering lag 0.28 s identified from the
 *   log (the logged angle is the steering command: est-eval's steer-lag fit).
 * generic: grip_est_config_default (the simulator's passenger car).
 * --vehicle-file then overrides single values (key = value, SI units). */
static grip_real_t si_qs(double x)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)floor(x * 65536.0 + 0.5);
#else
    return (grip_real_t)x;
#endif
}

static grip_real_t si_ql(double x)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)floor(x * 256.0 + 0.5);
#else
    return (grip_real_t)x;
#endif
}

static double real_to_si(grip_real_t v, int ql)
{
#if GRIP_ARITH_FIXED
    return (double)v / (ql ? 256.0 : 65536.0);
#else
    (void)ql;
    return (double)v;
#endif
}

static int vehicle_config(const char *name, const grip_mf_params *tire, int rate_hz, grip_est_config_t *cfg)
{
    if (grip_est_config_default(cfg, tire) != GRIP_OK) {
        return -1;
    }
    cfg->rate_hz = (uint32_t)rate_hz;
    if (name == NULL || strcmp(name, "rav4") == 0) {
        cfg->mass = si_ql(1640.0);
        cfg->iz = si_ql(2900.0);
        cfg->lf = si_qs(1.06);
        cfg->lr = si_qs(1.59);
        cfg->track_f = si_qs(1.57);
        cfg->track_r = si_qs(1.57);
        cfg->h_cg = si_qs(0.66);
        cfg->steer_ratio = si_qs(16.88);
        cfg->wheel_radius = si_qs(0.355);
        return 0;
    }
    if (strcmp(name, "av21") == 0) {
        cfg->mass = si_ql(790.0);
        cfg->iz = si_ql(1000.0);
        cfg->lf = si_qs(1.248);
        cfg->lr = si_qs(1.7328);
        cfg->track_f = si_qs(1.6);
        cfg->track_r = si_qs(1.6);
        cfg->h_cg = si_qs(0.30);
        cfg->steer_ratio = si_qs(1.0);
        cfg->wheel_radius = si_qs(0.30);
        cfg->roll_split_front = si_qs(0.5);
        cfg->roll_gradient = si_qs(0.001);
        cfg->steer_lag = si_qs(0.28);
        return 0;
    }
    return (strcmp(name, "generic") == 0) ? 0 : -1;
}

/* Reads a vehicle file: lines `key = value` (SI units), '#' comments, blank
 * lines. Keys: mass, iz, lf, lr, track (both), track_f, track_r, h_cg,
 * steer_ratio, wheel_radius, roll_split_front, roll_gradient, speed_ref_mu,
 * cla, aero_front, air_density, cda, crr, tan_bank, tan_grade, latency, steer_lag,
 * steer_latency.
 * The estimator's init checks the ranges. */
static int vehicle_file(const char *path, grip_est_config_t *cfg)
{
    /* one row per key: where it goes and in which format; "track" sets
     * both tracks */
    enum { VK_QS, VK_QL, VK_FLAG, VK_TRACK };
    static const struct {
        const char *key;
        size_t off;
        int kind;
    } keys[] = {
        { "mass", offsetof(grip_est_config_t, mass), VK_QL },
        { "iz", offsetof(grip_est_config_t, iz), VK_QL },
        { "lf", offsetof(grip_est_config_t, lf), VK_QS },
        { "lr", offsetof(grip_est_config_t, lr), VK_QS },
        { "track", 0, VK_TRACK },
        { "track_f", offsetof(grip_est_config_t, track_f), VK_QS },
        { "track_r", offsetof(grip_est_config_t, track_r), VK_QS },
        { "h_cg", offsetof(grip_est_config_t, h_cg), VK_QS },
        { "steer_ratio", offsetof(grip_est_config_t, steer_ratio), VK_QS },
        { "wheel_radius", offsetof(grip_est_config_t, wheel_radius), VK_QS },
        { "roll_split_front", offsetof(grip_est_config_t, roll_split_front), VK_QS },
        { "roll_gradient", offsetof(grip_est_config_t, roll_gradient), VK_QS },
        { "speed_ref_mu", offsetof(grip_est_config_t, speed_ref_mu), VK_FLAG },
        { "cla", offsetof(grip_est_config_t, cla), VK_QS },
        { "aero_front", offsetof(grip_est_config_t, aero_front), VK_QS },
        { "air_density", offsetof(grip_est_config_t, air_density), VK_QS },
        { "cda", offsetof(grip_est_config_t, cda), VK_QS },
        { "crr", offsetof(grip_est_config_t, crr), VK_QS },
        { "tan_bank", offsetof(grip_est_config_t, tan_bank), VK_QS },
        { "tan_grade", offsetof(grip_est_config_t, tan_grade), VK_QS },
        { "latency", offsetof(grip_est_config_t, latency), VK_QS },
        { "steer_lag", offsetof(grip_est_config_t, steer_lag), VK_QS },
        { "steer_latency", offsetof(grip_est_config_t, steer_latency), VK_QS },
    };
    const size_t nkeys = sizeof keys / sizeof keys[0];
    char line[512];
    unsigned long lineno = 0;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "grip-replay: cannot open vehicle file %s: %s\n", path, strerror(errno));
        return -1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char key[64];
        char *p = line;
        char *eq;
        char *end;
        size_t n;
        size_t k;
        double v;
        lineno++;
        if ((eq = strchr(line, '#')) != NULL) {
            *eq = '\0';
        }
        while (*p == ' ' || *p == '\t') {
            p++;
        }
        if (*p == '\0' || *p == '\n' || *p == '\r') {
            continue;
        }
        eq = strchr(p, '=');
        if (eq == NULL) {
            fprintf(stderr, "grip-replay: %s:%lu: expected key = value\n", path, lineno);
            fclose(f);
            return -1;
        }
        n = (size_t)(eq - p);
        while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\t')) {
            n--;
        }
        if (n == 0 || n >= sizeof key) {
            fprintf(stderr, "grip-replay: %s:%lu: bad key\n", path, lineno);
            fclose(f);
            return -1;
        }
        memcpy(key, p, n);
        key[n] = '\0';
        errno = 0;
        v = strtod(eq + 1, &end);
        while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n') {
            end++;
        }
        if (errno != 0 || end == eq + 1 || *end != '\0' || !isfinite(v) || fabs(v) > 1e6) {
            fprintf(stderr, "grip-replay: %s:%lu: %s: not a number\n", path, lineno, key);
            fclose(f);
            return -1;
        }
        for (k = 0; k < nkeys; k++) {
            if (strcmp(key, keys[k].key) == 0) {
                break;
            }
        }
        if (k == nkeys) {
            fprintf(stderr, "grip-replay: %s:%lu: unknown key '%s' (", path, lineno, key);
            for (k = 0; k < nkeys; k++) {
                fprintf(stderr, "%s%s", k ? " " : "", keys[k].key);
            }
            fprintf(stderr, ")\n");
            fclose(f);
            return -1;
        }
        switch (keys[k].kind) {
        case VK_QL:
            *(grip_real_t *)((char *)cfg + keys[k].off) = si_ql(v);
            break;
        case VK_QS:
            *(grip_real_t *)((char *)cfg + keys[k].off) = si_qs(v);
            break;
        case VK_TRACK:
            cfg->track_f = si_qs(v);
            cfg->track_r = si_qs(v);
            break;
        default:
            if (v != 0.0 && v != 1.0) {
                fprintf(stderr, "grip-replay: %s:%lu: %s must be 0 or 1\n", path, lineno, keys[k].key);
                fclose(f);
                return -1;
            }
            *(uint32_t *)((char *)cfg + keys[k].off) = (uint32_t)v;
            break;
        }
    }
    fclose(f);
    return 0;
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

static void usage(FILE *f)
{
    fprintf(f,
            "usage: grip-replay [options] LOG        replay a candump -l log ('-' = stdin)\n"
            "       grip-replay [options] -i IFACE   read a live SocketCAN interface\n"
            "       grip-replay -e TIR [options] --csv FILE   estimator inputs from a CSV file\n"
            "options:\n"
            "  -t, --table FILE       signal table, text form from `grip_tools can-table --text`\n"
            "                         (default: built-in table rav4)\n"
            "  -o, --output FILE      CSV of the input samples (default: standard output)\n"
            "  -s, --step-ms MS       estimator step (default 10)\n"
            "  -k, --stale N          a value older than N periods is stale (default 3)\n"
            "  -w, --reorder-us US    accept frames up to US late (default 0; < every period)\n"
            "  -j, --jump-ms MS       a time gap beyond MS restarts the step grid (default 1000)\n"
            "      --time-offset-us N add N us to every frame time (file replay)\n"
            "      --skip-bad         skip malformed log lines (counted) instead of stopping\n"
            "      --all-inputs       write every input, also those the table does not feed\n"
            "      --dump FILE        write every frame read as a candump -l log\n"
            "  -i, --interface IFACE  live: read this CAN interface\n"
            "      --fd               live: accept CAN FD frames too\n"
            "  -d, --duration S       live: stop after S seconds\n"
            "  -n, --frames N         stop after N frames\n"
            "      --idle-exit S      live: stop once no frame came for S seconds (after the first)\n"
            "  -e, --estimate TIR     run the estimator each step (tire .tir on both axles) and\n"
            "                         append its outputs to every row\n"
            "      --vehicle NAME     estimator vehicle: rav4 (default), av21 or generic\n"
            "      --vehicle-file F   override vehicle values: lines `key = value` (SI): mass iz lf lr\n"
            "                         track track_f track_r h_cg steer_ratio wheel_radius\n"
            "                         roll_split_front roll_gradient speed_ref_mu (0/1) cla aero_front\n"
            "                         air_density cda crr tan_bank tan_grade latency steer_lag\n"
            "                         steer_latency [s]\n"
            "      --csv FILE         estimator inputs from FILE ('-' = stdin) instead of CAN: one row per\n"
            "                         estimator step (every --step-ms), '#' lines skipped, a header row\n"
            "                         naming the columns: t_s [s], wheel_speed_fl wheel_speed_fr\n"
            "                         wheel_speed_rl wheel_speed_rr [m/s], steer_angle [rad, steering\n"
            "                         wheel], yaw_rate [rad/s], ax ay [m/s^2], optional vehicle_speed\n"
            "                         [m/s], brake_pressure_fl.. [Pa], brake_torque_fl.. [N m]; ISO axes\n"
            "                         (left positive). An empty or NaN cell = not valid in that step;\n"
            "                         other columns are ignored. Needs -e.\n"
            "  -q, --quiet            no summary\n"
            "exit: 0 ok, 2 usage, 3 table / DBC-map mismatch, 4 input, 5 output\n");
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

static int parse_args(int argc, char **argv, options *o)
{
    int i;
    memset(o, 0, sizeof *o);
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
            usage(stdout);
            exit(0);
        } else if (IS("-q", "--quiet")) {
            o->quiet = 1;
            takes = 0;
        } else if (strcmp(a, "--skip-bad") == 0) {
            o->skip_bad = 1;
            takes = 0;
        } else if (strcmp(a, "--all-inputs") == 0) {
            o->all_inputs = 1;
            takes = 0;
        } else if (strcmp(a, "--fd") == 0) {
            o->want_fd = 1;
            takes = 0;
        } else if (a[0] == '-' && a[1] != '\0' && v == NULL) {
            fprintf(stderr, "grip-replay: option %s needs a value\n", a);
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
        } else if (strcmp(a, "--vehicle") == 0) {
            o->vehicle = v;
        } else if (strcmp(a, "--vehicle-file") == 0) {
            o->vehicle_file = v;
        } else if (strcmp(a, "--csv") == 0) {
            o->csv_in = v;
        } else if (IS("-s", "--step-ms")) {
            if (!parse_double(v, 0.001, 1000.0, &o->step_ms)) {
                fprintf(stderr, "grip-replay: --step-ms must be 0.001..1000, not '%s'\n", v);
                return -1;
            }
            o->step_given = 1;
        } else if (IS("-j", "--jump-ms")) {
            if (!parse_double(v, 0.001, 100000.0, &o->jump_ms)) {
                fprintf(stderr, "grip-replay: --jump-ms must be 0.001..100000, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-k", "--stale")) {
            if (!parse_long(v, 1, 1000, &n)) {
                fprintf(stderr, "grip-replay: --stale must be 1..1000, not '%s'\n", v);
                return -1;
            }
            o->stale = (long)n;
        } else if (IS("-w", "--reorder-us")) {
            if (!parse_long(v, 0, 10000000, &n)) {
                fprintf(stderr, "grip-replay: --reorder-us must be 0..10000000, not '%s'\n", v);
                return -1;
            }
            o->reorder_us = (long)n;
        } else if (strcmp(a, "--time-offset-us") == 0) {
            if (!parse_long(v, -4000000000000000000LL, 4000000000000000000LL, &o->time_offset_us)) {
                fprintf(stderr, "grip-replay: --time-offset-us must be an integer, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-d", "--duration")) {
            if (!parse_double(v, 0.0, 1e9, &o->duration_s)) {
                fprintf(stderr, "grip-replay: --duration must be >= 0 seconds, not '%s'\n", v);
                return -1;
            }
        } else if (strcmp(a, "--idle-exit") == 0) {
            if (!parse_double(v, 0.0, 1e9, &o->idle_exit_s)) {
                fprintf(stderr, "grip-replay: --idle-exit must be >= 0 seconds, not '%s'\n", v);
                return -1;
            }
        } else if (IS("-n", "--frames")) {
            if (!parse_long(v, 1, 4000000000000LL, &n)) {
                fprintf(stderr, "grip-replay: --frames must be >= 1, not '%s'\n", v);
                return -1;
            }
            o->max_frames = (unsigned long)n;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "grip-replay: unknown option %s (try --help)\n", a);
            return -1;
        } else {
            if (o->log != NULL) {
                fprintf(stderr, "grip-replay: more than one log file given\n");
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
            fprintf(stderr, "grip-replay: --csv replaces the CAN log / interface: give only one source\n");
            return -1;
        }
        if (o->est_tir == NULL) {
            fprintf(stderr, "grip-replay: --csv needs the estimator (-e TIR)\n");
            return -1;
        }
        return 0;
    }
    if ((o->log == NULL) == (o->iface == NULL)) {
        fprintf(stderr, "grip-replay: give either a log file or -i IFACE (try --help)\n");
        return -1;
    }
    return 0;
}

/* ---- signal table ------------------------------------------------------------ */

static grip_can_table_text_t text_table;

static int load_table(const char *path, const grip_can_table_t **table)
{
    char line[GRIP_CAN_TEXT_LINE_MAX + 2];
    unsigned long lineno = 0;
    const char *why = "";
    FILE *f;
    if (path == NULL) {
        *table = &grip_can_table_rav4;
        return 0;
    }
    f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "grip-replay: cannot open signal table %s: %s\n", path, strerror(errno));
        return -1;
    }
    grip_can_table_text_init(&text_table);
    while (fgets(line, sizeof line, f) != NULL) {
        size_t n = strlen(line);
        lineno++;
        if (n > 0 && line[n - 1] != '\n' && !feof(f)) {
            fprintf(stderr, "grip-replay: %s:%lu: line too long\n", path, lineno);
            fclose(f);
            return -1;
        }
        if (grip_can_table_text_line(&text_table, line, (uint32_t)n, &why) != GRIP_OK) {
            fprintf(stderr, "grip-replay: %s:%lu: %s\n", path, lineno, why);
            fclose(f);
            return -1;
        }
    }
    if (ferror(f)) {
        fprintf(stderr, "grip-replay: cannot read signal table %s: %s\n", path, strerror(errno));
        fclose(f);
        return -1;
    }
    fclose(f);
    if (grip_can_table_text_finish(&text_table, table, &why) != GRIP_OK) {
        fprintf(stderr, "grip-replay: %s: %s\n", path, why);
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
    snprintf(buf, n, "%.9g", (double)v);
#endif
}

static void format_time(char *buf, size_t n, int64_t t_us)
{
    int64_t sec = (t_us >= 0) ? t_us / 1000000 : -((-t_us + 999999) / 1000000);
    snprintf(buf, n, "%" PRId64 ".%06" PRId64, sec, t_us - sec * 1000000);
}

static void write_header(replay *r)
{
    uint32_t i;
    fprintf(r->csv, "t_s,step");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        if (r->write_input[i]) {
            fprintf(r->csv, ",%s,%s_fault", grip_input_name(i), grip_input_name(i));
        }
    }
    if (r->est_on) {
        fprintf(r->csv, ",est_status,est_valid,est_flags,vx,beta,yaw_rate,yaw_rate_ref,delta,mu,mu_conf,"
                        "fy_front,fy_rear,util_front,util_rear,fy_margin_front,yaw_rate_bias,ay_model");
    }
    fprintf(r->csv, "\n");
}

static void emit(replay *r, const grip_input_sample_t *s)
{
    char t[32];
    char v[40];
    uint32_t i;
    grip_replay_estimator_step(r, s);
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
        /* the tire model's lateral acceleration sum Fy / m (body frame: the
         * front wheels' forces turned by the road-wheel angle), the
         * quantity the estimator's ay measurement update predicts */
        double d = real_to_si(e->delta, 0);
        double fyb = 0.0;
        for (i = 0; i < 4u; i++) {
            double fx = real_to_si(e->fx[i], 1);
            double fy = real_to_si(e->fy[i], 1);
            fyb += (i < 2u) ? fx * sin(d) + fy * cos(d) : fy;
        }
        fprintf(r->csv, ",%d,%" PRIu32 ",%" PRIu32 ",%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g",
                (int)r->est_status, e->valid, e->flags, real_to_si(e->vx, 0), real_to_si(e->beta, 0),
                real_to_si(e->yaw_rate, 0), real_to_si(e->yaw_rate_ref, 0), real_to_si(e->delta, 0),
                real_to_si(e->mu, 0), real_to_si(e->mu_conf, 0), real_to_si(e->fy_axle[0], 1),
                real_to_si(e->fy_axle[1], 1), real_to_si(e->util_axle[0], 0), real_to_si(e->util_axle[1], 0),
                real_to_si(e->fy_margin_front, 1));
        fprintf(r->csv, ",%.6g,", real_to_si(e->yaw_rate_bias, 0));
        if ((e->valid & GRIP_EST_V_AXLE) != 0u && r->mass_si > 0.0) {
            fprintf(r->csv, "%.6g", fyb / r->mass_si);
        }
    }
    if (fprintf(r->csv, "\n") < 0) {
        r->write_failed = 1;
    }
    r->rows++;
}

/* Emits every step due before time now. */
static void drain(replay *r, int64_t now)
{
    grip_input_sample_t s;
    while (grip_can_asm_poll(&r->a, now, &s)) {
        emit(r, &s);
    }
}

static void feed(replay *r, const grip_can_frame_t *f, const char *ifname)
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
    drain(r, f->t_us);
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
static void finish(replay *r)
{
    if (r->have_t && r->a.started) {
        int64_t newest = r->a.newest_t_us > r->last_t ? r->a.newest_t_us : r->last_t;
        drain(r, newest + (int64_t)r->opt->reorder_us + 1);
    }
}

/* ---- summary ------------------------------------------------------------------- */

static void summary(const replay *r, const can_sock *sock)
{
    const grip_can_stats_t *st = &r->a.stats;
    char t0[32];
    char t1[32];
    uint32_t i;
    uint32_t decode_errors = st->dlc_errors + st->checksum_errors + st->counter_frozen + st->range_errors +
                             st->qualifier_faults;
    format_time(t0, sizeof t0, r->first_t);
    format_time(t1, sizeof t1, r->last_t);
    fprintf(stderr, "grip-replay: %s, table %s (%u messages, %u signals), step %g ms, stale after %ld periods\n",
            r->source, r->table->name, (unsigned)r->table->n_messages, (unsigned)r->table->n_signals,
            r->opt->step_ms, r->opt->stale);
    fprintf(stderr, "  frames         %lu read (%s .. %s s), %" PRIu32 " decoded, %" PRIu32 " other ids, "
            "%" PRIu32 " error frames, %" PRIu32 " remote requests\n",
            r->frames_read, r->have_t ? t0 : "-", r->have_t ? t1 : "-", st->decoded, st->unknown_id,
            st->error_frames, st->rtr_frames);
    fprintf(stderr, "  decode errors  %" PRIu32 " (dlc %" PRIu32 ", checksum %" PRIu32 ", counter frozen %" PRIu32
            ", out of range %" PRIu32 ", sender fault %" PRIu32 "), counter skips %" PRIu32 "\n",
            decode_errors, st->dlc_errors, st->checksum_errors, st->counter_frozen, st->range_errors,
            st->qualifier_faults, st->counter_skips);
    fprintf(stderr, "  timing         %" PRIu32 " reordered, %" PRIu32 " late, %" PRIu32 " too old, %" PRIu32
            " timestamp jumps\n", st->reordered, st->late, st->too_old, st->jumps);
    fprintf(stderr, "  samples        %" PRIu32 " steps written\n", st->samples);
    fprintf(stderr, "  %-18s %8s %8s %8s %8s %8s\n", "input", "valid", "stale", "missing", "range", "fault");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        const uint32_t *c = st->input_faults[i];
        if (!r->write_input[i]) {
            continue;
        }
        fprintf(stderr, "  %-18s %8" PRIu32 " %8" PRIu32 " %8" PRIu32 " %8" PRIu32 " %8" PRIu32 "\n",
                grip_input_name(i), c[GRIP_SIG_OK], c[GRIP_SIG_STALE], c[GRIP_SIG_MISSING], c[GRIP_SIG_RANGE],
                c[GRIP_SIG_FAULT]);
    }
    if (sock != NULL) {
        fprintf(stderr, "  socket         %" PRIu32 " drops (kernel queue overflow), %" PRIu32 " bus-off, %" PRIu32
                " controller errors, %" PRIu32 " truncated reads, %" PRIu32 " interface-down, %" PRIu32
                " without kernel timestamp\n", sock->drops, sock->bus_off, sock->controller_errors, sock->truncated,
                sock->down, sock->no_timestamp);
    } else {
        fprintf(stderr, "  drops          0 (file replay)\n");
    }
    if (r->est_on) {
        fprintf(stderr, "  estimator      %" PRIu32 " steps, %lu errors; valid: beta %lu, yaw-rate reference %lu, "
                "mu %lu; final mu %.3f (confidence %.2f)\n", st->samples, r->est_errors, r->est_valid[0],
                r->est_valid[1], r->est_valid[2], real_to_si(r->est_out.mu, 0), real_to_si(r->est_out.mu_conf, 0));
    }
}

/* The table's ids never seen, or always of the wrong length: a DBC/map that
 * does not fit the log. Returns -1 if no frame of the table was usable. */
static int check_match(const replay *r)
{
    uint32_t i;
    unsigned long usable = 0;
    for (i = 0; i < r->table->n_messages; i++) {
        const grip_can_message_t *m = &r->table->messages[i];
        if (r->msg_seen[i] == 0) {
            fprintf(stderr, "grip-replay: warning: message %s (0x%03" PRIX32 ") of table %s never appeared\n",
                    m->name, m->id & GRIP_CAN_EFF_MASK, r->table->name);
        } else if (r->msg_dlc[i] == r->msg_seen[i]) {
            fprintf(stderr, "grip-replay: warning: all %lu frames of %s (0x%03" PRIX32 ") had a length other "
                    "than the table's %u bytes: DBC for another car?\n", r->msg_seen[i], m->name,
                    m->id & GRIP_CAN_EFF_MASK, (unsigned)m->len);
        }
        usable += r->msg_seen[i] - r->msg_dlc[i];
    }
    if (r->frames_read > 0 && usable == 0) {
        fprintf(stderr, "grip-replay: DBC/map mismatch: none of the %lu frames of %s has an id (and length) of "
                "table %s (", r->frames_read, r->source, r->table->name);
        for (i = 0; i < r->table->n_messages; i++) {
            fprintf(stderr, "%s0x%03" PRIX32, i ? " " : "", r->table->messages[i].id & GRIP_CAN_EFF_MASK);
        }
        fprintf(stderr, ")\n");
        return -1;
    }
    return 0;
}

/* ---- sources ------------------------------------------------------------------- */

static int run_file(replay *r)
{
    candump_reader rd;
    grip_can_frame_t f;
    char ifname[CANDUMP_IFNAME_MAX];
    char err[700];
    int rc;
    if (candump_open(&rd, r->opt->log, err, sizeof err) != 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    rd.skip_bad = r->opt->skip_bad;
    while ((rc = candump_next(&rd, &f, ifname, err, sizeof err)) == 1) {
        f.t_us += r->opt->time_offset_us;
        feed(r, &f, ifname);
        if (r->opt->max_frames && r->frames_read >= r->opt->max_frames) {
            break;
        }
    }
    if (rd.skipped > 0) {
        fprintf(stderr, "grip-replay: %lu malformed lines skipped (--skip-bad)\n", rd.skipped);
    }
    candump_close(&rd);
    finish(r);
    if (rc < 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    return 0;
}

/* ---- CSV input (--csv) ----------------------------------------------------------
 * One row per estimator step; docs/estimator.md "CSV input" is the schema. */

#define CSV_LINE_MAX 8192
#define CSV_MAX_COLS 256

/* Splits line (modified in place) at commas; returns the number of cells. */
static int csv_split(char *line, char **cell, int max)
{
    int n = 0;
    char *p = line;
    size_t len = strlen(line);
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
        line[--len] = '\0';
    }
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

static int run_csv(replay *r)
{
    static char line[CSV_LINE_MAX + 2];
    char *cell[CSV_MAX_COLS];
    int col_input[CSV_MAX_COLS];   /* input id of each column, -1 ignored, -2 time */
    int ncol = 0;
    int have_header = 0;
    int t_col = -1;
    unsigned long lineno = 0;
    double t_prev = 0.0;
    const double step_s = r->opt->step_ms * 1e-3;
    FILE *f = stdin;
    int status = 0;
    int k;
    if (strcmp(r->opt->csv_in, "-") != 0) {
        f = fopen(r->opt->csv_in, "r");
        if (f == NULL) {
            fprintf(stderr, "grip-replay: cannot open %s: %s\n", r->opt->csv_in, strerror(errno));
            return EXIT_INPUT;
        }
    }
    while (fgets(line, sizeof line, f) != NULL) {
        size_t n = strlen(line);
        int nc;
        lineno++;
        if (n > 0 && line[n - 1] != '\n' && !feof(f)) {
            fprintf(stderr, "grip-replay: %s:%lu: line longer than %d characters\n", r->opt->csv_in, lineno,
                    CSV_LINE_MAX);
            status = EXIT_INPUT;
            break;
        }
        if (line[0] == '#' || line[strspn(line, " \t\r\n")] == '\0') {
            continue;
        }
        nc = csv_split(line, cell, CSV_MAX_COLS);
        if (nc > CSV_MAX_COLS) {
            fprintf(stderr, "grip-replay: %s:%lu: more than %d columns\n", r->opt->csv_in, lineno, CSV_MAX_COLS);
            status = EXIT_INPUT;
            break;
        }
        if (!have_header) {
            uint32_t seen[GRIP_IN_COUNT];
            memset(seen, 0, sizeof seen);
            ncol = nc;
            for (k = 0; k < nc; k++) {
                const char *name = trim(cell[k]);
                int32_t id = grip_input_find(name, (uint32_t)(strlen(name) < 32 ? strlen(name) : 32));
                col_input[k] = -1;
                if (strcmp(name, "t_s") == 0 || strcmp(name, "t") == 0 || strcmp(name, "time") == 0) {
                    if (t_col >= 0) {
                        fprintf(stderr, "grip-replay: %s:%lu: two time columns\n", r->opt->csv_in, lineno);
                        status = EXIT_INPUT;
                    }
                    t_col = k;
                    col_input[k] = -2;
                } else if (id >= 0 && strlen(name) <= 32) {
                    if (seen[id]++) {
                        fprintf(stderr, "grip-replay: %s:%lu: column %s twice\n", r->opt->csv_in, lineno, name);
                        status = EXIT_INPUT;
                    }
                    col_input[k] = (int)id;
                    r->write_input[id] = 1;
                }
            }
            if (t_col < 0) {
                fprintf(stderr, "grip-replay: %s:%lu: no time column (t_s) in the header\n", r->opt->csv_in,
                        lineno);
                status = EXIT_INPUT;
            }
            if (status != 0) {
                break;
            }
            if (r->opt->all_inputs) {
                for (k = 0; k < GRIP_IN_COUNT; k++) {
                    r->write_input[k] = 1;
                }
            }
            write_header(r);
            have_header = 1;
            continue;
        }
        {
            grip_input_sample_t s;
            double t;
            char *end;
            if (nc != ncol) {
                fprintf(stderr, "grip-replay: %s:%lu: %d cells, the header has %d\n", r->opt->csv_in, lineno,
                        nc, ncol);
                status = EXIT_INPUT;
                break;
            }
            (void)grip_input_sample_clear(&s);
            errno = 0;
            t = strtod(trim(cell[t_col]), &end);
            if (errno != 0 || end == cell[t_col] || *end != '\0' || !isfinite(t) || fabs(t) > 9.0e12) {
                fprintf(stderr, "grip-replay: %s:%lu: bad time '%s'\n", r->opt->csv_in, lineno, cell[t_col]);
                status = EXIT_INPUT;
                break;
            }
            if (r->csv_rows > 0 && fabs((t - t_prev) - step_s) > 0.01 * step_s) {
                r->csv_bad_dt++;
            }
            t_prev = t;
            s.t_us = (int64_t)floor(t * 1e6 + 0.5);
            s.step = (uint32_t)r->csv_rows;
            for (k = 0; k < ncol; k++) {
                const char *c;
                double v;
                uint32_t id;
                if (col_input[k] < 0) {
                    continue;
                }
                id = (uint32_t)col_input[k];
                c = trim(cell[k]);
                s.fault[id] = GRIP_SIG_MISSING;
                if (*c == '\0') {
                    continue;
                }
                errno = 0;
                v = strtod(c, &end);
                if (end == c || *end != '\0') {
                    fprintf(stderr, "grip-replay: %s:%lu: column %s: not a number '%s'\n", r->opt->csv_in, lineno,
                            grip_input_name(id), c);
                    status = EXIT_INPUT;
                    break;
                }
                if (isnan(v)) {
                    continue;
                }
                if (!isfinite(v) || !to_input(v, id, &s.value[id])) {
                    s.value[id] = 0;
                    s.fault[id] = GRIP_SIG_RANGE;
                    r->csv_range[id]++;
                    continue;
                }
                s.valid[id] = 1;
                s.fault[id] = GRIP_SIG_OK;
                r->csv_valid[id]++;
            }
            if (status != 0) {
                break;
            }
            r->csv_rows++;
            emit(r, &s);
        }
    }
    if (status == 0 && ferror(f)) {
        fprintf(stderr, "grip-replay: cannot read %s: %s\n", r->opt->csv_in, strerror(errno));
        status = EXIT_INPUT;
    }
    if (status == 0 && !have_header) {
        fprintf(stderr, "grip-replay: %s: no header row\n", r->opt->csv_in);
        status = EXIT_INPUT;
    }
    if (f != stdin) {
        fclose(f);
    }
    return status;
}

static void summary_csv(const replay *r)
{
    uint32_t i;
    fprintf(stderr, "grip-replay: %s (CSV input), step %g ms: %lu rows, %lu with a time step off by > 1 %%\n",
            r->opt->csv_in, r->opt->step_ms, r->csv_rows, r->csv_bad_dt);
    fprintf(stderr, "  %-18s %8s %8s %8s\n", "input", "valid", "missing", "range");
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        if (r->write_input[i]) {
            fprintf(stderr, "  %-18s %8lu %8lu %8lu\n", grip_input_name(i), r->csv_valid[i],
                    r->csv_rows - r->csv_valid[i] - r->csv_range[i], r->csv_range[i]);
        }
    }
    fprintf(stderr, "  estimator      %lu steps, %lu errors; valid: beta %lu, yaw-rate reference %lu, "
            "mu %lu; final mu %.3f (confidence %.2f), yaw-rate bias %.5f rad/s\n", r->csv_rows, r->est_errors,
            r->est_valid[0], r->est_valid[1], r->est_valid[2], real_to_si(r->est_out.mu, 0),
            real_to_si(r->est_out.mu_conf, 0), real_to_si(r->est_out.yaw_rate_bias, 0));
}

static double mono_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int64_t realtime_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static can_sock sock;

static int run_live(replay *r)
{
    uint32_t ids[GRIP_CAN_MAX_MESSAGES];
    char err[300];
    char state[32];
    uint32_t bitrate = 0;
    uint32_t i;
    struct sigaction sa;
    double t_start;
    double t_last_frame = 0.0;
    unsigned long bad_reported = 0;
    int down_reported = 0;
    int status = 0;

    for (i = 0; i < r->table->n_messages; i++) {
        ids[i] = r->table->messages[i].id;
    }
    if (can_sock_open(&sock, r->opt->iface, ids, r->table->n_messages, r->opt->want_fd, RECV_TIMEOUT_MS,
                      err, sizeof err) != 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    can_sock_state(r->opt->iface, state, sizeof state, &bitrate);
    if (!r->opt->quiet) {
        char rate[32];
        if (bitrate) {
            snprintf(rate, sizeof rate, "%" PRIu32 " bit/s", bitrate);
        } else {
            snprintf(rate, sizeof rate, "unknown");
        }
        fprintf(stderr, "grip-replay: listening on %s (state %s, bit rate %s), %u ids%s\n", r->opt->iface, state,
                rate, (unsigned)r->table->n_messages, sock.fd_frames ? ", CAN FD on" : "");
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;   /* no SA_RESTART: a signal interrupts recvmsg */
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    t_start = mono_s();
    while (!stop_requested) {
        grip_can_frame_t f;
        double now = mono_s();
        int rc;
        if (r->opt->duration_s > 0.0 && now - t_start >= r->opt->duration_s) {
            break;
        }
        if (r->opt->idle_exit_s > 0.0 && r->frames_read > 0 && now - t_last_frame >= r->opt->idle_exit_s) {
            break;
        }
        rc = can_sock_read(&sock, &f, err, sizeof err);
        if (rc == CAN_SOCK_FRAME) {
            t_last_frame = mono_s();
            down_reported = 0;
            if ((f.id & GRIP_CAN_ID_ERR) != 0u && (f.id & 0x40u) != 0u) {   /* CAN_ERR_BUSOFF */
                char e2[300];
                fprintf(stderr, "grip-replay: %s is bus-off; restarting the controller\n", r->opt->iface);
                if (can_sock_restart(r->opt->iface, e2, sizeof e2) != 0) {
                    fprintf(stderr, "grip-replay: %s\n", e2);
                }
            }
            feed(r, &f, r->opt->iface);
            if (r->opt->max_frames && r->frames_read >= r->opt->max_frames) {
                break;
            }
        } else if (rc == CAN_SOCK_TIMEOUT) {
            /* Silence: every frame stamped before now - timeout has been
             * read, so the steps up to then can be emitted (stale values). */
            if (r->a.started) {
                drain(r, realtime_us() - RECV_TIMEOUT_MS * 1000);
            }
        } else if (rc == CAN_SOCK_INTR) {
            continue;
        } else if (rc == CAN_SOCK_DOWN) {
            struct timespec pause = { 0, 100000000L };
            if (!down_reported) {
                can_sock_state(r->opt->iface, state, sizeof state, &bitrate);
                fprintf(stderr, "grip-replay: %s (state %s); waiting for it to come back\n", err, state);
                down_reported = 1;
            }
            nanosleep(&pause, NULL);
        } else if (rc == CAN_SOCK_BAD) {
            if (bad_reported++ < 10) {
                fprintf(stderr, "grip-replay: %s (frame skipped)\n", err);
            }
        } else {
            fprintf(stderr, "grip-replay: %s\n", err);
            status = EXIT_INPUT;
            break;
        }
    }
    finish(r);
    can_sock_close(&sock);
    return status;
}

int main(int argc, char **argv)
{
    static replay r;
    options o;
    grip_can_asm_config_t cfg;
    grip_status_t st;
    int status;
    uint32_t i;

    if (parse_args(argc, argv, &o) != 0) {
        return EXIT_USAGE;
    }
    memset(&r, 0, sizeof r);
    r.opt = &o;
    if (o.csv_in != NULL) {
        /* no CAN: inputs straight from the file */
    } else if (load_table(o.table_path, &r.table) != 0) {
        return EXIT_TABLE;
    }
    if (o.csv_in != NULL) {
        goto estimator;
    }
    cfg.step_us = (uint32_t)(o.step_ms * 1000.0 + 0.5);
    cfg.stale_periods = (uint32_t)o.stale;
    cfg.reorder_us = (uint32_t)o.reorder_us;
    cfg.jump_us = (uint32_t)(o.jump_ms * 1000.0 + 0.5);
    st = grip_can_asm_init(&r.a, r.table, &cfg);
    if (st != GRIP_OK) {
        fprintf(stderr, "grip-replay: bad timing settings for table %s: need step > 0, jump >= step and "
                "<= %u steps, reorder < every message period and < jump (%s)\n", r.table->name,
                GRIP_CAN_MAX_GAP_STEPS, grip_status_str(st));
        return EXIT_USAGE;
    }
    for (i = 0; i < (uint32_t)GRIP_IN_COUNT; i++) {
        r.write_input[i] = o.all_inputs || r.a.input_msg[i] != UINT32_MAX;
    }
estimator:
    if (o.est_tir != NULL) {
        char err[512];
        grip_est_config_t ecfg;
        int rate_hz = (int)(1000.0 / o.step_ms + 0.5);
        if (grip_tir_read(o.est_tir, &r.tire, err, sizeof err) != 0) {
            fprintf(stderr, "grip-replay: %s\n", err);
            return EXIT_USAGE;
        }
        if (vehicle_config(o.vehicle, &r.tire, rate_hz, &ecfg) != 0) {
            fprintf(stderr, "grip-replay: unknown --vehicle '%s' (rav4, av21, generic)\n", o.vehicle);
            return EXIT_USAGE;
        }
        if (o.vehicle_file != NULL && vehicle_file(o.vehicle_file, &ecfg) != 0) {
            return EXIT_USAGE;
        }
        r.mass_si = real_to_si(ecfg.mass, 1);
        st = grip_est_init(&r.est, &ecfg);
        if (st != GRIP_OK) {
            fprintf(stderr, "grip-replay: the estimator rejects this configuration (step %g ms = %d Hz, "
                    "tire %s): %s\n", o.step_ms, rate_hz, o.est_tir, grip_status_str(st));
            return EXIT_USAGE;
        }
        r.est_on = 1;
    }
    r.source = o.csv_in ? o.csv_in : o.iface ? o.iface : o.log;
    r.csv = stdout;
    if (o.out != NULL && strcmp(o.out, "-") != 0) {
        r.csv = fopen(o.out, "w");
        if (r.csv == NULL) {
            fprintf(stderr, "grip-replay: cannot write %s: %s\n", o.out, strerror(errno));
            return EXIT_OUTPUT;
        }
    }
    if (o.dump != NULL) {
        r.dump = fopen(o.dump, "w");
        if (r.dump == NULL) {
            fprintf(stderr, "grip-replay: cannot write %s: %s\n", o.dump, strerror(errno));
            return EXIT_OUTPUT;
        }
    }
    if (o.csv_in != NULL) {
        status = run_csv(&r);   /* writes the header once it knows the columns */
        if (!o.quiet) {
            summary_csv(&r);
        }
        goto done;
    }
    write_header(&r);
    status = o.iface ? run_live(&r) : run_file(&r);
    if (!o.quiet) {
        summary(&r, o.iface ? &sock : NULL);
    }
    if (status == 0 && check_match(&r) != 0) {
        status = EXIT_TABLE;
    }
done:
    if (r.dump != NULL && fclose(r.dump) != 0) {
        r.write_failed = 1;
    }
    if (fflush(r.csv) != 0 || ferror(r.csv) || (r.csv != stdout && fclose(r.csv) != 0)) {
        r.write_failed = 1;
    }
    if (r.write_failed) {
        fprintf(stderr, "grip-replay: writing the output failed: %s\n", strerror(errno));
        return status ? status : EXIT_OUTPUT;
    }
    return status;
}
