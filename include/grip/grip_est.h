/*
 * grip_est.h - bounded-time onboard state estimator (grip issue 5).
 *
 * One call of grip_est_step per input sample (100 .. 1000 Hz) turns the ESC
 * sensor set (grip_input_sample_t, grip_signals.h) into:
 *   longitudinal speed, lateral speed and sideslip angle beta, the
 *   yaw-rate reference of the linear bicycle model with stability factor
 *   (seed 000, eqs 2.13-2.19), per wheel slip ratio, slip angle, vertical
 *   load (longitudinal and lateral load transfer), Fx, Fy, Mz and friction
 *   utilization, per axle Fy and utilization, the road friction mu with a
 *   confidence, an understeer / oversteer indication and the front-axle
 *   lateral force margin (for active front steering).
 * Every output has a validity bit in grip_est_output_t.valid (and a flag
 * word saying why not); invalid outputs are finite (usually 0).
 *
 * Method (docs/estimator.md): a 4-state extended Kalman filter
 * x = [vy, r, mu, yaw-rate sensor bias] with the tire model of each axle in the process model,
 * scalar sequential measurement updates of yaw rate, lateral and
 * longitudinal acceleration in Joseph form, covariance kept in scaled
 * units so that the same code runs in Q15.16; longitudinal speed from a
 * complementary filter of ax and the wheel speeds. Fixed dimensions, no
 * data-dependent loops, no heap: worst-case time is the time of every step.
 *
 * Axes: ISO 8855 (x forward, y left, z up); wheels FL FR RL RR (0..3);
 * axles front, rear (0, 1). Tire forces are in the wheel (ISO-W) frame:
 * alpha > 0 gives Fy < 0, kappa > 0 is driving.
 *
 * Formats (fixed build): speeds, angles, lengths, slips, utilization, mu,
 * times QS; forces, moments, masses, inertia, stiffnesses QL.
 */
#ifndef GRIP_EST_H
#define GRIP_EST_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_mf.h"
#include "grip_signals.h"

/* ---- tire model of an axle (tagged union: new models plug in here) ---- */
typedef enum {
    GRIP_EST_TIRE_NONE = 0,
    GRIP_EST_TIRE_MF = 1,     /* grip_mf_eval (combined slip), implemented           */
    GRIP_EST_TIRE_BRUSH = 2   /* Neo-FIALA (grip_brush.h): reserved, GRIP_ERR_PARAM now */
} grip_est_tire_kind_t;

typedef struct {
    int32_t kind;                        /* grip_est_tire_kind_t */
    union {
        const grip_mf_params *mf;        /* kind == GRIP_EST_TIRE_MF (fitted LEFT convention, */
                                         /* mirrored by the estimator on the right wheels)   */
        const void *brush;               /* kind == GRIP_EST_TIRE_BRUSH                        */
    } model;
} grip_est_tire_t;

