/*
 * can_decode.c - signal extraction, frame checks and integer scaling of the
 * DBC-driven CAN decoder (grip_can.h, docs/can.md).
 */
#include <stddef.h>

#include "grip/grip_can.h"
#include "can_internal.h"
#include "../core/check_internal.h"

#if !GRIP_ARITH_FIXED
#include <math.h>
#endif

/* Right shift of a negative int64_t must be arithmetic (checked once more
 * here; lib/arith/q16.c relies on it too). */
typedef char can_check_arith_shift[((-8 >> 1) == -4) ? 1 : -1];

grip_status_t grip_can_extract(const uint8_t *data, uint32_t len, uint32_t start, uint32_t length,
                               uint32_t order, uint32_t is_signed, uint64_t *raw)
{
    uint64_t acc = 0u;
    uint32_t got = 0u;
    uint32_t pos = start;
    uint32_t i;

    if (raw == NULL) {
        return GRIP_ERR_NULL;
    }
    *raw = 0u;
    if (data == NULL) {
        return GRIP_ERR_NULL;
    }
    if (length < 1u || length > 64u || order > (uint32_t)GRIP_CAN_MOTOROLA || len > GRIP_CAN_MAX_DATA) {
        return GRIP_ERR_PARAM;
    }
    if (order == (uint32_t)GRIP_CAN_INTEL) {
        /* start is the least significant bit; bits run upwards through the
         * bytes (bit b of byte n is bit 8n + b). */
        if (start > 8u * GRIP_CAN_MAX_DATA || start + length > 8u * len) {
            return GRIP_ERR_INPUT;
        }
        for (i = 0u; i < 9u && got < length; i++) {
            uint32_t bit = pos & 7u;
            uint32_t take = 8u - bit;
            if (take > length - got) {
                take = length - got;
            }
            acc |= (((uint64_t)data[pos >> 3] >> bit) & ((1u << take) - 1u)) << got;
            got += take;
            pos += take;
        }
    } else {
        /* start is the most significant bit; within a byte bits run from
         * high to low, then continue at bit 7 of the next byte. */
        for (i = 0u; i < 9u && got < length; i++) {
            uint32_t byte = pos >> 3;
            uint32_t bit = pos & 7u;
            uint32_t take = bit + 1u;
            if (byte >= len) {
                return GRIP_ERR_INPUT;
            }
            if (take > length - got) {
                take = length - got;
            }
            acc = (acc << take) | (((uint64_t)data[byte] >> (bit + 1u - take)) & ((1u << take) - 1u)); /* grip-deviation: MISRA-10.7 take <= 8: the mask fits 32 bits before widening */
            got += take;
            pos = 8u * (byte + 1u) + 7u;
        }
    }
    if (is_signed != 0u && length < 64u && ((acc >> (length - 1u)) & 1u) != 0u) { /* grip-deviation: MISRA-10.7 unsigned 64-bit shift of acc, 1u mask widened as intended */
        acc |= ~(uint64_t)0u << length;
    }
    *raw = acc;
    return GRIP_OK;
}

uint8_t grip_can_toyota_checksum(uint32_t id, const uint8_t *data, uint32_t len, uint32_t csum_byte)
{
    uint32_t sum;
    uint32_t i;
    uint32_t bare = ((id & GRIP_CAN_ID_EFF) != 0u) ? (id & GRIP_CAN_EFF_MASK) : (id & GRIP_CAN_SFF_MASK);

    sum = (bare & 0xFFu) + ((bare >> 8) & 0xFFu) + ((bare >> 16) & 0xFFu) + (bare >> 24) + len;
    if (data == NULL) {
        return 0u;
    }
    for (i = 0u; i < GRIP_CAN_MAX_DATA && i < len; i++) {
        if (i != csum_byte) {
            sum += data[i];
        }
    }
    return (uint8_t)(sum & 0xFFu);
}

uint32_t can_id_key(uint32_t id)
{
    return ((id & GRIP_CAN_ID_EFF) != 0u) ? (id & (GRIP_CAN_ID_EFF | GRIP_CAN_EFF_MASK)) : (id & GRIP_CAN_SFF_MASK);
}

