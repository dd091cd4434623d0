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
 * estimator and written as a CSV row; a summary with frame, decode-error,
 * stale-signal and drop counts goes to stderr. The replay itself (table,
 * CSV reader, estimator setup, rows, summary) is replay_core.c, which the
 * Python binding runs too; this file is the command line, the output
 * files and the live interface. docs/can.md is the manual (options, CSV columns, exit
 * codes). In --csv mode each row of the file is one estimator step
 * (docs/estimator.md, "Using it"), the CAN path is not used, and the output
 * has the same columns as in CAN mode.
 */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>

#include "grip/grip_can.h"
#include "grip/grip_signals.h"
#include "can_socket.h"
#include "replay_core.h"

#define RECV_TIMEOUT_MS 50

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
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
            "                         roll_split_front roll_gradient pitch_gradient speed_ref_mu\n"
            "                         bank_est stiff_est kx_est roll_est (0/1) drive_front (front\n"
            "                         drive share, -1: not known)\n"
            "                         cla aero_front\n"
            "                         air_density cda crr tan_bank tan_grade latency steer_lag\n"
            "                         steer_latency [s] tire_tol kin_acc_sd [m/s^2] beta_sd_max [rad]\n"
            "                         vx_sd_max [m/s] fy_sd_max [N];\n"
            "                         rear_tire = PATH (the rear axle's .tir, relative to F's folder)\n"
            "      --learned-in F     restore what the estimator learned (stiff_est, kx_est,\n"
            "                         roll_est), a blob\n"
            "                         --learned-out wrote for this car, tire and build\n"
            "      --learned-out F    write what it learned after the run (file and --csv modes)\n"
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
            replay_feed(r, &f, r->opt->iface);
            if (r->opt->max_frames && r->frames_read >= r->opt->max_frames) {
                break;
            }
        } else if (rc == CAN_SOCK_TIMEOUT) {
            /* Silence: every frame stamped before now - timeout has been
             * read, so the steps up to then can be emitted (stale values). */
            if (r->a.started) {
                replay_drain(r, realtime_us() - RECV_TIMEOUT_MS * 1000);
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
    replay_finish(r);
    can_sock_close(&sock);
    return status;
}

int main(int argc, char **argv)
{
    static replay r;
    replay_options o;
    int status;

    status = replay_parse_args(argc, argv, &o, stderr);
    if (status > 0) {
        usage(stdout);
        return 0;
    }
    if (status != 0) {
        return EXIT_USAGE;
    }
    memset(&r, 0, sizeof r);
    r.opt = &o;
    r.msg = stderr;
    status = replay_setup(&r);
    if (status != 0) {
        return status;
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
    if (o.csv_in == NULL) {
        if (replay_write_header(&r) != 0) {
            return EXIT_OUTPUT;
        }
        r.header_done = 1;
    }
    if (o.iface == NULL) {
        status = replay_run(&r);   /* the log or the --csv file, its summary */
    } else {
        status = run_live(&r);
        if (!o.quiet) {
            replay_summary(&r, &sock);
        }
        if (status == 0 && replay_check_match(&r) != 0) {
            status = EXIT_TABLE;
        }
    }
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
