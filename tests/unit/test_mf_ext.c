/*
 * test_mf_ext.c - grip_mf_eval_ext against the float64 reference
 * (grip_tools.reference.mf.evaluate_ext): every row of
 * build/golden/mf_ext_<tyre>.txt for every shared .tir file, every channel.
 *
 * A channel the reference marks nan (its parameters are not in the file)
 * must come back with its valid bit clear and the value 0; every other
 * channel must be valid and within its tolerance (docs/magic-formula-c.md
 * section 8, "Accuracy of the extended outputs"):
 *
 *   |err| <= a * scale + r * |want| (+ the output format's step, fixed)
 *
 * a and r per channel and build in CHANNELS below; the scales: R0
 * (lengths), (1 + |kappa|) / R0 (Omega: a is in m/s of vx), the file's
 * stiffness (Cz: VERTICAL_STIFFNESS, Cx, Cy: their own), FNOMIN R0
 * (moments), FNOMIN (Kxk, Kya per unit slip), 1 (mu). In the fixed build a
 * is a few to a few tens of Q15.16 steps of the normalized quantity (R0
 * 2^-16 = 1.5e-5 R0, FNOMIN R0 2^-16, ...) and r covers the Q15.16
 * rounding of coefficients such as QSY1 = 0.01 (5e-4 relative) and the
 * resolution of small normalized quantities (the MF 6.2 deflection in its
 * force correction); the figures include the rounding of the inputs to
 * Q15.16 / Q23.8. Each channel prints max |err|, max rel, SNR and the
 * largest |err| / scale.
 * fx, fy, mz must equal grip_mf_eval's bit for bit.
 * In a GRIP_DEBUG_SATURATION build no saturation may happen on any row.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "grip/grip_mf.h"
#include "grip/grip_q16.h"
#include "golden.h"
#include "mf_params.h"

#if GRIP_ARITH_FIXED
static grip_real_t to_qs(double v) { return (grip_real_t)lround(v * 65536.0); }
static grip_real_t to_ql(double v) { return (grip_real_t)lround(v * 256.0); }
static double from_qs(grip_real_t v) { return (double)v / 65536.0; }
static double from_ql(grip_real_t v) { return (double)v / 256.0; }
#define IS_FIXED 1
#else
static grip_real_t to_qs(double v) { return (grip_real_t)v; }
static grip_real_t to_ql(double v) { return (grip_real_t)v; }
static double from_qs(grip_real_t v) { return (double)v; }
static double from_ql(grip_real_t v) { return (double)v; }
#define IS_FIXED 0
#endif

/* scale of a channel's absolute tolerance */
enum { S_R0, S_OMEGA, S_CZ, S_CX, S_CY, S_MOM, S_FZ0, S_ONE };

typedef struct {
    const char *name;     /* column in the golden file */
    uint32_t bit;
    size_t off;           /* offset in grip_mf_output_ext */
    int ql;               /* format: 1 QL, 0 QS */
    int scale;
    double abs_f, rel_f;  /* float build: abs (times the scale), rel */
    double abs_x, rel_x;  /* fixed build */
    const char *unit;
} channel;

#define CH(n, b, f, q, s, af, rf, ax, rx, u) { n, b, offsetof(grip_mf_output_ext, f), q, s, af, rf, ax, rx, u }

