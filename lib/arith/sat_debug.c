/*
 * sat_debug.c - saturation accounting for GRIP_DEBUG_SATURATION builds.
 * In every other build the query functions exist and report zero, so tests
 * and tools link the same way against any build.
 */
#include "grip/grip_q16.h"
#include "q16_inline.h"

#if GRIP_DEBUG_SATURATION
static uint32_t sat_count;
static const char *sat_first;

void grip_debug_saturation_event(const char *op)
{
    if (sat_count == 0u) {
        sat_first = op;
    }
    if (sat_count < UINT32_MAX) {
        ++sat_count;
    }
}

uint32_t grip_debug_saturation_count(void) { return sat_count; }
const char *grip_debug_saturation_first(void) { return (sat_first != 0) ? sat_first : ""; }
void grip_debug_saturation_reset(void)
{
    sat_count = 0u;
    sat_first = 0;
}
#else
uint32_t grip_debug_saturation_count(void) { return 0u; }
const char *grip_debug_saturation_first(void) { return ""; }
void grip_debug_saturation_reset(void) { }
#endif
