/*
 * vehicle_config.h - the estimator's vehicle configuration of the host
 * tools: the named presets of `grip-replay --vehicle` and the `key = value`
 * vehicle file of `--vehicle-file`. Shared by grip-replay and the Python
 * binding's replay (grip._replay), so that both configure the estimator
 * with the same code.
 */
#ifndef GRIP_VEHICLE_CONFIG_H
#define GRIP_VEHICLE_CONFIG_H

#include <stddef.h>
#include <stdio.h>

#include "grip/grip_est.h"

/* An SI value in the build's number format: QS (Q15.16) and QL (Q23.8)
 * fields of grip_est_config_t; the value itself in the float build. */
grip_real_t vehicle_si_qs(double x);
grip_real_t vehicle_si_ql(double x);

/* grip_est_config_default with tire on both axles, rate_hz, then the preset
 * `name` (rav4, av21, generic; NULL = rav4). 0, or -1 for an unknown name
 * (or a default the library refuses). */
int vehicle_preset(const char *name, const grip_mf_params *tire, int rate_hz, grip_est_config_t *cfg);

/* Applies the vehicle file at path to cfg. A rear_tire key is returned as
 * a path (relative to the file's folder unless absolute) in rear_tire (of
 * rear_n bytes) with its line in *rear_line (0: none; *rear_line must be 0
 * on entry). 0, or -1 after a message "grip-replay: FILE:LINE: ..." on msg. */
int vehicle_file_read(const char *path, grip_est_config_t *cfg, char *rear_tire, size_t rear_n,
                      unsigned long *rear_line, FILE *msg);

#endif
