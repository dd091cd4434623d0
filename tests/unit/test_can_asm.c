/*
 * test_can_asm.c - the sample assembler (lib/can/can_asm.c):
 *   - the whole RAV4 log, read with the candump reader, against the
 *     zero-order-hold reference of tools/grip_tools/golden/can.py (every
 *     step, every input: same validity and fault, value within the decode
 *     tolerance of test_can_decode.c);
 *   - each fault on a synthetic table: stale, out of range, sender fault
 *     flag, wrong DLC, bad checksum, frozen and skipping counters, reordered
 *     and late frames, timestamp jumps both ways, error frames, remote
 *     requests, unknown ids, CAN FD with a 29-bit id; in every case no
 *     sample carries a corrupted or out-of-range number.
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
#include "candump.h"
#include "golden.h"

#define RAV4_LOG "tests/data/comma2k19-rav4/rav4_bus0.log"

static double to_si(grip_real_t v, uint32_t input)
{
#if GRIP_ARITH_FIXED
    return (double)v / (grip_input_is_ql(input) ? 256.0 : 65536.0);
#else
    (void)input;
    return (double)v;
#endif
}

static grip_real_t from_si(double v, uint32_t input)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)lround(v * (grip_input_is_ql(input) ? 256.0 : 65536.0));
#else
    (void)input;
    return (grip_real_t)v;
#endif
}

/* Decode tolerance (test_can_decode.c) of an input of the table. */
static double tol(const grip_can_table_t *t, uint32_t input, double want)
{
    double q = 0.0;
    uint32_t i;
    for (i = 0; i < t->n_signals; i++) {
        const grip_can_signal_t *s = &t->signals[i];
        if (s->input == input && s->role == GRIP_CAN_ROLE_VALUE) {
            q += (ldexp(1.0, s->length) + 1.0) * ldexp(1.0, -(int)s->shift - 1);
        }
    }
#if GRIP_ARITH_FIXED
    return (grip_input_is_ql(input) ? 0.5 / 256.0 : 0.5 / 65536.0) + q + ldexp(fabs(want), -50);
#else
    return ldexp(fabs(want), -24) + q + ldexp(fabs(want), -50);
#endif
}

/* ---- the RAV4 log against the reference assembler -------------------------- */

static grip_can_asm_t A;

static void test_rav4_steps_vs_reference(void **state)
{
    const grip_can_table_t *t = &grip_can_table_rav4;
    grip_can_asm_config_t cfg = { 10000u, 3u, 0u, 1000000u };
    candump_reader rd;
    golden_file g;
    grip_can_frame_t f;
    grip_input_sample_t s;
    char err[600];
    long steps = 0;
    long fault_bad = 0;
    long value_bad = 0;
    long valid_values = 0;
    double worst = 0.0;
    int rc;
    (void)state;
    assert_int_equal(grip_can_asm_init(&A, t, &cfg), GRIP_OK);
    assert_int_equal(candump_open(&rd, RAV4_LOG, err, sizeof err), 0);
    assert_int_equal(golden_open(&g, "can_rav4_steps.txt"), 0);
    for (;;) {
        int64_t now;
        rc = candump_next(&rd, &f, NULL, err, sizeof err);
        if (rc < 0) {
            fail_msg("%s", err);
        }
        now = (rc == 1) ? f.t_us : A.newest_t_us + 1;
        while (grip_can_asm_poll(&A, now, &s)) {
            uint32_t i;
            assert_true(golden_next(&g) >= 2 + 2 * GRIP_IN_COUNT);
            assert_int_equal(s.step, (uint32_t)golden_num(&g, 0));
            assert_true(s.t_us == strtoll(g.field[1], NULL, 10));
            for (i = 0; i < GRIP_IN_COUNT; i++) {
                double want = strtod(g.field[2 + 2 * i], NULL);
                uint8_t want_fault = (uint8_t)golden_num(&g, 3 + 2 * (int)i);
                if (s.fault[i] != want_fault || s.valid[i] != (want_fault == GRIP_SIG_OK)) {
                    fault_bad++;
                } else if (s.valid[i]) {
                    double e = fabs(to_si(s.value[i], i) - want);
                    valid_values++;
                    if (e > tol(t, i, want)) {
                        value_bad++;
                    }
                    if (e / tol(t, i, want) > worst) {
                        worst = e / tol(t, i, want);
                    }
                } else {
                    assert_true(s.value[i] == 0);
                }
            }
            steps++;
        }
        if (rc == 0) {
            break;
        }
        assert_int_equal(grip_can_asm_push(&A, &f, NULL), GRIP_OK);
    }
    assert_int_equal(golden_next(&g), 0);   /* no reference step left over */
    golden_close(&g);
    candump_close(&rd);
    print_message("# RAV4 log: %ld steps, %ld valid values, worst value error %.3f of its bound, %ld fault-flag "
                  "mismatches, %ld value mismatches; frames %u, decoded %u, decode errors %u\n",
                  steps, valid_values, worst, fault_bad, value_bad, A.stats.frames, A.stats.decoded,
                  A.stats.dlc_errors + A.stats.checksum_errors + A.stats.range_errors + A.stats.qualifier_faults);
    assert_true(steps > 5000);
    assert_int_equal(fault_bad, 0);
    assert_int_equal(value_bad, 0);
    assert_int_equal(A.stats.samples, (uint32_t)steps);
    assert_int_equal(A.stats.jumps, 0);
}

