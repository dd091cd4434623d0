/*
 * brush_core.c - the normalized contact-patch problem shared by Neo-FIALA
 * and the brush model: closed-form integrals of the generalized skewed
 * parabola, exact elimination of the couplings for a trial boundary, and the
 * fixed-iteration root for the adhesion boundary. Equations and their
 * derivation: docs/brush-models.md ("Neo-FIALA: closed form", "Root
 * finding"); float64 twin: nf_state / nf_solve in tools/grip_tools/reference/brush.py.
 *
 * Cost of brush_core_solve: at most GRIP_BRUSH_ROOT_ITERS + 1 evaluations
 * of core_state (one when the tyre slides fully), each with one power chain
 * (pow_geo), one square root (quadratic) and one hypot; no data-dependent
 * loop count.
 */
#include <stddef.h>

#include "brush_internal.h"
#include "brush_table.h"

/* Off-root trial boundaries can push the pressure skew beyond the valid
 * range; the residual uses |q| <= Q_MAX (never active at the root). */
#define Q_MAX RC(0.9)
/* Lower clamp of the slope 1 - N1 of the moment equation (never active at
 * the root in the valid range: measured minimum 0.90). */
#define SLOPE_MIN RC(0.125)
/* Below this 1 - rh the tip-displacement moment of the sliding region
 * (of order (1 - rh)^2) is taken as 0. */
#define IT_EPS RC(0.0009765625)

/* Inverse pressure-limit tables, rows n = 2..GRIP_BRUSH_N_MAX. */
#define TAB_W (GRIP_BRUSH_TABLE_M + 1)
static const grip_real_t k_tab[GRIP_BRUSH_N_MAX - 1][TAB_W] = {
    GRIP_BRUSH_TAB_2,
#if GRIP_BRUSH_N_MAX >= 3
    GRIP_BRUSH_TAB_3,
#endif
#if GRIP_BRUSH_N_MAX >= 4
    GRIP_BRUSH_TAB_4,
#endif
#if GRIP_BRUSH_N_MAX >= 5
    GRIP_BRUSH_TAB_5,
#endif
#if GRIP_BRUSH_N_MAX >= 6
    GRIP_BRUSH_TAB_6,
#endif
#if GRIP_BRUSH_N_MAX >= 7
    GRIP_BRUSH_TAB_7,
#endif
#if GRIP_BRUSH_N_MAX >= 8
    GRIP_BRUSH_TAB_8,
#endif
#if GRIP_BRUSH_N_MAX >= 9
    GRIP_BRUSH_TAB_9,
#endif
#if GRIP_BRUSH_N_MAX >= 10
    GRIP_BRUSH_TAB_10,
#endif
#if GRIP_BRUSH_N_MAX >= 11
    GRIP_BRUSH_TAB_11,
#endif
#if GRIP_BRUSH_N_MAX >= 12
    GRIP_BRUSH_TAB_12,
#endif
#if GRIP_BRUSH_N_MAX >= 13
    GRIP_BRUSH_TAB_13,
#endif
#if GRIP_BRUSH_N_MAX >= 14
    GRIP_BRUSH_TAB_14,
#endif
#if GRIP_BRUSH_N_MAX >= 15
    GRIP_BRUSH_TAB_15,
#endif
#if GRIP_BRUSH_N_MAX >= 16
    GRIP_BRUSH_TAB_16,
#endif
};

const grip_real_t brush_core_recip_tab[20] = {
    RC(0.0), RC(1.0), RC(1.0 / 2.0), RC(1.0 / 3.0), RC(1.0 / 4.0), RC(1.0 / 5.0),
    RC(1.0 / 6.0), RC(1.0 / 7.0), RC(1.0 / 8.0), RC(1.0 / 9.0), RC(1.0 / 10.0),
    RC(1.0 / 11.0), RC(1.0 / 12.0), RC(1.0 / 13.0), RC(1.0 / 14.0), RC(1.0 / 15.0),
    RC(1.0 / 16.0), RC(1.0 / 17.0), RC(1.0 / 18.0), RC(1.0 / 19.0),
};

