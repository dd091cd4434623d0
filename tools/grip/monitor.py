"""The sensor-plausibility monitor (lib/monitor, grip_monitor.h) over
arrays of samples.

    mon = grip.monitor.Monitor(arith="float")                 # the default car
    mon = grip.monitor.Monitor(est=estimator, driven=1)       # from an estimator
    cleaned, rep = mon.step(samples)
    rep["code"] (N, 9), rep["faulty"], rep["dropped"], rep["degraded"], rep["status"]

step() calls grip_monitor_step once per sample (in place on a copy: the
returned Samples are the ones with the monitor's faulty inputs dropped).
est_prev: an estimator Output of the same N samples (row k is given with
sample k) or None; for the documented coupling (the estimator's previous
output of the same run) use grip.est.run().
"""
import numpy as np

from grip import _core, signals
from grip._core import GripError, backend, check_arith

_CFG = "grip_monitor_config_t"
_REP = "grip_monitor_report_t"
N = 9   # GRIP_MON_N: inputs wheel_speed_fl .. vehicle_speed


class Report(dict):
    """{field of grip_monitor_report_t: array with one row per sample}
    (code, resid (N, 9); faulty, dropped bit sets; detected; degraded) and
    "status". .raw: the C structs."""

    def __init__(self, arith, raw, status):
        super().__init__(backend(arith).struct_to_dict(_REP, raw))
        self["status"] = np.asarray(status, np.int32)
        self.raw = raw
        self.arith = arith


def config_default(arith="float"):
    """grip_monitor_config_default: {field: SI value}."""
    be = backend(arith)
    cfg = be.ffi.new(_CFG + " *")
    be.lib.grip_monitor_config_default(cfg)
    return _core.get_fields(be, _CFG, cfg)


class Monitor:
    """One monitor instance (grip_monitor_t) of one arithmetic.

    config: {field of grip_monitor_config_t: SI value} over the default car
    (grip_monitor_config_default), or over the values taken from an
    initialized estimator (est=..., grip_monitor_config_from_est; driven:
    bit 0 front, bit 1 rear, default the default car's)."""

    def __init__(self, config=None, arith="float", est=None, driven=None):
        if est is not None:
            arith = est.arith
        check_arith(arith)
        self.arith = arith
        be = self._be = backend(arith)
        overrides = dict(config or {})
        self._est = est
        self._driven = driven
        self._cfg = self._make_cfg(overrides)
        self._mon = be.ffi.new("grip_monitor_t *")
        st = be.lib.grip_monitor_init(self._mon, self._cfg)
        if st != _core.OK:
            bad = _core.culprits(lambda o: self._try_init(o), overrides)
            raise GripError(st, "grip_monitor_init", _core.culprit_text(bad, "grip_monitor.h"),
                            param=", ".join(f"{k} = {overrides[k]!r}" for k in bad) or None, arith=arith)

    def _make_cfg(self, overrides):
        be = self._be
        cfg = be.ffi.new(_CFG + " *")
        be.lib.grip_monitor_config_default(cfg)
        if self._est is not None:
            driven = cfg.driven if self._driven is None else int(self._driven)
            st = be.lib.grip_monitor_config_from_est(cfg, self._est._est, driven)
            if st != _core.OK:
                raise GripError(st, "grip_monitor_config_from_est", arith=self.arith)
        _core.set_fields(be, _CFG, cfg, overrides, "grip.monitor.Monitor")
        return cfg

    def _try_init(self, overrides):
        m = self._be.ffi.new("grip_monitor_t *")
        return self._be.lib.grip_monitor_init(m, self._make_cfg(overrides))

    @property
    def config(self):
        return _core.get_fields(self._be, _CFG, self._cfg)

    def reset(self):
        st = self._be.lib.grip_monitor_reset(self._mon)
        if st != _core.OK:
            raise GripError(st, "grip_monitor_reset", arith=self.arith)

    def step(self, samples, est_prev=None):
        """grip_monitor_step on every sample: (the samples after the
        monitor, Report)."""
        be = self._be
        s = signals.as_samples(samples)
        n = len(s)
        arr = s.to_struct(self.arith)
        rep = np.zeros(n, be.dtype(_REP))
        status = np.zeros(n, np.int32)
        prev = be.ffi.NULL
        if est_prev is not None:
            raw = getattr(est_prev, "raw", est_prev)
            if getattr(est_prev, "arith", self.arith) != self.arith or raw.dtype != be.dtype("grip_est_output_t"):
                raise ValueError("est_prev must be an estimator Output of the same arithmetic")
            if len(raw) != n:
                raise ValueError(f"est_prev has {len(raw)} rows, the samples {n}")
            raw = np.ascontiguousarray(raw)
            prev = be.ptr("grip_est_output_t", raw)
        if n:
            be.lib.grip_py_monitor_run(self._mon, n, be.ptr("grip_input_sample_t", arr), prev,
                                       be.ptr(_REP, rep), be.ptr("int32_t", status))
        return signals.Samples.from_struct(self.arith, arr), Report(self.arith, rep, status)
