/*
 * est_internal.h - constants of the estimator (lib/est), shared by its
 * files. Every value here is mirrored in tools/grip_tools/reference/est.py (the
 * float64 reference) and documented in docs/estimator.md.
 */
#ifndef GRIP_EST_INTERNAL_H
#define GRIP_EST_INTERNAL_H

#include "grip/grip_est.h"
#include "arith.h"

#define EST_MAGIC 0x45535431u  /* "EST1" */

/* Keeps a helper of the step out of the step's stack frame: its locals then
 * take stack only while it runs, not under the Magic Formula evaluations
 * (M0+ worst-case stack 1024 -> 992 B with kf_predict and lateral_outputs,
 * docs/estimator.md "Cost"). GCC and clang; other compilers inline as they
 * see fit (the stack budget is measured with arm-none-eabi-gcc). */
#if defined(__GNUC__)
#define EST_NOINLINE __attribute__((noinline))
#else
#define EST_NOINLINE
#endif

#define EST_G        9.80665
#define EST_V_ON     3.0     /* m/s: lateral observer starts above          */
#define EST_V_OFF    2.5     /* m/s: and stops below                         */
#define EST_V_STAND  0.3     /* m/s: standstill                               */
#define EST_V_EXC    5.0     /* m/s: mu adapts only above                     */
#define EST_HOLD_T   0.05    /* s: a missing input is held this long          */
#define EST_NOWHEEL_T 0.5    /* s: vx stays valid this long without wheels    */
#define EST_DELTA_MAX 0.7    /* rad: road-wheel angle limit (steering at lock) */
#define EST_WS_MAX   120.0   /* m/s: wheel-speed range                        */
#define EST_YAW_MAX  2.5     /* rad/s: gyro range used                        */
#define EST_ACC_MAX  15.0    /* m/s^2: accelerometer range used               */
#define EST_AX_TH    0.3     /* m/s^2: braking / driving wheel selection       */
#define EST_K_HI     5.0     /* 1/s: wheel-speed gain of the vx filter         */
#define EST_WHEEL_DEV 0.15   /* a wheel 15 % (+0.5 m/s) off the vehicle is locked / spinning */
/* neither braking nor driving: trusted wheels spread wider than
 * SPREAD_REL |vx| + SPREAD_ABS move the reference from their mean towards
 * the cluster the odd wheel left (fully at twice that spread) */
#define EST_SPREAD_REL 0.01
#define EST_SPREAD_ABS 0.1   /* m/s */
#define EST_K_LO     0.5     /* 1/s: gain when the wheels disagree             */
#define EST_K_MID    1.5     /* 1/s: all wheels agree, but not with the prediction */
/* braking slips every wheel: wheels below the prediction pull vx at K_SLIP */
#define EST_K_SLIP   0.2     /* 1/s */
/* ax offset (unconfigured grade, accelerometer bias), learned from trusted
 * wheels: second-order complementary filter with vx */
#define EST_K_OFF    1.0     /* 1/s^2 */
#define EST_AX_OFF_MAX 1.5   /* m/s^2 */
/* every wheel locked or spinning while |ax| >= DR_AX: dead reckoning on ax,
 * vx valid for DR_T, beta not valid */
#define EST_DR_AX    0.5     /* m/s^2 */
#define EST_DR_T     2.0     /* s */
/* braking with a wheel at |kappa| >= LOCK_K (locked, or cycled by an ABS
 * past the tire's peak): the ax update measures mu without a speed
 * reference, noise R_LOCK (scaled: 1.5 m/s^2) */
#define EST_LOCK_K   0.15
#define EST_R_LOCK   9.0
#define EST_MU_MIN   0.1
#define EST_MU_MAX   1.2
#define EST_MU_INIT  1.0
/* excitation: a tire at EXC_U of its own friction (mu = 1); at 0.5 the gate
 * opened at the snow sine-with-dwell onset only once the truth's front axle
 * was at 90 % of its limit */
