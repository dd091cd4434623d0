"""Golden vectors of the onboard estimator (lib/est): whole input sequences
run through the float64 reference grip_tools.reference.est, written as
build/golden/est_<name>.txt for tests/unit/test_est_golden.c.

Input sequences (the C test replays exactly the same rows):
  bicycle_100hz   internal generator (below; single-track, Magic Formula
                  axles with the tire's lateral relaxation): steer steps,
                  slalom, braking in a turn, on mu = 1.0 then 0.5, 100 Hz
  bicycle_1khz    the same generator at 1 kHz, mu = 0.6, shorter
  faults_100hz    the generator's signals with faults injected: invalid and
                  stale flags, NaN/Inf values (valid flag set), saturated
                  values, a locked wheel, standstill, reversing
  road_bank_100hz the internal generator on a road banked 0.1 + 0.04 sin(2 pi
                  t / 6 s) rad that the configuration does not give, run
                  with bank_est = 1 (the bank estimated)
  stiffness_100hz the internal generator on mu 1.0 with half the steering,
                  its tires 1.5 x as stiff (LKY) as the estimator's, run
                  with stiff_est = 1 (each axle's stiffness learned)
  stiffness_long_100hz a straight drive (drive_inputs below: a light sine of
                  steering, coasting, traction at 1.5 and 2.5 m/s^2, braking,
                  a slalom while coasting at the end),
                  rear-wheel drive, the generator's tire 1.4 x as stiff in
                  slip (LKX) as the estimator's, the front wheels' rolling
                  radius 0.4 % larger, run with kx_est = 1, drive_front = 0
                  (the longitudinal slip stiffness and the mismatch learned);
                  one column more than the others: the learned kx
  front_drive_100hz the same drive on a front-driven car (front_drive_inputs
                  below: the left front wheel 10 % fast while driving, ax
                  0.1 m/s^2 high), run with drive_front = 1 (the rear
                  axle's mean as the speed reference while driving)
  roll_100hz      the internal generator whose body rolls 0.015 rad/(m/s^2)
                  (the accelerometer reads its gravity), 22 m/s: a 30 s
                  weave, then 5 s into a left curve on a road banked 8 deg
                  towards its centre; run with roll_est = 1 (the roll gradient
                  learned); one column more: the roll gradient in use
  aero_bank_100hz the internal generator at 26 m/s, run with the vehicle-level
                  effects on: downforce C_L A = 2.5 m^2 (front share 0.42,
                  rho 1.2), road bank tan = 0.04 (rise to the left) and grade
                  tan = 0.02, drag area C_D A = 0.62 m^2 and rolling
                  resistance 0.01, sensor latency 20 ms (outputs extrapolated),
                  road wheels 0.1 s (first order) behind the steering signal,
                  steering angle 10 ms old (AERO_BANK below;
                  test_est_golden.c sets the same); the
                  rear-left wheel locked 0.3 s while braking, so the
                  locked-wheel ax update (the one that uses drag and rolling
                  resistance) runs
  steer_offset_100hz the internal generator on mu = 1.0 at 40 % steering and
                  no braking, a +0.24 rad steering-wheel offset from 4.3 to
                  5.0 s in the steady turn (STEER_OFFSET below): the offset
                  fakes an understeer deficit, the understeer bound holds mu
                  down (~0.35), and after the offset the bound is withdrawn
                  (mu back to its value before), so that branch runs. The
                  offset is 0.24, not 0.26: at 0.26 the deficit falls on
                  0.15000, exactly the threshold, in the step the withdrawal
                  starts, and Q15.16 takes that decision a step later than
                  the float64 reference; at 0.24 the nearest step is 0.005
                  from the threshold
  rear_steer_100hz the internal generator at 9 m/s with twice the steering,
                  the rear wheels steered at -0.3 x the front road-wheel angle
                  (opposite phase, as production rear steering does at low
                  speed), the rear angle given as the input
                  rear_steer_angle and cfg rear_steer = 1
  sim_sine_dwell  the reference vehicle simulator (grip_tools.sim) when
                  present: sine with dwell on a wet road, its sensor models
                  (noise, delay, quantization); skipped if the simulator is
                  not importable

Each row: time, 18 input values, the valid mask (bit i = input i valid),
then the reference outputs (columns in the header). Configuration: the
passenger car of est_ref.config / grip_est_config_default with the
PacejkaBook_Defaults.tir tire on both axles.
"""
import math
import os

