/*
 * fuzz_can.c - the CAN frame decoder and sample assembler (lib/can) and the
 * text signal-table reader on hostile input.
 *
 * First byte: mode.
 *   mode even: a frame stream for the built-in RAV4 table. Config from 4
 *     bytes; then frames: [dt (2 bytes, us x 16, signed)] [message selector:
 *     < 0xF0 a table message, else a raw 11/29-bit id from 4 bytes] [len]
 *     [flags] [len data bytes]. Half of the table frames get a correct
 *     Toyota checksum so the decoders behind the checks are reached.
 *     Every frame also goes through grip_can_extract (fuzzed start/length/
 *     order), grip_can_check_frame and grip_can_decode_signal/_input.
 *   mode odd: the rest is text-table lines separated by '\n'; a table that
 *     finishes OK must pass grip_can_table_check and is then used for a
 *     short frame stream made of the same bytes.
 * Properties: no crash or sanitizer report; statuses documented; every
 * emitted sample: value finite, value 0 and fault != OK where not valid,
 * step times strictly increasing (between grid restarts, stats.jumps); stats counters
 * consistent (decoded <= frames); extract errors leave raw = 0.
 */
#include "fuzz_common.h"
#include "grip/grip_can.h"
#include "grip/grip_signals.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_sample(const grip_can_asm_t *a, const grip_input_sample_t *s, int64_t *last_t,
                         uint32_t *jumps)
{
    int i;
    if (a->stats.jumps != *jumps) {   /* the step grid was restarted: time may go back */
        *jumps = a->stats.jumps;
        *last_t = INT64_MIN;
    }
    FZ_CHECK(*last_t == INT64_MIN || s->t_us > *last_t, "sample time %lld not after %lld", (long long)s->t_us,
             (long long)*last_t);
    *last_t = s->t_us;
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        FZ_CHECK(fz_finite(s->value[i]), "input %d non-finite", i);
        FZ_CHECK(s->fault[i] < GRIP_SIG_FAULT_COUNT, "input %d fault %u", i, s->fault[i]);
        if (s->valid[i]) {
            FZ_CHECK(s->fault[i] == GRIP_SIG_OK, "input %d valid with fault %u", i, s->fault[i]);
        } else {
            FZ_CHECK(s->value[i] == 0, "input %d invalid but non-zero", i);
            FZ_CHECK(s->fault[i] != GRIP_SIG_OK, "input %d invalid with fault OK", i);
        }
    }
    FZ_CHECK(a->stats.decoded <= a->stats.frames, "decoded > frames");
}

