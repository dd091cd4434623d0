"""Candidate effects: each is a parametric term added to a base tire model,
with a fit() on a training mask. Every effect re-evaluates the base model
(never just a curve fitted to the residual), so its parameters mean
something physical and map onto a C configuration (docs/measured-data-loop.md,
"Onboard").

Base model: TireModel wraps grip_tools.mf.evaluate for one parameter set;
`over` passes overridden inputs (alpha, kappa, fz, ...) and array-valued
scaling factors (lmuy, lmux, lky, lkx), which mf.evaluate broadcasts.
"""
import numpy as np
from scipy.optimize import least_squares

from .. import mf
from ..relax_ref import lag_series
from .candidates import lowpass, slip_speed

G = 9.81


class TireModel:
    def __init__(self, params, name="mf"):
        self.params = dict(params)
        self.name = name
        self.fnomin = float(params.get("fnomin", 4000.0))
        self.nompres = float(params.get("nompres", 0.0) or 2e5)

    def predict(self, ch, over=None):
        over = over or {}
        n = len(ch["alpha"])
        z = np.zeros(n)
        P = dict(self.params)
        for k in ("lmuy", "lmux", "lky", "lkx"):
            if k in over:
                P[k] = P.get(k, 1.0) * over[k]
        g = {k: over.get(k, ch.get(k, d)) for k, d in
             (("kappa", z), ("alpha", z), ("gamma", z), ("fz", z), ("vx", z + 10.0))}
        p = over.get("p", ch.get("p"))
        out = mf.evaluate(P, g["kappa"], g["alpha"], g["gamma"], np.maximum(g["fz"], 0.0), p,
                          np.maximum(np.abs(g["vx"]), 0.1))
        return {k: out[k] for k in ("fx", "fy", "mz")}


class Effect:
    name = "?"
    tire_only = True        # needs a tire-level model (TireModel)
    pnames = ()
    x0 = ()
    lo = ()
    hi = ()
    onboard = ""

    def applicable(self, ds):
        return True, ""

    def predict(self, model, ds, x):
        raise NotImplementedError

    def fit(self, model, ds, mask, scale):
        """least squares of the scaled residual on mask; returns params."""
        outs = ds.outputs

        def resid(x):
            pr = self.predict(model, ds, x)
            return np.concatenate([(ds.ch[o][mask] - pr[o][mask]) / scale[o] for o in outs])
        best = None
        for start in self.starts():
            r = least_squares(resid, start, bounds=(self.lo, self.hi), x_scale="jac", max_nfev=60)
            if best is None or r.cost < best.cost:
                best = r
        return best.x

    def starts(self):
        return [np.array(self.x0, dtype=float)]

    def n_params(self, ds):
        return len(self.pnames)


def _varies(ds, name, tol):
    return name in ds.ch and float(np.std(ds.ch[name])) > tol


class Thermal(Effect):
    name = "thermal"
    pnames = ("a_mu", "tau_s")   # friction/stiffness scale per unit of heat state, heat time constant
    x0 = (0.0, 20.0)
    lo = (-5.0, 1.0)
    hi = (5.0, 600.0)
    onboard = "lib/mf_thermal (grip_mf_thermal.h): a_i, b_i, w, kappa = 1 / tau"

    def heat(self, model, ds, tau):
        base = model.predict(ds.ch)
        q = np.hypot(base["fx"], base["fy"]) * slip_speed(ds.ch)
        qn = q / (model.fnomin * 1.0)         # W per N of nominal load = m/s of sliding
        return lowpass(qn, ds.t, tau)

    def predict(self, model, ds, x):
        h = self.heat(model, ds, x[1])
        f = np.maximum(1.0 + x[0] * h, 0.05)
        return model.predict(ds.ch, {"lmuy": f, "lmux": f, "lky": f, "lkx": f})

    def starts(self):
        return [np.array([0.0, t]) for t in (5.0, 30.0, 150.0)]


class Relaxation(Effect):
    name = "relaxation"
    pnames = ("sigma_m",)
    x0 = (0.3,)
    lo = (0.0,)
    hi = (5.0,)
    onboard = "lib/relax (grip_relax.h): sigma_alpha = sigma_kappa = sigma"

    def predict(self, model, ds, x):
        s = float(x[0])
        over = {"alpha": lag_series(ds.ch["alpha"], ds.ch["vx"], ds.t, s)}
        if "kappa" in ds.ch:
            over["kappa"] = lag_series(ds.ch["kappa"], ds.ch["vx"], ds.t, s)
        return model.predict(ds.ch, over)

    def starts(self):
        return [np.array([s]) for s in (0.1, 0.5, 1.5)]


class SlipVelocity(Effect):
    name = "slip_velocity_friction"
    pnames = ("c_vs_s_per_m",)
    x0 = (0.0,)
    lo = (-0.5,)
    hi = (2.0,)
    onboard = "not yet in C (would be a mu(Vs) factor on LMUX/LMUY per step)"

    def predict(self, model, ds, x):
        f = 1.0 / np.maximum(1.0 + x[0] * slip_speed(ds.ch), 0.05)
        return model.predict(ds.ch, {"lmuy": f, "lmux": f})


