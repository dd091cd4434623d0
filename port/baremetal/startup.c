/*
 * startup.c - reset handler and vector table for Cortex-M (ARMv6-M and
 * ARMv7-M): copy .data, clear .bss, enable the FPU when the build uses it,
 * run main, report its return code through semihosting.
 */
#include <stdint.h>
#include "grip_bm.h"

extern uint32_t _data_load, _data_start, _data_end, _bss_start, _bss_end, _stack_top;
int main(void);
void grip_bm_reset(void);
void grip_bm_fault(void);

void grip_bm_reset(void)
{
    const uint32_t *src = &_data_load;
    uint32_t *dst;
    for (dst = &_data_start; dst < &_data_end; ++dst) {
        *dst = *src++;
    }
    for (dst = &_bss_start; dst < &_bss_end; ++dst) {
        *dst = 0u;
    }
#if defined(__ARM_FP)
    /* CPACR: full access to CP10/CP11, then flush the pipeline. */
    *(volatile uint32_t *)0xE000ED88u |= (0xFu << 20);
    __asm volatile("dsb\n\tisb" ::: "memory");
#endif
    grip_bm_exit(main());
}

void grip_bm_fault(void)
{
    grip_bm_puts("FAULT: hard fault or unexpected exception\n");
    grip_bm_exit(99);
}

typedef void (*grip_bm_vector)(void);

__attribute__((section(".vectors"), used))
static const grip_bm_vector vectors[16] = {
    (grip_bm_vector)(uintptr_t)&_stack_top,
    grip_bm_reset,
    grip_bm_fault, grip_bm_fault, grip_bm_fault, grip_bm_fault, grip_bm_fault,
    0, 0, 0, 0,
    grip_bm_fault, grip_bm_fault, 0, grip_bm_fault, grip_bm_fault,
};