/* ---- a synthetic table -------------------------------------------------------------- */

/* Message 0x100 (8 bytes, 10 ms, Toyota checksum in byte 7, 4-bit counter
 * in bits 48..51 Intel): wheel_speed_fl = bits 0..15 Intel x 0.01 m/s,
 * range 0..100 m/s, valid only if bit 16 is 0.
 * Message 0x200 (4 bytes, 20 ms): yaw_rate = signed 16 bits Motorola from
 * bit 7 x 2^-10 rad/s; brake_pressure_fl = bits 16..31 Intel x 100 Pa (QL).
 * Message 0x18FF0001 (29-bit, CAN FD, 12 bytes, 50 ms): brake_torque_fl =
 * signed 16 bits Intel from bit 80 x 1 N m. */
static const grip_can_message_t SM[3] = {
    { "A", 0x100u, 10000u, 0u, 2u, 8u, GRIP_CAN_CSUM_TOYOTA, 8u, GRIP_CAN_INTEL, 56u, 4u, GRIP_CAN_INTEL, 48u, { 0u } },
    { "B", 0x200u, 20000u, 2u, 2u, 4u, GRIP_CAN_CSUM_NONE, 0u, GRIP_CAN_INTEL, 0u, 0u, GRIP_CAN_INTEL, 0u, { 0u } },
    { "C", 0x98FF0001u, 50000u, 4u, 1u, 12u, GRIP_CAN_CSUM_NONE, 0u, GRIP_CAN_INTEL, 0u, 0u, GRIP_CAN_INTEL, 0u, { 0u } },
};
/* K and C for shift s: 0.01 m/s = 2^s x 0.01; here s = 30 -> K = 10737418 (0.01 x 2^30 rounded). */
static const grip_can_signal_t SS[5] = {
    { "WS", 0u, 0u, 16u, GRIP_CAN_INTEL, 0u, GRIP_IN_WHEEL_SPEED_FL, GRIP_CAN_ROLE_VALUE, 30u, 10737418, 0, 0, 10000 },
    { "WS_FAULT", 0u, 16u, 1u, GRIP_CAN_INTEL, 0u, GRIP_IN_WHEEL_SPEED_FL, GRIP_CAN_ROLE_QUALIFIER, 0u, 0, 0, 0, 0 },
    { "YAW", 1u, 7u, 16u, GRIP_CAN_MOTOROLA, 1u, GRIP_IN_YAW_RATE, GRIP_CAN_ROLE_VALUE, 26u, 65536, 0, -32768, 32767 },
    { "BP", 1u, 16u, 16u, GRIP_CAN_INTEL, 0u, GRIP_IN_BRAKE_PRESSURE_FL, GRIP_CAN_ROLE_VALUE, 16u, 6553600, 0, 0, 65535 },
    { "BT", 2u, 80u, 16u, GRIP_CAN_INTEL, 1u, GRIP_IN_BRAKE_TORQUE_FL, GRIP_CAN_ROLE_VALUE, 16u, 65536, 0, -5000, 5000 },
};
static const grip_can_table_t ST = { "synthetic", SM, SS, 3u, 5u };

static grip_input_sample_t out[64];
static int nout;

