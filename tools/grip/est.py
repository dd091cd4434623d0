"""The onboard estimator (lib/est, grip_est.h) over arrays of samples.

    tyre = grip.mf.load("tests/data/mfeval-tir/PacejkaBook_Defaults.tir")
    est = grip.est.Estimator({"tire": tyre, "mass": 1640.0, "rate_hz": 100}, arith="fixed")
    out = est.step(samples)          # grip.signals.Samples, or a dict of columns
    out["beta"], out["mu"], out["fy"] (N, 4), out["valid"], out["flags"], out["status"]

The configuration starts from grip_est_config_default (the passenger car)
with the given tire on both axles ("tire", or "tire_front" and
"tire_rear"); every other key is a field of grip_est_config_t in SI units
(mass [kg], lf [m], ..., rate_hz and speed_ref_mu integers). step() calls
grip_est_step once per sample in a C loop and keeps the state between
calls, as on the ECU. run() chains calibration, monitor, estimator and the
monitor's gate per sample, as grip_monitor.h documents.
"""
import numpy as np

from grip import _core, signals
from grip._core import GripError, backend, check_arith
from grip.mf import Params as MFParams

_CFG = "grip_est_config_t"
_OUT = "grip_est_output_t"


class Output(dict):
    """{field of grip_est_output_t: array with one row per sample} (SI;
    kappa, alpha, fz, fx, fy, mz, util (N, 4); fy_axle, util_axle (N, 2);
    steer_char, valid, flags integers) and "status" (grip_est_step's
    return). .raw: the C structs (numpy structured array), .arith."""

    def __init__(self, arith, raw, status):
        be = backend(arith)
        super().__init__(be.struct_to_dict(_OUT, raw))
        self["status"] = np.asarray(status, np.int32)
        self.raw = raw
        self.arith = arith


def _tires(config):
    front = config.get("tire_front", config.get("tire"))
    rear = config.get("tire_rear", front)
    if "tire" in config and ("tire_front" in config or "tire_rear" in config):
        raise GripError(_core.ERR_PARAM, "grip.est", "give 'tire' or 'tire_front'/'tire_rear', not both",
                        param="tire")
    for name, t in (("tire_front", front), ("tire_rear", rear)):
        if not isinstance(t, MFParams):
            raise GripError(_core.ERR_PARAM, "grip.est",
                            "a grip.mf.Params (grip.mf.load) is needed for the tire of each axle",
                            param="tire" if "tire" in config else name)
    return front, rear


def config_default(tire, arith="float"):
    """grip_est_config_default with this tire: {field: SI value}."""
    be = backend(arith)
    cfg = be.ffi.new(_CFG + " *")
    st = be.lib.grip_est_config_default(cfg, tire.struct(arith))
    if st != _core.OK:
        raise GripError(st, "grip_est_config_default", arith=arith)
    return _core.get_fields(be, _CFG, cfg, skip=("tire",))


