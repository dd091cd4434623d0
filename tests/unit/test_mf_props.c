/*
 * test_mf_props.c - properties of lib/mf that hold whatever the reference
 * says: the slope at zero slip is B*C*D, the peak is D, odd symmetry with
 * symmetric parameters, combined-slip forces inside the envelope the
 * weighting functions allow, input validation and clamping, and one test per
 * option bit / sign convention. The parameter sets are built here (the
 * Pacejka-book example values of mfeval-tir/PacejkaBook_Defaults.tir plus
 * chosen shifts), so the tests do not depend on the golden vectors; the
 * shared .tir sets (tests/support/mf_params.h) are used in addition where a
 * test applies to any parameter set.
 *
 * Tolerances are stated next to each check as absolute + relative, for the
 * float and the fixed build (docs/magic-formula-c.md, "Property tests").
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
/* One step of a normalized output (F / FNOMIN is Q15.16) plus the QL
 * rounding of the output, for FNOMIN = 4000 N: the unit of the fixed-point
 * tolerances below. */
#define LSB_N (4000.0 / 65536.0 + 1.0 / 256.0)
#define IS_FIXED 1
#else
static grip_real_t to_qs(double v) { return (grip_real_t)v; }
static grip_real_t to_ql(double v) { return (grip_real_t)v; }
static double from_qs(grip_real_t v) { return (double)v; }
static double from_ql(grip_real_t v) { return (double)v; }
#define LSB_N 0.0
#define IS_FIXED 0
#endif

#define FNOM 4000.0
#define R0 0.3135
#define PNOM 220000.0
#define V_TEST 16.7

/* ----------------------------------------------------------- parameters */

#define TO_QS(v) to_qs(v)
#define TO_QL(v) to_ql(v)
static void defaults(grip_mf_params *p)
{
    memset(p, 0, sizeof(*p));
#define SET_DEFAULT(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) p->field = TO_##FORMAT(DEFAULT);
    GRIP_MF_COEFFICIENTS(SET_DEFAULT)
#undef SET_DEFAULT
}

/* Symmetric MF 6.1 set: the Pacejka-book example values, no shifts, no
 * conicity or ply-steer, no kappa-induced side force. */
static void symmetric_params(grip_mf_params *p)
{
    defaults(p);
    p->fittyp = 61;
    p->tyreside = 1;
    p->options = 0u;
    p->longvl = to_qs(V_TEST);
    p->vxlow = to_qs(1.0);
    p->unloaded_radius = to_qs(R0);
    p->fnomin = to_ql(FNOM);
    p->nompres = to_ql(PNOM);
    p->inflpres = to_ql(PNOM);
    p->pcx1 = to_qs(1.6);
    p->pdx1 = to_qs(1.0);
    p->pdx2 = to_qs(-0.1);
    p->pkx1 = to_qs(16.0);
    p->pkx2 = to_qs(-2.0);
    p->pkx3 = to_qs(0.3);
    p->rbx1 = to_qs(8.3);
    p->rbx2 = to_qs(5.0);
    p->rcx1 = to_qs(0.9);
    p->pcy1 = to_qs(1.3);
    p->pdy1 = to_qs(1.0);
    p->pdy2 = to_qs(-0.05);
    p->pky1 = to_qs(-15.0);
    p->pky2 = to_qs(2.0);
    p->pky4 = to_qs(2.0);
    p->pky6 = to_qs(-1.0);
    p->rby1 = to_qs(4.9);
    p->rby2 = to_qs(2.2);
    p->rcy1 = to_qs(1.0);
    p->rvy4 = to_qs(20.0);
    p->rvy5 = to_qs(2.0);
    p->rvy6 = to_qs(10.0);
    p->qbz1 = to_qs(10.0);
    p->qbz9 = to_qs(10.0);
    p->qcz1 = to_qs(1.1);
    p->qdz1 = to_qs(0.12);
    p->qdz8 = to_qs(-0.05);
    p->ssz2 = to_qs(0.03);
}

/* The same with the shifts, asymmetries, pressure and camber terms of a
 * measured MF 6.1 tyre (values of the order of mfeval-tir's MF 6.1 file). */
static void asymmetric_params(grip_mf_params *p)
{
    symmetric_params(p);
    p->phx1 = to_qs(-0.0016);
    p->phx2 = to_qs(0.001);
    p->pvx1 = to_qs(0.07);
    p->pvx2 = to_qs(-0.008);
    p->pex1 = to_qs(0.4);
    p->pex2 = to_qs(0.09);
    p->pex4 = to_qs(0.38);
    p->pdx3 = to_qs(-1.4);
    p->ppx1 = to_qs(-1.0);
    p->ppx3 = to_qs(-0.06);
    p->ppx4 = to_qs(0.5);
    p->rbx3 = to_qs(186.0);
    p->rex1 = to_qs(-1.39);
    p->rhx1 = to_qs(0.0044);
    p->phy1 = to_qs(0.0012);
    p->phy2 = to_qs(0.0017);
    p->pvy1 = to_qs(0.0015);
    p->pvy2 = to_qs(0.027);
    p->pvy3 = to_qs(-0.34);
    p->pey1 = to_qs(-0.2);
    p->pey2 = to_qs(-0.27);
    p->pey3 = to_qs(0.78);
    p->pey4 = to_qs(-49.9);
    p->pey5 = to_qs(421.0);
    p->pky3 = to_qs(1.05);
    p->pky5 = to_qs(-46.6);
    p->ppy1 = to_qs(0.42);
    p->ppy3 = to_qs(0.067);
    p->rby3 = to_qs(-0.0325);
    p->rby4 = to_qs(204.0);
    p->rey1 = to_qs(0.44);
    p->rhy1 = to_qs(-0.0032);
    p->rhy2 = to_qs(0.0076);
    p->rvy1 = to_qs(1.24);
    p->rvy2 = to_qs(1.32);
    p->rvy3 = to_qs(121.0);
    p->qbz4 = to_qs(2.16);
    p->qbz5 = to_qs(1.03);
    p->qbz10 = to_qs(0.23);
    p->qdz3 = to_qs(-0.59);
    p->qdz4 = to_qs(-1.03);
    p->qdz6 = to_qs(0.004);
    p->qdz7 = to_qs(-0.0009);
    p->qez1 = to_qs(-1.6);
    p->qez4 = to_qs(0.53);
    p->qhz1 = to_qs(-0.0005);
    p->qhz2 = to_qs(0.005);
    p->qhz4 = to_qs(0.28);
    p->ppz1 = to_qs(0.85);
    p->ssz1 = to_qs(-0.041);
    p->ssz3 = to_qs(1.05);
}

