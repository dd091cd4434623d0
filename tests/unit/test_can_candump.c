/*
 * test_can_candump.c - the candump -l log reader and writer
 * (port/linux/candump.c): every frame form, every malformed-line reason
 * with its line number, format/parse round trips, unreadable files.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "grip/grip_can.h"
#include "candump.h"

static grip_can_frame_t parse_ok(const char *line, const char *want_if)
{
    grip_can_frame_t f;
    char ifn[CANDUMP_IFNAME_MAX];
    const char *why = "";
    if (candump_parse_line(line, &f, ifn, &why) != 0) {
        fail_msg("'%s' rejected: %s", line, why);
    }
    assert_string_equal(ifn, want_if);
    return f;
}

static void parse_bad(const char *line, const char *reason_part)
{
    grip_can_frame_t f;
    char ifn[CANDUMP_IFNAME_MAX];
    const char *why = "";
    if (candump_parse_line(line, &f, ifn, &why) == 0) {
        fail_msg("'%s' accepted", line);
    }
    if (strstr(why, reason_part) == NULL) {
        fail_msg("'%s': reason '%s' lacks '%s'", line, why, reason_part);
    }
}

static void test_frame_forms(void **state)
{
    grip_can_frame_t f;
    (void)state;
    f = parse_ok("(1436509052.249713) vcan0 123#DEADBEEF", "vcan0");
    assert_true(f.t_us == 1436509052249713LL);
    assert_int_equal(f.id, 0x123);
    assert_int_equal(f.len, 4);
    assert_int_equal(f.flags, 0);
    assert_int_equal(f.data[0], 0xDE);
    assert_int_equal(f.data[3], 0xEF);
    f = parse_ok("(0000046408.584930) can1 12345678#00.11.22\n", "can1");
    assert_int_equal(f.id, 0x12345678u | GRIP_CAN_ID_EFF);
    assert_int_equal(f.len, 3);
    assert_int_equal(f.data[2], 0x22);
    f = parse_ok("(1.5) c 7FF#R", "c");
    assert_true(f.t_us == 1500000);
    assert_int_equal(f.id, 0x7FFu | GRIP_CAN_ID_RTR);
    assert_int_equal(f.len, 0);
    f = parse_ok("(1.000000) c 100#R3", "c");
    assert_int_equal(f.len, 3);
    f = parse_ok("(1.123456789) can0 123##1" "00112233445566778899AABB", "can0");
    assert_true(f.t_us == 1123456);   /* nanoseconds truncated to us */
    assert_int_equal(f.flags, GRIP_CAN_FLAG_FD | GRIP_CAN_FLAG_BRS);
    assert_int_equal(f.len, 12);
    assert_int_equal(f.data[11], 0xBB);
    f = parse_ok("(2.0) can0 1F334455##2", "can0");
    assert_int_equal(f.flags, GRIP_CAN_FLAG_FD | GRIP_CAN_FLAG_ESI);
    assert_int_equal(f.len, 0);
    assert_int_equal(f.id, 0x1F334455u | GRIP_CAN_ID_EFF);
    f = parse_ok("(3.0) can0 20000040#0000000000000000", "can0");   /* bus-off error frame */
    assert_int_equal(f.id, GRIP_CAN_ID_ERR | 0x40u);
    f = parse_ok("(4.0) can0 123#1122334455667788_C R\r\n", "can0");
    assert_int_equal(f.len, 8);
    f = parse_ok("  (5.0)\tcan0\t321# T", "can0");
    assert_int_equal(f.len, 0);
}

