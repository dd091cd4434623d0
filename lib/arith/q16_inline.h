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

/* The same operations without a range test, for operands whose ranges the
 * caller has certified (a prepared Magic Formula set, MF_PF_CERT:
 * docs/numerics.md, "Certified operations"): where the exact result is
 * within the range they are q16_mac, q16_msub, q16_mul, q16_add bit for
 * bit. A GRIP_DEBUG_SATURATION build keeps the range test and counts a
 * value outside the range as the event "cert" (answered as the checked
 * operation), so that "0 saturations" also asserts the certificate. */
#if GRIP_DEBUG_SATURATION
#define Q16_CERTIFIED(v) q16_saturate((v), "cert")
#else
#define Q16_CERTIFIED(v) ((grip_q16_t)(v))
#endif

static inline grip_q16_t q16_mac_nt(grip_q16_t c, grip_q16_t a, grip_q16_t b)
{
    return Q16_CERTIFIED((int64_t)c + q16_mul_round(a, b));
}

static inline grip_q16_t q16_msub_nt(grip_q16_t c, grip_q16_t a, grip_q16_t b)
{
    return Q16_CERTIFIED((int64_t)c - q16_mul_round(a, b));
}

static inline grip_q16_t q16_mul_nt(grip_q16_t a, grip_q16_t b)
{
    return Q16_CERTIFIED(q16_mul_round(a, b));
}

static inline grip_q16_t q16_add_nt(grip_q16_t a, grip_q16_t b)
{
    return Q16_CERTIFIED((int64_t)a + (int64_t)b);
}

/* x s for a scale factor s that is exactly 1 in most parameter sets (the
 * lambdas of a Magic Formula set): x 1 = x exactly, so no product then; a
 * comparison and a branch where s is not 1. The bits of q16_mul(x, s). */
static inline grip_q16_t q16_mul_scale(grip_q16_t x, grip_q16_t s)
{
    return (s == 65536) ? x : q16_mul(x, s);
}

/* floor(n / d) for d > 0 and n < d 2^32 (the quotient is below 2^32) as
 * long division (Knuth, TAOCP vol. 2, 4.3.1, algorithm D) in two 16-bit
 * quotient digits, each estimated by a 32 / 32 division by the normalized
 * divisor's top half and corrected at most twice (fixed steps, no loop):
 * n / d exactly, without a 64-bit division. For ARMv6-M (below). */
static inline uint32_t q_udiv64_32_long(uint64_t n, uint32_t d)
{
    uint32_t dn = d;
    unsigned s = 0u;
    uint32_t nh;
    uint32_t nl;
    uint32_t d1;
    uint32_t d0;
    uint32_t q1;
    uint32_t r1;
    uint32_t q0;
    uint32_t r0;
    uint32_t mid;
    /* normalize: the divisor's top bit set, five fixed steps */
    if (dn <= 0xFFFFu) { s += 16u; dn <<= 16; }
    if (dn <= 0xFFFFFFu) { s += 8u; dn <<= 8; }
    if (dn <= 0xFFFFFFFu) { s += 4u; dn <<= 4; }
    if (dn <= 0x3FFFFFFFu) { s += 2u; dn <<= 2; }
    if (dn <= 0x7FFFFFFFu) { s += 1u; dn <<= 1; }
    n <<= s;                          /* < dn 2^32 <= 2^64: no bit lost */
    nh = (uint32_t)(n >> 32);         /* < dn */
    nl = (uint32_t)n;
    d1 = dn >> 16;                    /* >= 2^15 */
    d0 = dn & 0xFFFFu;
    /* first digit: (nh, top half of nl) / dn; q1 < 2^17 */
    q1 = nh / d1;
    r1 = nh - (q1 * d1);
    if ((q1 > 0xFFFFu) || ((q1 * d0) > ((r1 << 16) | (nl >> 16)))) {
        q1 -= 1u;
        r1 += d1;
        if ((r1 <= 0xFFFFu) && ((q1 > 0xFFFFu) || ((q1 * d0) > ((r1 << 16) | (nl >> 16))))) {
            q1 -= 1u;
        }
    }
    mid = ((nh << 16) | (nl >> 16)) - (q1 * dn);   /* the remainder, < dn */
    /* second digit: (mid, bottom half of nl) / dn */
    q0 = mid / d1;
    r0 = mid - (q0 * d1);
    if ((q0 > 0xFFFFu) || ((q0 * d0) > ((r0 << 16) | (nl & 0xFFFFu)))) {
        q0 -= 1u;
        r0 += d1;
        if ((r0 <= 0xFFFFu) && ((q0 > 0xFFFFu) || ((q0 * d0) > ((r0 << 16) | (nl & 0xFFFFu))))) {
            q0 -= 1u;
        }
    }
    return (q1 << 16) | q0;
}

/* q_udiv64_32_long out of line (lib/arith/q16.c): one copy in the image */
uint32_t grip_q16_i_udiv64_32(uint64_t n, uint32_t d);

/* floor(n / d) for d > 0 and n < d 2^32: the divisions of q16_div and of
 * the atan and atan2 kernels. On ARMv6-M (Cortex-M0/M0+: no divide
 * instruction) n / d is libgcc's 64 / 64 division, one quotient bit per
 * step (~450 instructions for the kernels' 30-bit quotients); there it is
 * grip_q16_i_udiv64_32, the same quotient. */
static inline uint64_t q_udiv64_32(uint64_t n, uint32_t d)
{
#if defined(__ARM_ARCH_6M__)
    return (uint64_t)grip_q16_i_udiv64_32(n, d);
#else
    return n / d;
#endif
}

