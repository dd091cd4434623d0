/*
 * check_internal.h - filling grip_check_detail_t (grip_types.h) in the
 * parameter checks of every module. Internal to lib/: not part of the
 * public API.
 */
#ifndef GRIP_CHECK_INTERNAL_H
#define GRIP_CHECK_INTERNAL_H

#include <stdint.h>

#include "grip/grip_types.h"

#define check_fail GRIP_TYPED(grip_core_i_check_fail)
/* Records in *d (d may be NULL) that `field` of element `index` of `part`
 * ("" and -1 for the checked struct itself) breaks `rule`; returns 0, so a
 * check reads `return check_fail(d, "", -1, "mu", "in (0, 3]");`. The
 * strings must be constants. */
int check_fail(grip_check_detail_t *d, const char *part, int32_t index, const char *field, const char *rule);

#define check_clear GRIP_TYPED(grip_core_i_check_clear)
/* *d (d may be NULL): no field failed. */
void check_clear(grip_check_detail_t *d);

#define check_within GRIP_TYPED(grip_core_i_check_within)
/* Sets the element of *d (d may be NULL) to part[index], keeping its field:
 * a nested check's detail seen from the struct that holds it. */
void check_within(grip_check_detail_t *d, const char *part, int32_t index);

#endif /* GRIP_CHECK_INTERNAL_H */
