/*
 * grip_can.h - DBC-driven CAN signal decoding and the sample assembler that
 * turns CAN frames into estimator input samples (grip_signals.h).
 *
 * Data flow (docs/can.md):
 *
 *   frame --> grip_can_asm_push --> message lookup (table, by id)
 *                                   frame checks: DLC, checksum, counter
 *                                   signal extraction and scaling, range
 *                                   newest values per input (2 kept)
 *   grip_can_asm_poll(now) -------> one grip_input_sample_t per estimator step
 *                                   (zero-order hold, staleness check)
 *
 * The signal table is plain constant data, generated from a DBC file and a
 * map file by `python -m grip_tools can-table` (tools/grip_tools/can/dbc.py),
 * either as C source (compiled in, e.g. grip_can_table_rav4) or as a text
 * table loaded at run time (grip_can_table_text_*).
 *
 * Scaling is integer-only: each signal carries K, C and s such that the SI
 * value is (raw * K + C) / 2^s exactly as the generator computed it from the
 * DBC's factor and offset and the unit conversion. The fixed build shifts
 * the 64-bit sum right (rounding) into QS or QL; the float build converts it
 * to float once and scales by 2^-s, so both builds see one rounding only.
 * Range checks compare the raw integer with precomputed raw bounds, so both
 * builds flag exactly the same values.
 *
 * Everything here is portable lib/ code: no heap, bounded loops, caller-owned
 * state. Timestamps are integer microseconds in any time base (a log's, or
 * the kernel's receive time).
 */
#ifndef GRIP_CAN_H
#define GRIP_CAN_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_signals.h"

/* ---- frames ------------------------------------------------------------ */

/* Flags in the id word, with the values of Linux's CAN_*_FLAG. */
#define GRIP_CAN_ID_EFF 0x80000000u   /* 29-bit extended id */
#define GRIP_CAN_ID_RTR 0x40000000u   /* remote transmission request */
#define GRIP_CAN_ID_ERR 0x20000000u   /* error frame (error class in the id bits) */
#define GRIP_CAN_SFF_MASK 0x000007FFu
#define GRIP_CAN_EFF_MASK 0x1FFFFFFFu

/* Frame flags. */
#define GRIP_CAN_FLAG_FD  0x01u       /* CAN FD frame */
#define GRIP_CAN_FLAG_BRS 0x02u       /* FD bit-rate switch */
#define GRIP_CAN_FLAG_ESI 0x04u       /* FD error state indicator */

#define GRIP_CAN_MAX_DATA 64u

typedef struct {
    int64_t t_us;                     /* receive time [us] */
    uint32_t id;                      /* id | GRIP_CAN_ID_* flags */
    uint8_t len;                      /* payload bytes, 0..8 (classic) or 0..64 (FD) */
    uint8_t flags;                    /* GRIP_CAN_FLAG_* */
    uint8_t data[GRIP_CAN_MAX_DATA];
} grip_can_frame_t;

/* ---- signal table -------------------------------------------------------- */

#define GRIP_CAN_MAX_MESSAGES 32u
#define GRIP_CAN_MAX_SIGNALS 64u
#define GRIP_CAN_MAX_TERMS 4u          /* VALUE signals summed into one input */

typedef enum { GRIP_CAN_INTEL = 0, GRIP_CAN_MOTOROLA = 1 } grip_can_byte_order_t;

/* Checksum families, named as opendbc names each car family's scheme
 * (docs/can-families.md; Python reference: tools/grip_tools/can/checksums.py).
 * The checksum lies in a field of the message (checksum_start/_length/
 * _order); grip_can_table_check refuses a field the family does not use. */