import numpy as np

from grip_tools.reference import est as est_ref, tir
from grip_tools.golden.io import header
from grip_tools.paths import TEST_DATA

TIRE = "PacejkaBook_Defaults"
SEED = 5


def tire_path():
    return os.path.join(TEST_DATA, "mfeval-tir", TIRE + ".tir")


def tire_params():
    return tir.load_params(tire_path())


# ---------------------------------------------------------------------------
# internal generator: single-track model with Magic Formula axle forces

def _measure(rng, value, valid, ws, swa, r, ax, ay, rear_steer=None):
    """One row of the generators' sensor inputs from the true states, in
    place: value, valid the row's (18,) slices; ws the four wheel speeds
    [m/s], swa the steering-wheel angle [rad], r the yaw rate [rad/s], ax, ay
    the specific forces [m/s^2], rear_steer the rear road-wheel angle [rad]
    (None: not measured, the input left invalid). Gaussian noise from rng,
    drawn in this order: the wheel speeds (0.01 m/s), steering (0.001 rad),
    yaw rate (0.002 rad/s), ax, ay (0.03 m/s^2), rear steering (0.0002 rad);
    the order is part of every golden sequence the generators make."""
    for i in range(4):
        value[est_ref.WS[i]] = ws[i] + rng.normal(0, 0.01)
    value[est_ref.STEER] = swa + rng.normal(0, 0.001)
    value[est_ref.YAW] = r + rng.normal(0, 0.002)
    value[est_ref.AX] = ax + rng.normal(0, 0.03)
    value[est_ref.AY] = ay + rng.normal(0, 0.03)
    valid[:8] = 1
    if rear_steer is not None:
        value[est_ref.REAR_STEER] = rear_steer + rng.normal(0, 0.0002)
        valid[est_ref.REAR_STEER] = 1

def bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5), seed=SEED, v0=22.0, steer_gain=1.0,
                   brake_demand=3.0, rear_gain=0.0, bank=None, lky=1.0, roll=0.0, swa_fn=None):
    """A nonlinear single-track run (steer steps, slalom, braking in a turn).
    mu_road: (mu of the first half, mu of the second half), as a scale of the
    tire's friction (LMUX, LMUY); steer_gain scales the steering-wheel angle,
    brake_demand [m/s^2] the braking in the turn, rear_gain the rear
    road-wheel angle as a share of the front one (negative: opposite phase;
    0: no rear steering, the input not given), bank a function of time that
    gives the road's bank [rad, left edge up positive] (gravity then pulls
    the car by -g sin(bank) along y, and the accelerometer, reading specific
    force, gives the tires' force over the mass), lky the generator tire's
    cornering stiffness as a scale of the estimator's (LKY), roll the body's
    roll gradient [rad/(m/s^2)] (the accelerometer rolls by roll x the
    road-plane specific force f and reads f cos(phi) + g sin(phi)), swa_fn a
    function of time giving the steering-wheel angle [rad] in place of the
    step, slalom and hold (then no braking). Returns time, value (N, 18), valid (N, 18)
    and the truth dict (vx, vy, r, mu)."""
    P0 = tire_params()
    cfg = est_ref.config(P0)
    P0 = dict(P0, lky=P0["lky"] * lky)
    m, iz, lf, lr = cfg["mass"], cfg["iz"], cfg["lf"], cfg["lr"]
    l = lf + lr
    fzf, fzr = 9.80665 * m * lr / l / 2, 9.80665 * m * lf / l / 2
    rng = np.random.default_rng(seed)
    n = int(round(duration / dt))
    t = np.arange(n) * dt
    value = np.zeros((n, est_ref.N_IN))
    valid = np.zeros((n, est_ref.N_IN), dtype=np.uint8)
    truth = {k: np.zeros(n) for k in ("vx", "vy", "r", "mu")}
    # the tires' lateral relaxation (first-order lag of the slip angle over
    # sigma = cornering stiffness / LATERAL_STIFFNESS, as the reference
    # simulator's MF 6.x tires): a tire answers a slip-angle change over a
    # rolling distance, not at once
    sigma = []
    for fz in (fzf, fzr):
        o = est_ref.mf.evaluate(P0, np.zeros(2), np.array([0.01, -0.01]), 0.0, np.full(2, fz), None, 20.0)
        k_alpha = (o["fy"][1] - o["fy"][0]) / 0.02
        sigma.append(k_alpha / P0["lateral_stiffness"] if P0.get("lateral_stiffness", 0.0) > 0 else 0.0)
    a_lag = None
    vx, vy, r = v0, 0.0, 0.0
    for k in range(n):
        tk = t[k]
        mu = mu_road[0] if tk < duration / 2 else mu_road[1]
        P = dict(P0)
        P["lmux"] = P0["lmux"] * mu
        P["lmuy"] = P0["lmuy"] * mu
        ph = tk % (duration / 2)
        # steering-wheel angle [rad]: step, slalom, hold in a turn
        if ph < 1.0:
            swa = 0.0
        elif ph < 2.5:
            swa = 1.2 * min(1.0, (ph - 1.0) / 0.2)
        elif ph < 4.0:
            swa = 1.6 * math.sin(2 * math.pi * 0.5 * (ph - 2.5))
        else:
            swa = 0.9
        swa *= steer_gain
        brake = brake_demand if (ph > 4.5 and ph < 5.5) else 0.0      # m/s^2 deceleration demand
        if swa_fn is not None:
            swa, brake = swa_fn(tk), 0.0
        delta = swa / cfg["steer_ratio"]
        dr_ = rear_gain * delta
        af = math.atan2(vy + lf * r, vx) - delta
        ar = math.atan2(vy - lr * r, vx) - dr_
        if a_lag is None:
            a_lag = [af, ar]
        for i, a in enumerate((af, ar)):
            if sigma[i] > 0.0:
                a_lag[i] += (1.0 - math.exp(-abs(vx) * dt / sigma[i])) * (a - a_lag[i])
            else:
                a_lag[i] = a
        o = est_ref.mf.evaluate(P, np.zeros(2), np.array(a_lag), 0.0, np.array([fzf, fzr]), None, vx)
        fyf, fyr = 2 * o["fy"][0], 2 * o["fy"][1]
        ax = -brake * min(1.0, mu)
        vyd = (fyf * math.cos(delta) + fyr * math.cos(dr_)) / m - r * vx
        rd = (lf * fyf * math.cos(delta) - lr * fyr * math.cos(dr_)) / iz
        ay = vyd + r * vx                   # specific force: the tires' force over the mass
        if bank is not None:
            vyd -= 9.80665 * math.sin(bank(tk))
        truth["vx"][k], truth["vy"][k], truth["r"][k], truth["mu"][k] = vx, vy, r, mu
        tf, tr = cfg["track_f"], cfg["track_r"]
        slip = -0.02 * brake / 3.0
        wsf = [(vx - r * tf / 2) * math.cos(delta) + (vy + lf * r) * math.sin(delta),
               (vx + r * tf / 2) * math.cos(delta) + (vy + lf * r) * math.sin(delta)]
        wsr = [(vx - r * tr / 2) * math.cos(dr_) + (vy - lr * r) * math.sin(dr_),
               (vx + r * tr / 2) * math.cos(dr_) + (vy - lr * r) * math.sin(dr_)]
        ws = [wsf[0] * (1 + slip), wsf[1] * (1 + slip), wsr[0] * (1 + slip), wsr[1] * (1 + slip)]
        if roll != 0.0:
            ay = ay * math.cos(roll * ay) + 9.80665 * math.sin(roll * ay)
        _measure(rng, value[k], valid[k], ws, swa, r, ax, ay, dr_ if rear_gain != 0.0 else None)
        vx = max(vx + (ax + r * vy) * dt, 0.0)
        vy += vyd * dt
        r += rd * dt
    return t, value, valid, truth


def _axle_slip(P, fz, fx):
    """The slip ratio at which the tire P at wheel load fz gives the
    longitudinal force fx (pure longitudinal slip, 20 m/s): the model's
    force over a grid of slips, interpolated (within the grid's +-0.3)."""
    k = np.linspace(-0.3, 0.3, 1201)
    o = est_ref.mf.evaluate(P, k, np.zeros_like(k), 0.0, np.full_like(k, fz), None, 20.0)
    f = np.asarray(o["fx"], float)
    j = int(np.argmax(f))
    i = int(np.argmin(f[:j]))      # the monotonic branch between the two peaks
    return float(np.interp(fx, f[i:j + 1], k[i:j + 1]))