/* ------------------------------------------------------------ evaluation */

typedef struct {
    double fx;
    double fy;
    double mz;
    grip_status_t st;
} res_t;

static uint32_t evaluations;

static res_t ev(const grip_mf_params *p, int combined, double kappa, double alpha, double gamma, double fz, double pr,
                double vx)
{
    grip_mf_input in;
    grip_mf_output out;
    res_t r;
    in.kappa = to_qs(kappa);
    in.alpha = to_qs(alpha);
    in.gamma = to_qs(gamma);
    in.fz = to_ql(fz);
    in.p = to_ql(pr);
    in.vx = to_qs(vx);
    out.fx = out.fy = out.mz = to_ql(12345.0);
    r.st = combined ? grip_mf_eval(p, &in, &out) : grip_mf_eval_pure(p, &in, &out);
    r.fx = from_ql(out.fx);
    r.fy = from_ql(out.fy);
    r.mz = from_ql(out.mz);
    evaluations++;
    return r;
}

static res_t evp(const grip_mf_params *p, double kappa, double alpha, double gamma, double fz)
{
    return ev(p, 0, kappa, alpha, gamma, fz, PNOM, V_TEST);
}

static res_t evc(const grip_mf_params *p, double kappa, double alpha, double gamma, double fz)
{
    return ev(p, 1, kappa, alpha, gamma, fz, PNOM, V_TEST);
}

static int finite3(res_t r)
{
    return isfinite(r.fx) && isfinite(r.fy) && isfinite(r.mz);
}

/* Every test starts with a clean saturation count; in-domain tests end by
 * asserting that it is still zero (GRIP_DEBUG_SATURATION builds). */
static int setup(void **state)
{
    (void)state;
    grip_debug_saturation_reset();
    evaluations = 0;
    return 0;
}

static void assert_no_saturation(void)
{
    if (grip_debug_saturation_count() != 0u) {
        fail_msg("%lu saturations (first: %s) in %lu in-domain evaluations",
                 (unsigned long)grip_debug_saturation_count(), grip_debug_saturation_first(),
                 (unsigned long)evaluations);
    }
}

/* ------------------------------------------------- slope at zero slip */

/* dFx0/dkappa at kappa = 0 = Bx Cx Dx = Kxk = Fz (PKX1 + PKX2 dfz) exp(PKX3 dfz)
 * (4.E15), by a central difference. Truncation error of the difference
 * (B h)^2 / 6 * (1 + 2 C^2)-ish: < 1e-5 (float, h = 1e-4), < 5e-4 (fixed,
 * h = 2e-3, where the difference of two outputs is also off by up to 2 LSB).
 * Tolerance: float 2e-4 relative, fixed 3e-3 relative. */
static void test_fx0_slope_is_bcd(void **state)
{
    grip_mf_params p;
    err_stats st;
    const double loads[] = { 0.5, 1.0, 1.5, 2.0 };
    const double h_req = IS_FIXED ? 2e-3 : 1e-4;
    const double h = from_qs(to_qs(h_req));
    const double tol = IS_FIXED ? 3e-3 : 2e-4;
    size_t i;
    (void)state;
    symmetric_params(&p);
    err_init(&st, "Fx0 slope / Kxk", 1.0);
    for (i = 0; i < sizeof(loads) / sizeof(loads[0]); i++) {
        double fz = loads[i] * FNOM;
        double dfz = loads[i] - 1.0;
        double kxk = fz * (16.0 - 2.0 * dfz) * exp(0.3 * dfz);
        double slope = (evp(&p, h, 0.0, 0.0, fz).fx - evp(&p, -h, 0.0, 0.0, fz).fx) / (2.0 * h);
        err_add(&st, slope / kxk, 1.0, fz, kxk, slope);
    }
    err_print(&st, "(relative)");
    assert_true(st.max_abs <= tol);
    assert_no_saturation();
}

/* dFy0/dalpha at alpha = 0 = By Cy Dy = Kya = PKY1 Fz0 sin(PKY4 atan(Fz /
 * (PKY2 Fz0))) (4.E25). Same differences and tolerances as for Fx0. */
static void test_fy0_slope_is_bcd(void **state)
{
    grip_mf_params p;
    err_stats st;
    const double loads[] = { 0.3, 1.0, 1.5, 2.5 };
    const double h_req = IS_FIXED ? 2e-3 : 1e-4;
    const double h = from_qs(to_qs(h_req));
    const double tol = IS_FIXED ? 3e-3 : 2e-4;
    size_t i;
    (void)state;
    symmetric_params(&p);
    err_init(&st, "Fy0 slope / Kya", 1.0);
    for (i = 0; i < sizeof(loads) / sizeof(loads[0]); i++) {
        double fz = loads[i] * FNOM;
        double kya = -15.0 * FNOM * sin(2.0 * atan(fz / (2.0 * FNOM)));
        double slope = (evp(&p, 0.0, h, 0.0, fz).fy - evp(&p, 0.0, -h, 0.0, fz).fy) / (2.0 * h);
        err_add(&st, slope / kya, 1.0, fz, kya, slope);
    }
    err_print(&st, "(relative)");
    assert_true(st.max_abs <= tol);
    assert_no_saturation();
}

/* ------------------------------------------------------- peak equals D */

/* The largest |Fx0| over kappa in [0, 0.6] (step 1e-4) is |Dx| = |PDX1 +
 * PDX2 dfz| Fz, the largest |Fy0| over alpha in [0, 0.6] is |Dy|, because
 * C > 1 and E = 0 put the peak inside the sweep and there are no shifts.
 * The sampled maximum misses the peak by < D (C pi/2 B step)^2 / 8 ~ 1e-7 D.
 * Tolerance: float 1e-5 relative, fixed 2e-4 relative (one output LSB is
 * 1.5e-5 FNOMIN). */
