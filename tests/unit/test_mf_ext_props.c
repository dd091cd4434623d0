/*
 * test_mf_ext_props.c - properties of grip_mf_eval_ext that hold whatever
 * the reference says: argument checks, the valid mask (requested and
 * available channels only, zero values elsewhere), the unloaded wheel, the
 * slip stiffnesses as the slopes of the pure-slip forces, the sign rules of
 * the mirror and SAE options, and the formats at the corners of the input
 * domain and beyond it (finite values; a channel that does not fit its
 * format is flagged, never saturated or wrapped); the use modes and turn
 * slip: their arguments and refusals, the clamps of phit and omega, the
 * mirror and SAE signs of phit, the limit at phit = 0. Tolerances next to
 * each check (docs/magic-formula-c.md sections 8 and 9).
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

#define PI 3.14159265358979323846

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

/* every channel: bit, field, format */
typedef struct {
    const char *name;
    uint32_t bit;
    size_t off;
    int ql;
} channel;

#define CH(n, b, f, q) { n, b, offsetof(grip_mf_output_ext, f), q }
static const channel CHANNELS[] = {
    CH("re", GRIP_MF_EXT_RE, re, 0), CH("omega", GRIP_MF_EXT_OMEGA, omega, 0),
    CH("rl", GRIP_MF_EXT_RL, rl, 0), CH("rho", GRIP_MF_EXT_RHO, rho, 0),
    CH("cz", GRIP_MF_EXT_CZ, cz, 1), CH("2a", GRIP_MF_EXT_LENGTH, contact_length, 0),
    CH("2b", GRIP_MF_EXT_WIDTH, contact_width, 0), CH("t", GRIP_MF_EXT_T, t, 0),
    CH("mzr", GRIP_MF_EXT_MZR, mzr, 1), CH("mux", GRIP_MF_EXT_MUX, mux, 0),
    CH("muy", GRIP_MF_EXT_MUY, muy, 0), CH("kxk", GRIP_MF_EXT_KXK, kxk, 1),
    CH("kya", GRIP_MF_EXT_KYA, kya, 1), CH("cx", GRIP_MF_EXT_CX, cx, 1),
    CH("cy", GRIP_MF_EXT_CY, cy, 1), CH("sigmax", GRIP_MF_EXT_SIGMAX, sigmax, 0),
    CH("sigmay", GRIP_MF_EXT_SIGMAY, sigmay, 0), CH("mx", GRIP_MF_EXT_MX, mx, 1),
    CH("my", GRIP_MF_EXT_MY, my, 1),
};
#define NCH ((int)(sizeof(CHANNELS) / sizeof(CHANNELS[0])))

static grip_real_t raw(const grip_mf_output_ext *o, int j)
{
    grip_real_t v;
    memcpy(&v, (const char *)o + CHANNELS[j].off, sizeof v);
    return v;
}

static double val(const grip_mf_output_ext *o, int j)
{
    return CHANNELS[j].ql ? from_ql(raw(o, j)) : from_qs(raw(o, j));
}

static grip_mf_input mk(double kappa, double alpha, double gamma, double fz, double p, double vx)
{
    grip_mf_input in;
    memset(&in, 0, sizeof in);
    in.kappa = to_qs(kappa);
    in.alpha = to_qs(alpha);
    in.gamma = to_qs(gamma);
    in.fz = to_ql(fz);
    in.p = to_ql(p);
    in.vx = to_qs(vx);
    return in;
}

static const grip_mf_params *tire(const char *name)
{
    const grip_mf_params *p = grip_test_tire_params(name);
    assert_non_null(p);
    return p;
}

static int setup(void **state)
{
    (void)state;
    grip_debug_saturation_reset();
    return 0;
}

static void assert_no_saturation(void)
{
    if (grip_debug_saturation_count() != 0u) {
        fail_msg("%lu saturations (first: %s)", (unsigned long)grip_debug_saturation_count(),
                 grip_debug_saturation_first());
    }
}

/* NULL pointers, unknown output bits, unusable parameters: the status of
 * grip_mf_eval (GRIP_ERR_INPUT for an unknown bit), everything zero, no
 * valid bit. A non-finite coefficient that only one channel uses flags
 * that channel (float build). */
