/*
 * can_table_text.c - reads a signal table from its text form, one line at a
 * time, into caller-owned storage (grip_can.h). The form, written by
 * `python -m grip_tools can-table` (docs/can.md):
 *
 *   grip-can-table 2 NAME
 *   msg NAME ID LEN PERIOD_US CHECKSUM CHECKSUM_START CHECKSUM_LENGTH CHECKSUM_ORDER
 *       COUNTER_START COUNTER_LENGTH COUNTER_ORDER MAGIC                 (one line)
 *   sig NAME INPUT ROLE START LENGTH ORDER SIGNED SHIFT K C RAW_MIN RAW_MAX
 *
 * ID is the table key (29-bit ids carry 0x80000000); numbers are decimal
 * or 0x-hex; CHECKSUM a family name (grip_can_checksum_name: none, toyota,
 * honda, ...), ORDER intel|motorola, MAGIC the 16 magic bytes as 32 hex
 * digits or '-' (none), ROLE value|qualifier, INPUT an input name of
 * grip_signals.h. Each sig line belongs to the msg line before it.
 *
 * Version 1 (`grip-can-table 1`), still read and written for tables that
 * need no more, has msg lines
 *   msg NAME ID LEN PERIOD_US CHECKSUM CHECKSUM_BYTE COUNTER_START COUNTER_LENGTH COUNTER_ORDER
 * with CHECKSUM none|toyota and the checksum in byte CHECKSUM_BYTE.
 */
#include <stddef.h>

#include "grip/grip_can.h"
#include "can_internal.h"
#include "../core/check_internal.h"

#define MAX_TOKENS 16u

typedef struct {
    const char *p;
    uint32_t n;
} token_t;

static uint32_t tokenize(const char *line, uint32_t len, token_t *tok, uint32_t *count)
{
    uint32_t i = 0u;
    uint32_t n = 0u;
    while (i < len && i < GRIP_CAN_TEXT_LINE_MAX) {
        uint32_t start;
        while (i < len && i < GRIP_CAN_TEXT_LINE_MAX && (line[i] == ' ' || line[i] == '\t')) {
            i++;
        }
        if (i >= len || i >= GRIP_CAN_TEXT_LINE_MAX) {
            break;
        }
        if (n >= MAX_TOKENS) {
            return 0u;
        }
        start = i;
        while (i < len && i < GRIP_CAN_TEXT_LINE_MAX && line[i] != ' ' && line[i] != '\t') {
            i++;
        }
        tok[n].p = line + start;
        tok[n].n = i - start;
        n++;
    }
    *count = n;
    return 1u;
}

static int tok_is(const token_t *t, const char *word)
{
    uint32_t i;
    for (i = 0u; i < t->n && i < 32u; i++) {
        if (word[i] == '\0' || word[i] != t->p[i]) { /* grip-deviation: arrayIndexOutOfBounds tool false positive: the loop returns at word's NUL */
            return 0;
        }
    }
    return i == t->n && word[i] == '\0';
}

