/*
 * test_q16_mul16.c - the Cortex-M0 / M0+ forms of the Q15.16 products
 * and divisions (lib/arith/q16_inline.h under __ARM_ARCH_6M__:
 * q16_mul_round and q_mul_wide from four 16 x 16 products instead of a
 * 64-bit multiply; q_udiv64_32 as long division in two 16-bit digits,
 * q_udiv64_32_long, and q16_div built on it instead of libgcc's 64-bit
 * division) compiled on the
 * host and compared with the 64-bit forms, (a b + 2^15) >> 16, a b, n / d
 * and q16_div's 64-bit form, on edge values and millions of pseudo-random
 * arguments of every magnitude. The target test
 * (tests/target) checks the same form on the emulated Cortex-M0+; this one
 * runs it in every host build.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

/* Select the ARMv6-M branch of q16_inline.h in this translation unit only. */
#ifndef __ARM_ARCH_6M__
#define __ARM_ARCH_6M__ 1
#endif
#include "q16_inline.h"

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static uint32_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 16);
}

static int64_t product_64(int32_t a, int32_t b)
{
    return ((int64_t)a * (int64_t)b + 32768) >> 16;
}

static void check(int32_t a, int32_t b)
{
    int64_t got = q16_mul_round(a, b);
    int64_t want = product_64(a, b);
    if (got != want) {
        fail_msg("q16_mul_round(%ld, %ld) = %lld, 64-bit product %lld", (long)a, (long)b, (long long)got,
                 (long long)want);
    }
    got = q_mul_wide(a, b);
    want = (int64_t)a * (int64_t)b;
    if (got != want) {
        fail_msg("q_mul_wide(%ld, %ld) = %lld, 64-bit product %lld", (long)a, (long)b, (long long)got,
                 (long long)want);
    }
}

static void test_edges(void **s)
{
    static const int32_t e[] = {0, 1, -1, 2, -2, 0x7FFF, -0x8000, 0x8000, -0x8001, 0xFFFF, -0xFFFF,
                                0x10000, -0x10000, 0x10001, -0x10001, 0x7FFF8000, -0x7FFF8000,
                                0x7FFF0000, -0x7FFF0000, INT32_MAX, -INT32_MAX, INT32_MIN};
    size_t i;
    size_t j;
    (void)s;
    for (i = 0; i < sizeof e / sizeof e[0]; ++i) {
        for (j = 0; j < sizeof e / sizeof e[0]; ++j) {
            check(e[i], e[j]);
        }
    }
}

static void test_random_pairs(void **s)
{
    uint32_t k;
    (void)s;
    for (k = 0; k < 20000000u; ++k) {
        int32_t a = (int32_t)rng();
        int32_t b = (int32_t)rng();
        /* every magnitude: shift each operand right by 0 - 31 bits */
        a >>= (rng() & 31u);
        b >>= (rng() & 31u);
        check(a, b);
    }
    print_message("# q16_mul_round, q_mul_wide (ARMv6-M forms): 20000000 random pairs equal to the 64-bit products\n");
}

static void check_udiv(uint64_t n, uint32_t d)
{
    uint64_t got;
    uint64_t want;
    if ((n >> 32) >= d) {
        return;   /* outside the precondition: the quotient needs more than 32 bits */
    }
    got = q_udiv64_32_long(n, d);
    want = n / d;
    if (got != want) {
        fail_msg("q_udiv64_32_long(%llu, %lu) = %llu, 64-bit quotient %llu", (unsigned long long)n, (unsigned long)d,
                 (unsigned long long)got, (unsigned long long)want);
    }
}

/* q16_div's 64-bit form (the other targets'): round half away from zero,
 * clamped to the symmetric range */