grip_real_t brush_core_tanc(grip_real_t a)
{
    grip_real_t a2;
    if (r_abs(a) >= RC(0.5)) {
        return r_div(r_sin(a), r_mul(a, r_cos(a)));
    }
    /* 1 + a^2/3 + 2a^4/15 + 17a^6/315 + 62a^8/2835 + 1382a^10/155925 + 21844a^12/6081075,
     * truncation < 1e-7 at 0.5 rad */
    a2 = r_sq(a);
    return r_add(R_ONE,
        r_mul(a2, r_add(RC(1.0 / 3.0),
        r_mul(a2, r_add(RC(2.0 / 15.0),
        r_mul(a2, r_add(RC(17.0 / 315.0),
        r_mul(a2, r_add(RC(62.0 / 2835.0),
        r_mul(a2, r_add(RC(1382.0 / 155925.0), r_mul(a2, RC(21844.0 / 6081075.0)))))))))))));
}

grip_real_t brush_core_sinc(grip_real_t a)
{
    grip_real_t a2;
    if (r_abs(a) >= RC(0.5)) {
        return r_div(r_sin(a), a);
    }
    /* 1 - a^2/6 + a^4/120 - a^6/5040 + a^8/362880, truncation < 1e-9 at 0.5 rad */
    a2 = r_sq(a);
    return r_add(R_ONE,
        r_mul(a2, r_add(RC(-1.0 / 6.0),
        r_mul(a2, r_add(RC(1.0 / 120.0),
        r_mul(a2, r_add(RC(-1.0 / 5040.0), r_mul(a2, RC(1.0 / 362880.0)))))))));
}

/* m as a real, m = 0..16 (GRIP_BRUSH_N_MAX <= 16) */
static const grip_real_t k_int[17] = {
    RC(0.0), RC(1.0), RC(2.0), RC(3.0), RC(4.0), RC(5.0), RC(6.0), RC(7.0), RC(8.0),
    RC(9.0), RC(10.0), RC(11.0), RC(12.0), RC(13.0), RC(14.0), RC(15.0), RC(16.0),
};

grip_real_t brush_core_hypot(grip_real_t x, grip_real_t y)
{
#if GRIP_ARITH_FIXED
    /* Scale both by a power of two so that the larger lies in [2^21, 2^23)
     * (Q15.16 values 32..128): the squares then keep full relative
     * precision, nothing overflows, and no division is needed. Fixed steps. */
    int32_t ax = r_abs(x);
    int32_t ay = r_abs(y);
    int32_t hi = (ax > ay) ? ax : ay;
    int up = 0;
    int down = 0;
    grip_real_t r;
    if (hi == 0) {
        return R_ZERO;
    }
    if (hi < (1 << 7)) { ax <<= 14; ay <<= 14; hi <<= 14; up += 14; }
    if (hi < (1 << 14)) { ax <<= 7; ay <<= 7; hi <<= 7; up += 7; }
    if (hi < (1 << 18)) { ax <<= 4; ay <<= 4; hi <<= 4; up += 4; }
    if (hi < (1 << 20)) { ax <<= 2; ay <<= 2; hi <<= 2; up += 2; }
    if (hi < (1 << 21)) { ax <<= 1; ay <<= 1; hi <<= 1; up += 1; }
    if (hi >= (1 << 27)) { ax >>= 4; ay >>= 4; hi >>= 4; down += 4; }
    if (hi >= (1 << 25)) { ax >>= 2; ay >>= 2; hi >>= 2; down += 2; }
    if (hi >= (1 << 24)) { ax >>= 1; ay >>= 1; hi >>= 1; down += 1; }
    if (hi >= (1 << 23)) { ax >>= 1; ay >>= 1; down += 1; }
    r = r_sqrt(r_add(r_sq(ax), r_sq(ay)));
    if (up > 0) {
        return (r + (1 << (up - 1))) >> up;
    }
    if (r > (INT32_MAX >> down)) {
        return INT32_MAX;                 /* beyond Q15.16: saturate */
    }
    return r << down;
#else
    return sqrtf(x * x + y * y);
#endif
}

