/*
 * test_can_decode.c - the CAN signal decoder against cantools (golden files
 * from tools/grip_tools/golden/can.py):
 *   - raw extraction: every byte order x signedness x length 1..64, several
 *     start bits, 8- and 64-byte payloads: bit-exact;
 *   - scaling and range checks of synthetic signals (QS and QL inputs);
 *   - every frame of the RAV4 log with the compiled-in table;
 * plus frame checks (DLC, Toyota checksum), the table consistency check and
 * the text form of tables.
 *
 * Tolerance of a decoded value v against cantools' float64 w (SI), per input
 * with terms of shift s and raw values r_i:
 *   quantisation of K and C:  q = sum_i (|r_i| + 1) 2^-(s+1)
 *   fixed build:  |v - w| <= 2^-F / 2 + q + 2^-50 |w|   (F = 16 QS, 8 QL: one rounding)
 *   float build:  |v - w| <= 2^-24 |w| + q + 2^-50 |w|  (one float rounding)
 * (2^-50 |w| covers cantools' own float64 rounding.)
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "grip/grip_can.h"
#include "grip/grip_signals.h"
#include "golden.h"

#define RAV4_SIGTAB "tests/data/comma2k19-rav4/rav4.sigtab"

#if GRIP_ARITH_FIXED
static double frac_lsb(uint32_t input)
{
    return grip_input_is_ql(input) ? 1.0 / 256.0 : 1.0 / 65536.0;
}
#endif

static double to_si(grip_real_t v, uint32_t input)
{
#if GRIP_ARITH_FIXED
    return (double)v * frac_lsb(input);
#else
    (void)input;
    return (double)v;
#endif
}

static double bound_of(double want, double q, uint32_t input)
{
#if GRIP_ARITH_FIXED
    return 0.5 * frac_lsb(input) + q + ldexp(fabs(want), -50);
#else
    (void)input;
    return ldexp(fabs(want), -24) + q + ldexp(fabs(want), -50);
#endif
}

static int hex_bytes(const char *hex, uint8_t *out, int max)
{
    int n = 0;
    while (hex[0] != '\0' && hex[1] != '\0' && n < max) {
        unsigned v;
        if (sscanf(hex, "%2x", &v) != 1) {
            return -1;
        }
        out[n++] = (uint8_t)v;
        hex += 2;
    }
    return n;
}

/* ---- raw extraction -------------------------------------------------------- */

static void test_raw_vs_cantools(void **state)
{
    golden_file g;
    long n = 0;
    long bad = 0;
    int seen[2][2][65];
    int lengths = 0;
    int i;
    int j;
    int k;
    (void)state;
    memset(seen, 0, sizeof seen);
    assert_int_equal(golden_open(&g, "can_raw.txt"), 0);
    while (golden_next(&g) > 0) {
        uint8_t data[64];
        uint32_t order = (uint32_t)golden_num(&g, 0);
        uint32_t sgn = (uint32_t)golden_num(&g, 1);
        uint32_t length = (uint32_t)golden_num(&g, 2);
        uint32_t start = (uint32_t)golden_num(&g, 3);
        int paylen = (int)golden_num(&g, 4);
        uint64_t want;
        uint64_t got = 1;
        assert_int_equal(hex_bytes(g.field[5], data, 64), paylen);
        want = sgn ? (uint64_t)strtoll(g.field[6], NULL, 10) : strtoull(g.field[6], NULL, 10);
        assert_int_equal(grip_can_extract(data, (uint32_t)paylen, start, length, order, sgn, &got), GRIP_OK);
        if (got != want) {
            if (bad++ < 5) {
                print_message("# mismatch order %u signed %u length %u start %u: got %llu want %s\n", order, sgn,
                              length, start, (unsigned long long)got, g.field[6]);
            }
        }
        seen[order][sgn][length] = 1;
        n++;
    }
    golden_close(&g);
    for (i = 0; i < 2; i++) {
        for (j = 0; j < 2; j++) {
            for (k = 1; k <= 64; k++) {
                lengths += seen[i][j][k];
            }
        }
    }
    print_message("# raw extraction: %ld frames, %d of 256 order/sign/length combinations, %ld mismatches\n", n,
                  lengths, bad);
    assert_int_equal(lengths, 256);
    assert_true(n > 5000);
    assert_int_equal(bad, 0);
}