#define EST_EXC_U    0.2     /* utilization that counts as excitation          */
#define EST_EXC_A    1.0     /* m/s^2: and at least this much acceleration     */
#define EST_LIM_TAU  0.15    /* s: lag of the linear yaw reference in the limit test */
#define EST_LIM_A    2.0     /* m/s^2: limit test needs this much acceleration  */
#define EST_LIM_REL  0.15    /* limit: |r - r_lin| > 0.15 |r_lin| + 0.03 rad/s  */
#define EST_LIM_ABS  0.03
#define EST_LIM_T    0.2     /* s: ... for this long                              */
/* low-friction detection at the understeer limit: yaw rate below the lagged
 * reference by the share US_D (reference above US_R rad/s) for LIM_T; the
 * front axle's friction in use over the utilization the deficit implies,
 * min(US_UMAX, US_U0 + US_U1 deficit), bounds mu from above when it is below
 * US_ZMAX */
#define EST_US_D     0.15
#define EST_US_R     0.02
#define EST_US_U0    0.3
#define EST_US_U1    1.4
#define EST_US_UMAX  0.85
#define EST_US_ZMAX  0.8
/* withdrawal of that bound: mu held down by it and unconfirmed since
 * (P_mu > EST_P_CONF, i.e. mu_conf < 0.5) goes back to its value before the
 * bound once the bound's own test has said "no deficit" (-LIM_REL < deficit
 * < US_D) in steady cornering (|ax| and |dvy/dt| = |ay - r vx| below B_AX)
 * for LIM_T at a front friction in use between REL_K and 1 / REL_K of the
 * one at which the bound was last set */
#define EST_REL_K    0.8
#define EST_P_CONF   (((EST_CONF_S0 - 0.05) / EST_S_MU) * ((EST_CONF_S0 - 0.05) / EST_S_MU))
#define EST_G_MIN    0.05    /* floor of the slope factor sqrt(1 - u)          */
/* tire relaxation: the tires work at the slip angle lagged by the relaxation
 * length, sigma d(alpha_t)/dt + |vx| alpha_t = |vx| alpha; sigma at the
 * axle's static load from the tire file (C_alpha / LATERAL_STIFFNESS, else
 * the MF 5.2 PTY1 / PTY2 form, else no lag), in proportion to the wheel's
 * load, at least SIG_MIN (the axle's at most SIG_MAX); exponent |vx| dt / sigma capped at RLX_A_MAX
 * (exp(-16) is below one QS unit) */
#define EST_SIG_MIN  0.02    /* m */
#define EST_SIG_MAX  5.0     /* m: a file's stiffnesses far off give at most this */
#define EST_RLX_A_MAX 16.0
/* scaled units of the covariance (state i in units of S_i) */
#define EST_S_VY     0.05    /* m/s   */
#define EST_S_R      0.005   /* rad/s */
#define EST_S_MU     0.02    /* -     */
#define EST_S_B      0.001   /* rad/s (gyro bias) */
#define EST_S_AY     0.5     /* m/s^2 (lateral and longitudinal acceleration) */
/* measurement noise (scaled units^2): yaw 0.006 rad/s, ay 0.4, ax 0.5 m/s^2 */
#define EST_R_YAW    1.44
#define EST_R_AY     0.64
#define EST_R_AX     1.0
/* continuous process noise per second (scaled units^2 / s):
 * vy' 0.5 m/s^2 (kinematic: ay error, roll and bank), r' 0.3 rad/s^2, mu 0.05 /sqrt(s) */