static void drain(int64_t now)
{
    while (nout < 64 && grip_can_asm_poll(&A, now, &out[nout])) {
        nout++;
    }
}

/* Polls, then pushes; returns the frame's grip_can_frame_fault_t. */
static uint32_t push(const grip_can_frame_t *f)
{
    uint32_t fault = 99;
    drain(f->t_us);
    assert_int_equal(grip_can_asm_push(&A, f, &fault), GRIP_OK);
    return fault;
}

static uint8_t ctr_a;

static grip_can_frame_t frame_a(int64_t t, unsigned raw, int fault_bit)
{
    grip_can_frame_t f;
    memset(&f, 0, sizeof f);
    f.t_us = t;
    f.id = 0x100;
    f.len = 8;
    f.data[0] = (uint8_t)(raw & 0xFF);
    f.data[1] = (uint8_t)(raw >> 8);
    f.data[2] = (uint8_t)(fault_bit ? 1 : 0);
    f.data[6] = (uint8_t)(ctr_a++ & 0x0F);
    f.data[7] = grip_can_toyota_checksum(f.id, f.data, 8, 7);
    return f;
}

static grip_can_frame_t frame_b(int64_t t, int yaw_raw, unsigned bp_raw)
{
    grip_can_frame_t f;
    memset(&f, 0, sizeof f);
    f.t_us = t;
    f.id = 0x200;
    f.len = 4;
    f.data[0] = (uint8_t)((unsigned)yaw_raw >> 8);
    f.data[1] = (uint8_t)((unsigned)yaw_raw & 0xFF);
    f.data[2] = (uint8_t)(bp_raw & 0xFF);
    f.data[3] = (uint8_t)(bp_raw >> 8);
    return f;
}

static void start(uint32_t reorder_us)
{
    grip_can_asm_config_t cfg = { 10000u, 3u, reorder_us, 200000u };
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_OK);
    nout = 0;
    ctr_a = 0;
}

static void assert_near(grip_real_t got, double want, uint32_t input)
{
    double b = tol(&ST, input, want);
    if (!(fabs(to_si(got, input) - want) <= b)) {
        fail_msg("%s: got %.9g, want %.9g (+- %.3g)", grip_input_name(input), to_si(got, input), want, b);
    }
}

