/*
 * example_main.c - a firmware image that links every public function of
 * libgrip, runs a short self-check and prints through semihosting. Used by
 * `make firmware` to prove the fixed Cortex-M0+ image holds no floating
 * point, and runnable on qemu-system-arm (mps2-an385 / mps2-an386).
 */
#include "grip/grip_types.h"
#include "grip/grip_q16.h"
#include "grip_bm.h"

/* volatile so that the compiler cannot fold the calls away */
static volatile grip_q16_t sink;

int main(void)
{
    grip_q16_t x = GRIP_Q16_ONE / 2;
    grip_bm_puts("grip firmware example (" GRIP_ARITH_NAME ")\n");
    sink = grip_q16_add(x, x);
    sink = grip_q16_sub(x, x);
    sink = grip_q16_mul(x, x);
    sink = grip_q16_div(x, 3 * GRIP_Q16_ONE);
    sink = grip_q16_sqrt(x);
    sink = grip_q16_atan(x);
    sink = grip_q16_atan2(x, -x);
    sink = grip_q16_sin(x);
    sink = grip_q16_cos(x);
    sink = grip_q16_exp(x);
    sink = grip_q16_log(x);
    grip_bm_puts("sin(0.5) * 2^16 = ");
    grip_bm_put_int(grip_q16_sin(x));
    grip_bm_puts("\nstatus: ");
    grip_bm_puts(grip_status_str(GRIP_OK));
    grip_bm_puts("\n");
    return (grip_q16_sin(x) == 31420) ? 0 : 1;   /* round(sin(0.5) * 2^16) */
}