static void test_extract_rejects_bits_beyond_payload(void **state)
{
    uint8_t d[8] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF };
    uint64_t raw = 7;
    (void)state;
    /* Intel: bits 60..67 need 9 bytes */
    assert_int_equal(grip_can_extract(d, 8, 60, 8, GRIP_CAN_INTEL, 0, &raw), GRIP_ERR_INPUT);
    assert_true(raw == 0);
    /* Motorola from bit 63 (MSB of byte 7) with 9 bits runs into byte 8 */
    assert_int_equal(grip_can_extract(d, 8, 63, 9, GRIP_CAN_MOTOROLA, 0, &raw), GRIP_ERR_INPUT);
    /* the same signal fits a DLC of 8 only, not 7 */
    assert_int_equal(grip_can_extract(d, 7, 7, 64, GRIP_CAN_MOTOROLA, 0, &raw), GRIP_ERR_INPUT);
    assert_int_equal(grip_can_extract(d, 8, 7, 64, GRIP_CAN_MOTOROLA, 0, &raw), GRIP_OK);
    assert_true(raw == UINT64_MAX);
    assert_int_equal(grip_can_extract(d, 8, 0, 0, GRIP_CAN_INTEL, 0, &raw), GRIP_ERR_PARAM);
    assert_int_equal(grip_can_extract(d, 8, 0, 65, GRIP_CAN_INTEL, 0, &raw), GRIP_ERR_PARAM);
    assert_int_equal(grip_can_extract(d, 8, 0, 8, 2, 0, &raw), GRIP_ERR_PARAM);
    assert_int_equal(grip_can_extract(NULL, 8, 0, 8, 0, 0, &raw), GRIP_ERR_NULL);
    assert_int_equal(grip_can_extract(d, 8, 0, 8, 0, 0, NULL), GRIP_ERR_NULL);
}

/* ---- scaling ----------------------------------------------------------------------- */

static void test_scaling_vs_cantools(void **state)
{
    golden_file g;
    err_stats qs;
    err_stats ql;
    long n = 0;
    long viol = 0;
    long flag_bad = 0;
    long out_of_range = 0;
    double worst_ratio = 0.0;
    (void)state;
    err_init(&qs, "scaling QS inputs vs cantools", 1.0);
    err_init(&ql, "scaling QL inputs vs cantools", 1.0);
    assert_int_equal(golden_open(&g, "can_scale.txt"), 0);
    while (golden_next(&g) > 0) {
        grip_can_message_t m;
        grip_can_signal_t s;
        grip_can_table_t t;
        grip_can_frame_t f;
        grip_can_value_t v;
        uint32_t input = (uint32_t)golden_num(&g, 0);
        double want = strtod(g.field[13], NULL);
        int in_range = (int)golden_num(&g, 14);
        int fits = (int)golden_num(&g, 15);
        int64_t raw = strtoll(g.field[12], NULL, 10);
        uint8_t expect_fault;
        memset(&m, 0, sizeof m);
        memset(&s, 0, sizeof s);
        memset(&f, 0, sizeof f);
        m.name = "M";
        m.id = 1;
        m.period_us = 10000;
        m.n_signals = 1;
        m.len = 8;
        s.name = "S";
        s.input = (uint8_t)input;
        s.shift = (uint8_t)golden_num(&g, 1);
        s.k_mul = (int32_t)strtol(g.field[2], NULL, 10);
        s.c_add = strtoll(g.field[3], NULL, 10);
        s.raw_min = strtoll(g.field[4], NULL, 10);
        s.raw_max = strtoll(g.field[5], NULL, 10);
        s.start = (uint16_t)golden_num(&g, 6);
        s.length = (uint8_t)golden_num(&g, 7);
        s.order = (uint8_t)golden_num(&g, 8);
        s.is_signed = (uint8_t)golden_num(&g, 9);
        t.name = "case";
        t.messages = &m;
        t.signals = &s;
        t.n_messages = 1;
        t.n_signals = 1;
        if (grip_can_table_check(&t, NULL) != GRIP_OK) {
            fail_msg("golden line %lu: table check refuses shift %s K %s C %s", g.lineno, g.field[1], g.field[2],
                     g.field[3]);
        }
        f.id = 1;
        f.len = 8;
        assert_int_equal(hex_bytes(g.field[11], f.data, 8), 8);
        assert_int_equal(grip_can_decode_signal(&t, 0, &f, &v), GRIP_OK);
        assert_true((int64_t)v.raw_bits == raw);
#if GRIP_ARITH_FIXED
        expect_fault = (in_range && fits) ? GRIP_SIG_OK : GRIP_SIG_RANGE;
#else
        (void)fits;
        expect_fault = in_range ? GRIP_SIG_OK : GRIP_SIG_RANGE;
#endif
        if (v.fault != expect_fault) {
            if (flag_bad++ < 5) {
                print_message("# flag mismatch: raw %s range [%s, %s] fault %u want %u\n", g.field[12], g.field[4],
                              g.field[5], v.fault, expect_fault);
            }
        }
        if (v.fault == GRIP_SIG_OK && expect_fault == GRIP_SIG_OK) {
            double got = to_si(v.value, input);
            double q = ((double)llabs(raw) + 1.0) * ldexp(1.0, -(int)s.shift - 1);
            double b = bound_of(want, q, input);
            err_add(grip_input_is_ql(input) ? &ql : &qs, got, want, (double)raw, (double)s.shift, 0.0);
            if (!(fabs(got - want) <= b)) {
                viol++;
            }
            if (fabs(got - want) / b > worst_ratio) {
                worst_ratio = fabs(got - want) / b;
            }
        } else {
            assert_true(v.value == 0);   /* never a number when flagged */
            out_of_range++;
        }
        n++;
    }
    golden_close(&g);
    err_print(&qs, "SI");
    err_print(&ql, "SI");
    print_message("# scaling: %ld values (%ld flagged out of range), worst error = %.3f of its bound, "
                  "%ld bound violations, %ld flag mismatches\n", n, out_of_range, worst_ratio, viol, flag_bad);
    assert_true(n > 2000);
    assert_true(out_of_range > 100);
    assert_true(qs.n > 1000 && ql.n > 200);
    assert_int_equal(viol, 0);
    assert_int_equal(flag_bad, 0);
}

