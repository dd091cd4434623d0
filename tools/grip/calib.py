"""The sensor calibration stage (lib/calib, grip_calib.h) over arrays of
samples.

    cal = grip.calib.Calib({"offset": {"yaw_rate": 0.004}, "gain": {"ax": 0.98},
                            "delay": {"steer_angle": 2}}, arith="fixed")
    corrected, status = cal.apply(samples)

offset [SI unit of the input], gain [-], delay [steps] of the inputs 0..8
(grip.signals.INPUTS[:9]): a sequence of 9 values or a {name: value} dict
(the others: 0, 1, 0). apply() calls grip_calib_apply once per sample.
"""
import numpy as np

from grip import _core, signals
from grip._core import GripError, backend, check_arith

_CFG = "grip_calib_config_t"
N = 9   # GRIP_CALIB_N


def config_identity(arith="float"):
    be = backend(arith)
    cfg = be.ffi.new(_CFG + " *")
    be.lib.grip_calib_config_identity(cfg)
    return _core.get_fields(be, _CFG, cfg)


class Calib:
    """One calibration instance (grip_calib_t) of one arithmetic."""

    def __init__(self, config=None, arith="float"):
        check_arith(arith)
        self.arith = arith
        be = self._be = backend(arith)
        overrides = dict(config or {})
        self._cfg = self._make_cfg(overrides)
        self._c = be.ffi.new("grip_calib_t *")
        st = be.lib.grip_calib_init(self._c, self._cfg)
        if st != _core.OK:
            bad = _culprits(self, overrides)
            raise GripError(st, "grip_calib_init", _core.culprit_text(bad, "grip_calib.h"),
                            param=", ".join(bad) or None, arith=arith)

    def _make_cfg(self, overrides):
        be = self._be
        cfg = be.ffi.new(_CFG + " *")
        be.lib.grip_calib_config_identity(cfg)
        _core.set_fields(be, _CFG, cfg, overrides, "grip.calib.Calib", names_for_arrays=signals.INPUTS)
        return cfg

    def _try_init(self, overrides):
        c = self._be.ffi.new("grip_calib_t *")
        return self._be.lib.grip_calib_init(c, self._make_cfg(overrides))

    @property
    def config(self):
        return _core.get_fields(self._be, _CFG, self._cfg)

    def reset(self):
        st = self._be.lib.grip_calib_reset(self._c)
        if st != _core.OK:
            raise GripError(st, "grip_calib_reset", arith=self.arith)

    def apply(self, samples):
        """grip_calib_apply on every sample: (the calibrated Samples, status
        per sample)."""
        be = self._be
        s = signals.as_samples(samples)
        n = len(s)
        arr = s.to_struct(self.arith)
        out = np.zeros(n, be.dtype("grip_input_sample_t"))
        status = np.zeros(n, np.int32)
        if n:
            be.lib.grip_py_calib_run(self._c, n, be.ptr("grip_input_sample_t", arr),
                                     be.ptr("grip_input_sample_t", out), be.ptr("int32_t", status))
        return signals.Samples.from_struct(self.arith, out), status


def _culprits(cal, overrides):
    """Element-wise: which offset/gain/delay entries the init rejects."""
    flat = {}
    for key, v in overrides.items():
        items = v.items() if isinstance(v, dict) else enumerate(v) if key in ("offset", "gain", "delay") else []
        for i, x in items:
            flat[(key, i)] = x
    def try_without(rest):
        cfg = {}
        for (key, i), x in rest.items():
            cfg.setdefault(key, {})
            cfg[key][signals.INPUTS[i] if isinstance(i, int) else i] = x
        return cal._try_init(cfg)

    bad = _core.culprits(try_without, flat)
    return [f"{k}[{i}] = {flat[(k, i)]!r}" for k, i in bad]
