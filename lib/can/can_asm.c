/*
 * can_asm.c - the sample assembler: aligns CAN messages that arrive at
 * different rates and times to the estimator's fixed step (grip_can.h,
 * docs/can.md).
 *
 * Steps lie on the grid of multiples of step_us in the frames' time base.
 * The sample of step t holds, for each input, the newest value whose frame
 * time is <= t (zero-order hold), if that value is no older than
 * stale_periods x its message's period. Two values per input are kept, so a
 * frame that arrives up to reorder_us late (less than one period) is still
 * placed in time order. A time gap beyond jump_us, forward (poll) or
 * backward (push), restarts the grid and forgets every value: the old
 * values' ages are meaningless in the new time base.
 */
#include <stddef.h>

#include "grip/grip_can.h"
#include "can_internal.h"

#define NO_MESSAGE UINT32_MAX

static void slot_clear(grip_can_slot_t *s)
{
    s->value = R_ZERO;
    s->t_us = 0;
    s->fault = (uint8_t)GRIP_SIG_MISSING;
    s->used = 0u;
}

/* First grid point >= t. */
static int64_t grid_ceil(int64_t t, uint32_t step)
{
    int64_t q = t / (int64_t)step;
    if (t % (int64_t)step != 0 && t < 0) {
        q -= 1;   /* floor division */
    }
    q *= (int64_t)step;
    return (q < t) ? q + (int64_t)step : q;
}

/* (Re)starts the step grid at time t, forgetting every value. */
static void restart(grip_can_asm_t *a, int64_t t)
{
    uint32_t i;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        slot_clear(&a->cur[i]);
        slot_clear(&a->prev[i]);
    }
    for (i = 0u; i < GRIP_CAN_MAX_MESSAGES; i++) {
        a->counter_last[i] = 0u;
        a->counter_have[i] = 0u;
    }
    a->next_t_us = grid_ceil(t, a->cfg.step_us);
    a->newest_t_us = t;
    a->step = 0u;
    a->started = 1u;
}

grip_status_t grip_can_asm_init(grip_can_asm_t *a, const grip_can_table_t *table, const grip_can_asm_config_t *cfg)
{
    uint32_t i;
    uint32_t j;

    if (a == NULL || table == NULL || cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    a->table = NULL;
    a->started = 0u;
    if (grip_can_table_check(table, NULL) != GRIP_OK) {
        return GRIP_ERR_PARAM;
    }
    if (cfg->step_us == 0u || cfg->stale_periods == 0u || cfg->stale_periods > 1000u ||
        cfg->jump_us < cfg->step_us || cfg->jump_us / cfg->step_us > GRIP_CAN_MAX_GAP_STEPS ||
        cfg->reorder_us >= cfg->jump_us) {
        return GRIP_ERR_PARAM;
    }
    for (i = 0u; i < GRIP_CAN_MAX_MESSAGES && i < table->n_messages; i++) {
        if (table->messages[i].n_signals > 0u && cfg->reorder_us >= table->messages[i].period_us) {
            return GRIP_ERR_PARAM;
        }
    }
    a->cfg = *cfg;
    a->next_t_us = 0;
    a->newest_t_us = 0;
    a->step = 0u;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        a->input_msg[i] = NO_MESSAGE;
        slot_clear(&a->cur[i]);
        slot_clear(&a->prev[i]);
    }
    for (i = 0u; i < GRIP_CAN_MAX_MESSAGES; i++) {
        a->counter_last[i] = 0u;
        a->counter_have[i] = 0u;
    }
    for (i = 0u; i < GRIP_CAN_MAX_SIGNALS && i < table->n_signals; i++) {
        a->input_msg[table->signals[i].input] = table->signals[i].message;
    }
    a->stats.frames = 0u;
    a->stats.decoded = 0u;
    a->stats.unknown_id = 0u;
    a->stats.error_frames = 0u;
    a->stats.rtr_frames = 0u;
    a->stats.dlc_errors = 0u;
    a->stats.checksum_errors = 0u;
    a->stats.counter_frozen = 0u;
    a->stats.counter_skips = 0u;
    a->stats.range_errors = 0u;
    a->stats.qualifier_faults = 0u;
    a->stats.reordered = 0u;
    a->stats.late = 0u;
    a->stats.too_old = 0u;
    a->stats.jumps = 0u;
    a->stats.samples = 0u;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        for (j = 0u; j < GRIP_SIG_FAULT_COUNT; j++) {
            a->stats.input_faults[i][j] = 0u;
        }
    }
    a->table = table;
    return GRIP_OK;
}

/* Keeps the two newest values of an input, in time order. */
static void insert(grip_can_asm_t *a, uint32_t input, grip_real_t v, int64_t t, uint8_t fault)
{
    grip_can_slot_t s;
    s.value = v;
    s.t_us = t;
    s.fault = fault;
    s.used = 1u;
    if (a->cur[input].used == 0u || t >= a->cur[input].t_us) {
        a->prev[input] = a->cur[input];
        a->cur[input] = s;
    } else if (a->prev[input].used == 0u || t >= a->prev[input].t_us) {
        a->prev[input] = s;
    } else {
        a->stats.too_old++;
    }
}

