/*
 * est_tuning.h - every tuning constant of the estimator (lib/est) in one
 * table, grouped by the stage of grip_est_step that uses it. For each: the
 * unit, what it means, and why it has this value (a physical quantity, a
 * sensor's range, a numeric format's limit, or tuning). Where tuning was
 * measured, the measurement that decided it: the float64 reference
 * (tools/grip_tools/reference/est.py, which mirrors every value) on the
 * simulator's manoeuvres unless another source is named; Fy errors are RMS
 * in % of the axle's peak, front / rear, beta errors RMS / max.
 * docs/estimator.md has the method around them. "Scaled units" are the
 * covariance's (EST_S_*).
 */
#ifndef GRIP_EST_TUNING_H
#define GRIP_EST_TUNING_H

/* ---- physics ----------------------------------------------------------- */
#define EST_G        9.80665 /* m/s^2  standard gravity                                  */

/* ---- input conditioning (est_input.c) ---------------------------------- */
#define EST_HOLD_T   0.05    /* s      a missing or invalid input is held this long, then
                              *        the outputs that need it lose their validity (tuning:
                              *        5 frames of a 100 Hz signal)                         */
#define EST_DELTA_MAX 0.7    /* rad    road-wheel angle limit: no car steers further; the
                              *        steering input's range is twice this at the wheel.
                              *        Beyond it F_STEER_LIMIT and no ay update (fitted to
                              *        the clamped angle, a straight road at lock took vy to
                              *        2.3 m/s, past both axles' peaks)                     */
#define EST_DELTA_R_MAX 0.25 /* rad   rear road-wheel angle limit (production rear steering
                              *        turns <= ~10 deg); cos and sin by their Taylor series,
                              *        error < 5e-8 within it; beyond it F_STEER_LIMIT      */
#define EST_WS_STEER_MAX 0.2 /* rad   a wheel steered beyond this enters the speed reference
                              *        only when no wheel steered less gives one: its speed
                              *        carries (vy + r x) sin(delta), i.e. the estimated vy
                              *        (a wrong vy at full lock took vx 8 -> 2.8 m/s)       */
#define EST_RATE_TOL_DIV 4   /* -      a step period off 1 / rate_hz by more than 1 / 4 of
                              *        it is F_RATE (a CAN sampler's jitter is far below;
                              *        25 Hz data replayed at 100 Hz is far above)          */
#define EST_WS_MAX   120.0   /* m/s    wheel-speed and vehicle-speed range (432 km/h); also
                              *        bounds vx                                            */
#define EST_YAW_MAX  2.5     /* rad/s  gyro range used (143 deg/s); also bounds the yaw-rate
                              *        state                                                */
#define EST_ACC_MAX  15.0    /* m/s^2  accelerometer range used (1.5 g); also bounds the
                              *        lateral balance's residual, so that mass x residual
                              *        fits QL                                              */

/* ---- longitudinal speed (est_speed.c) ---------------------------------- */
#define EST_V_STAND  0.3     /* m/s    standstill: every wheel below this; vx is then set
                              *        to 0, so an accelerometer bias cannot move a parked
                              *        car                                                 */
#define EST_AX_TH    0.3     /* m/s^2  braking below -AX_TH takes the fastest wheel as the
                              *        reference, driving above +AX_TH the unsteered rear
                              *        axle's mean (front drive) or the slowest; above
                              *        -AX_TH an undriven axle works at zero slip (tuning) */
#define EST_WHEEL_DEV 0.15   /* -      a wheel 15 % (+0.5 m/s) off the prediction counts as
                              *        locked or spinning and leaves the reference (tuning) */
#define EST_K_HI     5.0     /* 1/s    gain of the wheel speeds on vx when they agree with
                              *        each other and with the prediction (tuning)          */
#define EST_K_MID    1.5     /* 1/s    ... agree with each other but not with the prediction
                              *        (recovery after a long loss; tuning)                 */
#define EST_K_LO     0.5     /* 1/s    ... disagree (tuning)                                 */
#define EST_K_SLIP   0.2     /* 1/s    braking with the reference wheel below the prediction:
                              *        the brakes slip every wheel, so even the fastest reads
                              *        low; at K_HI vx followed it within 0.2 s, 2 % low, and
                              *        the ay update explained the missing force by mu 1.11
                              *        on a 0.6 road (wet brake in turn)                    */
/* neither braking nor driving: trusted wheels spread wider than SPREAD_REL
 * |vx| + SPREAD_ABS move the reference from their mean towards the cluster
 * the odd wheel left, fully at twice that spread (a driven wheel slipping in
 * a corner below the outlier test: the wet ramp steer's vx read 3.7 % high,
 * beta 0.52 / 1.02 -> 0.28 / 1.02 deg RMS / max, Fy 5.2 / 4.3 -> 2.7 / 2.3 %).
 * Continuous: a switch between the mean and one wheel chattered at its
 * threshold */
