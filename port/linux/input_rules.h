/*
 * input_rules.h - the physical plausibility of the estimator's inputs in a
 * CSV file (grip-replay --csv): for each input, the range its value can
 * have in its SI unit (grip_input_unit) and what a value outside it
 * usually is. A value outside is refused with file, line and column (or,
 * with --no-unit-check, taken as a range fault: not valid, never used).
 * The CAN path has its own ranges, in the signal table.
 *
 * X(input, lo, hi, hint, hint_max): a value outside [lo, hi] is refused;
 * when |value| <= hint_max the message adds hint; hint_max 0: no hint.
 * The bounds are wider than any car's (they catch units, not dynamics):
 * wheel and vehicle speed to 120 m/s (432 km/h, the estimator's own
 * range); a steering-wheel angle to 20 rad (3.2 turns of the wheel: no
 * steering column turns further); yaw rate to 10 rad/s (573 deg/s, twice
 * an automotive gyro's range); accelerations to 50 m/s^2 (5 g); brake
 * pressure to 300 bar; brake torque to 20 kN m per wheel; a rear-wheel
 * angle to 0.5 rad (production rear steering turns 10 deg at most).
 */
#ifndef GRIP_INPUT_RULES_H
#define GRIP_INPUT_RULES_H

#define GRIP_INPUT_RULES(X) \
    X(GRIP_IN_WHEEL_SPEED_FL, -10.0, 120.0, " (km/h?)", 450.0) \
    X(GRIP_IN_WHEEL_SPEED_FR, -10.0, 120.0, " (km/h?)", 450.0) \
    X(GRIP_IN_WHEEL_SPEED_RL, -10.0, 120.0, " (km/h?)", 450.0) \
    X(GRIP_IN_WHEEL_SPEED_RR, -10.0, 120.0, " (km/h?)", 450.0) \
    X(GRIP_IN_STEER_ANGLE, -20.0, 20.0, " (degrees?)", 1500.0) \
    X(GRIP_IN_YAW_RATE, -10.0, 10.0, " (degrees/s?)", 600.0) \
    X(GRIP_IN_AX, -50.0, 50.0, "", 0.0) \
    X(GRIP_IN_AY, -50.0, 50.0, "", 0.0) \
    X(GRIP_IN_VEHICLE_SPEED, -10.0, 120.0, " (km/h?)", 450.0) \
    X(GRIP_IN_BRAKE_PRESSURE_FL, -1.0e5, 3.0e7, "", 0.0) \
    X(GRIP_IN_BRAKE_PRESSURE_FR, -1.0e5, 3.0e7, "", 0.0) \
    X(GRIP_IN_BRAKE_PRESSURE_RL, -1.0e5, 3.0e7, "", 0.0) \
    X(GRIP_IN_BRAKE_PRESSURE_RR, -1.0e5, 3.0e7, "", 0.0) \
    X(GRIP_IN_BRAKE_TORQUE_FL, -2.0e4, 2.0e4, "", 0.0) \
    X(GRIP_IN_BRAKE_TORQUE_FR, -2.0e4, 2.0e4, "", 0.0) \
    X(GRIP_IN_BRAKE_TORQUE_RL, -2.0e4, 2.0e4, "", 0.0) \
    X(GRIP_IN_BRAKE_TORQUE_RR, -2.0e4, 2.0e4, "", 0.0) \
    X(GRIP_IN_REAR_STEER_ANGLE, -0.5, 0.5, " (degrees?)", 90.0)

#endif