def drive_inputs(dt=0.01, duration=14.0, seed=SEED + 5, v0=15.0, lkx=1.0, drive_front=0.0, radius_front=0.0,
                 profile=None):
    """A straight drive with a light sine of steering, coasting and traction
    phases, one braking and a slalom at the end (the longitudinal
    stiffness's sequence). The
    single-track lateral dynamics of bicycle_inputs; the tires' total
    longitudinal force m ax shared between the axles by drive_front while
    driving or coasting and 70 / 30 while braking; each axle's slip ratio the
    one at which the generator's tire (LKX x lkx: its slip stiffness a scale
    of the estimator's) gives the axle's force at the wheel's load with the
    longitudinal load transfer; the front wheels' rolling radius (1 +
    radius_front) x the rear's (their speeds read that much high). profile:
    [(t_end [s], ax [m/s^2]), ...] (default DRIVE_PROFILE). Returns time,
    value (N, 18), valid (N, 18) and the truth dict (vx, kappa_f, kappa_r)."""
    P0 = tire_params()
    cfg = est_ref.config(P0)
    PX = dict(P0, lkx=P0["lkx"] * lkx)
    m, iz, lf, lr, h = cfg["mass"], cfg["iz"], cfg["lf"], cfg["lr"], cfg["h_cg"]
    l = lf + lr
    fzf, fzr = 9.80665 * m * lr / l / 2, 9.80665 * m * lf / l / 2
    profile = DRIVE_PROFILE if profile is None else profile
    rng = np.random.default_rng(seed)
    n = int(round(duration / dt))
    t = np.arange(n) * dt
    value = np.zeros((n, est_ref.N_IN))
    valid = np.zeros((n, est_ref.N_IN), dtype=np.uint8)
    truth = {k: np.zeros(n) for k in ("vx", "kappa_f", "kappa_r")}
    vx, vy, r = v0, 0.0, 0.0
    for k in range(n):
        tk = t[k]
        ax = next((a for te, a in profile if tk < te), 0.0)
        swa = 0.04 * math.sin(2.0 * math.pi * 0.2 * tk)
        if DRIVE_SLALOM[0] <= tk < DRIVE_SLALOM[1]:
            swa += DRIVE_SLALOM[2] * math.sin(2.0 * math.pi * 0.5 * (tk - DRIVE_SLALOM[0]))
        delta = swa / cfg["steer_ratio"]
        af = math.atan2(vy + lf * r, vx) - delta
        ar = math.atan2(vy - lr * r, vx)
        o = est_ref.mf.evaluate(P0, np.zeros(2), np.array([af, ar]), 0.0, np.array([fzf, fzr]), None, vx)
        fyf, fyr = 2 * o["fy"][0], 2 * o["fy"][1]
        vyd = (fyf * math.cos(delta) + fyr) / m - r * vx
        rd = (lf * fyf * math.cos(delta) - lr * fyr) / iz
        ay = vyd + r * vx
        share = drive_front if ax >= 0.0 or ax > -0.3 else 0.7
        dfz = m * ax * h / l / 2                     # per wheel
        kf = _axle_slip(PX, fzf - dfz, share * m * ax / 2)
        kr = _axle_slip(PX, fzr + dfz, (1.0 - share) * m * ax / 2)
        truth["vx"][k], truth["kappa_f"][k], truth["kappa_r"][k] = vx, kf, kr
        tf, tr = cfg["track_f"], cfg["track_r"]
        wsf = [(vx - r * tf / 2) * math.cos(delta) + (vy + lf * r) * math.sin(delta),
               (vx + r * tf / 2) * math.cos(delta) + (vy + lf * r) * math.sin(delta)]
        wsr = [vx - r * tr / 2, vx + r * tr / 2]
        ws = [wsf[0] * (1 + kf) * (1 + radius_front), wsf[1] * (1 + kf) * (1 + radius_front),
              wsr[0] * (1 + kr), wsr[1] * (1 + kr)]
        _measure(rng, value[k], valid[k], ws, swa, r, ax, ay)
        vx = max(vx + (ax + r * vy) * dt, 0.0)
        vy += vyd * dt
        r += rd * dt
    return t, value, valid, truth


