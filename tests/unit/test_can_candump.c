/*
 * test_can_candump.c - the candump -l log reader and writer
 * (port/linux/candump.c): every frame form, every malformed-line reason
 * with its line number, format/parse round trips, unreadable files,
 * non-text bytes with their offsets, the line cap, and the frame-order
 * layer (strict tolerance, sorting window, its limits).
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

static void write_bytes(const char *path, const char *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    fclose(f);
}

static void test_reader_non_text_and_cap(void **state)
{
    static const char nul[] = "(1.000000) vcan0 123#00\n(1.000100) vc\0n0 123#00\n(1.000200) vcan0 124#01\n";
    static const char high[] = "(1.000000) vcan0 123#00\n(1.0001\xC3\xA9) vcan0 123#00\n";
    candump_reader r;
    grip_can_frame_t f;
    char err[700];
    char path[160];
    char longline[CANDUMP_LINE_MAX + 40];
    int n = 0;
    int rc;
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/grip-candump-XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    snprintf(path, sizeof path, "%s/nul.log", tmpdir);
    write_bytes(path, nul, sizeof nul - 1);
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), 1);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), -1);
    /* line 2 starts at byte 24; the NUL is its 14th byte */
    assert_non_null(strstr(err, "nul.log:2: malformed candump line: NUL byte at byte offset 37 (byte 14 of the line)"));
    candump_close(&r);
    /* skipped (counted) with skip_bad, like any malformed line */
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    r.skip_bad = 1;
    while ((rc = candump_next(&r, &f, NULL, err, sizeof err)) == 1) {
        n++;
    }
    assert_int_equal(rc, 0);
    assert_int_equal(n, 2);
    assert_int_equal(r.skipped, 1);
    candump_close(&r);
    unlink(path);
    snprintf(path, sizeof path, "%s/high.log", tmpdir);
    write_bytes(path, high, sizeof high - 1);
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), 1);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "high.log:2: malformed candump line: byte 0xC3 at byte offset 31"));
    candump_close(&r);
    unlink(path);
    /* a line of CANDUMP_LINE_MAX bytes is read, one more is an error, also with skip_bad */
    memset(longline, ' ', sizeof longline);
    memcpy(longline, "(1.0) vcan0 123#00", 18);
    longline[CANDUMP_LINE_MAX] = '\n';
    snprintf(path, sizeof path, "%s/long.log", tmpdir);
    write_bytes(path, longline, CANDUMP_LINE_MAX + 1);
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), 1);
    candump_close(&r);
    longline[CANDUMP_LINE_MAX] = ' ';
    longline[CANDUMP_LINE_MAX + 1] = '\n';
    write_bytes(path, longline, CANDUMP_LINE_MAX + 2);
    assert_int_equal(candump_open(&r, path, err, sizeof err), 0);
    r.skip_bad = 1;
    assert_int_equal(candump_next(&r, &f, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "long.log:1: line longer than 512 characters"));
    candump_close(&r);
    unlink(path);
    rmdir(tmpdir);
}

/* Reads path through the order layer; returns the frame count, the times
 * in t[], -1 on an error (message in err). */
static int read_ordered(const char *path, int64_t tol, int64_t window, size_t max_frames, int64_t *t, int max,
                        candump_order *o, char *err, size_t errlen)
{
    candump_reader r;
    grip_can_frame_t f;
    char ifn[CANDUMP_IFNAME_MAX];
    int n = 0;
    int rc;
    assert_int_equal(candump_open(&r, path, err, errlen), 0);
    assert_int_equal(candump_order_init(o, tol, window, max_frames, err, errlen), 0);
    while ((rc = candump_next_ordered(&r, o, &f, ifn, err, errlen)) == 1) {
        assert_string_equal(ifn, "vcan0");
        if (n < max) {
            t[n] = f.t_us;
        }
        n++;
    }
    candump_order_free(o);
    candump_close(&r);
    return rc < 0 ? -1 : n;
}