static void test_peak_is_d(void **state)
{
    grip_mf_params p;
    err_stats sx;
    err_stats sy;
    const double loads[] = { 0.5, 1.0, 2.0 };
    size_t i;
    int k;
    (void)state;
    symmetric_params(&p);
    err_init(&sx, "max |Fx0| vs Dx", 1.0);
    err_init(&sy, "max |Fy0| vs Dy", 1.0);
    for (i = 0; i < sizeof(loads) / sizeof(loads[0]); i++) {
        double fz = loads[i] * FNOM;
        double dfz = loads[i] - 1.0;
        double dx = fabs(1.0 - 0.1 * dfz) * fz;
        double dy = fabs(1.0 - 0.05 * dfz) * fz;
        double mx = 0.0;
        double my = 0.0;
        for (k = 0; k <= 6000; k++) {
            double s = 1e-4 * k;
            res_t r = evp(&p, s, s, 0.0, fz);
            if (fabs(r.fx) > mx) mx = fabs(r.fx);
            if (fabs(r.fy) > my) my = fabs(r.fy);
        }
        err_add(&sx, mx / dx, 1.0, fz, dx, mx);
        err_add(&sy, my / dy, 1.0, fz, dy, my);
    }
    err_print(&sx, "(relative)");
    err_print(&sy, "(relative)");
#if IS_FIXED
    assert_true(sx.max_abs <= 2e-4);
    assert_true(sy.max_abs <= 2e-4);
#else
    assert_true(sx.max_abs <= 1e-5);
    assert_true(sy.max_abs <= 1e-5);
#endif
    assert_no_saturation();
}

/* --------------------------------------------------------- odd symmetry */

/* With the symmetric set at gamma = 0: Fx0, Fy0, Mz0 are odd in their slip;
 * combined Fx is odd in kappa and even in alpha, Fy and Mz odd in alpha and
 * even in kappa. Tolerance: float 1e-5 N (+1e-6 relative), fixed 2 LSB. */
static void test_odd_symmetry(void **state)
{
    grip_mf_params p;
    err_stats st[6];
    const char *names[6] = { "Fx0(-k) + Fx0(k)", "Fy0(-a) + Fy0(a)", "Mz0(-a) + Mz0(a)",
                             "Fx(-k,a) + Fx(k,a)", "Fy(k,-a) + Fy(k,a)", "Mz(k,-a) + Mz(k,a)" };
    double worst = 0.0;
    int i;
    int j;
    int n;
    (void)state;
    symmetric_params(&p);
    for (n = 0; n < 6; n++) {
        err_init(&st[n], names[n], 1.0);
    }
    for (i = 1; i <= 30; i++) {
        for (j = 0; j <= 30; j++) {
            double k = 0.04 * i - 0.02 * j;
            double a = 0.025 * j;
            double fz = FNOM * (0.6 + 0.03 * i);
            res_t p1 = evp(&p, k, a, 0.0, fz);
            res_t p2 = evp(&p, -k, -a, 0.0, fz);
            res_t c1 = evc(&p, k, a, 0.0, fz);
            res_t c2 = evc(&p, -k, a, 0.0, fz);
            res_t c3 = evc(&p, k, -a, 0.0, fz);
            res_t c4 = evc(&p, -k, -a, 0.0, fz);
            double d[6];
            d[0] = p1.fx + p2.fx;
            d[1] = p1.fy + p2.fy;
            d[2] = p1.mz + p2.mz;
            d[3] = c1.fx + c2.fx;
            d[4] = c1.fy + c3.fy;
            d[5] = c1.mz + c3.mz;
            for (n = 0; n < 6; n++) {
                double scale = (n == 0) ? fabs(p1.fx) : (n == 1) ? fabs(p1.fy) : (n == 2) ? fabs(p1.mz)
                             : (n == 3) ? fabs(c1.fx) : (n == 4) ? fabs(c1.fy) : fabs(c1.mz);
                double tol = IS_FIXED ? 2.0 * 4000.0 / 65536.0 * ((n == 2 || n == 5) ? R0 : 1.0) + 2.0 / 256.0
                                      : 1e-5 + 1e-6 * scale;
                err_add(&st[n], d[n], 0.0, k, a, fz);
                if (fabs(d[n]) / tol > worst) worst = fabs(d[n]) / tol;
            }
            /* the even directions: equal, same tolerance */
            if (fabs(c1.fx - c3.fx) > (IS_FIXED ? 2.0 * LSB_N : 1e-5 + 1e-6 * fabs(c1.fx))) {
                fail_msg("Fx not even in alpha at k=%g a=%g: %.9g %.9g", k, a, c1.fx, c3.fx);
            }
            if (fabs(c1.fy - c2.fy) > (IS_FIXED ? 2.0 * LSB_N : 1e-5 + 1e-6 * fabs(c1.fy))) {
                fail_msg("Fy not even in kappa at k=%g a=%g: %.9g %.9g", k, a, c1.fy, c2.fy);
            }
            if (fabs(c1.fx + c4.fx - (c1.fx + c2.fx)) > (IS_FIXED ? 4.0 * LSB_N : 2e-5 + 1e-6 * fabs(c1.fx))) {
                fail_msg("Fx(-k,-a) != -Fx(k,a) at k=%g a=%g", k, a);
            }
        }
    }
    for (n = 0; n < 6; n++) {
        err_print(&st[n], (n == 2 || n == 5) ? "N m" : "N");
    }
    printf("# worst |asymmetry| / tolerance = %.3f\n", worst);
    assert_true(worst <= 1.0);
    assert_no_saturation();
}

/* -------------------------------------------------- combined envelope */

static double mf_cos_curve_d(double b, double c, double e, double x)
{
    double bx = b * x;
    return cos(c * atan(bx - e * (bx - atan(bx))));
}

/* Combined slip scales the pure forces by weighting functions G = cos(...) /
 * G0 (4.E51, 4.E59): |Fx| <= |Fx0| / Gxa0 and |Fy - SVyk| <= |Fy0| / Gyk0,
 * with |SVyk| <= |mu_y Fz| (|RVY1 + RVY2 dfz| + |RVY3 gamma|) LVYKA. With no
 * combined-slip shifts (G0 = 1, SVyk = 0) that is |Fx| <= |Fx0|, |Fy| <= |Fy0|.
 * Checked for the symmetric set, the asymmetric set and every shared .tir set
 * (p at INFLPRES, gamma 0 and 0.05 rad). Tolerance: float 1e-5 relative +
 * 1e-3 N, fixed 1e-4 relative + 4 LSB of the tyre's normalized force. */