# the drive sequence's longitudinal specific force [m/s^2] until each time
# [s]: coasting, traction, coasting, harder traction, coasting, braking,
# coasting
DRIVE_PROFILE = [(2.0, 0.0), (5.0, 1.5), (7.0, 0.0), (10.0, 2.5), (11.0, 0.0), (12.0, -2.0), (14.0, 0.0)]
# ... and a slalom while coasting at its end (start, end [s], steering-wheel
# amplitude [rad]): the lateral forces of the other sequences, and the
# cornering gate
DRIVE_SLALOM = (12.5, 14.0, 1.0)


def front_drive_inputs():
    """The straight drive of drive_inputs on a front-driven car, its
    accelerometer reading 0.1 m/s^2 high (an ESC cluster's offset) and the
    left front wheel 10 % fast while driving (below the 15 % outlier test):
    the speed reference while driving (est_speed.c). Returns time, value,
    valid, the truth dict and the driving steps' mask."""
    t, value, valid, truth = drive_inputs(drive_front=1.0)
    value[:, est_ref.AX] += 0.1
    drive = np.array([next((a for te, a in DRIVE_PROFILE if tk < te), 0.0) for tk in t]) > 0.0
    value[drive, est_ref.WS[0]] *= 1.10
    return t, value, valid, truth, drive


def road_bank(t):
    """The road_bank_100hz sequence's bank [rad] at time t: 0.1 rad (5.7 deg)
    plus 0.04 rad over a 6 s period, as a road whose bank changes along it."""
    return 0.10 + 0.04 * math.sin(2.0 * math.pi * t / 6.0)


def road_bank_inputs():
    """The internal generator on a banked road the estimator is not told
    of (tan_bank = 0): mu 1.0, half the steering, light braking in the turn."""
    return bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 1.0), seed=SEED + 4, steer_gain=0.5,
                          brake_demand=1.0, bank=road_bank)


def steer_offset_inputs():
    """The steer_offset_100hz inputs (module doc, STEER_OFFSET): time,
    value, valid."""
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 1.0), seed=SEED + 2,
                                 steer_gain=STEER_OFFSET["steer_gain"], brake_demand=0.0)
    a, b = STEER_OFFSET["span"]
    v[(t >= a) & (t < b), est_ref.STEER] += STEER_OFFSET["offset"]
    return t, v, ok


def inject_faults(t, value, valid):
    """Faults on a copy of a 100 Hz sequence (documented in the module doc)."""
    v, ok = value.copy(), valid.copy()
    n = len(t)

    def span(a, b):
        return slice(int(a * n), int(b * n))

    ok[span(0.10, 0.12), est_ref.YAW] = 0                       # yaw invalid 2 % of the run
    v[span(0.10, 0.12), est_ref.YAW] = 0.0
    v[span(0.20, 0.21), est_ref.AY] = np.nan                    # NaN with valid flag set
    v[span(0.25, 0.26), est_ref.AX] = np.inf
    v[span(0.30, 0.31), est_ref.AY] = 40.0                      # saturated accelerometer
    ok[span(0.35, 0.45), est_ref.STEER] = 0                     # steering angle lost 10 %
    v[span(0.35, 0.45), est_ref.STEER] = 0.0
    v[span(0.50, 0.55), 2] = 0.0                                # RL wheel locked
    ok[span(0.58, 0.60), 0:4] = 0                               # all wheel speeds lost
    v[span(0.58, 0.60), 0:4] = 0.0
    v[span(0.62, 0.63), 1] = np.nan
    v[span(0.70, 0.80), 0:4] = 0.0                              # standstill
    v[span(0.70, 0.80), est_ref.AX] = 0.0
    v[span(0.70, 0.80), est_ref.AY] = 0.0
    v[span(0.70, 0.80), est_ref.YAW] = 0.0
    v[span(0.80, 0.90), 0:4] = 2.0                              # reversing at 2 m/s:
    v[span(0.80, 0.90), est_ref.VSPEED] = -2.0                  # signed vehicle speed
    ok[span(0.80, 0.90), est_ref.VSPEED] = 1
    v[span(0.80, 0.90), est_ref.AX] = 0.0
    v[span(0.92, 0.94), est_ref.STEER] = 30.0                   # steering at lock
    ok[span(0.46, 0.49), est_ref.AX] = 0                        # ax lost 3 %: beta, mu not valid
    v[span(0.46, 0.49), est_ref.AX] = 0.0
    return v, ok


def inject_time_faults(t):
    """Sample times of the faults sequence: one step 1.5 periods late and
    one repeated time at 96 % of the run (F_RATE, then the check resumes)."""
    t = t.copy()
    k = int(0.96 * len(t))
    t[k] += 0.5 * (t[1] - t[0])
    t[k + 5] = t[k + 4]
    return t