/* ---- the RAV4 log ------------------------------------------------------------------- */

static double input_q(const grip_can_table_t *t, uint32_t msg, uint32_t input)
{
    const grip_can_message_t *m = &t->messages[msg];
    double q = 0.0;
    uint32_t i;
    for (i = 0; i < m->n_signals; i++) {
        const grip_can_signal_t *s = &t->signals[m->first_signal + i];
        if (s->input == input && s->role == GRIP_CAN_ROLE_VALUE) {
            q += (ldexp(1.0, s->length) + 1.0) * ldexp(1.0, -(int)s->shift - 1);
        }
    }
    return q;
}

static void test_rav4_log_vs_cantools(void **state)
{
    const grip_can_table_t *t = &grip_can_table_rav4;
    golden_file g;
    err_stats st[GRIP_IN_COUNT];
    long n = 0;
    long viol = 0;
    long flag_bad = 0;
    long csum_checked = 0;
    uint32_t i;
    (void)state;
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        err_init(&st[i], grip_input_name(i), 1.0);
    }
    assert_int_equal(grip_can_table_check(t, NULL), GRIP_OK);
    assert_int_equal(golden_open(&g, "can_rav4.txt"), 0);
    while (golden_next(&g) > 0) {
        grip_can_frame_t f;
        grip_real_t v = 1;
        uint8_t fault = 99;
        int32_t msg;
        uint32_t input = (uint32_t)golden_num(&g, 4);
        double want = strtod(g.field[5], NULL);
        uint8_t want_fault = (uint8_t)golden_num(&g, 6);
        int csum_ok = (int)golden_num(&g, 7);
        memset(&f, 0, sizeof f);
        f.id = (uint32_t)golden_num(&g, 1);
        f.len = (uint8_t)golden_num(&g, 2);
        assert_int_equal(hex_bytes(g.field[3], f.data, 64), f.len);
        msg = grip_can_find_message(t, f.id);
        assert_true(msg >= 0);
        assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f),
                         csum_ok ? GRIP_CAN_FRAME_OK : GRIP_CAN_FRAME_CHECKSUM);
        if (t->messages[msg].checksum != GRIP_CAN_CSUM_NONE) {
            csum_checked++;
        }
        assert_int_equal(grip_can_decode_input(t, (uint32_t)msg, input, &f, &v, &fault), GRIP_OK);
        if (fault != want_fault) {
            flag_bad++;
        } else if (fault == GRIP_SIG_OK) {
            double got = to_si(v, input);
            err_add(&st[input], got, want, (double)f.id, 0.0, 0.0);
            if (!(fabs(got - want) <= bound_of(want, input_q(t, (uint32_t)msg, input), input))) {
                if (viol++ < 5) {
                    print_message("# %s at t=%s: got %.12g want %.12g\n", grip_input_name(input), g.field[0], got,
                                  want);
                }
            }
        } else {
            assert_true(v == 0);
        }
        n++;
    }
    golden_close(&g);
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        if (st[i].n > 0) {
            err_print(&st[i], grip_input_unit(i));
        }
    }
    print_message("# RAV4 log: %ld decoded inputs, %ld checksummed frames, %ld bound violations, "
                  "%ld fault-flag mismatches vs cantools\n", n, csum_checked, viol, flag_bad);
    assert_true(n > 40000);
    assert_true(csum_checked > 2000);
    assert_int_equal(viol, 0);
    assert_int_equal(flag_bad, 0);
}

