/*
 * semihost.c - console output, exit and cycle counter for the bare-metal
 * example port. Semihosting traps to the debugger or emulator with BKPT 0xAB
 * (r0 = operation, r1 = argument).
 */
#include "grip_bm.h"

static int32_t semihost_call(int32_t op, const void *arg)
{
    register int32_t r0 __asm("r0") = op;
    register const void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void grip_bm_puts(const char *s)
{
    (void)semihost_call(0x04, s);   /* SYS_WRITE0 */
}

void grip_bm_put_int(int32_t v)
{
    char buf[12];
    int i = 11;
    uint32_t u = (v < 0) ? (0u - (uint32_t)v) : (uint32_t)v;
    buf[i] = '\0';
    do {
        buf[--i] = (char)('0' + (u % 10u));
        u /= 10u;
    } while (u != 0u && i > 1);
    if (v < 0) {
        buf[--i] = '-';
    }
    grip_bm_puts(&buf[i]);
}

void grip_bm_exit(int code)
{
    /* SYS_EXIT_EXTENDED: ADP_Stopped_ApplicationExit with a status code */
    uint32_t block[2] = { 0x20026u, (uint32_t)code };
    (void)semihost_call(0x20, block);
    for (;;) {
    }
}

#define DWT_CTRL   (*(volatile uint32_t *)0xE0001000u)
#define DWT_CYCCNT (*(volatile uint32_t *)0xE0001004u)
#define DEMCR      (*(volatile uint32_t *)0xE000EDFCu)

void grip_bm_cycles_enable(void)
{
#if defined(__ARM_ARCH_7M__) || defined(__ARM_ARCH_7EM__)
    DEMCR |= (1u << 24);   /* TRCENA */
    DWT_CYCCNT = 0u;
    DWT_CTRL |= 1u;
#endif
}

uint32_t grip_bm_cycles(void)
{
#if defined(__ARM_ARCH_7M__) || defined(__ARM_ARCH_7EM__)
    return DWT_CYCCNT;
#else
    return 0u;   /* ARMv6-M has no DWT cycle counter */
#endif
}
