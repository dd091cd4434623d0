/*
 * mf_lanes.c - the prepared Magic Formula over blocks of GRIP_MF_LANES_N
 * points at once, for the float build (grip_mf_eval_prepared_lanes,
 * grip_mf_eval_pure_prepared_lanes; grip_mf_batch.h).
 *
 * Why: one evaluation is one long chain of dependent operations with ~40
 * transcendental functions; the same chain for 8 points side by side is 8
 * independent chains, which the compiler turns into SIMD instructions (4
 * floats per SSE2 register on x86-64, the default build) when every step is
 * a loop over the lanes without a branch and without a call. So:
 *  - the points of a block are held as structure of arrays (one array of
 *    GRIP_MF_LANES_N floats per input);
 *  - the equations are those of mf_eval.c's prepared path (mf_combined,
 *    mf_pure_eval with a prepared set, the MF-Tyre forms), operation for
 *    operation in the same order, written once more here as one body per
 *    lane (mfl_point) with selections (?:) where mf_eval.c branches;
 *  - the functions are grip's float kernels (f32_kernels.h), in lane form
 *    below: the same operations, with selections where the kernels index a
 *    table, and without their libm fallbacks: an argument outside a
 *    kernel's own range marks the lane;
 *  - the per-point checks are masks: a non-finite input gives that point
 *    GRIP_ERR_INPUT and zero outputs, a clamp GRIP_WARN_CLAMPED, Fz <= 0
 *    zero outputs and GRIP_OK, as grip_mf_eval_prepared; a marked lane, or
 *    a lane whose result is not finite, is evaluated again by
 *    grip_mf_eval_prepared itself (whose status then says why);
 *  - the last block is padded with copies of its first point (their
 *    results are dropped), so that every block runs the same code.
 *
 * This is a second implementation of the prepared evaluation, kept in step
 * with mf_eval.c by tests/unit/test_mf_lanes.c: with GRIP_FLOAT_KERNELS=2
 * (the scalar path on the same kernels) every output is bit-identical to
 * grip_mf_eval_prepared's over the golden vectors of every shared .tir file
 * and a grid of operating points; at the default level (libm) it stays
 * within the kernels' accuracy of it and within the golden tolerance of
 * the float64 reference (docs/magic-formula-c.md section 7.2).
 *
 * Vectorization needs two flags for this file alone (the Makefile's
 * LANE_CFLAGS, the Python binding's FILE_CFLAGS in tools/grip/_build.py):
 * -fno-math-errno (sqrtf as one instruction: its arguments here are >= 1
 * or selected away, errno is never read) and -fno-trapping-math (the
 * selections may compute both sides; no floating-point exception is
 * looked at anywhere). Neither changes a result. gcc 12 -O2
 * -fopt-info-vec reports the lane loop of each form "vectorized using 16
 * byte vectors"; without the flags the code is the same, only scalar.
 * Written so that gcc's if-conversion succeeds: & and | instead of && and
 * ||, the set's values loaded outside the selections, and the range
 * checks, clamps and statuses as numbers (see mfl_range).
 *
 * Sets the lane form does not cover (GRIP_MF_OPT_BOOK) and builds without
 * it (the fixed build, GRIP_MF_LANES 0) take grip_mf_eval_prepared_batch's
 * loop: the same results as it, bit for bit.
 */
#include "mf_internal.h"
#include "grip/grip_mf_batch.h"

#if GRIP_MF_LANES

#include <float.h>
#include "f32_kernels.h" /* float build only: inside the lane selection #if */

#define MFL_N GRIP_MF_LANES_N

/* clang's cost model declines the lane loop (clang 14: "vectorization is
 * not beneficial", and the scalar lane loop is then slower than the scalar
 * path): asked for explicitly. gcc needs no hint. */
#if defined(__clang__)
#define MFL_VECTORIZE _Pragma("clang loop vectorize(enable)")
#else
#define MFL_VECTORIZE
#endif

/* ------------------------------------------------------- lane kernels */

/* grip_kf_atan without its table: the same operations and bits. */
static MF_ALWAYS_INLINE float mfl_atan(float x)
{
    float a = fabsf(x);
    int big = a > 1.0f;
    float inv = 1.0f / (a + GRIP_KF_FLT_MIN);
    float t = (inv < a) ? inv : a;
    float p = grip_kf_atan01(t);
    float hi = big ? GRIP_KF_PIO2_HI : 0.0f;
    float lo = big ? GRIP_KF_PIO2_LO : 0.0f;
    float s = big ? -1.0f : 1.0f;
    return copysignf(hi + (s * p + lo), x);
}

/* grip_kf_atan2 without its table and branches: the same bits where x and
 * y are finite; an infinite or NaN argument marks the lane (*bad, see
 * mfl_range below), whose result is then not used. */
static MF_ALWAYS_INLINE void mfl_range(float *bad, float t, float x);