/* ---- frame checks ---------------------------------------------------------------- */

/* The first SPEED frame of the RAV4 log (id 0xB4, Toyota checksum in byte 7). */
static const uint8_t SPEED_FRAME[8] = { 0x00, 0x00, 0x00, 0x00, 0x1D, 0x0B, 0x7A, 0x5E };

static void test_toyota_checksum_detects_every_single_bit_error(void **state)
{
    const grip_can_table_t *t = &grip_can_table_rav4;
    grip_can_frame_t f;
    int32_t msg = grip_can_find_message(t, 0xB4);
    int bit;
    (void)state;
    assert_true(msg >= 0);
    memset(&f, 0, sizeof f);
    f.id = 0xB4;
    f.len = 8;
    memcpy(f.data, SPEED_FRAME, 8);
    assert_int_equal(grip_can_toyota_checksum(0xB4, f.data, 8, 7), 0x5E);
    assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f), GRIP_CAN_FRAME_OK);
    for (bit = 0; bit < 64; bit++) {
        f.data[bit / 8] ^= (uint8_t)(1u << (bit % 8));
        assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f), GRIP_CAN_FRAME_CHECKSUM);
        f.data[bit / 8] ^= (uint8_t)(1u << (bit % 8));
    }
    f.len = 7;
    assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f), GRIP_CAN_FRAME_DLC);
    f.len = 8;
    f.id = 0xB4 | GRIP_CAN_ID_RTR;
    assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f), GRIP_CAN_FRAME_RTR);
    f.id = GRIP_CAN_ID_ERR | 0x40u;
    assert_int_equal(grip_can_check_frame(t, (uint32_t)msg, &f), GRIP_CAN_FRAME_ERROR);
}

static void test_find_message(void **state)
{
    const grip_can_table_t *t = &grip_can_table_rav4;
    uint32_t i;
    (void)state;
    for (i = 0; i < t->n_messages; i++) {
        assert_int_equal(grip_can_find_message(t, t->messages[i].id), (int32_t)i);
    }
    assert_int_equal(grip_can_find_message(t, 0x23), -1);
    assert_int_equal(grip_can_find_message(t, 0x7FF), -1);
    /* a 29-bit id with the same low bits is another id */
    assert_int_equal(grip_can_find_message(t, 0x24u | GRIP_CAN_ID_EFF), -1);
    assert_int_equal(grip_can_find_message(NULL, 0x24), -1);
}

/* ---- table check -------------------------------------------------------------------- */

static grip_can_message_t tm[2];
static grip_can_signal_t ts[3];
static grip_can_table_t tt;

static void make_valid_table(void)
{
    memset(tm, 0, sizeof tm);
    memset(ts, 0, sizeof ts);
    tm[0] = grip_can_table_rav4.messages[1];   /* STEER_ANGLE_SENSOR: 2 terms */
    tm[0].first_signal = 0;
    ts[0] = grip_can_table_rav4.signals[3];
    ts[1] = grip_can_table_rav4.signals[4];
    ts[0].message = 0;
    ts[1].message = 0;
    tm[1] = grip_can_table_rav4.messages[3];   /* SPEED */
    tm[1].first_signal = 2;
    ts[2] = grip_can_table_rav4.signals[13];
    ts[2].message = 1;
    tt.name = "t";
    tt.messages = tm;
    tt.signals = ts;
    tt.n_messages = 2;
    tt.n_signals = 3;
}

