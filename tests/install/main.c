/*
 * main.c - an external consumer of an installed grip: one point of the
 * brush model in braking (grip_brush_eval), its parameter set written in SI
 * and converted with grip_convert.h, so that the one source builds against
 * either library (grip-float / grip-fixed). Prints the result in whole
 * millinewtons; exits 0 when every conversion and the evaluation succeeded.
 *
 * Host: output on stdout. Bare metal (-DCONSUMER_BAREMETAL=1): output through
 * the semihosting of grip's example port (port/baremetal), on QEMU.
 */
#include <grip/grip_brush.h>
#include <grip/grip_convert.h>

#if defined(CONSUMER_BAREMETAL) && CONSUMER_BAREMETAL
#include "grip_bm.h"
static void put(const char *s) { grip_bm_puts(s); }
#else
#include <stdio.h>
static void put(const char *s) { (void)fputs(s, stdout); }
#endif

static void put_long(long v)
{
    char buf[24];
    int i = (int)sizeof buf - 1;
    unsigned long u = (v < 0) ? 0ul - (unsigned long)v : (unsigned long)v;
    buf[i] = '\0';
    do {
        buf[--i] = (char)('0' + (int)(u % 10ul));
        u /= 10ul;
    } while (u != 0ul);
    if (v < 0) {
        buf[--i] = '-';
    }
    put(&buf[i]);
}

/* SI value rounded to a whole number of thousandths */
static long milli(double x)
{
    return (long)(x * 1000.0 + ((x < 0.0) ? -0.5 : 0.5));
}

static int failures;

static grip_real_t qs(double si)
{
    grip_real_t r;
    if (grip_real_qs_from_si(si, &r) != GRIP_OK) {
        failures++;
    }
    return r;
}

static grip_real_t ql(double si)
{
    grip_real_t r;
    if (grip_real_ql_from_si(si, &r) != GRIP_OK) {
        failures++;
    }
    return r;
}

int main(void)
{
    grip_brush_params p;
    grip_brush_out out;
    grip_status_t st;
    int32_t q;

    p.kx = ql(80000.0);
    p.mu_s = qs(1.1);
    p.mu_d0 = qs(0.9);
    p.a_v = qs(0.005);
    p.n = 4;
    p.fz_min = ql(200.0);
    p.fz_max = ql(10000.0);
    p.kappa_max = qs(1.0);
    p.v_max = qs(60.0);

    st = grip_brush_eval(&p, qs(-0.1), ql(4000.0), qs(20.0), &out);

    put("grip " GRIP_VERSION_STRING " " GRIP_ARITH_NAME "\n");
    put("brush kappa -0.1, Fz 4000 N, vx 20 m/s: status ");
    put_long((long)st);
    put(" (");
    put(grip_status_str(st));
    put(")\nfx_mN ");
    put_long(milli(grip_real_ql_to_si(out.fx)));
    put("\nrh_milli ");
    put_long(milli(grip_real_qs_to_si(out.rh)));
    /* a value beyond QS is reported, not wrapped */
    put("\nqs(40000) status ");
    put_long((long)grip_qs_from_double(40000.0, &q));
    put(" q ");
    put_long((long)q);
    put("\n");
    return (st == GRIP_OK && failures == 0) ? 0 : 1;
}
