/* check.c - the detail of a failed parameter check (check_internal.h). */
#include <stddef.h>

#include "check_internal.h"

int check_fail(grip_check_detail_t *d, const char *part, int32_t index, const char *field, const char *rule)
{
    if (d != NULL) {
        d->part = part;
        d->index = index;
        d->field = field;
        d->rule = rule;
    }
    return 0;
}

void check_clear(grip_check_detail_t *d)
{
    (void)check_fail(d, "", -1, "", "");
}

void check_within(grip_check_detail_t *d, const char *part, int32_t index)
{
    if (d != NULL) {
        d->part = part;
        d->index = index;
    }
}
