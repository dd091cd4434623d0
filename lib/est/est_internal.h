/*
 * est_internal.h - what the estimator's files (lib/est) share; the tuning
 * constants are est_tuning.h.
 */
#ifndef GRIP_EST_INTERNAL_H
#define GRIP_EST_INTERNAL_H

#include "grip/grip_est.h"
#include "arith.h"
#include "est_tuning.h"

#define EST_MAGIC 0x45535431u  /* "EST1" */

/* Keeps a helper of the step out of the step's stack frame: its locals then
 * take stack only while it runs, not under the Magic Formula evaluations
 * (M0+ worst-case stack 1024 -> 992 B with kf_predict and lateral_outputs,
 * docs/estimator.md "Cost"). GCC and clang; other compilers inline as they
 * see fit (the stack budget is measured with arm-none-eabi-gcc). */
#if defined(__GNUC__)
#define EST_NOINLINE __attribute__((noinline))
#else
#define EST_NOINLINE
#endif

#endif