class Estimator:
    """One estimator instance (grip_est_t) of one arithmetic."""

    def __init__(self, config, arith="float"):
        check_arith(arith)
        if isinstance(config, MFParams):
            config = {"tire": config}
        config = dict(config)
        self.arith = arith
        be = self._be = backend(arith)
        front, rear = _tires(config)
        overrides = {k: v for k, v in config.items() if k not in ("tire", "tire_front", "tire_rear")}
        self._tires = (front, rear)       # the C config points at their structs
        self._cfg = self._make_cfg(overrides)
        self._est = be.ffi.new("grip_est_t *")
        st = be.lib.grip_est_init(self._est, self._cfg)
        if st != _core.OK:
            bad = _core.culprits(lambda o: self._try_init(o), overrides)
            raise GripError(st, "grip_est_init", _core.culprit_text(bad, "grip_est.h"),
                            param=", ".join(f"{k} = {overrides[k]!r}" for k in bad) or None, arith=arith)
        self._last = be.ffi.new(_OUT + " *")
        self._have_last = be.ffi.new("int *")

    def _make_cfg(self, overrides):
        be = self._be
        cfg = be.ffi.new(_CFG + " *")
        st = be.lib.grip_est_config_default(cfg, self._tires[0].struct(self.arith))
        if st != _core.OK:
            raise GripError(st, "grip_est_config_default", arith=self.arith)
        be.lib.grip_py_est_set_tire(cfg, 1, self._tires[1].struct(self.arith))
        _core.set_fields(be, _CFG, cfg, overrides, "grip.est.Estimator", skip=("tire",))
        return cfg

    def _try_init(self, overrides):
        e = self._be.ffi.new("grip_est_t *")
        return self._be.lib.grip_est_init(e, self._make_cfg(overrides))

    @property
    def config(self):
        """The configuration as stored: {field: SI value}."""
        return _core.get_fields(self._be, _CFG, self._cfg, skip=("tire",))

    def reset(self):
        """grip_est_reset: forget the dynamic state, keep the configuration."""
        st = self._be.lib.grip_est_reset(self._est)
        if st != _core.OK:
            raise GripError(st, "grip_est_reset", arith=self.arith)
        self._have_last[0] = 0

    def stability_factor(self):
        """grip_est_stability_factor: A [s^2/m^2] x 100."""
        be = self._be
        a = be.ffi.new("grip_real_t *")
        st = be.lib.grip_est_stability_factor(self._est, a)
        if st != _core.OK:
            raise GripError(st, "grip_est_stability_factor", arith=self.arith)
        return float(be.to_si(np.array(a[0], be.real), "QS"))

    def learned(self):
        """grip_est_learned_get: what the estimator learned (the axles'
        cornering-stiffness scales k_front, k_rear and the updates behind
        them; the longitudinal slip-stiffness scale kx, the axles'
        rolling-radius mismatch (front over rear, less 1) and kx's
        updates; the roll gradient in use and its updates) and the blob
        itself as bytes, for learned_set on another
        instance of the same car, tire and arithmetic."""
        be = self._be
        b = be.ffi.new("grip_est_learned_t *")
        st = be.lib.grip_est_learned_get(self._est, b)
        if st != _core.OK:
            raise GripError(st, "grip_est_learned_get", arith=self.arith)
        f = _core.get_fields(be, "grip_est_learned_t", b)
        return {"k_front": f["k"][0], "k_rear": f["k"][1], "updates": f["updates"],
                "kx": f["kx"], "radius_mismatch": f["kx_x"][1] * 1.0e-3, "kx_updates": f["kx_updates"],
                "roll_gradient": f["rg_k"], "roll_updates": f["rg_updates"],
                "blob": bytes(be.ffi.buffer(b))}

    def learned_set(self, blob):
        """grip_est_learned_set from learned()["blob"]; GripError (nothing
        changed) when the blob is not one, from another build, car or tire,
        out of range or corrupt."""
        be = self._be
        size = be.ffi.sizeof("grip_est_learned_t")
        blob = bytes(blob)
        if len(blob) != size:
            raise GripError(_core.ERR_PARAM, "grip_est_learned_set", f"a blob of {size} bytes, not {len(blob)}",
                            arith=self.arith)
        b = be.ffi.new("grip_est_learned_t *")
        be.ffi.memmove(b, blob, size)
        st = be.lib.grip_est_learned_set(self._est, b)
        if st != _core.OK:
            raise GripError(st, "grip_est_learned_set", "not a blob of this car, tire and build, or corrupt",
                            arith=self.arith)

    def measure_friction(self, mu_road, mu_road_sd):
        """grip_est_measure_friction: a road-friction measurement from
        outside (absolute peak |F| / Fz and its standard deviation), applied
        at once; GripError (state unchanged) when out of range."""
        be = self._be
        r = be.ffi.new("grip_real_t[2]")
        for i, v in enumerate((mu_road, mu_road_sd)):
            if be.lib.grip_py_param(float(v), 0, r + i) != 0:
                raise GripError(_core.ERR_INPUT, "grip_est_measure_friction", f"{v} is not representable",
                                arith=self.arith)
        st = be.lib.grip_est_measure_friction(self._est, r[0], r[1])
        if st != _core.OK:
            raise GripError(st, "grip_est_measure_friction", "mu_road in [0.05, 2], mu_road_sd in [0.01, 1]",
                            arith=self.arith)

    def step(self, samples, friction=()):
        """grip_est_step on every sample, in order: an Output with one row
        per sample. friction: (k, mu_road, mu_road_sd) rows, each
        measure_friction'd before sample k, in order of k."""
        be = self._be
        s = signals.as_samples(samples)
        n = len(s)
        arr = s.to_struct(self.arith)
        out = np.zeros(n, be.dtype(_OUT))
        status = np.zeros(n, np.int32)
        cuts = [0] + [min(max(int(k), 0), n) for k, _, _ in friction] + [n]
        for j in range(len(cuts) - 1):
            if j > 0:
                self.measure_friction(friction[j - 1][1], friction[j - 1][2])
            a, b = cuts[j], cuts[j + 1]
            if b > a:
                be.lib.grip_py_est_run(self._est, b - a, be.ptr("grip_input_sample_t", arr[a:b]),
                                       be.ptr(_OUT, out[a:b]), be.ptr("int32_t", status[a:b]))
        if n:
            be.ffi.memmove(self._last, be.ffi.from_buffer(out[-1:]), be.ffi.sizeof(_OUT))
            self._have_last[0] = 1
        return Output(self.arith, out, status)