def sim_inputs():
    """Sine with dwell on a wet road from the reference simulator (short),
    or None when the simulator is not available."""
    try:
        from grip_tools.sim import manoeuvres as M, model as VM, sensors, vehicles
    except Exception:          # the simulator is another module; optional here
        return None
    veh = vehicles.passenger()
    sc = M.build("sine-dwell", veh, surface="wet", amp_deg=90.0)
    sc.duration = min(sc.duration, 4.0)
    res = VM.simulate(veh, sc, h=2e-3)
    sd = sensors.measure(res.member(0), sensors.SensorConfig(seed=SEED))
    cols = sd.wide_columns()
    return est_ref.inputs_from_sensors(cols)


# ---------------------------------------------------------------------------

def out_columns():
    # (yaw_error = yaw rate - reference is not written: yaw_rate and
    # yaw_rate_ref give it)
    cols = ["vx", "vy", "beta", "yaw_rate", "yaw_rate_ref", "yaw_rate_bias", "delta", "mu", "mu_conf"]
    for q in ("fz", "kappa", "alpha", "fx", "fy", "mz", "util"):
        cols += [f"{q}{i}" for i in range(4)]
    cols += ["fy_axle0", "fy_axle1", "util_axle0", "util_axle1", "fy_margin_front",
             "steer_char", "valid", "flags", "beta_sd", "mu_sd", "vx_sd", "fy_axle_sd0", "fy_axle_sd1"]
    return cols


def out_row(o):
    row = [o["vx"], o["vy"], o["beta"], o["yaw_rate"], o["yaw_rate_ref"], o["yaw_rate_bias"], o["delta"],
           o["mu"], o["mu_conf"]]
    for q in ("fz", "kappa", "alpha", "fx", "fy", "mz", "util"):
        row += list(o[q])
    row += list(o["fy_axle"]) + list(o["util_axle"]) + [o["fy_margin_front"], o["steer_char"],
                                                         o["valid"], o["flags"], o["beta_sd"], o["mu_sd"],
                                                         o["vx_sd"]] + list(o["fy_axle_sd"])
    return row


AERO_BANK = dict(cla=2.5, aero_front=0.42, air_density=1.2, cda=0.62, crr=0.01, tan_bank=0.04, tan_grade=0.02,
                 latency=0.02, steer_lag=0.1, steer_latency=0.01)
STEER_OFFSET = dict(steer_gain=0.4, offset=0.24, span=(4.3, 5.0))  # [-], [rad] steering wheel, [s]
AERO_BANK_V0 = 26.0           # [m/s]
REAR_STEER_V0, REAR_STEER_GAIN = 9.0, -0.3   # [m/s], rear angle / front angle
AERO_BANK_LOCK = (4.6, 4.9)   # [s] rear-left wheel locked while braking (the locked-wheel ax update)