class LoadSensitivity(Effect):
    name = "load_sensitivity"
    pnames = ("c_dfz",)
    x0 = (0.0,)
    lo = (-2.0,)
    hi = (2.0,)
    onboard = "MF coefficients: PDY2 += c PDY1, PDX2 += c PDX1 (grip_mf_params)"

    def applicable(self, ds):
        return (_varies(ds, "fz", 1.0), "fz constant")

    def predict(self, model, ds, x):
        f = np.maximum(1.0 + x[0] * (ds.ch["fz"] - model.fnomin) / model.fnomin, 0.05)
        return model.predict(ds.ch, {"lmuy": f, "lmux": f})


class Camber(Effect):
    name = "camber"
    pnames = ("c_gamma",)
    x0 = (0.0,)
    lo = (-20.0,)
    hi = (20.0,)
    onboard = "MF coefficients: PVY3/PKY6 (camber thrust), grip_mf_params"

    def applicable(self, ds):
        return (_varies(ds, "gamma", 1e-4), "gamma constant")

    def predict(self, model, ds, x):
        out = dict(model.predict(ds.ch))
        out["fy"] = out["fy"] + x[0] * ds.ch["gamma"] * ds.ch["fz"]
        return out


class Pressure(Effect):
    name = "inflation_pressure"
    pnames = ("c_dp",)
    x0 = (0.0,)
    lo = (-2.0,)
    hi = (2.0,)
    onboard = "MF 6.1 coefficients PPY*/PPX* (grip_mf_params); p is an input"

    def applicable(self, ds):
        return (_varies(ds, "p", 100.0), "p constant or absent")

    def predict(self, model, ds, x):
        f = np.maximum(1.0 + x[0] * (ds.ch["p"] - model.nompres) / model.nompres, 0.05)
        return model.predict(ds.ch, {"lmuy": f, "lmux": f, "lky": f, "lkx": f})


class AeroLoad(Effect):
    name = "aero_load"
    pnames = ("c_v2_N_s2_m2",)
    x0 = (0.0,)
    lo = (-5.0,)
    hi = (20.0,)
    onboard = "vehicle configuration (downforce coefficient in the load model), not a tire parameter"

    def applicable(self, ds):
        return (_varies(ds, "vx", 0.5), "speed constant")

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"fz": ds.ch["fz"] + x[0] * ds.ch["vx"] ** 2})


class Bank(Effect):
    name = "road_bank"
    pnames = ("sin_bank",)
    x0 = (0.0,)
    lo = (-0.3,)
    hi = (0.3,)
    onboard = "estimator input (gravity component) / signal table offset; no tire term"

    def applicable(self, ds):
        return ("fy" in ds.outputs and _varies(ds, "fz", 1.0), "needs fy and varying fz")

    def predict(self, model, ds, x):
        out = dict(model.predict(ds.ch))
        out["fy"] = out["fy"] + x[0] * ds.ch["fz"]
        return out


class Bias(Effect):
    name = "sensor_bias"
    tire_only = False
    onboard = "signal table offset (grip_signals)"

    def n_params(self, ds):
        return len(ds.outputs)

    def fit(self, model, ds, mask, scale):
        base = model.predict(ds.ch)
        return np.array([np.mean(ds.ch[o][mask] - base[o][mask]) for o in ds.outputs])

    def predict(self, model, ds, x):
        out = dict(model.predict(ds.ch))
        for i, o in enumerate(ds.outputs):
            out[o] = out[o] + x[i]
        return out


class Scale(Effect):
    name = "sensor_scale"
    tire_only = False
    onboard = "signal table scale (grip_signals)"

    def n_params(self, ds):
        return len(ds.outputs)

    def fit(self, model, ds, mask, scale):
        base = model.predict(ds.ch)
        x = []
        for o in ds.outputs:
            b, y = base[o][mask], ds.ch[o][mask]
            x.append(float(np.dot(b, y) / max(np.dot(b, b), 1e-12)) - 1.0)
        return np.array(x)

    def predict(self, model, ds, x):
        out = dict(model.predict(ds.ch))
        for i, o in enumerate(ds.outputs):
            out[o] = out[o] * (1.0 + x[i])
        return out


class Delay(Effect):
    name = "sensor_delay"
    tire_only = False
    pnames = ("delay_s",)
    x0 = (0.0,)
    lo = (-0.5,)
    hi = (0.5,)
    onboard = "signal table / input buffer delay (whole samples)"

    def predict(self, model, ds, x):
        out = model.predict(ds.ch)
        t = ds.t
        return {k: np.interp(t - x[0], t, v) for k, v in out.items()}

    def starts(self):
        return [np.array([d]) for d in (-0.1, 0.0, 0.1)]


def all_effects():
    return [Thermal(), Relaxation(), SlipVelocity(), LoadSensitivity(), Camber(), Pressure(),
            AeroLoad(), Bank(), Bias(), Scale(), Delay()]
