/*
 * q16_inline.h - saturating Q15.16 add/sub/mul/div, inline so that model code
 * pays no call for them. Internal to lib/; the public names are in
 * include/grip/grip_q16.h.
 */
#ifndef GRIP_Q16_INLINE_H
#define GRIP_Q16_INLINE_H

#include <stdint.h>
#include "grip/grip_config.h"
#include "grip/grip_q16.h"

#if GRIP_DEBUG_SATURATION
void grip_debug_saturation_event(const char *op);
#define GRIP_SAT_EVENT(op) grip_debug_saturation_event(op)
#else
#define GRIP_SAT_EVENT(op) ((void)0)
#endif

/* Clamp a wide intermediate to the symmetric Q15.16 range. The in-range
 * test is one unsigned comparison (v + MAX in [0, 2 MAX]): the common path
 * of every saturating operation pays one compare and one branch instead of
 * two of each. v + MAX cannot overflow: every caller's v is within +-2^62. */
static inline grip_q16_t q16_saturate(int64_t v, const char *op)
{
    if ((uint64_t)(v + (int64_t)GRIP_Q16_MAX) <= (uint64_t)2u * (uint64_t)GRIP_Q16_MAX) {
        (void)op;
        return (grip_q16_t)v;
    }
    GRIP_SAT_EVENT(op);
    return (v > 0) ? GRIP_Q16_MAX : GRIP_Q16_MIN;
}

/* Arithmetic right shift with round-half-up. Right shift of a negative
 * value is arithmetic on every supported compiler (checked at compile time
 * in lib/arith/q16.c). */
static inline int64_t q_round_shift(int64_t v, unsigned shift)
{
    return (v + ((int64_t)1 << (shift - 1u))) >> shift;
}

static inline grip_q16_t q16_add(grip_q16_t a, grip_q16_t b)
{
    return q16_saturate((int64_t)a + (int64_t)b, "add");
}

static inline grip_q16_t q16_sub(grip_q16_t a, grip_q16_t b)
{
    return q16_saturate((int64_t)a - (int64_t)b, "sub");
}

static inline grip_q16_t q16_mul(grip_q16_t a, grip_q16_t b)
{
    return q16_saturate(q_round_shift((int64_t)a * (int64_t)b, 16u), "mul");
}

static inline grip_q16_t q16_div(grip_q16_t a, grip_q16_t b)
{
    int64_t num;
    int64_t den;
    if (b == 0) {
        if (a == 0) {
            return 0;
        }
        GRIP_SAT_EVENT("div0");
        return (a > 0) ? GRIP_Q16_MAX : GRIP_Q16_MIN;
    }
    num = (int64_t)a * 65536;
    den = (int64_t)b;
    if (den < 0) {
        num = -num;
        den = -den;
    }
    /* round half away from zero */
    num += (num >= 0) ? (den / 2) : -(den / 2);
    return q16_saturate(num / den, "div");
}

static inline grip_q16_t q16_neg(grip_q16_t a)
{
    return q16_saturate(-(int64_t)a, "neg");
}

static inline grip_q16_t q16_abs(grip_q16_t a)
{
    return (a < 0) ? q16_neg(a) : a;
}

/* Q23.8 <-> Q15.16 format changes. */
static inline grip_q16_t q16_from_ql(grip_q16_t a)
{
    return q16_saturate((int64_t)a * 256, "ql->qs");
}

static inline grip_q16_t q16_to_ql(grip_q16_t a)
{
    return (grip_q16_t)q_round_shift((int64_t)a, 8u);
}

#endif /* GRIP_Q16_INLINE_H */