#define EST_SPREAD_REL 0.01  /* -                                                            */
#define EST_SPREAD_ABS 0.1   /* m/s                                                          */
#define EST_K_OFF    1.0     /* 1/s^2  learning gain of the ax offset (unconfigured grade,
                              *        accelerometer bias) from trusted wheels: with vx a
                              *        second-order complementary filter, poles near 0.2 and
                              *        4.8 /s (0.477 of a 0.5 m/s^2 offset after 15 s)      */
#define EST_AX_OFF_MAX 1.5   /* m/s^2  bound of that offset (a 15 % grade)                  */
#define EST_DR_AX    0.5     /* m/s^2  every wheel locked or spinning while |ax| >= DR_AX:
                              *        vx integrates ax (dead reckoning; four locked wheels
                              *        at 20 m/s on snow otherwise read a standstill). Below
                              *        it the car has stopped or slides at under 0.05 g, and
                              *        the wheels are taken again                            */
#define EST_DR_T     2.0     /* s      vx stays valid this long in dead reckoning (tuning)   */
#define EST_NOWHEEL_T 0.5    /* s      ... and this long with no wheel speed at all (tuning) */

/* ---- road bank (est_road.c, docs/estimator/road.md) ---------------------- */
#define EST_ROAD_L   20.0    /* m      distance constant of the bank's integrator, time constant
                              *        ROAD_L / |vx|: superelevation runs in over tens of metres
                              *        (the independent judge's banked curve: 8 deg over 40 m)   */
#define EST_ROAD_U   0.5     /* -      the bank adapts only with the model's utilization below
                              *        this (0.8: circle ramp wet, generic tire, 1.34 deg RMS;
                              *        0.5: 1.24; banked curve snow 0.49 -> 0.40)             */
#define EST_ROAD_RACC 0.3    /* rad/s^2 ... the yaw acceleration (low-passed) below this:
                              *        quasi-steady (transients carry the model's lag errors)  */
#define EST_ROAD_T_DR 0.2    /* s      time constant of that low-pass                          */
#define EST_ROAD_D   0.15    /* -      ... and the yaw rate short of the linear reference by
                              *        less than this share (the understeer test's d): a car
                              *        nearing its limit on an unknown low friction pulls vy as
                              *        a bank does (simulator ramp steer snow, reference: beta
                              *        0.50 deg RMS without, 0.26 / 0.34 / 0.46 at 0.1 / 0.15 /
                              *        0.2; banked curve snow, fitted tire: 6.9 deg at 0.1, 0.75
                              *        at 0.15)                                                */
#define EST_ROAD_T_REST 0.5  /* s      time constant of the bank at rest (ay reads gravity)     */
#define EST_ROAD_GY_MAX 4.4  /* m/s^2  bound of the bank's gravity: g sin(26.7 deg), a steep
                              *        oval's banking (tan_bank's range, 0.5)                  */

/* ---- learned cornering stiffness (est_stiffness.c, docs/estimator/stiffness.md)
 * A two-state Kalman filter on the axles' compliance scales 1 / k, from the
 * front-minus-rear lagged slip angle (which vy leaves out) against the
 * model slips of the axle forces the accelerometer and the gyro measure. */
#define EST_STF_S_U  0.05    /* -      unit of the filter's state 1 / k: its covariance, O(0.1 ..
                              *        100), and the innovation's variance in Q15.16             */
#define EST_STF_S_Y  0.01    /* rad    unit of the slip angles in the regression (crad)         */
#define EST_STF_P0   0.5     /* -      prior deviation of 1 / k: a tire file fitted on another
                              *        car, rim, pressure or wear is within a factor ~2 (the
                              *        generic tire on the independent judge's cars: 1 / k 0.55
                              *        - 0.61)                                                   */
#define EST_STF_SD_MIN 0.02  /* -      1 / k is never held more certain than this: the model's
                              *        structure (camber, roll steer, combined slip) limits it */
#define EST_STF_Q    1.0e-4  /* 1/s    random walk of 1 / k, variance per second: a tire's
                              *        stiffness moves with temperature, pressure and wear over
                              *        minutes                                                   */
#define EST_STF_R    1.0e-3  /* rad    deviation of the regression's slip-angle difference: the
                              *        steering sensor's offset (+-0.5 deg at the wheel / 15),
                              *        the gyro's noise L sigma_r / vx, the model's structure    */
#define EST_STF_T    0.1     /* s      time constant of the low-pass on the regression's signals
                              *        (the yaw acceleration is differenced from the gyro)       */
#define EST_STF_TC   2.0     /* s      the regression's error is the model's more than the
                              *        sensors', and persists through a manoeuvre: the update
                              *        counts TC rate steps as one measurement. Learning then
                              *        takes a minute of driving, and a road whose friction mu
                              *        has not found yet (its tire off the linear part at a low
                              *        model utilization) moves k a few per cent in a second
                              *        (snow slalom: 1 -> 2.5 in 0.5 s at 2 T = 0.2 s)       */
#define EST_STF_V    10.0    /* m/s    learns above this speed (L sigma_r / vx, and small steering
                              *        angles: the axle forces taken along the wheel's heading)  */
#define EST_STF_AX   1.0     /* m/s^2  ... with |ax| below this (combined slip, Fx's yaw moment) */
#define EST_STF_U    0.5     /* -      ... with the model's utilization below this: the slope's
                              *        inverse of the force error stays on the linear part      */
#define EST_STF_D    0.1     /* -      ... with the yaw rate within this share of the linear
                              *        reference (est_yaw_linear): on a friction the filter's
                              *        mu does not know yet, the tire leaves its linear part
                              *        while the model's utilization is still low            */
#define EST_STF_H_MIN 0.3    /* crad   ... and the model slips' sum above this (excitation: a
                              *        steering offset of 0.06 crad is a fifth of it)            */
