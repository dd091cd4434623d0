"""Float64 reference of the ESC sensor-plausibility monitor (lib/monitor,
include/grip/grip_monitor.h).

Data flow: CAN -> signals (grip_input_sample_t) -> MONITOR -> estimator.
The monitor looks at the raw ESC signals of one sample (four wheel speeds,
steering-wheel angle, yaw rate, ax, ay, optional vehicle speed), judges
each plausible or not with checks the estimator does not have, clears the
valid flag of a signal it judges faulty (value 0, fault GRIP_SIG_FAULT) and
reports a fault code per signal. lib/monitor/monitor.c runs the same steps
in the same order with the same constants; docs/faults.md describes every
check and the measurement each constant comes from.

Checks per step (every loop runs a fixed 4 or 9 times):
  input    the signal layer's valid flag (LOST), finite and in range (RANGE)
  spike    a step change beyond the signal's physical rate: the sample is
           dropped; a rate-limited follower tracks the signal; repeated
           spikes latch the signal (SPIKE)
  noise    the low-passed |second difference| beyond the signal's physical
           bound (NOISE)
  frozen   the value bit-identical for N samples while the redundant signal
           moves (FROZEN)
  residual analytical redundancy (PLAUS), each only where its model holds:
    wheels   each wheel's speed at the CG (/ cos(delta) on the front,
             + r y) against the median of the other three; |ax| small
    yaw      yaw rate against the rear-wheel difference (v_rr - v_rl) /
             track_r; no braking / driving, wheels agree
    ay       ay against r vx (r from the wheels); the threshold widens with
             vx |dr/dt| (the sideslip rate, ay - r vx = vx dbeta/dt, goes
             with the yaw acceleration in a transient)
    ax       low-passed ax against the low-passed derivative of the
             wheel-speed median, when the wheels agree and ax or the wheel
             acceleration is steady
    steering yaw rate (sensor, or wheels) against the bicycle model
             r = vx delta / (l (1 + A vx^2)), lagged like the car, in the
             linear range (|a| small) and steady
    vspeed   vehicle-speed input against the wheel-speed median
  Residuals pass an up/down debounce counter; a signal judged faulty is
  latched (dropped) until every check of it has passed for HEAL_T.
  rep["degraded"]: DEGR_SUSPECT (a signal dropped / lost / latched or a
  check accumulating, held DEGR_T) | DEGR_UNVERIFIED (unstable-driving
  hold): the consumer does not trust beta and mu (docs/faults.md).

Use:
    mon = Monitor(config())
    rep = mon.step(value, valid, est_prev)  # est_prev: est_ref output dict or None
    rep["value"], rep["valid"]             # what the estimator gets
    rep["code"][s], rep["faulty"], rep["detected"]
"""
import math

import numpy as np

# grip_input_id_t
STEER, YAW, AX, AY, VSPEED = 4, 5, 6, 7, 8
N_IN = 18
N_MON = 9            # monitored inputs 0..8
NAMES = ("ws_fl", "ws_fr", "ws_rl", "ws_rr", "steer", "yaw", "ax", "ay", "vspeed")
G = 9.80665
BIG = 1000000

# degraded bits (grip_monitor.h GRIP_MON_DEGR_*)
DEGR_SUSPECT, DEGR_UNVERIFIED = 1, 2
# fault code bits (grip_monitor.h GRIP_MON_C_*)
C_LOST, C_RANGE, C_SPIKE, C_NOISE, C_FROZEN, C_PLAUS = 1, 2, 4, 8, 16, 32
SIG_FAULT = 5        # grip_sig_fault_t GRIP_SIG_FAULT
V_VX, V_BETA, V_STEER = 1, 2, 1 << 11   # grip_est.h GRIP_EST_V_*
# grip_monitor_gate (grip_monitor.h): the validity bits it clears (beta, mu,
# per-wheel tire outputs, axle forces, front margin), its default policy and
# the flag it sets (grip_est.h GRIP_EST_F_INPUT_DEGRADED)
GATE_CLEARS = (1 << 1) | (1 << 10) | (1 << 9) | (1 << 12) | (0xF << 5)
GATE_DEFAULT = DEGR_SUSPECT | DEGR_UNVERIFIED
F_INPUT_DEGRADED = 1 << 16

