/*
 * grip_signals.h - the estimator's input sample: the vehicle signals one
 * estimator step consumes, each with a validity flag and the reason when it
 * is not valid.
 *
 * A sample is produced for every estimator step by the CAN sample assembler
 * (grip_can.h, lib/can) or by any other source (a test, a simulator); the
 * estimator reads nothing else from the vehicle. Values are SI, ISO 8855
 * axes (x forward, y left, z up; yaw rate, steering angle and lateral
 * acceleration positive to the left), in the build's number format:
 *
 *   input                      unit     fixed-point format
 *   wheel speeds FL FR RL RR   m/s      QS  (circumferential, from the ABS sensors)
 *   steering-wheel angle       rad      QS  (at the steering wheel, not the road wheel)
 *   yaw rate                   rad/s    QS
 *   ax, ay                     m/s^2    QS  (body-fixed accelerometer)
 *   vehicle speed              m/s      QS  (the car's own reference speed, optional)
 *   brake pressures FL..RR     Pa       QL  (optional)
 *   brake torques FL..RR       N m      QL  (optional, positive = braking)
 *   rear road-wheel angle      rad      QS  (optional: rear-wheel steering, at the
 *                                           road wheels, positive to the left)
 *
 * A value is meaningful only where valid[i] is 1; everywhere else it is
 * exactly zero and fault[i] says why (grip_sig_fault_t). An out-of-range,
 * stale or sender-flagged signal is never passed on as a number.
 */
#ifndef GRIP_SIGNALS_H
#define GRIP_SIGNALS_H

#include <stdint.h>
#include "grip_types.h"

/* Index of each input in grip_input_sample_t's arrays. */
typedef enum {
    GRIP_IN_WHEEL_SPEED_FL = 0,
    GRIP_IN_WHEEL_SPEED_FR = 1,
    GRIP_IN_WHEEL_SPEED_RL = 2,
    GRIP_IN_WHEEL_SPEED_RR = 3,
    GRIP_IN_STEER_ANGLE = 4,
    GRIP_IN_YAW_RATE = 5,
    GRIP_IN_AX = 6,
    GRIP_IN_AY = 7,
    GRIP_IN_VEHICLE_SPEED = 8,
    GRIP_IN_BRAKE_PRESSURE_FL = 9,
    GRIP_IN_BRAKE_PRESSURE_FR = 10,
    GRIP_IN_BRAKE_PRESSURE_RL = 11,
    GRIP_IN_BRAKE_PRESSURE_RR = 12,
    GRIP_IN_BRAKE_TORQUE_FL = 13,
    GRIP_IN_BRAKE_TORQUE_FR = 14,
    GRIP_IN_BRAKE_TORQUE_RL = 15,
    GRIP_IN_BRAKE_TORQUE_RR = 16,
    GRIP_IN_REAR_STEER_ANGLE = 17,
    GRIP_IN_COUNT = 18
} grip_input_id_t;

/* Why an input is not valid in a sample. */
typedef enum {
    GRIP_SIG_OK = 0,        /* valid: fresh, in range, from a frame that passed its checks */
    GRIP_SIG_UNMAPPED = 1,  /* no signal of the table feeds this input (optional input absent) */
    GRIP_SIG_MISSING = 2,   /* no value received yet (since start or since a timestamp jump) */
    GRIP_SIG_STALE = 3,     /* newest value older than stale_periods x its message period */
    GRIP_SIG_RANGE = 4,     /* newest value outside its range, or not representable */
    GRIP_SIG_FAULT = 5      /* the sender flagged the newest value faulty (qualifier signal) */
} grip_sig_fault_t;

#define GRIP_SIG_FAULT_COUNT 6

/* One estimator step's inputs. */
typedef struct {
    int64_t t_us;                        /* step time [us], in the frames' time base */
    uint32_t step;                       /* step number since start (or since the last timestamp jump) */
    grip_real_t value[GRIP_IN_COUNT];    /* SI value; 0 where not valid */
    uint8_t valid[GRIP_IN_COUNT];        /* 1 = value may be used */
    uint8_t fault[GRIP_IN_COUNT];        /* grip_sig_fault_t; GRIP_SIG_OK where valid */
    uint32_t age_us[GRIP_IN_COUNT];      /* t_us minus the value's frame time (saturated); 0 if none */
} grip_input_sample_t;

#define grip_input_name GRIP_TYPED(grip_input_name)
/* Short lower-case name of an input ("wheel_speed_fl", "steer_angle",
 * "yaw_rate", "ax", ...), as used by the map files and CSV columns; "?" for
 * an invalid id. */
const char *grip_input_name(uint32_t input);

#define grip_input_is_ql GRIP_TYPED(grip_input_is_ql)
/* 1 if the input is in the QL format (pressures, torques), 0 for QS (and
 * for an invalid id). */
int grip_input_is_ql(uint32_t input);

#define grip_input_unit GRIP_TYPED(grip_input_unit)
/* SI unit of the input ("m/s", "rad", "rad/s", "m/s^2", "Pa", "N m"). */
const char *grip_input_unit(uint32_t input);

#define grip_input_find GRIP_TYPED(grip_input_find)
/* Input id of a name as returned by grip_input_name, or -1. The name need
 * not be NUL-terminated: len characters are compared (len <= 32). */
int32_t grip_input_find(const char *name, uint32_t len);

#define grip_sig_fault_str GRIP_TYPED(grip_sig_fault_str)
/* "ok", "unmapped", "missing", "stale", "range", "fault"; "?" otherwise. */
const char *grip_sig_fault_str(uint32_t fault);

#define grip_input_sample_clear GRIP_TYPED(grip_input_sample_clear)
/* Sets every value to 0, every valid flag to 0 and every fault to
 * GRIP_SIG_UNMAPPED, time and step to 0. GRIP_ERR_NULL for NULL. */
grip_status_t grip_input_sample_clear(grip_input_sample_t *s);

#endif /* GRIP_SIGNALS_H */