int32_t grip_can_find_message(const grip_can_table_t *table, uint32_t id)
{
    uint32_t key = can_id_key(id);
    uint32_t lo = 0u;
    uint32_t hi;
    uint32_t i;

    if (table == NULL || table->messages == NULL) {
        return -1;
    }
    hi = table->n_messages;   /* search [lo, hi) */
    for (i = 0u; i < 32u && lo < hi; i++) {
        uint32_t mid = lo + (hi - lo) / 2u;
        uint32_t k = table->messages[mid].id;
        if (k == key) {
            return (int32_t)mid;
        }
        if (k < key) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return -1;
}

uint32_t grip_can_check_frame(const grip_can_table_t *table, uint32_t msg, const grip_can_frame_t *frame)
{
    const grip_can_message_t *m;

    if (table == NULL || frame == NULL || msg >= table->n_messages) {
        return (uint32_t)GRIP_CAN_FRAME_UNKNOWN;
    }
    if ((frame->id & GRIP_CAN_ID_ERR) != 0u) {
        return (uint32_t)GRIP_CAN_FRAME_ERROR;
    }
    if ((frame->id & GRIP_CAN_ID_RTR) != 0u) {
        return (uint32_t)GRIP_CAN_FRAME_RTR;
    }
    m = &table->messages[msg];
    if (frame->len != m->len) {
        return (uint32_t)GRIP_CAN_FRAME_DLC;
    }
    if (m->checksum != (uint8_t)GRIP_CAN_CSUM_NONE &&
        grip_can_checksum_compute(m, frame->data, frame->len) != grip_can_checksum_received(m, frame->data, frame->len)) {
        return (uint32_t)GRIP_CAN_FRAME_CHECKSUM;
    }
    return (uint32_t)GRIP_CAN_FRAME_OK;
}

/* Raw value of signal s as a signed integer (length <= 32 guaranteed by the
 * table check), or GRIP_ERR_INPUT if it lies beyond the payload. */
static grip_status_t raw_of(const grip_can_signal_t *s, const grip_can_frame_t *f, uint64_t *bits, int64_t *raw)
{
    grip_status_t st = grip_can_extract(f->data, f->len, s->start, s->length, s->order, s->is_signed, bits);
    *raw = (int64_t)*bits;
    return st;
}

/* SI value (raw sum acc) / 2^shift in the input's format: fixed builds
 * shift right with rounding (half up) into QS or QL, float builds convert
 * once and scale by a power of two (exact). GRIP_SIG_RANGE if the fixed
 * result does not fit. */
uint8_t can_scale(int64_t acc, uint32_t shift, uint32_t input, grip_real_t *out)
{
#if GRIP_ARITH_FIXED
    uint32_t frac = grip_input_is_ql(input) ? (uint32_t)GRIP_QL_BITS : (uint32_t)GRIP_QS_BITS;
    uint32_t sh = shift - frac;   /* shift >= frac (table check) */
    int64_t v = (sh > 0u) ? ((acc + ((int64_t)1 << (sh - 1u))) >> sh) : acc;
    if (v > (int64_t)INT32_MAX || v < -(int64_t)INT32_MAX) {
        *out = R_ZERO;
        return (uint8_t)GRIP_SIG_RANGE;
    }
    *out = (grip_real_t)v;
    return (uint8_t)GRIP_SIG_OK;
#else
    (void)input;
    *out = ldexpf((float)acc, -(int)shift);
    return (uint8_t)GRIP_SIG_OK;
#endif
}

grip_status_t grip_can_decode_signal(const grip_can_table_t *table, uint32_t sig,
                                     const grip_can_frame_t *frame, grip_can_value_t *out)
{
    const grip_can_signal_t *s;
    int64_t raw;
    grip_status_t st;

    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    out->raw_bits = 0u;
    out->value = R_ZERO;
    out->fault = (uint8_t)GRIP_SIG_RANGE;
    if (table == NULL || frame == NULL || table->signals == NULL) {
        return GRIP_ERR_NULL;
    }
    if (sig >= table->n_signals) {
        return GRIP_ERR_PARAM;
    }
    s = &table->signals[sig];
    st = raw_of(s, frame, &out->raw_bits, &raw);
    if (st != GRIP_OK) {
        return st;
    }
    if (raw < s->raw_min || raw > s->raw_max) {
        out->fault = (s->role == (uint8_t)GRIP_CAN_ROLE_QUALIFIER) ? (uint8_t)GRIP_SIG_FAULT : (uint8_t)GRIP_SIG_RANGE;
        return GRIP_OK;
    }
    if (s->role == (uint8_t)GRIP_CAN_ROLE_QUALIFIER) {
        out->fault = (uint8_t)GRIP_SIG_OK;
        return GRIP_OK;
    }
    out->fault = can_scale(raw * (int64_t)s->k_mul + s->c_add, s->shift, s->input, &out->value);
    return GRIP_OK;
}

grip_status_t grip_can_decode_input(const grip_can_table_t *table, uint32_t msg, uint32_t input,
                                    const grip_can_frame_t *frame, grip_real_t *value, uint8_t *fault)
{
    const grip_can_message_t *m;
    int64_t acc = 0;
    uint32_t shift = 0u;
    uint32_t terms = 0u;
    uint8_t f = (uint8_t)GRIP_SIG_OK;
    uint32_t i;

    if (value == NULL || fault == NULL) {
        return GRIP_ERR_NULL;
    }
    *value = R_ZERO;
    *fault = (uint8_t)GRIP_SIG_UNMAPPED;
    if (table == NULL || frame == NULL || table->messages == NULL || table->signals == NULL) {
        return GRIP_ERR_NULL;
    }
    if (msg >= table->n_messages || input >= (uint32_t)GRIP_IN_COUNT) {
        return GRIP_ERR_PARAM;
    }
    m = &table->messages[msg];
    for (i = 0u; i < GRIP_CAN_MAX_SIGNALS && i < m->n_signals; i++) {
        const grip_can_signal_t *s = &table->signals[(uint32_t)m->first_signal + i];
        uint64_t bits;
        int64_t raw;
        if (s->input != input) {
            continue;
        }
        if (raw_of(s, frame, &bits, &raw) != GRIP_OK) {
            *fault = (uint8_t)GRIP_SIG_RANGE;
            return GRIP_ERR_INPUT;
        }
        if (s->role == (uint8_t)GRIP_CAN_ROLE_QUALIFIER) {
            if ((raw < s->raw_min || raw > s->raw_max) && f == (uint8_t)GRIP_SIG_OK) {
                f = (uint8_t)GRIP_SIG_FAULT;
            }
            continue;
        }
        terms++;
        shift = s->shift;
        if (raw < s->raw_min || raw > s->raw_max) {
            f = (uint8_t)GRIP_SIG_RANGE;   /* a range error outranks a qualifier fault */
            continue;
        }
        /* No overflow: the table check bounds the sum of every input's terms. */
        acc += raw * (int64_t)s->k_mul + s->c_add;
    }
    if (terms == 0u) {
        return GRIP_OK;   /* UNMAPPED */
    }
    if (f == (uint8_t)GRIP_SIG_OK) {
        f = can_scale(acc, shift, input, value);
    }
    *fault = f;
    return GRIP_OK;
}

/* |x| as uint64 (x > INT64_MIN guaranteed by the callers' bounds). */
static uint64_t mag(int64_t x)
{
    return (x < 0) ? (uint64_t)(-x) : (uint64_t)x;
}

/* Does the signal's every bit lie inside a payload of len bytes? */
static int bits_fit(uint32_t start, uint32_t length, uint32_t order, uint32_t len)
{
    uint8_t probe[GRIP_CAN_MAX_DATA] = { 0u }; /* grip-deviation: MISRA-9.3 {0} zero-initializes the whole array (C99 6.7.8) */
    uint64_t raw;
    return grip_can_extract(probe, len, start, length, order, 0u, &raw) == GRIP_OK;
}

/* The rule a message of the table breaks ("" if none); index i. */
static const char *table_message_rule(const grip_can_table_t *table, uint32_t i, const char **field)
{
    const grip_can_message_t *m = &table->messages[i];
    const char *rule = "";
    *field = "id";
    if (m->id != can_id_key(m->id)) {
        rule = "must be an 11-bit id or a 29-bit id with the extended flag";
    } else if (i > 0u && m->id <= table->messages[i - 1u].id) {
        rule = "must be greater than the id of the message before it (sorted, unique)";
    } else if (m->period_us == 0u) {
        *field = "period_us";
        rule = "must be > 0";
    } else if (m->len > GRIP_CAN_MAX_DATA) {
        *field = "len";
        rule = "must be at most 64 bytes";
    } else if ((uint32_t)m->first_signal + m->n_signals > table->n_signals ||
               (i > 0u && m->first_signal != table->messages[i - 1u].first_signal + table->messages[i - 1u].n_signals) ||
               (i == 0u && m->first_signal != 0u)) {
        *field = "first_signal";
        rule = "the signals must follow their message, in message order";
    } else if (!can_checksum_layout_ok(m) ||
               (m->checksum != (uint8_t)GRIP_CAN_CSUM_NONE &&
                !bits_fit(m->checksum_start, m->checksum_length, m->checksum_order, m->len))) {
        *field = "checksum";
        rule = "the checksum's bits must lie inside the payload, in the layout of its scheme";
    } else if (m->counter_length > 8u ||
               (m->counter_length > 0u && !bits_fit(m->counter_start, m->counter_length, m->counter_order, m->len))) {
        *field = "counter";
        rule = "the counter must have at most 8 bits, inside the payload";
    } else {
        *field = "";
    }
    return rule;
}

/* The rule a signal breaks ("" if none), before the per-input sums. */
static const char *table_signal_rule(const grip_can_table_t *table, uint32_t i, const char **field)
{
    const grip_can_signal_t *s = &table->signals[i];
    const char *rule = "";
    *field = "";
    if (s->message >= table->n_messages) {
        *field = "message";
        rule = "must name a message of the table";
    } else if (s->input >= (uint8_t)GRIP_IN_COUNT) {
        *field = "input";
        rule = "must be an input of grip_signals.h";
    } else if (s->role > (uint8_t)GRIP_CAN_ROLE_QUALIFIER) {
        *field = "role";
        rule = "must be value or qualifier";
    } else if (s->length < 1u || s->length > 32u || s->order > (uint8_t)GRIP_CAN_MOTOROLA || s->is_signed > 1u) {
        *field = "length";
        rule = "must be 1..32 bits, intel or motorola, signed 0 or 1";
    } else if (s->raw_min > s->raw_max) {
        *field = "raw_min";
        rule = "must not be greater than raw_max";
    } else if (i < table->messages[s->message].first_signal ||
               i >= (uint32_t)table->messages[s->message].first_signal + table->messages[s->message].n_signals) {
        *field = "message";
        rule = "the signal must lie in its message's group of signals";
    } else if (!bits_fit(s->start, s->length, s->order, table->messages[s->message].len)) {
        *field = "start";
        rule = "the signal's bits must lie inside its message's payload";
    } else {
        /* consistent */
    }
    return rule;
}

grip_status_t grip_can_table_check_detail(const grip_can_table_t *table, grip_check_detail_t *detail)
{
    uint32_t i;
    uint32_t j;
    uint32_t input_msg[GRIP_IN_COUNT];
    uint32_t input_terms[GRIP_IN_COUNT];
    uint32_t input_shift[GRIP_IN_COUNT];
    uint64_t input_bound[GRIP_IN_COUNT];
    const char *field = "";
    const char *rule;

    check_clear(detail);
    if (table == NULL || table->messages == NULL || table->signals == NULL) {
        return GRIP_ERR_NULL;
    }
    if (table->n_messages > GRIP_CAN_MAX_MESSAGES) {
        (void)check_fail(detail, "", -1, "n_messages", "must be at most GRIP_CAN_MAX_MESSAGES");
        return GRIP_ERR_PARAM;
    }
    if (table->n_signals > GRIP_CAN_MAX_SIGNALS) {
        (void)check_fail(detail, "", -1, "n_signals", "must be at most GRIP_CAN_MAX_SIGNALS");
        return GRIP_ERR_PARAM;
    }
    for (j = 0u; j < (uint32_t)GRIP_IN_COUNT; j++) {
        input_msg[j] = UINT32_MAX;
        input_terms[j] = 0u;
        input_shift[j] = 0u;
        input_bound[j] = 0u;
    }
    for (i = 0u; i < GRIP_CAN_MAX_MESSAGES && i < table->n_messages; i++) {
        rule = table_message_rule(table, i, &field);
        if (rule[0] != '\0') {
            (void)check_fail(detail, "message", (int32_t)i, field, rule);
            return GRIP_ERR_PARAM;
        }
    }
    if (table->n_messages > 0u) {
        const grip_can_message_t *last = &table->messages[table->n_messages - 1u];
        if ((uint32_t)last->first_signal + last->n_signals != table->n_signals) {
            (void)check_fail(detail, "message", (int32_t)table->n_messages - 1, "n_signals",
                             "the messages' signals must add up to the table's signals");
            return GRIP_ERR_PARAM;
        }
    } else if (table->n_signals != 0u) {
        (void)check_fail(detail, "", -1, "n_signals", "must be 0 in a table without messages");
        return GRIP_ERR_PARAM;
    } /* grip-deviation: MISRA-15.7 consistent table: nothing to reject */
    for (i = 0u; i < GRIP_CAN_MAX_SIGNALS && i < table->n_signals; i++) {
        const grip_can_signal_t *s = &table->signals[i];
        uint64_t term;
        rule = table_signal_rule(table, i, &field);
        if (rule[0] != '\0') {
            (void)check_fail(detail, "signal", (int32_t)i, field, rule);
            return GRIP_ERR_PARAM;
        }
        if (input_msg[s->input] != UINT32_MAX && input_msg[s->input] != s->message) {
            (void)check_fail(detail, "signal", (int32_t)i, "input",
                             "an input must come from one message (another message feeds it)");
            return GRIP_ERR_PARAM;
        }
        input_msg[s->input] = s->message;
        if (s->role == (uint8_t)GRIP_CAN_ROLE_QUALIFIER) {
            continue;
        }
        if (s->shift < (grip_input_is_ql(s->input) ? (uint32_t)GRIP_QL_BITS : (uint32_t)GRIP_QS_BITS) ||
            s->shift > 62u) {
            (void)check_fail(detail, "signal", (int32_t)i, "shift", "must be in [F, 62] (F = 16 QS, 8 QL)");
            return GRIP_ERR_PARAM;
        }
        if (s->k_mul >= (1 << 30) || s->k_mul <= -(1 << 30) || mag(s->c_add) >= ((uint64_t)1u << 61)) {
            (void)check_fail(detail, "signal", (int32_t)i, "k", "|K| must be < 2^30 and |C| < 2^61");
            return GRIP_ERR_PARAM;
        }
        if ((input_terms[s->input] > 0u && input_shift[s->input] != s->shift) ||
            input_terms[s->input] >= GRIP_CAN_MAX_TERMS) {
            (void)check_fail(detail, "signal", (int32_t)i, "input",
                             "the value signals of one input must share one shift, at most GRIP_CAN_MAX_TERMS");
            return GRIP_ERR_PARAM;
        }
        /* |raw| <= 2^length (<= 2^32), |K| < 2^30: each term < 2^62 + 2^61;
         * the input's sum must stay below 2^62 (room for the rounding). */
        term = ((uint64_t)1u << s->length) * mag((int64_t)s->k_mul) + mag(s->c_add);
        input_bound[s->input] += term;
        if (input_bound[s->input] >= ((uint64_t)1u << 62)) {
            (void)check_fail(detail, "signal", (int32_t)i, "k",
                             "the input's scaled sum could overflow (2^62)");
            return GRIP_ERR_PARAM;
        }
        input_terms[s->input]++;
        input_shift[s->input] = s->shift;
    }
    for (j = 0u; j < (uint32_t)GRIP_IN_COUNT; j++) {
        if (input_msg[j] != UINT32_MAX && input_terms[j] == 0u) {
            (void)check_fail(detail, "input", (int32_t)j, "role", "a qualifier needs a value signal of its input");
            return GRIP_ERR_PARAM;
        }
    }
    return GRIP_OK;
}

grip_status_t grip_can_table_check(const grip_can_table_t *table, uint32_t *where)
{
    grip_check_detail_t d;
    grip_status_t st = grip_can_table_check_detail(table, &d);
    if (where != NULL) {
        *where = (st == GRIP_ERR_PARAM && d.index >= 0) ? (uint32_t)d.index : 0u;
    }
    return st;
}
