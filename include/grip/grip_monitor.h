/*
 * grip_monitor.h - ESC sensor-plausibility monitor (grip issue 8).
 *
 * Data flow: CAN -> signals (grip_input_sample_t) -> MONITOR -> estimator.
 * grip_monitor_step looks at the raw ESC signals of one sample (four wheel
 * speeds, steering-wheel angle, yaw rate, ax, ay, and the vehicle speed if
 * present), judges each plausible or not with checks the estimator does not
 * have, and clears the valid flag of every signal it judges faulty (value 0,
 * fault GRIP_SIG_FAULT), so the estimator treats it as missing. It reports
 * a fault code per signal and a detection flag.
 *
 * Checks (docs/faults.md gives each constant and the measurement behind it):
 *   LOST    the signal layer marked a signal invalid that had been valid
 *   RANGE   valid flag set but non-finite or beyond the physical range
 *   SPIKE   a step beyond the signal's physical rate (the sample is dropped;
 *           three within ~0.5 s latch the signal)
 *   NOISE   low-passed |second difference| beyond the physical bound
 *   FROZEN  bit-identical for N samples while the redundant signal moves
 *   PLAUS   analytical redundancy, each where its model holds: wheel speeds
 *           against each other; yaw rate against the rear-wheel speed
 *           difference; ay against r vx (threshold widened with the yaw
 *           acceleration); ax against the wheel-speed derivative; steering
 *           against the yaw rate (bicycle model, linear range); vehicle
 *           speed against the wheels. Debounced (0.1 s).
 * A signal with NOISE, FROZEN, PLAUS or latched SPIKE is latched faulty and
 * dropped until its checks have passed for 1 s.
 *
 * Contract with the consumer of the estimator's output: rep->degraded != 0
 * means "do not trust beta and mu on this sample" even where the estimator
 * marks them valid (GRIP_EST_V_BETA, GRIP_EST_V_MU); grip_monitor_gate
 * applies it to the output (clears those bits and the ones that depend on
 * them, sets GRIP_EST_F_INPUT_DEGRADED); GRIP_MON_DEGR_SUSPECT:
 * a signal is dropped, lost or latched, or a check is accumulating a
 * suspicion, now or within 0.5 s; GRIP_MON_DEGR_UNVERIFIED: the ay, ax and
 * steering checks are held off (unstable driving). beta / mu are usable when
 * (valid bit set) AND (degraded == 0); the fault table (docs/faults.md)
 * counts a row as flagged under that rule, and gives the figures for a
 * consumer that honours SUSPECT only (UNVERIFIED costs availability in the
 * limit manoeuvres: docs/faults.md).
 *
 * Fixed size, no heap, every loop bounded by GRIP_MON_N or 4; the caller
 * owns the state. Float64 reference: tools/grip_tools/reference/monitor.py (the
 * same steps in the same order); golden test tests/unit/test_monitor.c.
 *
 * Formats (fixed build): lengths, ratios, speeds, rates QS.
 */
#ifndef GRIP_MONITOR_H
#define GRIP_MONITOR_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_signals.h"
#include "grip_est.h"

/* Monitored inputs: GRIP_IN_WHEEL_SPEED_FL (0) .. GRIP_IN_VEHICLE_SPEED (8). */
#define GRIP_MON_N 9

/* Fault code bits of grip_monitor_report_t.code[] */
#define GRIP_MON_C_LOST   (1u << 0)
#define GRIP_MON_C_RANGE  (1u << 1)
#define GRIP_MON_C_SPIKE  (1u << 2)
#define GRIP_MON_C_NOISE  (1u << 3)
#define GRIP_MON_C_FROZEN (1u << 4)
#define GRIP_MON_C_PLAUS  (1u << 5)

/* Bits of grip_monitor_report_t.degraded */
#define GRIP_MON_DEGR_SUSPECT    (1u << 0)  /* a signal dropped, lost or latched, or a
                                             * check accumulating a suspicion (3 net
                                             * steps), now or within the last 0.5 s */
#define GRIP_MON_DEGR_UNVERIFIED (1u << 1)  /* the unstable-driving hold keeps the ay,
                                             * ax and steering checks off: a fault of
                                             * those signals would go unseen */

