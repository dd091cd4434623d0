/*
 * can_internal.h - helpers shared by the files of lib/can (not public).
 */
#ifndef GRIP_CAN_INTERNAL_H
#define GRIP_CAN_INTERNAL_H

#include <stdint.h>
#include "grip/grip_can.h"
#include "arith.h"

/* The id as the table stores it: 11 bits, or 29 bits | GRIP_CAN_ID_EFF. */
uint32_t can_id_key(uint32_t id);

/* (acc / 2^shift) SI in the format of `input`; GRIP_SIG_OK or
 * GRIP_SIG_RANGE (not representable in the fixed build; *out = 0). */
uint8_t can_scale(int64_t acc, uint32_t shift, uint32_t input, grip_real_t *out);

/* Does m's checksum field suit its family (position, length, message
 * length; GRIP_CAN_CSUM_NONE always does)? */
int can_checksum_layout_ok(const grip_can_message_t *m);

#endif /* GRIP_CAN_INTERNAL_H */