/* ---- vehicle configuration (given once to grip_est_init) ---- */
typedef struct {
    grip_real_t mass;          /* QL kg, (0, 60000]                        */
    grip_real_t iz;            /* QL kg m^2 yaw inertia, (0, 2e5]          */
    grip_real_t lf;            /* QS m CG to front axle, (0, 10]           */
    grip_real_t lr;            /* QS m CG to rear axle, (0, 10]            */
    grip_real_t track_f;       /* QS m front track width, (0, 4]           */
    grip_real_t track_r;       /* QS m rear track width, (0, 4]            */
    grip_real_t h_cg;          /* QS m CG height, [0, 3]                   */
    grip_real_t steer_ratio;   /* QS steering-wheel / road-wheel angle, [1, 100] */
    grip_real_t wheel_radius;  /* QS m effective rolling radius the wheel speeds are
                                * calibrated with, (0, 2]; checked and kept, not used
                                * by this version (wheel speeds arrive in m/s)     */
    grip_real_t roll_split_front; /* QS front share of lateral load transfer [0, 1] */
    grip_real_t roll_gradient; /* QS rad of body roll per m/s^2 of ay, [0, 0.05]: the
                                * accelerometer's gravity component g sin(roll) is removed */
    grip_real_t pitch_gradient; /* QS rad of body pitch per m/s^2 of ax (nose down braking,
                                * up accelerating), [0, 0.05]: the accelerometer's gravity
                                * component g sin(pitch) is removed, ax used = ax /
                                * (1 + g pitch_gradient). 0 (default): not removed, as
                                * without it; a car's value from its K&C data or a
                                * braking run (docs/estimator.md)                     */
    uint32_t rate_hz;          /* step rate [Hz], [50, 2000] (exact in both builds,
                                * unlike a Q15.16 period: 1 ms is not representable) */
    uint32_t speed_ref_mu;     /* 1: the vehicle-speed input is a reference calibrated to
                                * the wheel speeds (GNSS, a fused reference) and may drive
                                * the longitudinal mu update; 0 (default): it never does.
                                * A speedometer signal reads a few per cent off the wheel
                                * speeds, i.e. shows slip that is not there (RAV4 log). */
    uint32_t rear_steer;       /* 1: the car steers its rear wheels; the input
                                * GRIP_IN_REAR_STEER_ANGLE is then required (missing
                                * beyond the hold time: GRIP_EST_F_NO_REAR_STEER, the
                                * lateral observer stops as without the steering).
                                * 0 (default): the rear angle is used when given, else 0.
                                * Range |angle| <= 0.25 rad (beyond: F_STEER_LIMIT). */
    uint32_t bank_est;         /* 1: estimate the road's bank beyond tan_bank (est_road.c,
                                * docs/estimator/road.md): at rest from the accelerometer,
                                * moving from the ay update's correction of vy. 0
                                * (default): the configured plane only, as without it.
                                * Off by default: with a tire model that misfits the car
                                * the bank learns the misfit (AV-21 log). */
    uint32_t stiff_est;        /* 1: learn each axle's cornering-stiffness scale online
                                * (est_stiffness.c, docs/estimator/stiffness.md): the
                                * tire model's slip angle is multiplied by it. 0
                                * (default): the tire file's stiffness, as without it.
                                * What was learned is kept across grip_est_reset and
                                * can be saved and restored (grip_est_learned_get/set). */
    uint32_t kx_est;           /* 1: learn the tires' longitudinal slip-stiffness scale kx
                                * online (est_stiffness_long.c, docs/estimator/stiffness.md):
                                * the tire model's slip ratio is multiplied by it. Needs
                                * drive_front; 0 (default): the tire file's, as without it.
                                * Kept and saved like stiff_est's scales.             */
    grip_real_t drive_front;   /* QS front share of the drive torque, [0, 1]: 0 rear-wheel
                                * drive, 1 front-wheel drive, 0.4 an AWD split 40 / 60.
                                * Negative (default -1, range [-1, 1]): not known, and
                                * kx_est learns nothing (the axles' force split is what
                                * the longitudinal stiffness is measured against).
                                * Exactly 1 (front-wheel drive), rear wheels not steered:
                                * while driving, the speed reference is the rear axle's
                                * mean wheel speed instead of the slowest wheel
                                * (est_speed.c). Exactly 0 or 1: the undriven axle's
                                * wheels work at zero slip while the car is not braking
                                * (est_tires.c) */
    uint32_t roll_est;         /* 1: learn the body's roll gradient online (est_roll.c,
                                * docs/estimator/roll.md), starting from roll_gradient,
                                * while the car weaves on the tires' linear part; kept
                                * and saved like stiff_est's scales. 0 (default): the
                                * configured roll_gradient, as without it (also after
                                * grip_est_learned_set of a blob that holds one).     */
    /* vehicle-level effects of the residual tool (docs/estimator.md); all 0 =
     * without them (grip_est_config_default) */
    grip_real_t cla;           /* QS m^2 aerodynamic downforce coefficient C_L A, [0, 20]:
                                * Fz_aero = 0.5 air_density cla vx^2 added to the static
                                * loads before load transfer                          */
    grip_real_t aero_front;    /* QS front share of the downforce, [0, 1]              */
    grip_real_t air_density;   /* QS kg/m^3, [0.5, 1.5]                                */
    grip_real_t cda;           /* QS m^2 aerodynamic drag area C_D A, [0, 5]: the drag
                                * 0.5 air_density cda vx^2 opposes the motion in the
                                * longitudinal force balance (the ax friction update) */
    grip_real_t crr;           /* QS rolling-resistance coefficient, [0, 0.05]: crr mass g
                                * opposes the motion in the same balance (the tire's QSY1
                                * is the usual value)                                   */
    grip_real_t tan_bank;      /* QS road plane, earth-fixed as in the residual tool: rise
                                * per metre to the LEFT of the heading at init / reset,
                                * [-0.5, 0.5]                                          */
    grip_real_t tan_grade;     /* QS rise per metre along that heading, [-0.5, 0.5];
                                * the body sees sx = tan_grade cos(psi) + tan_bank sin(psi),
                                * sy = tan_bank cos(psi) - tan_grade sin(psi), psi = the
                                * integral of the (bias-corrected) yaw rate since reset */
    grip_real_t latency;       /* QS s, [0, 0.1]: age of the inertial data (yaw rate, ay) when
                                * the step runs, i.e. the sensors' transport delay plus
                                * their filter time constant. vx, vy, beta, yaw_rate,
                                * alpha[], fy[] and fy_axle are extrapolated over it from
                                * the state derivative; 0 (default): outputs at the state */
    grip_real_t steer_lag;     /* QS s, [0, 0.5]: first-order time constant of the road
                                * wheels behind the steering signal (steer-by-wire, a
                                * logged steering command); tire slip angles and the yaw
                                * reference use the lagged angle. 0 (default): none, a
                                * mechanical column                                   */
    grip_real_t steer_latency; /* QS s, [0, 0.1]: age of the steering angle when the step
                                * runs (its transport delay), like latency for the inertial
                                * data: the angle moves along its last step's change to
                                * the state's time (the inertial data's) for the tire
                                * slip angles and the yaw reference, and to now for
                                * alpha[], fy[] and fy_axle. 0 (default): a fresh angle */
    /* error bounds and the consumer's limit (docs/estimator/integrity.md) */
    grip_real_t tire_tol;      /* QS [0, 2], default 0.3: relative force error of the
                                * tire model against the car's tires; it bounds the slip
                                * angle an axle's force gives by tire_tol |alpha| / g,
                                * g = max(0.05, sqrt(1 - utilization)) (0.1: a tire
                                * fitted to this car; 0.3: a generic tire)            */
    grip_real_t kin_acc_sd;    /* QS m/s^2 [0.01, 2], default 0.10: growth per second of
                                * the kinematic vy's deviation (accelerometer offset,
                                * road bank); the gyro offset's deviation times vx and
                                * 25 % of the roll compensation are added. Also the
                                * measured ay's error: each axle force's deviation
                                * carries its static share of mass times it        */
    grip_real_t beta_sd_max;   /* QS rad [0.001, 0.5], default 0.0175 (1 deg): V_BETA only
                                * while beta_sd is at most this                       */
    grip_real_t vx_sd_max;     /* QS m/s [0, 50], default 0 (no limit): V_VX only while vx_sd
                                * is at most this                                   */
    grip_real_t fy_sd_max;     /* QL N [0, 1e6], default 0 (no limit): V_AXLE and V_MARGIN
                                * only while both fy_axle_sd are at most this        */
    grip_est_tire_t tire[2];   /* front, rear axle; the tires' lateral relaxation
                                * length comes from the parameter set (C_alpha /
                                * LATERAL_STIFFNESS, else PTY1 / PTY2, else none:
                                * docs/estimator.md, "4. Lateral filter")       */
} grip_est_config_t;