/* Decimal or 0x-hex integer with optional sign, within [lo, hi]. */
static int tok_int(const token_t *t, int64_t lo, int64_t hi, int64_t *v)
{
    uint64_t acc = 0u;
    uint32_t i = 0u;
    uint32_t base = 10u;
    int neg = 0;
    uint64_t limit;
    if (t->n == 0u || t->n > 24u) {
        return 0;
    }
    if (t->p[0] == '-' || t->p[0] == '+') {
        neg = (t->p[0] == '-'); /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
        i = 1u;
    }
    if (i + 1u < t->n && t->p[i] == '0' && (t->p[i + 1u] == 'x' || t->p[i + 1u] == 'X')) {
        base = 16u;
        i += 2u;
    }
    if (i >= t->n) {
        return 0;
    }
    limit = neg ? (uint64_t)INT64_MAX + 1u : (uint64_t)INT64_MAX;
    for (; i < t->n && i < 24u; i++) {
        char c = t->p[i];
        uint32_t d;
        if (c >= '0' && c <= '9') {
            d = (uint32_t)(c - '0');
        } else if (base == 16u && c >= 'a' && c <= 'f') {
            d = (uint32_t)(c - 'a') + 10u;
        } else if (base == 16u && c >= 'A' && c <= 'F') {
            d = (uint32_t)(c - 'A') + 10u;
        } else {
            return 0;
        }
        if (acc > (limit - d) / base) {
            return 0;
        }
        acc = acc * base + d;
    }
    if (neg) {
        *v = (acc == (uint64_t)INT64_MAX + 1u) ? INT64_MIN : -(int64_t)acc; /* grip-deviation: MISRA-7.2 INT64_MAX is a signed <stdint.h> macro; converted explicitly */
    } else {
        *v = (int64_t)acc;
    }
    return *v >= lo && *v <= hi;
}

/* Copies a token into the name storage; NULL when full. */
static const char *keep_name(grip_can_table_text_t *b, const token_t *t)
{
    char *dst;
    uint32_t i;
    if (t->n == 0u || t->n > 64u || b->names_used + t->n + 1u > GRIP_CAN_TEXT_NAMES) {
        return NULL;
    }
    dst = &b->names[b->names_used];
    for (i = 0u; i < t->n && i < 64u; i++) {
        dst[i] = t->p[i];
    }
    dst[t->n] = '\0';
    b->names_used += t->n + 1u;
    return dst;
}

grip_status_t grip_can_table_text_init(grip_can_table_text_t *b)
{
    if (b == NULL) {
        return GRIP_ERR_NULL;
    }
    b->names_used = 0u;
    b->lines = 0u;
    b->have_header = 0u;
    b->version = 0u;
    b->names[0] = '\0';
    b->table.name = b->names;
    b->table.messages = b->messages;
    b->table.signals = b->signals;
    b->table.n_messages = 0u;
    b->table.n_signals = 0u;
    return GRIP_OK;
}

/* The checksum family named by a token, or -1. */
static int64_t checksum_of(const token_t *t)
{
    uint32_t i;
    for (i = 0u; i < (uint32_t)GRIP_CAN_CSUM_COUNT; i++) {
        if (tok_is(t, grip_can_checksum_name(i))) {
            return (int64_t)i;
        }
    }
    return -1;
}

static int hex_digit(char c, uint32_t *d)
{
    if (c >= '0' && c <= '9') {
        *d = (uint32_t)(c - '0');
    } else if (c >= 'a' && c <= 'f') {
        *d = (uint32_t)(c - 'a') + 10u;
    } else if (c >= 'A' && c <= 'F') {
        *d = (uint32_t)(c - 'A') + 10u;
    } else {
        return 0;
    }
    return 1;
}

/* MAGIC: '-' (all zero) or exactly 2 * GRIP_CAN_MAGIC_LEN hex digits. */
static int parse_magic(const token_t *t, uint8_t *magic)
{
    uint32_t i;
    for (i = 0u; i < GRIP_CAN_MAGIC_LEN; i++) {
        magic[i] = 0u;
    }
    if (t->n == 1u && t->p[0] == '-') {
        return 1;
    }
    if (t->n != 2u * GRIP_CAN_MAGIC_LEN) {
        return 0;
    }
    for (i = 0u; i < GRIP_CAN_MAGIC_LEN; i++) {
        uint32_t hi;
        uint32_t lo;
        uint32_t k = 2u * i;
        if (!hex_digit(t->p[k], &hi) || !hex_digit(t->p[k + 1u], &lo)) {
            return 0;
        }
        magic[i] = (uint8_t)((hi << 4) | lo);
    }
    return 1;
}

