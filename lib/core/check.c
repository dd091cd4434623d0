/* check.c - the detail of a failed parameter check (check_internal.h). */
#include <stddef.h>

#include "check_internal.h"
#include "arith.h"

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

int check_ranges(const check_range_t *r, size_t n, grip_check_detail_t *d)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        if (!(r_is_finite(r[i].v) && r[i].v >= r[i].lo && r[i].v <= r[i].hi)) {
            return check_fail(d, "", -1, r[i].name, r[i].rule);
        }
    }
    return 1;
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