typedef enum {
    GRIP_CAN_CSUM_NONE = 0,
    /* Toyota: (id & 0xFF) + (id >> 8 & 0xFF) + (id >> 16 & 0xFF) + (id >> 24)
     * + length + every payload byte except the checksum byte, modulo 256 */
    GRIP_CAN_CSUM_TOYOTA = 1,
    /* Honda: 8 - (nibbles of the id + every payload nibble except the
     * checksum, the low nibble of the last byte), + 3 for 29-bit ids, mod 16 */
    GRIP_CAN_CSUM_HONDA = 2,
    /* Hyundai/Kia CAN FD: CRC-16 poly 0x1021 init 0 over bytes 2.., then the
     * id's low and high byte, XOR a constant of the length; bytes 0-1 */
    GRIP_CAN_CSUM_HKG_CAN_FD = 3,
    /* classic Hyundai/Kia: (16 - every payload nibble but the checksum's) mod 16 */
    GRIP_CAN_CSUM_HYUNDAI = 4,
    /* classic Hyundai/Kia WHL_SPD11: 1 bits outside bits 6-7 of bytes 1, 3,
     * 5, 7, XOR 9, mod 16; checksum in bits 6-7 of bytes 5 (low) and 7 (high) */
    GRIP_CAN_CSUM_HYUNDAI_WHL_SPD = 5,
    /* Volkswagen MQB (AUTOSAR E2E profile 2): CRC-8 poly 0x2F init 0xFF over
     * bytes 1.., then magic[counter] (counter: low nibble of byte 1), XOR 0xFF; byte 0 */
    GRIP_CAN_CSUM_VOLKSWAGEN_MQB = 6,
    /* Subaru: bytes of the id + bytes 1.., mod 256; byte 0 */
    GRIP_CAN_CSUM_SUBARU = 7,
    /* Chrysler: CRC-8 poly 0x1D init 0xFF XOR 0xFF over all bytes but the last; last byte */
    GRIP_CAN_CSUM_CHRYSLER = 8,
    /* FCA Giorgio: CRC-8 poly 0x1D init 0 over all bytes but the last, XOR magic[0]; last byte */
    GRIP_CAN_CSUM_FCA_GIORGIO = 9,
    /* Nissan: CRC-8 poly 0x1D init 0 XOR 0xFF over all bytes but the last; last byte */
    GRIP_CAN_CSUM_NISSAN = 10,
    /* Ford: 0xFF - sum of the protected fields (ids 0x415 and 0x91 only) */
    GRIP_CAN_CSUM_FORD = 11,
    /* XOR of every payload byte but the checksum byte (Volkswagen PQ) */
    GRIP_CAN_CSUM_XOR = 12,
    GRIP_CAN_CSUM_COUNT = 13
} grip_can_checksum_t;

#define GRIP_CAN_MAGIC_LEN 16u         /* per-message checksum constants */

typedef enum {
    GRIP_CAN_ROLE_VALUE = 0,       /* scaled and summed into its input */
    GRIP_CAN_ROLE_QUALIFIER = 1    /* raw must lie in [raw_min, raw_max] or the input is GRIP_SIG_FAULT */
} grip_can_role_t;

typedef struct {
    const char *name;
    uint32_t id;              /* 11-bit id, or 29-bit id | GRIP_CAN_ID_EFF */
    uint32_t period_us;       /* expected transmission period, > 0 */
    uint16_t first_signal;    /* signals[first_signal .. first_signal + n_signals - 1] */
    uint8_t n_signals;
    uint8_t len;              /* the payload length a frame must have */
    uint8_t checksum;         /* grip_can_checksum_t */
    uint8_t checksum_length;  /* bits of the checksum field (0 without checksum) */
    uint8_t checksum_order;   /* grip_can_byte_order_t of the checksum field */
    uint16_t checksum_start;  /* DBC start bit of the checksum field */
    uint8_t counter_length;   /* 0: no rolling counter; else its bits (<= 8) */
    uint8_t counter_order;    /* grip_can_byte_order_t of the counter */
    uint16_t counter_start;   /* DBC start bit of the counter */
    uint8_t magic[GRIP_CAN_MAGIC_LEN]; /* Volkswagen MQB: the byte of each counter value;
                                        * FCA Giorgio: [0] = final XOR; else unused (0) */
} grip_can_message_t;

typedef struct {
    const char *name;
    uint16_t message;         /* index into the table's messages */
    uint16_t start;           /* DBC start bit: Intel = LSB, Motorola = MSB (DBC bit numbering) */
    uint8_t length;           /* bits, 1..64 (VALUE: 1..32) */
    uint8_t order;            /* grip_can_byte_order_t */
    uint8_t is_signed;        /* two's complement */
    uint8_t input;            /* grip_input_id_t fed (or qualified) */
    uint8_t role;             /* grip_can_role_t */
    uint8_t shift;            /* s: SI value = (raw * K + C) / 2^s; F <= s <= 62 (F = 16 QS, 8 QL) */
    int32_t k_mul;            /* K, |K| < 2^30 */
    int64_t c_add;            /* C, |C| < 2^61 */
    int64_t raw_min;          /* valid raw range, inclusive */
    int64_t raw_max;
} grip_can_signal_t;

