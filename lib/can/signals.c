/*
 * signals.c - names, units and formats of the estimator inputs
 * (grip_signals.h).
 */
#include <stddef.h>

#include "grip/grip_signals.h"
#include "arith.h"

static const char *const NAMES[GRIP_IN_COUNT] = {
    "wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr",
    "steer_angle", "yaw_rate", "ax", "ay", "vehicle_speed",
    "brake_pressure_fl", "brake_pressure_fr", "brake_pressure_rl", "brake_pressure_rr",
    "brake_torque_fl", "brake_torque_fr", "brake_torque_rl", "brake_torque_rr",
    "rear_steer_angle"
};

static const char *const UNITS[GRIP_IN_COUNT] = {
    "m/s", "m/s", "m/s", "m/s", "rad", "rad/s", "m/s^2", "m/s^2", "m/s",
    "Pa", "Pa", "Pa", "Pa", "N m", "N m", "N m", "N m", "rad"
};

static const char *const FAULTS[GRIP_SIG_FAULT_COUNT] = {
    "ok", "unmapped", "missing", "stale", "range", "fault"
};

const char *grip_input_name(uint32_t input)
{
    return (input < (uint32_t)GRIP_IN_COUNT) ? NAMES[input] : "?";
}

const char *grip_input_unit(uint32_t input)
{
    return (input < (uint32_t)GRIP_IN_COUNT) ? UNITS[input] : "?";
}

int grip_input_is_ql(uint32_t input)
{
    return (input >= (uint32_t)GRIP_IN_BRAKE_PRESSURE_FL && input <= (uint32_t)GRIP_IN_BRAKE_TORQUE_RR) ? 1 : 0;
}

int32_t grip_input_find(const char *name, uint32_t len)
{
    uint32_t i;
    uint32_t k;
    if (name == NULL || len == 0u || len > 32u) {
        return -1;
    }
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        const char *n = NAMES[i];
        for (k = 0u; k < len && k < 32u; k++) {
            if (n[k] != name[k] || n[k] == '\0') {
                break;
            }
        }
        if (k == len && n[k] == '\0') {
            return (int32_t)i;
        }
    }
    return -1;
}

const char *grip_sig_fault_str(uint32_t fault)
{
    return (fault < (uint32_t)GRIP_SIG_FAULT_COUNT) ? FAULTS[fault] : "?";
}

grip_status_t grip_input_sample_clear(grip_input_sample_t *s)
{
    uint32_t i;
    if (s == NULL) {
        return GRIP_ERR_NULL;
    }
    s->t_us = 0;
    s->step = 0u;
    for (i = 0u; i < (uint32_t)GRIP_IN_COUNT; i++) {
        s->value[i] = R_ZERO;
        s->valid[i] = 0u;
        s->fault[i] = (uint8_t)GRIP_SIG_UNMAPPED;
        s->age_us[i] = 0u;
    }
    return GRIP_OK;
}