# physical range |x| <= LIM (the estimator's limits; steering: 1.4 rad road wheel x ratio)
WS_MAX, YAW_MAX, ACC_MAX, DELTA_MAX = 120.0, 2.5, 15.0, 0.7
#          wheel x4                   steer  yaw   ax     ay     vspeed
# spike: largest physical rate [unit/s]; a step beyond RATE dt + JUMP_ABS is a spike
RATE = (500.0, 500.0, 500.0, 500.0, 25.0, 6.0, 300.0, 300.0, 30.0)
JUMP_ABS = (0.3, 0.3, 0.3, 0.3, 0.05, 0.03, 0.5, 0.5, 0.3)
SPIKE_INC, SPIKE_LATCH = 10, 25    # +10 per spike, -1 per step: 3 spikes within ~0.5 s latch
# noise: bound of the low-passed |second difference| [unit]
NOISE_TAU = 0.1
NOISE_MAX = (0.8, 0.8, 0.8, 0.8, 0.06, 0.06, 1.0, 1.0, 0.6)
# frozen: N samples bit-identical and the redundant signal moved by FROZEN_MOVE
FROZEN_T = (0.1, 0.1, 0.1, 0.1, 0.3, 0.1, 0.1, 0.1, 0.1)
FROZEN_MOVE = (0.5, 0.5, 0.5, 0.5, 0.05, 0.05, 0.8, 0.8, 0.5)
# residual checks
V_MIN = 5.0                                   # residual checks above this speed [m/s]
WH_ABS, WH_REL, WH_AX_MAX = 0.6, 0.03, 1.5    # wheel vs median [m/s, -], only |ax| < WH_AX_MAX
WH_SPIN_AY = 2.0                              # driven inner wheel may spin above this |ay|
CALM_ABS, CALM_REL = 0.5, 0.03                # wheels agree: spread of the others below
YAW_ABS, YAW_REL, YAW_AX_MAX = 0.04, 0.10, 1.0
AY_ABS, AY_REL = 0.5, 0.10
AY_DR = 0.30         # ay threshold widening with the yaw acceleration: + AY_DR vx |dr/dt| [s]
AY_DR_CAP = 20.0     # |dr/dt| clamp there [rad/s^2] (keeps it in Q15.16; 0.25 * 5 * 20 > any ay)
# ... counting only the yaw acceleration beyond AY_DR_DEAD [rad/s^2]: the
# settling tail of a steering step kept the threshold 0.7 - 1 m/s^2 wide at
# 22 m/s for 0.5 s, and an ay offset of 1.5 m/s^2 there went unseen for
# 0.3 s while beta drifted 0.7 deg (docs/faults.md)
AY_DR_DEAD = 0.08
AX_TAU, AX_ABS, AX_REL = 0.1, 0.8, 0.15
ST_TAU, ST_ABS, ST_REL, ST_A_MAX = 0.15, 0.04, 0.20, 2.0
VS_ABS, VS_REL = 1.0, 0.05
# steadiness: the yaw rate (ax) has changed slower than this for STEADY_T
DR_TAU, DR_MAX = 0.1, 0.15                    # dr/dt low-passed [s, rad/s^2]
DAX_MAX = 3.0                                 # dax/dt, d(dv)/dt low-passed (AX_TAU) [m/s^3]
STEADY_T = 0.5
BETA_UNST, UNST_T = 0.1, 1.0                  # |beta| of the estimator [rad], hold [s]
BETA_CALM = 0.025     # the hold's time runs only while |beta| of the estimator <= this [rad]
DIFF_MAX = 10.0      # a step difference is clamped to this before it is turned into a rate
DEB_T = 0.1          # residual debounce [s]
HEAL_T = 1.0         # a latched signal is released after its checks pass this long
FOLLOW_LOST_T = 0.1  # the follower is re-initialized after the input was lost this long
DEGR_N = 3           # degraded: a residual check has failed on this many net steps (deb >= DEGR_N)
DEGR_T = 0.5         # degraded is held this long after its last cause