static MF_ALWAYS_INLINE float mfl_atan2(float y, float x, float *bad)
{
    float ax = fabsf(x);
    float ay = fabsf(y);
    int sw = ay > ax;                        /* octant + 1 */
    int neg = copysignf(1.0f, x) < 0.0f;     /* octant + 2: x < 0 or x = -0 */
    float mx = sw ? ay : ax;
    float mn = sw ? ax : ay;
    float t = mn / ((mx > 0.0f) ? mx : 1.0f);
    float p;
    float hi;
    float lo;
    float s;
    mfl_range(bad, -1.0f, x + y);
    p = grip_kf_atan01(t);
    hi = neg ? (sw ? GRIP_KF_PIO2_HI : GRIP_KF_PI_HI) : (sw ? GRIP_KF_PIO2_HI : 0.0f);
    lo = neg ? (sw ? GRIP_KF_PIO2_LO : GRIP_KF_PI_LO) : (sw ? GRIP_KF_PIO2_LO : 0.0f);
    s = (sw != neg) ? -1.0f : 1.0f;
    return copysignf(hi + (s * p + lo), y);
}

/* grip_kf_sin_poly with the sign selected, not looked up. */
static MF_ALWAYS_INLINE float mfl_sin_poly(float x, float mf, int neg)
{
    float r = (((x - mf * GRIP_KF_PIO2_1) - mf * GRIP_KF_PIO2_2) - mf * GRIP_KF_PIO2_3) - mf * GRIP_KF_PIO2_4;
    float z = r * r;
    float p = (GRIP_KF_SIN_1 * z + GRIP_KF_SIN_0) + (z * z) * (GRIP_KF_SIN_3 * z + GRIP_KF_SIN_2);
    r = r * (neg ? -1.0f : 1.0f);
    return (z == 0.0f) ? r : (r + (r * z) * p);
}

/* The range check of a lane: *bad, starting at -1, becomes > 0 when an
 * argument is outside its kernel's range, NaN when one is not finite; the
 * lane is then evaluated again (mfl_point). A number, not a flag: gcc 12
 * does not vectorize the selections of flags that its jump threading makes
 * of flags set under other selections. t: how far x is outside (<= 0:
 * inside); x - x is 0, or NaN for an infinite or NaN x. */
static MF_ALWAYS_INLINE void mfl_range(float *bad, float t, float x)
{
    *bad = ((t > *bad) ? t : *bad) + (x - x);
}

/* grip_kf_sin, grip_kf_cos for |x| <= GRIP_KF_TRIG_MAX (else *bad, and
 * the result is not used). */
static MF_ALWAYS_INLINE float mfl_sin(float x, float *bad)
{
    float xs = (fabsf(x) <= GRIP_KF_TRIG_MAX) ? x : 0.0f;
    float mf = (xs * GRIP_KF_2_OVER_PI + GRIP_KF_SHIFTER2) - GRIP_KF_SHIFTER2;
    int neg = (int)(((uint32_t)(int32_t)mf >> 1) & 1u);
    mfl_range(bad, fabsf(x) - GRIP_KF_TRIG_MAX, x);
    return mfl_sin_poly(xs, mf, neg);
}

static MF_ALWAYS_INLINE float mfl_cos(float x, float *bad)
{
    float xs = (fabsf(x) <= GRIP_KF_TRIG_MAX) ? x : 0.0f;
    float mf = (((xs * GRIP_KF_2_OVER_PI - 1.0f) + GRIP_KF_SHIFTER2) - GRIP_KF_SHIFTER2) + 1.0f;
    int neg = (int)((((uint32_t)(int32_t)mf >> 1) & 1u) ^ 1u);
    mfl_range(bad, fabsf(x) - GRIP_KF_TRIG_MAX, x);
    return mfl_sin_poly(xs, mf, neg);
}

/* grip_kf_exp for GRIP_KF_EXP_MIN <= x <= GRIP_KF_EXP_MAX (else *bad). */
static MF_ALWAYS_INLINE float mfl_exp(float x, float *bad)
{
    float lo = GRIP_KF_EXP_MIN - x;
    float hi = x - GRIP_KF_EXP_MAX;
    float xs = ((lo <= 0.0f) & (hi <= 0.0f)) ? x : 0.0f;
    float kf = (xs * GRIP_KF_LOG2E + GRIP_KF_SHIFTER) - GRIP_KF_SHIFTER;
    int32_t k = (int32_t)kf;
    float r = (xs - kf * GRIP_KF_LN2_HI) - kf * GRIP_KF_LN2_LO;
    float r2 = r * r;
    float p = (GRIP_KF_EXP_1 * r + GRIP_KF_EXP_0) + r2 * ((GRIP_KF_EXP_3 * r + GRIP_KF_EXP_2) + r2 * GRIP_KF_EXP_4);
    mfl_range(bad, (lo > hi) ? lo : hi, x);
    return (1.0f + (r + r * (r * p))) * grip_kf_float((uint32_t)(k + 127) << 23);
}

/* ------------------------------------- mf_internal.h's helpers, lanes */

/* mf_div_lim: every case formed, one selected */
static MF_ALWAYS_INLINE float mfl_div_lim(float a, float b, float lim)
{
    float aa = fabsf(a);
    int sat = fabsf(b) <= aa / lim;
    int opp = (a < 0.0f) != (b < 0.0f);
    float q = a / b;
    float r = sat ? (opp ? -lim : lim) : q;
    return (aa == 0.0f) ? 0.0f : r;
}

