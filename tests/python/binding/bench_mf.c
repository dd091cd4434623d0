/*
 * bench_mf.c - the C reference point of test_throughput.py: the same work
 * as the binding's (SI double -> grip_convert.h -> the library -> output
 * array) over the same points, in a program linked to the Makefile's
 * build/<arith>-gcc/libgrip.a. Not part of the library.
 *
 *   bench_mf TIR N REPEAT [THREADS [batch|lanes]] < points (N x 2 doubles: kappa, alpha; binary)
 *
 * THREADS (default 1): the points cut into that many slices, each evaluated
 * by its own POSIX thread (the machine's own scaling, without Python);
 * "batch": each slice through grip_mf_eval_batch in blocks of 128 points
 * (as the binding does) instead of one grip_mf_eval per point; "lanes": the
 * set prepared once and each block through grip_mf_eval_prepared_lanes (as
 * the binding's lanes=True).
 * Prints: the best wall-clock and CPU seconds of REPEAT runs, and a checksum.
 */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "grip/grip_convert.h"
#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#include "tir_reader.h"

#define BLOCK 128u
#define MAX_THREADS 64

static grip_mf_params p;
static const double *in;
static grip_real_t *fx, *fy, *mz;
static int use_batch;     /* 1: grip_mf_eval_batch, 2: grip_mf_eval_prepared_lanes */
static grip_mf_prepared prep;

typedef struct {
    size_t a, b;
} slice_t;

static double now(clockid_t c)
{
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void point_in(size_t k, grip_mf_input *x)
{
    (void)grip_real_qs_from_si(in[2 * k], &x->kappa);
    (void)grip_real_qs_from_si(in[2 * k + 1], &x->alpha);
    (void)grip_real_qs_from_si(0.0, &x->gamma);
    (void)grip_real_ql_from_si(4000.0, &x->fz);
    (void)grip_real_ql_from_si(0.0, &x->p);
    (void)grip_real_qs_from_si(16.7, &x->vx);
}

static void *run_slice(void *arg)
{
    const slice_t *s = arg;
    size_t k;
    if (!use_batch) {
        for (k = s->a; k < s->b; k++) {
            grip_mf_input x;
            grip_mf_output y;
            point_in(k, &x);
            (void)grip_mf_eval(&p, &x, &y);
            fx[k] = y.fx;
            fy[k] = y.fy;
            mz[k] = y.mz;
        }
        return NULL;
    }
    for (k = s->a; k < s->b; k += BLOCK) {
        grip_mf_input x[BLOCK];
        grip_mf_output y[BLOCK];
        grip_status_t st[BLOCK];
        size_t m = (s->b - k < BLOCK) ? s->b - k : BLOCK;
        size_t j;
        for (j = 0; j < m; j++) {
            point_in(k + j, &x[j]);
        }
        if (use_batch == 2) {
            (void)grip_mf_eval_prepared_lanes(&prep, (uint32_t)m, x, y, st);
        } else {
            (void)grip_mf_eval_batch(&p, (uint32_t)m, x, y, st);
        }
        for (j = 0; j < m; j++) {
            fx[k + j] = y[j].fx;
            fy[k + j] = y[j].fy;
            mz[k + j] = y[j].mz;
        }
    }
    return NULL;
}

int main(int argc, char **argv)
{
    char err[512];
    size_t n, k;
    int r, repeat, threads = 1, t;
    double *buf;
    double best = 1e30, best_cpu = 1e30, sum = 0.0;
    pthread_t th[MAX_THREADS];
    slice_t sl[MAX_THREADS];
    if (argc < 4 || argc > 6 || grip_tir_read(argv[1], &p, err, sizeof err) != 0) {
        fprintf(stderr, "usage: bench_mf TIR N REPEAT [THREADS [batch|lanes]] < points\n");
        return 2;
    }
    n = (size_t)strtoul(argv[2], NULL, 10);
    repeat = atoi(argv[3]);
    if (argc >= 5) {
        threads = atoi(argv[4]);
    }
    use_batch = (argc == 6 && strcmp(argv[5], "batch") == 0) ? 1 : 0;
    if (argc == 6 && strcmp(argv[5], "lanes") == 0) {
        use_batch = 2;
        if (grip_mf_prepare(&p, p.options, &prep) != GRIP_OK) {
            return 2;
        }
    }
    if (threads < 1 || threads > MAX_THREADS) {
        return 2;
    }
    buf = malloc(2 * n * sizeof *buf);
    fx = malloc(n * sizeof *fx);
    fy = malloc(n * sizeof *fy);
    mz = malloc(n * sizeof *mz);
    if (buf == NULL || fx == NULL || fy == NULL || mz == NULL || fread(buf, sizeof *buf, 2 * n, stdin) != 2 * n) {
        return 3;
    }
    in = buf;
    for (t = 0; t < threads; t++) {
        sl[t].a = n * (size_t)t / (size_t)threads;
        sl[t].b = n * (size_t)(t + 1) / (size_t)threads;
    }
    for (r = 0; r < repeat; r++) {
        double t0 = now(CLOCK_MONOTONIC);
        double c0 = now(CLOCK_PROCESS_CPUTIME_ID);
        if (threads == 1) {
            run_slice(&sl[0]);
        } else {
            for (t = 0; t < threads; t++) {
                if (pthread_create(&th[t], NULL, run_slice, &sl[t]) != 0) {
                    return 4;
                }
            }
            for (t = 0; t < threads; t++) {
                pthread_join(th[t], NULL);
            }
        }
        t0 = now(CLOCK_MONOTONIC) - t0;
        c0 = now(CLOCK_PROCESS_CPUTIME_ID) - c0;
        best = (t0 < best) ? t0 : best;
        best_cpu = (c0 < best_cpu) ? c0 : best_cpu;
    }
    for (k = 0; k < n; k++) {
        sum += grip_real_ql_to_si(fx[k]) + grip_real_ql_to_si(fy[k]) + grip_real_ql_to_si(mz[k]);
    }
    printf("%.6f %.6f %.17g\n", best, best_cpu, sum);
    return 0;
}