def write_sequence(outdir, name, dt, t, value, valid, note, with_kx=False, with_roll=False, **cfg_kw):
    """Runs the reference over the inputs and writes est_<name>.txt;
    with_kx: one more column, the learned longitudinal scale kx after each
    step; with_roll: one more column, the roll gradient in use (rg_k)."""
    cfg = est_ref.config(tire_params(), rate_hz=int(round(1.0 / dt)), **cfg_kw)
    extra = "kx" if with_kx else ("roll_gradient" if with_roll else None)
    if extra:
        e = est_ref.Estimator(cfg)
        outs = []
        for k in range(len(t)):
            o = e.step(value[k], valid[k], int(round(float(t[k]) * 1e6)))
            outs.append(dict(o, **{extra: e.kx if with_kx else e.rg_k}))
    else:
        outs = est_ref.run(cfg, value, valid, t)
    in_cols = ["t"] + [f"in{i}" for i in range(est_ref.N_IN)] + ["valid_mask"]
    text = header("grip_tools.golden.est", est_ref.Estimator, SEED,
                  in_cols + out_columns() + ([extra] if extra else []),
                  {"sequence": name, "dt": dt, "tire": TIRE, "vehicle": "est_ref.config (passenger)",
                   "note": note, **{k: repr(v) for k, v in cfg_kw.items()}})
    lines = [text.rstrip("\n")]
    for k in range(len(t)):
        mask = int(sum(int(valid[k, i]) << i for i in range(est_ref.N_IN)))
        vals = [float(t[k])] + [float(x) for x in value[k]] + [mask] + out_row(outs[k])
        if extra:
            vals.append(outs[k][extra])
        lines.append(" ".join(_fmt(x) for x in vals))
    with open(os.path.join(outdir, f"est_{name}.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return outs


def _fmt(x):
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


# the stiffness sequence's generator tire: this much stiffer than the
# estimator's (LKY), so that the learned scales move
STIFF_LKY = 1.5
# the longitudinal stiffness sequence's generator tire: this much stiffer in
# slip (LKX), and its front wheels' rolling radius this much larger
STIFF_LKX, STIFF_RADIUS = 1.4, 0.004


# the roll sequence: the generator's body rolls by ROLL_K per m/s^2; a
# weave of ROLL_WEAVE s, then a left curve on a road banked ROLL_BANK_DEG
# towards its centre (curvature and bank faded in over 2 s together), its
# first 5 s: later the unconfigured bank's drift (docs/estimator.md, "Known
# limits") brings the filter to where the last bit picks its branch
ROLL_K, ROLL_WEAVE, ROLL_BANK_DEG, ROLL_DURATION = 0.015, 30.0, 8.0, 35.0


def _ramp(tk, t0, span):
    return min(1.0, max(0.0, (tk - t0) / span))


def roll_inputs(duration=ROLL_DURATION, weave=ROLL_WEAVE, bank_deg=ROLL_BANK_DEG, roll=ROLL_K, seed=SEED + 6):
    """The roll-gradient sequence's inputs (bicycle_inputs at 22 m/s on mu
    1.0): a weave of three sines of the steering-wheel angle (0.11, 0.37
    and 0.83 Hz, |ay| up to 3.3 m/s^2) for weave seconds, then a steady left
    curve (0.35 rad at the steering wheel, 2.6 m/s^2) whose road banks by
    bank_deg towards the curve's centre as the curve begins. Returns as
    bicycle_inputs."""
    def swa(tk):
        w = 0.17 * (math.sin(2 * math.pi * 0.11 * tk) + 0.8 * math.sin(2 * math.pi * 0.37 * tk + 1.0)
                    + 0.5 * math.sin(2 * math.pi * 0.83 * tk + 2.0))
        return w * (1.0 - _ramp(tk, weave - 1.0, 1.0)) + 0.35 * _ramp(tk, weave, 2.0)

    def bank(tk):
        return -math.radians(bank_deg) * _ramp(tk, weave, 2.0)
    return bicycle_inputs(dt=0.01, duration=duration, mu_road=(1.0, 1.0), seed=seed, roll=roll, swa_fn=swa,
                          bank=bank)


def _seq_bicycle_100hz(outdir):
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5))
    write_sequence(outdir, "bicycle_100hz", 0.01, t, v, ok, "internal generator, mu 1.0 then 0.5")


def _seq_bicycle_1khz(outdir):
    t, v, ok, _ = bicycle_inputs(dt=0.001, duration=4.0, mu_road=(0.6, 0.6))
    write_sequence(outdir, "bicycle_1khz", 0.001, t, v, ok, "internal generator, mu 0.6")


def _seq_faults_100hz(outdir):
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5), seed=SEED + 1)
    fv, fok = inject_faults(t, v, ok)
    write_sequence(outdir, "faults_100hz", 0.01, inject_time_faults(t), fv, fok,
                   "internal generator with injected faults")


def _seq_aero_bank_100hz(outdir):
    # 26 m/s: at 28 and 30 m/s the
    # estimator's open-loop stretch (vy unobservable with every tire at the
    # model's limit) ends in a recovery cascade that amplifies last-bit
    # differences (docs/estimator.md, "Robustness and golden tests")
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5), v0=AERO_BANK_V0)
    v[(t >= AERO_BANK_LOCK[0]) & (t < AERO_BANK_LOCK[1]), 2] = 0.0
    write_sequence(outdir, "aero_bank_100hz", 0.01, t, v, ok, "internal generator at 26 m/s, aero, drag, bank, latency, steering lag and latency on, RL locked while braking",
                   **AERO_BANK)


def _seq_steer_offset_100hz(outdir):
    t, v, ok = steer_offset_inputs()
    write_sequence(outdir, "steer_offset_100hz", 0.01, t, v, ok,
                   "internal generator, mu 1.0, 40 % steering, steering offset 4.3-5.0 s (understeer bound withdrawn)")


