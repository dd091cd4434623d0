"""Float64 reference of the sensor calibration stage lib/calib
(include/grip/grip_calib.h, docs/calibration.md), plus an exact model of the
fixed-point build's arithmetic (q16=True) for bit-exact golden checks.

For each calibrated input i < N (wheel speeds FL..RR, steering-wheel angle,
yaw rate, ax, ay, vehicle speed):
  1. delay alignment: the input of delay[i] steps ago with its valid flag,
     fault code and age (age + t_now - t_then); invalid (MISSING) until that
     many earlier samples exist;
  2. value = (raw - offset[i]) * gain[i]; invalid stays invalid with value 0;
     a non-finite valid value becomes invalid with fault RANGE.
"""
import math

import numpy as np

N = 9                 # GRIP_CALIB_N
DELAY_MAX = 32        # GRIP_CALIB_DELAY_MAX
SIG_OK, SIG_MISSING, SIG_RANGE = 0, 2, 4
NAMES = ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle",
         "yaw_rate", "ax", "ay", "vehicle_speed")
Q16_MAX = 2 ** 31 - 1


def identity():
    return {"offset": [0.0] * N, "gain": [1.0] * N, "delay": [0] * N}


def check(cfg):
    for i in range(N):
        o, g, d = cfg["offset"][i], cfg["gain"][i], cfg["delay"][i]
        if not (math.isfinite(o) and -10.0 <= o <= 10.0 and math.isfinite(g) and 0.5 <= g <= 2.0
                and int(d) == d and 0 <= d <= DELAY_MAX):
            raise ValueError(f"calibration of input {i} out of range: offset {o}, gain {g}, delay {d}")


def q16(x):
    """RC(x) of the fixed build: round to nearest Q15.16 (the C test's to_qs)."""
    return int(math.floor(x * 65536.0 + 0.5)) if x >= 0 else -int(math.floor(-x * 65536.0 + 0.5))


def _sat(v):
    return max(-Q16_MAX, min(Q16_MAX, v))


def correct(v, offset, gain, q=False):
    """(v - offset) * gain; with q=True on Q15.16 integers exactly as r_sub, r_mul."""
    if q:
        d = _sat(int(v) - int(offset))
        return _sat((d * int(gain) + (1 << 15)) >> 16)
    return (v - offset) * gain


class Calib:
    def __init__(self, cfg, q16_mode=False):
        check(cfg)
        self.q = q16_mode
        if q16_mode:
            self.off = [q16(x) for x in cfg["offset"]]
            self.gain = [q16(x) for x in cfg["gain"]]
        else:
            self.off = [float(x) for x in cfg["offset"]]
            self.gain = [float(x) for x in cfg["gain"]]
        self.delay = [int(d) for d in cfg["delay"]]
        self.reset()

    def reset(self):
        self.hist = []      # newest last: (t_us, value[N], valid[N], fault[N], age[N])

    def apply(self, t_us, value, valid, fault=None, age_us=None):
        """value, valid (and fault, age_us) of the first N inputs; returns the
        calibrated (value, valid, fault, age_us) lists."""
        fault = list(fault) if fault is not None else [SIG_OK if v else SIG_MISSING for v in valid]
        age_us = list(age_us) if age_us is not None else [0] * N
        self.hist.append((int(t_us), list(value[:N]), [int(v) for v in valid[:N]], fault[:N], age_us[:N]))
        if len(self.hist) > DELAY_MAX + 1:
            self.hist.pop(0)
        ov, ok_out, of, oa = [], [], [], []
        for i in range(N):
            d = self.delay[i]
            v, ok, f, a = 0, 0, SIG_MISSING, 0
            if d < len(self.hist):
                t0, vals, vl, fl, ag = self.hist[-1 - d]
                ok, f = vl[i], fl[i]
                a = min(ag[i] + max(int(t_us) - t0, 0), 2 ** 32 - 1)
                if ok:
                    x = vals[i]
                    if self.q or math.isfinite(x):
                        x = correct(x, self.off[i], self.gain[i], self.q)
                    if not self.q and not math.isfinite(x):
                        x, ok, f = 0, 0, SIG_RANGE
                    v = x
            ov.append(v if ok else 0)
            ok_out.append(ok)
            of.append(SIG_OK if ok else f)
            oa.append(a)
        return ov, ok_out, of, oa


def run(cfg, t_us, value, valid, q16_mode=False):
    """Whole sequence: arrays (n,), (n, >=N), (n, >=N) -> value, valid (n, N)."""
    c = Calib(cfg, q16_mode)
    n = len(t_us)
    out_v = np.zeros((n, N), dtype=np.int64 if q16_mode else float)
    out_ok = np.zeros((n, N), dtype=np.uint8)
    for k in range(n):
        v = [q16(x) if (q16_mode and math.isfinite(x)) else x for x in value[k][:N]] if q16_mode else value[k]
        ov, ok, _, _ = c.apply(t_us[k], v, valid[k])
        out_v[k] = ov
        out_ok[k] = ok
    return out_v, out_ok


def align_array(x, t, delay_s):
    """The calibrated series of a whole recorded channel (numpy, float): x
    delayed by round(delay_s / dt) samples (the first samples hold the first
    value; the stage itself marks them invalid)."""
    dt = float(np.median(np.diff(t)))
    d = int(round(delay_s / dt))
    if d <= 0:
        return np.asarray(x, float).copy()
    return np.concatenate([np.full(d, x[0]), x[:-d]])