/* ---- outputs ---- */
/* Validity bits of grip_est_output_t.valid */
#define GRIP_EST_V_VX        ((uint32_t)1u << 0)   /* vx (cleared 0.5 s without wheels, 2 s
                                                    * into dead reckoning with every wheel
                                                    * locked / spinning)                  */
#define GRIP_EST_V_BETA      ((uint32_t)1u << 1)   /* vy, beta (not while every wheel is
                                                    * locked / spinning, nor with
                                                    * F_MODEL_MISFIT)                     */
#define GRIP_EST_V_YAW       ((uint32_t)1u << 2)   /* yaw_rate (filtered)                 */
#define GRIP_EST_V_YAW_REF   ((uint32_t)1u << 3)   /* yaw_rate_ref, yaw_error             */
#define GRIP_EST_V_FZ        ((uint32_t)1u << 4)   /* fz[] (load transfer from ax, ay)    */
#define GRIP_EST_V_WHEEL(i)  ((uint32_t)1u << (5u + (uint32_t)(i)))   /* kappa, alpha, fx, fy, mz, util of wheel i */
#define GRIP_EST_V_AXLE      ((uint32_t)1u << 9)   /* fy_axle, util_axle                  */
#define GRIP_EST_V_MU        ((uint32_t)1u << 10)  /* mu with mu_conf >= 0.5              */
#define GRIP_EST_V_STEER     ((uint32_t)1u << 11)  /* steer_char (under/oversteer)        */
#define GRIP_EST_V_MARGIN    ((uint32_t)1u << 12)  /* fy_margin_front                     */

/* Condition flags of grip_est_output_t.flags (why something is invalid) */
#define GRIP_EST_F_STANDSTILL   ((uint32_t)1u << 0)
#define GRIP_EST_F_REVERSING    ((uint32_t)1u << 1)
#define GRIP_EST_F_LOW_SPEED    ((uint32_t)1u << 2)   /* |vx| below the observer's minimum speed  */
#define GRIP_EST_F_NO_WHEELS    ((uint32_t)1u << 3)   /* no valid wheel speed (vx from ax only)   */
#define GRIP_EST_F_NO_STEER     ((uint32_t)1u << 4)   /* steering angle missing beyond hold time  */
#define GRIP_EST_F_NO_YAW       ((uint32_t)1u << 5)
#define GRIP_EST_F_NO_AY        ((uint32_t)1u << 6)
#define GRIP_EST_F_NO_AX        ((uint32_t)1u << 7)
#define GRIP_EST_F_SATURATED    ((uint32_t)1u << 8)   /* an input was at/beyond its sensor range  */
#define GRIP_EST_F_STEER_LIMIT  ((uint32_t)1u << 9)   /* road-wheel angle clamped (steering at lock) */
#define GRIP_EST_F_WHEEL_LOCK   ((uint32_t)1u << 10)  /* a wheel far slower than the vehicle      */
#define GRIP_EST_F_WHEEL_SPIN   ((uint32_t)1u << 11)  /* a wheel far faster than the vehicle      */
#define GRIP_EST_F_EXCITED      ((uint32_t)1u << 12)  /* this step adapted mu (sufficient excitation) */
#define GRIP_EST_F_TIRE_ERROR   ((uint32_t)1u << 13)  /* a tire model call failed (its wheel zero) */
#define GRIP_EST_F_RESET        ((uint32_t)1u << 14)  /* the lateral observer was (re)initialized  */
#define GRIP_EST_F_MODEL_MISFIT ((uint32_t)1u << 15)  /* the tire model does not fit the car (ay NIS
                                                       * or saturated-model-without-limit share
                                                       * above threshold): mu_conf capped at 0.45,
                                                       * V_MU cleared, and V_BETA, V_AXLE, the
                                                       * wheel and margin bits not set            */
