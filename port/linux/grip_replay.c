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
 * (docs/estimator.md, "Using it"), the CAN path is not used, and the output
 * has the same columns as in CAN mode.
 */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>

#include "grip/grip_can.h"
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "candump.h"
#include "can_socket.h"
#include "csv.h"
#include "input_rules.h"
#include "tir_reader.h"

#define EXIT_USAGE 2    /* bad command line */
#define EXIT_TABLE 3    /* signal table unreadable, or it does not match the log (DBC/map mismatch) */
#define EXIT_INPUT 4    /* log unreadable or malformed, interface missing, socket error */
#define EXIT_OUTPUT 5   /* CSV or dump could not be written */

#define RECV_TIMEOUT_MS 50

/* the estimator's step rate (grip_est_config_t.rate_hz, checked by
 * grip_est_init): whole Hz in [50, 2000]; 1000 / --step-ms must be one
 * within EST_RATE_TOL */
#define EST_RATE_MIN 50
#define EST_RATE_MAX 2000
#define EST_RATE_TOL 5e-4

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
    const char *est_tir_rear;  /* --estimate-rear: the rear axle's tire instead; NULL = as front */
    const char *vehicle;       /* --vehicle: configuration preset */
    const char *vehicle_file;  /* --vehicle-file: key = value overrides of the preset */
    const char *csv_in;        /* --csv: estimator inputs from a CSV file instead of CAN */
    const char *ignore_cols;   /* --ignore-columns: comma-separated CSV columns to ignore */
    int step_given;            /* --step-ms was given */
    int sort_log;              /* --reorder: sort the log within CANDUMP_REORDER_WINDOW_US */
    int units;                 /* --units: unit suffixes in the output header */
    int skip_bad;
    int all_inputs;
    int no_unit_check;         /* --no-unit-check: a CSV value outside input_rules.h is a range fault */
    int quiet;
    int want_fd;
    unsigned tir_flags;        /* --strict, --no-range-check: GRIP_TIR_* of the .tir reader */
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
    int header_done;              /* --csv: the header is written with the first row */
    /* the estimator, when --estimate is given */
    int est_on;
    grip_mf_params tire;
    grip_mf_params tire_rear;  /* --estimate-rear: the rear axle's tire */
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
    /* log order (file replay) */
    unsigned long out_of_order;   /* frames older than one before them, within the tolerance or sorted */
    int64_t max_back_us;
    int64_t back_tolerance_us;
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
 * steer_ratio, wheel_radius, roll_split_front, roll_gradient, speed_ref_mu, bank_est,
 * cla, aero_front, air_density, cda, crr, tan_bank, tan_grade, latency, steer_lag,
 * steer_latency, tire_tol, kin_acc_sd, beta_sd_max; rear_tire = PATH (the rear
 * axle's .tir, relative to the vehicle file's folder; not with --estimate-rear).
 * The estimator's init checks the ranges. */
#define VEHICLE_LINE_MAX 511

