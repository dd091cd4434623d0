"""The estimator's input samples (grip_signals.h) as numpy arrays.

A Samples holds N steps of the 17 inputs (INPUTS: wheel speeds FL FR RL RR
[m/s], steering-wheel angle [rad], yaw rate [rad/s], ax, ay [m/s^2],
vehicle speed [m/s], brake pressures [Pa], brake torques [N m]; SI, ISO 8855
axes), each with a valid flag and a fault code (FAULTS):

    s = grip.signals.Samples.from_columns(t_s=t, wheel_speed_fl=w0, ...,
                                          yaw_rate=r, ax=ax, ay=ay)
    s.value   (N, 17) float64, SI; 0 where not valid
    s.valid   (N, 17) bool
    s.fault   (N, 17) uint8 (grip_sig_fault_t)
    s.age_us  (N, 17) uint32;  s.t_us (N,) int64;  s.step (N,) uint32

Conversion to the build's grip_input_sample_t (when a sample reaches the
library): float build: value -> float (a valid NaN or infinity is passed
on: the library's own checks judge it); fixed build: grip_convert.h (QS,
or QL for pressures and torques, rounded half away from zero); a valid
value the fixed build cannot hold (non-finite, beyond the Q range) is
passed as not valid with fault "range" and value 0, as grip-replay does.
Invalid inputs are passed with value 0 (the struct's contract).
"""
import numpy as np

from grip import _core
from grip._core import backend

INPUTS = ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle", "yaw_rate",
          "ax", "ay", "vehicle_speed", "brake_pressure_fl", "brake_pressure_fr", "brake_pressure_rl",
          "brake_pressure_rr", "brake_torque_fl", "brake_torque_fr", "brake_torque_rl", "brake_torque_rr", "rear_steer_angle")
FAULTS = ("ok", "unmapped", "missing", "stale", "range", "fault")   # grip_sig_fault_t
OK, UNMAPPED, MISSING, STALE, RANGE, FAULT = range(6)


def index(name):
    """Input id of a name ("yaw_rate" -> 5)."""
    try:
        return INPUTS.index(name)
    except ValueError:
        raise KeyError(f"unknown input {name!r}; inputs: {', '.join(INPUTS)}") from None


