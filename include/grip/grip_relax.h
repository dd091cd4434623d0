/*
 * grip_relax.h - first-order relaxation-length transient of the slip
 * quantities (Pacejka, Tyre and Vehicle Dynamics, ch. 7.2: the "stretched
 * string" first-order model):
 *
 *     sigma_k dkappa'/dt + |vx| kappa' = |vx| kappa
 *     sigma_a dalpha'/dt + |vx| alpha' = |vx| alpha
 *
 * kappa', alpha' are the transient (lagged) slips that feed the steady-state
 * tire model in place of kappa, alpha. The lag is a distance, sigma, not a
 * time: the time constant is sigma / |vx|.
 *
 * Time step: the inputs (kappa, alpha, vx) are held over dt and the linear
 * ODE is solved exactly for that:
 *     x' += (1 - exp(-|vx| dt / sigma)) (x - x')
 * which is stable for every dt (never overshoots). |vx| is clamped to
 * [v_min, v_max]: v_min > 0 keeps the state following the input at standstill
 * (the lag length is then v_min dt per step); v_min = 0 freezes it.
 *
 * Usage (caller-owned state, no heap):
 *   grip_relax_state s;
 *   grip_relax_init(&s, &params, kappa0, alpha0);   (params must outlive s)
 *   each sample: grip_relax_step(&s, kappa, alpha, vx, dt, &kappa_t, &alpha_t);
 *
 * Fixed-point formats: everything is QS (Q15.16): slips [-], angles [rad],
 * lengths [m], speeds [m/s], time [s].
 * Selection by configuration: a caller that does not want the transient
 * skips the step (or sets sigma to sigma_min, which makes the lag
 * negligible at any speed above a walking pace).
 */
#ifndef GRIP_RELAX_H
#define GRIP_RELAX_H

#include <stdint.h>
#include "grip_types.h"

/* Largest time step accepted by grip_relax_step [s]. */
#define GRIP_RELAX_DT_MAX 10

typedef struct {
    grip_real_t sigma_kappa; /* QS [m] longitudinal relaxation length, in [0.001, 100] */
    grip_real_t sigma_alpha; /* QS [m] lateral relaxation length, in [0.001, 100]      */
    grip_real_t v_min;       /* QS [m/s] lower clamp of |vx|, in [0, v_max]            */
    grip_real_t v_max;       /* QS [m/s] upper clamp of |vx|, in (0, 200]              */
    grip_real_t kappa_max;   /* QS |kappa| clamp, in (0, 10]                           */
    grip_real_t alpha_max;   /* QS [rad] |alpha| clamp, in (0, 1.5]                    */
} grip_relax_params;

/* Caller-owned instance; read kappa_t/alpha_t, do not write (re-init). */
typedef struct {
    const grip_relax_params *p;
    grip_real_t kappa_t;     /* QS transient longitudinal slip                          */
    grip_real_t alpha_t;     /* QS [rad] transient slip angle                           */
    uint32_t magic;
} grip_relax_state;

#define grip_relax_init GRIP_TYPED(grip_relax_init)
#define grip_relax_step GRIP_TYPED(grip_relax_step)
#define grip_relax_params_check GRIP_TYPED(grip_relax_params_check)

/* GRIP_OK when the parameter set is valid, GRIP_ERR_PARAM / GRIP_ERR_NULL otherwise. */
grip_status_t grip_relax_params_check(const grip_relax_params *p);

/* Sets the state to (kappa0, alpha0), clamped to the valid range
 * (GRIP_WARN_CLAMPED). On error the state is unusable (GRIP_ERR_STATE later). */
grip_status_t grip_relax_init(grip_relax_state *s, const grip_relax_params *p,
                              grip_real_t kappa0, grip_real_t alpha0);

/* One step of length dt (0 <= dt <= GRIP_RELAX_DT_MAX s). Out-of-range inputs
 * are clamped (GRIP_WARN_CLAMPED). kappa_t / alpha_t receive the state after
 * the step (either may be NULL). On error the state is unchanged and the
 * outputs are zero. */
grip_status_t grip_relax_step(grip_relax_state *s, grip_real_t kappa, grip_real_t alpha,
                              grip_real_t vx, grip_real_t dt,
                              grip_real_t *kappa_t, grip_real_t *alpha_t);

#endif
