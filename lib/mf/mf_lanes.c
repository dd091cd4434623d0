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
 *  - the equations are mf_equations.h's, the ones mf_eval.c's prepared
 *    path evaluates (MF-Tyre forms, no use mode), called by one body per
 *    lane (mfl_point) with the kernels' branch-free forms (mk = the lane's
 *    range mark: f32_kernels.h's grip_kf_lane_*, the guarded quotients with
 *    selections) and with the options as constants (MF 5.2 or 6.x, combined
 *    or pure: one loop per form), so that the blocks' branches compile away;
 *  - what this file writes itself is the input handling (and the
 *    low-speed reductions of kappa and alpha), as masks and selections
 *    where mf_eval.c (mf_prepare, mf_finish) branches and returns early: a
 *    non-finite input gives that point GRIP_ERR_INPUT and zero outputs, a
 *    clamp GRIP_WARN_CLAMPED, Fz <= 0 zero outputs and GRIP_OK, as
 *    grip_mf_eval_prepared; a lane whose kernel argument left the kernel's
 *    own range (the mark), or whose result is not finite, is evaluated again
 *    by grip_mf_eval_prepared itself (whose status then says why);
 *  - the last block is padded with copies of its first point (their
 *    results are dropped), so that every block runs the same code.
 *
 * tests/unit/test_mf_lanes.c checks that the input handling of both stays
 * equal: with GRIP_FLOAT_KERNELS=2 (the scalar path on the same kernels)
 * every output is bit-identical to grip_mf_eval_prepared's over the golden
 * vectors of every shared .tir file and a grid of operating points; at the
 * default level (libm) it stays within the kernels' accuracy of it and
 * within the golden tolerance of the float64 reference
 * (docs/magic-formula-c.md section 7.2).
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
 * checks, clamps and statuses as numbers (see grip_kf_lane_mark).
 *
 * Sets the lane form does not cover (GRIP_MF_OPT_BOOK, LMUV > 0,
 * GRIP_MF_OPT_MZ52_SVYK_CAMBER) and builds without it (the fixed build,
 * GRIP_MF_LANES 0) take grip_mf_eval_prepared_batch's loop: the same
 * results as it, bit for bit.
 */
#include "mf_equations.h"
#include "grip/grip_mf_batch.h"

#if GRIP_MF_LANES

#include <float.h>

#define MFL_N GRIP_MF_LANES_N

/* clang's cost model declines the lane loop (clang 14: "vectorization is
 * not beneficial", and the scalar lane loop is then slower than the scalar
 * path): asked for explicitly. gcc needs no hint. */
#if defined(__clang__)
#define MFL_VECTORIZE _Pragma("clang loop vectorize(enable)")
#else
#define MFL_VECTORIZE
#endif

/* x clamped to [-lim, lim] (mf_clamp_sym's value; its mark is *clamped:
 * how far the farthest input was outside, a number as the range mark) */