static void test_table_check_rejects_broken_tables(void **state)
{
    uint32_t where = 99;
    (void)state;
    make_valid_table();
    assert_int_equal(grip_can_table_check(&tt, &where), GRIP_OK);
    make_valid_table();
    tm[1].id = 0x20;   /* ids not sorted */
    assert_int_equal(grip_can_table_check(&tt, &where), GRIP_ERR_PARAM);
    assert_int_equal(where, 1);
    make_valid_table();
    ts[1].shift = 36;   /* terms of one input with different shifts */
    assert_int_equal(grip_can_table_check(&tt, &where), GRIP_ERR_PARAM);
    assert_int_equal(where, 1);
    make_valid_table();
    ts[2].start = 60;   /* 16-bit Motorola signal from bit 60 leaves the 8-byte payload */
    assert_int_equal(grip_can_table_check(&tt, &where), GRIP_ERR_PARAM);
    make_valid_table();
    ts[0].k_mul = 1 << 30;   /* could overflow the 64-bit accumulator */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    ts[2].input = GRIP_IN_STEER_ANGLE;   /* one input fed by two messages */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tm[1].checksum_start = 64;   /* checksum byte beyond the payload */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tm[1].checksum_start = 60;   /* a Toyota checksum is one whole byte */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tm[1].checksum = GRIP_CAN_CSUM_COUNT;   /* no such family */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tm[1].checksum = GRIP_CAN_CSUM_VOLKSWAGEN_MQB;   /* its checksum is byte 0, not 7 */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tm[1].checksum = GRIP_CAN_CSUM_CHRYSLER;   /* last byte: fits */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_OK);
    make_valid_table();
    tm[0].period_us = 0;
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    ts[2].length = 33;
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    make_valid_table();
    tt.n_signals = 2;   /* last message's signals beyond the table */
    assert_int_equal(grip_can_table_check(&tt, NULL), GRIP_ERR_PARAM);
    assert_int_equal(grip_can_table_check(NULL, NULL), GRIP_ERR_NULL);
}

/* The detail form names the message, signal or input and the field that
 * failed, and agrees with the plain check's status and index. */
static void expect_detail(const char *part, int32_t index, const char *field)
{
    grip_check_detail_t d;
    uint32_t where = 99;
    assert_int_equal(grip_can_table_check_detail(&tt, &d), GRIP_ERR_PARAM);
    assert_string_equal(d.part, part);
    assert_int_equal(d.index, index);
    assert_string_equal(d.field, field);
    assert_true(d.rule[0] != '\0');
    assert_int_equal(grip_can_table_check(&tt, &where), GRIP_ERR_PARAM);
    assert_int_equal(where, (uint32_t)(index < 0 ? 0 : index));
}

static void test_table_check_detail_names_the_member(void **state)
{
    grip_check_detail_t d;
    (void)state;
    make_valid_table();
    assert_int_equal(grip_can_table_check_detail(&tt, &d), GRIP_OK);
    assert_string_equal(d.field, "");
    assert_string_equal(d.rule, "");
    make_valid_table();
    tm[1].id = 0x20;
    expect_detail("message", 1, "id");
    make_valid_table();
    tm[0].period_us = 0;
    expect_detail("message", 0, "period_us");
    make_valid_table();
    tm[1].checksum_start = 64;
    expect_detail("message", 1, "checksum");
    make_valid_table();
    ts[1].shift = 36;
    expect_detail("signal", 1, "input");
    make_valid_table();
    ts[2].start = 60;
    expect_detail("signal", 2, "start");
    make_valid_table();
    ts[2].length = 33;
    expect_detail("signal", 2, "length");
    make_valid_table();
    ts[0].k_mul = 1 << 30;
    expect_detail("signal", 0, "k");
    make_valid_table();
    ts[2].input = GRIP_IN_STEER_ANGLE;
    expect_detail("signal", 2, "input");
    make_valid_table();
    tt.n_signals = 2;
    expect_detail("message", 1, "first_signal");
    make_valid_table();
    tt.n_messages = 0;
    expect_detail("", -1, "n_signals");
    assert_int_equal(grip_can_table_check_detail(NULL, NULL), GRIP_ERR_NULL);
    make_valid_table();
    assert_int_equal(grip_can_table_check_detail(&tt, NULL), GRIP_OK);
}

/* ---- text tables ---------------------------------------------------------------------- */

static grip_can_table_text_t tb;