static int vehicle_file(const char *path, grip_est_config_t *cfg, char *rear_tire, size_t rear_n,
                        unsigned long *rear_line)
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
        { "bank_est", offsetof(grip_est_config_t, bank_est), VK_FLAG },
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
        { "tire_tol", offsetof(grip_est_config_t, tire_tol), VK_QS },
        { "kin_acc_sd", offsetof(grip_est_config_t, kin_acc_sd), VK_QS },
        { "beta_sd_max", offsetof(grip_est_config_t, beta_sd_max), VK_QS },
    };
    const size_t nkeys = sizeof keys / sizeof keys[0];
    static char line[VEHICLE_LINE_MAX + 1];
    char err[700];
    unsigned long lineno = 0;
    csv_reader rd;
    csv_reader *f = &rd;
    unsigned long seen[sizeof keys / sizeof keys[0]];
    int rc;
    memset(seen, 0, sizeof seen);
    if (csv_reader_open(&rd, path, line, VEHICLE_LINE_MAX, 0, err, sizeof err) != 0) {
        fprintf(stderr, "grip-replay: vehicle file: %s\n", err);
        return -1;
    }
    while ((rc = csv_read_line(&rd, err, sizeof err)) == 1) {
        char key[64];
        char *p = line;
        char *eq;
        char *end;
        size_t n;
        size_t k;
        double v;
        lineno = rd.lineno;
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
            csv_reader_close(f);
            return -1;
        }
        n = (size_t)(eq - p);
        while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\t')) {
            n--;
        }
        if (n == 0 || n >= sizeof key) {
            fprintf(stderr, "grip-replay: %s:%lu: bad key\n", path, lineno);
            csv_reader_close(f);
            return -1;
        }
        memcpy(key, p, n);
        key[n] = '\0';
        if (strcmp(key, "rear_tire") == 0) {
            /* a path, not a number: the rear axle's .tir, relative to the
             * vehicle file's folder unless absolute */
            const char *v0 = eq + 1;
            const char *slash = strrchr(path, '/');
            size_t vn, dn;
            while (*v0 == ' ' || *v0 == '\t') {
                v0++;
            }
            dn = (slash != NULL && v0[0] != '/') ? (size_t)(slash - path) + 1u : 0u;
            vn = strlen(v0);
            while (vn > 0 && (v0[vn - 1] == ' ' || v0[vn - 1] == '\t' || v0[vn - 1] == '\r' || v0[vn - 1] == '\n')) {
                vn--;
            }
            if (*rear_line != 0) {
                fprintf(stderr, "grip-replay: %s:%lu: key 'rear_tire' given twice (first on line %lu)\n", path,
                        lineno, *rear_line);
                csv_reader_close(f);
                return -1;
            }
            if (vn == 0 || dn + vn >= rear_n) {
                fprintf(stderr, "grip-replay: %s:%lu: rear_tire: %s\n", path, lineno,
                        vn == 0 ? "empty (a .tir file path)" : "path too long");
                csv_reader_close(f);
                return -1;
            }
            memcpy(rear_tire, path, dn);
            memcpy(rear_tire + dn, v0, vn);
            rear_tire[dn + vn] = '\0';
            *rear_line = lineno;
            continue;
        }
        errno = 0;
        v = strtod(eq + 1, &end);
        while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n') {
            end++;
        }
        if (errno != 0 || end == eq + 1 || *end != '\0' || !isfinite(v) || fabs(v) > 1e6) {
            fprintf(stderr, "grip-replay: %s:%lu: %s: not a number\n", path, lineno, key);
            csv_reader_close(f);
            return -1;
        }
        for (k = 0; k < nkeys; k++) {
            if (strcmp(key, keys[k].key) == 0) {
                break;
            }
        }
        if (k < nkeys && seen[k]) {
            fprintf(stderr, "grip-replay: %s:%lu: key '%s' given twice (first on line %lu)\n", path, lineno, key,
                    seen[k]);
            csv_reader_close(f);
            return -1;
        }
        if (k < nkeys) {
            seen[k] = lineno;
        }
        if (k == nkeys) {
            fprintf(stderr, "grip-replay: %s:%lu: unknown key '%s' (", path, lineno, key);
            for (k = 0; k < nkeys; k++) {
                fprintf(stderr, "%s%s", k ? " " : "", keys[k].key);
            }
            fprintf(stderr, ")\n");
            csv_reader_close(f);
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
                csv_reader_close(f);
                return -1;
            }
            *(uint32_t *)((char *)cfg + keys[k].off) = (uint32_t)v;
            break;
        }
    }
    csv_reader_close(f);
    if (rc < 0) {
        fprintf(stderr, "grip-replay: vehicle file: %s\n", err);
        return -1;
    }
    {
        /* "track" sets both tracks: with track_f or track_r as well, the
         * result would depend on the line order */
        unsigned long both = 0;
        unsigned long one = 0;
        size_t k;
        for (k = 0; k < nkeys; k++) {
            if (keys[k].kind == VK_TRACK) {
                both = seen[k];
            } else if (strncmp(keys[k].key, "track_", 6) == 0 && seen[k] && !one) {
                one = seen[k];
            }
        }
        if (both && one) {
            fprintf(stderr, "grip-replay: %s:%lu: track (line %lu) and track_f / track_r both given\n", path,
                    both > one ? both : one, both);
            return -1;
        }
    }
    return 0;
}