/* |u|^n and G = 1 + |u| + ... + |u|^(n-1) for a = |u| in [0, 1]. For the
 * default exponents n <= 8 a short product chain per n (at most 3 squarings
 * and 4 further operations; G by the factorizations
 * 1 + a + ... + a^(2m-1) = (1 + a + ... + a^(m-1)) (1 + a^m) and
 * G_(m+1) = 1 + a G_m, all terms positive); larger n (GRIP_BRUSH_N_MAX > 8)
 * run a loop of GRIP_BRUSH_N_MAX steps. */
static void pow_geo(grip_real_t a, int32_t n, grip_real_t *p_out, grip_real_t *g_out)
{
    grip_real_t a2 = r_sq(a);
    grip_real_t g2 = r_add(R_ONE, a);
    grip_real_t p;
    grip_real_t g;
    switch (n) {
    case 2:
        p = a2;
        g = g2;
        break;
    case 3:
        p = r_mul(a2, a);
        g = r_add(R_ONE, r_mul(a, g2));
        break;
    case 4:
        p = r_sq(a2);
        g = r_mul(g2, r_add(R_ONE, a2));
        break;
    case 5:
        p = r_mul(r_sq(a2), a);
        g = r_add(R_ONE, r_mul(a, r_mul(g2, r_add(R_ONE, a2))));
        break;
    case 6: {
        grip_real_t a3 = r_mul(a2, a);
        p = r_sq(a3);
        g = r_mul(r_add(R_ONE, r_mul(a, g2)), r_add(R_ONE, a3));
        break;
    }
    case 7: {
        grip_real_t a3 = r_mul(a2, a);
        p = r_mul(r_sq(a3), a);
        g = r_add(R_ONE, r_mul(a, r_mul(r_add(R_ONE, r_mul(a, g2)), r_add(R_ONE, a3))));
        break;
    }
    case 8: {
        grip_real_t a4 = r_sq(a2);
        p = r_sq(a4);
        g = r_mul(r_mul(g2, r_add(R_ONE, a2)), r_add(R_ONE, a4));
        break;
    }
    default: {
        int32_t j;
        p = R_ONE;
        g = R_ZERO;
        for (j = 0; j < GRIP_BRUSH_N_MAX; ++j) {
            if (j < n) {
                g = r_add(g, p);
                p = r_mul(p, a);
            }
        }
        break;
    }
    }
    *p_out = p;
    *g_out = g;
}

grip_real_t brush_core_slide(grip_real_t rh, int32_t n, grip_real_t inv1)
{
    grip_real_t u = r_sub(r_add(rh, rh), R_ONE);
    grip_real_t p;
    grip_real_t g;
    pow_geo(r_abs(u), n, &p, &g);
    /* int_rh^1 D = (1/2) [(1 - u) - (1 - |u|^n u) / (n + 1)] */
    return r_mul(RC(0.5), r_sub(r_sub(R_ONE, u), r_mul(r_sub(R_ONE, r_mul(p, u)), inv1)));
}

/* rh of the table variable y in [0, 1] (y = 1: rh = 0). */
static grip_real_t table_rh(const grip_real_t *row, grip_real_t y)
{
    return r_table_lerp(row, GRIP_BRUSH_TABLE_M, y);
}

/* Per-call coefficients of core_state that do not depend on the trial
 * boundary: formed once per solve instead of once per residual. */