static int load_text(const char *path, const grip_can_table_t **out, unsigned long *bad_line, const char **why)
{
    char line[600];
    unsigned long n = 0;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        return -2;
    }
    grip_can_table_text_init(&tb);
    while (fgets(line, sizeof line, f) != NULL) {
        n++;
        if (grip_can_table_text_line(&tb, line, (uint32_t)strlen(line), why) != GRIP_OK) {
            *bad_line = n;
            fclose(f);
            return -1;
        }
    }
    fclose(f);
    return grip_can_table_text_finish(&tb, out, why) == GRIP_OK ? 0 : -1;
}

static void test_text_table_equals_compiled_table(void **state)
{
    const grip_can_table_t *a = &grip_can_table_rav4;
    const grip_can_table_t *b = NULL;
    unsigned long bad = 0;
    const char *why = "";
    uint32_t i;
    (void)state;
    assert_int_equal(load_text(RAV4_SIGTAB, &b, &bad, &why), 0);
    assert_string_equal(b->name, a->name);
    assert_int_equal(b->n_messages, a->n_messages);
    assert_int_equal(b->n_signals, a->n_signals);
    for (i = 0; i < a->n_messages; i++) {
        const grip_can_message_t *x = &a->messages[i];
        const grip_can_message_t *y = &b->messages[i];
        assert_string_equal(x->name, y->name);
        assert_true(x->id == y->id && x->period_us == y->period_us && x->first_signal == y->first_signal &&
                    x->n_signals == y->n_signals && x->len == y->len && x->checksum == y->checksum &&
                    x->checksum_start == y->checksum_start && x->checksum_length == y->checksum_length &&
                    x->checksum_order == y->checksum_order && memcmp(x->magic, y->magic, sizeof x->magic) == 0 &&
                    x->counter_length == y->counter_length &&
                    x->counter_order == y->counter_order && x->counter_start == y->counter_start);
    }
    for (i = 0; i < a->n_signals; i++) {
        const grip_can_signal_t *x = &a->signals[i];
        const grip_can_signal_t *y = &b->signals[i];
        assert_string_equal(x->name, y->name);
        assert_true(x->message == y->message && x->start == y->start && x->length == y->length &&
                    x->order == y->order && x->is_signed == y->is_signed && x->input == y->input &&
                    x->role == y->role && x->shift == y->shift && x->k_mul == y->k_mul && x->c_add == y->c_add &&
                    x->raw_min == y->raw_min && x->raw_max == y->raw_max);
    }
}

static grip_status_t tline(const char *line, const char **why)
{
    return grip_can_table_text_line(&tb, line, (uint32_t)strlen(line), why);
}

static void expect_line_error_v(int version, const char *line, const char *reason_part)
{
    const char *why = "";
    grip_can_table_text_init(&tb);
    if (version == 1) {
        assert_int_equal(tline("grip-can-table 1 t\n", &why), GRIP_OK);
        assert_int_equal(tline("msg M 0x24 8 12000 none 0 0 0 intel", &why), GRIP_OK);
    } else {
        assert_int_equal(tline("grip-can-table 2 t\n", &why), GRIP_OK);
        assert_int_equal(tline("msg M 0x24 8 12000 none 0 0 intel 0 0 intel -", &why), GRIP_OK);
    }
    assert_int_not_equal(tline(line, &why), GRIP_OK);
    if (strstr(why, reason_part) == NULL) {
        fail_msg("line '%s': reason '%s' lacks '%s'", line, why, reason_part);
    }
}

static void expect_line_error(const char *line, const char *reason_part)
{
    expect_line_error_v(1, line, reason_part);
}