#define GRIP_EST_F_INPUT_DEGRADED ((uint32_t)1u << 16) /* set by grip_monitor_gate (grip_monitor.h):
                                                       * the plausibility monitor does not vouch
                                                       * for this sample's inputs; every output
                                                       * that depends on the lateral state is
                                                       * marked invalid (GRIP_MON_GATE_CLEARS) */
#define GRIP_EST_F_RATE         ((uint32_t)1u << 17)  /* the sample's time t_us is not 1 / rate_hz after
                                                       * the last one (beyond 25 %, or backwards): the
                                                       * filter's per-step gains do not hold; V_BETA,
                                                       * V_AXLE, the wheel, margin and mu bits not set,
                                                       * grip_est_step returns GRIP_WARN_RATE. No check
                                                       * while t_us is 0 or repeats.             */
#define GRIP_EST_F_NO_REAR_STEER ((uint32_t)1u << 18) /* rear steering configured, its angle missing */
#define GRIP_EST_F_BETA_KIN     ((uint32_t)1u << 19)  /* vy, beta from the kinematic estimate
                                                       * (integrated ay - r vx): its bound is the
                                                       * smaller (docs/estimator/integrity.md) */
#define GRIP_EST_F_BETA_DISAGREE ((uint32_t)1u << 20) /* the filter's vy and the kinematic one
                                                       * differ beyond 3 joint deviations: the
                                                       * tire model is fitted where it is wrong;
                                                       * V_BETA, V_AXLE, the wheel, margin and mu
                                                       * bits not set                          */

typedef struct {
    grip_real_t vx;              /* QS m/s longitudinal speed of the CG          */
    grip_real_t vy;              /* QS m/s lateral speed of the CG               */
    grip_real_t beta;            /* QS rad sideslip atan(vy/vx)                   */
    grip_real_t yaw_rate;        /* QS rad/s filtered yaw rate                    */
    grip_real_t yaw_rate_ref;    /* QS rad/s bicycle reference, friction limited  */
    grip_real_t yaw_error;       /* QS rad/s yaw_rate - yaw_rate_ref              */
    grip_real_t delta;           /* QS rad road-wheel steer angle                 */
    grip_real_t kappa[4];        /* QS slip ratio (ISO, > 0 driving) the tire works
                                  * at: 0 on the undriven axle while not braking */
    grip_real_t alpha[4];        /* QS rad slip angle (ISO-W), kinematic          */
    grip_real_t fz[4];           /* QL N vertical load                            */
    grip_real_t fx[4];           /* QL N                                          */
    grip_real_t fy[4];           /* QL N (wheel frame), at the lagged slip angle,
                                  * plus the yaw balance's share (yaw_mb)      */
    grip_real_t mz[4];           /* QL N m                                        */
    grip_real_t util[4];         /* QS friction utilization |F| / (mu mu0 Fz), [0, 1.5] */
    grip_real_t fy_axle[2];      /* QL N front, rear (wheel frame, summed)        */
    grip_real_t util_axle[2];    /* QS                                            */
    grip_real_t mu;              /* QS road friction relative to the tire's own (1 = as fitted) */
    grip_real_t mu_conf;         /* QS [0, 1] confidence of mu                    */
    grip_real_t yaw_rate_bias;   /* QS rad/s estimated yaw-rate sensor offset (removed
                                  * from yaw_rate, yaw_error); valid with V_YAW      */
    grip_real_t fy_margin_front; /* QL N mu mu0 Fz_front - |Fy_front| (AFS)        */
    grip_real_t vy_sd;           /* QS m/s standard deviation of vy (0 with the observer off) */
    grip_real_t beta_sd;         /* QS rad standard deviation of beta; V_BETA needs
                                  * beta_sd <= beta_sd_max                        */
    grip_real_t yaw_rate_sd;     /* QS rad/s the filter's standard deviation of yaw_rate */
    grip_real_t mu_sd;           /* QS the filter's standard deviation of mu      */
    grip_real_t vx_sd;           /* QS m/s standard deviation of vx (0 before vx is known) */
    grip_real_t fy_axle_sd[2];   /* QL N standard deviation of fy_axle[] (0 with the
                                  * observer off)                                 */
    int32_t steer_char;          /* +1 understeer, -1 oversteer, 0 neutral        */
    uint32_t valid;              /* GRIP_EST_V_* */
    uint32_t flags;              /* GRIP_EST_F_* */
} grip_est_output_t;