typedef struct {
    grip_real_t ga;       /* kf teq:    gy = ga + gb m (tread-base twist)     */
    grip_real_t gb;       /* -kf gn                                         */
    grip_real_t sya;      /* kf syt:    sy = Ky gy = sya + syb m            */
    grip_real_t syb;      /* -kf kyg                                        */
    grip_real_t sya3;     /* (2/3) sya                                      */
    grip_real_t syb3;     /* (2/3) syb                                      */
    grip_real_t sx3;      /* (2/3) sx                                       */
    grip_real_t ek1;      /* eky k                                          */
    grip_real_t ek2;      /* (2/3) eky k^2                                  */
    grip_real_t ek3;      /* eky k^2                                        */
    grip_real_t e3;       /* (2/3) eky k                                    */
    grip_real_t e4;       /* (1/2) eky k^2                                  */
} core_coef;

static void core_coef_init(const brush_problem *pb, core_coef *cc)
{
    grip_real_t k = pb->k;
    cc->ga = r_mul(pb->kf, pb->teq);
    cc->gb = r_neg(r_mul(pb->kf, pb->gn));
    cc->sya = r_mul(pb->kf, pb->syt);
    cc->syb = r_neg(r_mul(pb->kf, pb->kyg));
    cc->sya3 = r_mul(RC(2.0 / 3.0), cc->sya);
    cc->syb3 = r_mul(RC(2.0 / 3.0), cc->syb);
    cc->sx3 = r_mul(RC(2.0 / 3.0), pb->sx);
    cc->ek1 = r_mul(pb->eky, k);
    cc->ek3 = r_mul(cc->ek1, k);
    cc->ek2 = r_mul(RC(2.0 / 3.0), cc->ek3);
    cc->e3 = r_mul(RC(2.0 / 3.0), cc->ek1);
    cc->e4 = r_mul(RC(0.5), cc->ek3);
}

/*
 * The state at trial boundary rh and the transformed residual
 *   F(rh) = c fac G - |(sx, sy_r)| / (1 - q u)
 * (= [Lmax(rh) - |stress gradient at rh|] / (1 - q u)); see nf_state in
 * tools/grip_tools/reference/brush.py for the same steps in float64 (here the factors
 * that do not depend on rh come from core_coef).
 */