static void test_values_and_zero_order_hold(void **state)
{
    grip_can_frame_t f;
    int k;
    (void)state;
    start(0);
    for (k = 0; k < 10; k++) {
        f = frame_a(1000000 + 10000 * k + 3000, 1234u + (unsigned)k, 0);
        assert_int_equal(push(&f), GRIP_CAN_FRAME_OK);
        if (k % 2 == 0) {
            f = frame_b(1000000 + 10000 * k + 5000, -1000 + k, 50u * (unsigned)k);
            assert_int_equal(push(&f), GRIP_CAN_FRAME_OK);
        }
    }
    drain(1000000 + 100001);   /* step t is due once now > t */
    /* steps at 1.01 .. 1.10 s (the first frame at 1.003 s starts the grid at 1.01 s) */
    assert_int_equal(nout, 10);
    assert_true(out[0].t_us == 1010000);
    assert_int_equal(out[0].step, 0);
    assert_int_equal(out[0].valid[GRIP_IN_WHEEL_SPEED_FL], 1);
    assert_near(out[0].value[GRIP_IN_WHEEL_SPEED_FL], 12.34, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(out[0].age_us[GRIP_IN_WHEEL_SPEED_FL], 7000);
    assert_near(out[0].value[GRIP_IN_YAW_RATE], -1000.0 / 1024.0, GRIP_IN_YAW_RATE);
    assert_near(out[0].value[GRIP_IN_BRAKE_PRESSURE_FL], 0.0, GRIP_IN_BRAKE_PRESSURE_FL);
    /* step 1.05 s: A from 1.043 s (raw 1238), B from 1.045 s (k = 4) */
    assert_true(out[4].t_us == 1050000);
    assert_near(out[4].value[GRIP_IN_WHEEL_SPEED_FL], 12.38, GRIP_IN_WHEEL_SPEED_FL);
    assert_near(out[4].value[GRIP_IN_YAW_RATE], -996.0 / 1024.0, GRIP_IN_YAW_RATE);
    assert_near(out[4].value[GRIP_IN_BRAKE_PRESSURE_FL], 20000.0, GRIP_IN_BRAKE_PRESSURE_FL);
    /* step 1.06 s: B unchanged (zero-order hold), 15 ms old */
    assert_near(out[5].value[GRIP_IN_YAW_RATE], -996.0 / 1024.0, GRIP_IN_YAW_RATE);
    assert_int_equal(out[5].age_us[GRIP_IN_YAW_RATE], 15000);
    assert_int_equal(out[5].fault[GRIP_IN_BRAKE_TORQUE_FL], GRIP_SIG_MISSING);
    assert_int_equal(out[5].fault[GRIP_IN_AX], GRIP_SIG_UNMAPPED);
    assert_int_equal(A.stats.decoded, 15);
}

static void test_stale_after_k_periods(void **state)
{
    grip_can_frame_t f;
    int k;
    (void)state;
    start(0);
    f = frame_b(0, 100, 1);   /* B once, at t = 0; period 20 ms, k = 3: stale when older than 60 ms */
    push(&f);
    for (k = 1; k <= 12; k++) {
        f = frame_a(10000 * k, 500, 0);
        push(&f);
    }
    drain(130000);
    /* steps at 0, 10, ..., 120 ms */
    assert_int_equal(nout, 13);
    for (k = 0; k < nout; k++) {
        int stale = out[k].t_us > 60000;
        assert_int_equal(out[k].fault[GRIP_IN_YAW_RATE], stale ? GRIP_SIG_STALE : GRIP_SIG_OK);
        assert_int_equal(out[k].valid[GRIP_IN_YAW_RATE], !stale);
        if (stale) {
            assert_true(out[k].value[GRIP_IN_YAW_RATE] == 0);
        }
    }
    assert_int_equal(A.stats.input_faults[GRIP_IN_YAW_RATE][GRIP_SIG_STALE], 6);
}

static void test_range_and_sender_fault_never_give_a_number(void **state)
{
    grip_can_frame_t f;
    (void)state;
    start(0);
    f = frame_a(0, 5000, 0);
    push(&f);
    f = frame_a(10000, 10001, 0);   /* 100.01 m/s > 100 */
    push(&f);
    f = frame_a(20000, 6000, 1);    /* fault bit set */
    push(&f);
    f = frame_a(30000, 7000, 0);
    push(&f);
    drain(40000);
    assert_int_equal(nout, 4);
    assert_int_equal(out[0].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_OK);
    assert_int_equal(out[1].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_RANGE);
    assert_true(out[1].value[GRIP_IN_WHEEL_SPEED_FL] == 0 && !out[1].valid[GRIP_IN_WHEEL_SPEED_FL]);
    assert_int_equal(out[2].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_FAULT);
    assert_true(out[2].value[GRIP_IN_WHEEL_SPEED_FL] == 0 && !out[2].valid[GRIP_IN_WHEEL_SPEED_FL]);
    assert_int_equal(out[3].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_OK);
    assert_near(out[3].value[GRIP_IN_WHEEL_SPEED_FL], 70.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(A.stats.range_errors, 1);
    assert_int_equal(A.stats.qualifier_faults, 1);
}

static void test_rejected_frames_keep_the_last_good_value(void **state)
{
    grip_can_frame_t f;
    (void)state;
    start(0);
    f = frame_a(0, 1000, 0);
    assert_int_equal(push(&f), GRIP_CAN_FRAME_OK);
    f = frame_a(10000, 2000, 0);
    f.data[0] ^= 0x01;   /* corrupted payload: checksum no longer matches */
    assert_int_equal(push(&f), GRIP_CAN_FRAME_CHECKSUM);
    f = frame_a(20000, 3000, 0);
    f.len = 7;           /* wrong DLC */
    assert_int_equal(push(&f), GRIP_CAN_FRAME_DLC);
    f = frame_a(30000, 4000, 0);
    ctr_a--;             /* repeat the counter of the last accepted frame ... */
    f.data[6] = 0;
    f.data[7] = grip_can_toyota_checksum(f.id, f.data, 8, 7);
    assert_int_equal(push(&f), GRIP_CAN_FRAME_FROZEN);
    ctr_a = 5;           /* ... then skip counter values: accepted, counted */
    f = frame_a(40000, 5000, 0);
    assert_int_equal(push(&f), GRIP_CAN_FRAME_OK);
    drain(50000);
    assert_int_equal(nout, 5);
    /* steps 10, 20, 30 ms: still the frame of t = 0 (raw 1000), never a corrupted value */
    assert_near(out[1].value[GRIP_IN_WHEEL_SPEED_FL], 10.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_near(out[2].value[GRIP_IN_WHEEL_SPEED_FL], 10.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(out[3].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_OK);   /* 30 ms old: period 10 ms x 3 */
    assert_near(out[3].value[GRIP_IN_WHEEL_SPEED_FL], 10.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_near(out[4].value[GRIP_IN_WHEEL_SPEED_FL], 50.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(A.stats.checksum_errors, 1);
    assert_int_equal(A.stats.dlc_errors, 1);
    assert_int_equal(A.stats.counter_frozen, 1);
    assert_int_equal(A.stats.counter_skips, 1);
    assert_int_equal(A.stats.decoded, 2);
}

static void test_reordered_and_late_frames(void **state)
{
    grip_can_frame_t f;
    (void)state;
    start(5000);   /* accept frames up to 5 ms late */
    f = frame_a(0, 100, 0);
    push(&f);
    f = frame_a(12000, 300, 0);   /* arrives before ... */
    push(&f);
    f = frame_a(9000, 200, 0);    /* ... this older one: reordered, still in time for step 10 ms */
    push(&f);
    f = frame_a(16000, 400, 0);
    push(&f);
    /* step 10 ms was emitted when the frame at 16 ms came (10 + 5 < 16) */
    assert_int_equal(nout, 2);
    assert_near(out[1].value[GRIP_IN_WHEEL_SPEED_FL], 2.0, GRIP_IN_WHEEL_SPEED_FL);
    f = frame_a(8000, 999, 0);    /* too late for step 10 ms, older than both kept values */
    push(&f);
    drain(30000);
    assert_int_equal(nout, 3);
    assert_near(out[2].value[GRIP_IN_WHEEL_SPEED_FL], 4.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(A.stats.reordered, 2);
    assert_int_equal(A.stats.late, 1);
    assert_int_equal(A.stats.too_old, 1);
}

static void test_timestamp_jumps(void **state)
{
    grip_can_frame_t f;
    int k;
    (void)state;
    start(0);
    for (k = 0; k < 5; k++) {
        f = frame_a(1000000 + 10000 * k, 100, 0);
        push(&f);
    }
    /* the clock jumps back 10 s */
    f = frame_a(-9000000, 200, 0);
    push(&f);
    assert_int_equal(A.stats.jumps, 1);
    assert_int_equal(nout, 4);
    f = frame_b(-8995000, 1, 1);
    push(&f);
    drain(-8980000);
    /* the grid restarted at -9.0 s: its first step has A (0 ms old) but B only from -8.995 s */
    assert_int_equal(nout, 6);
    assert_true(out[4].t_us == -9000000);
    assert_int_equal(out[4].step, 0);
    assert_int_equal(out[4].fault[GRIP_IN_YAW_RATE], GRIP_SIG_MISSING);
    assert_near(out[4].value[GRIP_IN_WHEEL_SPEED_FL], 2.0, GRIP_IN_WHEEL_SPEED_FL);
    assert_int_equal(out[5].fault[GRIP_IN_YAW_RATE], GRIP_SIG_OK);
    /* and forward by 1 hour: no flood of samples, a restart instead */
    f = frame_a(3600000000LL, 300, 0);
    push(&f);
    assert_int_equal(nout, 6);
    assert_int_equal(A.stats.jumps, 2);
    drain(3600000000LL + 25000);
    assert_int_equal(nout, 9);
    assert_int_equal(out[6].fault[GRIP_IN_YAW_RATE], GRIP_SIG_MISSING);   /* old values forgotten */
    assert_near(out[6].value[GRIP_IN_WHEEL_SPEED_FL], 3.0, GRIP_IN_WHEEL_SPEED_FL);
    /* a silence shorter than jump_us (200 ms) gives stale samples, not a restart */
    drain(3600000000LL + 150000);
    assert_int_equal(A.stats.jumps, 2);
    assert_int_equal(out[nout - 1].fault[GRIP_IN_WHEEL_SPEED_FL], GRIP_SIG_STALE);
}

static void test_error_remote_unknown_and_fd_frames(void **state)
{
    grip_can_frame_t f;
    (void)state;
    start(0);
    memset(&f, 0, sizeof f);
    f.id = GRIP_CAN_ID_ERR | 0x40u;   /* bus-off error frame */
    f.len = 8;
    assert_int_equal(push(&f), GRIP_CAN_FRAME_ERROR);
    f.id = 0x200 | GRIP_CAN_ID_RTR;
    f.len = 0;
    assert_int_equal(push(&f), GRIP_CAN_FRAME_RTR);
    f.id = 0x123;
    f.len = 8;
    assert_int_equal(push(&f), GRIP_CAN_FRAME_UNKNOWN);
    f.id = 0x18FF0001;                /* the 11/29-bit distinction matters */
    f.len = 12;
    assert_int_equal(push(&f), GRIP_CAN_FRAME_UNKNOWN);
    assert_int_equal(A.started, 0);   /* none of these starts the step grid */
    memset(&f, 0, sizeof f);
    f.id = 0x18FF0001 | GRIP_CAN_ID_EFF;
    f.flags = GRIP_CAN_FLAG_FD | GRIP_CAN_FLAG_BRS;
    f.len = 12;
    f.data[10] = 0x30;                /* -2000 N m = 0xF830, Intel */
    f.data[11] = 0xF8;
    assert_int_equal(push(&f), GRIP_CAN_FRAME_OK);
    drain(1);
    assert_int_equal(nout, 1);
    assert_near(out[0].value[GRIP_IN_BRAKE_TORQUE_FL], -2000.0, GRIP_IN_BRAKE_TORQUE_FL);
    assert_true(out[0].value[GRIP_IN_BRAKE_TORQUE_FL] == from_si(-2000.0, GRIP_IN_BRAKE_TORQUE_FL));
    assert_int_equal(A.stats.error_frames, 1);
    assert_int_equal(A.stats.rtr_frames, 1);
    assert_int_equal(A.stats.unknown_id, 2);
    assert_int_equal(A.stats.frames, 5);
}

static void test_config_and_null_checks(void **state)
{
    grip_can_asm_config_t cfg = { 10000u, 3u, 0u, 200000u };
    grip_input_sample_t s;
    grip_can_frame_t f;
    (void)state;
    memset(&f, 0, sizeof f);
    assert_int_equal(grip_can_asm_init(NULL, &ST, &cfg), GRIP_ERR_NULL);
    assert_int_equal(grip_can_asm_init(&A, NULL, &cfg), GRIP_ERR_NULL);
    cfg.step_us = 0;
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_ERR_PARAM);
    assert_int_equal(grip_can_asm_push(&A, &f, NULL), GRIP_ERR_STATE);   /* failed init leaves it unusable */
    cfg.step_us = 10000;
    cfg.stale_periods = 0;
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_ERR_PARAM);
    cfg.stale_periods = 3;
    cfg.reorder_us = 10000;   /* not below the 10 ms period of message A */
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_ERR_PARAM);
    cfg.reorder_us = 0;
    cfg.jump_us = 10000u * (GRIP_CAN_MAX_GAP_STEPS + 1u);
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_ERR_PARAM);
    cfg.jump_us = 200000;
    assert_int_equal(grip_can_asm_init(&A, &ST, &cfg), GRIP_OK);
    assert_int_equal(grip_can_asm_poll(&A, 1000000, &s), 0);   /* nothing before the first frame */
    assert_int_equal(grip_can_asm_poll(NULL, 0, &s), 0);
    assert_int_equal(grip_can_asm_poll(&A, 0, NULL), 0);
    assert_int_equal(grip_can_asm_push(NULL, &f, NULL), GRIP_ERR_NULL);
    assert_int_equal(grip_can_asm_push(&A, NULL, NULL), GRIP_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rav4_steps_vs_reference),
        cmocka_unit_test(test_values_and_zero_order_hold),
        cmocka_unit_test(test_stale_after_k_periods),
        cmocka_unit_test(test_range_and_sender_fault_never_give_a_number),
        cmocka_unit_test(test_rejected_frames_keep_the_last_good_value),
        cmocka_unit_test(test_reordered_and_late_frames),
        cmocka_unit_test(test_timestamp_jumps),
        cmocka_unit_test(test_error_remote_unknown_and_fd_frames),
        cmocka_unit_test(test_config_and_null_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