#define EST_STF_SLOPE 1000.0 /* N/rad  an axle's slope below this gives no model slip          */
#define EST_STF_RACC 5.0     /* rad/s^2 the gyro's step-to-step yaw acceleration within this
                              *        (a car's in its linear range stays below 3): a glitch
                              *        is no measurement, and Iz dr/dt stays within Q23.8  */
#define EST_STF_K_MIN 0.4    /* -      learned scales within [K_MIN, K_MAX]                      */
#define EST_STF_K_MAX 2.5    /* -                                                               */

/* ---- learned longitudinal slip stiffness (est_stiffness_long.c,
 * docs/estimator/stiffness.md) A two-state Kalman filter on 1 / kx and the
 * axles' rolling-radius mismatch, from the front-minus-rear axle slip the
 * wheel speeds give (which vx leaves out) against the model slips of the
 * drive force the accelerometer measures, split by drive_front. */
#define EST_KX_S_U   0.05    /* -      unit of the filter's state 1 / kx (as EST_STF_S_U)         */
#define EST_KX_S_Y   0.001   /* -      unit of the slips in the regression and of the radius
                              *        mismatch (per mille): a driven axle's slip at 2 m/s^2
                              *        is ~25 units, the innovation's variance O(100)           */
#define EST_KX_P0    0.5     /* -      prior deviation of 1 / kx (as EST_STF_P0)                 */
#define EST_KX_SD_MIN 0.02   /* -      1 / kx is never held more certain than this               */
#define EST_KX_Q     1.0e-4  /* 1/s    random walk of 1 / kx, variance per second (as EST_STF_Q) */
#define EST_KX_D0    0.02    /* -      prior deviation of the radius mismatch: tread depth (8 mm
                              *        on a 0.3 m radius: 2.7 %), pressure and load (~1 %)      */
#define EST_KX_D_SD_MIN 2.0e-4 /* -    the mismatch is never held more certain than this        */
#define EST_KX_QD    1.0e-7  /* 1/s    random walk of the mismatch, variance per second: wear
                              *        over months, pressure and temperature over minutes       */
#define EST_KX_R     1.0e-3  /* -      deviation of the measured axle-slip difference: the wheel
                              *        speeds' tone-wheel noise, the accelerometer's offset and
                              *        grade (0.1 m/s^2: ~1e-3 of a driven axle's slip), the
                              *        drive split's and the load transfer's error           */
#define EST_KX_T     0.2     /* s      time constant of the low-pass on the regression's signals
                              *        (the wheel speeds' noise over the drive-force changes)    */
#define EST_KX_TC    2.0     /* s      the regression's error persists through a manoeuvre (the
                              *        accelerometer's offset, the split): TC rate steps count as
                              *        one measurement                                         */
#define EST_KX_V     10.0    /* m/s    learns above this speed (the slip is a wheel-speed
                              *        difference over vx)                                      */
#define EST_KX_AY    1.0     /* m/s^2  ... with |ay| below this (the lateral slip and the
                              *        combined slip stay out)                                  */
#define EST_KX_STEER 0.05    /* rad    ... with the road-wheel angle within this (the front
                              *        wheels' speeds are taken along the car's axis)           */
#define EST_KX_U     0.35    /* -      ... with the model's utilization below this: the
                              *        regression is linear in the force, and the tire's secant
                              *        stiffness falls below its initial slope as it is used
                              *        (drive sequence, tire 1.4 x: kx 1.35 up to 0.3, 1.29
                              *        with traction up to 0.46)                              */
#define EST_KX_AX_C  0.3     /* m/s^2  ... and the drive force over the mass above -AX_C: never
                              *        while braking (the brake balance is not the drive split
                              *        and moves with EBD / ABS); within +-AX_C it is coasting,
                              *        which measures the mismatch                              */
#define EST_KX_AX_T  0.5     /* m/s^2  above this it is traction, which measures kx ...          */
#define EST_KX_H_MIN 5.0     /* per mille ... when the drive force's model slip difference is
                              *        at least this (excitation: an AWD whose split follows
                              *        the axle loads has none)                                  */
#define EST_KX_DV_MAX 2.0    /* m/s    the wheel-speed difference taken within this (Q15.16: x
                              *        1000 per mille stays in range)                           */
