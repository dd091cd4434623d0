/*
 * grip_mf.h - Magic Formula tire models (MF 5.2 / PAC2002, MF 6.1 / 6.2).
 *
 * CONTRACT (shared by lib/mf, port/linux's .tir reader and the Python
 * emitter in tools/grip_tools): the parameter struct is the three header
 * fields below followed by one grip_real_t per entry of
 * GRIP_MF_COEFFICIENTS (grip_mf_coefs.h), in that order, each in SI units
 * and in its listed fixed-point format.
 */
#ifndef GRIP_MF_H
#define GRIP_MF_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_mf_coefs.h"

typedef struct {
    int32_t fittyp;      /* 5, 6, 21 (MF 5.2 / PAC2002), 61, 62 (MF 6.1 / 6.2) */
    int32_t tyreside;    /* +1: LEFT or not given; -1: RIGHT (mirrored)     */
    uint32_t options;    /* GRIP_MF_OPT_* bit set                            */
#define GRIP_MF_X_FIELD(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) grip_real_t field;
    GRIP_MF_COEFFICIENTS(GRIP_MF_X_FIELD)
#undef GRIP_MF_X_FIELD
} grip_mf_params;

#endif /* GRIP_MF_H */
