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
    CH("2b", GRIP_MF_EXT_WIDTH, contact_width, 0, S_R0, 1e-6, 1e-5, 3e-4, 1e-3, "m"),
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

/* Per-channel tallies of one golden file. */
typedef struct {
    const grip_test_tire *t;
    err_stats st[NCH];
    char label[NCH][96];
    double worst[NCH];
    double worst_scaled[NCH];  /* max |err| / scale */
    long over[NCH];
    long nvalid[NCH];
    long bad_valid;
} tally;

static void tally_init(tally *y, const grip_test_tire *t, const char *what)
{
    int j;
    memset(y, 0, sizeof *y);
    y->t = t;
    for (j = 0; j < NCH; j++) {
        snprintf(y->label[j], sizeof y->label[j], "%s%s %s", t->name, what, CHANNELS[j].name);
        err_init(&y->st[j], y->label[j], 1e-9);
    }
}

/* One row: x = kappa alpha gamma fz p vx, want[j] the reference's channel j. */
static void tally_row(tally *y, const grip_mf_params *p, const double *x, const grip_mf_output_ext *out,
                      const double *want_ch, int n)
{
    const char *name = y->t->name;
    double r0 = from_qs(p->unloaded_radius);
    double fnomin = from_ql(p->fnomin);
    int j;
    for (j = 0; j < NCH; j++) {
        const channel *c = &CHANNELS[j];
        double want = want_ch[j];
        double got = channel_value(out, c);
        int valid = (out->valid & c->bit) != 0u;
        double scale;
        double allowed;
        double e;
        if (isnan(want)) {
            if (valid || got != 0.0) {
                if (y->bad_valid < 5) {
                    printf("# %s %s row %d: not available in the reference, valid %d value %g\n", name, c->name, n,
                           valid, got);
                }
                y->bad_valid++;
            }
            continue;
        }
        if (!valid) {
            if (y->bad_valid < 5) {
                printf("# %s %s row %d: k=%.6g a=%.6g g=%.6g fz=%.6g p=%.6g vx=%.6g: flagged invalid, want %.9g\n",
                       name, c->name, n, x[0], x[1], x[2], x[3], x[4], x[5], want);
            }
            y->bad_valid++;
            continue;
        }
        y->nvalid[j]++;
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
        err_add(&y->st[j], got, want, x[0], x[1], x[3]);
        if (scale > 0.0 && e / scale > y->worst_scaled[j]) {
            y->worst_scaled[j] = e / scale;
        }
        if (!(e <= allowed)) {
            if (y->over[j] < 3) {
                printf("# %s %s row %d: k=%.6g a=%.6g g=%.6g fz=%.6g p=%.6g vx=%.6g got %.9g want %.9g"
                       " (|err| %.3e > %.3e)\n",
                       name, c->name, n, x[0], x[1], x[2], x[3], x[4], x[5], got, want, e, allowed);
            }
            y->over[j]++;
        }
        if (allowed > 0.0 && e / allowed > y->worst[j]) {
            y->worst[j] = e / allowed;
        }
    }
}

/* Prints the channels' figures; returns the number of failing channels. */
static int tally_finish(tally *y, int n)
{
    int failures = 0;
    int j;
    for (j = 0; j < NCH; j++) {
        if (y->nvalid[j] == 0) {
            printf("# %-34s not in the file's parameters (flagged on all %d rows)\n", y->label[j], n);
            continue;
        }
        err_print(&y->st[j], CHANNELS[j].unit);
        printf("#   %-32s worst |err| / tolerance = %.3f (%ld rows over), max |err| / scale = %.2e\n", y->label[j],
               y->worst[j], y->over[j], y->worst_scaled[j]);
        if (y->over[j] != 0) {
            printf("# FAIL %s: %ld rows beyond the tolerance (worst %.2f x)\n", y->label[j], y->over[j], y->worst[j]);
            failures++;
        }
    }
    return failures;
}