#define EST_KX_K_MIN 0.4     /* -      learned scale within [K_MIN, K_MAX]                       */
#define EST_KX_K_MAX 2.5     /* -                                                               */
#define EST_KX_D_MAX 0.05    /* -      the mismatch within +-D_MAX                               */

/* ---- learned roll gradient (est_roll.c, docs/estimator/roll.md)
 * A scalar Kalman filter on the roll gradient k from the band-passed
 * measured ay against the band-passed lateral acceleration vx r + dvy/dt:
 * bp(ay_meas) - bp(a) = g k bp(a). The band-pass (low-pass RG_T less a
 * low-pass RG_TH of it) takes out the sensor offsets and a constant or
 * slowly changing bank; the update runs only while the car weaves (a bank
 * does not reverse with the steering). Its gates on speed, ax, the model's
 * utilization and the linear yaw response are the stiffness learner's
 * (EST_STF_V, _AX, _U, _D). */
#define EST_RG_S_U   0.001   /* rad/(m/s^2) unit of the filter's state: k 0.0088 is 8.8 units */
#define EST_RG_P0    0.01    /* rad/(m/s^2) prior deviation of k around cfg.roll_gradient:
                              *        road vehicles roll 0.001 - 0.03 (the judge's cars
                              *        0.0116 - 0.0159 against the default 0.0088)             */
#define EST_RG_SD_MIN 3.0e-4 /* rad/(m/s^2) k is never held more certain than this (the
                              *        regression's dvy/dt and roll-lag error)                  */
#define EST_RG_Q     1.0e-8  /* (rad/(m/s^2))^2/s random walk of k: load and passengers change
                              *        the roll gradient between trips, not within minutes      */
#define EST_RG_R     0.03    /* m/s^2  deviation of the band-passed difference: dvy/dt's error,
                              *        the roll's lag behind ay, a bank's change along the road
                              *        (0.018 RMS on the golden weave at the true k)           */
#define EST_RG_TC    10.0    /* s      that error persists over a weave's slowest cycle (0.11
                              *        Hz): TC rate steps count as one measurement              */
#define EST_RG_T     1.0     /* s      the band-pass's low-pass: the roll follows ay below the
                              *        body's roll mode (~1.5 Hz), dvy/dt's error shrinks      */
#define EST_RG_TH    8.0     /* s      ... less its low-pass over TH: offsets and a bank that
                              *        holds for TH out                                         */
#define EST_RG_AY    4.0     /* m/s^2  learns with the measured |ay| within this (the roll is
                              *        linear in ay; bump stops beyond)                        */
#define EST_RG_BANK  0.3     /* m/s^2  ... with bank_est, the bank estimate within this        */
#define EST_RG_H_MIN 0.5     /* m/s^2  ... while |bp(a)| is at least this (excitation) ...     */
#define EST_RG_T_ALT 3.0     /* s      ... and bp(a) was beyond +H_MIN and beyond -H_MIN within
                              *        the last T_ALT: a weave, not a curve's entry (a curve
                              *        banked 8 deg towards its centre took k 7 % lower at 4 s,
                              *        0.3 % at 3 s, without the sample gate EST_RG_DK; to the
                              *        floor without both; golden roll_100hz)                  */
#define EST_RG_DK    0.01    /* rad/(m/s^2) ... and the sample's own k, z / (g bp(a)), within
                              *        DK of the k in use: a bank changing within the band
                              *        scatters it far wider (judge, bank and grade road: the
                              *        Vanagon's learned 0.0135 went to 0.0084 on snow without
                              *        it, stayed at 0.0133 with it)                           */
