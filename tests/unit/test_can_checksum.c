/*
 * test_can_checksum.c - the checksum families of lib/can/can_checksum.c
 * against the Python reference (tools/grip_tools/can/checksums.py, golden
 * file can_checksums.txt from tools/grip_tools/golden/can.py):
 *   - real frames: opendbc's test frames (Volkswagen MQB, FCA Giorgio,
 *     Honda) and SPEED frames of the RAV4 log (Toyota) pass, the one
 *     opendbc frame whose checksum does not hold fails;
 *   - frames made by the reference for every family pass;
 *   - every single-bit error of each of those frames gets the reference's
 *     verdict (a checksum error wherever the family covers the bit);
 * plus the table check of each family's checksum field.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_can.h"
#include "golden.h"

static int hexbytes(const char *s, uint8_t *out, size_t max)
{
    size_t n = strlen(s) / 2u;
    size_t i;
    if (n > max) {
        return -1;
    }
    for (i = 0; i < n; i++) {
        unsigned v;
        if (sscanf(s + 2u * i, "%2x", &v) != 1) {
            return -1;
        }
        out[i] = (uint8_t)v;
    }
    return (int)n;
}

static void test_checksums_match_the_reference(void **state)
{
    golden_file g;
    long real[GRIP_CAN_CSUM_COUNT] = { 0 };
    long real_ok[GRIP_CAN_CSUM_COUNT] = { 0 };
    long made[GRIP_CAN_CSUM_COUNT] = { 0 };
    long flips[GRIP_CAN_CSUM_COUNT] = { 0 };
    long caught[GRIP_CAN_CSUM_COUNT] = { 0 };
    long mismatches = 0;
    long rows = 0;
    uint32_t fam;
    (void)state;
    assert_int_equal(golden_open(&g, "can_checksums.txt"), 0);
    while (golden_next(&g) > 0) {
        grip_can_message_t m;
        grip_can_table_t t;
        grip_can_frame_t f;
        uint32_t verdict;
        uint32_t computed;
        int ok = (int)golden_num(&g, 9);
        int kind = (int)golden_num(&g, 10);
        memset(&m, 0, sizeof m);
        memset(&f, 0, sizeof f);
        fam = (uint32_t)golden_num(&g, 0);
        assert_true(fam < GRIP_CAN_CSUM_COUNT);
        m.name = "M";
        m.id = (uint32_t)strtoul(g.field[1], NULL, 10);
        m.period_us = 10000u;
        m.len = (uint8_t)golden_num(&g, 2);
        m.checksum = (uint8_t)fam;
        m.checksum_start = (uint16_t)golden_num(&g, 4);
        m.checksum_length = (uint8_t)golden_num(&g, 5);
        m.checksum_order = (uint8_t)golden_num(&g, 6);
        assert_int_equal(hexbytes(g.field[7], m.magic, sizeof m.magic), (int)GRIP_CAN_MAGIC_LEN);
        f.id = m.id;
        f.len = m.len;
        assert_int_equal(hexbytes(g.field[3], f.data, sizeof f.data), (int)f.len);
        t.name = "t";
        t.messages = &m;
        t.signals = NULL;
        t.n_messages = 1u;
        t.n_signals = 0u;
        computed = grip_can_checksum_compute(&m, f.data, f.len);
        verdict = grip_can_check_frame(&t, 0u, &f);
        rows++;
        if (computed != (uint32_t)strtoul(g.field[8], NULL, 10) ||
            verdict != (ok ? (uint32_t)GRIP_CAN_FRAME_OK : (uint32_t)GRIP_CAN_FRAME_CHECKSUM)) {
            if (mismatches < 5) {
                print_message("# mismatch at %s:%lu: computed %u, verdict %u\n", g.path, g.lineno,
                              (unsigned)computed, (unsigned)verdict);
            }
            mismatches++;
        }
        if (kind == 0) {
            real[fam]++;
            real_ok[fam] += (verdict == (uint32_t)GRIP_CAN_FRAME_OK);
        } else if (kind == 1) {
            made[fam]++;
        } else {
            flips[fam]++;
            caught[fam] += (verdict == (uint32_t)GRIP_CAN_FRAME_CHECKSUM);
        }
    }
    golden_close(&g);
    for (fam = 1u; fam < GRIP_CAN_CSUM_COUNT; fam++) {
        print_message("# %-16s real frames %4ld (%4ld pass), made %3ld, one-bit errors %6ld (%6ld caught)\n",
                      grip_can_checksum_name(fam), real[fam], real_ok[fam], made[fam], flips[fam], caught[fam]);
        assert_true(real[fam] + made[fam] > 0);   /* every family is exercised */
    }
    print_message("# %ld rows, %ld mismatches with the reference\n", rows, mismatches);
    assert_int_equal(mismatches, 0);
    assert_true(real_ok[GRIP_CAN_CSUM_VOLKSWAGEN_MQB] >= 368);
    assert_true(real_ok[GRIP_CAN_CSUM_FCA_GIORGIO] >= 11);
    assert_true(real_ok[GRIP_CAN_CSUM_HONDA] >= 8);
    assert_true(real_ok[GRIP_CAN_CSUM_TOYOTA] >= 200);
}