static grip_status_t parse_msg(grip_can_table_text_t *b, const token_t *tok, uint32_t n, const char **why)
{
    grip_can_message_t *m;
    int64_t v[10];
    uint32_t i;
    uint32_t nf;
    /* version 2: ID LEN PERIOD CHECKSUM CS_START CS_LENGTH CS_ORDER CNT_START CNT_LENGTH CNT_ORDER */
    static const int64_t hi2[10] = { 0xFFFFFFFF, 64, 0xFFFFFFFF, 0, 511, 16, 0, 511, 8, 0 }; /* grip-deviation: MISRA-7.2 int64_t table: the constants are signed by intent */
    /* version 1: ID LEN PERIOD CHECKSUM CHECKSUM_BYTE CNT_START CNT_LENGTH CNT_ORDER */
    static const int64_t hi1[8] = { 0xFFFFFFFF, 64, 0xFFFFFFFF, 0, 63, 511, 8, 0 }; /* grip-deviation: MISRA-7.2 int64_t table: the constants are signed by intent */
    const int64_t *hi = (b->version == 1u) ? hi1 : hi2;
    uint32_t ntok;
    if (b->version == 1u) {
        nf = 8u;
        ntok = 10u;
    } else {
        nf = 10u;
        ntok = 13u;
    }
    if (n != ntok) {
        *why = (b->version == 1u)
                   ? "msg line needs 9 fields: NAME ID LEN PERIOD_US CHECKSUM CHECKSUM_BYTE COUNTER_START "
                     "COUNTER_LENGTH COUNTER_ORDER"
                   : "msg line needs 12 fields: NAME ID LEN PERIOD_US CHECKSUM CHECKSUM_START CHECKSUM_LENGTH "
                     "CHECKSUM_ORDER COUNTER_START COUNTER_LENGTH COUNTER_ORDER MAGIC";
        return GRIP_ERR_INPUT;
    }
    if (b->table.n_messages >= GRIP_CAN_MAX_MESSAGES) {
        *why = "too many messages (GRIP_CAN_MAX_MESSAGES)";
        return GRIP_ERR_INPUT;
    }
    for (i = 0u; i < nf && i < 10u; i++) {
        const token_t *t = &tok[i + 2u];
        if (i == 3u) {   /* checksum family */
            v[i] = checksum_of(t);
            if (b->version == 1u && v[i] > (int64_t)GRIP_CAN_CSUM_TOYOTA) {
                v[i] = -1;
            } /* grip-deviation: MISRA-15.7 a version-2 name is refused in version 1 only */
        } else if (hi[i] == 0) {   /* a byte order */
            v[i] = tok_is(t, "intel") ? 0 : (tok_is(t, "motorola") ? 1 : -1);
        } else if (!tok_int(t, 0, hi[i], &v[i])) {
            v[i] = -1;
        } /* grip-deviation: MISRA-15.7 a valid token needs no action */
        if (v[i] < 0) {
            *why = "msg line: a field is not a number in range (or not a checksum family name, intel|motorola)";
            return GRIP_ERR_INPUT;
        }
    }
    m = &b->messages[b->table.n_messages];
    if (b->version != 1u && !parse_magic(&tok[12], m->magic)) {
        *why = "msg line: MAGIC must be '-' or 32 hex digits";
        return GRIP_ERR_INPUT;
    }
    m->name = keep_name(b, &tok[1]);
    if (m->name == NULL) {
        *why = "names too long or too many (GRIP_CAN_TEXT_NAMES)";
        return GRIP_ERR_INPUT;
    }
    m->id = (uint32_t)v[0];
    m->len = (uint8_t)v[1];
    m->period_us = (uint32_t)v[2];
    m->checksum = (uint8_t)v[3];
    if (b->version == 1u) {
        for (i = 0u; i < GRIP_CAN_MAGIC_LEN; i++) {
            m->magic[i] = 0u;
        }
        m->checksum_start = (m->checksum != (uint8_t)GRIP_CAN_CSUM_NONE) ? (uint16_t)(8 * v[4]) : 0u;
        m->checksum_length = (m->checksum != (uint8_t)GRIP_CAN_CSUM_NONE) ? 8u : 0u;
        m->checksum_order = (uint8_t)GRIP_CAN_INTEL;
        m->counter_start = (uint16_t)v[5];
        m->counter_length = (uint8_t)v[6];
        m->counter_order = (uint8_t)v[7];
    } else {
        m->checksum_start = (uint16_t)v[4];
        m->checksum_length = (uint8_t)v[5];
        m->checksum_order = (uint8_t)v[6];
        m->counter_start = (uint16_t)v[7];
        m->counter_length = (uint8_t)v[8];
        m->counter_order = (uint8_t)v[9];
    }
    m->first_signal = b->table.n_signals;
    m->n_signals = 0u;
    b->table.n_messages++;
    return GRIP_OK;
}