static void test_ext_arguments(void **state)
{
    const grip_mf_params *p = tire("MagicFormula61_Paramerters");
    grip_mf_params bad = *p;
    grip_mf_input in = mk(0.05, 0.05, 0.0, 5000.0, 0.0, 16.0);
    grip_mf_output_ext o;
    int j;
    (void)state;
    assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, NULL), GRIP_ERR_NULL);
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext(NULL, &in, GRIP_MF_EXT_ALL, &o), GRIP_ERR_NULL);
    assert_int_equal(o.valid, 0u);
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext(p, NULL, GRIP_MF_EXT_ALL, &o), GRIP_ERR_NULL);
    assert_int_equal(o.valid, 0u);
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL + 1u, &o), GRIP_ERR_INPUT);
    assert_int_equal(o.valid, 0u);
    assert_true(o.fx == 0 && o.fy == 0 && o.mz == 0);
    for (j = 0; j < NCH; j++) {
        assert_true(raw(&o, j) == 0);
    }
    bad.fittyp = 7;
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext(&bad, &in, GRIP_MF_EXT_ALL, &o), GRIP_ERR_PARAM);
    assert_int_equal(o.valid, 0u);
    assert_int_equal(grip_mf_ext_supported(&bad), 0u);
    assert_int_equal(grip_mf_ext_supported(NULL), 0u);
#if !GRIP_ARITH_FIXED
    /* a non-finite coefficient only My uses (grip_mf_check_params would
     * reject the set): My flagged and 0, the rest as usual */
    bad = *p;
    bad.qsy1 = NAN;
    assert_int_equal(grip_mf_eval_ext(&bad, &in, GRIP_MF_EXT_ALL, &o), GRIP_OK);
    assert_int_equal(o.valid, GRIP_MF_EXT_ALL & ~GRIP_MF_EXT_MY);
    assert_true(o.my == 0.0f);
    in.alpha = NAN;
    assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &o), GRIP_ERR_INPUT);
    assert_int_equal(o.valid, 0u);
#endif
}

/* Each channel alone: only its bit, the same value as with every channel
 * requested (bit for bit), every other channel zero. */
static void test_ext_subset(void **state)
{
    const grip_mf_params *p = tire("MagicFormula62_Paramerters");
    grip_mf_input in = mk(-0.08, 0.06, 0.03, 7000.0, 240000.0, 20.0);
    grip_mf_output_ext all;
    grip_mf_output_ext one;
    int j;
    int k;
    (void)state;
    assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &all), GRIP_OK);
    assert_int_equal(all.valid, GRIP_MF_EXT_ALL);
    assert_int_equal(grip_mf_eval_ext(p, &in, 0u, &one), GRIP_OK);
    assert_int_equal(one.valid, 0u);
    assert_true(one.fx == all.fx && one.fy == all.fy && one.mz == all.mz);
    for (j = 0; j < NCH; j++) {
        assert_int_equal(grip_mf_eval_ext(p, &in, CHANNELS[j].bit, &one), GRIP_OK);
        assert_int_equal(one.valid, CHANNELS[j].bit);
        for (k = 0; k < NCH; k++) {
            if (k == j) {
                if (raw(&one, k) != raw(&all, k)) {
                    fail_msg("%s alone %.9g, with all %.9g", CHANNELS[j].name, val(&one, k), val(&all, k));
                }
            } else {
                assert_true(raw(&one, k) == 0);
            }
        }
    }
    assert_no_saturation();
}

/* What a parameter set supports: the G275 files have no LONGITUDINAL_ /
 * LATERAL_STIFFNESS (Cx, Cy missing; MF 5.2 takes sigma from PTX, PTY);
 * without VERTICAL_STIFFNESS the radii, the vertical model and the contact
 * patch are missing (MF 5.2 keeps the width WIDTH); a requested channel
 * that is not supported is never valid. */