typedef struct {
    grip_real_t lf;               /* QS m CG to front axle, (0, 10]            */
    grip_real_t lr;               /* QS m CG to rear axle, (0, 10]             */
    grip_real_t track_f;          /* QS m, [0.2, 4]                            */
    grip_real_t track_r;          /* QS m, [0.2, 4]                            */
    grip_real_t steer_ratio;      /* QS steering-wheel / road-wheel angle, [1, 100] */
    grip_real_t stab_factor_x100; /* QS stability factor A [s^2/m^2] x 100, [-1, 1]
                                   * (the linear bicycle model r = v delta / (l (1 + A v^2))) */
    grip_real_t roll_gradient;    /* QS rad per m/s^2, [0, 0.05] (ay gravity part removed) */
    uint32_t driven;              /* driven axles: bit 0 front, bit 1 rear, [1, 3]    */
    uint32_t rate_hz;             /* step rate [Hz], [50, 2000]                */
} grip_monitor_config_t;

typedef struct {
    uint8_t code[GRIP_MON_N];     /* GRIP_MON_C_* found this step              */
    grip_real_t resid[GRIP_MON_N];/* QS residual of the signal's plausibility check this
                                   * step (signal minus its redundant estimate, in the
                                   * signal's unit; steering: bicycle minus measured yaw
                                   * rate [rad/s]); 0 where the check did not run */
    uint32_t faulty;              /* bit s: signal s latched faulty             */
    uint32_t dropped;             /* bit s: the monitor cleared its valid flag this step */
    int32_t detected;             /* 1: some signal has a code or is latched    */
    uint32_t degraded;            /* GRIP_MON_DEGR_* bits; nonzero: do not trust the
                                   * estimator's beta and mu on this sample, whatever
                                   * their valid bits say (docs/faults.md, "degraded") */
} grip_monitor_report_t;

typedef struct {
    uint32_t magic;
    grip_monitor_config_t cfg;
    /* derived at init */
    grip_real_t rate;             /* QS [1/s] */
    grip_real_t ay_fac;           /* QS 1 / (1 + g roll_gradient) */
    grip_real_t a_noise, a_ax, a_st, a_dr;   /* QS low-pass factors dt / tau */
    grip_real_t jump[GRIP_MON_N]; /* QS spike threshold per step */
    grip_real_t rate_step[GRIP_MON_N];       /* QS largest physical change per step */
    grip_real_t lim[GRIP_MON_N];  /* QS physical range */
    int32_t n_frozen[GRIP_MON_N];
    int32_t n_deb, n_heal, n_lost, n_steady, n_unst, n_degr;
    /* per signal */
    grip_real_t fol[GRIP_MON_N];  /* spike follower */
    grip_real_t x1[GRIP_MON_N], x2[GRIP_MON_N];   /* previous accepted values */
    grip_real_t noise[GRIP_MON_N];
    grip_real_t frz_val[GRIP_MON_N], frz_lo[GRIP_MON_N], frz_hi[GRIP_MON_N];
    int32_t lost[GRIP_MON_N], spk[GRIP_MON_N], frz[GRIP_MON_N], deb[GRIP_MON_N], heal[GRIP_MON_N];
    uint8_t have[GRIP_MON_N], hist[GRIP_MON_N], latch[GRIP_MON_N], seen[GRIP_MON_N];
    /* shared */
    grip_real_t ax_f, dv_f, v_prev, ax_prev, dax_f, r_lin_f, r_prev, dr_f, dv_prev, ddv_f;
    int32_t ax_steady, r_steady, unst, dv_steady, degr;
    uint8_t v_have, r_have, init_f, pad_;
} grip_monitor_t;

#define grip_monitor_config_default GRIP_TYPED(grip_monitor_config_default)
#define grip_monitor_init GRIP_TYPED(grip_monitor_init)
#define grip_monitor_reset GRIP_TYPED(grip_monitor_reset)
#define grip_monitor_step GRIP_TYPED(grip_monitor_step)
#define grip_monitor_gate GRIP_TYPED(grip_monitor_gate)
#define grip_monitor_config_from_est GRIP_TYPED(grip_monitor_config_from_est)

/* Validity bits grip_monitor_gate clears: everything that depends on the
 * estimator's lateral state (vy) or on mu. vx, yaw rate, its reference,
 * loads and the under/oversteer indication stay as the estimator set them. */
#define GRIP_MON_GATE_CLEARS (GRIP_EST_V_BETA | GRIP_EST_V_MU | GRIP_EST_V_AXLE | GRIP_EST_V_MARGIN | \
                              GRIP_EST_V_WHEEL(0) | GRIP_EST_V_WHEEL(1) | GRIP_EST_V_WHEEL(2) | GRIP_EST_V_WHEEL(3))
