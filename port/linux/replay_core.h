/*
 * replay_core.h - a log replayed into estimator steps: the part of
 * `grip-replay` that turns a candump log (with its signal table) or an
 * estimator-input CSV file (input_rules.h) and the estimator's
 * configuration (.tir, vehicle preset and file: vehicle_config.h) into
 * per-step rows and a summary. grip-replay (grip_replay.c: the command
 * line, the output files, the live interface) and the Python binding
 * (grip._replay, tools/grip/_build.py) both run this code, so that an
 * in-process replay gives what the program gives.
 *
 * Use: replay_parse_args, then (replay zeroed, opt and msg set)
 * replay_setup, then csv or row set, then replay_run. Messages and the
 * summary go to msg, each line starting "grip-replay: " as the program
 * prints them. Not reentrant: the line buffers are static.
 */
#ifndef GRIP_REPLAY_CORE_H
#define GRIP_REPLAY_CORE_H

#include <stdint.h>
#include <stdio.h>

#include "grip/grip_can.h"
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "can_socket.h"

#define EXIT_USAGE 2    /* bad command line */
#define EXIT_TABLE 3    /* signal table unreadable, or it does not match the log (DBC/map mismatch) */
#define EXIT_INPUT 4    /* log unreadable or malformed, interface missing, socket error */
#define EXIT_OUTPUT 5   /* CSV or dump could not be written */

/* the estimator's step rate (grip_est_config_t.rate_hz, checked by
 * grip_est_init): whole Hz in [50, 2000]; 1000 / --step-ms must be one
 * within EST_RATE_TOL */
#define EST_RATE_MIN 50
#define EST_RATE_MAX 2000
#define EST_RATE_TOL 5e-4

/* Significant digits of the output's numbers: an input value (float
 * build; the fixed build writes %.17g of the exact value), an estimator
 * output. replay_as_printed gives the double a reader of the text gets. */
#define REPLAY_DIGITS_INPUT 9
#define REPLAY_DIGITS_EST 6

/* The estimator's real-valued output columns after est_status, est_valid,
 * est_flags (replay_est_values; ay_model NaN = an empty cell). */
#define REPLAY_EST_REALS 19

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
    const char *learned_in;    /* --learned-in: a grip_est_learned_t blob restored after init */
    const char *learned_out;   /* --learned-out: the blob written after the run */
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
} replay_options;

typedef struct replay replay;

/* Receives each estimator step (the sample as the estimator saw it; the
 * estimator's output in r->est_out) instead of the CSV row. */
typedef void (*replay_row_fn)(void *ctx, const replay *r, const grip_input_sample_t *s);

struct replay {
    const replay_options *opt;
    FILE *msg;                    /* messages and the summary (grip-replay: stderr) */
    replay_row_fn row;            /* non-NULL: each step goes here, csv is not written */
    void *row_ctx;
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
    int header_done;              /* the header is written (--csv: with the first row) */
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
};

/* The command line (argv[0] the program) into *o. 0, 1 for -h/--help,
 * -1 after a message on msg. */
int replay_parse_args(int argc, char **argv, replay_options *o, FILE *msg);

/* The signal table (CAN input) and the sample assembler, the tire(s), the
 * vehicle and the estimator (-e). 0, or the exit status after a message. */
int replay_setup(replay *r);

/* Replays the log file or the --csv file: its rows (or r->row calls) and,
 * unless -q, the summary. Returns the exit status (0: ok). r->csv (or
 * r->row) must be set; the caller closes the files. */
int replay_run(replay *r);

/* For the live interface of grip-replay: the header, one frame in, the
 * steps due before now out, the steps up to the newest frame out, the
 * summary and the table check (-1: no frame of the table was usable). */
int replay_write_header(replay *r);
void replay_feed(replay *r, const grip_can_frame_t *f, const char *ifname);
void replay_drain(replay *r, int64_t now);
void replay_finish(replay *r);
void replay_summary(const replay *r, const can_sock *sock);
int replay_check_match(const replay *r);

/* A value of the build's format as SI (ql: a QL field or input). */
double replay_real_to_si(grip_real_t v, int ql);

/* The estimator's real-valued output columns of the last step, in output
 * order (vx, beta, ..., ay_model, beta_sd, mu_sd), as SI doubles before
 * formatting; ay_model NaN when not written. */
void replay_est_values(const replay *r, double v[REPLAY_EST_REALS]);

/* Input i's value as the output writes it, read back: %.9g (float build)
 * or the exact value (fixed build). */
double replay_input_value(grip_real_t v, uint32_t input);

/* A step's time as the output's t_s column writes it, read back. */
double replay_time_value(int64_t t_us);

/* v formatted with %.*g (digits) and read back with strtod. */
double replay_as_printed(double v, int digits);

#endif