static void test_ext_supported(void **state)
{
    const grip_mf_params *g275 = tire("G275MSA_60psi");
    const grip_mf_params *m61 = tire("MagicFormula61_Paramerters");
    grip_mf_params q = *m61;
    grip_mf_input in = mk(0.05, 0.05, 0.0, 5000.0, 0.0, 16.0);
    grip_mf_output_ext o;
    int i;
    (void)state;
    assert_int_equal(grip_mf_ext_supported(g275), GRIP_MF_EXT_ALL & ~(GRIP_MF_EXT_CX | GRIP_MF_EXT_CY));
    assert_int_equal(grip_mf_ext_supported(m61), GRIP_MF_EXT_ALL);
    q.vertical_stiffness = 0;
    q.longitudinal_stiffness = 0;
    assert_int_equal(grip_mf_ext_supported(&q),
                     GRIP_MF_EXT_ALL & ~(GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO |
                                         GRIP_MF_EXT_CZ | GRIP_MF_EXT_LENGTH | GRIP_MF_EXT_WIDTH | GRIP_MF_EXT_CX |
                                         GRIP_MF_EXT_SIGMAX));
    assert_int_equal(grip_mf_eval_ext(&q, &in, GRIP_MF_EXT_ALL, &o), GRIP_OK);
    assert_int_equal(o.valid, grip_mf_ext_supported(&q));
    assert_true(o.re == 0 && o.cx == 0 && o.sigmax == 0);
    /* Q_FZ1^2 = (Cz0 R0 / FNOMIN)^2 - 4 Q_FZ2 < 0: no vertical model */
    q = *m61;
    q.q_fz2 = to_qs(1000.0);
    assert_int_equal(grip_mf_ext_supported(&q), GRIP_MF_EXT_ALL & ~(GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ));
    /* every shared set, in the domain: valid == supported */
    for (i = 0; i < grip_test_tire_count; i++) {
        const grip_mf_params *p = grip_test_tires[i].params;
        double fn = from_ql(p->fnomin);
        in = mk(-0.1, 0.08, 0.02, fn, 0.0, from_qs(p->longvl));
        assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &o), GRIP_OK);
        if (o.valid != grip_mf_ext_supported(p)) {
            fail_msg("%s: valid %x, supported %x", grip_test_tires[i].name, o.valid, grip_mf_ext_supported(p));
        }
    }
    assert_no_saturation();
}

/* Fz <= 0: forces and moments, mu, Kxk, Kya, t, rho, Cz, the contact
 * length 0; Re = Rl = the free radius (with Q_V1 = 0: UNLOADED_RADIUS *
 * Q_RE0, exactly R0 for the book set); Omega = (1 + kappa) vx / Re; MF 6.x
 * width 0, MF 5.2 width WIDTH. Status GRIP_OK, every supported channel
 * valid. */
static void test_ext_unloaded(void **state)
{
    const grip_mf_params *p = tire("PacejkaBook_Defaults");
    const grip_mf_params *p52 = tire("MagicFormula52_Paramerters");
    const double fzs[] = { 0.0, -500.0 };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof fzs / sizeof fzs[0]; i++) {
        grip_mf_input in = mk(0.1, 0.1, 0.02, fzs[i], 0.0, 10.0);
        grip_mf_output_ext o;
        double r0 = from_qs(p->unloaded_radius);
        int j;
        assert_int_equal(grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &o), GRIP_OK);
        assert_int_equal(o.valid, GRIP_MF_EXT_ALL);
        assert_true(o.fx == 0 && o.fy == 0 && o.mz == 0);
        assert_true(fabs(from_qs(o.re) - r0) <= (IS_FIXED ? 4.0 / 65536.0 : 1e-6));
        assert_true(o.rl == o.re);
        assert_true(fabs(from_qs(o.omega) - 1.1 * 10.0 / from_qs(o.re)) <= (IS_FIXED ? 1e-3 : 1e-5));
        for (j = 0; j < NCH; j++) {
            uint32_t b = CHANNELS[j].bit;
            if ((b & (GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_CX | GRIP_MF_EXT_CY)) == 0u) {
                if (raw(&o, j) != 0) {
                    fail_msg("Fz = %g: %s = %g, not 0", fzs[i], CHANNELS[j].name, val(&o, j));
                }
            }
        }
        /* Cx, Cy at dfz = -1 */
        assert_true(fabs(from_ql(o.cx) - from_ql(p->longitudinal_stiffness) *
                                             (1.0 - from_qs(p->pcfx1) + from_qs(p->pcfx2))) <= 1.0);
        assert_int_equal(grip_mf_eval_ext(p52, &in, GRIP_MF_EXT_WIDTH | GRIP_MF_EXT_LENGTH, &o), GRIP_OK);
        assert_true(o.contact_width == p52->width && o.contact_length == 0);
    }
    assert_no_saturation();
}