/* r_sqrt */
static MF_ALWAYS_INLINE float mfl_sqrt(float a)
{
    float s = sqrtf(a);   /* NaN for a < 0: not selected */
    return (a > 0.0f) ? s : 0.0f;
}

static MF_ALWAYS_INLINE float mfl_hypot(float a, float b)
{
    float x = fabsf(a);
    float y = fabsf(b);
    int sw = x < y;
    float hi = sw ? y : x;
    float lo = sw ? x : y;
    float t = lo / hi;
    float r = mfl_sqrt(1.0f + t * t) * hi;
    return (hi == 0.0f) ? 0.0f : r;
}

static MF_ALWAYS_INLINE float mfl_cos_atan(float a)
{
    return 1.0f / sqrtf(1.0f + a * a);
}

static MF_ALWAYS_INLINE float mfl_min(float a, float b)
{
    return (a < b) ? a : b;
}

static MF_ALWAYS_INLINE float mfl_max(float a, float b)
{
    return (a > b) ? a : b;
}

/* mf_shape, mf_sin_curve, mf_cos_curve */
static MF_ALWAYS_INLINE float mfl_shape(float b, float c, float e, float x)
{
    float bx = b * x;
    float arg = bx - e * (bx - mfl_atan(bx));
    return c * mfl_atan(arg);
}

static MF_ALWAYS_INLINE float mfl_sin_curve(float b, float c, float d, float e, float x, float *bad)
{
    return d * mfl_sin(mfl_shape(b, c, e, x), bad);
}

static MF_ALWAYS_INLINE float mfl_cos_curve(float b, float c, float e, float x, float *bad)
{
    return mfl_cos(mfl_shape(b, c, e, x), bad);
}

/* ------------------------------------------------- one call's constants */

/* What a call decides once from the prepared set (mf_prepare's k paths). */
/* The decisions are numbers here, not flags: a selection on a flag of the
 * call would be a mask made from a scalar in every lane, which gcc 12 does
 * not vectorize; a sign change is a product with +-1 (exact, the same bits
 * as the negation), and the constants make the lane's own comparisons come
 * out as the scalar path's tests do. */
typedef struct {
    float s_alpha;       /* -1: SAE and mirror (twice: +1)                 */
    float s_fz;          /* -1: SAE                                        */
    float s_kappa;       /* -1: GRIP_MF_OPT_KAPPA_BRAKE                    */
    float s_gamma;       /* -1: mirror                                     */
    float s_out;         /* Fy, Mz: -1 when mirrored or SAE, not both      */
    float dpi0_clamp;    /* 1: the default pressure is clamped, else -1     */
    float plo;           /* the pressure's domain (mf_dpi), or one that     */
    float phi;           /* nothing leaves without NOMPRES (MF 5.2)        */
    float nom_sub;       /* NOMPRES, 0 without                             */
    float nom_div;       /* NOMPRES, 1 without                             */
    float dpi_scale;     /* 1, 0 without                                   */
    float vxlow;         /* VXLOW, -1 without the low-speed model          */
    float vxlow_div;     /* VXLOW, or 1 (not used) without it              */
    float pky5;          /* MF6_ONLY coefficients                          */
    float pey5;
    float rbx3;
    float rby4;
    float qdz10;
    float qdz11;
    float kyc;           /* MF_KYC, MF_KZC                                 */
    float kzc;
} mfl_const;

/* Results of one lane. */
typedef struct {
    float fx;
    float fy;
    float mz;
    int st;
    int redo;
} mfl_res;

/* ------------------------------------------------------ one lane's body */

/* The pure lateral force at inclination g (mf_lat_body, no turn slip,
 * emax = 1). */
typedef struct {
    float fy0;
    float muy;
    float kya;
    float shy;
    float svy;
    float by;
    float cy;
} mfl_lat;

static MF_ALWAYS_INLINE void mfl_lat_body(const grip_mf_params *p, const mfl_const *c, float dfz, float fzp,
                                          float alpha, float smooth, float lmuy_s, float lmuy_p, float kyb,
                                          float kyd, float mub, float svb0, float shb, float eyb, float dp_py_g,
                                          float g, int mf52, float *bad, mfl_lat *o)
{
    float g2 = g * g;
    float den = (p->pky2 + c->pky5 * g2) * kyd;
    float at = mfl_atan2(fzp, den, bad);
    float kya;
    float muy;
    float svyg;
    float svy;
    float shy;
    float ay;
    float ey;
    float by;
    float cy = p->pcy1 * p->lcy;
    at = (den < 0.0f) ? at - MF_PI : at;                                         /* mf_atan_ratio */
    kya = ((kyb * (1.0f - p->pky3 * fabsf(g))) * mfl_div_lim(mfl_sin(p->pky4 * at, bad), fzp, MF_LIM_B)) * p->lky;
    muy = (mub * (1.0f - p->pdy3 * g2)) * lmuy_s;
    svyg = (((p->pvy3 + p->pvy4 * dfz) * g) * c->kyc) * lmuy_p;
    svy = svb0 + svyg;
    if (mf52) {
        shy = shb + p->phy3 * g;
    } else {
        float kyg0 = ((p->pky6 + p->pky7 * dfz) * dp_py_g) * c->kyc;
        shy = shb + mfl_div_lim(kyg0 * g - svyg, kya, MF_LIM_SHIFT);
    }
    shy = shy * smooth;
    svy = svy * smooth;
    ay = alpha + shy;
    ey = (eyb * ((1.0f + c->pey5 * g2) - (p->pey3 + p->pey4 * g) * ((ay < 0.0f) ? -1.0f : 1.0f))) * p->ley;
    ey = mfl_min(ey, 1.0f);
    by = mfl_div_lim(kya, cy * muy, MF_LIM_B);
    o->fy0 = mfl_sin_curve(by, cy, muy, ey, ay, bad) + svy;
    o->muy = muy;
    o->kya = kya;
    o->shy = shy;
    o->svy = svy;
    o->by = by;
    o->cy = cy;
}