typedef struct {
    const char *name;
    const grip_can_message_t *messages;   /* sorted by id, ids unique */
    const grip_can_signal_t *signals;     /* grouped by message, in message order */
    uint16_t n_messages;
    uint16_t n_signals;
} grip_can_table_t;

/* Built-in table: Toyota RAV4 2017 (comma2k19), generated from
 * tests/data/comma2k19-rav4/rav4_map.toml. */
extern const grip_can_table_t grip_can_table_rav4;

#define grip_can_table_check GRIP_TYPED(grip_can_table_check)
/* Checks every invariant the decoder relies on (sorted unique ids, signal
 * grouping, bits inside the payload, scaling bounds that cannot overflow,
 * at most one message and GRIP_CAN_MAX_TERMS terms per input, one shift per
 * input). GRIP_OK, GRIP_ERR_NULL, or GRIP_ERR_PARAM with the index of the
 * offending message or signal in *where (if where is not NULL). */
grip_status_t grip_can_table_check(const grip_can_table_t *table, uint32_t *where);

#define grip_can_table_check_detail GRIP_TYPED(grip_can_table_check_detail)
/* The same checks, in the same order; on GRIP_ERR_PARAM *detail (may be
 * NULL) names what failed: part "message" or "signal" with its index in
 * the table, or "input" with the grip_input_id_t (a qualifier without a
 * value), or "" for the table itself; the field ("id", "start", "shift",
 * ...) and the rule it breaks (grip_types.h). */
grip_status_t grip_can_table_check_detail(const grip_can_table_t *table, grip_check_detail_t *detail);

/* ---- decoding ------------------------------------------------------------ */

#define grip_can_extract GRIP_TYPED(grip_can_extract)
/* Raw bits of a signal as a DBC defines it: `length` bits (1..64) from
 * `start` in Intel (little-endian, start = LSB) or Motorola (big-endian,
 * start = MSB in DBC numbering) order, sign-extended to 64 bits when
 * is_signed. GRIP_ERR_INPUT if a bit lies beyond len bytes, GRIP_ERR_PARAM
 * for a bad length or order; *raw is 0 on error. */
grip_status_t grip_can_extract(const uint8_t *data, uint32_t len, uint32_t start, uint32_t length,
                               uint32_t order, uint32_t is_signed, uint64_t *raw);

#define grip_can_toyota_checksum GRIP_TYPED(grip_can_toyota_checksum)
/* The Toyota checksum of a frame whose checksum sits in byte csum_byte. */
uint8_t grip_can_toyota_checksum(uint32_t id, const uint8_t *data, uint32_t len, uint32_t csum_byte);

#define grip_can_checksum_compute GRIP_TYPED(grip_can_checksum_compute)
/* The checksum a frame of message m with this payload must carry (the
 * family, field and magic bytes of m; the id is m's). 0 for
 * GRIP_CAN_CSUM_NONE, a NULL argument or a field the family does not use. */
uint32_t grip_can_checksum_compute(const grip_can_message_t *m, const uint8_t *data, uint32_t len);

#define grip_can_checksum_received GRIP_TYPED(grip_can_checksum_received)
/* The checksum the payload carries in m's checksum field (0 on error). */
uint32_t grip_can_checksum_received(const grip_can_message_t *m, const uint8_t *data, uint32_t len);

#define grip_can_checksum_name GRIP_TYPED(grip_can_checksum_name)
/* The family's name as the text form writes it ("none", "toyota", ...), or
 * NULL for an unknown value. */
const char *grip_can_checksum_name(uint32_t checksum);

#define grip_can_find_message GRIP_TYPED(grip_can_find_message)
/* Index of the message with this id (flags other than EFF ignored), or -1. */
int32_t grip_can_find_message(const grip_can_table_t *table, uint32_t id);

/* Result of a frame check, in the order they are made. */
typedef enum {
    GRIP_CAN_FRAME_OK = 0,
    GRIP_CAN_FRAME_DLC = 1,        /* payload length differs from the table's */
    GRIP_CAN_FRAME_CHECKSUM = 2,   /* checksum mismatch */
    GRIP_CAN_FRAME_FROZEN = 3,     /* rolling counter did not advance */
    GRIP_CAN_FRAME_UNKNOWN = 4,    /* id not in the table */
    GRIP_CAN_FRAME_RTR = 5,        /* remote request: no data */
    GRIP_CAN_FRAME_ERROR = 6       /* error frame */
} grip_can_frame_fault_t;