static int envelope_violations(const grip_mf_params *p, const char *name)
{
    double fnom = from_ql(p->fnomin);
    double lsb = IS_FIXED ? 4.0 * fnom / 65536.0 + 2.0 / 256.0 : 1e-3;
    double rel = IS_FIXED ? 1e-4 : 1e-5;
    int bad = 0;
    int i;
    int j;
    int g;
    double worst = 0.0;
    for (g = 0; g < 2; g++) {
        double gamma = 0.05 * g;
        for (i = 0; i <= 20; i++) {
            for (j = 0; j <= 20; j++) {
                double k = -0.8 + 0.08 * i;
                double a = -0.4 + 0.04 * j;
                double fz = fnom;
                double dfz = 1.0 / from_qs(p->lfzo) - 1.0;
                double gs = (p->fittyp == 61 || p->fittyp == 62) ? gamma : gamma * from_qs(p->lgax);
                double bxa = (from_qs(p->rbx1) + from_qs(p->rbx3) * gs * gs) * cos(atan(from_qs(p->rbx2) * k)) *
                             from_qs(p->lxal);
                double exa = fmin(from_qs(p->rex1) + from_qs(p->rex2) * dfz, 1.0);
                double gxa0 = mf_cos_curve_d(bxa, from_qs(p->rcx1), exa, from_qs(p->rhx1));
                double shyk = from_qs(p->rhy1) + from_qs(p->rhy2) * dfz;
                double eyk = fmin(from_qs(p->rey1) + from_qs(p->rey2) * dfz, 1.0);
                double byk_max = fabs(from_qs(p->rby1) + from_qs(p->rby4) * gs * gs) * from_qs(p->lyka);
                double gyk0_min = 1.0;
                double muy = fabs((from_qs(p->pdy1) + from_qs(p->pdy2) * dfz) * (1.0 - from_qs(p->pdy3) * gs * gs) *
                                  from_qs(p->lmuy));
                double svyk_max = muy * fz *
                                  (fabs(from_qs(p->rvy1) + from_qs(p->rvy2) * dfz) + fabs(from_qs(p->rvy3) * gs)) *
                                  fabs(from_qs(p->lvyka)) * (1.0 + 1e-9);
                double pr = from_ql(p->inflpres);
                res_t p0 = ev(p, 0, k, a, gamma, fz, pr, from_qs(p->longvl));
                res_t c = ev(p, 1, k, a, gamma, fz, pr, from_qs(p->longvl));
                int m;
                /* Byk varies with alpha (cos(atan(RBY2 (alpha - RBY3)))):
                 * bound Gyk0 from below over Byk in [0, byk_max]. */
                for (m = 0; m <= 50; m++) {
                    double gk = mf_cos_curve_d(byk_max * m / 50.0, from_qs(p->rcy1), eyk, shyk);
                    if (gk < gyk0_min) gyk0_min = gk;
                }
                {
                    double limx = fabs(p0.fx) / gxa0;
                    double limy = fabs(p0.fy) / gyk0_min + svyk_max;
                    double ex = fabs(c.fx) - (limx * (1.0 + rel) + lsb);
                    double ey = fabs(c.fy) - (limy * (1.0 + rel) + lsb);
                    if (ex > 0.0 || ey > 0.0) {
                        if (bad < 3) {
                            printf("# %s: k=%g a=%g g=%g: |Fx|=%.6g limit %.6g, |Fy|=%.6g limit %.6g\n", name, k, a,
                                   gamma, fabs(c.fx), limx, fabs(c.fy), limy);
                        }
                        bad++;
                    }
                    if (limx > 0.0 && fabs(c.fx) / limx > worst) worst = fabs(c.fx) / limx;
                    if (limy > 0.0 && fabs(c.fy) / limy > worst) worst = fabs(c.fy) / limy;
                }
            }
        }
    }
    printf("# %-28s combined / envelope <= %.6f (%d violations)\n", name, worst, bad);
    return bad;
}

static void test_combined_within_envelope(void **state)
{
    grip_mf_params p;
    int bad = 0;
    int i;
    (void)state;
    symmetric_params(&p);
    bad += envelope_violations(&p, "symmetric set");
    asymmetric_params(&p);
    bad += envelope_violations(&p, "asymmetric set");
    for (i = 0; i < grip_test_tire_count; i++) {
        bad += envelope_violations(grip_test_tires[i].params, grip_test_tires[i].name);
    }
    assert_int_equal(bad, 0);
    assert_no_saturation();
}

/* Without combined-slip shifts, G <= 1 exactly: |Fx| <= |Fx0|, |Fy| <= |Fy0|. */
static void test_combined_reduces_force(void **state)
{
    grip_mf_params p;
    int i;
    int j;
    double worst = 0.0;
    (void)state;
    symmetric_params(&p);
    for (i = 0; i <= 40; i++) {
        for (j = 0; j <= 40; j++) {
            double k = -1.0 + 0.05 * i;
            double a = -0.6 + 0.03 * j;
            res_t p0 = evp(&p, k, a, 0.0, FNOM);
            res_t c = evc(&p, k, a, 0.0, FNOM);
            double tol = IS_FIXED ? 2.0 * LSB_N : 1e-3;
            assert_true(fabs(c.fx) <= fabs(p0.fx) * (1.0 + 1e-6) + tol);
            assert_true(fabs(c.fy) <= fabs(p0.fy) * (1.0 + 1e-6) + tol);
            if (fabs(p0.fx) > 1.0 && fabs(c.fx) / fabs(p0.fx) > worst) worst = fabs(c.fx) / fabs(p0.fx);
        }
    }
    printf("# symmetric set: max |Fx| / |Fx0| = %.6f\n", worst);
    /* and combined slip does reduce: at kappa = 0.1, alpha = 0.2 */
    assert_true(fabs(evc(&p, 0.1, 0.2, 0.0, FNOM).fx) < 0.9 * fabs(evp(&p, 0.1, 0.2, 0.0, FNOM).fx));
    assert_true(fabs(evc(&p, 0.1, 0.2, 0.0, FNOM).fy) < 0.95 * fabs(evp(&p, 0.1, 0.2, 0.0, FNOM).fy));
    assert_no_saturation();
}

/* ---------------------------------------------------------- edge inputs */

static void check_zero(res_t r, grip_status_t want)
{
    assert_int_equal(r.st, want);
    assert_true(r.fx == 0.0 && r.fy == 0.0 && r.mz == 0.0);
}