/* mf_gyk_body (emax = 1) */
static MF_ALWAYS_INLINE float mfl_gyk(const grip_mf_params *p, const mfl_const *c, float dfz, float kappa,
                                      float alpha, float g, float *bad)
{
    float shyk = p->rhy1 + p->rhy2 * dfz;
    float eyk = mfl_min(p->rey1 + p->rey2 * dfz, 1.0f);
    float byk = ((p->rby1 + c->rby4 * (g * g)) * mfl_cos_atan(p->rby2 * (alpha - p->rby3))) * p->lyka;
    float ks = kappa + shyk;
    return mfl_div_lim(mfl_cos_curve(byk, p->rcy1, eyk, ks, bad), mfl_cos_curve(byk, p->rcy1, eyk, shyk, bad),
                       MF_LIM_G);
}

/* mf_alpha_eq, MF-Tyre form */
static MF_ALWAYS_INLINE float mfl_alpha_eq(float a, float kappa, float kxk, float kya, float *bad)
{
    float ca = mfl_cos(a, bad);
    float num = mfl_hypot(kya * mfl_sin(a, bad), (kxk * kappa) * ca);
    return mfl_atan2(num, fabsf(kya * ca), bad);
}

/* One point: mf_prepare, mf_long_pure, mf_lat_common_init, mf_lat_body,
 * mf_trail_body, then mf_combined's or mf_pure_eval's rest and mf_finish,
 * for a prepared set without GRIP_MF_OPT_BOOK. */