static int check_tire(const grip_test_tire *t)
{
    golden_file g;
    char fname[128];
    const grip_mf_params *p = t->params;
    tally y;
    long bad_base = 0;
    long bad_status = 0;
    int failures = 0;
    int n = 0;
    int nf;
    int j;
    uint32_t sat;
    snprintf(fname, sizeof fname, "mf_ext_%s.txt", t->name);
    tally_init(&y, t, "");
    assert_int_equal(golden_open(&g, fname), 0);
    grip_debug_saturation_reset();
    while ((nf = golden_next(&g)) > 0) {
        grip_mf_input in;
        grip_mf_output base;
        grip_mf_output_ext out;
        double x[NIN];
        double want[NCH];
        grip_status_t s1;
        grip_status_t s2;
        assert_int_equal(nf, COL0 + NCH);
        for (j = 0; j < NIN; j++) {
            x[j] = golden_num(&g, j);
        }
        for (j = 0; j < NCH; j++) {
            want[j] = golden_num(&g, COL0 + j);
        }
        memset(&in, 0, sizeof in);
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
        tally_row(&y, p, x, &out, want, n);
        n++;
    }
    golden_close(&g);
    sat = grip_debug_saturation_count();
    assert_true(n > 100);
    failures += tally_finish(&y, n);
    printf("# %s: %d rows, %ld wrong valid bits, %ld base outputs != grip_mf_eval, %lu saturations%s%s\n", t->name, n,
           y.bad_valid, bad_base, (unsigned long)sat, sat ? ", first: " : "", sat ? grip_debug_saturation_first() : "");
    failures += (y.bad_valid != 0) + (bad_base != 0) + (bad_status != 0);
#if GRIP_DEBUG_SATURATION
    if (sat != 0u) {
        printf("# FAIL %s: %lu saturations inside the valid range\n", t->name, (unsigned long)sat);
        failures++;
    }
#endif
    return failures;
}

/* ---------------------------------------------------------------------
 * The use modes: build/golden/mf_mode_<tyre>.txt (columns mode kappa alpha
 * gamma fz p vx phit omega fx fy mz and the channels). mode holds the
 * GRIP_MF_OPT_* bits of the row: TURN_SLIP and NO_LIMITS are asked for per
 * call (GRIP_MF_USE_*), TS_CAMBER through the set's options. Fx, Fy, Mz:
 * the tolerances of test_mf_golden (float 1e-4 Fz, 1e-4 Fz x 1 m; fixed
 * 0.5 % of the peak force D + 4 LSB, 1 % of the peak |Mz| at the row's load
 * among the rows of its mode + 4 LSB); the channels: CHANNELS. The same
 * evaluation through the set's option bits must give the same outputs bit
 * for bit; grip_mf_eval must equal it in mode 111 and refuse a set with a
 * use-mode bit (GRIP_MF_OPT_TURN_SLIP, GRIP_MF_OPT_NO_LIMITS: GRIP_ERR_PARAM).
 */
#define MODE_MAX_ROWS 12000
#define MODE_COL0 12
#define MODE_NMODES 5
static const uint32_t MODE_LIST[MODE_NMODES] = { 0u, GRIP_MF_OPT_NO_LIMITS, GRIP_MF_OPT_TURN_SLIP,
                                                 GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS,
                                                 GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_TS_CAMBER };
static const char *const MODE_NAME[MODE_NMODES] = { "111", "211", "112", "212", "112+camber" };

typedef struct {
    int mode;
    double x[9];         /* kappa alpha gamma fz p vx phit omega */
    double f[3];         /* fx fy mz */
    double ch[NCH];
} mode_row;

static mode_row mrows[MODE_MAX_ROWS];

static int mode_index(uint32_t m)
{
    int k;
    for (k = 0; k < MODE_NMODES; k++) {
        if (MODE_LIST[k] == m) {
            return k;
        }
    }
    return -1;
}

#if GRIP_ARITH_FIXED
static double mode_peak_mz(int n, int mode, double fz)
{
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        if (mrows[i].mode == mode && fabs(mrows[i].x[3] - fz) <= 0.1 * fz && fabs(mrows[i].f[2]) > m) {
            m = fabs(mrows[i].f[2]);
        }
    }
    return m;
}
#endif

/* Peak forces mu Fz from the parameters (test_mf_golden's), |.| */
static void mode_peaks(const grip_mf_params *p, const double *x, double *dx, double *dy)
{
    double fz = x[3];
    double fz0 = from_ql(p->fnomin) * from_qs(p->lfzo);
    double dfz = (fz - fz0) / fz0;
    double nom = from_ql(p->nompres);
    double dpi = (nom > 0.0 && x[4] > 0.0 && p->fittyp >= 61) ? (x[4] - nom) / nom : 0.0;
    double g2 = x[2] * x[2];
    *dx = fabs((from_qs(p->pdx1) + from_qs(p->pdx2) * dfz) * (1.0 + from_qs(p->ppx3) * dpi + from_qs(p->ppx4) * dpi * dpi) *
               (1.0 - from_qs(p->pdx3) * g2) * from_qs(p->lmux) * fz);
    *dy = fabs((from_qs(p->pdy1) + from_qs(p->pdy2) * dfz) * (1.0 + from_qs(p->ppy3) * dpi + from_qs(p->ppy4) * dpi * dpi) *
               (1.0 - from_qs(p->pdy3) * g2) * from_qs(p->lmuy) * fz);
}

