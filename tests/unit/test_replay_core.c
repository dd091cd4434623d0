/* replay_core's numbers as grip-replay's text gives them: replay_as_printed
 * and replay_time_value (the fast paths without text) against snprintf and
 * strtod, bit for bit, on values the replay writes and on hard cases. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "replay_core.h"

static double by_text(double v, int digits)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    return strtod(buf, NULL);
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* a deterministic generator (xorshift64*) */
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545f4914f6cdd1dull;
}

static void check(double v, int digits, unsigned long *bad)
{
    double a = replay_as_printed(v, digits);
    double b = by_text(v, digits);
    if (!same_bits(a, b)) {
        if (*bad < 5) {
            print_error("%.17g at %d digits: %.17g, text %.17g\n", v, digits, a, b);
        }
        (*bad)++;
    }
}

static void test_as_printed_random(void **state)
{
    unsigned long bad = 0;
    unsigned long n = 0;
    long i;
    (void)state;
    for (i = 0; i < 400000; i++) {
        uint64_t r = rng();
        /* log-uniform magnitudes 1e-30 .. 1e30, both signs */
        double mag = pow(10.0, -30.0 + 60.0 * (double)(r >> 11) / 9007199254740992.0);
        double v = (rng() & 1u) ? -mag : mag;
        float f = (float)v;
        check(v, REPLAY_DIGITS_EST, &bad);
        check((double)f, REPLAY_DIGITS_EST, &bad);
        check((double)f, REPLAY_DIGITS_INPUT, &bad);
        check((double)(int32_t)(r >> 33) / 65536.0, REPLAY_DIGITS_EST, &bad);
        check((double)(int32_t)(r >> 33) / 256.0, REPLAY_DIGITS_EST, &bad);
        n += 5;
    }
    print_message("# replay_as_printed: %lu values, %lu differ from the text\n", n, bad);
    assert_int_equal(bad, 0);
}

static void test_as_printed_hard(void **state)
{
    /* ties and near-ties of the last digit, powers of ten and their
     * neighbours, zeros, the largest and smallest magnitudes */
    unsigned long bad = 0;
    int e;
    int d;
    long m;
    (void)state;
    for (e = -25; e <= 25; e++) {
        double p = pow(10.0, (double)e);
        check(p, 6, &bad);
        check(nextafter(p, 0.0), 6, &bad);
        check(nextafter(p, INFINITY), 6, &bad);
        check(-p, 9, &bad);
        for (m = 100000; m < 1000000; m += 99991) {
            double t = ((double)m + 0.5) * pow(10.0, (double)(e - 5));
            check(t, 6, &bad);
            check(nextafter(t, 0.0), 6, &bad);
            check(nextafter(t, INFINITY), 6, &bad);
        }
    }
    for (d = 0; d < 2; d++) {
        int digits = d ? REPLAY_DIGITS_INPUT : REPLAY_DIGITS_EST;
        check(0.0, digits, &bad);
        check(-0.0, digits, &bad);
        check(0.5, digits, &bad);
        check(2.5, digits, &bad);
        check(1234565.0, digits, &bad);
        check(0.1234565, digits, &bad);
        check(1.0e300, digits, &bad);
        check(4.9e-324, digits, &bad);
        check(3.4028234663852886e38, digits, &bad);
        check(INFINITY, digits, &bad);
        check(-INFINITY, digits, &bad);
    }
    assert_int_equal(bad, 0);
}

static void test_time_value(void **state)
{
    static const int64_t t[] = { 0, 1, 999999, 1000000, 10000, 46408584930, 46468577630, 123456789012345,
                                 -1, -500000, -1000000, -1234567 };
    char buf[64];
    size_t i;
    long k;
    (void)state;
    for (i = 0; i < sizeof t / sizeof t[0]; i++) {
        int64_t s = (t[i] >= 0) ? t[i] / 1000000 : -((-t[i] + 999999) / 1000000);
        snprintf(buf, sizeof buf, "%lld.%06lld", (long long)s, (long long)(t[i] - s * 1000000));
        assert_true(same_bits(replay_time_value(t[i]), strtod(buf, NULL)));
    }
    for (k = 0; k < 200000; k++) {
        int64_t v = (int64_t)(rng() >> 17);
        snprintf(buf, sizeof buf, "%lld.%06lld", (long long)(v / 1000000), (long long)(v % 1000000));
        assert_true(same_bits(replay_time_value(v), strtod(buf, NULL)));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_as_printed_random),
        cmocka_unit_test(test_as_printed_hard),
        cmocka_unit_test(test_time_value),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