static MF_ALWAYS_INLINE void mfl_point(const grip_mf_prepared *k, const mfl_const *c, float kappa, float alpha,
                                       float gamma, float fz, float vx, float pr, int mf52, int pure,
                                       mfl_res *res)
{
    const grip_mf_params *p = k->p;
    /* the set's values that only some lanes select, loaded for all (a load
     * in one arm of a selection would be a branch) */
    const float dpi0 = k->dpi0;
    const float fz_max = k->fz_max;
    const float dpi0_clamp = c->dpi0_clamp;
    float bad = -1.0f;           /* a kernel argument outside its range: > 0 or NaN (mfl_range) */
    /* > 0 when an input was clamped: how far the farthest was outside (a
     * number, as bad) */
    float clamped = -1.0f;
    /* x - x is 0 for a finite x, NaN otherwise */
    int badin = !(((((kappa - kappa) + (alpha - alpha)) + ((gamma - gamma) + (fz - fz))) +
                   ((vx - vx) + (pr - pr))) == 0.0f);
    int zero;
    int low;
    int red;
    float lim;
    float fzn;
    float fzp;
    float dfz;
    float dpi;
    float sa;
    float ca;
    float avx;
    float smooth;
    float cosa;
    float lmux_s;
    float lmuy_s;
    float lmux_p;
    float lmuy_p;
    float ky_mu;
    float gmux;
    float gx;
    float gy;
    float gz;
    float dp[GRIP_MF_DP_N];
    /* non-finite inputs: ERR_INPUT; the lane computes on, its results are
     * dropped (the kernels take any float: an argument outside their range
     * is replaced before it is converted to an integer) */

    /* sign conventions -> ISO-W */
    alpha = alpha * c->s_alpha;
    fz = fz * c->s_fz;
    kappa = kappa * c->s_kappa;
    gamma = gamma * c->s_gamma;
    zero = !(fz > 0.0f);

    /* the domain (mf_clamp_sym) */
    lim = (float)GRIP_MF_KAPPA_MAX;
    clamped = mfl_max(clamped, fabsf(kappa) - lim);
    kappa = (kappa > lim) ? lim : ((kappa < -lim) ? -lim : kappa);
    lim = (float)GRIP_MF_ALPHA_MAX;
    clamped = mfl_max(clamped, fabsf(alpha) - lim);
    alpha = (alpha > lim) ? lim : ((alpha < -lim) ? -lim : alpha);
    lim = (float)GRIP_MF_GAMMA_MAX;
    clamped = mfl_max(clamped, fabsf(gamma) - lim);
    gamma = (gamma > lim) ? lim : ((gamma < -lim) ? -lim : gamma);
    lim = (float)GRIP_MF_VX_MAX;
    clamped = mfl_max(clamped, fabsf(vx) - lim);
    vx = (vx > lim) ? lim : ((vx < -lim) ? -lim : vx);
    clamped = mfl_max(clamped, fz - fz_max);     /* <= 0 where zero (fz_max > 0) */
    fz = zero ? 0.0f : ((fz > fz_max) ? fz_max : fz);

    fzn = fz / p->fnomin;
    fzp = fzn / p->lfzo;                                                         /* 4.E1 */
    dfz = fzp - 1.0f;                                                            /* 4.E2a */
    /* dpi: the prepared default (p <= 0), else mf_dpi */
    {
        float plo = c->plo;
        float phi = c->phi;
        float q = ((pr - c->nom_sub) / c->nom_div) * c->dpi_scale;                /* 4.E2b */
        float d = (pr < plo) ? (float)GRIP_MF_DPI_MIN : ((pr > phi) ? (float)GRIP_MF_DPI_MAX : q);
        int given = pr > 0.0f;
        clamped = mfl_max(clamped, given ? mfl_max(plo - pr, pr - phi) : dpi0_clamp);
        dpi = given ? d : dpi0;
    }
    dp[MF_DP_PX_MU] = mf_dp_form(p, dpi, MF_DP_PX_MU);
    dp[MF_DP_PX_K] = mf_dp_form(p, dpi, MF_DP_PX_K);
    dp[MF_DP_KYB] = mf_dp_form(p, dpi, MF_DP_KYB);
    dp[MF_DP_KYD] = mf_dp_form(p, dpi, MF_DP_KYD);
    dp[MF_DP_PY_MU] = mf_dp_form(p, dpi, MF_DP_PY_MU);
    dp[MF_DP_PY_G] = mf_dp_form(p, dpi, MF_DP_PY_G);
    dp[MF_DP_PZ_T] = mf_dp_form(p, dpi, MF_DP_PZ_T);
    dp[MF_DP_PZ_R] = mf_dp_form(p, dpi, MF_DP_PZ_R);

    /* low speed (mf_prepare) */
    smooth = 1.0f;
    sa = mfl_sin(alpha, &bad);
    ca = mfl_cos(alpha, &bad);
    avx = fabsf(vx);
    {
        float cc = fabsf(ca);
        float num = avx * (cc + fabsf(sa));
        float den = c->vxlow * cc;
        float q = num / den;
        float rl;
        float sm;
        low = avx <= c->vxlow;
        red = num < den;
        rl = (low ? avx : 0.0f) / c->vxlow_div;
        sm = 0.5f * (1.0f - mfl_cos(MF_PI * rl, &bad));
        kappa = low ? rl * kappa : kappa;
        smooth = low ? sm : smooth;
        alpha = red ? q * alpha : alpha;
    }
    /* the reduced angle's cosine (the same as above where not reduced; its
     * sine served LMUV > 0 only, which the lanes leave to the scalar path) */
    ca = mfl_cos(alpha, &bad);
    cosa = fabsf(ca);                                                            /* 4.E6 */

    /* LMUV = 0 (the lanes' sets): LMU*, LMU', LKY / LMUY* prepared */
    lmux_s = p->lmux;
    lmuy_s = p->lmuy;
    lmux_p = k->lmux_p;
    lmuy_p = k->lmuy_p;
    ky_mu = k->ky_mu;
    gmux = mf52 ? gamma * p->lgax : gamma;
    gx = mf52 ? gamma * p->lgax : gamma;
    gy = mf52 ? gamma * p->lgay : gamma;
    gz = mf52 ? gamma * p->lgaz : gamma;

    {
        /* Fx0 (mf_long_pure) */
        float shx = ((p->phx1 + p->phx2 * dfz) * p->lhx) * smooth;
        float kx = kappa + shx;
        float cx = p->pcx1 * p->lcx;
        float mux = (((p->pdx1 + p->pdx2 * dfz) * dp[MF_DP_PX_MU]) * (1.0f - p->pdx3 * (gmux * gmux))) * lmux_s;
        float sgn = (kx > 0.0f) ? 1.0f : ((kx < 0.0f) ? -1.0f : 0.0f);
        float ex = ((p->pex1 + (p->pex2 * dfz + p->pex3 * (dfz * dfz))) * (1.0f - p->pex4 * sgn)) * p->lex;
        float kxk = (((p->pkx1 + p->pkx2 * dfz) * mfl_exp(p->pkx3 * dfz, &bad)) * dp[MF_DP_PX_K]) * p->lkx;
        float bx = mfl_div_lim(kxk, cx * mux, MF_LIM_B);
        float svx = (((p->pvx1 + p->pvx2 * dfz) * p->lvx) * lmux_p) * smooth;
        float fx0;
        /* the common lateral factors (mf_lat_common_init) */
        float kyb = dp[MF_DP_KYB];
        float kyd = dp[MF_DP_KYD];
        float mub = (p->pdy1 + p->pdy2 * dfz) * dp[MF_DP_PY_MU];
        float svb = ((p->pvy1 + p->pvy2 * dfz) * p->lvy) * lmuy_p;
        float shb = (p->phy1 + p->phy2 * dfz) * p->lhy;
        float eyb = p->pey1 + p->pey2 * dfz;
        mfl_lat lat;
        mfl_lat lat0;
        /* trail coefficients (mf_trail_body, MF-Tyre) */
        float ga = fabsf(gz);
        float sht;
        float shf;
        float dt;
        float bt;
        float at;
        float ar;
        float ct = p->qcz1;
        float et;
        float br;
        float dr;
        float fx;
        float fy;
        float mz;
        float mref;
        ex = mfl_min(ex, 1.0f);
        fx0 = mfl_sin_curve(bx, cx, mux, ex, kx, &bad) + svx;
        mfl_lat_body(p, c, dfz, fzp, alpha, smooth, lmuy_s, lmuy_p, kyb, kyd, mub, svb, shb, eyb,
                     dp[MF_DP_PY_G], gy, mf52, &bad, &lat);
        if (!mf52) {
            /* Fy0 at gamma = 0 (MF 6.x's Mz; mf_lat_gamma0): equal to lat
             * where gy is 0 */
            mfl_lat_body(p, c, dfz, fzp, alpha, smooth, lmuy_s, lmuy_p, kyb, kyd, mub, svb, shb, eyb,
                         dp[MF_DP_PY_G], 0.0f, mf52, &bad, &lat0);
        } else {
            lat0 = lat;
        }
        sht = (p->qhz1 + p->qhz2 * dfz) + (p->qhz3 + p->qhz4 * dfz) * gz;
        shf = lat.shy + mfl_div_lim(lat.svy, lat.kya, MF_LIM_SHIFT);
        dt = (((fzp * (p->qdz1 + p->qdz2 * dfz)) * dp[MF_DP_PZ_T]) * (1.0f + (p->qdz3 * gz + p->qdz4 * (gz * gz)))) *
             p->ltr;
        bt = ((p->qbz1 + (p->qbz2 * dfz + p->qbz3 * (dfz * dfz))) * (1.0f + (p->qbz4 * gz + p->qbz5 * ga))) * ky_mu;
        at = alpha + sht;                                                        /* 4.E34 */
        ar = alpha + shf;                                                        /* 4.E37 */
        et = (p->qez1 + (p->qez2 * dfz + p->qez3 * (dfz * dfz))) *
             (1.0f + ((p->qez4 + p->qez5 * gz) * MF_2_OVER_PI) * mfl_atan((bt * ct) * at));
        et = mfl_min(et, 1.0f);
        br = p->qbz9 * ky_mu + (p->qbz10 * lat.by) * lat.cy;
        dr = (((p->qdz6 + p->qdz7 * dfz) * p->lres) +
              ((((p->qdz8 + p->qdz9 * dfz) * dp[MF_DP_PZ_R]) + (c->qdz10 + c->qdz11 * dfz) * ga) * gz) * c->kzc) *
             lmuy_s;
        dr = dr * cosa;
        if (pure) {
            /* mf_pure_eval */
            float fy_ref = mf52 ? lat.fy0 : lat0.fy0;
            float t0 = ((dt * mfl_cos_curve(bt, ct, et, at, &bad)) * cosa) * p->lfzo;
            mz = ((dr * mfl_cos_atan(br * ar)) * cosa) - t0 * fy_ref;
            mz = mz * smooth;
            fx = fx0;
            fy = lat.fy0;
        } else {
            float bxa = ((p->rbx1 + c->rbx3 * (gx * gx)) * mfl_cos_atan(p->rbx2 * kappa)) * p->lxal;
            float exa = mfl_min(p->rex1 + p->rex2 * dfz, 1.0f);
            float as = alpha + p->rhx1;
            float gxa = mfl_div_lim(mfl_cos_curve(bxa, p->rcx1, exa, as, &bad),
                                    mfl_cos_curve(bxa, p->rcx1, exa, p->rhx1, &bad), MF_LIM_G);
            float dvy = (p->rvy1 + p->rvy2 * dfz) + p->rvy3 * gy;
            float dva = mfl_cos_atan(p->rvy4 * alpha);
            float svk = mfl_sin(p->rvy5 * mfl_atan(p->rvy6 * kappa), &bad);
            float dvyk = (lat.muy * dvy) * dva;
            float svyk = ((dvyk * svk) * p->lvyka) * smooth;
            float gyk = mfl_gyk(p, c, dfz, kappa, alpha, gy, &bad);
            float svyk_mz = ((((mub * lmuy_s) * dvy) * dva) * svk * p->lvyka) * smooth;
            float ar_eq;
            float at_eq;
            float sarm;
            float mzr;
            float t;
            float fy_prime;
            fx = gxa * fx0;
            fy = gyk * lat.fy0 + svyk;
            ar_eq = mfl_alpha_eq(ar, kappa, kxk, lat.kya, &bad);
            at_eq = mfl_alpha_eq(at, kappa, kxk, lat.kya, &bad);
            sarm = ((p->ssz1 + p->ssz2 * (fy * fzn)) + (p->ssz3 + p->ssz4 * dfz) * gz) * p->ls;
            mzr = dr * mfl_cos_atan(br * ar_eq);
            t = ((dt * mfl_cos_curve(bt, ct, et, at_eq, &bad)) * cosa) * p->lfzo;
            t = t * smooth;
            mzr = mzr * smooth;
            fy_prime = mf52 ? fy - svyk_mz : gyk * lat0.fy0;
            mz = (mzr - t * fy_prime) + sarm * fx;
        }
        /* mf_finish */
        mref = p->unloaded_radius * fz;
        fx = fx * fz;
        fy = fy * fz;
        mz = mz * mref;
        fy = fy * c->s_out;
        mz = mz * c->s_out;
        {
            /* the status and the redo mark as numbers too (see bad) */
            float stf = (clamped > 0.0f) ? (float)GRIP_WARN_CLAMPED : (float)GRIP_OK;
            float rf = (bad <= 0.0f) ? 0.0f : 1.0f;
            rf = ((((fx - fx) + (fy - fy)) + (mz - mz)) == 0.0f) ? rf : 1.0f;   /* not finite */
            stf = zero ? (float)GRIP_OK : stf;
            rf = zero ? 0.0f : rf;
            fx = zero ? 0.0f : fx;
            fy = zero ? 0.0f : fy;
            mz = zero ? 0.0f : mz;
            stf = badin ? (float)GRIP_ERR_INPUT : stf;
            rf = badin ? 0.0f : rf;
            res->fx = badin ? 0.0f : fx;
            res->fy = badin ? 0.0f : fy;
            res->mz = badin ? 0.0f : mz;
            res->st = (int)stf;
            res->redo = (int)rf;
        }
    }
}