static void edge_inputs_for(const grip_mf_params *p, const char *name)
{
    double fnom = from_ql(p->fnomin);
    double pr = from_ql(p->inflpres);
    double v = from_qs(p->longvl);
    int c;
    for (c = 0; c < 2; c++) {
        res_t r;
        res_t ref;
        /* no load, negative load: zero outputs, OK */
        check_zero(ev(p, c, 0.1, 0.1, 0.0, 0.0, pr, v), GRIP_OK);
        check_zero(ev(p, c, 0.1, 0.1, 0.0, -500.0, pr, v), GRIP_OK);
        /* |kappa| = 1e3: clamped to +-GRIP_MF_KAPPA_MAX */
        r = ev(p, c, 1e3, 0.1, 0.0, fnom, pr, v);
        ref = ev(p, c, GRIP_MF_KAPPA_MAX, 0.1, 0.0, fnom, pr, v);
        assert_int_equal(r.st, GRIP_WARN_CLAMPED);
        assert_int_equal(ref.st, GRIP_OK);
        assert_true(finite3(r) && r.fx == ref.fx && r.fy == ref.fy && r.mz == ref.mz);
        r = ev(p, c, -1e3, -0.1, 0.0, fnom, pr, v);
        assert_int_equal(r.st, GRIP_WARN_CLAMPED);
        assert_true(finite3(r));
        /* alpha = +-pi/2 is inside the domain */
        r = ev(p, c, 0.05, GRIP_MF_ALPHA_MAX, 0.0, fnom, pr, v);
        assert_int_equal(r.st, GRIP_OK);
        assert_true(finite3(r));
        r = ev(p, c, -0.05, -GRIP_MF_ALPHA_MAX, 0.0, fnom, pr, v);
        assert_int_equal(r.st, GRIP_OK);
        assert_true(finite3(r));
        r = ev(p, c, 0.0, 2.5, 0.0, fnom, pr, v);
        assert_int_equal(r.st, GRIP_WARN_CLAMPED);
        assert_true(finite3(r));
        /* vx = 0: the low-speed model makes every slip and output zero */
        r = ev(p, c, 0.3, 0.3, 0.05, fnom, pr, 0.0);
        assert_int_equal(r.st, GRIP_OK);
        assert_true(finite3(r));
        if (p->vxlow > 0) {
            assert_true(fabs(r.fx) <= 1e-9 && fabs(r.fy) <= 1e-9 && fabs(r.mz) <= 1e-9);
        }
        /* vx < 0 behaves as |vx| */
        r = ev(p, c, 0.1, 0.1, 0.02, fnom, pr, -v);
        ref = ev(p, c, 0.1, 0.1, 0.02, fnom, pr, v);
        assert_true(r.st == GRIP_OK && r.fx == ref.fx && r.fy == ref.fy && r.mz == ref.mz);
        /* very large load: clamped to GRIP_MF_FZ_MAX_REL * FNOMIN */
        r = ev(p, c, 0.1, 0.1, 0.0, 1e6, pr, v);
        ref = ev(p, c, 0.1, 0.1, 0.0, GRIP_MF_FZ_MAX_REL * fnom, pr, v);
        assert_int_equal(r.st, GRIP_WARN_CLAMPED);
        assert_true(finite3(r) && r.fx == ref.fx && r.fy == ref.fy && r.mz == ref.mz);
    }
    (void)name;
}

/* Fz = 0, Fz < 0, kappa = +-1e3, alpha = +-pi/2 and beyond, vx = 0, vx < 0,
 * Fz = 1e6 N: the documented status and finite (or exactly zero) outputs. */
static void test_edge_inputs(void **state)
{
    grip_mf_params p;
    int i;
    (void)state;
    symmetric_params(&p);
    edge_inputs_for(&p, "symmetric");
    asymmetric_params(&p);
    edge_inputs_for(&p, "asymmetric");
    for (i = 0; i < grip_test_tire_count; i++) {
        edge_inputs_for(grip_test_tires[i].params, grip_test_tires[i].name);
    }
    /* VXLOW = 0 switches the low-speed model off: vx = 0 still finite */
    asymmetric_params(&p);
    p.vxlow = 0;
    assert_true(finite3(evc(&p, 0.2, 0.2, 0.05, FNOM)));
    assert_true(finite3(ev(&p, 1, 0.2, 0.2, 0.05, FNOM, PNOM, 0.0)));
    assert_no_saturation();
}

/* Random inputs far outside the valid domain: never an error for finite
 * inputs, never a non-finite output, never a saturation (the clamps keep the
 * fixed-point arithmetic in range). */
static void test_random_inputs_stay_finite(void **state)
{
    grip_mf_params sets[2];
    uint32_t seed = 12345u;
    int n;
    int s;
    long clamped = 0;
    (void)state;
    symmetric_params(&sets[0]);
    asymmetric_params(&sets[1]);
    for (s = 0; s < 2 + grip_test_tire_count; s++) {
        const grip_mf_params *p = (s < 2) ? &sets[s] : grip_test_tires[s - 2].params;
        double fnom = from_ql(p->fnomin);
        for (n = 0; n < 3000; n++) {
            double u[6];
            int j;
            res_t r;
            for (j = 0; j < 6; j++) {
                seed = seed * 1664525u + 1013904223u;
                u[j] = (double)(seed >> 8) / 16777216.0 * 2.0 - 1.0;   /* [-1, 1) */
            }
            r = ev(p, n & 1, 1e3 * u[0] * u[0] * u[0], 4.0 * u[1], 2.0 * u[2], fnom * (1.0 + 8.0 * u[3]),
                   4.0 * PNOM * u[4], 400.0 * u[5]);
            assert_true(r.st == GRIP_OK || r.st == GRIP_WARN_CLAMPED);
            assert_true(finite3(r));
            if (r.st == GRIP_WARN_CLAMPED) clamped++;
        }
    }
    printf("# %lu random evaluations, %ld clamped, %lu saturations\n", (unsigned long)evaluations, clamped,
           (unsigned long)grip_debug_saturation_count());
    assert_no_saturation();
}

/* ---------------------------------------------------- invalid / NULL */

static void expect_param_error(const grip_mf_params *p)
{
    res_t r;
    assert_int_equal(grip_mf_check_params(p), GRIP_ERR_PARAM);
    r = evp(p, 0.1, 0.1, 0.0, FNOM);
    check_zero(r, GRIP_ERR_PARAM);
    r = evc(p, 0.1, 0.1, 0.0, FNOM);
    check_zero(r, GRIP_ERR_PARAM);
}