/* The degraded bits grip_monitor_gate honours by default (docs/faults.md) */
#define GRIP_MON_GATE_DEFAULT (GRIP_MON_DEGR_SUSPECT | GRIP_MON_DEGR_UNVERIFIED)

/* The simulator's passenger car (as grip_est_config_default): front drive,
 * rate_hz = 100. GRIP_ERR_NULL for NULL. */
grip_status_t grip_monitor_config_default(grip_monitor_config_t *cfg);

/* The monitor's vehicle values taken from the application's initialized
 * estimator, so the two cannot drift apart: lf, lr, track widths, steering
 * ratio, roll gradient and rate from its configuration, the stability
 * factor from grip_est_stability_factor; `driven` (bit 0 front, bit 1
 * rear) is not an estimator setting. GRIP_ERR_NULL, GRIP_ERR_STATE (est not
 * initialized), GRIP_ERR_PARAM (a value outside the monitor's ranges, e.g.
 * a stability factor beyond +-0.01 s^2/m^2; cfg is then unchanged). */
grip_status_t grip_monitor_config_from_est(grip_monitor_config_t *cfg, const grip_est_t *est, uint32_t driven);

/* Checks cfg (ranges above), copies it and derives the per-step constants.
 * GRIP_ERR_NULL, GRIP_ERR_PARAM (mon is then unusable: step returns
 * GRIP_ERR_STATE). */
grip_status_t grip_monitor_init(grip_monitor_t *mon, const grip_monitor_config_t *cfg);

#define grip_monitor_init_detail GRIP_TYPED(grip_monitor_init_detail)
/* grip_monitor_init; on GRIP_ERR_PARAM *detail (may be NULL) names the
 * first configuration member outside its range ("stab_factor_x100"). */
grip_status_t grip_monitor_init_detail(grip_monitor_t *mon, const grip_monitor_config_t *cfg,
                                       grip_check_detail_t *detail);

/* Forgets the dynamic state (filters, counters, latches); keeps the
 * configuration. GRIP_ERR_NULL, GRIP_ERR_STATE. */
grip_status_t grip_monitor_reset(grip_monitor_t *mon);

/* One step on one sample, in place: the valid flag of a signal judged
 * faulty (latched, or a spike this step) is cleared, its value set to 0 and
 * its fault to GRIP_SIG_FAULT; other inputs are left as they are. est_prev
 * is the estimator's previous output or NULL: its speed is used when fewer
 * than two wheel speeds are usable, and its sideslip (|beta| > 0.1 rad) or
 * oversteer indication holds the model checks (ay, ax, steering) off for
 * 1 s (in a spin those models do not hold; without est_prev there is no
 * such hold: docs/faults.md). rep may be NULL.
 * GRIP_ERR_NULL (mon or sample NULL), GRIP_ERR_STATE (mon not initialized:
 * every monitored input of the sample is then marked invalid, fault
 * GRIP_SIG_FAULT, and rep says all of them faulty). */
grip_status_t grip_monitor_step(grip_monitor_t *mon, grip_input_sample_t *sample,
                                const grip_est_output_t *est_prev, grip_monitor_report_t *rep);

/* The degraded contract applied to the estimator's output of the same
 * sample (call after grip_est_step): when rep->degraded has a bit of
 * `honour`, clears GRIP_MON_GATE_CLEARS in out->valid and sets
 * GRIP_EST_F_INPUT_DEGRADED in out->flags; otherwise out is unchanged.
 * honour: GRIP_MON_GATE_DEFAULT (both bits), or GRIP_MON_DEGR_SUSPECT alone
 * for a consumer that trades the unverified limit-manoeuvre rows for
 * availability (docs/faults.md gives both policies' figures); 0 = no gate.
 * The values are not touched. GRIP_ERR_NULL, GRIP_ERR_PARAM (honour has a
 * bit that is not a GRIP_MON_DEGR_* bit; out unchanged).
 * Gate a copy for the consumer and give grip_monitor_step the estimator's
 * own output as est_prev: the monitor's unstable-driving test reads beta,
 * which the gate marks invalid exactly when the monitor is unsure. Per step:
 *   grip_monitor_step(&mon, &sample, &est_out, &rep);
 *   grip_est_step(&est, &sample, &est_out);
 *   use = est_out; grip_monitor_gate(&rep, GRIP_MON_GATE_DEFAULT, &use); */
grip_status_t grip_monitor_gate(const grip_monitor_report_t *rep, uint32_t honour, grip_est_output_t *out);

#endif /* GRIP_MONITOR_H */
