/*
 * grip_bm.h - the bare-metal example port: what a Cortex-M program needs
 * around libgrip (startup in startup.c, output through semihosting, a cycle
 * counter hook). An ECU integration replaces these with its own BSP.
 */
#ifndef GRIP_BM_H
#define GRIP_BM_H

#include <stdint.h>

/* Write a NUL-terminated string to the debugger/emulator console. */
void grip_bm_puts(const char *s);
/* Write a signed decimal integer. */
void grip_bm_put_int(int32_t v);
/* End the program with an exit code (semihosting SYS_EXIT_EXTENDED). */
void grip_bm_exit(int code);
/* Cycle counter: DWT->CYCCNT on silicon. QEMU does not model the DWT, so
 * the emulator-based benchmarks count instructions from its trace instead. */
uint32_t grip_bm_cycles(void);
void grip_bm_cycles_enable(void);

#endif
