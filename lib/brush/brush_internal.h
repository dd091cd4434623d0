/*
 * brush_internal.h - shared core of the brush-model family (lib/brush/).
 * Internal to lib/: not part of the public API.
 *
 * The core solves the normalized Neo-FIALA contact-patch problem
 * (docs/brush-models.md, "Neo-FIALA: closed form"): for a trial adhesion
 * boundary rh every integral is closed-form and every coupling is solved
 * exactly; a fixed number of Anderson-Bjorck steps on a tabulated variable
 * finds rh. The pure-longitudinal brush model is the same problem without
 * lateral slip and couplings.
 */
#ifndef GRIP_BRUSH_INTERNAL_H
#define GRIP_BRUSH_INTERNAL_H

#include <stdint.h>

#include "grip/grip_brush.h"
#include "arith.h"

/* One normalized problem: forces / (mu_s Fz), moments / (mu_s Fz l),
 * stress gradients s = K g / (mu_s Fz). All QS. Mirrored so that the lateral
 * excitation is >= 0. */
typedef struct {
    int32_t n;            /* pressure exponent                                     */
    grip_real_t c;        /* (n + 1) / n                                           */
    grip_real_t inv1;     /* 1 / (n + 1)                                           */
    grip_real_t inv2;     /* 1 / (n + 2)                                           */
    grip_real_t inv3;     /* 1 / (n + 3)                                           */
    grip_real_t sx;       /* Kx gx / (mu_s Fz), signed (ISO: > 0 driving)         */
    grip_real_t kf;       /* factor of tan(alpha_e) in the lateral gradient        */
    grip_real_t k;        /* tread-base coordinate factor (1 - S braking, else 1)  */
    grip_real_t teq;      /* |tan(alpha) + c_gamma gamma_e| (moment arms)          */
    grip_real_t syt;      /* Ky teq / (mu_s Fz), formed without rounding teq first */
    grip_real_t ky;       /* Ky / (mu_s Fz)                                        */
    grip_real_t kyg;      /* Ky l / G_mz (0: no twist)                             */
    grip_real_t gn;       /* mu_s Fz l / G_mz                                      */
    grip_real_t eky;      /* eps l Ky                                              */
    grip_real_t rdcc;     /* (mu_d / mu_s) c cos(theta)                            */
    grip_real_t rdcs;     /* (mu_d / mu_s) c sin(theta)                            */
    grip_real_t axn;      /* Ax / (mu_s Fz l)                                      */
    grip_real_t cqx;      /* c_q mu_s Fz                                           */
    grip_real_t cqm;      /* c_qm mu_s Fz l                                        */
    grip_real_t cxc;      /* c_xc mu_s Fz                                          */
    grip_real_t xin;      /* xi mu_s Fz / l                                        */
    grip_real_t q0;
} brush_problem;

/* The normalized solution. */
typedef struct {
    grip_real_t fx;
    grip_real_t fy;
    grip_real_t mz;
    grip_real_t rh;
} brush_state;

#define brush_core_solve GRIP_TYPED(grip_brush_i_solve)
/* Solves one problem: at most GRIP_BRUSH_ROOT_ITERS + 1 residual evaluations. */
void brush_core_solve(const brush_problem *pb, brush_state *st);

#define brush_core_slide GRIP_TYPED(grip_brush_i_slide)
/* Closed-form integral of D(x; n, 0) over [rh, 1]. */
grip_real_t brush_core_slide(grip_real_t rh, int32_t n, grip_real_t inv1);

#define brush_core_hypot GRIP_TYPED(grip_brush_i_hypot)
/* sqrt(x^2 + y^2) without overflow of the squares in QS. */
grip_real_t brush_core_hypot(grip_real_t x, grip_real_t y);

#define brush_core_tanc GRIP_TYPED(grip_brush_i_tanc)
/* tan(a) / a for |a| <= 1 (1 at a = 0): series below 0.5 rad, so that
 * K tan(a) = (K a) tan(a)/a keeps the relative precision of small angles
 * in the fixed build. */
grip_real_t brush_core_tanc(grip_real_t a);

#define brush_core_sinc GRIP_TYPED(grip_brush_i_sinc)
/* sin(a) / a for |a| <= 1 (1 at a = 0), likewise. */
grip_real_t brush_core_sinc(grip_real_t a);

#define brush_core_recip_tab GRIP_TYPED(grip_brush_i_recip_tab)
/* 1/m, m = 0..19 (entry 0 unused; QS constants). */
extern const grip_real_t brush_core_recip_tab[20];

/* 1 / m for the integers m = 1 .. GRIP_BRUSH_N_MAX + 3 (QS constants). */
static inline grip_real_t brush_core_recip(int32_t m)
{
    return (m >= 1 && m <= 19) ? brush_core_recip_tab[m] : R_ZERO;
}

/* Clamping helpers shared by the models. */
static inline grip_real_t brush_clamp_sym(grip_real_t x, grip_real_t lim, grip_status_t *st)
{
    if (x > lim) {
        *st = GRIP_WARN_CLAMPED;
        return lim;
    }
    if (x < r_neg(lim)) {
        *st = GRIP_WARN_CLAMPED;
        return r_neg(lim);
    }
    return x;
}

static inline grip_real_t brush_clamp(grip_real_t x, grip_real_t lo, grip_real_t hi, grip_status_t *st)
{
    if (x < lo) {
        *st = GRIP_WARN_CLAMPED;
        return lo;
    }
    if (x > hi) {
        *st = GRIP_WARN_CLAMPED;
        return hi;
    }
    return x;
}

static inline void brush_out_zero(grip_brush_out *out)
{
    out->fx = R_ZERO;
    out->fy = R_ZERO;
    out->mz = R_ZERO;
    out->rh = R_ONE;
}

/* Theoretical-slip split of seed 000 for a stiffness kn (QS): braking
 * (kappa < 0): S = -kappa, gradients (-S, tan) in the road coordinate,
 * tread-base factor 1 - S; driving: S = kappa / (1 + kappa), gradients
 * (S, (1 - S) tan). Returns kn gx (formed before rounding gx), kf (factor of
 * tan in gy) and k. */
static inline grip_real_t brush_slip_split(grip_real_t kappa, grip_real_t kn, grip_real_t *kf, grip_real_t *k)
{
    if (kappa < R_ZERO) {
        *kf = R_ONE;
        *k = r_add(R_ONE, kappa);
        return r_mul(kn, kappa);
    }
    *kf = r_div(R_ONE, r_add(R_ONE, kappa));
    *k = R_ONE;
    return r_div(r_mul(kn, kappa), r_add(R_ONE, kappa));
}

#endif /* GRIP_BRUSH_INTERNAL_H */