class Samples:
    """N estimator input samples (see the module's text). value: (N, 17)
    SI; valid: default "not NaN"; fault: default ok where valid, else
    missing; t_us: default 10 ms steps; step: default 0 .. N-1."""

    def __init__(self, value, valid=None, fault=None, t_us=None, step=None, age_us=None):
        value = np.array(value, dtype=np.float64, copy=True)
        if value.ndim != 2 or value.shape[1] != len(INPUTS):
            raise ValueError(f"value must have the shape (N, {len(INPUTS)}), not {value.shape}")
        n = value.shape[0]
        self.valid = (~np.isnan(value) if valid is None
                      else np.broadcast_to(np.asarray(valid, bool), value.shape).copy())
        if fault is None:
            fault = np.where(self.valid, OK, MISSING)
        self.fault = np.broadcast_to(np.asarray(fault, np.uint8), value.shape).copy()
        self.value = np.where(self.valid, value, 0.0)
        self.t_us = (np.arange(n, dtype=np.int64) * 10000 if t_us is None
                     else np.broadcast_to(np.asarray(t_us, np.int64), (n,)).copy())
        self.step = (np.arange(n, dtype=np.uint32) if step is None
                     else np.broadcast_to(np.asarray(step, np.uint32), (n,)).copy())
        self.age_us = (np.zeros(value.shape, np.uint32) if age_us is None
                       else np.broadcast_to(np.asarray(age_us, np.uint32), value.shape).copy())

    def __len__(self):
        return self.value.shape[0]

    def __repr__(self):
        return f"grip.signals.Samples({len(self)} steps, {int(self.valid.any(axis=0).sum())} inputs with data)"

    def __getitem__(self, k):
        """Samples of a slice (or index array) of steps."""
        if isinstance(k, (int, np.integer)):
            k = slice(int(k), int(k) + 1 if int(k) != -1 else None)
        return Samples(self.value[k], self.valid[k], self.fault[k], self.t_us[k], self.step[k], self.age_us[k])

    @classmethod
    def from_columns(cls, columns=None, t_s=None, t_us=None, dt=None, **named):
        """From named columns (INPUTS names; a dict and/or keywords), each an
        array of N values with NaN where not valid; inputs not given are
        "unmapped". Time: t_us, or t_s (rounded to us), or dt [s] (t = k dt),
        else 10 ms steps."""
        cols = dict(columns or {})
        cols.update(named)
        for k in ("t_s", "t_us", "dt"):
            if k in cols:
                raise TypeError(f"give {k} as its own argument")
        unknown = [k for k in cols if k not in INPUTS]
        if unknown:
            raise KeyError(f"unknown input(s) {', '.join(unknown)}; inputs: {', '.join(INPUTS)}")
        lens = {np.asarray(v).shape[0] if np.ndim(v) else 1 for v in cols.values()}
        for t in (t_s, t_us):
            if t is not None:
                lens.add(np.asarray(t).shape[0])
        if len(lens) != 1:
            raise ValueError(f"columns of different lengths: {sorted(lens)}")
        n = lens.pop()
        value = np.zeros((n, len(INPUTS)))
        valid = np.zeros((n, len(INPUTS)), bool)
        fault = np.full((n, len(INPUTS)), UNMAPPED, np.uint8)
        for k, v in cols.items():
            i = INPUTS.index(k)
            v = np.broadcast_to(np.asarray(v, np.float64), (n,))
            ok = ~np.isnan(v)
            value[:, i] = np.where(ok, v, 0.0)
            valid[:, i] = ok
            fault[:, i] = np.where(ok, OK, MISSING)
        if t_us is None and t_s is not None:
            t_us = np.floor(np.asarray(t_s, np.float64) * 1e6 + 0.5).astype(np.int64)
        elif t_us is None and dt is not None:
            t_us = np.floor(np.arange(n) * float(dt) * 1e6 + 0.5).astype(np.int64)
        return cls(value, valid, fault, t_us)

    def column(self, name):
        """The values of one input, NaN where not valid."""
        i = index(name)
        return np.where(self.valid[:, i], self.value[:, i], np.nan)

    def to_columns(self):
        """{name: values with NaN where not valid} of every input, and t_s."""
        out = {"t_s": self.t_us / 1e6}
        for i, name in enumerate(INPUTS):
            out[name] = np.where(self.valid[:, i], self.value[:, i], np.nan)
        return out

    # ---- the C struct array of one arithmetic
    def to_struct(self, arith):
        """A numpy array of grip_input_sample_t of the arithmetic (the layout
        the compiler gave the struct)."""
        be = backend(arith)
        n = len(self)
        arr = np.zeros(n, be.dtype("grip_input_sample_t"))
        arr["t_us"] = self.t_us
        arr["step"] = self.step
        valid = self.valid.copy()
        fault = self.fault.copy()
        if be.fixed:
            q, st = be.inputs_real(self.value, be.input_ql[None, :])
            bad = valid & (st != _core.OK)
            valid[bad] = False
            fault[bad] = RANGE
            q[~valid] = 0
        else:
            with np.errstate(over="ignore", invalid="ignore"):
                q = self.value.astype(np.float32)
            q[~valid] = 0.0
        arr["value"] = q
        arr["valid"] = valid.astype(np.uint8)
        arr["fault"] = fault
        arr["age_us"] = self.age_us
        return arr

    @classmethod
    def from_struct(cls, arith, arr):
        """From an array of grip_input_sample_t of the arithmetic (kept as
        .raw: the exact values the library wrote)."""
        be = backend(arith)
        q = arr["value"]
        if be.fixed:
            value = np.where(be.input_ql[None, :] == 1, q * _core.SCALE["QL"], q * _core.SCALE["QS"])
        else:
            value = q.astype(np.float64)
        s = cls.__new__(cls)
        s.valid = arr["valid"].astype(bool)
        s.value = np.where(s.valid, value, 0.0)
        s.fault = np.array(arr["fault"], np.uint8)
        s.t_us = np.array(arr["t_us"], np.int64)
        s.step = np.array(arr["step"], np.uint32)
        s.age_us = np.array(arr["age_us"], np.uint32)
        s.raw = arr
        s.arith = arith
        return s


def as_samples(x):
    """A Samples from a Samples, a dict of columns, or a (value) array."""
    if isinstance(x, Samples):
        return x
    if isinstance(x, dict):
        d = dict(x)
        t_s = d.pop("t_s", None)
        t_us = d.pop("t_us", None)
        return Samples.from_columns(d, t_s=t_s, t_us=t_us)
    return Samples(x)
