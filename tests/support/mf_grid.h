/*
 * mf_grid.h - a deterministic grid of Magic Formula operating points for
 * the tests that compare two evaluation paths point by point (batch,
 * prepared): kappa, alpha, gamma, Fz, p and vx each cycle through values
 * inside, at and beyond the domain's limits (grip_mf.h), with co-prime
 * periods so that every combination class occurs. Fz and p are multiples
 * of the set's FNOMIN and NOMPRES; p 0 and -1 select the default
 * pressure, 0.4 and 2.5 are clamped. Finite points only: a test adds its
 * own non-finite ones.
 */
#ifndef GRIP_TEST_MF_GRID_H
#define GRIP_TEST_MF_GRID_H

#include <math.h>

#include "grip/grip_mf.h"

#if GRIP_ARITH_FIXED
#define MF_GRID_QS(v) ((grip_real_t)lround((v) * 65536.0))
#define MF_GRID_QL(v) ((grip_real_t)lround((v) * 256.0))
#define MF_GRID_FROM_QL(v) ((double)(v) / 256.0)
#else
#define MF_GRID_QS(v) ((grip_real_t)(v))
#define MF_GRID_QL(v) ((grip_real_t)(v))
#define MF_GRID_FROM_QL(v) ((double)(v))
#endif

static inline void mf_grid_fill(grip_mf_input *in, int n, grip_real_t fnomin, grip_real_t nompres)
{
    static const double kap[] = { 0.0, 0.02, -0.12, 0.6, -1.0, 1.5, 2.0, -0.003 };
    static const double alp[] = { 0.0, 0.03, -0.12, 0.35, -1.5, 1.5707963, 1.7, 0.004, -0.6 };
    static const double gam[] = { 0.0, -0.01, 0.03, 0.2, -0.6 };
    static const double fzr[] = { 1.0, 0.25, 0.0, -0.1, 1.7, 4.5, 0.01 };
    static const double prr[] = { 0.0, 1.0, 0.4, 2.5, 1.3, -1.0 };
    static const double vxs[] = { 20.0, 0.0, 0.3, -5.0, 16.7, 350.0, 1.0, 60.0, -0.2, 2.0, 8.0 };
    double fn = MF_GRID_FROM_QL(fnomin);
    double pn = MF_GRID_FROM_QL(nompres);
    int k;
    for (k = 0; k < n; k++) {
        in[k].kappa = MF_GRID_QS(kap[k % 8]);
        in[k].alpha = MF_GRID_QS(alp[(k / 3) % 9]);
        in[k].gamma = MF_GRID_QS(gam[(k / 7) % 5]);
        in[k].fz = MF_GRID_QL(fzr[(k / 5) % 7] * fn);
        in[k].p = MF_GRID_QL(prr[(k / 11) % 6] * pn);
        in[k].vx = MF_GRID_QS(vxs[(k / 13) % 11]);
    }
}

#endif
