/*
 * grip_brush.h - brush-model family of tyre models (seed 000, ch. 2.3 and 5):
 *
 *   grip_fiala_eval     classic FIALA lateral force and aligning moment,
 *                       normalized form (2.60-2.66), full sliding for phi >= 3
 *   grip_brush_eval     brush model in braking/driving: adhesive mu_s and
 *                       sliding mu_d = mu_d0 - a_v Vs, n-th power pressure
 *                       (2.67-2.92); longitudinal force only
 *   grip_sakai_eval     Sakai's combined-slip brush model (2.93-2.125)
 *   grip_neofiala_eval  reduced Neo-FIALA, pure and combined slip (5.1-5.40):
 *                       generalized skewed parabola pressure, tread-base
 *                       deflection and twist, pressure skew and centre shift
 *                       from Fx and Mz, slip-speed dependent sliding
 *                       friction, camber through gamma_e
 *
 * Derivations, sign conventions, every modelling choice and the measured
 * accuracy: docs/brush-models.md. Float64 closed forms and the quadrature
 * reference: tools/grip_tools/reference/brush.py.
 *
 * Evaluation cost is bounded: every contact-patch integral is closed-form;
 * the implicit couplings of Neo-FIALA are eliminated exactly for a trial
 * adhesion boundary r_h, which leaves one scalar root solved by
 * GRIP_BRUSH_ROOT_ITERS Anderson-Bjorck steps on a tabulated variable
 * (at most 7 residual evaluations per call); powers |x|^n are a short
 * product chain per n (n <= 8) or a loop of GRIP_BRUSH_N_MAX steps (larger
 * n). No loop count depends on data.
 *
 * Sign convention (inputs and outputs): ISO-W as grip's Magic Formula:
 * kappa > 0 driving (Fx > 0), kappa < 0 braking (kappa = -1: locked wheel);
 * alpha > 0 gives Fy < 0 and, at small slip, Mz > 0 (aligning). Only |vx|
 * is used (sliding speed).
 *
 * Fixed-point formats (grip_types.h): QS for dimensionless values, angles
 * [rad], lengths [m], speeds [m/s] and the coefficients marked QS below
 * (several are stored per kN so that their values are well inside QS
 * resolution); QL for forces [N], moments [N m] and stiffnesses. Internally
 * every model runs normalized (forces / (mu_s Fz), moments / (mu_s Fz l)) in
 * QS and scales to QL at the end.
 *
 * Status: GRIP_OK; GRIP_WARN_CLAMPED when an input was outside its valid
 * range and was clamped (Fz below fz_min or above fz_max, |alpha| above
 * alpha_max, kappa outside [-1, kappa_max], |gamma| above gamma_max, |vx|
 * above v_max); errors leave *out all zero (rh = 1): GRIP_ERR_NULL,
 * GRIP_ERR_PARAM (the set fails grip_*_check_params: e.g. mu_s < mu_d, n out
 * of range, l or w <= 0, a coupling outside its valid range),
 * GRIP_ERR_INPUT (a non-finite input, or Fz <= 0).
 */
#ifndef GRIP_BRUSH_H
#define GRIP_BRUSH_H

#include <stdint.h>
#include "grip_types.h"

/* Supported pressure exponents n (integers). GRIP_BRUSH_N_MAX can be set
 * between 2 and 16 (-D or GRIP_CONFIG_FILE); exponents above 8 use a power
 * loop of GRIP_BRUSH_N_MAX steps instead of the product chains of n <= 8. */
#define GRIP_BRUSH_N_MIN 2
#ifndef GRIP_BRUSH_N_MAX
#define GRIP_BRUSH_N_MAX 8
#endif
#if GRIP_BRUSH_N_MAX < 2 || GRIP_BRUSH_N_MAX > 16
#error "GRIP_BRUSH_N_MAX must be in [2, 16]"
#endif

/* Anderson-Bjorck steps for the adhesion boundary (docs/brush-models.md,
 * "Root finding": measured worst-case truncation error over the valid
 * parameter range). Not a tuning knob: the documented accuracy holds for 6. */
#define GRIP_BRUSH_ROOT_ITERS 6
#if GRIP_BRUSH_ROOT_ITERS < 2
#error "GRIP_BRUSH_ROOT_ITERS must be at least 2"
#endif

/* Outputs of every model. */
typedef struct {
    grip_real_t fx;   /* QL [N]   longitudinal force (ISO-W)                   */
    grip_real_t fy;   /* QL [N]   lateral force (ISO-W)                        */
    grip_real_t mz;   /* QL [N m] aligning moment (ISO-W)                      */
    grip_real_t rh;   /* QS [-]   adhesion fraction l_h / l: 1 = no sliding,
                       *          0 = full sliding                             */
} grip_brush_out;