static void test_frame_order(void **state)
{
    candump_order o;
    int64_t t[16];
    char err[700];
    const char *path;
    int n;
    int k;
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/grip-candump-XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    /* 0.4 ms back: within the 1 ms tolerance, passed on as it came, counted */
    path = write_tmp("small.log", "(1.000000) vcan0 123#00\n(1.001000) vcan0 123#00\n(1.000600) vcan0 124#00\n"
                                  "(1.002000) vcan0 123#00\n");
    n = read_ordered(path, 1000, 0, 0, t, 16, &o, err, sizeof err);
    assert_int_equal(n, 4);
    assert_true(t[2] == 1000600);
    assert_int_equal(o.out_of_order, 1);
    assert_true(o.max_back_us == 400);
    /* 2 ms back: an error naming both lines and timestamps */
    path = write_tmp("back.log", "(1.000000) vcan0 123#00\n(1.003000) vcan0 123#00\n# c\n(1.001000) vcan0 124#00\n");
    assert_int_equal(read_ordered(path, 1000, 0, 0, t, 16, &o, err, sizeof err), -1);
    assert_non_null(strstr(err, "back.log:4: timestamp 1.001000 goes back 2.000 ms behind 1.003000 (line 2): more "
                                "than the 1.000 ms"));
    assert_non_null(strstr(err, "--reorder"));
    /* sorting: every frame comes out in time order, equal times in file order */
    path = write_tmp("shuffled.log", "(1.3) vcan0 103#00\n(1.1) vcan0 101#00\n(1.0) vcan0 100#00\n"
                                     "(1.2) vcan0 102#00\n(1.2) vcan0 10A#00\n(2.4) vcan0 104#00\n"
                                     "(1.9) vcan0 105#00\n(3.0) vcan0 106#00\n");
    n = read_ordered(path, 1000, 1000000, 64, t, 16, &o, err, sizeof err);
    assert_int_equal(n, 8);
    for (k = 1; k < n; k++) {
        assert_true(t[k] >= t[k - 1]);
    }
    assert_int_equal(o.out_of_order, 5);
    assert_true(o.max_back_us == 500000);
    /* beyond the window: an error */
    path = write_tmp("far.log", "(5.0) vcan0 100#00\n(3.9) vcan0 100#00\n");
    assert_int_equal(read_ordered(path, 1000, 1000000, 64, t, 16, &o, err, sizeof err), -1);
    assert_non_null(strstr(err, "far.log:2: timestamp 3.900000 goes back 1100.000 ms behind 5.000000 (line 1): beyond "
                                "the 1000.000 ms reorder window"));
    /* more frames waiting than allowed: an error */
    path = write_tmp("many.log", "(1.0) vcan0 100#00\n(1.1) vcan0 100#00\n(1.2) vcan0 100#00\n(1.3) vcan0 100#00\n");
    assert_int_equal(read_ordered(path, 1000, 1000000, 3, t, 16, &o, err, sizeof err), -1);
    assert_non_null(strstr(err, "many.log:4: more than 3 frames within the 1000 ms reorder window"));
    unlink(path);
    snprintf(err, sizeof err, "%s/small.log", tmpdir);
    unlink(err);
    snprintf(err, sizeof err, "%s/back.log", tmpdir);
    unlink(err);
    snprintf(err, sizeof err, "%s/shuffled.log", tmpdir);
    unlink(err);
    snprintf(err, sizeof err, "%s/far.log", tmpdir);
    unlink(err);
    rmdir(tmpdir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_forms),
        cmocka_unit_test(test_malformed_lines),
        cmocka_unit_test(test_format_round_trip),
        cmocka_unit_test(test_reader_line_numbers_and_skipping),
        cmocka_unit_test(test_unreadable_files),
        cmocka_unit_test(test_reader_non_text_and_cap),
        cmocka_unit_test(test_frame_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