/* Checks, decodes and stores one frame; returns its grip_can_frame_fault_t. */
static uint32_t push_frame(grip_can_asm_t *a, const grip_can_frame_t *frame)
{
    const grip_can_table_t *tab = a->table;
    const grip_can_message_t *m;
    uint32_t check;
    int32_t msg;
    int64_t t;
    uint32_t i;

    if ((frame->id & GRIP_CAN_ID_ERR) != 0u) {
        a->stats.error_frames++;
        return (uint32_t)GRIP_CAN_FRAME_ERROR;
    }
    msg = grip_can_find_message(tab, frame->id);
    if (msg < 0) {
        a->stats.unknown_id++;
        return (uint32_t)GRIP_CAN_FRAME_UNKNOWN;
    }
    if ((frame->id & GRIP_CAN_ID_RTR) != 0u) {
        a->stats.rtr_frames++;
        return (uint32_t)GRIP_CAN_FRAME_RTR;
    }
    t = frame->t_us;
    if (a->started == 0u) {
        restart(a, t);
    } else if (t < a->next_t_us - (int64_t)a->cfg.step_us - (int64_t)a->cfg.jump_us) {
        /* far behind the steps already emitted: the clock jumped back */
        a->stats.jumps++;
        restart(a, t);
    } /* grip-deviation: MISRA-15.7 no action for an in-order frame */
    if (t < a->newest_t_us) {
        a->stats.reordered++;
    } else {
        a->newest_t_us = t;
    }
    if (a->step > 0u && t <= a->next_t_us - (int64_t)a->cfg.step_us) {
        a->stats.late++;
    }
    m = &tab->messages[msg];
    check = grip_can_check_frame(tab, (uint32_t)msg, frame);
    if (check == (uint32_t)GRIP_CAN_FRAME_DLC) {
        a->stats.dlc_errors++;
        return check;
    }
    if (check == (uint32_t)GRIP_CAN_FRAME_CHECKSUM) {
        a->stats.checksum_errors++;
        return check;
    }
    if (m->counter_length > 0u) {
        uint64_t c = 0u;
        uint8_t cnt;
        (void)grip_can_extract(frame->data, frame->len, m->counter_start, m->counter_length,
                               m->counter_order, 0u, &c);   /* inside the payload: table check, DLC check */
        cnt = (uint8_t)c;
        if (a->counter_have[msg] != 0u) {
            uint8_t expect = (uint8_t)((a->counter_last[msg] + 1u) & ((1u << m->counter_length) - 1u));
            if (cnt == a->counter_last[msg]) {
                a->stats.counter_frozen++;
                return (uint32_t)GRIP_CAN_FRAME_FROZEN;
            }
            if (cnt != expect) {
                a->stats.counter_skips++;
            }
        }
        a->counter_last[msg] = cnt;
        a->counter_have[msg] = 1u;
    }
    a->stats.decoded++;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        grip_real_t v;
        uint8_t f;
        if (a->input_msg[i] != (uint32_t)msg) {
            continue;
        }
        (void)grip_can_decode_input(tab, (uint32_t)msg, i, frame, &v, &f);
        if (f == (uint8_t)GRIP_SIG_RANGE) {
            a->stats.range_errors++;
        } else if (f == (uint8_t)GRIP_SIG_FAULT) {
            a->stats.qualifier_faults++;
        } /* grip-deviation: MISRA-15.7 no counter for other faults */
        insert(a, i, v, t, f);
    }
    return (uint32_t)GRIP_CAN_FRAME_OK;
}

grip_status_t grip_can_asm_push(grip_can_asm_t *a, const grip_can_frame_t *frame, uint32_t *fault)
{
    uint32_t check;

    if (fault != NULL) {
        *fault = (uint32_t)GRIP_CAN_FRAME_OK;
    }
    if (a == NULL || frame == NULL) {
        return GRIP_ERR_NULL;
    }
    if (a->table == NULL) {
        return GRIP_ERR_STATE;
    }
    a->stats.frames++;
    check = push_frame(a, frame);
    if (fault != NULL) {
        *fault = check;
    }
    return GRIP_OK;
}

int grip_can_asm_poll(grip_can_asm_t *a, int64_t now_us, grip_input_sample_t *out)
{
    int64_t t;
    uint32_t i;

    if (a == NULL || out == NULL || a->table == NULL || a->started == 0u) {
        return 0;
    }
    t = a->next_t_us;
    if (now_us - t > (int64_t)a->cfg.jump_us) {
        /* a gap longer than jump_us: restart the grid at now instead of
         * emitting it step by step */
        a->stats.jumps++;
        restart(a, now_us);
        return 0;
    }
    if (t + (int64_t)a->cfg.reorder_us >= now_us) {
        return 0;
    }
    out->t_us = t;
    out->step = a->step;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        const grip_can_slot_t *s = NULL;
        uint8_t f;
        int64_t age = 0;
        if (a->input_msg[i] == NO_MESSAGE) {
            f = (uint8_t)GRIP_SIG_UNMAPPED;
        } else {
            if (a->cur[i].used != 0u && a->cur[i].t_us <= t) {
                s = &a->cur[i];
            } else if (a->prev[i].used != 0u && a->prev[i].t_us <= t) {
                s = &a->prev[i];
            } /* grip-deviation: MISRA-15.7 s stays NULL: no usable value */
            if (s == NULL) {
                f = (uint8_t)GRIP_SIG_MISSING;
            } else {
                age = t - s->t_us;
                if (age > (int64_t)a->cfg.stale_periods * (int64_t)a->table->messages[a->input_msg[i]].period_us) {
                    f = (uint8_t)GRIP_SIG_STALE;
                } else {
                    f = s->fault;
                }
            }
        }
        out->fault[i] = f;
        out->valid[i] = (f == (uint8_t)GRIP_SIG_OK) ? 1u : 0u;
        out->value[i] = R_ZERO;
        if (f == (uint8_t)GRIP_SIG_OK && s != NULL) {
            out->value[i] = s->value;
        }
        out->age_us[i] = (age > (int64_t)UINT32_MAX) ? UINT32_MAX : (uint32_t)age;
        a->stats.input_faults[i][f]++;
    }
    a->next_t_us = t + (int64_t)a->cfg.step_us;
    a->step++;
    a->stats.samples++;
    return 1;
}