static grip_status_t parse_sig(grip_can_table_text_t *b, const token_t *tok, uint32_t n, const char **why)
{
    grip_can_signal_t *s;
    grip_can_message_t *m;
    int64_t v[7];
    int32_t input;
    uint32_t i;
    static const int64_t lo[7] = { 0, 1, 0, 0, 0, -(((int64_t)1) << 30) + 1, -(((int64_t)1) << 61) + 1 };
    static const int64_t hi[7] = { 511, 64, 1, 1, 62, (((int64_t)1) << 30) - 1, (((int64_t)1) << 61) - 1 };
    if (n != 13u) {
        *why = "sig line needs 12 fields: NAME INPUT ROLE START LENGTH ORDER SIGNED SHIFT K C RAW_MIN RAW_MAX";
        return GRIP_ERR_INPUT;
    }
    if (b->table.n_messages == 0u) {
        *why = "sig line before any msg line";
        return GRIP_ERR_INPUT;
    }
    if (b->table.n_signals >= GRIP_CAN_MAX_SIGNALS) {
        *why = "too many signals (GRIP_CAN_MAX_SIGNALS)";
        return GRIP_ERR_INPUT;
    }
    input = grip_input_find(tok[2].p, tok[2].n);
    if (input < 0) {
        *why = "sig line: unknown input name (see grip_signals.h)";
        return GRIP_ERR_INPUT;
    }
    s = &b->signals[b->table.n_signals];
    if (tok_is(&tok[3], "value")) {
        s->role = (uint8_t)GRIP_CAN_ROLE_VALUE;
    } else if (tok_is(&tok[3], "qualifier")) {
        s->role = (uint8_t)GRIP_CAN_ROLE_QUALIFIER;
    } else {
        *why = "sig line: role must be value or qualifier";
        return GRIP_ERR_INPUT;
    }
    for (i = 0u; i < 7u; i++) {
        const token_t *t = &tok[i + 4u];
        int ok;
        if (i == 2u) {
            v[i] = tok_is(t, "intel") ? 0 : (tok_is(t, "motorola") ? 1 : -1);
            ok = v[i] >= 0; /* grip-deviation: MISRA-10.3 comparison result 0/1 stored in an int flag */
        } else {
            ok = tok_int(t, lo[i], hi[i], &v[i]);
        }
        if (!ok) {
            *why = "sig line: a field is not a number in range (or not intel|motorola)";
            return GRIP_ERR_INPUT;
        }
    }
    if (!tok_int(&tok[11], INT64_MIN, INT64_MAX, &s->raw_min) || !tok_int(&tok[12], INT64_MIN, INT64_MAX, &s->raw_max)) { /* grip-deviation: MISRA-7.2 INT64_MIN/INT64_MAX are <stdint.h> macros */
        *why = "sig line: RAW_MIN / RAW_MAX not integers";
        return GRIP_ERR_INPUT;
    }
    s->name = keep_name(b, &tok[1]);
    if (s->name == NULL) {
        *why = "names too long or too many (GRIP_CAN_TEXT_NAMES)";
        return GRIP_ERR_INPUT;
    }
    s->message = (uint16_t)(b->table.n_messages - 1u);
    s->input = (uint8_t)input;
    s->start = (uint16_t)v[0];
    s->length = (uint8_t)v[1];
    s->order = (uint8_t)v[2];
    s->is_signed = (uint8_t)v[3];
    s->shift = (uint8_t)v[4];
    s->k_mul = (int32_t)v[5];
    s->c_add = v[6];
    m = &b->messages[b->table.n_messages - 1u];
    m->n_signals++;
    b->table.n_signals++;
    return GRIP_OK;
}

