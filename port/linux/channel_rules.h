/*
 * channel_rules.h - the physical plausibility of measured and model-input
 * channels in CSV files: name, SI unit, the range a value can have in that
 * unit, and what values outside it usually are (a unit error). ONE table
 * for grip-tire (grip_tire.c) and the Python reader of measured data
 * (tools/grip_tools/channels.py parses this file), so a slip angle in
 * degrees or a load in kN is refused by the same rule everywhere.
 * docs/guarantees.md and docs/tools.md explain the rules.
 *
 * X(name, unit, lo, hi, what, hint, hint_max): a value outside [lo, hi]
 * (SI) is refused; when the largest |value| of the column is at most
 * hint_max, the message adds hint (" (degrees?)"); hint_max 0: no hint.
 * Keep the X(...) lines one per line and their arguments literal: the
 * Python reader reads them with a regular expression.
 */
#ifndef GRIP_CHANNEL_RULES_H
#define GRIP_CHANNEL_RULES_H

/* Slip and inclination angles: 1.5 rad is 86 degrees, beyond any slip
 * angle of a rolling tyre, so a larger value is an angle in degrees;
 * camber reaches 1.05 rad (60 degrees) on a motorcycle tyre. kappa: -1 is
 * a locked wheel, 1.5 a wheel spinning 2.5 times faster than it rolls.
 * Loads: negative up to -500 N is a lifted tyre in measured data. */
#define GRIP_CHANNELS(X) \
    X(t, "s", -1e9, 1e9, "time", "", 0) \
    X(kappa, "-", -1.5, 1.5, "longitudinal slip ratio (-1 = locked wheel)", " (percent?)", 100) \
    X(alpha, "rad", -1.5, 1.5, "slip angle", " (degrees?)", 90) \
    X(gamma, "rad", -1.05, 1.05, "inclination (camber) angle", " (degrees?)", 90) \
    X(fz, "N", -500, 1e5, "vertical load, positive when loaded", "", 0) \
    X(p, "Pa", 0, 1.5e6, "inflation pressure", " (bar?)", 20) \
    X(vx, "m/s", -150, 150, "longitudinal speed", " (km/h?)", 600) \
    X(vy, "m/s", -100, 100, "lateral speed", " (km/h?)", 600) \
    X(fx, "N", -1e5, 1e5, "longitudinal force", "", 0) \
    X(fy, "N", -1e5, 1e5, "lateral force", "", 0) \
    X(mz, "Nm", -1e4, 1e4, "aligning moment", "", 0) \
    X(r, "rad/s", -10, 10, "yaw rate", "", 0) \
    X(ay, "m/s2", -50, 50, "lateral acceleration", "", 0) \
    X(delta, "rad", -1.5, 1.5, "road-wheel steering angle", " (degrees?)", 90) \
    X(t_road, "degC", -50, 150, "road temperature", "", 0)

/* Whole-column rules, for unit errors that stay inside the ranges above:
 * - loads: a column whose largest load is positive but below
 *   GRIP_CHANNEL_FZ_KN_N newtons, or below GRIP_CHANNEL_FZ_KN_FNOMIN times
 *   the tyre's nominal load when the tool knows it (FNOMIN), is a load in
 *   kN labelled N (a tyre carries tens of kN at most: 60 kN is 60 "N");
 * - pressure: a largest positive pressure below GRIP_CHANNEL_P_BAR_PA
 *   pascals is bar, psi or kPa labelled Pa (no tyre runs below 20 kPa). */
#define GRIP_CHANNEL_FZ_KN_N 100.0
#define GRIP_CHANNEL_FZ_KN_FNOMIN 0.1
#define GRIP_CHANNEL_P_BAR_PA 20000.0

#endif
