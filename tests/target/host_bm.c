/*
 * host_bm.c - the bare-metal console hooks (port/baremetal/grip_bm.h) on the
 * host, so that target_main.c runs unchanged there for the bit-identity
 * comparison.
 */
#include <stdio.h>
#include <stdlib.h>
#include "grip_bm.h"

void grip_bm_puts(const char *s)
{
    fputs(s, stdout);
}

void grip_bm_put_int(int32_t v)
{
    printf("%ld", (long)v);
}

void grip_bm_exit(int code)
{
    exit(code);
}

uint32_t grip_bm_cycles(void)
{
    return 0u;
}

void grip_bm_cycles_enable(void)
{
}