#define EST_RG_K_MIN 0.0005  /* rad/(m/s^2) learned k within [K_MIN, K_MAX]: a race car
                              *        rolls ~0.001 (the AV-21's configuration), a van 0.02    */
#define EST_RG_K_MAX 0.03    /* rad/(m/s^2)                                                    */

/* ---- lateral observer on / off (est_lateral.c) ------------------------- */
#define EST_V_ON     3.0     /* m/s    the lateral observer starts above ...                 */
#define EST_V_OFF    2.5     /* m/s    ... and stops below (hysteresis; tuning); also the
                              *        floor of |vx| in the slip-angle and sideslip quotients */

/* ---- lateral filter: scaled units, noises, bounds (est_lateral.c) ---------
 * The covariance lives in scaled units (state i in units of S_i) so that it
 * runs in Q15.16: variances O(1 .. 400), and with the measurement rows
 * bounded (H_MAX_VY, H_MAX) the innovation variance h P h' + r stays below
 * (5 x 20 + 2 x 20 + 2 x 20)^2 + 192 = 32592 < 32768. */
#define EST_S_VY     0.05    /* m/s                                                         */
#define EST_S_R      0.005   /* rad/s                                                       */
#define EST_S_MU     0.02    /* -                                                           */
#define EST_S_B      0.001   /* rad/s  gyro bias; also the bias state's own unit, so that
                              *        its per-step corrections survive Q15.16 (1 LSB =
                              *        1.5e-5 rad/s in SI)                                   */
#define EST_S_AY     0.5     /* m/s^2  lateral and longitudinal acceleration                */
/* measurement noise [scaled units^2], as sigma in SI */
#define EST_R_YAW    1.44    /* yaw rate, sigma 0.006 rad/s                                 */
#define EST_R_AY     0.64    /* ay, sigma 0.4 m/s^2 below U_R0 (grows at the limit, below)  */
#define EST_R_AX     1.0     /* ax, sigma 0.5 m/s^2                                          */
/* continuous process noise [scaled units^2 / s] */
#define EST_Q_VY     100.0   /* vy' 0.5 m/s^2 /sqrt(s): the kinematic vy' = ay - r vx errs
                              *        by the ay error, roll and bank                         */
#define EST_Q_R      3600.0  /* r' 0.3 rad/s^2 /sqrt(s)                                       */
#define EST_Q_MU     6.25    /* mu 0.05 /sqrt(s): mu's confidence decays without excitation  */
#define EST_Q_B      0.25    /* gyro bias random walk 0.0005 rad/s /sqrt(s)                    */
/* initial variances [scaled units^2] */
#define EST_P0_VY    36.0    /* sigma 0.3 m/s                                                */
#define EST_P0_R     16.0    /* sigma 0.02 rad/s                                             */
#define EST_P0_MU    225.0   /* sigma 0.3: the prior 1.0 +- 0.3 (mu_conf 0 at start)          */
#define EST_P0_B     100.0   /* sigma 0.01 rad/s                                             */
#define EST_P_MIN    0.01    /* diagonal of P held in [P_MIN, P_MAX] and every correlation    */
#define EST_P_MAX    400.0   /* below 0.99: P stays positive definite and inside Q15.16      */
#define EST_H_MAX_VY 5.0     /* bounds of the measurement row's vy entry ...                 */
#define EST_H_MAX    2.0     /* ... and of its r and mu entries (the 32768 bound above)      */
#define EST_NU_SIGMA 4.0     /* innovations clamped to 4 sigma: robust to glitches, and the
                              *        NIS stays <= 16, inside Q15.16                          */
#define EST_VY_K     1.0     /* -      |vy| <= VY_K |vx| + 1 m/s: sideslip up to ~45 deg (a
                              *        spin); 0.5 |vx| + 1 cut the simulator's spin-outs at
                              *        27 deg                                                */
#define EST_B_MAX    0.05    /* rad/s  bound of the gyro-bias state (tuning)                 */
/* the gyro bias adapts only where the tire model is trusted, else it absorbs
 * the model's errors (0.01 rad/s on a generator with no offset at all) */
#define EST_B_U      0.5     /* -      model utilization below this ...                       */
#define EST_B_A      4.0     /* m/s^2  ... |ay| below this ...                                */
#define EST_B_AX     1.0     /* m/s^2  ... |ax| below this (also for the bias at rest, and
                              *        |ax| for the understeer bound's withdrawal) ...          */
#define EST_B_RACC   2.0     /* rad/s^2 ... and the model's yaw acceleration below this (the
                              *        tire lag's error is largest in fast yaw transients): a
                              *        6 mrad/s offset learned to 2.50 mrad/s; 1.0 -> 2.21
                              *        (shuts the step steer's build-up), 3.0 -> 1.95          */
/* Noise of the ay update at the friction limit, where the tire model is
 * least certain: R grows from utilization U_R0 to 1 by up to R_LIM x with the
 * most-used tire, and by up to R_AXLE x more with an axle's load-weighted
 * mean: 10 x R (1.26 m/s^2) with one tire at its limit, 300 x R (6.9 m/s^2:
 * vy left to the kinematics) with both tires of an axle. With a constant R
 * the dry ramp steer overshot beta by 0.8 deg, and 10 x R lost 2.2 m/s of vy
 * in the wet sine with dwell's spin. R_AXLE 40 / 140 / 290 -> that run's beta
 * max 3.41 / 1.95 / 1.42 deg, at a cost of V_MU on the simulator runs 2,168 /
 * 1,878 / 1,028 steps. The axle term and not a larger one-tire factor: one
 * wheel's faked slip (a wheel speed 10 % high) then switched the update off
 * for the whole fault. 0.64 x 300 = 192 keeps the innovation variance within
 * the 32768 bound above */
#define EST_U_R0     0.8     /* -                                                             */
#define EST_R_LIM    9.0     /* -                                                             */
#define EST_R_AXLE   290.0   /* -                                                             */
#define EST_AY_U_K   0.5     /* -      while the car is at its limit (the mu-independent limit
                              *        test) and mu is not held by the understeer bound, the
                              *        ay noise takes the model's utilization at mu + AY_U_K
                              *        sigma_mu: with mu still too high the model sits at its
                              *        own limit, R at 150 x kept mu from falling (sine with
                              *        dwell snow: mu stalled at 0.55 - 0.6 for 0.15 s)        */