static void test_invalid_params(void **state)
{
    grip_mf_params p;
    int i;
    (void)state;
    symmetric_params(&p);
    assert_int_equal(grip_mf_check_params(&p), GRIP_OK);
    asymmetric_params(&p);
    assert_int_equal(grip_mf_check_params(&p), GRIP_OK);
    for (i = 0; i < grip_test_tire_count; i++) {
        assert_int_equal(grip_mf_check_params(grip_test_tires[i].params), GRIP_OK);
    }
    symmetric_params(&p); p.fittyp = 7; expect_param_error(&p);
    symmetric_params(&p); p.fittyp = 0; expect_param_error(&p);
    symmetric_params(&p); p.fnomin = 0; expect_param_error(&p);
    symmetric_params(&p); p.fnomin = to_ql(-4000.0); expect_param_error(&p);
    symmetric_params(&p); p.fnomin = to_ql(2e6); expect_param_error(&p);
    symmetric_params(&p); p.unloaded_radius = 0; expect_param_error(&p);
    symmetric_params(&p); p.unloaded_radius = to_qs(-0.3); expect_param_error(&p);
    symmetric_params(&p); p.lfzo = 0; expect_param_error(&p);
    symmetric_params(&p); p.tyreside = 0; expect_param_error(&p);
    symmetric_params(&p); p.options = 1u << 9; expect_param_error(&p);
    symmetric_params(&p); p.options = GRIP_MF_OPT_TURN_SLIP; expect_param_error(&p);   /* no turn-slip coefficients */
    symmetric_params(&p); p.lmux = to_qs(-1.0); expect_param_error(&p);
    symmetric_params(&p); p.lmuv = to_qs(1.0); p.longvl = 0; expect_param_error(&p);
    symmetric_params(&p); p.nompres = to_ql(-1.0); expect_param_error(&p);
#if !IS_FIXED
    symmetric_params(&p); p.pkx1 = NAN; expect_param_error(&p);
    symmetric_params(&p); p.qdz1 = INFINITY; expect_param_error(&p);
    symmetric_params(&p); p.fnomin = NAN; expect_param_error(&p);
    /* finite but absurd: SVx = 2e37 FNOMIN overflows float; the output
     * guard turns the non-finite result into zeros and GRIP_ERR_DOMAIN */
    symmetric_params(&p);
    p.pvx1 = 1e37f;
    assert_int_equal(grip_mf_check_params(&p), GRIP_OK);
    check_zero(evp(&p, 0.1, 0.1, 0.0, 2.0 * FNOM), GRIP_ERR_DOMAIN);
    check_zero(evc(&p, 0.1, 0.1, 0.0, 2.0 * FNOM), GRIP_ERR_DOMAIN);
#endif
}

static void test_null_pointers(void **state)
{
    grip_mf_params p;
    grip_mf_input in;
    grip_mf_output out;
    (void)state;
    symmetric_params(&p);
    memset(&in, 0, sizeof(in));
    in.fz = to_ql(FNOM);
    assert_int_equal(grip_mf_check_params(NULL), GRIP_ERR_NULL);
    out.fx = out.fy = out.mz = to_ql(1.0);
    assert_int_equal(grip_mf_eval(NULL, &in, &out), GRIP_ERR_NULL);
    assert_true(out.fx == 0 && out.fy == 0 && out.mz == 0);
    out.fx = out.fy = out.mz = to_ql(1.0);
    assert_int_equal(grip_mf_eval(&p, NULL, &out), GRIP_ERR_NULL);
    assert_true(out.fx == 0 && out.fy == 0 && out.mz == 0);
    assert_int_equal(grip_mf_eval(&p, &in, NULL), GRIP_ERR_NULL);
    out.fx = out.fy = out.mz = to_ql(1.0);
    assert_int_equal(grip_mf_eval_pure(NULL, &in, &out), GRIP_ERR_NULL);
    assert_true(out.fx == 0 && out.fy == 0 && out.mz == 0);
    assert_int_equal(grip_mf_eval_pure(&p, NULL, &out), GRIP_ERR_NULL);
    assert_int_equal(grip_mf_eval_pure(&p, &in, NULL), GRIP_ERR_NULL);
}

#if !IS_FIXED
/* Float build: a NaN or infinity in any input is GRIP_ERR_INPUT with zero
 * outputs (pure and combined). */
static void test_nonfinite_inputs(void **state)
{
    grip_mf_params p;
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    int field;
    int b;
    int c;
    (void)state;
    symmetric_params(&p);
    for (field = 0; field < 6; field++) {
        for (b = 0; b < 3; b++) {
            for (c = 0; c < 2; c++) {
                grip_mf_input in = { 0.1f, 0.1f, 0.0f, (float)FNOM, (float)PNOM, (float)V_TEST };
                grip_mf_output out = { 1.0f, 1.0f, 1.0f };
                grip_status_t st;
                float *f = (field == 0) ? &in.kappa : (field == 1) ? &in.alpha : (field == 2) ? &in.gamma
                         : (field == 3) ? &in.fz : (field == 4) ? &in.p : &in.vx;
                *f = bad[b];
                st = c ? grip_mf_eval(&p, &in, &out) : grip_mf_eval_pure(&p, &in, &out);
                assert_int_equal(st, GRIP_ERR_INPUT);
                assert_true(out.fx == 0.0f && out.fy == 0.0f && out.mz == 0.0f);
            }
        }
    }
}
#endif

/* ------------------------------------------------------------- options */

static void assert_same(res_t a, res_t b, double sfx, double sfy, double smz)
{
    assert_int_equal(a.st, b.st);
    if (!(a.fx == sfx * b.fx && a.fy == sfy * b.fy && a.mz == smz * b.mz)) {
        fail_msg("(%.9g %.9g %.9g) != (%.9g %.9g %.9g) * (%g %g %g)", a.fx, a.fy, a.mz, b.fx, b.fy, b.mz, sfx, sfy,
                 smz);
    }
}

/* GRIP_MF_OPT_KAPPA_BRAKE: kappa is positive in braking. Exact. */
static void test_option_kappa_brake(void **state)
{
    grip_mf_params p;
    grip_mf_params q;
    int i;
    (void)state;
    asymmetric_params(&p);
    q = p;
    q.options = GRIP_MF_OPT_KAPPA_BRAKE;
    for (i = 0; i <= 20; i++) {
        double k = -1.0 + 0.1 * i;
        assert_same(evc(&q, k, 0.1, 0.02, FNOM), evc(&p, -k, 0.1, 0.02, FNOM), 1, 1, 1);
        assert_same(evp(&q, k, 0.1, 0.02, FNOM), evp(&p, -k, 0.1, 0.02, FNOM), 1, 1, 1);
    }
    /* braking (kappa > 0 in this convention) gives a negative Fx */
    assert_true(evp(&q, 0.1, 0.0, 0.0, FNOM).fx < -0.5 * FNOM);
    assert_no_saturation();
}

/* GRIP_MF_OPT_MIRROR: Fx(k, a, g) = Fx(k, -a, -g), Fy and Mz change sign.
 * Exact, since mirroring only negates inputs and outputs. */