/* The magnitude of a / b in Q15.16, rounded half away from zero, from the
 * magnitudes ua = |a|, ub = |b| > 0: floor((ua 2^16 + floor(ub / 2)) /
 * ub). On ARMv6-M by q_udiv64_32 where it fits 32 bits, else 2^32 - 1
 * (every caller saturates it or has excluded such a quotient). */
static inline uint64_t q16_div_mag(uint32_t ua, uint32_t ub)
{
    uint64_t un = ((uint64_t)ua << 16) + ((uint64_t)ub >> 1);
#if defined(__ARM_ARCH_6M__)
    if ((uint32_t)(un >> 32) >= ub) {
        return 0xFFFFFFFFu;           /* the quotient is 2^32 or more */
    }
#endif
    return q_udiv64_32(un, ub);
}

/* round(a 2^16 / b), half away from zero, for b != 0: the quotient that
 * q16_div, q16_div_lim and q16_div_nt form before their range tests (or
 * instead of them). ARMv6-M: q16_div_mag of the magnitudes with the sign
 * of a / b (no 64-bit signed division); elsewhere the signed 64-bit
 * division (the same value; on x86-64 the bench's r_div case is 38
 * instructions with it, 44 with the magnitudes). */
static inline int64_t q16_div_signed(grip_q16_t a, grip_q16_t b)
{
#if defined(__ARM_ARCH_6M__)
    uint32_t ua = (a < 0) ? (0u - (uint32_t)a) : (uint32_t)a;
    uint32_t ub = (b < 0) ? (0u - (uint32_t)b) : (uint32_t)b;
    int64_t q = (int64_t)q16_div_mag(ua, ub);
    return ((a < 0) != (b < 0)) ? -q : q;
#else
    int64_t num = (int64_t)a * 65536;
    int64_t den = (int64_t)b;
    if (den < 0) {
        num = -num;
        den = -den;
    }
    num += (num >= 0) ? (den / 2) : -(den / 2);
    /* grip-deviation: clang-analyzer-core.DivideZero false positive: no caller passes b = 0 (q16_div tests it first, q16_div_lim's limit test takes it, q16_div_nt's precondition excludes it) */
    return num / den;
#endif
}

static inline grip_q16_t q16_div(grip_q16_t a, grip_q16_t b)
{
    if (b == 0) {
        if (a == 0) {
            return 0;
        }
        GRIP_SAT_EVENT("div0");
        return (a > 0) ? GRIP_Q16_MAX : GRIP_Q16_MIN;
    }
    return q16_saturate(q16_div_signed(a, b), "div");
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

/* a / b limited to +-lim, lim >= 1 (lib/mf's mf_div_lim): 0 when a = 0;
 * the signed lim where |b| <= q16_div(|a|, lim) (|.| as q16_abs); else
 * q16_div(a, b). The same values as that composition, with the limit's test
 * as a product - |b| lim <= |a| 2^16 + floor(lim / 2), the integer form of
 * |b| <= floor((|a| 2^16 + floor(lim / 2)) / lim), no division - and the
 * quotient without q16_div's zero and range tests: where it is formed,
 * |b| > 0 and |a / b| < lim + 1/2 (below 2^15 for every lim in use). */
static inline grip_q16_t q16_div_lim(grip_q16_t a, grip_q16_t b, grip_q16_t lim)
{
    grip_q16_t aa = q16_abs(a);
    grip_q16_t ab;
    if (aa == 0) {
        return 0;
    }
    ab = q16_abs(b);
    if (((int64_t)ab * (int64_t)lim) <= (((int64_t)aa * 65536) + (int64_t)(lim / 2))) {
        return ((a < 0) != (b < 0)) ? q16_neg(lim) : lim;
    }
    return (grip_q16_t)q16_div_signed(a, b);
}

/* a / b where the caller knows b != 0 and |a / b| < 32767 (its argument
 * stated where it is used; the rounded quotient is then within the range):
 * q16_div's value without its zero and range tests. A GRIP_DEBUG_SATURATION build checks the precondition: a
 * violation is counted as the event "div_nt" and answered by q16_div. */
static inline grip_q16_t q16_div_nt(grip_q16_t a, grip_q16_t b)
{
#if GRIP_DEBUG_SATURATION
    {
        int64_t ua = (a < 0) ? -(int64_t)a : (int64_t)a;
        int64_t ub = (b < 0) ? -(int64_t)b : (int64_t)b;
        if (ua >= (ub * 32767)) {       /* b = 0, or |a / b| >= 32767 */
            GRIP_SAT_EVENT("div_nt");
            return q16_div(a, b);
        }
    }
#endif
    return (grip_q16_t)q16_div_signed(a, b);
}

/* a / b where the caller knows 0 <= a <= b, b > 0 (a ratio of magnitudes,
 * the smaller over the larger): the quotient is within [0, 1], so
 * q16_div's zero and range tests go; its values. A GRIP_DEBUG_SATURATION
 * build checks the precondition: a violation is counted as the event
 * "div_le1" and answered by q16_div. */
static inline grip_q16_t q16_div_le1(grip_q16_t a, grip_q16_t b)
{
#if GRIP_DEBUG_SATURATION
    if ((a < 0) || (b <= 0) || (a > b)) {
        GRIP_SAT_EVENT("div_le1");
        return q16_div(a, b);
    }
#endif
    return (grip_q16_t)q16_div_mag((uint32_t)a, (uint32_t)b);
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