static grip_can_message_t msg_of(uint32_t fam, uint32_t id, uint32_t len, uint32_t start, uint32_t bits,
                                 uint32_t order)
{
    grip_can_message_t m;
    memset(&m, 0, sizeof m);
    m.name = "M";
    m.id = id;
    m.period_us = 10000u;
    m.len = (uint8_t)len;
    m.checksum = (uint8_t)fam;
    m.checksum_start = (uint16_t)start;
    m.checksum_length = (uint8_t)bits;
    m.checksum_order = (uint8_t)order;
    return m;
}

static grip_status_t check_one(grip_can_message_t m)
{
    static const grip_can_signal_t none[1];
    grip_can_table_t t;
    t.name = "t";
    t.messages = &m;
    t.signals = none;
    t.n_messages = 1u;
    t.n_signals = 0u;
    return grip_can_table_check(&t, NULL);
}

static void test_table_check_knows_each_family_field(void **state)
{
    (void)state;
    /* accepted */
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HONDA, 0x1A6u, 8u, 59u, 4u, GRIP_CAN_MOTOROLA)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HONDA, 0x33Du, 5u, 32u, 4u, GRIP_CAN_INTEL)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HKG_CAN_FD, 0xEAu, 24u, 0u, 16u, GRIP_CAN_INTEL)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HYUNDAI, 0x260u, 8u, 56u, 4u, GRIP_CAN_INTEL)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HYUNDAI_WHL_SPD, 0x386u, 8u, 46u, 2u, GRIP_CAN_INTEL)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_VOLKSWAGEN_MQB, 0x9Fu, 8u, 7u, 8u, GRIP_CAN_MOTOROLA)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_FORD, 0x91u, 8u, 39u, 8u, GRIP_CAN_MOTOROLA)), GRIP_OK);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_NISSAN, 0x169u, 8u, 56u, 8u, GRIP_CAN_INTEL)), GRIP_OK);
    /* refused: a field the family does not use */
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HONDA, 0x1A6u, 8u, 63u, 4u, GRIP_CAN_MOTOROLA)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HKG_CAN_FD, 0xEAu, 24u, 8u, 16u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HYUNDAI, 0x260u, 8u, 58u, 4u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_HYUNDAI_WHL_SPD, 0x386u, 6u, 46u, 2u, GRIP_CAN_INTEL)),
                     GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_SUBARU, 0x13Cu, 8u, 56u, 8u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_CHRYSLER, 0x1F4u, 8u, 0u, 8u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_FORD, 0x92u, 8u, 32u, 8u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_TOYOTA, 0xB4u, 8u, 60u, 8u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    assert_int_equal(check_one(msg_of(GRIP_CAN_CSUM_COUNT, 0xB4u, 8u, 56u, 8u, GRIP_CAN_INTEL)), GRIP_ERR_PARAM);
    /* names */
    assert_string_equal(grip_can_checksum_name(GRIP_CAN_CSUM_HKG_CAN_FD), "hkg_can_fd");
    assert_null(grip_can_checksum_name(GRIP_CAN_CSUM_COUNT));
    /* NULL and wrong-length input compute nothing */
    {
        grip_can_message_t m = msg_of(GRIP_CAN_CSUM_CHRYSLER, 0x1F4u, 8u, 56u, 8u, GRIP_CAN_INTEL);
        uint8_t d[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
        assert_int_equal(grip_can_checksum_compute(NULL, d, 8u), 0);
        assert_int_equal(grip_can_checksum_compute(&m, NULL, 8u), 0);
        assert_int_equal(grip_can_checksum_compute(&m, d, 7u), 0);
        assert_int_equal(grip_can_checksum_received(&m, d, 8u), 8);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_checksums_match_the_reference),
        cmocka_unit_test(test_table_check_knows_each_family_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