/* Kxk and Kya are the slopes of the pure-slip forces at zero slip (MFeval's
 * BCD): central differences of grip_mf_eval_pure at zero slip (shifts
 * zeroed here: PHX*, PHY*, PVX*, PVY* = 0), h = 2^-13 (float) or 2^-10
 * (fixed; exact in Q15.16), at 4 loads for three MF 6.1 shared sets.
 * Tolerance: float 2e-4 relative, fixed 3e-3 relative (the slope test of
 * test_mf_props; the curvature over h, (B h)^2, is 4e-4 at most). */
static void test_ext_slip_stiffness_is_slope(void **state)
{
    const char *names[] = { "PacejkaBook_Defaults", "MagicFormula61_Paramerters", "FSAE_Defaults" };
    size_t n;
    int k;
    double worst = 0.0;
    (void)state;
    for (n = 0; n < sizeof names / sizeof names[0]; n++) {
        grip_mf_params p = *tire(names[n]);
        double fn = from_ql(p.fnomin);
        p.phx1 = p.phx2 = p.pvx1 = p.pvx2 = 0;
        p.phy1 = p.phy2 = p.pvy1 = p.pvy2 = 0;
        for (k = 1; k <= 4; k++) {
            double fz = 0.4 * k * fn;
            double h = IS_FIXED ? 1.0 / 1024.0 : 1.0 / 8192.0;
            grip_mf_output a;
            grip_mf_output b;
            grip_mf_output_ext o;
            grip_mf_input in = mk(0.0, 0.0, 0.0, fz, 0.0, 16.0);
            double sx;
            double sy;
            double ex;
            double ey;
            assert_int_equal(grip_mf_eval_ext(&p, &in, GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA, &o), GRIP_OK);
            in = mk(h, h, 0.0, fz, 0.0, 16.0);
            (void)grip_mf_eval_pure(&p, &in, &a);
            in = mk(-h, -h, 0.0, fz, 0.0, 16.0);
            (void)grip_mf_eval_pure(&p, &in, &b);
            sx = (from_ql(a.fx) - from_ql(b.fx)) / (2.0 * h);
            sy = (from_ql(a.fy) - from_ql(b.fy)) / (2.0 * h);
            ex = fabs(from_ql(o.kxk) - sx) / fabs(sx);
            ey = fabs(from_ql(o.kya) - sy) / fabs(sy);
            if (ex > worst) worst = ex;
            if (ey > worst) worst = ey;
            if (ex > (IS_FIXED ? 3e-3 : 2e-4) || ey > (IS_FIXED ? 3e-3 : 2e-4)) {
                fail_msg("%s Fz %g: Kxk %g vs slope %g, Kya %g vs slope %g", names[n], fz, from_ql(o.kxk), sx,
                         from_ql(o.kya), sy);
            }
        }
    }
    printf("# Kxk, Kya vs the slope of Fx0, Fy0 at zero slip: worst relative difference %.2e\n", worst);
    assert_no_saturation();
}

/* Mirror (x-z plane) and SAE: Mx and Mzr change sign in the mirror image,
 * My and Mzr in SAE (as Mz); every other channel is unchanged. Exact. */
static void test_ext_conventions(void **state)
{
    grip_mf_params p = *tire("MagicFormula61_Paramerters");
    grip_mf_params q;
    int i;
    int j;
    (void)state;
    p.tyreside = 1;
    q = p;
    q.options = GRIP_MF_OPT_MIRROR;
    for (i = 0; i <= 10; i++) {
        double a = -0.3 + 0.06 * i;
        grip_mf_input in = mk(0.05, a, 0.04, 6000.0, 0.0, 16.0);
        grip_mf_input inm = mk(0.05, -a, -0.04, 6000.0, 0.0, 16.0);
        grip_mf_output_ext om;
        grip_mf_output_ext ob;
        assert_int_equal(grip_mf_eval_ext(&q, &in, GRIP_MF_EXT_ALL, &om), GRIP_OK);
        assert_int_equal(grip_mf_eval_ext(&p, &inm, GRIP_MF_EXT_ALL, &ob), GRIP_OK);
        for (j = 0; j < NCH; j++) {
            int flip = (CHANNELS[j].bit & (GRIP_MF_EXT_MX | GRIP_MF_EXT_MZR)) != 0u;
            grip_real_t want = flip ? (grip_real_t)(-raw(&ob, j)) : raw(&ob, j);
            if (raw(&om, j) != want) {
                fail_msg("mirror %s: %.9g vs %.9g", CHANNELS[j].name, val(&om, j), val(&ob, j));
            }
        }
    }
    q = p;
    q.options = GRIP_MF_OPT_SAE;
    for (i = 0; i <= 10; i++) {
        double a = -0.3 + 0.06 * i;
        grip_mf_input in = mk(0.05, a, 0.04, -6000.0, 0.0, 16.0);
        grip_mf_input iso = mk(0.05, -a, 0.04, 6000.0, 0.0, 16.0);
        grip_mf_output_ext os;
        grip_mf_output_ext oi;
        assert_int_equal(grip_mf_eval_ext(&q, &in, GRIP_MF_EXT_ALL, &os), GRIP_OK);
        assert_int_equal(grip_mf_eval_ext(&p, &iso, GRIP_MF_EXT_ALL, &oi), GRIP_OK);
        for (j = 0; j < NCH; j++) {
            int flip = (CHANNELS[j].bit & (GRIP_MF_EXT_MY | GRIP_MF_EXT_MZR)) != 0u;
            grip_real_t want = flip ? (grip_real_t)(-raw(&oi, j)) : raw(&oi, j);
            if (raw(&os, j) != want) {
                fail_msg("SAE %s: %.9g vs %.9g", CHANNELS[j].name, val(&os, j), val(&oi, j));
            }
        }
    }
    assert_no_saturation();
}