static void test_text_table_malformed_lines(void **state)
{
    const char *why = "";
    const grip_can_table_t *t = NULL;
    (void)state;
    grip_can_table_text_init(&tb);
    assert_int_not_equal(tline("msg M 0x24 8 12000 none 0 0 0 intel", &why), GRIP_OK);
    assert_non_null(strstr(why, "not a grip signal table"));
    expect_line_error("sig S yaw_rate value 1 10 motorola 0 37 585297991 -299845282323 43", "12 fields");
    expect_line_error("sig S yaw_rat value 1 10 motorola 0 37 585297991 -299845282323 43 981", "unknown input");
    expect_line_error("sig S yaw_rate value 1 10 big 0 37 585297991 -299845282323 43 981", "intel|motorola");
    expect_line_error("sig S yaw_rate value 1 10 motorola 0 37 1073741824 0 43 981", "not a number in range");
    expect_line_error("sig S yaw_rate val 1 10 motorola 0 37 1 0 43 981", "role");
    expect_line_error("frob", "unknown line kind");
    expect_line_error("msg M 0x24 8 12000 crc 0 0 0 intel", "checksum family name");
    expect_line_error("msg M 0x24 8 12000 honda 7 0 0 intel", "checksum family name");   /* not in version 1 */
    expect_line_error("msg M 0x24 8 12000 none 0 0 0", "9 fields");
    /* version 2: the checksum field and the magic bytes */
    expect_line_error_v(2, "msg M 0x24 8 12000 none 0 0 0 intel", "12 fields");
    expect_line_error_v(2, "msg M 0x24 8 12000 volkswagen_mqb 0 8 intel 8 4 intel 40404040", "MAGIC");
    expect_line_error_v(2, "msg M 0x24 8 12000 volkswagen_mqb 0 8 intel 8 4 intel 4040404040404040404040404040404g",
                        "MAGIC");
    expect_line_error_v(2, "msg M 0x24 8 12000 volkswagen_mqb 0 17 intel 8 4 intel -", "not a number in range");
    expect_line_error_v(2, "msg M 0x24 8 12000 crc16 0 16 intel 8 4 intel -", "checksum family name");
    grip_can_table_text_init(&tb);
    assert_int_equal(tline("grip-can-table 2 t", &why), GRIP_OK);
    assert_int_equal(tline("msg M 0x40 8 12000 volkswagen_mqb 0 8 intel 8 4 intel "
                           "404142434445464748494a4b4c4d4e4f", &why), GRIP_OK);
    assert_int_equal(tb.messages[0].magic[0], 0x40);
    assert_int_equal(tb.messages[0].magic[15], 0x4F);
    assert_int_equal(tb.messages[0].checksum, GRIP_CAN_CSUM_VOLKSWAGEN_MQB);
    assert_int_equal(tb.messages[0].counter_length, 4);
    /* well-formed lines, inconsistent table: the check in finish catches it */
    grip_can_table_text_init(&tb);
    assert_int_equal(tline("grip-can-table 1 t", &why), GRIP_OK);
    assert_int_equal(tline("msg M 0x25 8 12000 none 0 0 0 intel", &why), GRIP_OK);
    assert_int_equal(tline("msg N 0x24 8 12000 none 0 0 0 intel", &why), GRIP_OK);
    assert_int_equal(grip_can_table_text_finish(&tb, &t, &why), GRIP_ERR_PARAM);
    assert_null(t);
    assert_non_null(strstr(why, "consistency"));
}

/* ---- input names ---------------------------------------------------------------------- */

static void test_input_names_round_trip(void **state)
{
    uint32_t i;
    grip_input_sample_t s;
    (void)state;
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        const char *n = grip_input_name(i);
        assert_int_equal(grip_input_find(n, (uint32_t)strlen(n)), (int32_t)i);
    }
    assert_int_equal(grip_input_find("ax2", 3), -1);
    assert_int_equal(grip_input_find("a", 1), -1);
    assert_string_equal(grip_input_name(GRIP_IN_COUNT), "?");
    assert_int_equal(grip_input_is_ql(GRIP_IN_BRAKE_PRESSURE_FL), 1);
    assert_int_equal(grip_input_is_ql(GRIP_IN_YAW_RATE), 0);
    assert_string_equal(grip_sig_fault_str(GRIP_SIG_STALE), "stale");
    assert_int_equal(grip_input_sample_clear(&s), GRIP_OK);
    assert_int_equal(s.fault[GRIP_IN_AX], GRIP_SIG_UNMAPPED);
    assert_int_equal(grip_input_sample_clear(NULL), GRIP_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_raw_vs_cantools),
        cmocka_unit_test(test_extract_rejects_bits_beyond_payload),
        cmocka_unit_test(test_scaling_vs_cantools),
        cmocka_unit_test(test_rav4_log_vs_cantools),
        cmocka_unit_test(test_toyota_checksum_detects_every_single_bit_error),
        cmocka_unit_test(test_find_message),
        cmocka_unit_test(test_table_check_rejects_broken_tables),
        cmocka_unit_test(test_table_check_detail_names_the_member),
        cmocka_unit_test(test_text_table_equals_compiled_table),
        cmocka_unit_test(test_text_table_malformed_lines),
        cmocka_unit_test(test_input_names_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