#define EST_Q_VY     100.0
#define EST_Q_R      3600.0
#define EST_Q_MU     6.25
#define EST_Q_B      0.25    /* gyro bias random walk 0.0005 rad/s /sqrt(s) */
/* initial variances and bounds (scaled units^2) */
#define EST_P0_VY    36.0
#define EST_P0_R     16.0
#define EST_P0_MU    225.0
#define EST_P0_B     100.0   /* gyro bias sigma 0.01 rad/s at start */
#define EST_B_MAX    0.05    /* rad/s: bound of the gyro bias state */
#define EST_U_R0     0.8     /* ay noise grows from R_AY at this utilization ... */
#define EST_R_LIM    9.0     /* ... by R_LIM R_AY at the most-used tire's 1 ... */
#define EST_R_AXLE   290.0   /* ... and by R_AXLE R_AY at an axle's mean 1 */
#define EST_B_U      0.5     /* gyro bias adapts below this model utilization ... */
#define EST_B_A      4.0     /* ... below this |ay| [m/s^2] ... */
#define EST_B_AX     1.0     /* ... below this |ax| [m/s^2] ... */
#define EST_B_RACC   2.0     /* ... and below this model yaw acceleration [rad/s^2] */
#define EST_VY_K     1.0     /* |vy| <= VY_K |vx| + 1 m/s (sideslip up to ~45 deg: spins) */
#define EST_P_MIN    0.01
#define EST_P_MAX    400.0
#define EST_H_MAX_VY 5.0     /* bounds of the measurement row (keeps h P h' < 32768) */
#define EST_H_MAX    2.0
#define EST_NU_SIGMA 4.0     /* innovations clamped to 4 sigma */
#define EST_CONF_S0  0.15    /* mu confidence 1 at sigma <= 0.05, 0 at >= 0.15 */
/* model-consistency (misfit) check, docs/estimator.md: two statistics
 * low-passed over MF_TAU: the ay update's normalized innovation squared
 * (clamped to 16 by the 4-sigma innovation clamp, so it stays in Q15.16) and
 * the share of time [0, 1] the model claims saturated tires (utilization
 * >= SAT_U) while the mu-independent friction-limit test does not fire */
#define EST_MF_TAU   2.0     /* s: low-pass time constant (window) of both     */
#define EST_NIS_HI   3.84    /* misfit above: chi-square(1) 95 % point         */
#define EST_NIS_LO   1.0     /* ... cleared below: a consistent filter's mean  */
#define EST_SAT_U    0.95    /* model utilization counted as saturated         */
#define EST_SAT_HI   0.7     /* misfit above: saturated 70 % of the window     */
#define EST_SAT_LO   0.1     /* ... cleared below (with NIS below NIS_LO)      */
#define EST_CONF_MISFIT 0.45 /* mu_conf cap while misfit (below V_MU's 0.5)    */
#define EST_SAT_MU   0.1     /* ... and from when the saturation share rises    */
#define EST_SAT_MU_LO 0.05   /* above this until it falls below this            */
/* the axle forces' yaw balance (docs/estimator.md): the yaw moment the
 * model lacks (the yaw-rate update's correction of the predicted r as a yaw
 * acceleration, at most MB_RACC rad/s^2, times Iz / l) moves force from one
 * axle to the other at the outputs, low-passed over MB_TAU s; not while
 * |ax| >= MB_AX m/s^2 (the model's left / right Fx moment errs there too) */
#define EST_MB_TAU   0.05
#define EST_MB_RACC  20.0
#define EST_MB_AX    1.0
/* ... and the lateral balance: the lateral force the model lacks after the
 * updates (mass times the measured ay less the model's at the updated
 * state), low-passed over SB_TAU s, in the axles' static shares (no yaw
 * moment); not while |ax| >= MB_AX */
#define EST_SB_TAU   0.02
/* mu's column of the Jacobians (docs/estimator.md, "mu's secant"): the
 * secant of mu F0(alpha / mu) from mu down to mu - dmu, dmu = SEC_K
 * sigma_mu within [SEC_MIN, mu - mu_floor] (the friction in use), on the
 * force shape tabulated at init (grip_est_t.fy_shape); no column where the shape is below
 * SHAPE_F_MIN (the origin: 0 / 0, and the column is 0 there anyway) */
#define EST_SEC_K    3.0     /* the prior 1.0 +- 0.3 puts snow 2.3 sigma away */
#define EST_SEC_MIN  0.02
#define EST_SHAPE_F_MIN 0.01
/* while the car is at its limit (the limit test) and mu is not held by the
 * understeer bound, the ay noise's utilization is the model's at mu +
 * AY_U_K sigma_mu: with mu still too high the model sits at its own limit,
 * R is up to 150 x and the ay update cannot pull mu down (snow sine with
 * dwell) */
#define EST_AY_U_K   0.5
/* the balances' memory is cleared at the understeer bound's cut only when
 * the cut exceeds CUT_CLEAR: small cuts re-armed the bound every few steps
 * and the balances never built up (step steer snow) */
#define EST_CUT_CLEAR 0.05

#endif