static void test_option_mirror(void **state)
{
    grip_mf_params p;
    grip_mf_params q;
    int i;
    (void)state;
    asymmetric_params(&p);
    q = p;
    q.options = GRIP_MF_OPT_MIRROR;
    for (i = 0; i <= 20; i++) {
        double a = -0.5 + 0.05 * i;
        assert_same(evc(&q, 0.05, a, 0.03, FNOM), evc(&p, 0.05, -a, -0.03, FNOM), 1, -1, -1);
        assert_same(evp(&q, 0.05, a, 0.03, FNOM), evp(&p, 0.05, -a, -0.03, FNOM), 1, -1, -1);
    }
    /* an asymmetric tyre really is changed by mirroring (ply-steer) */
    assert_true(fabs(evc(&q, 0.0, 0.0, 0.0, FNOM).fy - evc(&p, 0.0, 0.0, 0.0, FNOM).fy) > 1.0);
    assert_no_saturation();
}

/* TYRESIDE: tyreside = -1 (RIGHT file) is mirrored by default (a left-side
 * tyre); GRIP_MF_OPT_RIGHT_SIDE evaluates a right-side tyre, which mirrors a
 * LEFT file instead. */
static void test_option_tyreside(void **state)
{
    grip_mf_params left;
    grip_mf_params right;
    grip_mf_params q;
    (void)state;
    asymmetric_params(&left);
    right = left;
    right.tyreside = -1;
    /* default: RIGHT file mirrored */
    assert_same(evc(&right, 0.05, 0.1, 0.03, FNOM), evc(&left, 0.05, -0.1, -0.03, FNOM), 1, -1, -1);
    /* right-side mounting: RIGHT file as fitted, LEFT file mirrored */
    q = right;
    q.options = GRIP_MF_OPT_RIGHT_SIDE;
    assert_same(evc(&q, 0.05, 0.1, 0.03, FNOM), evc(&left, 0.05, 0.1, 0.03, FNOM), 1, 1, 1);
    q = left;
    q.options = GRIP_MF_OPT_RIGHT_SIDE;
    assert_same(evc(&q, 0.05, 0.1, 0.03, FNOM), evc(&left, 0.05, -0.1, -0.03, FNOM), 1, -1, -1);
    /* MIRROR on top of TYRESIDE undoes it */
    q = right;
    q.options = GRIP_MF_OPT_MIRROR;
    assert_same(evp(&q, 0.05, 0.1, 0.03, FNOM), evp(&left, 0.05, 0.1, 0.03, FNOM), 1, 1, 1);
    assert_no_saturation();
}

/* GRIP_MF_OPT_SAE: SAE J670 inputs and outputs (y right, z down): alpha, Fz,
 * Fy, Mz change sign, kappa, gamma, Fx do not. Exact. */
static void test_option_sae(void **state)
{
    grip_mf_params p;
    grip_mf_params q;
    int i;
    (void)state;
    asymmetric_params(&p);
    q = p;
    q.options = GRIP_MF_OPT_SAE;
    for (i = 0; i <= 20; i++) {
        double a = -0.5 + 0.05 * i;
        assert_same(evc(&q, 0.05, a, 0.03, -FNOM), evc(&p, 0.05, -a, 0.03, FNOM), 1, -1, -1);
        assert_same(evp(&q, 0.05, a, 0.03, -FNOM), evp(&p, 0.05, -a, 0.03, FNOM), 1, -1, -1);
    }
    /* a normal tyre has a negative cornering stiffness in both systems */
    assert_true(evp(&p, 0.0, 0.05, 0.0, FNOM).fy < -1000.0);
    assert_true(evp(&q, 0.0, 0.05, 0.0, -FNOM).fy < -1000.0);
    /* Fz > 0 is a tyre off the ground in SAE */
    check_zero(evc(&q, 0.05, 0.1, 0.0, FNOM), GRIP_OK);
    assert_no_saturation();
}

/* GRIP_MF_OPT_BOOK: (1) at gamma = 0 and without shifts the book's alpha* =
 * tan(alpha) is the only difference in Fy0: Fy0_book(alpha) =
 * Fy0_mftyre(tan alpha), and Fx0 is unchanged (A_mu only acts on SVx = 0);
 * (2) |gamma*| in Dt makes the book's Mz0 even in camber where MF-Tyre's
 * QDZ3 gamma does not. Tolerance (1): float 2e-6 Fz, fixed 4 LSB + the
 * slope times the Q15.16 step of tan(alpha). */
static void test_option_book(void **state)
{
    grip_mf_params p;
    grip_mf_params q;
    int i;
    double worst = 0.0;
    (void)state;
    symmetric_params(&p);
    q = p;
    q.options = GRIP_MF_OPT_BOOK;
    for (i = 0; i <= 20; i++) {
        double a = -1.0 + 0.1 * i;
        res_t b = evp(&q, 0.1, a, 0.0, FNOM);
        res_t m = evp(&p, 0.1, tan(a), 0.0, FNOM);
        double tol = IS_FIXED ? 4.0 * LSB_N + 15.0 * FNOM * 4.0 / 65536.0 : 2e-6 * FNOM;
        assert_int_equal(b.st, GRIP_OK);
        if (fabs(b.fy - m.fy) > tol || fabs(b.fx - m.fx) > tol) {
            fail_msg("book vs MF-Tyre at alpha=%g: Fy %.9g vs %.9g, Fx %.9g vs %.9g", a, b.fy, m.fy, b.fx, m.fx);
        }
        if (fabs(b.fy - m.fy) / tol > worst) worst = fabs(b.fy - m.fy) / tol;
    }
    printf("# book Fy0(alpha) vs MF-Tyre Fy0(tan alpha): worst |diff| / tolerance = %.3f\n", worst);

    /* camber: only QDZ3 acts on Mz0 */
    p.pky6 = 0;
    p.qdz8 = 0;
    p.qdz3 = to_qs(0.5);
    q = p;
    q.options = GRIP_MF_OPT_BOOK;
    for (i = 1; i <= 10; i++) {
        double a = 0.03 * i;
        res_t bp = evp(&q, 0.0, a, 0.1, FNOM);
        res_t bm = evp(&q, 0.0, a, -0.1, FNOM);
        res_t mp = evp(&p, 0.0, a, 0.1, FNOM);
        res_t mm = evp(&p, 0.0, a, -0.1, FNOM);
        assert_true(fabs(bp.mz - bm.mz) <= (IS_FIXED ? 2.0 * LSB_N * R0 : 1e-5 * fabs(bp.mz) + 1e-6));
        assert_true(fabs(mp.mz - mm.mz) > 0.05 * fabs(mp.mz));   /* (1 + 0.05) vs (1 - 0.05): 10 % apart */
    }
    assert_no_saturation();
}

