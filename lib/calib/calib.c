/*
 * calib.c - sensor calibration stage (offset, gain, delay alignment) of the
 * estimator's inputs. Definition: include/grip/grip_calib.h; reference
 * tools/grip_tools/reference/calib.py; docs/calibration.md.
 */
#include <stddef.h>

#include "grip/grip_calib.h"
#include "arith.h"

#define CALIB_MAGIC 0x43414c42u   /* "CALB" */

static int in_range(grip_real_t x, grip_real_t lo, grip_real_t hi)
{
    return r_is_finite(x) && x >= lo && x <= hi;
}

grip_status_t grip_calib_config_identity(grip_calib_config_t *cfg)
{
    uint32_t i;
    if (cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
        cfg->offset[i] = R_ZERO;
        cfg->gain[i] = R_ONE;
        cfg->delay[i] = 0u;
    }
    return GRIP_OK;
}

grip_status_t grip_calib_reset(grip_calib_t *c)
{
    uint32_t k, i;
    if (c == NULL) {
        return GRIP_ERR_NULL;
    }
    if (c->magic != CALIB_MAGIC) {
        return GRIP_ERR_STATE;
    }
    c->head = 0u;
    c->filled = 0u;
    for (k = 0u; k < GRIP_CALIB_RING; ++k) {
        c->t_us[k] = 0;
        for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
            c->value[k][i] = R_ZERO;
            c->age_us[k][i] = 0u;
            c->valid[k][i] = 0u;
            c->fault[k][i] = (uint8_t)GRIP_SIG_MISSING;
        }
    }
    return GRIP_OK;
}

grip_status_t grip_calib_init(grip_calib_t *c, const grip_calib_config_t *cfg)
{
    uint32_t i;
    if (c == NULL || cfg == NULL) {
        return GRIP_ERR_NULL;
    }
    c->magic = 0u;
    for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
        if (!in_range(cfg->offset[i], RC(-10.0), RC(10.0)) || !in_range(cfg->gain[i], RC(0.5), RC(2.0)) ||
            cfg->delay[i] > GRIP_CALIB_DELAY_MAX) {
            return GRIP_ERR_PARAM;
        }
    }
    c->cfg = *cfg;
    c->magic = CALIB_MAGIC;
    return grip_calib_reset(c);
}

static uint32_t age_add(uint32_t age, int64_t dt_us)
{
    int64_t a = (int64_t)age + ((dt_us > 0) ? dt_us : 0);
    return (a > (int64_t)UINT32_MAX) ? UINT32_MAX : (uint32_t)a;
}

grip_status_t grip_calib_apply(grip_calib_t *c, const grip_input_sample_t *in, grip_input_sample_t *out)
{
    uint32_t i, h;
    if (in == NULL || out == NULL) {
        return GRIP_ERR_NULL;
    }
    if (out != in) {
        *out = *in;
    }
    if (c == NULL || c->magic != CALIB_MAGIC) {
        for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
            out->value[i] = R_ZERO;
            out->valid[i] = 0u;
            out->fault[i] = (uint8_t)GRIP_SIG_MISSING;
            out->age_us[i] = 0u;
        }
        return (c == NULL) ? GRIP_ERR_NULL : GRIP_ERR_STATE;
    }
    /* push the raw sample */
    h = (c->filled == 0u) ? 0u : ((c->head + 1u) % GRIP_CALIB_RING);
    c->head = h;
    if (c->filled < GRIP_CALIB_RING) {
        c->filled += 1u;
    }
    c->t_us[h] = in->t_us;
    for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
        c->value[h][i] = in->value[i];
        c->valid[h][i] = in->valid[i];
        c->fault[h][i] = in->fault[i];
        c->age_us[h][i] = in->age_us[i];
    }
    /* delayed, corrected output */
    for (i = 0u; i < (uint32_t)GRIP_CALIB_N; ++i) {
        uint32_t d = c->cfg.delay[i];
        grip_real_t v = R_ZERO;
        uint8_t ok = 0u, fault = (uint8_t)GRIP_SIG_MISSING;
        uint32_t age = 0u;
        if (d < c->filled) {
            uint32_t k = (h + GRIP_CALIB_RING - d) % GRIP_CALIB_RING;
            ok = c->valid[k][i] ? 1u : 0u;
            fault = c->fault[k][i];
            age = age_add(c->age_us[k][i], in->t_us - c->t_us[k]);
            if (ok) {
                v = c->value[k][i];
                if (r_is_finite(v)) {
                    v = r_mul(r_sub(v, c->cfg.offset[i]), c->cfg.gain[i]);
                }
                if (!r_is_finite(v)) {
                    v = R_ZERO;
                    ok = 0u;
                    fault = (uint8_t)GRIP_SIG_RANGE;
                }
            }
        }
        out->value[i] = ok ? v : R_ZERO;
        out->valid[i] = ok;
        out->fault[i] = ok ? (uint8_t)GRIP_SIG_OK : fault;
        out->age_us[i] = age;
    }
    /* The inputs passed through uncalibrated get the same guarantee: a
     * valid non-finite value leaves as invalid (range), never as a number. */
    for (i = (uint32_t)GRIP_CALIB_N; i < (uint32_t)GRIP_IN_COUNT; ++i) {
        if ((out->valid[i] != 0u) && !r_is_finite(out->value[i])) {
            out->value[i] = R_ZERO;
            out->valid[i] = 0u;
            out->fault[i] = (uint8_t)GRIP_SIG_RANGE;
        }
    }
    return GRIP_OK;
}