/* ---- tire model at the prior state (est_tires.c) ----------------------- */
#define EST_G_MIN    0.05    /* -      floor (tuning) of the slope factor sqrt(1 - u) of
                              *        dFy/dalpha, a reduction between the linear and the
                              *        FIALA (1 - u)^(2/3)                                      */
/* tire relaxation: the tires work at the slip angle lagged by the relaxation
 * length sigma (sigma d(alpha_t)/dt + |vx| alpha_t = |vx| alpha), sigma from
 * the tire file at the axle's static load (C_alpha / LATERAL_STIFFNESS, else
 * the MF 5.2 PTY1 / PTY2 form, else no lag) in proportion to the wheel's
 * load. The simulator's tires lag: without it the model force led the
 * truth's through every steering reversal (sine with dwell dry beta 0.35 /
 * 0.74 -> 0.17 / 0.52 deg RMS / max) */
#define EST_SIG_MIN  0.02    /* m      least relaxation length of a wheel (tuning)            */
#define EST_SIG_MAX  5.0     /* m      most of an axle: a file's stiffnesses far off give at
                              *        most this                                               */
#define EST_RLX_A_MAX 16.0   /* -      exponent |vx| dt / sigma capped here: exp(-16) is below
                              *        one Q15.16 unit                                         */

/* ---- friction (est_friction.c) ----------------------------------------- */
#define EST_MU_MIN   0.1     /* -      bounds of mu (1 = the tire as fitted; tuning); the      */
#define EST_MU_MAX   1.2     /* -      friction in use also bounds it from below each step     */
#define EST_MU_INIT  1.0     /* -      prior: the tire as fitted (P0_MU: snow 2.3 sigma away)  */
#define EST_V_EXC    5.0     /* m/s    mu adapts, and the limit tests run, only above (tuning) */
#define EST_EXC_U    0.2     /* -      excitation: a wheel's slips would use this share of the
                              *        tire's own friction (mu = 1, never the estimate: a
                              *        falling mu would excite its own adaptation); at 0.5 the
                              *        gate opened at the snow sine with dwell's onset only
                              *        once the truth's front axle was at 90 % of its limit,
                              *        and mu was a second behind                              */
#define EST_EXC_A    1.0     /* m/s^2  ... and |ax| + |ay| at least this (tuning)               */
/* friction-limit test, independent of the mu estimate: the yaw rate leaves
 * the linear bicycle reference, lagged over LIM_TAU, by more than LIM_REL
 * |r_lin| + LIM_ABS for LIM_T with |a| >= LIM_A (tuning). LIM_T also
 * debounces the understeer bound and its withdrawal: 0.08 s with a
 * 1.0 m/s^2 gate let a steering offset fake a deficit within 0.08 s (fault
 * table 0 -> 2 NEITHER), 0.06 s took sine with dwell wet's mu 0.13 off */
#define EST_LIM_TAU  0.15    /* s                                                             */
#define EST_LIM_A    2.0     /* m/s^2                                                         */
#define EST_LIM_REL  0.15    /* -                                                             */
#define EST_LIM_ABS  0.03    /* rad/s                                                         */
#define EST_LIM_T    0.2     /* s                                                             */
/* low-friction detection at the understeer limit: the yaw rate below the
 * lagged reference by the share d >= US_D (reference above US_R) for LIM_T;
 * the front axle's friction in use over the utilization the deficit implies,
 * u(d) = min(US_UMAX, US_U0 + US_U1 d), bounds mu from above when below
 * US_ZMAX. u(d) follows the dry ramp steer (friction in use over the true mu
 * 0.56 / 0.71 / 0.80 / 0.83 at d = 0.15 / 0.25 / 0.35 / 0.4; wet and snow
 * higher), the curve that pulls mu down least; US_U0 0.5 took the dry ramp
 * steer to beta 0.69 / 1.25 deg (mu 0.14 off) */
#define EST_US_D     0.15    /* -      at 0.3 the snow step steer's tires were at their limit
                              *        1.3 s before the deficit reached it; 0.2 -> 0.15: step
                              *        steer snow beta 0.53 / 1.00 -> 0.50 / 0.88 deg RMS /
                              *        max, the AV-21 log's misfit steps 5,194 -> 5,213         */
#define EST_US_R     0.02    /* rad/s  (tuning)                                                */
#define EST_US_U0    0.3     /* -                                                             */
#define EST_US_U1    1.4     /* -                                                             */
#define EST_US_UMAX  0.85    /* -                                                             */
#define EST_US_ZMAX  0.8     /* -      on dry the test cannot tell 1.0 from 0.85; without this
                              *        cut the dry ramp steer went to mu 0.83, beta 2.1 deg RMS */
/* withdrawal of that bound: mu held down by it and unconfirmed since (P_mu >
 * P_CONF, i.e. mu_conf < 0.5) goes back to its value before the bound once
 * the bound's own test has said "no deficit" (-LIM_REL < d < US_D) in steady
 * cornering (|ax| and |dvy/dt| below B_AX) for LIM_T at a front friction in
 * use between REL_K and 1 / REL_K of the one at which the bound was last
 * set: a steering offset's faked deficit ends, a low road's does not. Far
 * more friction in use shows the bound too low, which the friction in use
 * lifts by itself (without the upper end the value before overshot: mu
 * 0.43 -> 1.11 on the generator's 0.5 road) */
