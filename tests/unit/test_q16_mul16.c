/*
 * test_q16_mul16.c - the Cortex-M0 / M0+ forms of the Q15.16 products
 * (lib/arith/q16_inline.h under __ARM_ARCH_6M__: q16_mul_round and
 * q_mul_wide from four 16 x 16 products instead of a 64-bit multiply)
 * compiled on the host and compared with the 64-bit forms,
 * (a b + 2^15) >> 16 and a b, on edge values and 20 million pseudo-random
 * pairs of every magnitude. The target test
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edges),
        cmocka_unit_test(test_random_pairs),
    };
    return cmocka_run_group_tests_name("q16_mul16", tests, NULL, NULL);
}