/* A warning of the .tir reader ("FILE:LINE: KEY: what"). */
static void print_tir_warning(void *ctx, const char *message)
{
    (void)ctx;
    fprintf(stderr, "grip-replay: warning: %s\n", message);
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
            "      --reorder          sort a log whose frames are out of time order, within a 1 s\n"
            "                         window (at most 65536 frames waiting); without it a frame\n"
            "                         more than 1 ms (or -w, if larger) older than one before it\n"
            "                         is an error\n"
            "  -j, --jump-ms MS       a time gap beyond MS restarts the step grid (default 1000)\n"
            "      --time-offset-us N add N us to every frame time (file replay)\n"
            "      --skip-bad         skip malformed log lines (counted) instead of stopping\n"
            "      --all-inputs       write every input, also those the table does not feed\n"
            "      --units            unit suffixes in the output header (beta_rad, vx_m_s, ...)\n"
            "      --dump FILE        write every frame read as a candump -l log\n"
            "  -i, --interface IFACE  live: read this CAN interface\n"
            "      --fd               live: accept CAN FD frames too\n"
            "  -d, --duration S       live: stop after S seconds\n"
            "  -n, --frames N         stop after N frames\n"
            "      --idle-exit S      live: stop once no frame came for S seconds (after the first)\n"
            "  -e, --estimate TIR     run the estimator each step (tire .tir on both axles) and\n"
            "                         append its outputs to every row\n"
            "      --estimate-rear TIR  the rear axle's tire (-e's then on the front axle only)\n"
            "      --strict           .tir: every warning is an error (an unknown key, a key in\n"
            "                         another section, an empty value)\n"
            "      --no-range-check   .tir: accept coefficients outside their plausible ranges\n");
    fprintf(f,
            "      --vehicle NAME     estimator vehicle: rav4 (default), av21 or generic\n"
            "      --vehicle-file F   override vehicle values: lines `key = value` (SI): mass iz lf lr\n"
            "                         track track_f track_r h_cg steer_ratio wheel_radius\n"
            "                         roll_split_front roll_gradient speed_ref_mu bank_est (0/1) cla aero_front\n"
            "                         air_density cda crr tan_bank tan_grade latency steer_lag\n"
            "                         steer_latency [s] tire_tol kin_acc_sd [m/s^2] beta_sd_max [rad];\n"
            "                         rear_tire = PATH (the rear axle's .tir, relative to F's folder)\n"
            "      --csv FILE         estimator inputs from FILE ('-' = stdin) instead of CAN: one row per\n"
            "                         estimator step (every --step-ms), '#' lines skipped, a header row\n"
            "                         naming the columns: t_s [s], wheel_speed_fl wheel_speed_fr\n"
            "                         wheel_speed_rl wheel_speed_rr [m/s], steer_angle [rad, steering\n"
            "                         wheel], yaw_rate [rad/s], ax ay [m/s^2], optional vehicle_speed\n"
            "                         [m/s], brake_pressure_fl.. [Pa], brake_torque_fl.. [N m]; ISO axes\n"
            "                         (left positive). An empty or NaN cell = not valid in that step;\n"
            "                         t_s and the eight inputs before vehicle_speed are required\n"
            "                         (give an empty column for a signal you do not have). Also\n"
            "                         known and ignored: step, NAME_fault, comment. Any other\n"
            "                         column is an error. The rows' time step must be --step-ms\n"
            "                         (within 1 %%). Needs -e.\n"
            "                         A value outside its input's plausible range (a unit error:\n"
            "                         a steering angle in degrees, a speed in km/h) is an error.\n"
            "      --ignore-columns A,B  --csv: also ignore these columns\n"
            "      --no-unit-check    --csv: take such a value as a range fault (not valid)\n"
            "  -q, --quiet            no summary\n"
            "output: t_s, step, per input NAME and NAME_fault, with -e the estimator's columns;\n"
            "  with -e the measured yaw rate is yaw_rate_in (yaw_rate is the estimate)\n"
            "limits: candump line 512 bytes, CSV line 8192 bytes and 256 columns, table line\n"
            "  512 bytes, vehicle-file line 511, .tir line 4096 and file 4 MiB (docs/guarantees.md)\n"
            "exit: 0 ok, 2 usage, 3 table / DBC-map mismatch, 4 input (malformed or refused data),\n"
            "      5 output\n");
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
};
#define N_OPTS (sizeof OPTS / sizeof OPTS[0])