static void run_frames(const grip_can_table_t *table, fz_reader *r)
{
    static grip_can_asm_t a;   /* large: keep it off the stack */
    grip_can_asm_config_t cfg;
    grip_input_sample_t s;
    int64_t t = 1000000;
    int64_t last_t = INT64_MIN;
    uint32_t jumps = 0;
    int nframes = 0;
    grip_status_t st;

    cfg.step_us = 1000u + 1000u * (uint32_t)(fz_u8(r) % 20u);
    cfg.stale_periods = (uint32_t)(fz_u8(r) % 5u);
    cfg.reorder_us = 500u * (uint32_t)(fz_u8(r) % 8u);
    cfg.jump_us = 100000u * (uint32_t)(fz_u8(r) % 12u);
    st = grip_can_asm_init(&a, table, &cfg);
    FZ_CHECK(st == GRIP_OK || st == GRIP_ERR_PARAM, "asm_init status %d", (int)st);
    if (st != GRIP_OK) {
        return;
    }
    while (r->n > 0 && nframes < 256) {
        grip_can_frame_t f;
        uint8_t sel;
        uint32_t fault = 99u;
        int16_t dt = (int16_t)(uint16_t)(fz_u8(r) | (fz_u8(r) << 8));
        int32_t msg = -1;
        uint32_t i;
        int polls = 0;
        memset(&f, 0, sizeof f);
        t += (int64_t)dt * 16;
        f.t_us = t;
        sel = fz_u8(r);
        if (sel < 0xF0u && table->n_messages > 0u) {
            msg = (int32_t)(sel % table->n_messages);
            f.id = table->messages[msg].id;
        } else {
            f.id = fz_u32(r);
        }
        f.len = (uint8_t)(fz_u8(r) % (GRIP_CAN_MAX_DATA + 1u));
        f.flags = fz_u8(r);
        for (i = 0; i < f.len; i++) {
            f.data[i] = fz_u8(r);
        }
        if (msg >= 0 && (sel & 1u) && table->messages[msg].checksum == GRIP_CAN_CSUM_TOYOTA &&
            table->messages[msg].checksum_start / 8u < f.len) {
            uint32_t cb = table->messages[msg].checksum_start / 8u;
            f.data[cb] = grip_can_toyota_checksum(f.id, f.data, f.len, cb);
        }
        /* stateless decoders */
        {
            uint64_t raw = 1u;
            uint32_t start = fz_u8(r);
            uint32_t length = fz_u8(r) % 70u;
            uint32_t mode = fz_u8(r);
            grip_status_t se = grip_can_extract(f.data, f.len, start * 2u, length, mode & 3u, (mode >> 2) & 1u, &raw);
            FZ_CHECK(se == GRIP_OK || se == GRIP_ERR_INPUT || se == GRIP_ERR_PARAM, "extract status %d", (int)se);
            if (se != GRIP_OK) {
                FZ_CHECK(raw == 0u, "extract error with raw != 0");
            }
        }
        if (msg >= 0) {
            const grip_can_message_t *m = &table->messages[msg];
            uint32_t cf = grip_can_check_frame(table, (uint32_t)msg, &f);
            FZ_CHECK(cf <= GRIP_CAN_FRAME_ERROR, "check_frame %u", cf);
            for (i = m->first_signal; i < (uint32_t)m->first_signal + m->n_signals; i++) {
                grip_can_value_t v;
                grip_status_t sd = grip_can_decode_signal(table, i, &f, &v);
                FZ_CHECK(fz_status_known(sd), "decode_signal status %d", (int)sd);
                FZ_CHECK(fz_finite(v.value), "decode_signal non-finite");
                if (sd == GRIP_OK && v.fault != GRIP_SIG_OK) {
                    FZ_CHECK(v.value == 0, "decode_signal fault with value");
                }
            }
            for (i = 0; i < GRIP_IN_COUNT; i++) {
                grip_real_t val = 1;
                uint8_t ft = 0xFFu;
                grip_status_t sd = grip_can_decode_input(table, (uint32_t)msg, i, &f, &val, &ft);
                FZ_CHECK(fz_status_known(sd), "decode_input status %d", (int)sd);
                FZ_CHECK(fz_finite(val), "decode_input non-finite");
                if (sd == GRIP_OK) {
                    FZ_CHECK(ft < GRIP_SIG_FAULT_COUNT, "decode_input fault %u", ft);
                    FZ_CHECK(ft == GRIP_SIG_OK || val == 0, "decode_input fault with value");
                }
            }
        }
        /* the assembler, as documented: poll up to the frame's time, then push */
        while (grip_can_asm_poll(&a, f.t_us, &s) == 1) {
            check_sample(&a, &s, &last_t, &jumps);
            FZ_CHECK(++polls <= 200000, "poll does not stop");
        }
        st = grip_can_asm_push(&a, &f, &fault);
        FZ_CHECK(st == GRIP_OK, "push status %d", (int)st);
        FZ_CHECK(fault <= GRIP_CAN_FRAME_ERROR, "push fault %u", fault);
        nframes++;
    }
    /* drain */
    {
        int polls = 0;
        while (grip_can_asm_poll(&a, t + 50000, &s) == 1) {
            check_sample(&a, &s, &last_t, &jumps);
            FZ_CHECK(++polls <= 200000, "poll does not stop");
        }
    }
    FZ_CHECK(grip_can_asm_poll(NULL, t, &s) == 0, "poll NULL");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    uint8_t mode = fz_u8(&r);
    if ((mode & 1u) == 0u) {
        run_frames(&grip_can_table_rav4, &r);
    } else {
        static grip_can_table_text_t b;
        const grip_can_table_t *table = NULL;
        const char *why = NULL;
        grip_status_t st = grip_can_table_text_init(&b);
        size_t i = 0;
        FZ_CHECK(st == GRIP_OK, "text_init");
        while (i < r.n) {
            size_t j = i;
            while (j < r.n && r.p[j] != '\n') {
                j++;
            }
            st = grip_can_table_text_line(&b, (const char *)r.p + i, (uint32_t)(j - i), &why);
            FZ_CHECK(fz_status_known(st), "text_line status %d", (int)st);
            if (st != GRIP_OK) {
                FZ_CHECK(why != NULL, "text_line error without reason");
                return 0;
            }
            i = j + 1;
        }
        st = grip_can_table_text_finish(&b, &table, &why);
        FZ_CHECK(fz_status_known(st), "text_finish status %d", (int)st);
        if (st == GRIP_OK) {
            uint32_t where = 0;
            FZ_CHECK(table != NULL, "finish OK without table");
            FZ_CHECK(grip_can_table_check(table, &where) == GRIP_OK, "finished table fails check at %u", where);
            r.p = data;
            r.n = size;
            run_frames(table, &r);
        }
    }
    return 0;
}