/* ---- instance (all state; fixed size, no heap) ---- */
#define GRIP_EST_NX 4
#define GRIP_EST_SHAPE_N 16     /* intervals of the tabulated lateral force shape */
typedef struct {
    uint32_t magic;
    grip_est_config_t cfg;
    /* derived at init */
    grip_mf_prepared tire_prep[2]; /* the axles' MF sets prepared (grip_mf_prepare) for the
                                    * step's four evaluations */
    grip_real_t fz_static[2];   /* QL per wheel, front / rear  */
    grip_real_t xw[4], yw[4];   /* QS m wheel positions from the CG (x forward, y left) */
    grip_real_t c_alpha[2];     /* QL N/rad per wheel at static load */
    grip_real_t c_kappa[2];     /* QL N per wheel at static load */
    grip_real_t mu0[2];         /* QS peak |F|/Fz of the tire at static load */
    grip_real_t alpha_pk[2];    /* QS slip angle of that peak [rad] */
    grip_real_t inv_apk[2];     /* QS 1 / alpha_pk [1/rad] */
    grip_real_t fy_shape[2][GRIP_EST_SHAPE_N + 1]; /* QS |Fy| / Fz at static load, alpha = k alpha_pk / N
                                                     * (mu's secant, docs/estimator.md) */
    grip_real_t kappa_pk[2];    /* QS |slip ratio| of the braking force's peak at static load */
    grip_real_t mu_xy[2];       /* QS mu0 over the braking peak |Fx|/Fz at static load: the
                                 * friction ellipse's axis ratio (utilization, excitation) */
    grip_real_t mu0_k[2];       /* QS load sensitivity of the peak: mu0(Fz) = mu0 + mu0_k (Fz / Fz_static - 1) */
    grip_real_t k_us;           /* QS stability factor A [s^2/m^2] times 100 (learned stiffness) */
    grip_real_t k_us0;          /* QS the same of the tire file's car (the learners' gate) */
    grip_real_t steer_k;        /* QS per-step gain of the steering lag, 1: none */
    grip_real_t st_k_in;        /* QS (steer_latency - latency) rate: steps of the angle's change to the state's time */
    grip_real_t st_k_out;       /* QS steer_latency rate: ... and to the outputs' time */
    grip_real_t sb_a;           /* QS low-pass gain of the lateral balance (lat_sb) per step */
    grip_real_t sb_share_f;     /* QS front share lr / l of the lateral balance */
    grip_real_t q[GRIP_EST_NX]; /* QS process noise per step (scaled units) */
    int32_t hold_steps;         /* steps an input is held after it became invalid */
    int32_t lim_n;              /* steps of the friction-limit test */
    int32_t nowheel_n;          /* steps vx stays valid without a speed reference */
    int32_t dr_n;               /* steps vx stays valid dead-reckoning (every wheel locked / spinning) */
    grip_real_t rate;           /* QS step rate [1/s] */
    grip_real_t ay_fac;         /* QS 1 / (1 + g rg_k): the roll gradient in use */
    grip_real_t ax_fac;         /* QS 1 / (1 + g cfg.pitch_gradient) */
    grip_real_t fz_base[2];     /* QL per wheel at rest on the road plane: fz_static x cos */
    grip_real_t k_aero[2];      /* QS N/(m/s)^2 downforce per wheel, front / rear */
    grip_real_t k_drag;         /* QS N/(m/s)^2 drag: 0.5 air_density cda */
    grip_real_t f_roll;         /* QL N rolling resistance: crr mass g */
    int32_t plane;              /* 1: tan_bank or tan_grade non-zero */
    grip_real_t psi;            /* QS rad heading since reset (only with plane), (-pi, pi] */
    /* state */
    grip_real_t vx;             /* QS */
    grip_real_t ax_off;         /* QS m/s^2 ax offset learned from the wheels (grade, accelerometer bias) */
    grip_real_t road_gy;        /* QS m/s^2 gravity along the body's y axis beyond the configured
                                 * plane: the road's bank, estimated (est_road.c) */
    grip_real_t road_g0;        /* QS m/s^2 the bank measured at the last standstill (est_road.c) */
    grip_real_t road_r;         /* QS rad/s the yaw rate of the last step (est_road.c) */
    grip_real_t road_dr;        /* QS rad/s^2 the yaw acceleration, low-passed: quasi-steady test */
    grip_real_t x[GRIP_EST_NX]; /* QS vy [m/s], r [rad/s], mu [-], gyro bias [0.001 rad/s] */
    grip_real_t p[GRIP_EST_NX][GRIP_EST_NX]; /* QS covariance in scaled units */
    grip_real_t hold[6];        /* QS last valid steer, yaw, ax, ay, vehicle speed, rear steer */
    int32_t age[6];             /* steps since each was valid (saturating) */
    int64_t t_prev;             /* us the last sample's time (rate check); 0: none */
    grip_real_t delta_f;        /* QS lagged road-wheel angle [rad] x 1024 (the per-step change of a
                                 * 0.5 s lag at 1 kHz survives Q15.16) */
    grip_real_t r_lin_f;        /* QS linear yaw-rate reference, low-passed (limit detection) */
    int32_t lim_steps;          /* consecutive steps at the friction limit */
    int32_t us_steps;           /* consecutive steps at the understeer limit (low-friction detection) */
    int32_t us_low;             /* 1: mu held down by the understeer bound, unconfirmed since */
    int32_t rel_steps;          /* consecutive steps that contradict that bound (withdrawal) */
    grip_real_t mu_pre;         /* QS mu before the understeer bound held it down */
    grip_real_t use_b;          /* QS front friction in use at the bound's last step */
    grip_real_t nis_a;          /* QS low-pass gain of the misfit statistic per step */
    grip_real_t mb_a;           /* QS low-pass gain of the yaw balance (yaw_mb) per step */
    grip_real_t nis_f;          /* QS low-passed ay NIS, [0, 16] (misfit check) */
    grip_real_t sat_f;          /* QS low-passed share of saturated-but-not-at-limit steps, [0, 1] */
    int32_t misfit;             /* model misfit declared (hysteresis state) */
    int32_t sat_cap;            /* mu confidence capped by the saturation share (hysteresis state) */
    grip_real_t sig_a[2];       /* QS m lateral relaxation length at static load, front / rear; 0: none */
    grip_real_t alpha_t[4];     /* QS rad lagged (relaxed) slip angles the tires work at */
    grip_real_t yaw_mb;         /* QL N front-axle force the model's yaw moment lacks (low-passed) */
    grip_real_t lat_sb;         /* QL N lateral force the model lacks after the updates (low-passed) */
    grip_real_t fy_dmu[4];      /* QL N d Fy / d mu of the step's tire evaluation (mu's secant) */
    grip_real_t mu_lin;         /* QS mu the step's tire evaluation used (before the updates) */
    grip_real_t mu_floor;       /* QS the step's friction in use, mu's lower bound and its secant's floor */
    grip_real_t p_mu_own;       /* QS mu's scaled variance from the tires alone (mu_conf, V_MU) once */
    int32_t mu_src;             /*    mu_src: a friction measurement from outside was applied */
    grip_real_t p_mu_start;     /* QS the step's P_mu before its stages and after the predict */
    grip_real_t p_mu_pred;      /*    (est_mu_own) */
    grip_real_t sec_inv_mu;     /* QS the step's mu's secant: 1 / mu, 1 / (mu - dmu), 1 / dmu, */
    grip_real_t sec_inv_mu2;    /*    (mu - dmu) / mu (est_friction_floor: the same for the four */
    grip_real_t sec_inv_dmu;    /*    wheels)                                                     */
    grip_real_t sec_ratio;
    grip_real_t delta_prev;     /* QS rad road-wheel angle of the previous step */
    grip_real_t delta_o_d;      /* QS rad this step's outputs' road-wheel angle less the state's */
    int32_t delta_prev_ok;      /* delta_prev from a valid steering angle */
    int32_t rlx_init;           /* alpha_t set since the lateral observer started */
    int32_t no_wheel_steps;
    int32_t dr_steps;           /* consecutive dead-reckoning steps */
    int32_t braking;            /* this step's braking test (est_speed.c: the wheels' own
                                 * acceleration below -EST_AX_TH): the speed reference's
                                 * and the tire stage's undriven axle's                  */
    int32_t active;             /* lateral observer running */
    int32_t vx_init;
    grip_real_t vy_k;           /* QS m/s kinematic vy (est_integrity.c) */
    grip_real_t sd_k;           /* QS m/s its standard deviation without mu's share (the share's),
                                 * [0, EST_SD_CAP] */
    grip_real_t sd_kmu;         /* QS m/s the same with mu's share: the outputs' */
    grip_real_t sd_vx;          /* QS m/s vx's standard deviation, [0, EST_SD_CAP] */
    grip_real_t slip_acc;       /* QS s^2/m the wheels' mean slip per m/s^2 of ax: m / (4 c_kappa),
                                 * the softer axle's static stiffness (vx's deviation) */
    /* learned cornering stiffness (est_stiffness.c) */
    grip_real_t stf_k[2];       /* QS the axles' cornering-stiffness scale k, front / rear (1: the
                                 * tire file's); the tires work at k alpha */
    grip_real_t stf_x[2];       /* QS the filter's state: 1 / k in units of EST_STF_S_U */
    grip_real_t stf_p[3];       /* QS its covariance P00, P01, P11 (units of EST_STF_S_U) */
    grip_real_t stf_q, stf_r;   /* QS process noise per step, measurement noise (scaled) */
    grip_real_t stf_a;          /* QS low-pass gain per step of the regression's signals */
    grip_real_t stf_z;          /* QS crad low-passed front-minus-rear lagged slip angle */
    grip_real_t stf_h[2];       /* QS crad low-passed model slips of the measured axle forces */
    grip_real_t stf_yaw;        /* QS rad/s the last step's yaw rate (its derivative) */
    int32_t stf_n;              /* consecutive steps the regression's conditions held */
    int32_t stf_n_min;          /* steps they must hold before an update (the low-pass settled) */
    uint32_t stf_updates;       /* updates since init (saturating) */
    /* learned longitudinal slip stiffness (est_stiffness_long.c) */
    grip_real_t kx;             /* QS the tires' longitudinal slip-stiffness scale (1: the tire
                                 * file's); the tires work at kx kappa */
    grip_real_t c_kappa_kx[2];  /* QL c_kappa x kx, front / rear (the step's slip stiffness) */
    grip_real_t kx_x[2];        /* QS the filter's state: 1 / kx in units of EST_KX_S_U, the
                                 * axles' rolling-radius mismatch in units of EST_KX_S_Y */
    grip_real_t kx_p[3];        /* QS its covariance P00, P01, P11 (scaled) */
    grip_real_t kx_q, kx_qd, kx_r; /* QS process noises per step (1 / kx, mismatch), measurement noise */
    grip_real_t kx_a;           /* QS low-pass gain per step of the regression's signals */
    grip_real_t kx_z;           /* QS per mille low-passed front-minus-rear axle slip (wheel speeds) */
    grip_real_t kx_h;           /* QS per mille low-passed model slip difference of the drive force */
    grip_real_t kx_dv;          /* QS m/s this step's front-minus-rear mean wheel speed at the CG
                                 * (est_speed.c) */
    int32_t kx_n;               /* consecutive steps the regression's conditions held */
    int32_t kx_n_min;           /* steps they must hold before an update (the low-pass settled) */
    uint32_t kx_updates;        /* updates since init (saturating) */
    /* learned roll gradient (est_roll.c) */
    grip_real_t rg_k;           /* QS rad/(m/s^2) the roll gradient in use (cfg.roll_gradient
                                 * until roll_est learns) */
    grip_real_t rg_x;           /* QS the filter's state: rg_k in units of EST_RG_S_U */
    grip_real_t rg_p;           /* QS its variance (units of EST_RG_S_U squared) */
    grip_real_t rg_q, rg_r;     /* QS process noise per step, measurement noise (scaled) */
    grip_real_t rg_a1, rg_a2;   /* QS low-pass gains per step: the band-pass's fast and slow part */
    grip_real_t rg_f[2];        /* QS m/s^2 measured ay, vx r + dvy/dt: low-passed over EST_RG_T */
    grip_real_t rg_m[2];        /* QS m/s^2 ... and those low-passed again over EST_RG_TH */
    grip_real_t rg_vy;          /* QS m/s the filter's vy of the last step (dvy/dt) */
    int32_t rg_n;               /* consecutive steps the band-pass ran */
    int32_t rg_n_min;           /* steps it must run before an update (settled) */
    int32_t rg_n_alt;           /* steps within which vx r must have been beyond +- EST_RG_H_MIN */
    int32_t rg_pos, rg_neg;     /* steps since it was beyond + / - EST_RG_H_MIN (saturating) */
    uint32_t rg_updates;        /* updates since init (saturating) */
} grip_est_t;