def run(samples, estimator, monitor=None, calib=None, honour=None):
    """The chain of grip_calib.h / grip_monitor.h, per sample:
        calib (if given) -> monitor (if given; est_prev: the estimator's own
        previous output) -> estimator -> gate (a copy, `honour` bits of the
        monitor's degraded flags; default GRIP_MON_GATE_DEFAULT).
    Returns {"out": the estimator's Output, "gated": the gated Output (the
    consumer's; = out without monitor), "report": the monitor's report or
    None, "samples": the samples as the estimator saw them, "status_calib",
    "status_monitor" (or None)}. The objects keep their state across calls."""
    arith = estimator.arith
    for o in (monitor, calib):
        if o is not None and o.arith != arith:
            raise ValueError("estimator, monitor and calib must be of the same arithmetic")
    be = backend(arith)
    s = signals.as_samples(samples)
    n = len(s)
    arr = s.to_struct(arith)
    used = np.zeros(n, be.dtype("grip_input_sample_t"))
    own = np.zeros(n, be.dtype(_OUT))
    gated = np.zeros(n, be.dtype(_OUT))
    rep = np.zeros(max(n, 1), be.dtype("grip_monitor_report_t"))
    st = {k: np.zeros(max(n, 1), np.int32) for k in ("cal", "mon", "est")}
    if honour is None:
        honour = int(be.lib.GRIP_MON_GATE_DEFAULT)
    if n:
        be.lib.grip_py_chain_run(calib._c if calib is not None else be.ffi.NULL,
                                 monitor._mon if monitor is not None else be.ffi.NULL,
                                 estimator._est, honour, estimator._last, estimator._have_last, n,
                                 be.ptr("grip_input_sample_t", arr), be.ptr("grip_input_sample_t", used),
                                 be.ptr("grip_monitor_report_t", rep), be.ptr(_OUT, own), be.ptr(_OUT, gated),
                                 be.ptr("int32_t", st["cal"]), be.ptr("int32_t", st["mon"]),
                                 be.ptr("int32_t", st["est"]))
    from grip.monitor import Report
    return {"out": Output(arith, own, st["est"][:n]),
            "gated": Output(arith, gated, st["est"][:n]),
            "report": Report(arith, rep[:n], st["mon"][:n]) if monitor is not None else None,
            "samples": signals.Samples.from_struct(arith, used),
            "status_calib": st["cal"][:n] if calib is not None else None,
            "status_monitor": st["mon"][:n] if monitor is not None else None}
