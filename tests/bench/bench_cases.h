/*
 * bench_cases.h - the benchmark cases, shared by the host benchmark
 * (ns/call, callgrind) and the Cortex-M benchmark (instructions counted on
 * qemu-system-arm). Each case evaluates one public function on input set i
 * of BENCH_INPUTS representative inputs; the result goes to a volatile sink
 * so nothing is optimized away.
 */
#ifndef GRIP_BENCH_CASES_H
#define GRIP_BENCH_CASES_H

#include <stdint.h>

#define BENCH_INPUTS 16

typedef struct {
    const char *name;
    void (*run)(int i);
} bench_case;

extern const bench_case bench_cases[];
extern const int bench_case_count;

/* Called once by each harness before it measures anything: prepares every
 * case table linked into the image and lists all their cases. */
void bench_cases_setup(void);

/* Every case of every linked table, valid after bench_cases_setup(). The
 * model families' tables (tests/bench/bench_<family>.c) are optional:
 * each is linked when its file is built in. */
#define BENCH_MAX_CASES 64
extern const bench_case *bench_all[BENCH_MAX_CASES];
extern int bench_all_count;

#endif