/* What the estimator learned that outlives an ignition cycle: the axles'
 * cornering-stiffness scales, the longitudinal slip-stiffness scale (with the
 * axles' rolling-radius mismatch), the body's roll gradient and their
 * covariances. A caller-owned blob,
 * stored as bytes in non-volatile memory; grip_est_learned_set checks its
 * format, build, configuration fingerprint, ranges and checksum before any
 * of it is used. */
#define GRIP_EST_LEARNED_MAGIC 0x474C524Eu /* "GLRN" */
#define GRIP_EST_LEARNED_VERSION 3u
typedef struct {
    uint32_t magic;             /* GRIP_EST_LEARNED_MAGIC */
    uint32_t version;           /* GRIP_EST_LEARNED_VERSION x 2 + 1 in the fixed build */
    uint32_t config_crc;        /* CRC-32 of the axle constants the scales apply to */
    uint32_t updates;           /* cornering-stiffness updates behind it (0: nothing learned) */
    grip_real_t k[2];           /* QS the learned scales, front / rear (for reading; set
                                 * recomputes them from x) */
    grip_real_t x[2];           /* QS the filter's state (grip_est_t.stf_x) */
    grip_real_t p[3];           /* QS its covariance */
    uint32_t kx_updates;        /* longitudinal-stiffness updates behind kx (0: nothing learned) */
    grip_real_t kx;             /* QS the longitudinal slip-stiffness scale (for reading) */
    grip_real_t kx_x[2];        /* QS its filter's state (grip_est_t.kx_x) */
    grip_real_t kx_p[3];        /* QS its covariance */
    uint32_t rg_updates;        /* roll-gradient updates behind rg_k (0: nothing learned) */
    grip_real_t rg_k;           /* QS the roll gradient, rad/(m/s^2) (for reading) */
    grip_real_t rg_x;           /* QS its filter's state (grip_est_t.rg_x) */
    grip_real_t rg_p;           /* QS its variance */
    uint32_t crc;               /* CRC-32 (IEEE 802.3) of every byte before it */
} grip_est_learned_t;