static grip_real_t core_state(const brush_problem *pb, const core_coef *cc, grip_real_t rh, brush_state *st)
{
    grip_real_t u = r_sub(r_add(rh, rh), R_ONE);
    grip_real_t p;
    grip_real_t g;
    grip_real_t u2;
    grip_real_t u3;
    grip_real_t ab0;
    grip_real_t ab1;
    grip_real_t ab2;
    grip_real_t i00, i01, i10, i11, it0, it1;
    grip_real_t om = r_sub(R_ONE, rh);
    grip_real_t r2 = r_sq(rh);
    grip_real_t r3 = r_mul(r2, rh);
    grip_real_t a_, b_, dq, qa, qb, fxa, fxb;
    grip_real_t ida, idb, ixa, ixb, ita, itb;
    grip_real_t den, fya, fyb, wm, m1a, m1b, xca, xcb, za, zb;
    grip_real_t n0, n1, n2, bq, disc, m;
    grip_real_t q, sy, fy, fx, syr, fac, qc, lim;

    pow_geo(r_abs(u), pb->n, &p, &g);
    u2 = r_sq(u);
    u3 = r_mul(u2, u);
    /* A_k - B_k = int_u^1 (1 - |v|^n) v^k dv, k = 0, 1, 2 */
    ab0 = r_sub(r_sub(R_ONE, u), r_mul(r_sub(R_ONE, r_mul(p, u)), pb->inv1));
    ab1 = r_sub(r_mul(r_sub(R_ONE, u2), RC(0.5)), r_mul(r_sub(R_ONE, r_mul(p, u2)), pb->inv2));
    ab2 = r_sub(r_mul(r_sub(R_ONE, u3), RC(1.0 / 3.0)), r_mul(r_sub(R_ONE, r_mul(p, u3)), pb->inv3));
    /* sliding-region integrals, split by q: int D, int D x, int D (1-x)/(1-rh) */
    i00 = r_mul(RC(0.5), ab0);
    i01 = r_mul(RC(-0.5), ab1);
    i10 = r_mul(RC(0.25), r_add(ab0, ab1));
    i11 = r_mul(RC(-0.25), r_add(ab1, ab2));
    if (om >= IT_EPS) {
        grip_real_t q_om = r_div(RC(0.25), om);
        it0 = r_mul(q_om, r_sub(ab0, ab1));
        it1 = r_mul(q_om, r_sub(ab2, ab1));
    } else {
        it0 = R_ZERO;
        it1 = R_ZERO;
    }

    /* q = q0 + cqx Fx + cqm m with Fx = A + B q  ->  q = qa + qb m */
    a_ = r_add(r_mul(pb->sx, r2), r_mul(pb->rdcc, i00));
    b_ = r_mul(pb->rdcc, i01);
    dq = r_div(R_ONE, r_sub(R_ONE, r_mul(pb->cqx, b_)));
    qa = r_mul(r_add(pb->q0, r_mul(pb->cqx, a_)), dq);
    qb = r_mul(pb->cqm, dq);
    fxa = r_add(a_, r_mul(b_, qa));
    fxb = r_mul(b_, qb);
    ida = r_add(i00, r_mul(i01, qa));
    idb = r_mul(i01, qb);
    ixa = r_add(i10, r_mul(i11, qa));
    ixb = r_mul(i11, qb);
    ita = r_add(it0, r_mul(it1, qa));
    itb = r_mul(it1, qb);
    /* Fy (1 + eky (k r^2 - 2/3 k^2 r^3)) = r^2 sy + rd c sin(theta) ID */
    den = r_div(R_ONE, r_add(R_ONE, r_mul(r2, r_sub(cc->ek1, r_mul(cc->ek2, rh)))));
    fya = r_mul(r_add(r_mul(r2, cc->sya), r_mul(pb->rdcs, ida)), den);
    fyb = r_mul(r_add(r_mul(r2, cc->syb), r_mul(pb->rdcs, idb)), den);
    /* first moment about the leading edge:
     * 2 [r^3 sy/3 - eky (k r^3/3 - k^2 r^4/4) Fy] + rd c sin(theta) IX */
    wm = r_mul(r3, r_sub(cc->e3, r_mul(cc->e4, rh)));
    m1a = r_add(r_sub(r_mul(r3, cc->sya3), r_mul(wm, fya)), r_mul(pb->rdcs, ixa));
    m1b = r_add(r_sub(r_mul(r3, cc->syb3), r_mul(wm, fyb)), r_mul(pb->rdcs, ixb));
    /* moment reference x_c / l = 1/2 + cxc Fx - xi m */
    xca = r_add(RC(0.5), r_mul(pb->cxc, fxa));
    xcb = r_sub(r_mul(pb->cxc, fxb), pb->xin);
    /* longitudinal stresses at the tip's lateral position, plus Ax term */
    za = r_add(r_mul(cc->sx3, r3), r_mul(rh, r_add(r_mul(pb->rdcc, ita), pb->axn)));
    zb = r_mul(rh, r_mul(pb->rdcc, itb));
    /* Mz = M1 - x_c Fy + gy Z = n0 + n1 m + n2 m^2 */
    n0 = r_add(r_sub(m1a, r_mul(xca, fya)), r_mul(cc->ga, za));
    n1 = r_add(r_sub(m1b, r_add(r_mul(xca, fyb), r_mul(xcb, fya))), r_add(r_mul(cc->ga, zb), r_mul(cc->gb, za)));
    n2 = r_add(r_neg(r_mul(xcb, fyb)), r_mul(cc->gb, zb));
    bq = r_max(r_sub(R_ONE, n1), SLOPE_MIN);
    if (n2 == R_ZERO) {
        m = r_div(n0, bq);                /* no Mz-dependent skew or shift: linear */
    } else {
        disc = r_max(r_sub(r_sq(bq), r_mul(RC(4.0), r_mul(n2, n0))), R_ZERO);
        m = r_div(r_add(n0, n0), r_add(bq, r_sqrt(disc)));
    }

    q = r_add(qa, r_mul(qb, m));
    sy = r_add(cc->sya, r_mul(cc->syb, m));
    fy = r_add(fya, r_mul(fyb, m));
    fx = r_add(fxa, r_mul(fxb, m));
    /* lateral stress gradient at rh: sy - eky k (1 - k rh) Fy */
    syr = r_sub(sy, r_mul(fy, r_sub(cc->ek1, r_mul(cc->ek3, rh))));
    fac = (rh <= RC(0.5)) ? R_ONE : r_div(om, rh);
    qc = r_clamp(q, r_neg(Q_MAX), Q_MAX);
    lim = r_mul(pb->c, r_mul(fac, g));
    st->fx = fx;
    st->fy = fy;
    st->mz = m;
    st->rh = rh;
    return r_sub(lim, r_div(brush_core_hypot(pb->sx, syr), r_sub(R_ONE, r_mul(qc, u))));
}