#define grip_can_check_frame GRIP_TYPED(grip_can_check_frame)
/* DLC and checksum of a frame of message msg (counters need history: see
 * the assembler). Returns a grip_can_frame_fault_t. */
uint32_t grip_can_check_frame(const grip_can_table_t *table, uint32_t msg, const grip_can_frame_t *frame);

typedef struct {
    uint64_t raw_bits;     /* as grip_can_extract */
    grip_real_t value;     /* this signal alone, SI, in its input's format; 0 unless fault == OK */
    uint8_t fault;         /* GRIP_SIG_OK or GRIP_SIG_RANGE (outside raw range, or not representable) */
} grip_can_value_t;

#define grip_can_decode_signal GRIP_TYPED(grip_can_decode_signal)
/* Decodes signal sig of the table from a frame of its message (the frame
 * checks are the caller's). A qualifier's value is its raw integer as
 * grip_real_t (QS). GRIP_ERR_INPUT if the signal lies beyond the payload. */
grip_status_t grip_can_decode_signal(const grip_can_table_t *table, uint32_t sig,
                                     const grip_can_frame_t *frame, grip_can_value_t *out);

#define grip_can_decode_input GRIP_TYPED(grip_can_decode_input)
/* Decodes the input fed by the VALUE signals of message msg: their terms
 * summed before the one rounding, the qualifiers applied. *fault is
 * GRIP_SIG_OK, _RANGE (a term out of range, or the sum not representable),
 * _FAULT (a qualifier) or _UNMAPPED (msg feeds no such input); *value is 0
 * unless OK. */
grip_status_t grip_can_decode_input(const grip_can_table_t *table, uint32_t msg, uint32_t input,
                                    const grip_can_frame_t *frame, grip_real_t *value, uint8_t *fault);

/* ---- sample assembler -------------------------------------------------- */

typedef struct {
    uint32_t step_us;        /* estimator step [us], > 0 */
    uint32_t stale_periods;  /* k >= 1: a value older than k x its message period is stale */
    uint32_t reorder_us;     /* frames may arrive up to this late; must be < every period */
    uint32_t jump_us;        /* a time gap beyond this restarts the step grid; <= GRIP_CAN_MAX_GAP_STEPS steps */
} grip_can_asm_config_t;

#define GRIP_CAN_MAX_GAP_STEPS 100000u

typedef struct {
    uint32_t frames;            /* pushed */
    uint32_t decoded;           /* frames of the table's ids that passed every check */
    uint32_t unknown_id;        /* ids not in the table (ignored) */
    uint32_t error_frames;      /* error frames */
    uint32_t rtr_frames;        /* remote requests of the table's ids (ignored) */
    uint32_t dlc_errors;        /* rejected: wrong payload length */
    uint32_t checksum_errors;   /* rejected: checksum mismatch */
    uint32_t counter_frozen;    /* rejected: rolling counter repeated */
    uint32_t counter_skips;     /* accepted, but the counter skipped values (frames lost upstream) */
    uint32_t range_errors;      /* inputs decoded out of range */
    uint32_t qualifier_faults;  /* inputs flagged faulty by their qualifier */
    uint32_t reordered;         /* frames older than the newest frame seen before */
    uint32_t late;              /* frames at or before an already emitted step */
    uint32_t too_old;           /* values older than both kept for their input (dropped) */
    uint32_t jumps;             /* timestamp jumps: the step grid was restarted */
    uint32_t samples;           /* samples emitted */
    uint32_t input_faults[GRIP_IN_COUNT][GRIP_SIG_FAULT_COUNT]; /* samples per input and fault */
} grip_can_stats_t;

typedef struct {
    grip_real_t value;
    int64_t t_us;
    uint8_t fault;            /* GRIP_SIG_OK, _RANGE or _FAULT */
    uint8_t used;
} grip_can_slot_t;