grip_status_t grip_can_table_text_line(grip_can_table_text_t *b, const char *line, uint32_t len,
                                       const char **why)
{
    token_t tok[MAX_TOKENS];
    uint32_t n = 0u;
    const char *dummy;

    if (why == NULL) {
        why = &dummy;
    }
    *why = "";
    if (b == NULL || line == NULL) {
        *why = "NULL argument";
        return GRIP_ERR_NULL;
    }
    b->lines++;
    while (len > 0u && (line[len - 1u] == '\n' || line[len - 1u] == '\r')) {
        len--;
    }
    if (len > GRIP_CAN_TEXT_LINE_MAX) {
        *why = "line too long";
        return GRIP_ERR_INPUT;
    }
    if (!tokenize(line, len, tok, &n)) {
        *why = "too many fields";
        return GRIP_ERR_INPUT;
    }
    if (n == 0u || tok[0].p[0] == '#') {
        return GRIP_OK;
    }
    if (tok_is(&tok[0], "grip-can-table")) {
        int64_t version;
        if (b->have_header != 0u || n != 3u || !tok_int(&tok[1], 1, 2, &version)) {
            *why = "header must be the first line: grip-can-table VERSION NAME (VERSION 1 or 2)";
            return GRIP_ERR_INPUT;
        }
        b->version = (uint8_t)version;
        b->table.name = keep_name(b, &tok[2]);
        if (b->table.name == NULL) {
            *why = "table name too long";
            return GRIP_ERR_INPUT;
        }
        b->have_header = 1u;
        return GRIP_OK;
    }
    if (b->have_header == 0u) {
        *why = "not a grip signal table (first line must be: grip-can-table VERSION NAME)";
        return GRIP_ERR_INPUT;
    }
    if (tok_is(&tok[0], "msg")) {
        return parse_msg(b, tok, n, why);
    }
    if (tok_is(&tok[0], "sig")) {
        return parse_sig(b, tok, n, why);
    }
    *why = "unknown line kind (expected msg or sig)";
    return GRIP_ERR_INPUT;
}

grip_status_t grip_can_table_text_finish_detail(grip_can_table_text_t *b, const grip_can_table_t **table,
                                                const char **why, grip_check_detail_t *detail)
{
    const char *dummy;
    if (why == NULL) {
        why = &dummy;
    }
    *why = "";
    check_clear(detail);
    if (b == NULL || table == NULL) {
        *why = "NULL argument";
        return GRIP_ERR_NULL;
    }
    *table = NULL;
    if (b->have_header == 0u) {
        *why = "empty table (no grip-can-table header)";
        return GRIP_ERR_INPUT;
    }
    if (grip_can_table_check_detail(&b->table, detail) != GRIP_OK) {
        *why = "table fails its consistency check (ids sorted and unique, bits inside the payload, "
               "scaling bounds, one message per input)";
        return GRIP_ERR_PARAM;
    }
    *table = &b->table;
    return GRIP_OK;
}

grip_status_t grip_can_table_text_finish(grip_can_table_text_t *b, const grip_can_table_t **table,
                                         const char **why)
{
    return grip_can_table_text_finish_detail(b, table, why, NULL);
}