#define grip_est_config_default GRIP_TYPED(grip_est_config_default)
#define grip_est_init GRIP_TYPED(grip_est_init)
#define grip_est_step GRIP_TYPED(grip_est_step)
#define grip_est_reset GRIP_TYPED(grip_est_reset)
#define grip_est_stability_factor GRIP_TYPED(grip_est_stability_factor)
#define grip_est_learned_get GRIP_TYPED(grip_est_learned_get)
#define grip_est_learned_set GRIP_TYPED(grip_est_learned_set)
#define grip_est_measure_friction GRIP_TYPED(grip_est_measure_friction)

/* A mid-size passenger car (the simulator's 'passenger' set) with the given
 * tire on both axles, rate_hz = 100. GRIP_ERR_NULL for NULL cfg. */
grip_status_t grip_est_config_default(grip_est_config_t *cfg, const grip_mf_params *tire);

/* Checks cfg (ranges above, tire kinds and parameter sets), copies it into
 * est and derives the axle constants (cornering and slip stiffness, peak
 * friction, stability factor) from the tire models at static load.
 * GRIP_ERR_NULL, GRIP_ERR_PARAM (est is then unusable: step returns
 * GRIP_ERR_STATE). */
grip_status_t grip_est_init(grip_est_t *est, const grip_est_config_t *cfg);

