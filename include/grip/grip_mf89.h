/*
 * grip_mf89.h - 1989-style lateral Magic Formula with coefficients a0..a17
 * (seed 000, eqs. 3.1-3.9) and its identification constraints (3.10-3.16).
 *
 *   Fy  = D sin[C atan{B x - E (B x - atan(B x))}] + Sv,   x = alpha + Sh
 *   C   = a0
 *   D   = (a1 Fz^2 + a2 Fz) (1 - a15 gamma^2)
 *   BCD = a3 sin(2 atan(Fz / a4)) (1 - a5 |gamma|),        B = BCD / (C D)
 *   E   = (a6 Fz + a7) (1 - (a16 gamma + a17) sgn(alpha + Sh))
 *   Sh  = (a8 Fz + a9 + a10 gamma) Fz
 *   Sv  = a11 Fz^2 + a12 Fz + (a13 Fz^2 + a14 Fz) gamma
 *
 * The coefficients keep the seed's units (Fz in kN, alpha, gamma, Sh in deg,
 * forces in N); the function's inputs and output are SI like the rest of
 * grip (rad, N). Signs re-derived from the extraction: docs/mf89-thermal.md.
 * Fy has the sign of alpha + Sh (positive cornering stiffness, JASO axes).
 *
 * Fixed-point formats (grip_types.h): a[i] QS (so |a[i]| < 32768), fz_max
 * QL [N], alpha_max and gamma_max QS [rad]; inputs alpha, gamma QS [rad],
 * fz QL [N]; output fy QL [N]. Internally the model runs in kN and rad.
 */
#ifndef GRIP_MF89_H
#define GRIP_MF89_H

#include <stdint.h>
#include "grip_types.h"

#define GRIP_MF89_NCOEF 18

typedef struct {
    grip_real_t a[GRIP_MF89_NCOEF]; /* a0..a17, seed units, QS                   */
    grip_real_t fz_max;             /* QL [N]:   valid load range [0, fz_max]      */
    grip_real_t alpha_max;          /* QS [rad]: valid |alpha| <= alpha_max        */
    grip_real_t gamma_max;          /* QS [rad]: valid |gamma| <= gamma_max        */
} grip_mf89_params;

/* Bits of the constraint mask (one per seed equation). */
#define GRIP_MF89_C_3_10 (1u << 0)  /* 1.0 < C < 1.65                             */
#define GRIP_MF89_C_3_11 (1u << 1)  /* E < 1 over the load and camber range       */
#define GRIP_MF89_C_3_12 (1u << 2)  /* a17 = 0                                    */
#define GRIP_MF89_C_3_13 (1u << 3)  /* Sh = Sv = 0 at zero camber: a8=a9=a11=a12=0 */
#define GRIP_MF89_C_3_14 (1u << 4)  /* |dSh/dgamma| = |a10 Fz| <= 0.1 deg/deg      */
#define GRIP_MF89_C_3_15 (1u << 5)  /* |dSv/dgamma| < 25 Fz N/deg (Fz in kN)       */
#define GRIP_MF89_C_3_16 (1u << 6)  /* a15 > 0                                    */

#define grip_mf89_check_params GRIP_TYPED(grip_mf89_check_params)
/* Is the set evaluable over its valid range? GRIP_OK or GRIP_ERR_PARAM
 * (0 < C < 2, a4 > 0, D > 0 and BCD > 0 over the load and camber range,
 * positive limits with fz_max <= 30 kN, alpha_max <= 1.5 rad, gamma_max
 * <= 0.5 rad), GRIP_ERR_NULL. Does not test the identification
 * constraints (grip_mf89_check_constraints). */
grip_status_t grip_mf89_check_params(const grip_mf89_params *p);

#define grip_mf89_fy GRIP_TYPED(grip_mf89_fy)
/* Lateral force for slip angle alpha [rad], load fz [N], camber gamma [rad].
 * Returns GRIP_OK; GRIP_WARN_CLAMPED if an input was outside the valid range
 * (fz < 0 is taken as 0, i.e. a lifted wheel, Fy = 0); GRIP_ERR_NULL,
 * GRIP_ERR_PARAM (see grip_mf89_check_params) or GRIP_ERR_INPUT (non-finite)
 * with *fy = 0. */
grip_status_t grip_mf89_fy(const grip_mf89_params *p, grip_real_t alpha, grip_real_t fz,
                           grip_real_t gamma, grip_real_t *fy);

#define grip_mf89_check_constraints GRIP_TYPED(grip_mf89_check_constraints)
/* The seed's identification constraints (3.10)-(3.16) for data with loads in
 * [fz_lo, fz_hi] (QL, N, 0 < fz_lo <= fz_hi) and |gamma| <= p->gamma_max.
 * *violated receives the GRIP_MF89_C_* bits of every violated constraint.
 * Returns GRIP_OK when none is violated, GRIP_ERR_PARAM when one is (or the
 * set is not evaluable), GRIP_ERR_INPUT for a bad load range, GRIP_ERR_NULL. */
grip_status_t grip_mf89_check_constraints(const grip_mf89_params *p, grip_real_t fz_lo,
                                          grip_real_t fz_hi, uint32_t *violated);

#endif /* GRIP_MF89_H */