/* The assembler's state: caller-owned, set up by grip_can_asm_init. */
typedef struct {
    const grip_can_table_t *table;
    grip_can_asm_config_t cfg;
    int64_t next_t_us;        /* time of the next step to emit */
    int64_t newest_t_us;      /* newest frame time pushed */
    uint32_t step;
    uint8_t started;
    uint32_t input_msg[GRIP_IN_COUNT];       /* message feeding each input, or UINT32_MAX */
    grip_can_slot_t cur[GRIP_IN_COUNT];      /* newest value of each input */
    grip_can_slot_t prev[GRIP_IN_COUNT];     /* the one before */
    uint8_t counter_last[GRIP_CAN_MAX_MESSAGES];
    uint8_t counter_have[GRIP_CAN_MAX_MESSAGES];
    grip_can_stats_t stats;
} grip_can_asm_t;

#define grip_can_asm_init GRIP_TYPED(grip_can_asm_init)
/* Checks the table (grip_can_table_check) and the configuration and resets
 * the state. GRIP_ERR_PARAM for a bad table or configuration. */
grip_status_t grip_can_asm_init(grip_can_asm_t *a, const grip_can_table_t *table, const grip_can_asm_config_t *cfg);

#define grip_can_asm_push GRIP_TYPED(grip_can_asm_push)
/* Feeds one received frame. Call grip_can_asm_poll(a, frame->t_us, ...)
 * until it returns 0 BEFORE pushing the frame, so that every step up to
 * the frame's time is emitted with the frames before it. Returns
 * GRIP_OK (also for ignored and rejected frames: see *fault) or GRIP_ERR_NULL
 * / GRIP_ERR_STATE. *fault (may be NULL) receives the grip_can_frame_fault_t. */
grip_status_t grip_can_asm_push(grip_can_asm_t *a, const grip_can_frame_t *frame, uint32_t *fault);

#define grip_can_asm_poll GRIP_TYPED(grip_can_asm_poll)
/* Emits the next estimator step if its time t satisfies t + reorder_us <
 * now_us: returns 1 with *out filled, or 0 (nothing due; *out untouched).
 * Call it in a loop; it returns 1 at most jump_us / step_us + 1 times in a
 * row, then restarts the grid (counted as a jump) instead of emitting a
 * long gap. Before the first frame it returns 0. Returns 0 for NULL. */
int grip_can_asm_poll(grip_can_asm_t *a, int64_t now_us, grip_input_sample_t *out);

/* ---- text tables ----------------------------------------------------------- */

#define GRIP_CAN_TEXT_NAMES 4096u    /* bytes of name storage */
#define GRIP_CAN_TEXT_LINE_MAX 512u  /* longest accepted line */

/* A table read from the text form that `python -m grip_tools can-table`
 * writes (docs/can.md), one line at a time, into caller-owned storage. */
typedef struct {
    grip_can_message_t messages[GRIP_CAN_MAX_MESSAGES];
    grip_can_signal_t signals[GRIP_CAN_MAX_SIGNALS];
    char names[GRIP_CAN_TEXT_NAMES];
    uint32_t names_used;
    uint32_t lines;
    uint8_t have_header;
    uint8_t version;                 /* of the header: 1 or 2 */
    uint8_t pad[2];
    grip_can_table_t table;
} grip_can_table_text_t;

#define grip_can_table_text_init GRIP_TYPED(grip_can_table_text_init)
grip_status_t grip_can_table_text_init(grip_can_table_text_t *b);

#define grip_can_table_text_line GRIP_TYPED(grip_can_table_text_line)
/* Parses one line (len bytes, no terminator needed; a trailing CR/LF is
 * ignored). Blank lines and '#' comments are skipped. GRIP_ERR_INPUT with a
 * constant reason in *why for a malformed line. */
grip_status_t grip_can_table_text_line(grip_can_table_text_t *b, const char *line, uint32_t len,
                                       const char **why);

#define grip_can_table_text_finish GRIP_TYPED(grip_can_table_text_finish)
/* Completes and checks the table; *table points into b. */
grip_status_t grip_can_table_text_finish(grip_can_table_text_t *b, const grip_can_table_t **table,
                                         const char **why);

#define grip_can_table_text_finish_detail GRIP_TYPED(grip_can_table_text_finish_detail)
/* The same, with the failed consistency check of a complete table in
 * *detail (grip_can_table_check_detail; the index of a message or signal
 * counts the msg or sig lines of the text from 0). */
grip_status_t grip_can_table_text_finish_detail(grip_can_table_text_t *b, const grip_can_table_t **table,
                                                const char **why, grip_check_detail_t *detail);

#endif /* GRIP_CAN_H */
