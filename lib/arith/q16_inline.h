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

/* Inline whatever the optimizer's estimate: the rounded product below is
 * shared by q16_mul, q16_mac, q16_msub and q16_mul_unit, and gcc -Os (the
 * Cortex-M0+ firmware) made it a function of its own that each of them
 * called. */
#if defined(__GNUC__)
#define GRIP_Q16_KINLINE inline __attribute__((always_inline))
#else
#define GRIP_Q16_KINLINE inline
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

/* The exact 64-bit product of two int32 values. On ARMv6-M (Cortex-M0/M0+,
 * 32 x 32 -> 32 multiplies only) (int64_t)a * b is a call to libgcc's
 * __aeabi_lmul (64 x 64); there it is formed from 16-bit halves,
 * a = ah 2^16 + al with 0 <= al < 2^16:
 * a b = ah bh 2^32 + (ah bl + al bh) 2^16 + al bl, each product within its
 * 32-bit type (|ah bh| <= 2^30, |ah bl| < 2^31, al bl < 2^32): four MULS
 * and 64-bit additions, the same value. */
static inline int64_t q_mul_wide(int32_t a, int32_t b)
{
#if defined(__ARM_ARCH_6M__)
    int32_t ah = a >> 16;
    int32_t bh = b >> 16;
    uint32_t al = (uint32_t)a & 0xFFFFu;
    uint32_t bl = (uint32_t)b & 0xFFFFu;
    int64_t mid = (int64_t)(ah * (int32_t)bl) + (int64_t)((int32_t)al * bh);
    return ((int64_t)(ah * bh) * 4294967296) + (mid * 65536) + (int64_t)(al * bl);
#else
    return (int64_t)a * (int64_t)b;
#endif
}

/* round(a b / 2^16) before saturation: (a b + 2^15) >> 16. */
static GRIP_Q16_KINLINE int64_t q16_mul_round(grip_q16_t a, grip_q16_t b)
{
#if defined(__ARM_ARCH_6M__)
    /* ARMv6-M (Cortex-M0/M0+) multiplies 32 x 32 -> 32 only: the 64-bit
     * product is a call to libgcc's __aeabi_lmul (64 x 64). The same value
     * from 16-bit halves, a = ah 2^16 + al with 0 <= al < 2^16:
     * a b = ah bh 2^32 + (ah bl + al bh) 2^16 + al bl, so
     * (a b + 2^15) >> 16 = ah bh 2^16 + ah bl + al bh + ((al bl + 2^15) >> 16)
     * exactly; each product fits its 32-bit type (|ah bh| <= 2^30,
     * |ah bl| < 2^31, al bl + 2^15 < 2^32). Four MULS instead of the call;
     * the host and target builds give the same bits (tests/target). */
    int32_t ah = a >> 16;
    int32_t bh = b >> 16;
    uint32_t al = (uint32_t)a & 0xFFFFu;
    uint32_t bl = (uint32_t)b & 0xFFFFu;
    int64_t hi = (int64_t)(ah * bh) * 65536;
    int32_t m1 = ah * (int32_t)bl;
    int32_t m2 = (int32_t)al * bh;
    uint32_t lo = ((al * bl) + 0x8000u) >> 16;
    return hi + (int64_t)m1 + (int64_t)m2 + (int64_t)lo;
#else
    return q_round_shift((int64_t)a * (int64_t)b, 16u);
#endif
}

static inline grip_q16_t q16_mul(grip_q16_t a, grip_q16_t b)
{
    return q16_saturate(q16_mul_round(a, b), "mul");
}

/* c + a b (c in the format of b) with one rounding and one saturation.
 * c is an integer in the units of the result, so c + round(a b / 2^16)
 * = round((c 2^16 + a b) / 2^16): the bits of q16_add(c, q16_mul(a, b))
 * wherever that product does not saturate, and where it does, the exact
 * sum clamped once. |c + round(a b / 2^16)| < 2^47: no 64-bit overflow. */
static inline grip_q16_t q16_mac(grip_q16_t c, grip_q16_t a, grip_q16_t b)
{
    return q16_saturate((int64_t)c + q16_mul_round(a, b), "mac");
}

/* c - a b, likewise: q16_sub(c, q16_mul(a, b)) wherever that product does
 * not saturate. (c - round(a b), not c + round(-a b): the rounding of a
 * half differs.) */
static inline grip_q16_t q16_msub(grip_q16_t c, grip_q16_t a, grip_q16_t b)
{
    return q16_saturate((int64_t)c - q16_mul_round(a, b), "msub");
}

/* u b where the caller knows |u| <= 1 (u Q15.16, |u| <= 65536): then
 * |round(u b / 2^16)| <= |b| <= GRIP_Q16_MAX, so the product cannot leave
 * the range and has no range test; the bits of q16_mul(u, b). A
 * GRIP_DEBUG_SATURATION build checks the precondition: a violation is
 * counted as the event "mul_unit" and the product saturated as q16_mul's. */
static inline grip_q16_t q16_mul_unit(grip_q16_t u, grip_q16_t b)
{
#if GRIP_DEBUG_SATURATION
    if ((u > 65536) || (u < -65536)) {
        GRIP_SAT_EVENT("mul_unit");
        return q16_mul(u, b);
    }
#endif
    return (grip_q16_t)q16_mul_round(u, b);
}

/* x s for a scale factor s that is exactly 1 in most parameter sets (the
 * lambdas of a Magic Formula set): x 1 = x exactly, so no product then; a
 * comparison and a branch where s is not 1. The bits of q16_mul(x, s). */
static inline grip_q16_t q16_mul_scale(grip_q16_t x, grip_q16_t s)
{
    return (s == 65536) ? x : q16_mul(x, s);
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

/* -a: the range is symmetric, so only INT32_MIN (an input, never a result
 * of these operations) leaves it; that one test instead of a 64-bit
 * negation and range test, the same values. */
static inline grip_q16_t q16_neg(grip_q16_t a)
{
    if (a == INT32_MIN) {
        GRIP_SAT_EVENT("neg");
        return GRIP_Q16_MAX;
    }
    return -a;
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
