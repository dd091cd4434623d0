/*
 * grip_mf_thermal.h - temperature-dependent Magic Formula with a tire
 * surface temperature state (seed 000, chapter 4, eqs. 4.1-4.18).
 *
 * Thermal state:  dT/dt = q / W - kappa (T - T_R)                  (4.6)
 *                 q = sqrt(Fx^2 + Fy^2) Vs                         (4.2, 4.3)
 *                 Vs = V sqrt((S cos alpha)^2 + sin^2 alpha)       (4.4, 4.5)
 *                 (= sqrt((V cos alpha - re omega)^2 + V^2 sin^2 alpha)
 *                  with re omega = V cos alpha (1 - S))
 * Pure slip, i = x (p = S + shx) or y (p = alpha + shy):           (4.11-4.14)
 *   F_i0 = D_i(T) sin[C_i atan{B_i p - E_i (B_i p - atan(B_i p))}] + Sv_i
 *   D_i(T) = D_i0 (1 + a_i (T - T0)),  K_i(T) = K_i0 (1 + b_i (T - T0)),
 *   B_i = K_i(T) / (C_i D_i(T))
 * Combined slip:  Fx = Fx0 G_xa(alpha),  Fy = Fy0 G_yS(S) + Sv_yS   (4.15-4.18)
 *   G_xa = cos[C_xa atan{B_xa a_s - E_xa (B_xa a_s - atan(B_xa a_s))}] / (same at
 *          a_s = shxa), a_s = alpha + shxa; G_yS likewise in S_s = S + shys.
 * Force coefficients (D_i0, K_i0, Sv) are given at the load fz0 and scale
 * with fz / fz0. S is the seed's slip ratio (positive braking); Fx > 0 is a
 * braking force for S > 0, Fy has the sign of alpha + shy.
 *
 * Time step: forces and q at the temperature at the start of the step, q
 * held over dt, and the exact solution of the linear ODE for that:
 *   T += phi (q / W - kappa (T - T_R)),  phi = (1 - exp(-kappa dt)) / kappa,
 * which is stable for every dt (for constant q, T relaxes monotonically
 * toward T_R + q / (kappa W); the one-step lag of q(T) is first order in dt);
 * T is then limited to [t_min, t_max].
 *
 * Usage (CMSIS style: caller-owned state, no heap):
 *   grip_mf_thermal_state s;
 *   grip_mf_thermal_init(&s, &params, t_init);     (params must outlive s)
 *   each sample: grip_mf_thermal_step(&s, &inputs, dt, &out);
 *
 * Fixed-point formats: QS = Q15.16 for temperatures [degC], angles [rad],
 * slip, speeds [m/s], time [s], dimensionless coefficients and the
 * temperature coefficients a_i, b_i [1/K] and kappa [1/s]; QL = Q23.8 for
 * forces and force coefficients [N, N/rad, N per unit slip], heat capacity
 * W [J/K] and heat flux q [W]. Internally the Magic Formula runs normalized
 * by fz0 (QS) and is scaled by the load at the end; q = F Vs is QL (up to
 * 8.3 MW) and q / W a QL / QL ratio [K/s].
 */
#ifndef GRIP_MF_THERMAL_H
#define GRIP_MF_THERMAL_H

#include <stdint.h>
#include "grip_types.h"

/* Largest time step accepted by grip_mf_thermal_step [s]. */
#define GRIP_MF_THERMAL_DT_MAX 10

typedef struct {
    grip_real_t fz0;        /* QL [N]   load of the force coefficients              */
    grip_real_t t0;         /* QS [degC] temperature of the force coefficients      */
    /* longitudinal, pure slip */
    grip_real_t dx0;        /* QL [N]   peak factor at T0                           */
    grip_real_t kx0;        /* QL [N]   slip stiffness BCD at T0 (per unit slip)    */
    grip_real_t cx;         /* QS       shape factor, 0 < C < 2                      */
    grip_real_t ex;         /* QS       curvature factor                             */
    grip_real_t shx;        /* QS       horizontal shift (slip)                      */
    grip_real_t svx;        /* QL [N]   vertical shift                               */
    grip_real_t ax;         /* QS [1/K] temperature coefficient of Dx                */
    grip_real_t bx;         /* QS [1/K] temperature coefficient of Kx                */
    /* lateral, pure slip */
    grip_real_t dy0;        /* QL [N]                                                */
    grip_real_t ky0;        /* QL [N/rad] cornering stiffness at T0                  */
    grip_real_t cy;         /* QS                                                    */
    grip_real_t ey;         /* QS                                                    */
    grip_real_t shy;        /* QS [rad]                                              */
    grip_real_t svy;        /* QL [N]                                                */
    grip_real_t ay;         /* QS [1/K]                                              */
    grip_real_t by;         /* QS [1/K]                                              */
    /* combined-slip weighting functions */
    grip_real_t bxa;        /* QS [1/rad]                                            */
    grip_real_t cxa;        /* QS, 0 < C <= 1 (keeps G > 0)                          */
    grip_real_t exa;        /* QS                                                    */
    grip_real_t shxa;       /* QS [rad]                                              */
    grip_real_t bys;        /* QS (per unit slip)                                    */
    grip_real_t cys;        /* QS, 0 < C <= 1                                        */
    grip_real_t eys;        /* QS                                                    */
    grip_real_t shys;       /* QS (slip)                                             */
    grip_real_t svys;       /* QL [N]                                                */
    /* thermal */
    grip_real_t w;          /* QL [J/K] heat capacity of the surface layer           */
    grip_real_t kappa;      /* QS [1/s] lambda A / W, 0 <= kappa <= 100              */
    /* valid ranges: inputs outside are clamped (GRIP_WARN_CLAMPED) */
    grip_real_t fz_max;     /* QL [N]   load in [0, fz_max], fz_max <= 100 fz0       */
    grip_real_t alpha_max;  /* QS [rad] |alpha| <= alpha_max <= 1.5                  */
    grip_real_t slip_max;   /* QS       |S| <= slip_max <= 2                         */
    grip_real_t v_max;      /* QS [m/s] V in [0, v_max], v_max <= 200                */
    grip_real_t t_min;      /* QS [degC] temperatures (state, road) in [t_min, t_max] */
    grip_real_t t_max;      /* QS [degC]                                             */
} grip_mf_thermal_params;