static int parse_args(int argc, char **argv, options *o)
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
            usage(stdout);
            exit(0);
        }
        for (k = 0; k < N_OPTS; k++) {
            if (strcmp(a, OPTS[k].l) == 0 || (OPTS[k].s[0] != '\0' && strcmp(a, OPTS[k].s) == 0)) {
                break;
            }
        }
        if (k < N_OPTS) {
            if (given[k]++) {
                fprintf(stderr, "grip-replay: option %s given twice\n", OPTS[k].l);
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
        } else if (strcmp(a, "--estimate-rear") == 0) {
            o->est_tir_rear = v;
        } else if (strcmp(a, "--vehicle") == 0) {
            o->vehicle = v;
        } else if (strcmp(a, "--vehicle-file") == 0) {
            o->vehicle_file = v;
        } else if (strcmp(a, "--csv") == 0) {
            o->csv_in = v;
        } else if (strcmp(a, "--ignore-columns") == 0) {
            o->ignore_cols = v;
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
                fprintf(stderr, "grip-replay: more than one log file given ('%s' and '%s')\n", o->log, a);
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
        mode = "--csv input";
    } else if ((o->log == NULL) == (o->iface == NULL)) {
        fprintf(stderr, "grip-replay: give either a log file or -i IFACE (try --help)\n");
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
            fprintf(stderr, "grip-replay: option %s is for %s, not %s\n", bad, where, mode);
            return -1;
        }
    }
    return 0;
}

/* ---- signal table ------------------------------------------------------------ */

static grip_can_table_text_t text_table;