static int32_t div_64(int32_t a, int32_t b)
{
    int64_t num = (int64_t)a * 65536;
    int64_t den = b;
    int64_t q;
    if (den < 0) {
        num = -num;
        den = -den;
    }
    num += (num >= 0) ? (den / 2) : -(den / 2);
    q = num / den;
    return (q > INT32_MAX) ? INT32_MAX : ((q < -INT32_MAX) ? -INT32_MAX : (int32_t)q);
}

static void check_div(int32_t a, int32_t b)
{
    int32_t got;
    int32_t want;
    if (b == 0) {
        return;
    }
    got = q16_div(a, b);
    want = div_64(a, b);
    if (got != want) {
        fail_msg("q16_div(%ld, %ld) = %ld, 64-bit form %ld", (long)a, (long)b, (long)got, (long)want);
    }
}

static void test_udiv(void **s)
{
    static const uint32_t de[] = {1u, 2u, 3u, 0x7FFFu, 0x8000u, 0xFFFFu, 0x10000u, 0x10001u, 0xFFFFFFu,
                                  0x1000000u, 0x7FFFFFFFu, 0x80000000u, 0x80000001u, 0xFFFF0000u,
                                  0xFFFF8000u, 0xFFFFFFFEu, 0xFFFFFFFFu};
    size_t i;
    uint32_t k;
    (void)s;
    for (i = 0; i < sizeof de / sizeof de[0]; ++i) {
        uint64_t d = de[i];
        uint64_t top = (d << 32) - 1u;   /* the largest n with a 32-bit quotient */
        check_udiv(0u, de[i]);
        check_udiv(d - 1u, de[i]);
        check_udiv(d, de[i]);
        check_udiv(top, de[i]);
        check_udiv(top - d, de[i]);
        check_udiv(top / 2u, de[i]);
        check_udiv(((uint64_t)1 << 46) + (d >> 1), de[i]);
    }
    for (k = 0; k < 20000000u; ++k) {
        /* d of every magnitude; n = q d + r with q < 2^32, r < d */
        uint32_t d = rng() >> (rng() & 31u);
        uint64_t q;
        uint64_t r;
        if (d == 0u) {
            d = 1u;
        }
        q = (uint64_t)(rng() >> (rng() & 31u));
        r = (uint64_t)rng() % d;
        check_udiv(q * d + r, d);
    }
    print_message("# q_udiv64_32_long (ARMv6-M form): edges and 20000000 random quotients equal to n / d\n");
}

static void test_div(void **s)
{
    static const int32_t e[] = {0, 1, -1, 2, -2, 3, 0x7FFF, -0x8000, 0x8000, 0xFFFF, -0xFFFF, 0x10000,
                                -0x10000, 0x10001, 0x18000, -0x18000, 0x7FFF8000, -0x7FFF8000, INT32_MAX,
                                -INT32_MAX, INT32_MIN};
    size_t i;
    size_t j;
    uint32_t k;
    (void)s;
    for (i = 0; i < sizeof e / sizeof e[0]; ++i) {
        for (j = 0; j < sizeof e / sizeof e[0]; ++j) {
            check_div(e[i], e[j]);
        }
    }
    for (k = 0; k < 10000000u; ++k) {
        int32_t a = (int32_t)rng();
        int32_t b = (int32_t)rng();
        a >>= (rng() & 31u);
        b >>= (rng() & 31u);
        check_div(a, b);
        /* exact halves: a 2^16 = (m + 1/2) b, the rounding's ties */
        if ((b > -0x4000) && (b < 0x4000) && ((b & 1) == 0) && (b != 0)) {
            check_div((int32_t)(((int64_t)(a >> 16) * b + b / 2) / 65536), b);
        }
    }
    print_message("# q16_div (ARMv6-M form): edges and 10000000 random pairs equal to the 64-bit form\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edges),
        cmocka_unit_test(test_random_pairs),
        cmocka_unit_test(test_udiv),
        cmocka_unit_test(test_div),
    };
    return cmocka_run_group_tests_name("q16_mul16", tests, NULL, NULL);
}