typedef struct {
    grip_real_t v;          /* QS [m/s] wheel centre speed, >= 0                    */
    grip_real_t alpha;      /* QS [rad] slip angle                                  */
    grip_real_t slip;       /* QS       slip ratio S (positive braking)             */
    grip_real_t fz;         /* QL [N]   vertical load                               */
    grip_real_t t_road;     /* QS [degC] road surface temperature T_R               */
} grip_mf_thermal_inputs;

typedef struct {
    grip_real_t fx;         /* QL [N]   at the temperature at the start of the step */
    grip_real_t fy;         /* QL [N]                                               */
    grip_real_t q;          /* QL [W]   heat flux F Vs                              */
    grip_real_t vs;         /* QS [m/s] slip speed                                  */
    grip_real_t t;          /* QS [degC] surface temperature after the step         */
} grip_mf_thermal_output;

/* Caller-owned instance. Read the temperature as state.t; do not write the
 * fields (re-initialise instead). */
typedef struct {
    const grip_mf_thermal_params *p;
    grip_real_t t;          /* QS [degC] current surface temperature                */
    /* derived at init */
    grip_real_t dxn, kxn, svxn;   /* dx0, kx0, svx over fz0 (QS)                    */
    grip_real_t dyn, kyn, svyn;   /* dy0, ky0, svy over fz0 (QS)                    */
    grip_real_t svysn;            /* svys over fz0 (QS)                             */
    grip_real_t gx_den, gy_den;   /* weighting-function denominators (QS)           */
    uint32_t magic;
} grip_mf_thermal_state;

#define grip_mf_thermal_init GRIP_TYPED(grip_mf_thermal_init)
/* Validate params, precompute, and set T = t_init [degC, QS]. Returns GRIP_OK,
 * GRIP_WARN_CLAMPED (t_init limited to [t_min, t_max]), GRIP_ERR_NULL,
 * GRIP_ERR_PARAM (invalid set: the state is marked uninitialised) or
 * GRIP_ERR_INPUT (t_init non-finite; state uninitialised). */
grip_status_t grip_mf_thermal_init(grip_mf_thermal_state *s, const grip_mf_thermal_params *p,
                                   grip_real_t t_init);

#define grip_mf_thermal_step GRIP_TYPED(grip_mf_thermal_step)
/* Forces at the current temperature, heat flux, then advance T by dt [s, QS,
 * 0 <= dt <= GRIP_MF_THERMAL_DT_MAX]. Returns GRIP_OK, GRIP_WARN_CLAMPED (an
 * input clamped to its range, or T limited to [t_min, t_max]),
 * GRIP_ERR_NULL, GRIP_ERR_STATE (not initialised) or GRIP_ERR_INPUT
 * (non-finite input, dt out of range). On error *out is zero and the state
 * is unchanged. */
grip_status_t grip_mf_thermal_step(grip_mf_thermal_state *s, const grip_mf_thermal_inputs *in,
                                   grip_real_t dt, grip_mf_thermal_output *out);

#define grip_mf_thermal_heat_step GRIP_TYPED(grip_mf_thermal_heat_step)
/* Advance the surface temperature by one step of (4.6) with a heat flux q
 * [W, QL, >= 0] the caller supplies (e.g. sqrt(Fx^2 + Fy^2) Vs from another
 * tire model, such as the full Magic Formula of grip_mf.h), road temperature
 * t_road [degC, QS, limited to [t_min, t_max]] and 0 <= dt <=
 * GRIP_MF_THERMAL_DT_MAX: the same exact step grip_mf_thermal_step takes
 * with its own q. *t_out is the new temperature. Returns GRIP_OK,
 * GRIP_WARN_CLAMPED, GRIP_ERR_NULL, GRIP_ERR_STATE or GRIP_ERR_INPUT
 * (non-finite or negative q, non-finite t_road, dt out of range); on error
 * *t_out is zero and the state is unchanged. */
grip_status_t grip_mf_thermal_heat_step(grip_mf_thermal_state *s, grip_real_t q, grip_real_t t_road,
                                        grip_real_t dt, grip_real_t *t_out);

#define grip_mf_thermal_forces GRIP_TYPED(grip_mf_thermal_forces)
/* Forces [N, QL] at a given surface temperature t [degC, QS] (limited to
 * [t_min, t_max]), without touching the state's temperature. in->t_road is
 * not used. Same statuses as grip_mf_thermal_step; on error *fx = *fy = 0. */
grip_status_t grip_mf_thermal_forces(const grip_mf_thermal_state *s, const grip_mf_thermal_inputs *in,
                                     grip_real_t t, grip_real_t *fx, grip_real_t *fy);

#endif /* GRIP_MF_THERMAL_H */
