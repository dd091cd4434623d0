/*
 * grip_q16.h - fixed-point primitives on Q15.16 (int32_t, 1 LSB = 2^-16).
 *
 * Integer-only, available in both builds; the fixed build's models are
 * written on top of them. Every function saturates instead of wrapping: a
 * result beyond [GRIP_Q16_MIN, GRIP_Q16_MAX] returns the nearest bound and
 * (in a GRIP_DEBUG_SATURATION build) is counted. Error bounds are measured
 * against numpy float64 over each function's whole input domain by
 * tests/unit/test_q16.c and documented in docs/numerics.md.
 *
 * Scaling: unless stated, inputs and outputs are Q15.16. The multiply and
 * divide work for any second format: grip_q16_mul(a_Q16, b_Qn) is Qn and
 * grip_q16_div(a_Qn, b_Qm) is Q(16+n-m).
 */
#ifndef GRIP_Q16_H
#define GRIP_Q16_H

#include <stdint.h>

typedef int32_t grip_q16_t;

#define GRIP_Q16_ONE   ((grip_q16_t)65536)
#define GRIP_Q16_MAX   ((grip_q16_t)INT32_MAX)
#define GRIP_Q16_MIN   ((grip_q16_t)(-INT32_MAX))  /* symmetric: -MIN is representable */
#define GRIP_Q16_PI    ((grip_q16_t)205887)        /* round(pi * 2^16) */
#define GRIP_Q16_PI_2  ((grip_q16_t)102944)        /* round(pi/2 * 2^16) */

/* a + b, a - b, saturating. */
grip_q16_t grip_q16_add(grip_q16_t a, grip_q16_t b);
grip_q16_t grip_q16_sub(grip_q16_t a, grip_q16_t b);
/* round(a * b / 2^16), saturating. Exact to 0.5 LSB when not saturated. */
grip_q16_t grip_q16_mul(grip_q16_t a, grip_q16_t b);
/* round(a * 2^16 / b), saturating; b == 0 gives +-MAX (0 for a == 0) and
 * counts as a saturation. Exact to 0.5 LSB when not saturated. */
grip_q16_t grip_q16_div(grip_q16_t a, grip_q16_t b);
/* sqrt(a) for a >= 0 (a < 0 gives 0, counted as saturation). 0.5 LSB. */
grip_q16_t grip_q16_sqrt(grip_q16_t a);
/* atan(a), output in [-pi/2, pi/2] rad. Whole int32 domain. */
grip_q16_t grip_q16_atan(grip_q16_t a);
/* atan2(y, x) in (-pi, pi]; y and x in any one common format;
 * atan2(0, 0) = 0. */
grip_q16_t grip_q16_atan2(grip_q16_t y, grip_q16_t x);
/* sin(a), cos(a) of a in rad, whole int32 domain (|a| < 32768 rad). */
grip_q16_t grip_q16_sin(grip_q16_t a);
grip_q16_t grip_q16_cos(grip_q16_t a);
/* Both of them from one argument reduction: *s, *c exactly as grip_q16_sin(a),
 * grip_q16_cos(a). s and c must be valid. */
void grip_q16_sincos(grip_q16_t a, grip_q16_t *s, grip_q16_t *c);
/* exp(a); saturates to MAX for a > ln(32768) ~ 10.397, 0 for a < -11.1. */
grip_q16_t grip_q16_exp(grip_q16_t a);
/* Natural logarithm of a > 0; a <= 0 gives MIN (counted as saturation). */
grip_q16_t grip_q16_log(grip_q16_t a);

/* Saturation events since the last reset (GRIP_DEBUG_SATURATION builds;
 * always 0 otherwise) and the name of the first saturating operation. */
uint32_t grip_debug_saturation_count(void);
const char *grip_debug_saturation_first(void);
void grip_debug_saturation_reset(void);

#endif /* GRIP_Q16_H */
