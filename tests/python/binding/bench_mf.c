/*
 * bench_mf.c - the C reference point of test_throughput.py: the same loop
 * as the binding's (SI double -> grip_convert.h -> grip_mf_eval -> output
 * array) over the same points, in a program linked to the Makefile's
 * build/<arith>-gcc/libgrip.a. Not part of the library.
 *
 *   bench_mf TIR N REPEAT < points (N x 2 doubles: kappa, alpha; binary)
 * prints: the best wall-clock and CPU seconds of REPEAT runs, and a checksum.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "grip/grip_convert.h"
#include "grip/grip_mf.h"
#include "tir_reader.h"

static double now(clockid_t c)
{
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    static grip_mf_params p;
    char err[512];
    size_t n, k;
    int r, repeat;
    double *in;
    grip_real_t *fx, *fy, *mz;
    double best = 1e30, best_cpu = 1e30, sum = 0.0;
    if (argc != 4 || grip_tir_read(argv[1], &p, err, sizeof err) != 0) {
        fprintf(stderr, "usage: bench_mf TIR N REPEAT < points\n");
        return 2;
    }
    n = (size_t)strtoul(argv[2], NULL, 10);
    repeat = atoi(argv[3]);
    in = malloc(2 * n * sizeof *in);
    fx = malloc(n * sizeof *fx);
    fy = malloc(n * sizeof *fy);
    mz = malloc(n * sizeof *mz);
    if (in == NULL || fx == NULL || fy == NULL || mz == NULL || fread(in, sizeof *in, 2 * n, stdin) != 2 * n) {
        return 3;
    }
    for (r = 0; r < repeat; r++) {
        double t0 = now(CLOCK_MONOTONIC);
        double c0 = now(CLOCK_PROCESS_CPUTIME_ID);
        for (k = 0; k < n; k++) {
            grip_mf_input x;
            grip_mf_output y;
            (void)grip_real_qs_from_si(in[2 * k], &x.kappa);
            (void)grip_real_qs_from_si(in[2 * k + 1], &x.alpha);
            (void)grip_real_qs_from_si(0.0, &x.gamma);
            (void)grip_real_ql_from_si(4000.0, &x.fz);
            (void)grip_real_ql_from_si(0.0, &x.p);
            (void)grip_real_qs_from_si(16.7, &x.vx);
            (void)grip_mf_eval(&p, &x, &y);
            fx[k] = y.fx;
            fy[k] = y.fy;
            mz[k] = y.mz;
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