/* The corners of the input domain (kappa +-1.5, alpha +-pi/2, gamma +-30 deg,
 * Fz 1 N .. 4 FNOMIN, vx 0.1 .. 300 m/s, p 0.5 .. 2 NOMPRES) for every shared
 * set: status GRIP_OK, every valid channel finite and inside its format's
 * range (|QS| < 30000, |QL| < 8e6), every flagged channel zero, no
 * saturation (DEBUG_SAT build). Prints how often each channel was flagged
 * (a corner can have no MF 6.2 loaded radius, or an Re whose cubic has no
 * root). */
static void test_ext_domain_corners(void **state)
{
    const double ks[] = { -1.5, 0.0, 1.5 };
    const double as[] = { -1.5707963, 0.0, 1.5707963 };
    const double gs[] = { -0.5235988, 0.0, 0.5235988 };
    const double frel[] = { 0.0, 1.0, 4.0 };
    const double vs[] = { 0.1, -1.0, 300.0 };
    const double prel[] = { 0.5, 2.0 };
    long flagged[NCH];
    long total = 0;
    int t;
    int j;
    (void)state;
    memset(flagged, 0, sizeof flagged);
    for (t = 0; t < grip_test_tire_count; t++) {
        const grip_mf_params *p = grip_test_tires[t].params;
        uint32_t sup = grip_mf_ext_supported(p);
        double fn = from_ql(p->fnomin);
        size_t a, b, c, d, e, f;
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++)
                for (c = 0; c < 3; c++)
                    for (d = 0; d < 3; d++)
                        for (e = 0; e < 3; e++)
                            for (f = 0; f < 2; f++) {
                                double fz = (d == 0) ? 1.0 : frel[d] * fn;
                                double vx = (vs[e] < 0.0) ? from_qs(p->longvl) : vs[e];
                                double pr = prel[f] * from_ql(p->nompres);
                                grip_mf_input in = mk(ks[a], as[b], gs[c], fz, pr, vx);
                                grip_mf_output_ext o;
                                grip_status_t st = grip_mf_eval_ext(p, &in, GRIP_MF_EXT_ALL, &o);
                                if (st != GRIP_OK) {
                                    fail_msg("%s corner k=%g a=%g g=%g fz=%g vx=%g: status %d", grip_test_tires[t].name,
                                             ks[a], as[b], gs[c], fz, vx, (int)st);
                                }
                                assert_true((o.valid & ~sup) == 0u);
                                total++;
                                for (j = 0; j < NCH; j++) {
                                    double v = val(&o, j);
                                    if ((o.valid & CHANNELS[j].bit) == 0u) {
                                        assert_true(raw(&o, j) == 0);
                                        flagged[j] += ((sup & CHANNELS[j].bit) != 0u);
                                    } else if (!isfinite(v) || fabs(v) >= (CHANNELS[j].ql ? 8.0e6 : 30000.0)) {
                                        fail_msg("%s %s = %g", grip_test_tires[t].name, CHANNELS[j].name, v);
                                    }
                                }
                            }
    }
    printf("# %ld domain corners:", total);
    for (j = 0; j < NCH; j++) {
        if (flagged[j] != 0) {
            printf(" %s flagged %ld,", CHANNELS[j].name, flagged[j]);
        }
    }
    printf(" the rest valid\n");
    assert_no_saturation();
}

