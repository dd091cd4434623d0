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
    kind = "tire"

    def __init__(self, params, name="mf", tir_path=None):
        self.tir_path = tir_path
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
        if "lmuv" in over:                     # absolute: the .tir LMUV of the updated set
            P["lmuv"] = over["lmuv"]
        g = {k: over.get(k, ch.get(k, d)) for k, d in
             (("kappa", z), ("alpha", z), ("gamma", z), ("fz", z), ("vx", z + 10.0))}
        p = over.get("p", ch.get("p"))
        out = mf.evaluate(P, g["kappa"], g["alpha"], g["gamma"], np.maximum(g["fz"], 0.0), p,
                          np.maximum(np.abs(g["vx"]), 0.1))
        return {k: out[k] for k in ("fx", "fy", "mz")}


class Effect:
    name = "?"
    level = "tire"          # "tire": needs a TireModel; "vehicle": a model listing it in
                            # model.supports; "any": a term on the outputs (sensor effects)
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
    """Friction falling with slip speed in the Magic Formula's own LMUV form,
    LMU* = LMU / (1 + LMUV Vs / LONGVL), Vs = |vx| sqrt(kappa^2 + tan^2 alpha)
    (lib/mf/mf_eval.c, mf.py): the fitted value is the .tir coefficient LMUV
    itself, so the updated file runs in grip_mf unchanged. LMUV >= 0 (the C
    library rejects a negative LMUV: friction rising with slip speed is not
    representable)."""
    name = "slip_velocity_friction"
    pnames = ("lmuv",)
    x0 = (0.0,)
    lo = (0.0,)
    hi = (50.0,)
    onboard = "lib/mf: .tir LMUV (SCALING_COEFFICIENTS), grip_mf_params.lmuv"

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"lmuv": float(x[0])})

    def starts(self):
        return [np.array([s]) for s in (0.5, 5.0)]


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
    level = "any"
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
    level = "any"
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
    level = "any"
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


# ---------------------------------------------------------------------------
# Vehicle-level effects: terms of residual.vehicle.VehicleModel (switched on
# through predict(ch, over)). Each simulation costs tens of ms, so the fit is
# a few damped Gauss-Newton iterations with a forward-difference Jacobian
# (k + 1 simulations per iteration), not a general least-squares search.

class VehicleEffect(Effect):
    level = "vehicle"
    steps = ()
    iters = 4

    def over(self, x):
        raise NotImplementedError

    def predict(self, model, ds, x):
        return model.predict(ds.ch, self.over(x))

    def fit(self, model, ds, mask, scale):
        outs = ds.outputs

        def resid(x):
            pr = self.predict(model, ds, x)
            return np.concatenate([(ds.ch[o][mask] - pr[o][mask]) / scale[o] for o in outs])
        best = None
        for start in self.starts():
            x, c = gauss_newton(resid, start, self.steps, self.lo, self.hi, self.iters, self.free(start))
            if best is None or c < best[1]:
                best = (x, c)
        return best[0]

    def free(self, start):
        return np.ones(len(start), bool)


def gauss_newton(resid, x0, steps, lo, hi, iters, free):
    """Damped Gauss-Newton within bounds on the free parameters. Returns (x, cost)."""
    x = np.array(x0, dtype=float)
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    r = resid(x)
    cost = float(r @ r)
    lam = 1e-3
    for _ in range(iters):
        J = np.zeros((len(r), len(x)))
        for j in np.flatnonzero(free):
            xp = x.copy()
            h = steps[j] if xp[j] + steps[j] <= hi[j] else -steps[j]
            xp[j] += h
            J[:, j] = (resid(xp) - r) / h
        A = J.T @ J
        g = J.T @ r
        improved = False
        for _ in range(3):
            dx = -np.linalg.solve(A + lam * np.diag(np.diag(A) + 1e-12), g)
            xn = np.clip(x + dx, lo, hi)
            rn = resid(xn)
            cn = float(rn @ rn)
            if cn < cost:
                x, r, cost, lam, improved = xn, rn, cn, lam * 0.3, True
                break
            lam *= 10.0
        if not improved or np.all(np.abs(dx) < 1e-3 * np.asarray(steps)):
            break
    return x, cost


class VRelaxation(VehicleEffect):
    name = "relaxation"
    pnames = ("sigma_m",)
    x0, lo, hi, steps = (0.3,), (0.02,), (5.0,), (0.05,)
    iters = 3
    onboard = "lib/relax (grip_relax.h) per tyre: sigma_alpha = sigma"

    def over(self, x):
        return {"sigma": float(x[0])}


class VBank(VehicleEffect):
    """Road plane (bank and grade, earth-fixed to the initial heading): two
    parameters, since the lateral slope the body sees turns with the heading."""
    name = "road_bank"
    pnames = ("tan_bank", "tan_grade")
    x0, lo, hi, steps = (0.0, 0.0), (-0.3, -0.3), (0.3, 0.3), (0.01, 0.01)
    iters = 3
    onboard = "estimator gravity input (lateral slope); not a tyre term"

    def over(self, x):
        return {"tan_bank": float(x[0]), "tan_grade": float(x[1])}


class VAero(VehicleEffect):
    name = "aero_load"
    pnames = ("cla_add_m2",)
    x0, lo, hi, steps = (0.0,), (-3.0,), (10.0,), (0.5,)
    iters = 3
    onboard = "vehicle configuration: downforce coefficient C_L A in the load model (lib/est), not a tyre parameter"

    def over(self, x):
        return {"cla_add": float(x[0])}


class VThermal(VehicleEffect):
    """Axle surface temperature, seed ch. 4 (W fixed at 1500 J/K: only a / W,
    b / W and kappa are identifiable without a temperature channel); a
    grid over kappa, Gauss-Newton on (a, b) at each, then on all three."""
    name = "thermal"
    pnames = ("a_mu_per_K", "b_k_per_K", "kappa_per_s")
    lo, hi, steps = (-1.0, -1.0, 0.005), (1.0, 1.0, 5.0), (0.002, 0.002, 0.05)
    W = 1500.0
    onboard = ("lib/mf_thermal temperature state (w, kappa) per tyre; LMUY, LKY of lib/mf scaled by "
               "1 + a (T - T0), 1 + b (T - T0)")

    def over(self, x):
        return {"thermal": (float(x[0]), float(x[1]), float(x[2]), self.W)}

    def fit(self, model, ds, mask, scale):
        outs = ds.outputs

        def resid(x):
            pr = self.predict(model, ds, x)
            return np.concatenate([(ds.ch[o][mask] - pr[o][mask]) / scale[o] for o in outs])
        best = None
        for k in (0.05, 0.3):
            x, c = gauss_newton(resid, [-0.002, -0.002, k], self.steps, self.lo, self.hi, 2,
                                np.array([True, True, False]))
            if best is None or c < best[1]:
                best = (x, c)
        x, _ = gauss_newton(resid, best[0], self.steps, self.lo, self.hi, 2, np.ones(3, bool))
        return x


def all_effects():
    return [Thermal(), Relaxation(), SlipVelocity(), LoadSensitivity(), Camber(), Pressure(),
            AeroLoad(), Bank(), VThermal(), VRelaxation(), VBank(), VAero(), Bias(), Scale(), Delay()]