static const channel CHANNELS[] = {
    /*  name      bit                 field           QL  scale     float a, r     fixed a, r        unit */
    CH("re", GRIP_MF_EXT_RE, re, 0, S_R0, 1e-6, 1e-6, 2e-4, 0.0, "m"),
    CH("omega", GRIP_MF_EXT_OMEGA, omega, 0, S_OMEGA, 1e-6, 1e-5, 1e-4, 4e-4, "rad/s"),
    CH("rl", GRIP_MF_EXT_RL, rl, 0, S_R0, 1e-6, 1e-5, 2e-4, 2e-4, "m"),
    CH("rho", GRIP_MF_EXT_RHO, rho, 0, S_R0, 1e-6, 1e-5, 2e-4, 2e-3, "m"),
    CH("cz", GRIP_MF_EXT_CZ, cz, 1, S_CZ, 1e-6, 1e-5, 2e-3, 4e-3, "N/m"),
    CH("2a", GRIP_MF_EXT_LENGTH, contact_length, 0, S_R0, 1e-6, 1e-5, 2e-4, 1e-3, "m"),
    CH("2b", GRIP_MF_EXT_WIDTH, contact_width, 0, S_R0, 1e-6, 1e-5, 2e-4, 1e-3, "m"),
    CH("t", GRIP_MF_EXT_T, t, 0, S_R0, 1e-6, 1e-5, 2e-4, 2e-3, "m"),
    CH("mzr", GRIP_MF_EXT_MZR, mzr, 1, S_MOM, 1e-6, 1e-5, 4e-4, 2e-3, "N m"),
    CH("mux", GRIP_MF_EXT_MUX, mux, 0, S_ONE, 1e-6, 1e-5, 4e-4, 0.0, "-"),
    CH("muy", GRIP_MF_EXT_MUY, muy, 0, S_ONE, 1e-6, 1e-5, 4e-4, 0.0, "-"),
    CH("kxk", GRIP_MF_EXT_KXK, kxk, 1, S_FZ0, 1e-4, 1e-5, 1e-3, 1e-3, "N"),
    CH("kya", GRIP_MF_EXT_KYA, kya, 1, S_FZ0, 1e-4, 1e-5, 1e-3, 1e-3, "N/rad"),
    CH("cx", GRIP_MF_EXT_CX, cx, 1, S_CX, 1e-6, 1e-5, 2e-4, 2e-4, "N/m"),
    CH("cy", GRIP_MF_EXT_CY, cy, 1, S_CY, 1e-6, 1e-5, 2e-4, 2e-4, "N/m"),
    CH("sigmax", GRIP_MF_EXT_SIGMAX, sigmax, 0, S_R0, 1e-6, 1e-5, 1e-3, 1e-3, "m"),
    CH("sigmay", GRIP_MF_EXT_SIGMAY, sigmay, 0, S_R0, 1e-6, 1e-5, 1e-3, 1e-3, "m"),
    CH("mx", GRIP_MF_EXT_MX, mx, 1, S_MOM, 1e-6, 1e-5, 4e-4, 2e-3, "N m"),
    CH("my", GRIP_MF_EXT_MY, my, 1, S_MOM, 1e-6, 1e-5, 4e-4, 2e-3, "N m"),
};
#define NCH ((int)(sizeof(CHANNELS) / sizeof(CHANNELS[0])))
#define NIN 6
#define COL0 10   /* first channel column: kappa alpha gamma fz p vx fx fy mz mz_svyk_camber */

static double channel_value(const grip_mf_output_ext *o, const channel *c)
{
    grip_real_t v;
    memcpy(&v, (const char *)o + c->off, sizeof v);
    return c->ql ? from_ql(v) : from_qs(v);
}