/* Parameter sets at the ends of their formats: FNOMIN = 1e6 N (the largest
 * accepted) makes Kxk, Kya at 4 FNOMIN exceed 8e6 N: flagged in both
 * builds, never a saturated value; inputs far outside the domain (clamped,
 * GRIP_WARN_CLAMPED) give finite channels. */
static void test_ext_format_ends(void **state)
{
    grip_mf_params p = *tire("MagicFormula61_Paramerters");
    grip_mf_input in;
    grip_mf_output_ext o;
    int i;
    (void)state;
    p.fnomin = to_ql(1.0e6);
    in = mk(0.0, 0.0, 0.0, 4.0e6, 0.0, 16.0);
    assert_int_equal(grip_mf_eval_ext(&p, &in, GRIP_MF_EXT_ALL, &o), GRIP_OK);
    assert_true((o.valid & (GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA)) == 0u);
    assert_true(o.kxk == 0 && o.kya == 0);
    assert_true((o.valid & (GRIP_MF_EXT_MUX | GRIP_MF_EXT_T)) == (GRIP_MF_EXT_MUX | GRIP_MF_EXT_T));
    printf("# FNOMIN = 1e6 N at Fz = 4e6 N: valid %05x (Kxk, Kya flagged)\n", o.valid);
    p = *tire("MagicFormula62_Paramerters");
    for (i = 0; i < 200; i++) {
        double u = (double)i / 199.0;
        in = mk(-1e3 + 2e3 * u, -10.0 + 20.0 * u, 3.0 - 6.0 * u, (u - 0.1) * 1e7, 1e7 * u, -1000.0 + 2000.0 * u);
        grip_status_t st = grip_mf_eval_ext(&p, &in, GRIP_MF_EXT_ALL, &o);
        int j;
        assert_true(st == GRIP_OK || st == GRIP_WARN_CLAMPED);
        for (j = 0; j < NCH; j++) {
            assert_true(isfinite(val(&o, j)));
        }
    }
}

/* The use modes' arguments and refusals: both bits of a pair, a NaN spin
 * (float), turn slip on a set without its coefficients (every output 0,
 * nothing valid); grip_mf_eval and grip_mf_eval_pure refuse a set that asks
 * for turn slip or no limits; grip_mf_check_params accepts turn slip only
 * with the coefficients; phit is not read without turn slip; the set's
 * option and the per-call bit give the same result bit for bit. */
static void test_use_mode_arguments(void **state)
{
    const grip_mf_params *p = tire("MagicFormula61_Paramerters");
    const grip_mf_params *p52 = tire("MagicFormula52_Paramerters");
    grip_mf_params q = *p;
    grip_mf_input in = mk(0.05, 0.05, 0.02, 5000.0, 0.0, 16.0);
    grip_mf_output_ext o;
    grip_mf_output_ext o2;
    grip_mf_output b;
    grip_mf_spin sp = { 0 };
    (void)state;
    sp.phit = to_qs(1.0);
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP | GRIP_MF_USE_NO_TURN_SLIP, &o),
                     GRIP_ERR_INPUT);
    assert_true(o.valid == 0u && o.fx == 0 && o.fy == 0 && o.mz == 0 && o.re == 0);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_USE_LIMITS | GRIP_MF_USE_NO_LIMITS, &o), GRIP_ERR_INPUT);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, 1u << 23, &o), GRIP_ERR_INPUT);
    memset(&o, 0x5a, sizeof o);
    assert_int_equal(grip_mf_eval_ext_spin(p52, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP, &o), GRIP_ERR_PARAM);
    assert_true(o.valid == 0u && o.fx == 0 && o.fy == 0 && o.mz == 0);
    /* per set: refused by the evaluations without turn slip */
    q.options |= GRIP_MF_OPT_TURN_SLIP;
    assert_int_equal(grip_mf_check_params(&q), GRIP_OK);
    assert_int_equal(grip_mf_eval(&q, &in, &b), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_eval_pure(&q, &in, &b), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &o), GRIP_OK);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP, &o2), GRIP_OK);
    assert_memory_equal(&o, &o2, sizeof o);
    /* ... and switched off per call: the set's own model */
    assert_int_equal(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_NO_TURN_SLIP, &o), GRIP_OK);
    assert_int_equal(grip_mf_eval(p, &in, &b), GRIP_OK);
    assert_true(o.fx == b.fx && o.fy == b.fy && o.mz == b.mz);
    q = *p52;
    q.options |= GRIP_MF_OPT_TURN_SLIP;
    assert_int_equal(grip_mf_check_params(&q), GRIP_ERR_PARAM);
    /* no limits (2xx) too is grip_mf_eval_ext's */
    q = *p;
    q.options |= GRIP_MF_OPT_NO_LIMITS;
    assert_int_equal(grip_mf_check_params(&q), GRIP_OK);
    assert_int_equal(grip_mf_eval(&q, &in, &b), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_eval_pure(&q, &in, &b), GRIP_ERR_PARAM);
    assert_int_equal(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &o), GRIP_OK);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_NO_LIMITS, &o2), GRIP_OK);
    assert_memory_equal(&o, &o2, sizeof o);