/* ------------------------------------------------------------- blocks */

/* Summary of the statuses seen so far: the first error wins, then a clamp
 * (as mf_batch.c's). */
static grip_status_t mfl_merge(grip_status_t sum, grip_status_t st)
{
    if (sum < 0) {
        return sum;
    }
    if ((st < 0) || (st == GRIP_WARN_CLAMPED)) {
        return st;
    }
    return sum;
}

/* Points in[0..m-1] (1 <= m <= MFL_N) into out, status: gathered into
 * lanes (lanes m.. copy point 0), evaluated lane by lane in one loop
 * without branches (the loop the compiler vectorizes), scattered back;
 * lanes to redo go through grip_mf_eval_prepared. Returns the summary. */
static MF_ALWAYS_INLINE grip_status_t mfl_block(const grip_mf_prepared *k, const mfl_const *c, uint32_t m,
                                                const grip_mf_input *in, grip_mf_output *out,
                                                grip_status_t *status, int mf52, int pure)
{
    float kap[MFL_N];
    float alp[MFL_N];
    float gam[MFL_N];
    float fzs[MFL_N];
    float vxs[MFL_N];
    float prs[MFL_N];
    float fx[MFL_N];
    float fy[MFL_N];
    float mz[MFL_N];
    int st[MFL_N];
    int redo[MFL_N];
    grip_status_t sum = GRIP_OK;
    uint32_t l;
    for (l = 0u; l < MFL_N; l++) {
        const grip_mf_input *x = &in[(l < m) ? l : 0u];
        kap[l] = x->kappa;
        alp[l] = x->alpha;
        gam[l] = x->gamma;
        fzs[l] = x->fz;
        vxs[l] = x->vx;
        prs[l] = x->p;
    }
    MFL_VECTORIZE
    for (l = 0u; l < MFL_N; l++) {
        mfl_res r;
        mfl_point(k, c, kap[l], alp[l], gam[l], fzs[l], vxs[l], prs[l], mf52, pure, &r);
        fx[l] = r.fx;
        fy[l] = r.fy;
        mz[l] = r.mz;
        st[l] = r.st;
        redo[l] = r.redo;
    }
    for (l = 0u; l < m; l++) {
        grip_status_t s = (grip_status_t)st[l];
        if (redo[l]) {
            s = pure ? grip_mf_eval_pure_prepared(k, &in[l], &out[l]) : grip_mf_eval_prepared(k, &in[l], &out[l]);
        } else {
            out[l].fx = fx[l];
            out[l].fy = fy[l];
            out[l].mz = mz[l];
        }
        if (status != NULL) {
            status[l] = s;
        }
        sum = mfl_merge(sum, s);
    }
    return sum;
}