def _seq_rear_steer_100hz(outdir):
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 0.5), seed=SEED + 3, v0=REAR_STEER_V0,
                                 steer_gain=2.0, brake_demand=1.0, rear_gain=REAR_STEER_GAIN)
    write_sequence(outdir, "rear_steer_100hz", 0.01, t, v, ok,
                   "internal generator at 9 m/s, rear wheels steered opposite to the front (0.3 x), rear_steer = 1",
                   rear_steer=1)


def _seq_road_bank_100hz(outdir):
    t, v, ok, _ = road_bank_inputs()
    write_sequence(outdir, "road_bank_100hz", 0.01, t, v, ok,
                   "internal generator, mu 1.0, half steering, road bank 5.7 +- 2.3 deg along the run, not configured, bank_est = 1",
                   bank_est=1)


def _seq_stiffness_100hz(outdir):
    t, v, ok, _ = bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 1.0), seed=SEED + 4, steer_gain=0.5,
                                 brake_demand=0.5, lky=STIFF_LKY)
    write_sequence(outdir, "stiffness_100hz", 0.01, t, v, ok,
                   f"internal generator, mu 1.0, half steering, the generator's tire {STIFF_LKY} x as stiff, stiff_est = 1",
                   stiff_est=1)


def _seq_stiffness_long_100hz(outdir):
    t, v, ok, _ = drive_inputs(lkx=STIFF_LKX, radius_front=STIFF_RADIUS)
    write_sequence(outdir, "stiffness_long_100hz", 0.01, t, v, ok,
                   f"straight drive, coasting, traction and braking, rear-wheel drive, the generator's tire "
                   f"{STIFF_LKX} x as stiff in slip, front radius {STIFF_RADIUS} larger, kx_est = 1, "
                   f"drive_front = 0", with_kx=True, kx_est=1, drive_front=0.0)


def _seq_front_drive_100hz(outdir):
    t, v, ok, _, _ = front_drive_inputs()
    write_sequence(outdir, "front_drive_100hz", 0.01, t, v, ok,
                   "straight drive, front-wheel drive, the left front wheel 10 % fast while driving, "
                   "ax 0.1 m/s^2 high, drive_front = 1, pitch_gradient = 0.005", drive_front=1.0, pitch_gradient=0.005)


def _seq_roll_100hz(outdir):
    t, v, ok, _ = roll_inputs()
    write_sequence(outdir, "roll_100hz", 0.01, t, v, ok,
                   f"internal generator, mu 1.0, the body rolling {ROLL_K} rad/(m/s^2), a weave of {ROLL_WEAVE} s, "
                   f"then a curve banked {ROLL_BANK_DEG} deg towards its centre, roll_est = 1",
                   with_roll=True, roll_est=1)


def _seq_sim_sine_dwell(outdir):
    sim = sim_inputs()
    path = os.path.join(outdir, "est_sim_sine_dwell.txt")
    if sim is not None:
        t, v, ok = sim
        write_sequence(outdir, "sim_sine_dwell", 0.01, t, v, ok, "sim sine-dwell, wet, 4 s")
    elif os.path.exists(path):
        os.remove(path)


# Every sequence, the slowest first (the simulator's run, the 1 kHz one): each
# writes its own file, so golden-all runs them in parallel.
SEQUENCES = {f.__name__[len("_seq_"):]: f for f in (
    _seq_sim_sine_dwell, _seq_bicycle_1khz, _seq_bicycle_100hz, _seq_faults_100hz, _seq_aero_bank_100hz,
    _seq_steer_offset_100hz, _seq_rear_steer_100hz, _seq_road_bank_100hz, _seq_stiffness_100hz,
    _seq_stiffness_long_100hz, _seq_front_drive_100hz, _seq_roll_100hz)}


def golden_jobs():
    """The names write_job takes, one per sequence file."""
    return list(SEQUENCES)


def write_job(outdir, name):
    os.makedirs(outdir, exist_ok=True)
    SEQUENCES[name](outdir)


def write_golden(outdir):
    for name in golden_jobs():
        write_job(outdir, name)


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip golden-est", description=__doc__)
    ap.add_argument("-o", "--outdir", default="build/golden")
    a = ap.parse_args(argv)
    write_golden(a.outdir)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