#if !GRIP_ARITH_FIXED
    sp.phit = NAN;
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_ALL, &o), GRIP_OK);   /* phit not read */
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP, &o), GRIP_ERR_INPUT);
    assert_int_equal(o.valid, 0u);
    sp.phit = 0.0f;
    sp.omega = INFINITY;
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_EXT_RE, &o), GRIP_ERR_INPUT);
#endif
}

/* phit beyond +-100 1/m and omega beyond +-3000 rad/s are clamped
 * (GRIP_WARN_CLAMPED), equal to the evaluation at the limit; phit is a rate
 * about z: mirrored (alpha, gamma, phit negated) Fx stays, Fy and Mz change
 * sign; SAE (alpha, phit, Fz negated) likewise, bit for bit. */
static void test_turn_slip_clamps_and_signs(void **state)
{
    const grip_mf_params *p = tire("MagicFormula61_Paramerters");
    grip_mf_params q;
    grip_mf_input in = mk(0.05, 0.04, 0.03, 5000.0, 0.0, 16.0);
    grip_mf_input m;
    grip_mf_output_ext a;
    grip_mf_output_ext b;
    grip_mf_spin sp = { 0 };
    grip_mf_spin sm = { 0 };
    const uint32_t ts = GRIP_MF_EXT_ALL | GRIP_MF_USE_TURN_SLIP;
    (void)state;
    sp.phit = to_qs(500.0);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, ts, &a), GRIP_WARN_CLAMPED);
    sp.phit = to_qs(GRIP_MF_PHIT_MAX);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, ts, &b), GRIP_OK);
    assert_memory_equal(&a, &b, sizeof a);
    sp.phit = to_qs(1.5);
    sp.omega = to_qs(-5000.0);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, ts, &a), GRIP_WARN_CLAMPED);
    sp.omega = to_qs(-GRIP_MF_OMEGA_MAX);
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, ts, &b), GRIP_OK);
    assert_memory_equal(&a, &b, sizeof a);
    sp.omega = 0;
    /* mirror: the set mounted on the other side */
    assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, ts, &a), GRIP_OK);
    q = *p;
    q.options ^= GRIP_MF_OPT_MIRROR;
    m = in;
    m.alpha = -in.alpha;
    m.gamma = -in.gamma;
    sm.phit = -sp.phit;
    assert_int_equal(grip_mf_eval_ext_spin(&q, &m, &sm, ts, &b), GRIP_OK);
    assert_true(a.fx == b.fx && a.fy == -b.fy && a.mz == -b.mz);
    /* SAE */
    q = *p;
    q.options |= GRIP_MF_OPT_SAE;
    m = in;
    m.alpha = -in.alpha;
    sm.phit = -sp.phit;
    m.fz = -in.fz;
    assert_int_equal(grip_mf_eval_ext_spin(&q, &m, &sm, ts, &b), GRIP_OK);
    assert_true(a.fx == b.fx && a.fy == -b.fy && a.mz == -b.mz);
}

/* With the spin given, Romega / R0 = a + Q_V1 (Omega R0 / LONGVL)^2: a
 * negative Q_V1 at a high spin takes it to 0 and below, where no rolling
 * radius exists; Re and the channels built on it are not valid there
 * (neither is anything else flagged that is not finite: float build, Q_V1
 * infinite). At a moderate spin the same set gives a valid Re. */