static int check_modes(const grip_test_tire *t)
{
    golden_file g;
    char fname[128];
    const grip_mf_params *p = t->params;
    tally y[2];          /* without, with turn slip */
    err_stats fst[MODE_NMODES][3];
    char flabel[MODE_NMODES][3][96];
    double fworst[MODE_NMODES][3];
    long fover[MODE_NMODES][3];
    int count[MODE_NMODES];
    long bad_status = 0;
    long bad_same = 0;
    long bad_plain = 0;
    int failures = 0;
    int n = 0;
    int nf;
    int i;
    int j;
    int k;
    uint32_t sat;
    double fnomin = from_ql(p->fnomin);
    double r0 = from_qs(p->unloaded_radius);
    static const char *const fnames[3] = { "Fx", "Fy", "Mz" };
    snprintf(fname, sizeof fname, "mf_mode_%s.txt", t->name);
    tally_init(&y[0], t, " 1xx/2xx");
    tally_init(&y[1], t, " turn slip");
    for (k = 0; k < MODE_NMODES; k++) {
        count[k] = 0;
        for (j = 0; j < 3; j++) {
            snprintf(flabel[k][j], sizeof flabel[k][j], "%s %s %s", t->name, MODE_NAME[k], fnames[j]);
            err_init(&fst[k][j], flabel[k][j], 1e-9);
            fworst[k][j] = 0.0;
            fover[k][j] = 0;
        }
    }
    assert_int_equal(golden_open(&g, fname), 0);
    while ((nf = golden_next(&g)) > 0) {
        assert_int_equal(nf, MODE_COL0 + NCH);
        assert_true(n < MODE_MAX_ROWS);
        mrows[n].mode = (int)golden_num(&g, 0);
        for (j = 0; j < 8; j++) {
            mrows[n].x[j] = golden_num(&g, 1 + j);
        }
        for (j = 0; j < 3; j++) {
            mrows[n].f[j] = golden_num(&g, 9 + j);
        }
        for (j = 0; j < NCH; j++) {
            mrows[n].ch[j] = golden_num(&g, MODE_COL0 + j);
        }
        n++;
    }
    golden_close(&g);
    assert_true(n > 100);
    grip_debug_saturation_reset();
    for (i = 0; i < n; i++) {
        const mode_row *r = &mrows[i];
        uint32_t m = (uint32_t)r->mode;
        int mi = mode_index(m);
        int ts = (m & GRIP_MF_OPT_TURN_SLIP) != 0u;
        grip_mf_params q = *p;
        grip_mf_input in;
        grip_mf_spin sp;
        grip_mf_output_ext out;
        grip_mf_output_ext out2;
        grip_mf_output plain;
        uint32_t use = GRIP_MF_EXT_ALL | (ts ? GRIP_MF_USE_TURN_SLIP : GRIP_MF_USE_NO_TURN_SLIP) |
                       (((m & GRIP_MF_OPT_NO_LIMITS) != 0u) ? GRIP_MF_USE_NO_LIMITS : GRIP_MF_USE_LIMITS);
        grip_status_t s1;
        grip_status_t s2;
        grip_status_t s3;
        double dx;
        double dy;
        assert_true(mi >= 0);
        count[mi]++;
        q.options |= (m & GRIP_MF_OPT_TS_CAMBER);
        memset(&in, 0, sizeof in);
        in.kappa = to_qs(r->x[0]);
        in.alpha = to_qs(r->x[1]);
        in.gamma = to_qs(r->x[2]);
        in.fz = to_ql(r->x[3]);
        in.p = to_ql(r->x[4]);
        in.vx = to_qs(r->x[5]);
        sp.phit = to_qs(r->x[6]);
        sp.omega = to_qs(r->x[7]);
        s1 = grip_mf_eval_ext_spin(&q, &in, &sp, use, &out);
        if (s1 != GRIP_OK) {
            if (bad_status < 3) {
                printf("# %s mode %s row %d: status %d\n", t->name, MODE_NAME[mi], i, (int)s1);
            }
            bad_status++;
        }
        /* the same through the set's options */
        q.options |= m;
        s2 = grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &out2);
        if (s2 != s1 || memcmp(&out, &out2, sizeof out) != 0) {
            bad_same++;
        }
        s3 = grip_mf_eval(&q, &in, &plain);
        if ((m & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) != 0u) {
            bad_plain += (s3 != GRIP_ERR_PARAM);   /* the use modes are grip_mf_eval_ext's */
        } else {
            bad_plain += (s3 != s1 || plain.fx != out.fx || plain.fy != out.fy || plain.mz != out.mz);
        }
        mode_peaks(p, r->x, &dx, &dy);
        for (j = 0; j < 3; j++) {
            double got = from_ql(j == 0 ? out.fx : (j == 1 ? out.fy : out.mz));
            double want = r->f[j];
            double e = fabs(got - want);
            double allowed;
#if GRIP_ARITH_FIXED
            double lsb = (j == 2 ? fnomin * r0 : fnomin) / 65536.0;
            allowed = (j == 2 ? 0.01 * mode_peak_mz(n, r->mode, r->x[3]) : 0.005 * (j == 0 ? dx : dy)) + 4.0 * lsb;
#else
            allowed = 1e-4 * r->x[3];
            (void)dx;
            (void)dy;
            (void)fnomin;
            (void)r0;
#endif
            err_add(&fst[mi][j], got, want, r->x[0], r->x[1], r->x[3]);
            if (!(e <= allowed)) {
                if (fover[mi][j] < 3) {
                    printf("# %s mode %s %s row %d: k=%.6g a=%.6g g=%.6g fz=%.6g vx=%.6g phit=%.6g omega=%.6g "
                           "got %.9g want %.9g (|err| %.3e > %.3e)\n",
                           t->name, MODE_NAME[mi], fnames[j], i, r->x[0], r->x[1], r->x[2], r->x[3], r->x[5],
                           r->x[6], r->x[7], got, want, e, allowed);
                }
                fover[mi][j]++;
            }
            if (allowed > 0.0 && e / allowed > fworst[mi][j]) {
                fworst[mi][j] = e / allowed;
            }
        }
        tally_row(&y[ts], p, r->x, &out, r->ch, i);
    }
    sat = grip_debug_saturation_count();
    for (k = 0; k < MODE_NMODES; k++) {
        if (count[k] == 0) {
            continue;
        }
        for (j = 0; j < 3; j++) {
            err_print(&fst[k][j], j == 2 ? "N m" : "N");
            printf("#   %-32s worst |err| / tolerance = %.3f (%ld rows over)\n", flabel[k][j], fworst[k][j],
                   fover[k][j]);
            if (fover[k][j] != 0) {
                printf("# FAIL %s: %ld rows beyond the tolerance\n", flabel[k][j], fover[k][j]);
                failures++;
            }
        }
    }
    failures += tally_finish(&y[0], n);
    if (count[2] + count[3] + count[4] > 0) {
        failures += tally_finish(&y[1], n);
    }
    printf("# %s use modes: %d rows (111 %d, 211 %d, 112 %d, 212 %d, 112+camber %d), %ld status != OK, %ld wrong "
           "valid bits, %ld differ by options, %ld differ from grip_mf_eval, %lu saturations%s%s\n",
           t->name, n, count[0], count[1], count[2], count[3], count[4], bad_status, y[0].bad_valid + y[1].bad_valid,
           bad_same, bad_plain, (unsigned long)sat, sat ? ", first: " : "", sat ? grip_debug_saturation_first() : "");
    failures += (bad_status != 0) + (y[0].bad_valid + y[1].bad_valid != 0) + (bad_same != 0) + (bad_plain != 0);
#if GRIP_DEBUG_SATURATION
    if (sat != 0u) {
        printf("# FAIL %s: %lu saturations inside the valid range (use modes)\n", t->name, (unsigned long)sat);
        failures++;
    }
#endif
    return failures;
}

static void test_mode_golden_all_tires(void **state)
{
    int i;
    int failures = 0;
    (void)state;
    for (i = 0; i < grip_test_tire_count; i++) {
        failures += check_modes(&grip_test_tires[i]);
    }
    assert_int_equal(failures, 0);
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
        cmocka_unit_test(test_mode_golden_all_tires),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