/* GRIP_MF_OPT_MZ52_SVYK_CAMBER: only the MF 5.2 combined Mz changes (its
 * Fy' = Fy - SVyk takes the cambered mu_y instead of mu_y at gamma = 0).
 * Exact: Fx, Fy, the pure outputs and, at gamma = 0 (mu_y(gamma) = mu_y(0)),
 * Mz are bit for bit the same; MF 6.x does not change at all. */
static void test_option_mz52_svyk_camber(void **state)
{
    grip_mf_params p;
    grip_mf_params q;
    int i;
    int differ = 0;
    (void)state;
    asymmetric_params(&p);
    p.fittyp = 6;
    p.pdy3 = to_qs(3.0);
    q = p;
    q.options = GRIP_MF_OPT_MZ52_SVYK_CAMBER;
    for (i = 0; i <= 20; i++) {
        double k = -0.5 + 0.05 * i;
        res_t a = evc(&p, k, 0.1, 0.1, FNOM);
        res_t b = evc(&q, k, 0.1, 0.1, FNOM);
        assert_int_equal(a.st, b.st);
        assert_true(a.fx == b.fx && a.fy == b.fy);
        differ += (a.mz != b.mz);
        assert_same(evc(&q, k, 0.1, 0.0, FNOM), evc(&p, k, 0.1, 0.0, FNOM), 1, 1, 1);
        assert_same(evp(&q, k, 0.1, 0.1, FNOM), evp(&p, k, 0.1, 0.1, FNOM), 1, 1, 1);
    }
    assert_true(differ >= 18);   /* all but kappa ~ 0, where SVyk = 0 */
    p.fittyp = 61;
    q.fittyp = 61;
    for (i = 0; i <= 20; i++) {
        double k = -0.5 + 0.05 * i;
        assert_same(evc(&q, k, 0.1, 0.1, FNOM), evc(&p, k, 0.1, 0.1, FNOM), 1, 1, 1);
    }
    assert_no_saturation();
}

/* Inflation pressure: p <= 0 means INFLPRES; p outside [0.5, 2] NOMPRES is
 * clamped. Exact. */
static void test_pressure_input(void **state)
{
    grip_mf_params p;
    res_t a;
    res_t b;
    (void)state;
    asymmetric_params(&p);
    p.inflpres = to_ql(250000.0);
    a = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, 0.0, V_TEST);
    b = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, 250000.0, V_TEST);
    assert_same(a, b, 1, 1, 1);
    b = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, PNOM, V_TEST);
    assert_true(fabs(a.fx - b.fx) > 1.0);                /* the pressure terms act */
    a = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, 10.0 * PNOM, V_TEST);
    b = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, (1.0 + GRIP_MF_DPI_MAX) * PNOM, V_TEST);
    assert_int_equal(a.st, GRIP_WARN_CLAMPED);
    assert_true(a.fx == b.fx && a.fy == b.fy && a.mz == b.mz);
    a = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, 0.1 * PNOM, V_TEST);
    b = ev(&p, 1, 0.1, 0.1, 0.02, FNOM, (1.0 + GRIP_MF_DPI_MIN) * PNOM, V_TEST);
    assert_int_equal(a.st, GRIP_WARN_CLAMPED);
    assert_true(a.fx == b.fx && a.fy == b.fy && a.mz == b.mz);
    assert_no_saturation();
}

/* LMUV: friction decays with the slip speed, LMU* = LMU / (1 + LMUV Vs / V0)
 * with Vs = |Vx| sqrt(kappa^2 + tan^2 alpha) (4.E7). With Cx = 1 and Ex = 0,
 * Fx0 = Dx Bx k / sqrt(1 + (Bx k)^2) with Dx = PDX1 LMUX* Fz and
 * Bx = PKX1 / (PDX1 LMUX*), computed here directly. With LMUV = 0 (the
 * default) the speed has no effect above VXLOW. Tolerance: float 1e-5
 * relative, fixed 2e-4 relative. */
static void test_slip_speed_friction(void **state)
{
    grip_mf_params p;
    res_t a;
    res_t b;
    const double speeds[] = { 5.0, 10.0, 20.0, 40.0 };
    size_t i;
    err_stats st;
    (void)state;
    symmetric_params(&p);
    p.pcx1 = to_qs(1.0);
    a = ev(&p, 0, 1.0, 0.0, 0.0, FNOM, PNOM, 10.0);
    b = ev(&p, 0, 1.0, 0.0, 0.0, FNOM, PNOM, 20.0);
    assert_true(a.fx == b.fx);
    p.lmuv = to_qs(0.5);
    assert_int_equal(grip_mf_check_params(&p), GRIP_OK);
    err_init(&st, "Fx0 with LMUV = 0.5", 1.0);
    for (i = 0; i < sizeof(speeds) / sizeof(speeds[0]); i++) {
        double k = 0.3;
        double lam = 1.0 / (1.0 + 0.5 * speeds[i] * k / V_TEST);
        double dx = lam * FNOM;
        double bx = 16.0 / lam;
        double want = dx * bx * k / sqrt(1.0 + bx * bx * k * k);
        a = ev(&p, 0, k, 0.0, 0.0, FNOM, PNOM, speeds[i]);
        err_add(&st, a.fx / want, 1.0, speeds[i], want, a.fx);
    }
    err_print(&st, "(relative)");
    assert_true(st.max_abs <= (IS_FIXED ? 2e-4 : 1e-5));
    assert_no_saturation();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_fx0_slope_is_bcd, setup),
        cmocka_unit_test_setup(test_fy0_slope_is_bcd, setup),
        cmocka_unit_test_setup(test_peak_is_d, setup),
        cmocka_unit_test_setup(test_odd_symmetry, setup),
        cmocka_unit_test_setup(test_combined_within_envelope, setup),
        cmocka_unit_test_setup(test_combined_reduces_force, setup),
        cmocka_unit_test_setup(test_edge_inputs, setup),
        cmocka_unit_test_setup(test_random_inputs_stay_finite, setup),
        cmocka_unit_test_setup(test_invalid_params, setup),
        cmocka_unit_test_setup(test_null_pointers, setup),
#if !IS_FIXED
        cmocka_unit_test_setup(test_nonfinite_inputs, setup),
#endif
        cmocka_unit_test_setup(test_option_kappa_brake, setup),
        cmocka_unit_test_setup(test_option_mirror, setup),
        cmocka_unit_test_setup(test_option_tyreside, setup),
        cmocka_unit_test_setup(test_option_sae, setup),
        cmocka_unit_test_setup(test_option_book, setup),
        cmocka_unit_test_setup(test_option_mz52_svyk_camber, setup),
        cmocka_unit_test_setup(test_pressure_input, setup),
        cmocka_unit_test_setup(test_slip_speed_friction, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