/*
 * core_state at rh = 0 (full sliding, y = 1), with the terms that vanish
 * there left out: u = -1, |u|^n = 1, G = n, r^2 = r^3 = 0, den = 1, AB_1 = 0,
 * AB_0 = 2 n/(n + 1), AB_2 = 2/3 - 2/(n + 3); no adhesive term and no tip
 * displacement, so the moment equation is linear (n2 = 0). The same
 * equations as core_state (the golden tests compare both paths against the
 * float64 reference), about a third of its operations.
 */
static grip_real_t core_state0(const brush_problem *pb, const core_coef *cc, brush_state *st)
{
    grip_real_t i00 = r_sub(R_ONE, pb->inv1);                 /* n / (n + 1) */
    grip_real_t i10 = r_mul(RC(0.5), i00);
    grip_real_t i11 = r_sub(r_mul(RC(0.5), pb->inv3), RC(1.0 / 6.0));
    grip_real_t fxa = r_mul(pb->rdcc, i00);
    grip_real_t qa = r_add(pb->q0, r_mul(pb->cqx, fxa));
    grip_real_t fya = r_mul(pb->rdcs, i00);
    grip_real_t m1a = r_mul(pb->rdcs, r_add(i10, r_mul(i11, qa)));
    grip_real_t m1b = r_mul(pb->rdcs, r_mul(i11, pb->cqm));
    grip_real_t xca = r_add(RC(0.5), r_mul(pb->cxc, fxa));
    grip_real_t n0 = r_sub(m1a, r_mul(xca, fya));
    grip_real_t n1 = r_add(m1b, r_mul(pb->xin, fya));
    grip_real_t m = r_div(n0, r_max(r_sub(R_ONE, n1), SLOPE_MIN));
    grip_real_t q = r_add(qa, r_mul(pb->cqm, m));
    grip_real_t sy = r_add(cc->sya, r_mul(cc->syb, m));
    grip_real_t syr = r_sub(sy, r_mul(fya, cc->ek1));
    grip_real_t qc = r_clamp(q, r_neg(Q_MAX), Q_MAX);
    st->fx = fxa;
    st->fy = fya;
    st->mz = m;
    st->rh = R_ZERO;
    /* Lmax(0) = c G = c n */
    return r_sub(r_mul(pb->c, k_int[pb->n]), r_div(brush_core_hypot(pb->sx, syr), r_add(R_ONE, qc)));
}