static void test_malformed_lines(void **state)
{
    (void)state;
    parse_bad("1436509052.249713 vcan0 123#00", "expected '('");
    parse_bad("(1436509052) vcan0 123#00", "SECONDS.FRACTION");
    parse_bad("(1.0)vcan0 123#00", "blank after the timestamp");
    parse_bad("(1.0) vcan0", "missing frame");
    parse_bad("(1.0) vcan0 12#00", "3 (11-bit) or 8 (29-bit)");
    parse_bad("(1.0) vcan0 1234#00", "3 (11-bit) or 8 (29-bit)");
    parse_bad("(1.0) vcan0 123456789#00", "expected 3 or 8 hex digits");
    parse_bad("(1.0) vcan0 800#00", "above 0x7FF");
    parse_bad("(1.0) vcan0 123#0G", "not a hex digit");
    parse_bad("(1.0) vcan0 123#001", "odd number");
    parse_bad("(1.0) vcan0 123#001122334455667788", "more than 8 bytes");
    parse_bad("(1.0) vcan0 123##0001122334455667788", "CAN FD: length");
    parse_bad("(1.0) vcan0 123##X00", "flags digit");
    parse_bad("(1.0) vcan0 123#00 junk", "unexpected text");
    parse_bad("(1.0) vcan0 123#0011_C", "DLC suffix");
    parse_bad("(1.0)  ", "missing interface");
    parse_bad("(1.0) vcan0 123 00", "'#'");
}

static void test_format_round_trip(void **state)
{
    static const char *const LINES[] = {
        "(0000046408.584930) vcan0 024#01FE01D541F980BB\n",
        "(1436509052.249713) can0 12345678#DEADBEEF\n",
        "(0000000001.000000) can0 7FF#R\n",
        "(0000000002.500000) can0 123##1001122334455667788990011\n",
        "(0000000003.000001) can0 20000040#0000000000000000\n",
        "(0000000004.000000) can0 000#\n",
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof LINES / sizeof LINES[0]; i++) {
        grip_can_frame_t f;
        grip_can_frame_t g;
        char ifn[CANDUMP_IFNAME_MAX];
        char buf[CANDUMP_LINE_MAX];
        const char *why = "";
        assert_int_equal(candump_parse_line(LINES[i], &f, ifn, &why), 0);
        assert_true(candump_format(&f, ifn, buf, sizeof buf) > 0);
        assert_string_equal(buf, LINES[i]);
        assert_int_equal(candump_parse_line(buf, &g, ifn, &why), 0);
        assert_memory_equal(&f, &g, sizeof f);
    }
}

static char tmpdir[64];

static const char *write_tmp(const char *name, const char *text)
{
    static char path[160];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

static void test_reader_line_numbers_and_skipping(void **state)
{
    candump_reader r;
    grip_can_frame_t f;
    char err[700];
    const char *path;
    int n = 0;
    int rc;
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/grip-candump-XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    path = write_tmp("bad.log", "(1.000000) vcan0 123#00\n"
                                "\n"
                                "# a comment\n"
                                "(1.000100) vcan0 123#0\n"
                                "(1.000200) vcan0 124#01\n");
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), 1);
    rc = candump_next(&r, &f, NULL, err, sizeof err);
    assert_int_equal(rc, -1);
    assert_non_null(strstr(err, "bad.log:4: malformed candump line: data: odd number"));
    candump_close(&r);
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    r.skip_bad = 1;
    while ((rc = candump_next(&r, &f, NULL, err, sizeof err)) == 1) {
        n++;
    }
    assert_int_equal(rc, 0);
    assert_int_equal(n, 2);
    assert_int_equal(r.skipped, 1);
    assert_int_equal(f.id, 0x124);
    candump_close(&r);
    unlink(path);
    rmdir(tmpdir);
}

static void test_unreadable_files(void **state)
{
    candump_reader r;
    grip_can_frame_t f;
    char err[700];
    (void)state;
    assert_int_equal(candump_open(&r, "/nonexistent/x.log", err, sizeof err), -1);
    assert_non_null(strstr(err, "cannot open log file /nonexistent/x.log: No such file"));
    /* a directory opens but cannot be read */
    assert_int_equal(candump_open(&r, "/tmp", err, sizeof err), 0);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "read error"));
    candump_close(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_forms),
        cmocka_unit_test(test_malformed_lines),
        cmocka_unit_test(test_format_round_trip),
        cmocka_unit_test(test_reader_line_numbers_and_skipping),
        cmocka_unit_test(test_unreadable_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
