/*
 * grip_calib.h - sensor calibration stage between the signals and the
 * estimator (docs/calibration.md):
 *
 *   CAN / source -> grip_input_sample_t -> grip_calib_apply -> (monitor) -> grip_est_step
 *
 * For each calibrated input i (wheel speeds FL..RR, steering-wheel angle,
 * yaw rate, ax, ay, vehicle speed: ids 0 .. GRIP_CALIB_N - 1, all QS):
 *
 *   1. delay alignment: the input is taken from delay[i] steps ago (a
 *      fixed ring of GRIP_CALIB_DELAY_MAX + 1 entries per input, no heap),
 *      with the valid flag, fault code and age it had then (the age grows
 *      by the time since, t_us now minus t_us then); until the ring holds
 *      delay[i] earlier samples the input is invalid (GRIP_SIG_MISSING);
 *   2. offset and scale: value = (raw - offset[i]) * gain[i]
 *      (a sensor that reads (1 + s) x true + b is corrected by offset = b,
 *      gain = 1 / (1 + s)).
 * A sensor cannot be advanced in time: to compensate a sensor that lags by
 * d steps, delay the OTHER inputs by d (the residual tool writes it so).
 * Invalid inputs stay invalid with value 0; a valid input that is not
 * finite (float build) or whose corrected value is not finite becomes
 * invalid with GRIP_SIG_RANGE. Inputs GRIP_CALIB_N .. GRIP_IN_COUNT - 1
 * (brake pressures and torques) pass through unchanged, except that a
 * valid non-finite value leaves invalid with GRIP_SIG_RANGE.
 *
 * Formats (fixed build): offset QS in the input's SI unit, gain QS, delay
 * in whole steps. Output values are the build's grip_real_t; the fixed
 * build rounds (raw - offset) * gain once to QS (round half up, saturating).
 */
#ifndef GRIP_CALIB_H
#define GRIP_CALIB_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_signals.h"

#define GRIP_CALIB_N 9             /* inputs 0 .. 8 are calibrated */
#define GRIP_CALIB_DELAY_MAX 32u   /* steps (0.32 s at 100 Hz, 32 ms at 1 kHz) */

typedef struct {
    grip_real_t offset[GRIP_CALIB_N];  /* QS SI unit of the input, [-10, 10] (0 = none) */
    grip_real_t gain[GRIP_CALIB_N];    /* QS, [0.5, 2] (1 = none)                       */
    uint32_t delay[GRIP_CALIB_N];      /* steps, [0, GRIP_CALIB_DELAY_MAX] (0 = none)   */
} grip_calib_config_t;

#define GRIP_CALIB_RING (GRIP_CALIB_DELAY_MAX + 1u)

typedef struct {
    uint32_t magic;
    grip_calib_config_t cfg;
    uint32_t head;                                   /* index of the newest entry */
    uint32_t filled;                                 /* entries written, saturating at GRIP_CALIB_RING */
    int64_t t_us[GRIP_CALIB_RING];
    grip_real_t value[GRIP_CALIB_RING][GRIP_CALIB_N];
    uint32_t age_us[GRIP_CALIB_RING][GRIP_CALIB_N];
    uint8_t valid[GRIP_CALIB_RING][GRIP_CALIB_N];
    uint8_t fault[GRIP_CALIB_RING][GRIP_CALIB_N];
} grip_calib_t;

#define grip_calib_config_identity GRIP_TYPED(grip_calib_config_identity)
#define grip_calib_init GRIP_TYPED(grip_calib_init)
#define grip_calib_reset GRIP_TYPED(grip_calib_reset)
#define grip_calib_apply GRIP_TYPED(grip_calib_apply)

/* offset 0, gain 1, delay 0 for every input. GRIP_ERR_NULL for NULL. */
grip_status_t grip_calib_config_identity(grip_calib_config_t *cfg);

/* Checks cfg (ranges above; non-finite in float), copies it and empties the
 * ring. GRIP_ERR_NULL, GRIP_ERR_PARAM (c is then unusable: apply returns
 * GRIP_ERR_STATE). */
grip_status_t grip_calib_init(grip_calib_t *c, const grip_calib_config_t *cfg);

/* Empties the ring (e.g. after a timestamp jump); keeps the configuration. */
grip_status_t grip_calib_reset(grip_calib_t *c);

/* One step: pushes `in` into the ring and writes the calibrated sample to
 * `out` (out may be in). GRIP_ERR_NULL, GRIP_ERR_STATE (out then a copy of
 * in with every calibrated input invalid, GRIP_SIG_MISSING), else GRIP_OK. */
grip_status_t grip_calib_apply(grip_calib_t *c, const grip_input_sample_t *in, grip_input_sample_t *out);

#endif /* GRIP_CALIB_H */