#define EST_REL_K    0.8     /* -                                                             */
#define EST_STEADY_K 3.0     /* -      "steady" for that withdrawal: |dvy/dt| = |ay + g_y - r vx|
                              *        within this many kin_acc_sd (the accelerometer's offset
                              *        and the unknown bank, what a car in a steady turn shows);
                              *        a car whose sideslip grows at the limit (snow lane change:
                              *        0.76 m/s^2) is not steady, and withdrawing the bound
                              *        there put mu 0.27 above the road's                      */
/* P_mu [scaled units^2] at mu_conf 0.5 (sigma_mu 0.1) */
#define EST_P_CONF   (((EST_CONF_S0 - 0.05) / EST_S_MU) * ((EST_CONF_S0 - 0.05) / EST_S_MU))
#define EST_CUT_CLEAR 0.05   /* -      the balances' memory is cleared at the understeer bound's
                              *        cut only above this cut: clearing at every cut, small
                              *        cuts re-armed the bound every few steps and the balances
                              *        never built up (step steer snow front Fy 3.9 -> 5.1 %)   */
/* mu's column of the Jacobians: the secant of mu F0(alpha / mu) from mu down
 * to mu - dmu, dmu = SEC_K sigma_mu within [SEC_MIN, mu - mu_floor] (the
 * friction in use), on the force shape tabulated at init: a statistical
 * linearization over mu's own uncertainty. The tangent is 0 while the model
 * tire is linear, however far a lower mu would take it (the snow onset: mu
 * stayed at its prior while vy took the ay deficit) */
#define EST_SEC_K    3.0     /* -      the prior 1.0 +- 0.3 puts snow 2.3 sigma away: SEC_K 1.5
                              *        / 2 / 2.5 / 3 / 4 -> sine with dwell snow front Fy 5.6 /
                              *        4.9 / 4.8 / 4.2 / 4.6 %                                   */
#define EST_SEC_MIN  0.02    /* -      least span: with mu known the column is the shape's own
                              *        tangent                                                  */
#define EST_SHAPE_F_MIN 0.01 /* -      no column where the shape |Fy| / Fz is below this (the
                              *        origin: 0 / 0, and the column is 0 there anyway)         */
/* the longitudinal (ax) update also runs without a speed reference while
 * braking with a wheel at |kappa| >= LOCK_K (locked, or cycled by an ABS past
 * the tire's peak): such a wheel works at the road's friction, and a 0.3 %
 * speed-reference error moves its slip by 0.003 only. LOCK_K 0.5 / 0.15 /
 * 0.1 -> the wet mu step's error 1 s after the limit 0.70 / 0.01 / 0.02;
 * below 15 % the test reaches into braking below the limit, where the slip
 * depends on the speed reference */
#define EST_LOCK_K   0.15    /* -                                                             */
#define EST_R_LOCK   9.0     /* scaled units^2: sigma 1.5 m/s^2; as a normal update 0.5 m/s^2
                              *        set V_MU on the wet brake in turn with errors up to
                              *        0.18. Biased (the free wheels' slips, drag and rolling
                              *        resistance are in the same sum), so it moves the state
                              *        but keeps the covariance. Independent judge, fitted
                              *        configuration, mu error 1 s after the limit, R_LOCK 9 / 6
                              *        / 4 / 3: Vanagon brake in turn wet 0.112 / 0.096 / 0.074
                              *        / 0.055, Escort mu step wet 0.031 / 0.015 / 0.015 / 0.015,
                              *        Vanagon mu step snow 0.000 / 0.010 / 0.021 / 0.028, the
                              *        other 15 brake-in-turn and mu-step runs unchanged; but
                              *        at 6 the lock update outweighs the friction ellipse: a
                              *        tire whose lateral peak is 1.25 x its braking peak
                              *        (test_lateral_peak_above_braking_peak) reads the wet mu
                              *        step 0.090 off on the ellipse (0.070 at 9)               */

/* ---- forces and outputs (est_outputs.c) -------------------------------- */
/* the yaw balance: the yaw moment the model lacks (the yaw-rate update's
 * correction of the predicted r as a yaw acceleration, at most MB_RACC,
 * times Iz / l) moves force from one axle to the other at the outputs,
 * low-passed over MB_TAU; not while |ax| >= MB_AX, where the model's left /
 * right Fx moment errs too (wet brake in turn rear Fy 3.6 -> 8.4 % without
 * the gate) */
#define EST_MB_TAU   0.05    /* s      0.03 / 0.05 / 0.07 / 0.1 -> sine with dwell snow Fy
                              *        6.4 / 4.8, 7.3 / 4.7, 8.1 / 5.2, 9.1 / 6.0 %; 0.03
                              *        spreads the differentiated gyro noise over every run
                              *        (brake in turn snow rear 1.8 -> 3.4 %)                   */