static int check_tire(const grip_test_tire *t)
{
    golden_file g;
    char fname[128];
    const grip_mf_params *p = t->params;
    double r0 = from_qs(p->unloaded_radius);
    double fnomin = from_ql(p->fnomin);
    err_stats st[NCH];
    char label[NCH][80];
    double worst[NCH];
    double worst_scaled[NCH];  /* max |err| / scale */
    long over[NCH];
    long nvalid[NCH];
    long bad_valid = 0;
    long bad_base = 0;
    long bad_status = 0;
    int failures = 0;
    int n = 0;
    int nf;
    int j;
    uint32_t sat;
    snprintf(fname, sizeof fname, "mf_ext_%s.txt", t->name);
    for (j = 0; j < NCH; j++) {
        snprintf(label[j], sizeof label[j], "%s %s", t->name, CHANNELS[j].name);
        err_init(&st[j], label[j], 1e-9);
        worst[j] = 0.0;
        worst_scaled[j] = 0.0;
        over[j] = 0;
        nvalid[j] = 0;
    }
    assert_int_equal(golden_open(&g, fname), 0);
    grip_debug_saturation_reset();
    while ((nf = golden_next(&g)) > 0) {
        grip_mf_input in;
        grip_mf_output base;
        grip_mf_output_ext out;
        double x[NIN];
        grip_status_t s1;
        grip_status_t s2;
        assert_int_equal(nf, COL0 + NCH);
        for (j = 0; j < NIN; j++) {
            x[j] = golden_num(&g, j);
        }
        in.kappa = to_qs(x[0]);
        in.alpha = to_qs(x[1]);
        in.gamma = to_qs(x[2]);
        in.fz = to_ql(x[3]);
        in.p = to_ql(x[4]);
        in.vx = to_qs(x[5]);
        s1 = grip_mf_eval(p, &in, &base);
        s2 = grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &out);
        if (s1 != GRIP_OK || s2 != GRIP_OK) {
            if (bad_status < 3) {
                printf("# %s row %d: status %d %d\n", t->name, n, (int)s1, (int)s2);
            }
            bad_status++;
        }
        if (out.fx != base.fx || out.fy != base.fy || out.mz != base.mz) {
            bad_base++;
        }
        for (j = 0; j < NCH; j++) {
            const channel *c = &CHANNELS[j];
            double want = golden_num(&g, COL0 + j);
            double got = channel_value(&out, c);
            int valid = (out.valid & c->bit) != 0u;
            double scale;
            double allowed;
            double e;
            if (isnan(want)) {
                if (valid || got != 0.0) {
                    if (bad_valid < 5) {
                        printf("# %s %s row %d: not available in the reference, valid %d value %g\n", t->name,
                               c->name, n, valid, got);
                    }
                    bad_valid++;
                }
                continue;
            }
            if (!valid) {
                if (bad_valid < 5) {
                    printf("# %s %s row %d: k=%.6g a=%.6g g=%.6g fz=%.6g p=%.6g vx=%.6g: flagged invalid, want %.9g\n",
                           t->name, c->name, n, x[0], x[1], x[2], x[3], x[4], x[5], want);
                }
                bad_valid++;
                continue;
            }
            nvalid[j]++;
            switch (c->scale) {
            case S_R0: scale = r0; break;
            case S_OMEGA: scale = (1.0 + fabs(x[0])) / r0; break;
            case S_CZ: scale = from_ql(p->vertical_stiffness); break;
            case S_CX: scale = from_ql(p->longitudinal_stiffness); break;
            case S_CY: scale = from_ql(p->lateral_stiffness); break;
            case S_MOM: scale = fnomin * r0; break;
            case S_FZ0: scale = fnomin; break;
            default: scale = 1.0; break;
            }
            allowed = (IS_FIXED ? c->abs_x : c->abs_f) * scale + (IS_FIXED ? c->rel_x : c->rel_f) * fabs(want);
            /* the output format's rounding */
            allowed += IS_FIXED ? (c->ql ? 1.0 / 256.0 : 1.0 / 65536.0) : 0.0;
            e = fabs(got - want);
            err_add(&st[j], got, want, x[0], x[1], x[3]);
            if (scale > 0.0 && e / scale > worst_scaled[j]) {
                worst_scaled[j] = e / scale;
            }
            if (!(e <= allowed)) {
                if (over[j] < 3) {
                    printf("# %s %s row %d: k=%.6g a=%.6g g=%.6g fz=%.6g p=%.6g vx=%.6g got %.9g want %.9g"
                           " (|err| %.3e > %.3e)\n",
                           t->name, c->name, n, x[0], x[1], x[2], x[3], x[4], x[5], got, want, e, allowed);
                }
                over[j]++;
            }
            if (allowed > 0.0 && e / allowed > worst[j]) {
                worst[j] = e / allowed;
            }
        }
        n++;
    }
    golden_close(&g);
    sat = grip_debug_saturation_count();
    assert_true(n > 100);
    for (j = 0; j < NCH; j++) {
        if (nvalid[j] == 0) {
            printf("# %-34s not in the file's parameters (flagged on all %d rows)\n", label[j], n);
            continue;
        }
        err_print(&st[j], CHANNELS[j].unit);
        printf("#   %-32s worst |err| / tolerance = %.3f (%ld rows over), max |err| / scale = %.2e\n", label[j],
               worst[j], over[j], worst_scaled[j]);
        if (over[j] != 0) {
            printf("# FAIL %s: %ld rows beyond the tolerance (worst %.2f x)\n", label[j], over[j], worst[j]);
            failures++;
        }
    }
    printf("# %s: %d rows, %ld wrong valid bits, %ld base outputs != grip_mf_eval, %lu saturations%s%s\n", t->name, n,
           bad_valid, bad_base, (unsigned long)sat, sat ? ", first: " : "", sat ? grip_debug_saturation_first() : "");
    failures += (bad_valid != 0) + (bad_base != 0) + (bad_status != 0);
#if GRIP_DEBUG_SATURATION
    if (sat != 0u) {
        printf("# FAIL %s: %lu saturations inside the valid range\n", t->name, (unsigned long)sat);
        failures++;
    }
#endif
    return failures;
}

static void test_ext_golden_all_tires(void **state)
{
    int i;
    int failures = 0;
    (void)state;
    assert_true(grip_test_tire_count > 0);
    for (i = 0; i < grip_test_tire_count; i++) {
        failures += check_tire(&grip_test_tires[i]);
    }
    assert_int_equal(failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ext_golden_all_tires),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