static int load_table(const char *path, const grip_can_table_t **table)
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
        fprintf(stderr, "grip-replay: signal table: %s\n", err);
        return -1;
    }
    grip_can_table_text_init(&text_table);
    while ((rc = csv_read_line(&rd, err, sizeof err)) == 1) {
        uint16_t nm = text_table.table.n_messages;
        uint16_t ns = text_table.table.n_signals;
        if (grip_can_table_text_line(&text_table, line, (uint32_t)rd.len, &why) != GRIP_OK) {
            fprintf(stderr, "grip-replay: %s:%lu: %s\n", rd.path, rd.lineno, why);
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
        fprintf(stderr, "grip-replay: signal table: %s\n", err);
        return -1;
    }
    if (grip_can_table_text_finish_detail(&text_table, table, &why, &d) != GRIP_OK) {
        if (d.rule[0] != '\0') {
            /* the refused message or signal by its line and name */
            const grip_can_table_t *t = &text_table.table;
            int msg = strcmp(d.part, "message") == 0 && d.index >= 0 && d.index < (int32_t)t->n_messages;
            int sig = strcmp(d.part, "signal") == 0 && d.index >= 0 && d.index < (int32_t)t->n_signals;
            if (msg || sig) {
                fprintf(stderr, "grip-replay: %s:%lu: %s %s: %s: %s (the table's consistency check)\n", path,
                        msg ? msg_line[d.index] : sig_line[d.index], d.part,
                        msg ? t->messages[d.index].name : t->signals[d.index].name, d.field, d.rule);
            } else if (strcmp(d.part, "input") == 0 && d.index >= 0) {
                fprintf(stderr, "grip-replay: %s: input %s: %s: %s (the table's consistency check)\n", path,
                        grip_input_name((uint32_t)d.index), d.field, d.rule);
            } else {
                fprintf(stderr, "grip-replay: %s: %s: %s (the table's consistency check)\n", path, d.field,
                        d.rule);
            }
        } else {
            fprintf(stderr, "grip-replay: %s: %s\n", path, why);
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
    snprintf(buf, n, "%.9g", (double)v);
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
    { "ay_model", "m_s2" },   { "beta_sd", "rad" },     { "mu_sd", "" },
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
static int write_header(replay *r)
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
                fprintf(stderr, "grip-replay: internal error: output columns %lu and %lu are both named %s\n",
                        (unsigned long)a + 1ul, (unsigned long)b + 1ul, names[a]);
                return -1;
            }
        }
    }
    for (a = 0; a < nc; a++) {
        fprintf(r->csv, "%s%s", a ? "," : "", names[a]);
    }
    fprintf(r->csv, "\n");
    return 0;
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
        fprintf(r->csv, ",%.6g,%.6g", real_to_si(e->beta_sd, 0), real_to_si(e->mu_sd, 0));
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
        if (r->opt->sort_log) {
            fprintf(stderr, "  log order      %lu frames older than one before them (at most %.3f ms), sorted "
                    "(--reorder: %d ms window)\n", r->out_of_order, (double)r->max_back_us / 1000.0,
                    CANDUMP_REORDER_WINDOW_US / 1000);
        } else {
            fprintf(stderr, "  log order      %lu frames older than one before them (at most %.3f ms, tolerance "
                    "%.3f ms), passed on as they came\n", r->out_of_order, (double)r->max_back_us / 1000.0,
                    (double)r->back_tolerance_us / 1000.0);
        }
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
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (candump_order_init(&ord, tol, r->opt->sort_log ? CANDUMP_REORDER_WINDOW_US : 0, CANDUMP_REORDER_MAX_FRAMES,
                           err, sizeof err) != 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        candump_close(&rd);
        return EXIT_INPUT;
    }
    rd.skip_bad = r->opt->skip_bad;
    while ((rc = candump_next_ordered(&rd, &ord, &f, ifname, err, sizeof err)) == 1) {
        f.t_us += r->opt->time_offset_us;
        feed(r, &f, ifname);
        if (r->opt->max_frames && r->frames_read >= r->opt->max_frames) {
            break;
        }
    }
    r->out_of_order = ord.out_of_order;
    r->max_back_us = ord.max_back_us;
    r->back_tolerance_us = tol;
    if (rd.skipped > 0) {
        fprintf(stderr, "grip-replay: %lu malformed lines skipped (--skip-bad)\n", rd.skipped);
    }
    candump_order_free(&ord);
    candump_close(&rd);
    if (rc < 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (r->frames_read == 0) {
        fprintf(stderr, "grip-replay: %s: no CAN frame in the log (%lu lines%s)\n", rd.path, rd.lineno,
                rd.skipped ? ", all skipped as malformed or blank" : ", none a frame");
        return EXIT_INPUT;
    }
    finish(r);
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
        fprintf(stderr, "grip-replay: ");
        va_start(ap, fmt);
        vfprintf(stderr, fmt, ap);
        va_end(ap);
        fprintf(stderr, "\n");
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

static input_rule input_rules[GRIP_IN_COUNT];

static void input_rules_init(void)
{
#define INPUT_RULE(id, lo_, hi_, hint_, hint_max_) \
    input_rules[id].lo = (lo_); input_rules[id].hi = (hi_); input_rules[id].hint = (hint_); \
    input_rules[id].hint_max = (hint_max_);
    GRIP_INPUT_RULES(INPUT_RULE)
#undef INPUT_RULE
}

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
        if (write_header(r) != 0) {
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
    input_rules_init();
    if (csv_reader_open(&rd, r->opt->csv_in, line, CSV_LINE_MAX, 1, err, sizeof err) != 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
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
        fprintf(stderr, "grip-replay: %s: stopped after %d errors\n", c.path, CSV_MAX_ERRORS);
        return EXIT_INPUT;
    }
    if (rc < 0) {
        fprintf(stderr, "grip-replay: %s\n", err);
        return EXIT_INPUT;
    }
    if (!have_header) {
        if (c.errors == 0) {
            fprintf(stderr, "grip-replay: %s: no header row (%lu lines)\n", c.path, rd.lineno);
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
        double hz = 1000.0 / o.step_ms;
        int rate_hz = (int)(hz + 0.5);
        /* grip_est_config_t.rate_hz: a whole number of Hz in [EST_RATE_MIN,
         * EST_RATE_MAX]; the step must give it within EST_RATE_TOL, or the
         * estimator would integrate with another time step than the data's */
        if (hz < EST_RATE_MIN * (1.0 - EST_RATE_TOL) || hz > EST_RATE_MAX * (1.0 + EST_RATE_TOL)) {
            fprintf(stderr, "grip-replay: --step-ms %g is %g Hz; the estimator runs at %d..%d Hz (step %g..%g ms): "
                    "resample the input to a rate in that range\n", o.step_ms, hz, EST_RATE_MIN, EST_RATE_MAX,
                    1000.0 / EST_RATE_MAX, 1000.0 / EST_RATE_MIN);
            return EXIT_USAGE;
        }
        if (fabs(hz - rate_hz) > EST_RATE_TOL * hz) {
            fprintf(stderr, "grip-replay: --step-ms %g is %.6g Hz; the estimator's rate is a whole number of Hz "
                    "(%d would integrate %.3g %% off): use a step of 1000/N ms, e.g. 2, 2.5, 4, 5 or 10\n",
                    o.step_ms, hz, rate_hz, 100.0 * fabs(hz - rate_hz) / hz);
            return EXIT_USAGE;
        }
        {
            /* bounded (4 MiB, 4096-byte lines: /dev/zero and a 1 GiB file end
             * at once) and validated; warnings name the file, line and key */
            grip_tir_options to;
            grip_tir_options_init(&to);
            to.flags = o.tir_flags;
            to.warn = print_tir_warning;
            if (grip_tir_read_opts(o.est_tir, &to, &r.tire, err, sizeof err) != 0) {
                fprintf(stderr, "grip-replay: %s\n", err);
                return EXIT_USAGE;
            }
        }
        if (vehicle_config(o.vehicle, &r.tire, rate_hz, &ecfg) != 0) {
            fprintf(stderr, "grip-replay: unknown --vehicle '%s' (rav4, av21, generic)\n", o.vehicle);
            return EXIT_USAGE;
        }
        if (o.est_tir_rear != NULL) {
            grip_tir_options to;
            grip_tir_options_init(&to);
            to.flags = o.tir_flags;
            to.warn = print_tir_warning;
            if (grip_tir_read_opts(o.est_tir_rear, &to, &r.tire_rear, err, sizeof err) != 0) {
                fprintf(stderr, "grip-replay: %s\n", err);
                return EXIT_USAGE;
            }
            ecfg.tire[1].kind = GRIP_EST_TIRE_MF;
            ecfg.tire[1].model.mf = &r.tire_rear;
        }
        if (o.vehicle_file != NULL) {
            static char rear_path[1024];
            unsigned long rear_line = 0;
            if (vehicle_file(o.vehicle_file, &ecfg, rear_path, sizeof rear_path, &rear_line) != 0) {
                return EXIT_USAGE;
            }
            if (rear_line != 0) {
                grip_tir_options to;
                if (o.est_tir_rear != NULL) {
                    fprintf(stderr, "grip-replay: %s:%lu: rear_tire: the rear tire is also given by --estimate-rear\n",
                            o.vehicle_file, rear_line);
                    return EXIT_USAGE;
                }
                grip_tir_options_init(&to);
                to.flags = o.tir_flags;
                to.warn = print_tir_warning;
                if (grip_tir_read_opts(rear_path, &to, &r.tire_rear, err, sizeof err) != 0) {
                    fprintf(stderr, "grip-replay: %s:%lu: rear_tire: %s\n", o.vehicle_file, rear_line, err);
                    return EXIT_USAGE;
                }
                ecfg.tire[1].kind = GRIP_EST_TIRE_MF;
                ecfg.tire[1].model.mf = &r.tire_rear;
            }
        }
        r.mass_si = real_to_si(ecfg.mass, 1);
        {
            grip_check_detail_t d;
            char what[96];
            st = grip_est_init_detail(&r.est, &ecfg, &d);
            if (st != GRIP_OK) {
                if (d.part[0] != '\0') {
                    snprintf(what, sizeof what, "%s[%d] (%s axle).%s", d.part, (int)d.index,
                             d.index == 0 ? "front" : "rear", d.field);
                } else {
                    snprintf(what, sizeof what, "%s", d.field[0] ? d.field : "-");
                }
                fprintf(stderr, "grip-replay: the estimator rejects the vehicle (%s%s%s) with tire %s at %d Hz: "
                        "%s must be %s (%s; grip_est_init's ranges: include/grip/grip_est.h)\n",
                        o.vehicle ? o.vehicle : "rav4", o.vehicle_file ? " + " : "",
                        o.vehicle_file ? o.vehicle_file : "", o.est_tir, rate_hz, what, d.rule, grip_status_str(st));
                return EXIT_USAGE;
            }
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
        if (!o.quiet && status == 0) {   /* on an error, its message is the last word */
            summary_csv(&r);
        }
        goto done;
    }
    if (write_header(&r) != 0) {
        return EXIT_OUTPUT;
    }
    status = o.iface ? run_live(&r) : run_file(&r);
    if (!o.quiet && (status == 0 || o.iface != NULL)) {
        summary(&r, o.iface ? &sock : NULL);
    }
    if (status == 0 && check_match(&r) != 0) {
        status = EXIT_TABLE;
    }
done:
    if (r.dump != NULL && fclose(r.dump) != 0) {
        r.write_failed = 1;
    }
    if (status == EXIT_INPUT && o.iface == NULL && r.csv != stdout) {
        /* a data error: the rows written so far are not the file's answer;
         * an output file (a regular one, never a device or pipe) is removed
         * so that nobody mistakes it for one */
        struct stat st_out;
        int regular = fstat(fileno(r.csv), &st_out) == 0 && S_ISREG(st_out.st_mode);
        fclose(r.csv);
        if (regular && remove(o.out) == 0) {
            fprintf(stderr, "grip-replay: %s removed (incomplete)\n", o.out);
        }
        return status;
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
