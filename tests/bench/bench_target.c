/*
 * bench_target.c - Cortex-M benchmark image. Every case runs on every input
 * set between two calls of bench_mark(); tools/grip_tools/bench_qemu.py counts
 * the instructions qemu-system-arm executes between the marks (one
 * instruction per translation block) and subtracts the cost of an empty case.
 */
#include "bench_cases.h"
#include "grip_bm.h"

volatile int bench_mark_sink;

__attribute__((noinline)) void bench_mark(int tag);
__attribute__((noinline)) void bench_mark(int tag) { bench_mark_sink = tag; }

static void empty_case(int i) { bench_mark_sink = i; }

int main(void)
{
    int c;
    int i;
    bench_cases_setup();
    grip_bm_puts("bench: empty\n");
    for (i = 0; i < BENCH_INPUTS; ++i) {
        bench_mark(-1);
        empty_case(i);
        bench_mark(-2);
    }
    for (c = 0; c < bench_all_count; ++c) {
        grip_bm_puts("bench: ");
        grip_bm_puts(bench_all[c]->name);
        grip_bm_puts("\n");
        for (i = 0; i < BENCH_INPUTS; ++i) {
            bench_mark(c);
            bench_all[c]->run(i);
            bench_mark(-2);
        }
    }
    return 0;
}