/* Regula-falsi point between (yb, fb <= 0) and (ya, fa > 0), yb < ya:
 * yb + (ya - yb) fb / (fb - fa). The ratio lies in [0, 1] and keeps full
 * precision in the fixed build even when fa and fb are a few LSB. */
static grip_real_t secant(grip_real_t ya, grip_real_t yb, grip_real_t fa, grip_real_t fb)
{
    grip_real_t d = r_sub(fb, fa);
    grip_real_t t = (d < R_ZERO) ? r_clamp(r_div(fb, d), R_ZERO, R_ONE) : RC(0.5);
    return r_add(yb, r_mul(t, r_sub(ya, yb)));
}

void brush_core_solve(const brush_problem *pb, brush_state *st)
{
    const grip_real_t *row = k_tab[pb->n - GRIP_BRUSH_N_MIN];
    brush_state buf[2];
    const brush_state *s1;
    const brush_state *s2;
    grip_real_t fa;
    grip_real_t fb;
    grip_real_t f1 = R_ZERO;
    grip_real_t f2 = R_ZERO;
    grip_real_t ya = R_ONE;
    grip_real_t yb = R_ZERO;
    grip_real_t s_unc;
    grip_real_t w;
    core_coef cc;
    int side = 0;
    int i;

    core_coef_init(pb, &cc);
    fa = core_state0(pb, &cc, st);       /* rh = 0 (y = 1) */
    if (fa <= R_ZERO) {
        return;                           /* full sliding: the state is final */
    }
    s_unc = brush_core_hypot(pb->sx, cc.sya);
    if (s_unc <= R_ZERO) {
        (void)core_state(pb, &cc, R_ONE, st); /* no slip: all zero */
        return;
    }
    /* f(y = 0), i.e. rh = 1, replaced by the uncoupled value: < 0, and the
     * true value is <= 0, so [0, 1] is a bracket either way. */
    fb = r_neg(r_div(s_unc, r_sub(R_ONE, pb->q0)));
    for (i = 0; i < GRIP_BRUSH_ROOT_ITERS; ++i) {
        grip_real_t y = secant(ya, yb, fa, fb);
        grip_real_t fx = core_state(pb, &cc, table_rh(row, y), &buf[i & 1]);
        f1 = f2;
        f2 = fx;
        if (fx > R_ZERO) {
            if (side > 0) {
                grip_real_t mf = (fa > R_ZERO) ? r_sub(R_ONE, r_div(fx, fa)) : R_ZERO;
                fb = (mf > R_ZERO) ? r_mul(mf, fb) : r_mul(RC(0.5), fb);
            }
            ya = y;
            fa = fx;
            side = 1;
        } else {
            if (side < 0 && fb < R_ZERO) {
                grip_real_t mf = r_sub(R_ONE, r_div(fx, fb));
                fa = (mf > R_ZERO) ? r_mul(mf, fa) : r_mul(RC(0.5), fa);
            }
            yb = y;
            fb = fx;
            side = -1;
        }
    }
    /* No further evaluation: the outputs are smooth in y, so the states of
     * the last two points combined along their secant (weight
     * w = f1 / (f1 - f2)) are as accurate as another step. */
    s2 = &buf[(GRIP_BRUSH_ROOT_ITERS - 1) & 1];
    s1 = &buf[GRIP_BRUSH_ROOT_ITERS & 1];
    w = (f1 != f2) ? r_clamp(r_div(f1, r_sub(f1, f2)), RC(-1.0), RC(2.0)) : R_ONE;
    st->fx = r_add(s1->fx, r_mul(w, r_sub(s2->fx, s1->fx)));
    st->fy = r_add(s1->fy, r_mul(w, r_sub(s2->fy, s1->fy)));
    st->mz = r_add(s1->mz, r_mul(w, r_sub(s2->mz, s1->mz)));
    st->rh = r_clamp(r_add(s1->rh, r_mul(w, r_sub(s2->rh, s1->rh))), R_ZERO, R_ONE);
}
