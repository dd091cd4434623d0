/*
 * bench_host.c - host benchmark.
 *   bench_host            ns per call of every case (median of 5 runs)
 *   bench_host NAME N     run case NAME N times between callgrind's
 *                         start/stop instrumentation markers, for a
 *                         deterministic instruction count
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <valgrind/callgrind.h>

#include "bench_cases.h"
#include "grip/grip_types.h"

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    int c;
    bench_cases_setup();
    if (argc == 3) {
        long n = strtol(argv[2], NULL, 10);
        for (c = 0; c < bench_all_count; ++c) {
            if (strcmp(bench_all[c]->name, argv[1]) == 0) {
                long k;
                CALLGRIND_START_INSTRUMENTATION;
                for (k = 0; k < n; ++k) {
                    bench_all[c]->run((int)(k % BENCH_INPUTS));
                }
                CALLGRIND_STOP_INSTRUMENTATION;
                return 0;
            }
        }
        fprintf(stderr, "bench_host: no case %s\n", argv[1]);
        return 2;
    }
    printf("case,arith,ns_per_call\n");
    for (c = 0; c < bench_all_count; ++c) {
        double runs[5];
        int r;
        for (r = 0; r < 5; ++r) {
            const long n = 200000;
            long k;
            double t0 = now_ns();
            for (k = 0; k < n; ++k) {
                bench_all[c]->run((int)(k % BENCH_INPUTS));
            }
            runs[r] = (now_ns() - t0) / (double)n;
        }
        qsort(runs, 5, sizeof(runs[0]), cmp_double);
        printf("%s,%s,%.1f\n", bench_all[c]->name, GRIP_ARITH_NAME, runs[2]);
    }
    return 0;
}