/* Every block of in[0..n-1]. */
static MF_ALWAYS_INLINE grip_status_t mfl_run(const grip_mf_prepared *k, const mfl_const *c, uint32_t n,
                                              const grip_mf_input *in, grip_mf_output *out, grip_status_t *status,
                                              int mf52, int pure)
{
    grip_status_t sum = GRIP_OK;
    uint32_t b;
    for (b = 0u; b < n; b += MFL_N) {
        uint32_t m = ((n - b) < MFL_N) ? (n - b) : MFL_N;
        sum = mfl_merge(sum, mfl_block(k, c, m, &in[b], &out[b], (status != NULL) ? &status[b] : NULL, mf52, pure));
    }
    return sum;
}

/* One function per form, so that mf52 and pure are constants in each. */
static MF_NOINLINE grip_status_t mfl_run61(const grip_mf_prepared *k, const mfl_const *c, uint32_t n,
                                           const grip_mf_input *in, grip_mf_output *out, grip_status_t *status)
{
    return mfl_run(k, c, n, in, out, status, 0, 0);
}

static MF_NOINLINE grip_status_t mfl_run52(const grip_mf_prepared *k, const mfl_const *c, uint32_t n,
                                           const grip_mf_input *in, grip_mf_output *out, grip_status_t *status)
{
    return mfl_run(k, c, n, in, out, status, 1, 0);
}