static MF_ALWAYS_INLINE float mfl_clamp(float x, float lim, float *clamped)
{
    *clamped = r_max(*clamped, fabsf(x) - lim);
    return (x > lim) ? lim : ((x < -lim) ? -lim : x);
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
    float nom;           /* NOMPRES, 1 without                             */
    float dpi_scale;     /* 1, 0 without (dpi 0: the factors' zero's sign  */
                         /* does not matter, each is 1 + c dpi ...)        */
    float vxlow;         /* VXLOW, -1 without the low-speed model          */
    float vxlow_div;     /* VXLOW, or 1 (not used) without it              */
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

/* One point: the input handling of mf_prepare as masks, then the blocks of
 * mf_equations.h in the order of mf_eval.c's prepared path (mf_pure_begin,
 * mf_lat_pure, mf_trail_coefs, then mf_combined's or mf_pure_eval's rest)
 * and mf_finish's scaling and signs, for a prepared set without
 * GRIP_MF_OPT_BOOK and with LMUV = 0. */
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
    float bad = -1.0f;           /* a kernel argument outside its range: > 0 or NaN (grip_kf_lane_mark) */
    /* > 0 when an input was clamped: how far the farthest was outside (a
     * number, as bad) */
    float clamped = -1.0f;
    /* x - x is 0 for a finite x, NaN otherwise */
    int badin = !(((((kappa - kappa) + (alpha - alpha)) + ((gamma - gamma) + (fz - fz))) +
                   ((vx - vx) + (pr - pr))) == 0.0f);
    int zero;
    float sa;
    float ca;
    float avx;
    float fx;
    float fy;
    float mz;
    mf_op op;
    mf_long lon;
    mf_lat_common latc;
    mf_lat lat;
    mf_lat lat0;
    mf_trail tc;
    grip_mf_output o;
    /* non-finite inputs: ERR_INPUT; the lane computes on, its results are
     * dropped (the kernels take any float: an argument outside their range
     * is replaced before it is converted to an integer) */

    /* sign conventions -> ISO-W */
    alpha = alpha * c->s_alpha;
    fz = fz * c->s_fz;
    kappa = kappa * c->s_kappa;
    gamma = gamma * c->s_gamma;
    zero = !(fz > 0.0f);

    /* the domain */
    kappa = mfl_clamp(kappa, (float)GRIP_MF_KAPPA_MAX, &clamped);
    alpha = mfl_clamp(alpha, (float)GRIP_MF_ALPHA_MAX, &clamped);
    gamma = mfl_clamp(gamma, (float)GRIP_MF_GAMMA_MAX, &clamped);
    vx = mfl_clamp(vx, (float)GRIP_MF_VX_MAX, &clamped);
    clamped = r_max(clamped, fz - fz_max);       /* <= 0 where zero (fz_max > 0) */
    fz = zero ? 0.0f : ((fz > fz_max) ? fz_max : fz);

    op.mf52 = mf52;
    op.book = 0;
    mf_load(p, fz, &op);
    /* dpi: the prepared default (p <= 0), else mf_dpi's */
    {
        float plo = c->plo;
        float phi = c->phi;
        float q = r_mul(mf_dpi_of(pr, c->nom), c->dpi_scale);                    /* 4.E2b */
        float d = (pr < plo) ? (float)GRIP_MF_DPI_MIN : ((pr > phi) ? (float)GRIP_MF_DPI_MAX : q);
        int given = pr > 0.0f;
        clamped = r_max(clamped, given ? r_max(plo - pr, pr - phi) : dpi0_clamp);
        op.dpi = given ? d : dpi0;
    }
    op.dp = NULL;   /* the pressure factors formed where used, at the lane's dpi */

    /* low speed (mf_prepare; c->vxlow is -1 without VXLOW: neither applies) */
    sa = mfk_sin(alpha, &bad);
    ca = mfk_cos(alpha, &bad);
    avx = fabsf(vx);
    {
        float num;
        float den;
        float rl;
        float sm;
        int low = avx <= c->vxlow;
        int red;
        mf_low_alpha(avx, sa, ca, c->vxlow, &num, &den);
        red = num < den;
        rl = (low ? avx : 0.0f) / c->vxlow_div;
        sm = mf_low_smooth(rl, &bad);
        kappa = low ? r_mul(rl, kappa) : kappa;
        op.smooth = low ? sm : R_ONE;
        alpha = red ? r_mul(num / den, alpha) : alpha;
    }
    /* the reduced angle's cosine (the same as above where not reduced; its
     * sine served LMUV > 0 only, which the lanes leave to the scalar path) */
    ca = mfk_cos(alpha, &bad);
    op.kappa = kappa;
    op.cosa = fabsf(ca);                                                         /* 4.E6 */
    op.alpha = alpha;
    op.gamma = gamma;
    /* LMUV = 0 (the lanes' sets): LMU*, LMU', LKY / LMUY* prepared */
    op.lmux_s = p->lmux;
    op.lmuy_s = p->lmuy;
    op.lmux_p = k->lmux_p;
    op.lmuy_p = k->lmuy_p;
    op.ky_mu = k->ky_mu;
    mf_cambers(p, gamma, &op);

    mf_long_pure(p, &op, NULL, R_ONE, &bad, 0, &lon);
    mf_lat_common_init(p, &op, 0, &latc);
    mf_lat_body(p, &op, &latc, op.gy, NULL, R_ONE, &bad, 0, &lat);
    if (!mf52) {
        /* Fy0 at gamma = 0 (MF 6.x's Mz; mf_lat_gamma0): equal to lat
         * where gy is 0 */
        mf_lat_body(p, &op, &latc, R_ZERO, NULL, R_ONE, &bad, 0, &lat0);
    } else {
        lat0 = lat;
    }
    mf_trail_body(p, &op, &lat, R_ONE, &bad, 0, &tc);
    if (pure) {
        /* mf_pure_eval */
        mz = mf_mz0(p, &op, mf_trail_at_k(&op, &tc, tc.alpha_t, &bad, 0), mf_residual_at_k(&tc, tc.alpha_r),
                    mf52 ? lat.fy0 : lat0.fy0);
        fx = lon.fx0;
        fy = lat.fy0;
    } else {
        /* mf_combined */
        mf_svyk_f sf;
        float svyk;
        float svyk_mz;
        float gyk;
        float t;
        float mzr;
        fx = r_mul(mf_gxa(p, &op, R_ONE, &bad, 0), lon.fx0);
        mf_svyk_factors(p, &op, &bad, 0, &sf);
        svyk = mf_svyk(p, &op, &sf, mf_dvyk(lat.muy, &sf));
        gyk = mf_gyk_body(p, &op, op.gy, R_ONE, &bad, 0);
        fy = r_add(r_mul(gyk, lat.fy0), svyk);
        svyk_mz = mf_svyk(p, &op, &sf, mf_dvyk(r_mul(latc.mub, op.lmuy_s), &sf));
        mzr = mf_residual_at_k(&tc, mf_alpha_eq_k(op.book, op.kappa, tc.alpha_r, lon.kxk, lat.kya, &bad));
        t = mf_trail_at_k(&op, &tc, mf_alpha_eq_k(op.book, op.kappa, tc.alpha_t, lon.kxk, lat.kya, &bad), &bad, 0);
        mf_mz_scale(p, &op, &t, &mzr);
        mz = mf_mz_sum(mzr, t, mf52 ? r_sub(fy, svyk_mz) : r_mul(gyk, lat0.fy0), mf_sarm(p, &op, fy, 0), fx);
    }
    /* mf_finish */
    mf_scale_out(p, &op, fx, fy, mz, &o);
    fx = o.fx;
    fy = o.fy * c->s_out;
    mz = o.mz * c->s_out;
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
    c->nom = haspr ? p->nompres : 1.0f;
    c->dpi_scale = haspr ? 1.0f : 0.0f;
    c->vxlow = (p->vxlow > 0.0f) ? p->vxlow : -1.0f;
    c->vxlow_div = (p->vxlow > 0.0f) ? p->vxlow : 1.0f;
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