/* ---- FIALA (2.54-2.66) ---------------------------------------------- */
typedef struct {
    grip_real_t ky;        /* QL [N/rad] cornering stiffness Ky (2.61)          */
    grip_real_t mu;        /* QS [-]     friction coefficient                   */
    grip_real_t l;         /* QS [m]     contact length                          */
    grip_real_t fz_min;    /* QL [N]     loads in (0, fz_min) are clamped        */
    grip_real_t fz_max;    /* QL [N]                                             */
    grip_real_t alpha_max; /* QS [rad]   <= 1                                    */
} grip_fiala_params;

/* ---- brush, braking/driving (2.67-2.92) ------------------------------ */
typedef struct {
    grip_real_t kx;        /* QL [N]     Kx = Cx w l^2 / 2 (2.78)               */
    grip_real_t mu_s;      /* QS [-]     adhesive friction                       */
    grip_real_t mu_d0;     /* QS [-]     sliding friction at zero sliding speed  */
    grip_real_t a_v;       /* QS [s/m]   mu_d = mu_d0 - a_v Vs (2.85-2.87)       */
    int32_t n;             /* pressure exponent, GRIP_BRUSH_N_MIN..N_MAX (2.88) */
    grip_real_t fz_min;    /* QL [N]                                             */
    grip_real_t fz_max;    /* QL [N]                                             */
    grip_real_t kappa_max; /* QS [-]     driving slip limit (braking to -1)      */
    grip_real_t v_max;     /* QS [m/s]                                           */
} grip_brush_params;

/* ---- Sakai combined slip (2.93-2.125) -------------------------------- */
typedef struct {
    grip_real_t k;         /* QL [N]     K = C w l^2 / 2, both directions (2.115) */
    grip_real_t g_y;       /* QL [N/m]   lateral carcass stiffness, y0 = Fy/G_y  */
    grip_real_t mu_s;      /* QS [-]                                             */
    grip_real_t mu_d;      /* QS [-]                                             */
    grip_real_t l;         /* QS [m]                                             */
    grip_real_t fz_min;    /* QL [N]                                             */
    grip_real_t fz_max;    /* QL [N]                                             */
    grip_real_t alpha_max; /* QS [rad]                                           */
    grip_real_t kappa_max; /* QS [-]                                             */
} grip_sakai_params;

/* ---- reduced Neo-FIALA (5.1-5.40) ------------------------------------ */
typedef struct {
    grip_real_t l;         /* QS [m]        contact length                       */
    grip_real_t w;         /* QS [m]        contact width (camber geometry)      */
    grip_real_t kx;        /* QL [N]        Kx = Cx w l^2 / 2                     */
    grip_real_t ky;        /* QL [N/rad]    Ky = Cy w l^2 / 2 (5.8)               */
    grip_real_t mu_s;      /* QS [-]        adhesive friction                     */
    grip_real_t mu_d0;     /* QS [-]        sliding friction at zero slip speed   */
    grip_real_t a_v;       /* QS [s/m]      mu_d = mu_d0 - a_v Vs (5.35)          */
    int32_t n;             /* pressure exponent (5.6)                           */
    grip_real_t q0;        /* QS [-]        pressure skew at zero force           */
    grip_real_t c_q;       /* QS [1/kN]     q += c_q Fx (5.30)                    */
    grip_real_t c_qm;      /* QS [1/(kN m)] q += c_qm Mz (5.17)                   */
    grip_real_t c_xc;      /* QS [1/kN]     x_c/l += c_xc Fx (5.31)               */
    grip_real_t xi;        /* QS [m/kN]     x_c/l -= xi Mz / l^2 (5.18)           */
    grip_real_t eps;       /* QS [1/(kN m)] tread-base deflection (5.10, 5.13)   */
    grip_real_t g_mz;      /* QL [N m/rad]  tread-base twist (5.11); 0 = rigid   */
    grip_real_t a_x;       /* QL [N m]      Ax = fx w l^2 / 2 (5.27-5.28)         */
    grip_real_t c_gamma;   /* QS [-]        camber: equivalent slope per rad      */
    grip_real_t h;         /* QS [m]        camber: eta = 2 h w sin(gamma_e)/l^2  */
    grip_real_t g_my;      /* QL [N/rad]    camber: gamma_e = gamma + eta Fy_g/G_my; 0 = off */
    grip_real_t fz_min;    /* QL [N]                                             */
    grip_real_t fz_max;    /* QL [N]                                             */
    grip_real_t alpha_max; /* QS [rad]      <= 1                                 */
    grip_real_t kappa_max; /* QS [-]        <= 10                                */
    grip_real_t gamma_max; /* QS [rad]      <= 0.35                              */
    grip_real_t v_max;     /* QS [m/s]      <= 150                               */
} grip_neofiala_params;

#define grip_fiala_check_params GRIP_TYPED(grip_fiala_check_params)
#define grip_brush_check_params GRIP_TYPED(grip_brush_check_params)
#define grip_sakai_check_params GRIP_TYPED(grip_sakai_check_params)
#define grip_neofiala_check_params GRIP_TYPED(grip_neofiala_check_params)
/* GRIP_OK when the set lies in the valid range the accuracy is documented
 * for (docs/brush-models.md, "Valid range"), GRIP_ERR_PARAM otherwise,
 * GRIP_ERR_NULL for p == NULL. */