static MF_NOINLINE grip_status_t mfl_run61_pure(const grip_mf_prepared *k, const mfl_const *c, uint32_t n,
                                                const grip_mf_input *in, grip_mf_output *out,
                                                grip_status_t *status)
{
    return mfl_run(k, c, n, in, out, status, 0, 1);
}

static MF_NOINLINE grip_status_t mfl_run52_pure(const grip_mf_prepared *k, const mfl_const *c, uint32_t n,
                                                const grip_mf_input *in, grip_mf_output *out,
                                                grip_status_t *status)
{
    return mfl_run(k, c, n, in, out, status, 1, 1);
}

static void mfl_const_init(const grip_mf_prepared *k, mfl_const *c)
{
    const grip_mf_params *p = k->p;
    int mf52 = (k->flags & MF_PF_MF52) != 0u;
    int sae = (k->flags & MF_PF_SAE) != 0u;
    int mirror = (k->flags & MF_PF_MIRROR) != 0u;
    int haspr = !mf52 && (p->nompres > 0.0f);
    c->s_alpha = (sae != mirror) ? -1.0f : 1.0f;
    c->s_fz = sae ? -1.0f : 1.0f;
    c->s_kappa = ((k->flags & MF_PF_KAPPA_BRAKE) != 0u) ? -1.0f : 1.0f;
    c->s_gamma = mirror ? -1.0f : 1.0f;
    c->s_out = (sae != mirror) ? -1.0f : 1.0f;
    c->dpi0_clamp = ((k->flags & MF_PF_DPI0_CLAMP) != 0u) ? 1.0f : -1.0f;
    c->plo = haspr ? (float)(1.0 + GRIP_MF_DPI_MIN) * p->nompres : -FLT_MAX;
    c->phi = haspr ? (float)(1.0 + GRIP_MF_DPI_MAX) * p->nompres : FLT_MAX;
    c->nom_sub = haspr ? p->nompres : 0.0f;
    c->nom_div = haspr ? p->nompres : 1.0f;
    c->dpi_scale = haspr ? 1.0f : 0.0f;
    c->vxlow = (p->vxlow > 0.0f) ? p->vxlow : -1.0f;
    c->vxlow_div = (p->vxlow > 0.0f) ? p->vxlow : 1.0f;
    c->pky5 = mf52 ? 0.0f : p->pky5;
    c->pey5 = mf52 ? 0.0f : p->pey5;
    c->rbx3 = mf52 ? 0.0f : p->rbx3;
    c->rby4 = mf52 ? 0.0f : p->rby4;
    c->qdz10 = mf52 ? 0.0f : p->qdz10;
    c->qdz11 = mf52 ? 0.0f : p->qdz11;
    c->kyc = mf52 ? 1.0f : p->lkyc;
    c->kzc = mf52 ? 1.0f : p->lkzc;
}

static grip_status_t mfl_eval(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                              grip_mf_output *out, grip_status_t *status, int pure)
{
    mfl_const c;
    int mf52;
    if (n == 0u) {
        return GRIP_OK;
    }
    if ((prep == NULL) || (in == NULL) || (out == NULL)) {
        return GRIP_ERR_NULL;
    }
    /* not prepared, or a form the lanes do not have: the scalar loop */
    if ((prep->p == NULL) || ((prep->flags & (MF_PF_BOOK | MF_PF_LMU_CONST)) != MF_PF_LMU_CONST) ||
        ((prep->options & GRIP_MF_OPT_MZ52_SVYK_CAMBER) != 0u)) {
        return mf_prepared_batch_scalar(prep, n, in, out, status, pure);
    }
    mfl_const_init(prep, &c);
    mf52 = (prep->flags & MF_PF_MF52) != 0u;
    if (pure) {
        return mf52 ? mfl_run52_pure(prep, &c, n, in, out, status) : mfl_run61_pure(prep, &c, n, in, out, status);
    }
    return mf52 ? mfl_run52(prep, &c, n, in, out, status) : mfl_run61(prep, &c, n, in, out, status);
}

grip_status_t grip_mf_eval_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                          grip_mf_output *out, grip_status_t *status)
{
    return mfl_eval(prep, n, in, out, status, 0);
}

grip_status_t grip_mf_eval_pure_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                               grip_mf_output *out, grip_status_t *status)
{
    return mfl_eval(prep, n, in, out, status, 1);
}

#else /* !GRIP_MF_LANES: the scalar loop */

grip_status_t grip_mf_eval_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                          grip_mf_output *out, grip_status_t *status)
{
    return mf_prepared_batch_scalar(prep, n, in, out, status, 0);
}

grip_status_t grip_mf_eval_pure_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                               grip_mf_output *out, grip_status_t *status)
{
    return mf_prepared_batch_scalar(prep, n, in, out, status, 1);
}

#endif /* GRIP_MF_LANES */