#define grip_est_init_detail GRIP_TYPED(grip_est_init_detail)
/* grip_est_init; on GRIP_ERR_PARAM *detail (may be NULL) names what failed:
 * a configuration member ("mass", "rate_hz"), or part "tire" with the
 * axle's index and the parameter set's member ("fnomin") or "model.mf"
 * when the set is valid but gives no usable tire at the static load. */
grip_status_t grip_est_init_detail(grip_est_t *est, const grip_est_config_t *cfg, grip_check_detail_t *detail);

/* Forgets the dynamic state (speed, observer, held inputs); keeps the
 * configuration. */
grip_status_t grip_est_reset(grip_est_t *est);

/* One estimator step. Invalid, stale, non-finite or saturated inputs are
 * never used as numbers; missing inputs are held for 50 ms, then the
 * outputs that need them lose their validity bits (flags say why) and come
 * back once the inputs do. Returns GRIP_OK (possibly with outputs marked
 * invalid), GRIP_ERR_NULL or GRIP_ERR_STATE (zero outputs, valid = 0). */
grip_status_t grip_est_step(grip_est_t *est, const grip_input_sample_t *in, grip_est_output_t *out);

/* The linear stability factor A [s^2/m^2] of the configured car and tires
 * (seed eq. 2.17, from the tires' cornering stiffness at static load times
 * the learned scales with stiff_est, as the yaw-rate reference uses it),
 * times 100, in *a_x100 (QS).
 * GRIP_ERR_NULL, GRIP_ERR_STATE (est not initialized). */
grip_status_t grip_est_stability_factor(const grip_est_t *est, grip_real_t *a_x100);

/* Copies what the estimator learned into *blob (all of it, checksummed),
 * for the caller to store. GRIP_ERR_NULL, GRIP_ERR_STATE. */
grip_status_t grip_est_learned_get(const grip_est_t *est, grip_est_learned_t *blob);

/* Restores a blob from grip_est_learned_get (at start-up, after
 * grip_est_init). GRIP_ERR_PARAM, and est unchanged, when the blob is not
 * one (magic, version), comes from the other arithmetic build, from
 * another car or tire (config_crc), holds values out of range or fails its
 * checksum. GRIP_ERR_NULL, GRIP_ERR_STATE. */
grip_status_t grip_est_learned_set(grip_est_t *est, const grip_est_learned_t *blob);

/* A road-friction measurement from outside the estimator (the brake
 * controller's friction at an ABS or traction-control event, a
 * road-condition service, a camera's surface class): mu_road the absolute
 * peak friction coefficient |F| / Fz (QS, [0.05, 2]), mu_road_sd its
 * standard deviation (QS, [0.01, 1]). Applied at once as a measurement of
 * mu (docs/estimator/integrity.md, "Road friction from outside"); call it
 * whenever the source has a new value, between steps. Until mu is known
 * the bound of beta carries the lowest friction the filter cannot exclude,
 * so a source lets beta be valid where the tires' own excitation cannot
 * show mu. mu_conf and V_MU keep resting on the tires' own evidence. The
 * promise of the bounds holds only while the source's deviation is
 * honest. GRIP_ERR_NULL, GRIP_ERR_STATE, GRIP_ERR_INPUT (a value out of
 * range or not finite; est unchanged). */
grip_status_t grip_est_measure_friction(grip_est_t *est, grip_real_t mu_road, grip_real_t mu_road_sd);

#endif /* GRIP_EST_H */