grip_status_t grip_fiala_check_params(const grip_fiala_params *p);
grip_status_t grip_brush_check_params(const grip_brush_params *p);
grip_status_t grip_sakai_check_params(const grip_sakai_params *p);
grip_status_t grip_neofiala_check_params(const grip_neofiala_params *p);

#define grip_fiala_check_params_detail GRIP_TYPED(grip_fiala_check_params_detail)
#define grip_brush_check_params_detail GRIP_TYPED(grip_brush_check_params_detail)
#define grip_sakai_check_params_detail GRIP_TYPED(grip_sakai_check_params_detail)
#define grip_neofiala_check_params_detail GRIP_TYPED(grip_neofiala_check_params_detail)
/* The same checks, in the same order; on GRIP_ERR_PARAM *detail (may be
 * NULL) names the first member that failed and the rule it breaks. */
grip_status_t grip_fiala_check_params_detail(const grip_fiala_params *p, grip_check_detail_t *detail);
grip_status_t grip_brush_check_params_detail(const grip_brush_params *p, grip_check_detail_t *detail);
grip_status_t grip_sakai_check_params_detail(const grip_sakai_params *p, grip_check_detail_t *detail);
grip_status_t grip_neofiala_check_params_detail(const grip_neofiala_params *p, grip_check_detail_t *detail);

#define grip_fiala_eval GRIP_TYPED(grip_fiala_eval)
/* FIALA: Fy and Mz for slip angle alpha [rad] at load fz [N]; fx = 0. */
grip_status_t grip_fiala_eval(const grip_fiala_params *p, grip_real_t alpha, grip_real_t fz,
                              grip_brush_out *out);

#define grip_brush_eval GRIP_TYPED(grip_brush_eval)
/* Brush model, pure longitudinal slip kappa at load fz and speed vx;
 * fy = mz = 0. */
grip_status_t grip_brush_eval(const grip_brush_params *p, grip_real_t kappa, grip_real_t fz,
                              grip_real_t vx, grip_brush_out *out);

#define grip_sakai_eval GRIP_TYPED(grip_sakai_eval)
/* Sakai combined slip: kappa, alpha [rad], fz [N]. */
grip_status_t grip_sakai_eval(const grip_sakai_params *p, grip_real_t kappa, grip_real_t alpha,
                              grip_real_t fz, grip_brush_out *out);

#define grip_neofiala_eval GRIP_TYPED(grip_neofiala_eval)
/* Neo-FIALA, pure or combined slip: kappa, alpha [rad], gamma [rad],
 * fz [N], vx [m/s]. Validates the parameter set on every call; an ECU task
 * evaluating one set many times uses grip_neofiala_prepare once and
 * grip_neofiala_eval_model per call (same results, bit for bit). */
grip_status_t grip_neofiala_eval(const grip_neofiala_params *p, grip_real_t kappa,
                                 grip_real_t alpha, grip_real_t gamma, grip_real_t fz,
                                 grip_real_t vx, grip_brush_out *out);

/* A validated Neo-FIALA parameter set with its load-independent constants
 * (caller-owned; fill it with grip_neofiala_prepare, do not edit it). */
typedef struct {
    grip_neofiala_params p;
    grip_real_t c;        /* QS (n + 1) / n                          */
    grip_real_t inv1;     /* QS 1 / (n + 1)                          */
    grip_real_t inv2;     /* QS 1 / (n + 2)                          */
    grip_real_t inv3;     /* QS 1 / (n + 3)                          */
    grip_real_t kyg;      /* QS Ky l / G_mz                          */
    grip_real_t eky;      /* QS eps l Ky                             */
    grip_real_t cam_a;    /* QS A_gamma of gamma_e (5.39-5.40)       */
    uint32_t magic;       /* set by grip_neofiala_prepare            */
} grip_neofiala_model;

#define grip_neofiala_prepare GRIP_TYPED(grip_neofiala_prepare)
/* Validates p (as grip_neofiala_check_params) and fills *m. GRIP_OK,
 * GRIP_ERR_NULL or GRIP_ERR_PARAM (then *m is marked invalid). */
grip_status_t grip_neofiala_prepare(const grip_neofiala_params *p, grip_neofiala_model *m);

#define grip_neofiala_eval_model GRIP_TYPED(grip_neofiala_eval_model)
/* As grip_neofiala_eval on a prepared set; GRIP_ERR_STATE when *m was not
 * prepared successfully. */
grip_status_t grip_neofiala_eval_model(const grip_neofiala_model *m, grip_real_t kappa,
                                       grip_real_t alpha, grip_real_t gamma, grip_real_t fz,
                                       grip_real_t vx, grip_brush_out *out);

#endif /* GRIP_BRUSH_H */