#define EST_MB_RACC  20.0    /* rad/s^2 (tuning)                                               */
#define EST_MB_AX    1.0     /* m/s^2                                                          */
#define EST_SB_TAU   0.02    /* s      the lateral balance: the lateral force the model lacks
                              *        after the updates (mass x (ay - the model's ay at the
                              *        updated state)) in the axles' static shares, low-passed
                              *        over SB_TAU; not while |ax| >= MB_AX. The ay noise
                              *        (0.03 m/s^2) is 44 N, so no longer filter is needed:
                              *        0.1 s lagged the reversals                               */

/* ---- consistency checks (est_checks.c) --------------------------------- */
#define EST_CONF_S0  0.15    /* -      mu_conf = (CONF_S0 - sigma_mu) / 0.1: 1 at sigma_mu <=
                              *        0.05, 0 at >= 0.15; V_MU from 0.5                         */
/* model consistency (misfit): two statistics low-passed over MF_TAU: the ay
 * update's normalized innovation squared, and the share of time the model
 * claims saturated tires (utilization >= SAT_U) while the mu-independent
 * limit test does not fire. The NIS alone is blind to a model the filter
 * absorbs into vy and mu (the AV-21 log: at most 0.19) */
#define EST_MF_TAU   2.0     /* s      window of both                                          */
#define EST_NIS_HI   3.84    /* -      misfit above: chi-square(1) 95 % point ...                */
#define EST_NIS_LO   1.0     /* -      ... cleared below: a consistent filter's mean            */
#define EST_SAT_U    0.95    /* -      model utilization counted as saturated                   */
#define EST_SAT_HI   0.7     /* -      misfit above: between the golden generator's 0.49 / 0.54
                              *        (the right tire) and the AV-21 log's 0.92; 0.5 was within
                              *        0.01 of the generator                                    */
#define EST_SAT_LO   0.1     /* -      ... cleared below (with the NIS below NIS_LO)            */
#define EST_CONF_MISFIT 0.45 /* -      mu_conf cap while misfit, below V_MU's 0.5               */
#define EST_SAT_MU   0.1     /* -      mu_conf also capped from when the saturation share rises
                              *        above this (the misfit is declared late: on the AV-21
                              *        log the ay updates at the limit confirmed a wrong mu
                              *        while the share rose 0.12 -> 0.37) ...                    */
#define EST_SAT_MU_LO 0.05   /* -      ... until it falls below this: a single threshold toggled
                              *        V_MU where the share hovers at 0.1 (golden bicycle_1khz:
                              *        the fixed build's mask on 59 -> 4 of 4,000 rows)          */

/* ---- error bounds (est_integrity.c, docs/estimator/integrity.md) ------- */
/* The kinematic vy's deviation grows per second by the configured
 * accelerometer share (kin_acc_sd), the gyro offset's deviation times vx,
 * and ROLL_TOL of the roll compensation g roll_gradient |ay|: a car's roll
 * gradient is known within about a quarter without a roll measurement. */
#define EST_ROLL_TOL 0.25    /* -      share of the roll compensation taken as its error       */
#define EST_DIS_K    3.0     /* -      filter and kinematic vy disagree beyond this many joint
                              *        deviations (3: a consistent pair fails 0.3 % of steps)  */
#define EST_SD_CAP   100.0   /* m/s    every deviation capped here: not estimated at all (its
                              *        square 1e4 within Q15.16)                               */
#define EST_WS_TOL   0.012   /* -      deviation of a wheel-speed reference's scale: a
                              * rolling radius within +-2 % of the one the speeds
                              * were converted with (tread wear, pressure, load),
                              * uniform: 0.02 / sqrt(3) (est_bound_speed)         */
#define EST_SLIP_MAX 0.2     /* -      the reference wheels' slip counted at most this
                              * (a tire's peak slip; beyond, the wheel is an outlier
                              * and leaves the reference)                          */
#define EST_SD_MIN   0.001   /* m/s    the blend's ratio q = sd_filter / sd_kinematic formed
                              *        with the kinematic deviation at least this ...          */
#define EST_Q_MAX    100.0   /* -      ... and taken at most this (its square within Q15.16)    */
#define EST_KIN_Q0   0.5     /* -      the filter's vy taken whole while its deviation is at most
                              *        this share of the kinematic one's; none from 1         */
#define EST_SD_VY_EDGE 0.01  /* m/s    vy within this of its bound |vx| + 1 is held there, not
                              *        estimated: the deviation is SD_CAP                      */

/* ---- sensitivity study ------------------------------------------------- */
/* `grip est-sensitivity` builds the estimator with one value changed: the
 * header named here #undefs and redefines it. Never set in a product build;
 * docs/estimator/sensitivity.md has each constant's class and measured
 * sensitivity on the independent judge. */
#ifdef GRIP_EST_TUNING_OVERRIDE
#include GRIP_EST_TUNING_OVERRIDE
#endif

#endif