def config(rate_hz=100, **kw):
    """The passenger car of grip_monitor_config_default (the simulator's
    'passenger' set, as est_ref.config)."""
    c = dict(lf=1.10, lr=1.60, track_f=1.55, track_r=1.53, steer_ratio=15.5,
             stab_factor_x100=0.0367, roll_gradient=0.0088, driven=1, rate_hz=int(rate_hz))
    c.update(kw)
    return c


def _clamp(x, lo, hi):
    return min(max(x, lo), hi)


def _steps(t, rate):
    return max(1, int(math.floor(t * rate + 0.5)))


class Monitor:
    def __init__(self, cfg):
        self.cfg = cfg
        rate = cfg["rate_hz"]
        self.dt = 1.0 / rate
        self.rate = float(rate)
        self.ay_fac = 1.0 / (1.0 + G * cfg["roll_gradient"])
        self.n_frozen = [_steps(t, rate) for t in FROZEN_T]
        self.n_deb = _steps(DEB_T, rate)
        self.n_heal = _steps(HEAL_T, rate)
        self.n_lost = _steps(FOLLOW_LOST_T, rate)
        self.n_steady = _steps(STEADY_T, rate)
        self.n_unst = _steps(UNST_T, rate)
        self.n_degr = _steps(DEGR_T, rate)
        self.a_noise = min(1.0 / (NOISE_TAU * rate), 1.0)
        self.a_ax = min(1.0 / (AX_TAU * rate), 1.0)
        self.a_st = min(1.0 / (ST_TAU * rate), 1.0)
        self.a_dr = min(1.0 / (DR_TAU * rate), 1.0)
        self.rate_step = [RATE[s] / rate for s in range(N_MON)]
        self.jump = [self.rate_step[s] + JUMP_ABS[s] for s in range(N_MON)]
        self.lim = [WS_MAX] * 4 + [2.0 * DELTA_MAX * cfg["steer_ratio"], YAW_MAX, ACC_MAX, ACC_MAX, WS_MAX]
        self.reset()

    def reset(self):
        n = N_MON
        self.fol = [0.0] * n          # spike follower
        self.have = [0] * n           # follower set
        self.lost = [0] * n           # steps since the input was last ok
        self.x1 = [0.0] * n           # previous accepted value
        self.x2 = [0.0] * n           # the one before
        self.hist = [0] * n           # how many of x1, x2 are set (0..2)
        self.noise = [0.0] * n        # low-passed |second difference|
        self.spk = [0] * n            # spike counter
        self.frz = [0] * n            # bit-identical count
        self.frz_val = [0.0] * n
        self.frz_lo = [0.0] * n       # range of the redundant signal while frozen
        self.frz_hi = [0.0] * n
        self.deb = [0] * n            # residual debounce counters
        self.latch = [0] * n
        self.heal = [0] * n
        self.ax_f = 0.0               # low-passed ax
        self.dv_f = 0.0               # low-passed derivative of the wheel median
        self.v_prev = 0.0
        self.v_have = 0
        self.ax_prev = 0.0
        self.dax_f = 0.0              # low-passed dax/dt
        self.ax_steady = 0            # steps ax has been steady
        self.dv_prev = 0.0            # previous dv_f
        self.ddv_f = 0.0              # low-passed d(dv_f)/dt
        self.dv_steady = 0            # steps the wheel acceleration has been steady
        self.degr = 0                 # steps left of the degraded hold
        self.r_lin_f = 0.0            # lagged bicycle yaw rate
        self.r_prev = 0.0             # previous consensus yaw rate
        self.r_have = 0
        self.dr_f = 0.0               # low-passed dr/dt
        self.r_steady = 0             # steps the yaw rate has been steady
        self.init_f = 0
        self.unst = 0                 # steps left of the unstable-driving hold
        self.seen = [0] * N_MON       # the input has been valid since reset

    # -- one step --
    def step(self, value, valid, est=None):
        c = self.cfg
        dt, rate = self.dt, self.rate
        x = [float(value[s]) for s in range(N_MON)]
        code = [0] * N_MON
        ok = [0] * N_MON              # usable as a number this step
        sus = [0] * N_MON             # a residual check fails this step
        res = [0.0] * N_MON           # residual of each plausibility check (0: not run)

        # -- input, spike, noise --
        for s in range(N_MON):
            if not valid[s]:
                if self.seen[s]:
                    code[s] |= C_LOST          # lost after having been there (not unmapped)
            elif not (math.isfinite(x[s]) and abs(x[s]) <= self.lim[s]):
                code[s] |= C_RANGE
            else:
                ok[s] = 1
                self.seen[s] = 1
            if not ok[s]:
                self.lost[s] = min(self.lost[s] + 1, BIG)
                if self.lost[s] >= self.n_lost:
                    self.have[s] = 0
                    self.hist[s] = 0
                continue
            self.lost[s] = 0
            if not self.have[s]:
                self.fol[s] = x[s]
                self.have[s] = 1
            d = x[s] - self.fol[s]
            if abs(d) > self.jump[s]:
                stp = self.rate_step[s]
                self.fol[s] += _clamp(d, -stp, stp)
                self.spk[s] = min(self.spk[s] + SPIKE_INC, BIG)
                code[s] |= C_SPIKE
                ok[s] = 0
                continue
            self.fol[s] = x[s]
            self.spk[s] = max(self.spk[s] - 1, 0)
            if self.hist[s] >= 2:
                dd = abs(x[s] - 2.0 * self.x1[s] + self.x2[s])
                self.noise[s] += self.a_noise * (dd - self.noise[s])
            else:
                self.noise[s] = 0.0
            self.x2[s] = self.x1[s]
            self.x1[s] = x[s]
            self.hist[s] = min(self.hist[s] + 1, 2)

        for s in range(N_MON):
            if not ok[s]:
                x[s] = 0.0            # never used as a number
        use = [1 if (ok[s] and not self.latch[s]) else 0 for s in range(N_MON)]

        # -- derived quantities --
        steer_ok = use[STEER]
        delta = _clamp(x[STEER] / c["steer_ratio"], -DELTA_MAX, DELTA_MAX) if steer_ok else 0.0
        cd = math.cos(delta)
        yw = (0.5 * c["track_f"], -0.5 * c["track_f"], 0.5 * c["track_r"], -0.5 * c["track_r"])
        r_ws = x[YAW] if use[YAW] else 0.0
        vc = [0.0] * 4
        for i in range(4):
            if ok[i]:
                vc[i] = (x[i] / cd if i < 2 else x[i]) + r_ws * yw[i]
        # wheel-speed median of the usable wheels
        n_good, v_ref = 0, 0.0
        lo, hi, s1, s2 = 1e9, -1e9, 0.0, 0.0
        for i in range(4):
            if use[i]:
                n_good += 1
                lo, hi = min(lo, vc[i]), max(hi, vc[i])
                s1 += vc[i]
        if n_good == 4:
            v_ref = 0.5 * (s1 - lo - hi)            # mean of the middle two
        elif n_good == 3:
            v_ref = s1 - lo - hi                    # the middle one
        elif n_good == 2:
            v_ref = 0.5 * s1
        vw_ok = n_good >= 2
        spread = hi - lo if vw_ok else 0.0
        vx, vx_ok = v_ref, vw_ok
        if not vw_ok and est is not None and (est["valid"] & V_VX):
            vx, vx_ok = float(est["vx"]), True      # no two wheels: the estimator's speed
        moving = vx_ok and vx >= V_MIN
        ax_m = x[AX] if use[AX] else 0.0
        ay_c = self.ay_fac * x[AY] if ok[AY] else 0.0
        ay_u = ay_c if use[AY] else 0.0

        # steadiness of ax
        if ok[AX]:
            self.dax_f += self.a_ax * (_clamp(x[AX] - self.ax_prev, -DIFF_MAX, DIFF_MAX) * rate - self.dax_f)
            self.ax_prev = x[AX]
            self.ax_f += self.a_ax * (x[AX] - self.ax_f)
        self.ax_steady = min(self.ax_steady + 1, BIG) if (ok[AX] and abs(self.dax_f) < DAX_MAX) else 0

        # -- wheels: each against the median of the others (|ax| small) --
        calm = n_good >= 3 and spread <= CALM_ABS + CALM_REL * vx
        wh_chk = [0] * 4                    # the wheel's checks ran (others agree, no braking)
        if moving and abs(ax_m) < WH_AX_MAX:
            for i in range(4):
                if not ok[i]:
                    continue
                m, lo, hi, s1 = 0, 1e9, -1e9, 0.0
                for j in range(4):
                    if j != i and use[j]:
                        m += 1
                        lo, hi = min(lo, vc[j]), max(hi, vc[j])
                        s1 += vc[j]
                if m < 3:
                    continue
                ref = s1 - lo - hi
                if hi - lo > CALM_ABS + CALM_REL * vx:
                    continue                        # the others disagree: slip, not a sensor
                e = vc[i] - ref
                wh_chk[i] = 1
                res[i] = e
                # a driven wheel faster than the others at high |ay| is the
                # unloaded inner wheel spinning (open differential), not a
                # sensor; the loaded outer wheel does not spin alone. Inner:
                # the left wheels (0, 2) in a left turn (ay > 0)
                inner = (i % 2 == 0) if ay_u > 0.0 else (i % 2 == 1)
                spin = e > 0.0 and ((c["driven"] >> (i // 2)) & 1) and inner and abs(ay_u) > WH_SPIN_AY
                if abs(e) > WH_ABS + WH_REL * vx and not spin:
                    sus[i] = 1

        # -- yaw rate against the rear-wheel speed difference --
        wheel_sus = sus[0] or sus[1] or sus[2] or sus[3]
        # trusted only without braking / driving and with the wheels agreeing
        rw_ok = use[2] and use[3] and not wheel_sus and calm and abs(ax_m) < YAW_AX_MAX
        r_w = (x[3] - x[2]) / c["track_r"] if rw_ok else 0.0
        if moving and ok[YAW] and rw_ok:
            e = x[YAW] - r_w
            res[YAW] = e
            if abs(e) > YAW_ABS + YAW_REL * abs(r_w):
                sus[YAW] = 1
        # consensus yaw rate: the sensor when usable, else the wheels
        if use[YAW] and not sus[YAW]:
            r_c, rc_ok = x[YAW], True
        elif rw_ok:
            r_c, rc_ok = r_w, True
        else:
            r_c, rc_ok = 0.0, False
        if rc_ok and self.r_have:
            self.dr_f += self.a_dr * (_clamp(r_c - self.r_prev, -DIFF_MAX, DIFF_MAX) * rate - self.dr_f)
        self.r_prev, self.r_have = (r_c, 1) if rc_ok else (self.r_prev, 0)
        self.r_steady = min(self.r_steady + 1, BIG) if (rc_ok and abs(self.dr_f) < DR_MAX) else 0
        r_steady = self.r_steady >= self.n_steady

        # unstable driving (the estimator sees a large sideslip or oversteer):
        # the sideslip rate, ay - r vx, and the bicycle model are then unbounded
        if est is not None and (((est["valid"] & V_BETA) and abs(est["beta"]) > BETA_UNST) or
                                ((est["valid"] & V_STEER) and est["steer_char"] < 0)):
            self.unst = self.n_unst
        elif self.unst > 0 and not (est is not None and (est["valid"] & V_BETA) and abs(est["beta"]) > BETA_CALM):
            # the hold's time runs only once the estimated sideslip is back
            # near the linear range (a car still drifting at 2 - 5 deg can
            # turn into the next oversteer swing: the hold would lapse between)
            self.unst -= 1
        r_steady = r_steady and self.unst == 0

        # -- ay against r vx (r from the wheels when they can give it) --
        # (no steadiness gate: the threshold widens with the yaw acceleration,
        # as the sideslip rate does in a transient)
        if moving and ok[AY] and rc_ok and self.unst == 0:
            r_x = r_w if rw_ok else r_c
            e = ay_c - r_x * vx
            res[AY] = e
            if abs(e) > AY_ABS + AY_DR * vx * min(max(abs(self.dr_f) - AY_DR_DEAD, 0.0), AY_DR_CAP) + AY_REL * abs(ay_c):
                sus[AY] = 1

        # -- ax against the derivative of the wheel median --
        if vw_ok and self.v_have:
            self.dv_f += self.a_ax * (_clamp(v_ref - self.v_prev, -DIFF_MAX, DIFF_MAX) * rate - self.dv_f)
            self.ddv_f += self.a_ax * (_clamp(self.dv_f - self.dv_prev, -DIFF_MAX, DIFF_MAX) * rate - self.ddv_f)
            self.dv_prev = self.dv_f
        self.dv_steady = min(self.dv_steady + 1, BIG) if (vw_ok and self.v_have and abs(self.ddv_f) < DAX_MAX) else 0
        self.v_prev, self.v_have = v_ref, (1 if vw_ok else 0)
        # ax steady (a step fault of ax itself closes this) or the wheel
        # acceleration steady (closed at a real brake onset, open at an ax step)
        # (the yaw rate need not be steady: ax - dv/dt = -r vy stays small)
        if moving and ok[AX] and calm and self.unst == 0 and (self.ax_steady >= self.n_steady or
                                                        self.dv_steady >= self.n_steady):
            e = self.ax_f - self.dv_f
            res[AX] = e
            if abs(e) > AX_ABS + AX_REL * abs(self.dv_f):
                sus[AX] = 1

        # -- steering against the yaw rate (bicycle model, linear range) --
        l = c["lf"] + c["lr"]
        dl = x[STEER] / c["steer_ratio"] if ok[STEER] else 0.0
        dl = _clamp(dl, -DELTA_MAX, DELTA_MAX)
        r_lin = vx * dl / (l * (1.0 + 0.01 * (c["stab_factor_x100"] * vx * vx))) if moving else 0.0
        if not self.init_f:
            self.r_lin_f = r_lin
            self.init_f = 1
        self.r_lin_f += self.a_st * (r_lin - self.r_lin_f)
        a_tot = math.sqrt(ax_m * ax_m + ay_u * ay_u)
        if moving and ok[STEER] and rc_ok and r_steady and a_tot < ST_A_MAX:
            e = self.r_lin_f - r_c
            res[STEER] = e
            if abs(e) > ST_ABS + ST_REL * abs(r_c):
                sus[STEER] = 1

        # -- vehicle speed against the wheels --
        if ok[VSPEED] and n_good >= 2:
            e = x[VSPEED] - v_ref
            res[VSPEED] = e
            if abs(e) > VS_ABS + VS_REL * abs(v_ref):
                sus[VSPEED] = 1

        # -- frozen: bit-identical while the redundant signal moves --
        red = [vx, vx, vx, vx, r_c, r_w if rw_ok else ay_u / max(vx, V_MIN), self.dv_f,
               (r_w if rw_ok else r_c) * vx, vx]
        for s in range(N_MON):
            if not ok[s] or not moving or (s < 4 and x[s] == 0.0):
                self.frz[s] = 0         # (a locked wheel reads exactly 0)
                continue
            if self.frz[s] > 0 and x[s] == self.frz_val[s]:
                self.frz[s] = min(self.frz[s] + 1, BIG)
                self.frz_lo[s] = min(self.frz_lo[s], red[s])
                self.frz_hi[s] = max(self.frz_hi[s], red[s])
            else:
                self.frz[s] = 1
                self.frz_val[s] = x[s]
                self.frz_lo[s] = self.frz_hi[s] = red[s]
            if self.frz[s] >= self.n_frozen[s] and self.frz_hi[s] - self.frz_lo[s] > FROZEN_MOVE[s]:
                code[s] |= C_FROZEN

        # -- noise, spike latch, debounce, latch and heal --
        faulty = 0
        degr = 0
        out_valid = [int(v) for v in valid[:N_IN]]
        out_value = [float(v) for v in value[:N_IN]]
        out_fault = [0] * N_IN
        for s in range(N_MON):
            if ok[s] and self.noise[s] > NOISE_MAX[s] and (s >= 4 or wh_chk[s]):
                code[s] |= C_NOISE
            if self.spk[s] >= SPIKE_LATCH:
                code[s] |= C_SPIKE
            if sus[s]:
                self.deb[s] = min(self.deb[s] + 1, self.n_deb)
            elif self.deb[s] > 0:
                self.deb[s] -= 1
            if self.deb[s] >= self.n_deb:
                code[s] |= C_PLAUS
            if code[s] & (C_NOISE | C_FROZEN | C_PLAUS) or self.spk[s] >= SPIKE_LATCH:
                self.latch[s] = 1
                self.heal[s] = 0
            elif self.latch[s] and not (code[s] & C_SPIKE) and self.deb[s] == 0:
                self.heal[s] += 1
                if self.heal[s] >= self.n_heal:
                    self.latch[s] = 0
                    self.heal[s] = 0
            if self.latch[s]:
                faulty |= 1 << s
            if self.latch[s] or code[s] != 0 or self.deb[s] >= DEGR_N:
                degr = 1
            if (self.latch[s] or (code[s] & C_SPIKE)) and valid[s]:
                out_valid[s] = 0
                out_value[s] = 0.0
                out_fault[s] = SIG_FAULT
        detected = any(code[s] != 0 for s in range(N_MON)) or faulty != 0
        # degraded (the consumer should not trust beta nor mu on such a sample):
        #   SUSPECT     a signal is dropped, lost or latched, or a residual check
        #               is accumulating (deb >= DEGR_N), now or within DEGR_T
        #   UNVERIFIED  the unstable-driving hold keeps the ay, ax and steering
        #               checks off: a fault of those signals would go unseen
        if degr:
            self.degr = self.n_degr
        elif self.degr > 0:
            self.degr -= 1
        degraded = (DEGR_SUSPECT if self.degr > 0 else 0) | (DEGR_UNVERIFIED if self.unst > 0 else 0)
        return dict(valid=out_valid, value=out_value, fault=out_fault, code=code, faulty=faulty,
                    detected=detected, res=res, sus=sus, degraded=degraded)


def gate(degraded, honour, valid, flags):
    """grip_monitor_gate: the degraded contract applied to one estimator
    output (valid, flags); works elementwise on numpy integer arrays."""
    if honour & ~GATE_DEFAULT:
        raise ValueError("honour has a bit that is not a degraded bit")
    hit = (degraded & honour) != 0
    return (np.where(hit, valid & ~GATE_CLEARS, valid),
            np.where(hit, flags | F_INPUT_DEGRADED, flags))