static void test_ext_spin_radius_positive(void **state)
{
    const grip_mf_params *p = tire("MagicFormula61_Paramerters");
    grip_mf_params q = *p;
    grip_mf_input in = mk(0.0, 0.0, 0.0, 4000.0, 0.0, 16.0);
    grip_mf_output_ext o;
    grip_mf_spin sp = { 0 };
    const uint32_t radius = GRIP_MF_EXT_RE | GRIP_MF_EXT_OMEGA | GRIP_MF_EXT_RL | GRIP_MF_EXT_RHO | GRIP_MF_EXT_CZ;
    int j;
    (void)state;
    q.q_v1 = to_qs(-0.5);
    sp.omega = to_qs(20.0);
    assert_true(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &o) >= 0);
    assert_true((o.valid & GRIP_MF_EXT_RE) != 0u);
    assert_true(from_qs(o.re) > 0.1);
    sp.omega = to_qs(-500.0);
    assert_true(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &o) >= 0);
    assert_true((o.valid & radius) == 0u);
    for (j = 0; j < NCH; j++) {
        if ((CHANNELS[j].bit & radius) != 0u) {
            assert_true(raw(&o, j) == 0);
        }
    }
#if !GRIP_ARITH_FIXED
    q.q_v1 = -INFINITY;
    sp.omega = to_qs(-3000.0);
    assert_true(grip_mf_eval_ext_spin(&q, &in, &sp, GRIP_MF_EXT_ALL, &o) >= 0);
    assert_true((o.valid & radius) == 0u);
    for (j = 0; j < NCH; j++) {
        assert_true(isfinite(val(&o, j)));
    }
#endif
    assert_no_saturation();
}

/* At phit = 0 MFeval's zeta7 is 0/0; grip takes the limit. No jump at 0:
 * the step of Mz from 0 to h is at most twice the step from h to 2h (+ 4
 * LSB in the fixed build, 1e-6 relative in float), on both sides, h = 1e-5
 * 1/m (float) or one Q15.16 step (fixed). */
static void test_turn_slip_phit_zero_limit(void **state)
{
    const char *const names[] = { "MagicFormula61_Paramerters", "FSAE_Defaults" };
    int t;
    (void)state;
    for (t = 0; t < 2; t++) {
        const grip_mf_params *p = tire(names[t]);
        double fz = from_ql(p->fnomin);
        double h = IS_FIXED ? 1.0 / 65536.0 : 1e-5;
        grip_mf_input in = mk(0.02, 0.05, 0.03, fz, 0.0, 16.0);
        grip_mf_output_ext o[3];
        grip_mf_spin sp = { 0 };
        int s;
        int k;
        for (s = -1; s <= 1; s += 2) {
            double m[3];
            double slack;
            for (k = 0; k < 3; k++) {
                sp.phit = to_qs((double)(s * k) * h);
                assert_int_equal(grip_mf_eval_ext_spin(p, &in, &sp, GRIP_MF_USE_TURN_SLIP, &o[k]), GRIP_OK);
                m[k] = from_ql(o[k].mz);
                assert_true(isfinite(m[k]));
            }
            slack = IS_FIXED ? 4.0 * fz * from_qs(p->unloaded_radius) / 65536.0 : 1e-6 * fabs(m[0]);
            printf("# %s: Mz(0) = %.6f N m, steps %+.3e, %+.3e N m (phit %+.1e 1/m)\n", names[t], m[0], m[1] - m[0],
                   m[2] - m[1], s * h);
            assert_true(fabs(m[1] - m[0]) <= 2.0 * fabs(m[2] - m[1]) + slack);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ext_arguments, setup),
        cmocka_unit_test_setup(test_ext_subset, setup),
        cmocka_unit_test_setup(test_ext_supported, setup),
        cmocka_unit_test_setup(test_ext_unloaded, setup),
        cmocka_unit_test_setup(test_ext_slip_stiffness_is_slope, setup),
        cmocka_unit_test_setup(test_ext_conventions, setup),
        cmocka_unit_test_setup(test_ext_domain_corners, setup),
        cmocka_unit_test_setup(test_ext_format_ends, setup),
        cmocka_unit_test_setup(test_use_mode_arguments, setup),
        cmocka_unit_test_setup(test_turn_slip_clamps_and_signs, setup),
        cmocka_unit_test_setup(test_turn_slip_phit_zero_limit, setup),
        cmocka_unit_test_setup(test_ext_spin_radius_positive, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
