/*
 * vehicle_config.c - the vehicle presets and the vehicle file of
 * grip-replay (vehicle_config.h).
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "grip/grip_convert.h"
#include "vehicle_config.h"

/* Vehicle presets for --vehicle.
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
/* SI to the build's format through grip_convert.h: rounded half away from
 * zero; beyond the format the nearest bound (which grip_est_init's ranges
 * then refuse), never an out-of-range integer conversion */
grip_real_t vehicle_si_qs(double x)
{
    grip_real_t r;
    (void)grip_real_qs_from_si(x, &r);
    return r;
}

grip_real_t vehicle_si_ql(double x)
{
    grip_real_t r;
    (void)grip_real_ql_from_si(x, &r);
    return r;
}

int vehicle_preset(const char *name, const grip_mf_params *tire, int rate_hz, grip_est_config_t *cfg)
{
    if (grip_est_config_default(cfg, tire) != GRIP_OK) {
        return -1;
    }
    cfg->rate_hz = (uint32_t)rate_hz;
    if (name == NULL || strcmp(name, "rav4") == 0) {
        cfg->mass = vehicle_si_ql(1640.0);
        cfg->iz = vehicle_si_ql(2900.0);
        cfg->lf = vehicle_si_qs(1.06);
        cfg->lr = vehicle_si_qs(1.59);
        cfg->track_f = vehicle_si_qs(1.57);
        cfg->track_r = vehicle_si_qs(1.57);
        cfg->h_cg = vehicle_si_qs(0.66);
        cfg->steer_ratio = vehicle_si_qs(16.88);
        cfg->wheel_radius = vehicle_si_qs(0.355);
        return 0;
    }
    if (strcmp(name, "av21") == 0) {
        cfg->mass = vehicle_si_ql(790.0);
        cfg->iz = vehicle_si_ql(1000.0);
        cfg->lf = vehicle_si_qs(1.248);
        cfg->lr = vehicle_si_qs(1.7328);
        cfg->track_f = vehicle_si_qs(1.6);
        cfg->track_r = vehicle_si_qs(1.6);
        cfg->h_cg = vehicle_si_qs(0.30);
        cfg->steer_ratio = vehicle_si_qs(1.0);
        cfg->wheel_radius = vehicle_si_qs(0.30);
        cfg->roll_split_front = vehicle_si_qs(0.5);
        cfg->roll_gradient = vehicle_si_qs(0.001);
        cfg->steer_lag = vehicle_si_qs(0.28);
        return 0;
    }
    return (strcmp(name, "generic") == 0) ? 0 : -1;
}

/* Reads a vehicle file: lines `key = value` (SI units), '#' comments, blank
 * lines. Keys: mass, iz, lf, lr, track (both), track_f, track_r, h_cg,
 * steer_ratio, wheel_radius, roll_split_front, roll_gradient, pitch_gradient, speed_ref_mu, bank_est, stiff_est,
 * kx_est, roll_est, drive_front,
 * cla, aero_front, air_density, cda, crr, tan_bank, tan_grade, latency, steer_lag,
 * steer_latency, tire_tol, kin_acc_sd, beta_sd_max, vx_sd_max, fy_sd_max; rear_tire = PATH (the rear
 * axle's .tir, relative to the vehicle file's folder; not with --estimate-rear).
 * The estimator's init checks the ranges. */
#define VEHICLE_LINE_MAX 511

int vehicle_file_read(const char *path, grip_est_config_t *cfg, char *rear_tire, size_t rear_n,
                      unsigned long *rear_line, FILE *msg)
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
        { "pitch_gradient", offsetof(grip_est_config_t, pitch_gradient), VK_QS },
        { "speed_ref_mu", offsetof(grip_est_config_t, speed_ref_mu), VK_FLAG },
        { "bank_est", offsetof(grip_est_config_t, bank_est), VK_FLAG },
        { "stiff_est", offsetof(grip_est_config_t, stiff_est), VK_FLAG },
        { "kx_est", offsetof(grip_est_config_t, kx_est), VK_FLAG },
        { "roll_est", offsetof(grip_est_config_t, roll_est), VK_FLAG },
        { "drive_front", offsetof(grip_est_config_t, drive_front), VK_QS },
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
        { "vx_sd_max", offsetof(grip_est_config_t, vx_sd_max), VK_QS },
        { "fy_sd_max", offsetof(grip_est_config_t, fy_sd_max), VK_QL },
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
        fprintf(msg, "grip-replay: vehicle file: %s\n", err);
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
            fprintf(msg, "grip-replay: %s:%lu: expected key = value\n", path, lineno);
            csv_reader_close(f);
            return -1;
        }
        n = (size_t)(eq - p);
        while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\t')) {
            n--;
        }
        if (n == 0 || n >= sizeof key) {
            fprintf(msg, "grip-replay: %s:%lu: bad key\n", path, lineno);
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
                fprintf(msg, "grip-replay: %s:%lu: key 'rear_tire' given twice (first on line %lu)\n", path,
                        lineno, *rear_line);
                csv_reader_close(f);
                return -1;
            }
            if (vn == 0 || dn + vn >= rear_n) {
                fprintf(msg, "grip-replay: %s:%lu: rear_tire: %s\n", path, lineno,
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
            fprintf(msg, "grip-replay: %s:%lu: %s: not a number\n", path, lineno, key);
            csv_reader_close(f);
            return -1;
        }
        for (k = 0; k < nkeys; k++) {
            if (strcmp(key, keys[k].key) == 0) {
                break;
            }
        }
        if (k < nkeys && seen[k]) {
            fprintf(msg, "grip-replay: %s:%lu: key '%s' given twice (first on line %lu)\n", path, lineno, key,
                    seen[k]);
            csv_reader_close(f);
            return -1;
        }
        if (k < nkeys) {
            seen[k] = lineno;
        }
        if (k == nkeys) {
            fprintf(msg, "grip-replay: %s:%lu: unknown key '%s' (", path, lineno, key);
            for (k = 0; k < nkeys; k++) {
                fprintf(msg, "%s%s", k ? " " : "", keys[k].key);
            }
            fprintf(msg, ")\n");
            csv_reader_close(f);
            return -1;
        }
        switch (keys[k].kind) {
        case VK_QL:
            *(grip_real_t *)((char *)cfg + keys[k].off) = vehicle_si_ql(v);
            break;
        case VK_QS:
            *(grip_real_t *)((char *)cfg + keys[k].off) = vehicle_si_qs(v);
            break;
        case VK_TRACK:
            cfg->track_f = vehicle_si_qs(v);
            cfg->track_r = vehicle_si_qs(v);
            break;
        default:
            if (v != 0.0 && v != 1.0) {
                fprintf(msg, "grip-replay: %s:%lu: %s must be 0 or 1\n", path, lineno, keys[k].key);
                csv_reader_close(f);
                return -1;
            }
            *(uint32_t *)((char *)cfg + keys[k].off) = (uint32_t)v;
            break;
        }
    }
    csv_reader_close(f);
    if (rc < 0) {
        fprintf(msg, "grip-replay: vehicle file: %s\n", err);
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
            fprintf(msg, "grip-replay: %s:%lu: track (line %lu) and track_f / track_r both given\n", path,
                    both > one ? both : one, both);
            return -1;
        }
    }
    return 0;
}
