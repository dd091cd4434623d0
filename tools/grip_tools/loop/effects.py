"""Candidate effects: each is a parametric term added to a base tire model,
with a fit() on a training mask. Every effect re-evaluates the base model
(never just a curve fitted to the residual), so its parameters mean
something physical and map onto a C configuration (docs/measured-data-loop.md,
"Onboard").

Base model: TireModel wraps grip_tools.reference.mf.evaluate for one parameter set;
`over` passes overridden inputs (alpha, kappa, fz, ...) and array-valued
scaling factors (lmuy, lmux, lky, lkx), which mf.evaluate broadcasts;
over["coef"] = {name: value} replaces MF coefficients (grip_mf_params field
names, lower case) by absolute values: the effects that are .tir changes
(camber, pressure) predict with the Magic Formula of the updated set itself.
"""
import math

import numpy as np
from scipy.optimize import least_squares

from grip_tools.reference import mf
from grip_tools.loop.grammar import relax_series

G = 9.81
# Magic Formula scaling factors `over` may multiply (arrays broadcast in mf.evaluate)
SCALING = ("lmux", "lmuy", "lkx", "lky", "lcx", "lcy", "lex", "ley", "ltr", "lres", "lkyc", "lkzc",
           "lhx", "lhy", "lvx", "lvy", "lxal", "lyka", "lvyka", "ls")
FIT_ROWS = 4000     # training rows an effect's least-squares fit evaluates at most (evenly strided)


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
        for k, v in over.items():             # scaling factors: multiply the set's own
            if k in SCALING:
                P[k] = P.get(k, 1.0) * v
        if "lmuv" in over:                     # absolute: the .tir LMUV of the updated set
            P["lmuv"] = over["lmuv"]
        for k, v in over.get("cmul", {}).items():   # coefficients x (arrays broadcast)
            P[k] = P[k] * v
        for k, v in over.get("coef", {}).items():   # absolute: coefficients of the updated .tir
            if k not in P:
                raise KeyError(f"unknown MF coefficient {k!r}")
            P[k] = float(v)
        g = {k: over.get(k, ch.get(k, d)) for k, d in
             (("kappa", z), ("alpha", z), ("gamma", z), ("fz", z), ("vx", z + 10.0))}
        p = over.get("p", ch.get("p"))
        out = mf.evaluate(P, g["kappa"], g["alpha"], g["gamma"], np.maximum(g["fz"], 0.0), p,
                          np.maximum(np.abs(g["vx"]), 0.1))
        return {k: out[k] for k in ("fx", "fy", "mz")}


class RowModel:
    """A TireModel evaluated on some rows only: predict() slices the record's
    arrays (channels and array-valued overrides) to `rows`, evaluates the
    model there and returns whole-record arrays (zero elsewhere), so that an
    effect's own whole-record arithmetic keeps working while its fit costs
    len(rows) evaluations."""

    def __init__(self, model, rows, n):
        self._m, self.rows, self.n = model, rows, n

    def __getattr__(self, name):
        return getattr(self._m, name)

    def _cut(self, d):
        return {k: (self._cut(v) if isinstance(v, dict) else
                    v[self.rows] if isinstance(v, np.ndarray) and v.shape == (self.n,) else v)
                for k, v in d.items()}

    def predict(self, ch, over=None):
        out = self._m.predict(self._cut(ch), self._cut(over or {}))
        full = {}
        for k, v in out.items():
            a = np.zeros(self.n)
            a[self.rows] = v
            full[k] = a
        return full


def fit_rows(mask, limit=FIT_ROWS):
    idx = np.flatnonzero(mask)
    if len(idx) > limit:
        idx = idx[np.linspace(0, len(idx) - 1, limit).round().astype(int)]
    return idx


class Effect:
    name = "?"
    level = "tire"          # "tire": needs a TireModel; "vehicle": a model listing it in
                            # model.supports; "any": a term on the outputs (sensor effects)
    pnames = ()
    x0 = ()
    lo = ()
    hi = ()
    onboard = ""
    families = ()           # grammar (target, driver) pairs this named form competes with
    rows_ok = True          # the fit may evaluate a stride of the training rows (RowModel)

    def applicable(self, ds):
        return True, ""

    def predict(self, model, ds, x):
        raise NotImplementedError

    def fit(self, model, ds, mask, scale):
        """least squares of the scaled residual on mask (a stride of at most
        FIT_ROWS of its rows for a tyre model); returns params."""
        outs = ds.outputs
        if self.rows_ok and isinstance(model, TireModel) and mask.sum() > FIT_ROWS:
            rows = fit_rows(mask)
            model = RowModel(model, rows, len(ds))
            mask = np.zeros(len(ds), bool)
            mask[rows] = True

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

    def hint(self, screened):
        """Called with the grammar's screened pairs (best first) before fit:
        a named form may take its start from them."""

    def n_params(self, ds):
        return len(self.pnames)


def _varies(ds, name, tol):
    return name in ds.ch and float(np.std(ds.ch[name])) > tol


def thermal_params_from_mf(P, a, b, kappa, w, t0, fz_max=None):
    """mf_thermal.ThermalParams (lib/mf_thermal's parameter set) whose force
    model is the Magic Formula set P at its nominal load, gamma = 0, nominal
    pressure: D, K from the MF's own mu and slip stiffnesses, C, E, the
    combined-slip B, C, E, Sh from the pure coefficients (load, sign and
    cross terms of E and B dropped; shifts 0). It serves as the heat source
    q = |F| Vs of the temperature state; the output forces stay those of P."""
    from grip_tools.reference import mf_thermal
    fz0 = float(P["fnomin"])
    o = mf.evaluate(P, 0.0, 0.0, 0.0, fz0, None, float(P.get("longvl", 16.7)) or 16.7, details=True)
    d = o["details"]
    mux, muy = abs(float(np.ravel(d["mux"])[0])), abs(float(np.ravel(d["muy"])[0]))
    kx, ky = abs(float(np.ravel(d["Kxk"])[0])), abs(float(np.ravel(d["Kya"])[0]))
    g = lambda k, dflt: float(P.get(k, dflt) or dflt)     # noqa: E731
    return mf_thermal.ThermalParams(
        fz0=fz0, t0=t0,
        dx0=mux * fz0, kx0=kx, cx=min(max(g("pcx1", 1.6) * g("lcx", 1.0), 0.1), 1.99),
        ex=min(g("pex1", 0.0) * g("lex", 1.0), 0.99), shx=0.0, svx=0.0, ax=a, bx=b,
        dy0=muy * fz0, ky0=ky, cy=min(max(g("pcy1", 1.3) * g("lcy", 1.0), 0.1), 1.99),
        ey=min(g("pey1", 0.0) * g("ley", 1.0), 0.99), shy=0.0, svy=0.0, ay=a, by=b,
        bxa=abs(g("rbx1", 10.0)) * g("lxal", 1.0), cxa=min(abs(g("rcx1", 1.0)), 1.0),
        exa=min(g("rex1", 0.0), 0.99), shxa=0.0,
        bys=abs(g("rby1", 10.0)) * g("lyka", 1.0), cys=min(abs(g("rcy1", 1.0)), 1.0),
        eys=min(g("rey1", 0.0), 0.99), shys=0.0, svys=0.0,
        w=w, kappa=kappa, fz_max=fz_max or 3.0 * fz0, alpha_max=0.5, slip_max=1.0, v_max=100.0,
        # the library requires 1 + a (T - T0) > 0 over [t_min, t_max]: the
        # temperature is limited where a factor would reach 0.05
        t_min=max(t0 - 0.95 / max(a, b, 1e-6), -1000.0), t_max=min(t0 + 0.95 / max(-a, -b, 1e-6), 1000.0))


def thermal_temperature(prm, ch, t, t_road=None):
    """Surface temperature T_k at the start of every step, exactly as
    grip_mf_thermal_step advances it: q_k = |F(T_k)| Vs from the thermal
    model's own forces at T_k (mf_thermal.forces, eqs. 4.11-4.18), then
    T_{k+1} = T_k + phi (q_k / W - kappa (T_k - T_R)), limited to
    [t_min, t_max]. Inputs as the C caller passes them: V = vx / cos(alpha),
    alpha_seed = -alpha, S = -kappa. A scalar loop in plain Python floats
    (mf_thermal.simulate is the same recurrence with numpy scalars, 20x
    slower; tests/python/loop/test_onboard.py checks the two agree)."""
    from grip_tools.reference import mf_thermal
    alpha = np.asarray(ch["alpha"], dtype=float)
    n = len(alpha)
    al = (-alpha).tolist()
    sl = (-np.asarray(ch.get("kappa", 0.0 * alpha), dtype=float)).tolist()
    vl = (np.abs(np.asarray(ch["vx"], dtype=float)) / np.cos(alpha)).tolist()
    fzl = (np.asarray(ch["fz"], dtype=float) / prm.fz0).tolist()
    tr = np.broadcast_to(prm.t0 if t_road is None else np.asarray(t_road, dtype=float), (n,)).tolist()
    dt = np.diff(np.asarray(t, dtype=float)).tolist()
    ph = [mf_thermal.phi(prm.kappa, d) for d in dt]
    P = prm
    atan, sin, cos, sqrt = math.atan, math.sin, math.cos, math.sqrt

    def mfs(d, b, c, e, x):
        bp = b * x
        return d * sin(c * atan(bp - e * (bp - atan(bp))))

    def mfc(b, c, e, x):
        bp = b * x
        return cos(c * atan(bp - e * (bp - atan(bp))))
    gx_den = mfc(P.bxa, P.cxa, P.exa, P.shxa)
    gy_den = mfc(P.bys, P.cys, P.eys, P.shys)
    T = [0.0] * n
    x = float(P.t0)
    inv_w = 1.0 / P.w
    for i in range(n):
        T[i] = x
        if i == n - 1:
            break
        a, sp = al[i], sl[i]
        u = x - P.t0
        dxx, kxx = P.dx0 * (1 + P.ax * u), P.kx0 * (1 + P.bx * u)
        dyy, kyy = P.dy0 * (1 + P.ay * u), P.ky0 * (1 + P.by * u)
        fx0 = mfs(dxx, kxx / (P.cx * dxx), P.cx, P.ex, sp + P.shx) + P.svx
        fy0 = mfs(dyy, kyy / (P.cy * dyy), P.cy, P.ey, a + P.shy) + P.svy
        fx = fzl[i] * fx0 * mfc(P.bxa, P.cxa, P.exa, a + P.shxa) / gx_den
        fy = fzl[i] * (fy0 * mfc(P.bys, P.cys, P.eys, sp + P.shys) / gy_den + P.svys)
        ca = cos(a)
        vs = vl[i] * sqrt((sp * ca) ** 2 + sin(a) ** 2)
        q = sqrt(fx * fx + fy * fy) * vs
        x = x + ph[i] * (q * inv_w - P.kappa * (x - tr[i]))
        x = min(max(x, P.t_min), P.t_max)
    return np.array(T)


class Thermal(Effect):
    """Tyre surface temperature, seed 000 ch. 4, in the form that runs
    onboard: the temperature state of lib/mf_thermal (grip_mf_thermal_step,
    its step scheme reproduced exactly by thermal_temperature) with the
    heat q = |F| Vs of a thermal parameter set derived from the model's
    MF at nominal load (thermal_params_from_mf), and the output forces of
    the model itself with LMUX, LMUY x (1 + a (T - T0)) and LKX, LKY x
    (1 + b (T - T0)) (D and K of the seed's eqs. 4.13-4.14). W is fixed at
    1500 J/K: without a temperature channel only a / W, b / W and kappa are
    identifiable. T0 = T_R = 25 degC (or the t_road channel as T_R)."""
    name = "thermal"
    pnames = ("a_mu_per_K", "b_k_per_K", "kappa_per_s")
    families = (("grip", "state:energy"), ("mu", "state:energy"), ("k", "state:energy"))
    x0 = (-0.002, -0.002, 0.05)
    lo = (-0.2, -0.2, 0.001)
    hi = (0.2, 0.2, 5.0)
    W, T0 = 1500.0, 25.0
    onboard = ("lib/mf_thermal state (update.json grip_mf_thermal_params) + lib/mf with LMUX/LMUY "
               "x (1 + a (T - T0)), LKX/LKY x (1 + b (T - T0)); tests/python/loop/test_onboard.py")

    def thermal_params(self, model, x):
        return thermal_params_from_mf(model.params, float(x[0]), float(x[1]), float(x[2]), self.W, self.T0)

    def temperature(self, model, ds, x):
        return thermal_temperature(self.thermal_params(model, x), ds.ch, ds.t, ds.ch.get("t_road"))

    def predict(self, model, ds, x):
        dT = self.temperature(model, ds, x) - self.T0
        fd = np.maximum(1.0 + x[0] * dT, 0.05)
        fk = np.maximum(1.0 + x[1] * dT, 0.05)
        return model.predict(ds.ch, {"lmuy": fd, "lmux": fd, "lky": fk, "lkx": fk})

    _kappa0 = None

    def hint(self, screened):
        for sc in screened:
            if sc.spec.driver.name == "state:energy" and sc.spec.target.name in ("grip", "mu", "k"):
                self._kappa0 = min(max(1.0 / float(sc.p[0]), self.lo[2]), self.hi[2])
                return

    def starts(self):
        if self._kappa0 is not None:
            return [np.array([-0.002, -0.002, self._kappa0])]
        return [np.array([-0.002, -0.002, k]) for k in (0.02, 0.2)]


class Relaxation(Effect):
    """alpha and kappa through lib/relax's first-order relaxation, stepped
    with the current sample (grammar.relax_series): sigma -> 0 is the base
    model itself. The grammar's lag:relax~const is the same term."""
    name = "relaxation"
    pnames = ("sigma_m",)
    x0 = (0.3,)
    lo = (0.0,)
    hi = (5.0,)
    onboard = "lib/relax (grip_relax.h): sigma_alpha = sigma_kappa = sigma, stepped with the current sample"
    families = (("lag:relax", "const"),)

    def predict(self, model, ds, x):
        s = float(x[0])
        over = {"alpha": relax_series(ds.ch["alpha"], ds.ch["vx"], ds.t, s)}
        if "kappa" in ds.ch:
            over["kappa"] = relax_series(ds.ch["kappa"], ds.ch["vx"], ds.t, s)
        return model.predict(ds.ch, over)

    def starts(self):
        return [np.array([s]) for s in (0.1, 0.5, 1.5)]


def first_order_lag(x, t, tau):
    """x through a first-order lag of time constant tau [s], discretized as
    lib/est does its steering lag (k = min(dt / tau, 1) per sample)."""
    if tau <= 0.0:
        return np.asarray(x, dtype=float).copy()
    x = np.asarray(x, dtype=float)
    k = np.minimum(np.diff(np.asarray(t, dtype=float)) / tau, 1.0).tolist()
    y = [float(x[0])] * len(x)
    xl = x.tolist()
    for i in range(1, len(xl)):
        y[i] = y[i - 1] + k[i - 1] * (xl[i] - y[i - 1])
    return np.array(y)


class SteerLag(Effect):
    """The road wheels follow the steering signal with a first-order lag
    (steer-by-wire actuator, a logged steering command, steering
    compliance): the front slip angle built from delta is rebuilt from the
    lagged delta, alpha_iso' = alpha_iso + delta - lag(delta). Needs a front
    axle data set with its delta channel (vehicle data turned into axle
    forces, loop/av21.py)."""
    name = "steer_lag"
    pnames = ("tau_s",)
    x0 = (0.1,)
    lo = (0.0,)
    hi = (0.5,)
    onboard = "lib/est grip_est_config_t.steer_lag (est_eval.steer_lag_fit identifies it from yaw rate)"

    def applicable(self, ds):
        if ds.meta.get("axle") != "front":
            return False, "not a front axle"
        return (_varies(ds, "delta", 1e-4), "no delta channel")

    def predict(self, model, ds, x):
        d = ds.ch["delta"]
        return model.predict(ds.ch, {"alpha": ds.ch["alpha"] + d - first_order_lag(d, ds.t, float(x[0]))})

    def starts(self):
        return [np.array([s]) for s in (0.05, 0.2, 0.4)]


class MeasuringPoint(Effect):
    """The lateral velocity behind the slip angles was measured (or moved)
    to a point dx off the one assumed (an INS lever arm along x): the slip
    angles shift by -dx r / vx on both axles (ISO sign; the force side,
    which uses d(vy)/dt, is left as it is). Needs r and vx channels."""
    name = "measuring_point"
    pnames = ("dx_m",)
    x0 = (0.0,)
    lo = (-2.0,)
    hi = (2.0,)
    onboard = "no tyre term: the velocity source's position in the data reader (av21_log.INS_X)"

    def applicable(self, ds):
        return (_varies(ds, "r", 1e-3) and "vx" in ds.ch, "no yaw-rate channel")

    def predict(self, model, ds, x):
        v = np.maximum(np.abs(ds.ch["vx"]), 1.0)
        return model.predict(ds.ch, {"alpha": ds.ch["alpha"] - float(x[0]) * ds.ch["r"] / v})

    def starts(self):
        return [np.array([s]) for s in (-0.5, 0.0, 0.5)]


class SlipVelocity(Effect):
    """Friction falling with slip speed in the Magic Formula's own LMUV form,
    LMU* = LMU / (1 + LMUV Vs / LONGVL), Vs = |vx| sqrt(kappa^2 + tan^2 alpha)
    (lib/mf/mf_eval.c, mf.py): the fitted value is the .tir coefficient LMUV
    itself, so the updated file runs in grip_mf unchanged. LMUV >= 0 (the C
    library rejects a negative LMUV: friction rising with slip speed is not
    representable)."""
    name = "slip_velocity_friction"
    pnames = ("lmuv",)
    families = tuple((t, d) for d in ("vs", "vs2") for t in ("mu", "mux", "muy", "grip"))
    x0 = (0.0,)
    lo = (0.0,)
    hi = (50.0,)
    onboard = "lib/mf: .tir LMUV (SCALING_COEFFICIENTS), grip_mf_params.lmuv"

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"lmuv": float(x[0])})

    def starts(self):
        return [np.array([s]) for s in (0.5, 5.0)]


class LoadSensitivity(Effect):
    """LMUX = LMUY = 1 + c dfz, dfz = (Fz - FNOMIN) / FNOMIN: the grammar's
    mu~dfz, written as PDY2 += c PDY1, PDX2 += c PDX1."""
    name = "load_sensitivity"
    families = (("mu", "dfz"),)
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
    """Camber thrust beyond the model, as a change c of two MF 6.1
    coefficients: PKY6 += c and PVY3 += c. In MF 6.1 (mf.py _fy0) PKY6 is
    the camber stiffness Kyg0 = Fz (PKY6 + PKY7 dfz)(1 + PPY5 dpi) LKYC,
    which enters only through SHy (+Kyg0 gamma / Kya); PVY3 is in
    SVyg = Fz (PVY3 + PVY4 dfz) gamma LKYC LMUY', which enters SVy (+SVyg)
    and SHy (-SVyg / Kya), so that in the linear range it cancels and acts
    only at saturation. Together, the change adds about c gamma Fz to Fy at
    every slip (linear range through PKY6, saturation through PVY3): the
    one-parameter term of the earlier form, now exactly the Magic Formula
    with the updated coefficients (the prediction IS mf.evaluate of the
    updated set; the updated .tir runs in grip_mf_eval unchanged). MF 5.2
    (no PKY6; SVy = Fz (... + (PVY3 + PVY4 dfz) gamma) LMUY' without the
    SHy cancellation): PVY3 += c alone."""
    name = "camber"
    pnames = ("c_gamma",)
    x0 = (0.0,)
    lo = (-5.0,)
    hi = (5.0,)
    keys = ("pky6", "pvy3")
    families = (("kyc", "const"), ("svy", "gamma"), ("in:gamma", "const"))
    onboard = "lib/mf: .tir PKY6 += c, PVY3 += c (MF 6.x camber stiffness and camber thrust), grip_mf_params"

    def applicable(self, ds):
        return (_varies(ds, "gamma", 1e-4), "gamma constant")

    def coefficients(self, params, x):
        keys = self.keys if int(params.get("fittyp", 61)) in mf.MF6 else ("pvy3",)
        return {k: float(params[k]) + float(x[0]) for k in keys}

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"coef": self.coefficients(model.params, x)})


class Pressure(Effect):
    """Inflation-pressure dependence beyond the model, as a change c of the
    MF 6.1 linear pressure coefficients of friction and slip stiffness:
    PPX3 += c, PPY3 += c (mu_x, mu_y x (1 + PP*3 dpi + PP*4 dpi^2)) and
    PPX1 += c, PPY1 += c (Kxk x (1 + PPX1 dpi + PPX2 dpi^2), Kya x
    (1 + PPY1 dpi)), dpi = (p - NOMPRES) / NOMPRES. To first order in dpi
    the earlier LMU, LK x (1 + c dpi); now the prediction is the Magic
    Formula of the updated set itself (p is an input of grip_mf_eval,
    dpi limited to [GRIP_MF_DPI_MIN, GRIP_MF_DPI_MAX] = [-0.5, 1] there).
    MF 5.2 has no pressure terms: the change does nothing there and the
    effect is never accepted on an MF 5.2 model."""
    name = "inflation_pressure"
    pnames = ("c_dp",)
    x0 = (0.0,)
    lo = (-2.0,)
    hi = (2.0,)
    keys = ("ppx1", "ppy1", "ppx3", "ppy3")
    families = (("grip", "dpi"), ("k", "dpi"), ("mu", "dpi"), ("in:p", "dpi"))
    onboard = "lib/mf: .tir PPX1, PPY1, PPX3, PPY3 += c (MF 6.x), grip_mf_params; p is an input"

    def applicable(self, ds):
        return (_varies(ds, "p", 100.0), "p constant or absent")

    def coefficients(self, params, x):
        return {k: float(params[k]) + float(x[0]) for k in self.keys}

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"coef": self.coefficients(model.params, x)})


def derived(ds, name):
    """True when channel `name` of ds was derived from vehicle motion (a load
    model, m ay, kinematics) rather than measured at the tyre: ds.meta
    ['derived'] lists them (grip analyze --derived; loop/av21.py). Effects
    of the vehicle on a derived channel (downforce in a modelled load, road
    bank in a force from m ay) apply only there: a rig or a wheel-force
    transducer measures Fz and Fy with them included."""
    return name in ds.meta.get("derived", ())


class AeroLoad(Effect):
    name = "aero_load"
    pnames = ("c_v2_N_s2_m2",)
    x0 = (0.0,)
    lo = (-5.0,)
    hi = (20.0,)
    onboard = "vehicle configuration (downforce coefficient in the load model), not a tire parameter"

    def applicable(self, ds):
        if not derived(ds, "fz"):
            return False, "Fz is measured (not derived from a load model): a downforce is in it already"
        return (_varies(ds, "vx", 0.5), "speed constant")

    def predict(self, model, ds, x):
        return model.predict(ds.ch, {"fz": ds.ch["fz"] + x[0] * ds.ch["vx"] ** 2})


class Bank(Effect):
    name = "road_bank"
    pnames = ("sin_bank",)
    families = (("svy", "const"),)
    x0 = (0.0,)
    lo = (-0.3,)
    hi = (0.3,)
    onboard = "no tyre term; at vehicle level grip_est_config_t.tan_bank / tan_grade (lib/est)"

    def applicable(self, ds):
        if not derived(ds, "fy"):
            return False, "Fy is measured at the tyre (not derived from m ay): no road bank in it"
        return ("fy" in ds.outputs and _varies(ds, "fz", 1.0), "needs fy and varying fz")

    def predict(self, model, ds, x):
        out = dict(model.predict(ds.ch))
        out["fy"] = out["fy"] + x[0] * ds.ch["fz"]
        return out


class Bias(Effect):
    name = "sensor_bias"
    level = "any"
    families = (("out:offset", "const"),)
    onboard = "lib/calib grip_calib_config_t.offset (vehicle level: yaw rate, ay)"

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
    families = (("out:scale", "const"),)
    onboard = "lib/calib grip_calib_config_t.gain = 1 / (1 + s) (vehicle level: yaw rate, ay)"

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
    rows_ok = False
    families = (("out:delay", "const"),)
    pnames = ("delay_s",)
    x0 = (0.0,)
    lo = (-0.5,)
    hi = (0.5,)
    onboard = "lib/calib grip_calib_config_t.delay (whole steps, <= 32; vehicle level)"

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
    onboard = "lib/est grip_est_config_t.tan_bank, tan_grade (earth-fixed road plane); not a tyre term"

    def over(self, x):
        return {"tan_bank": float(x[0]), "tan_grade": float(x[1])}


class VAero(VehicleEffect):
    name = "aero_load"
    pnames = ("cla_add_m2",)
    x0, lo, hi, steps = (0.0,), (-3.0,), (10.0,), (0.5,)
    iters = 3
    onboard = "lib/est grip_est_config_t.cla (+ aero_front, air_density): downforce in the load model"

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


def tyre_specials():
    """The named tyre-level forms the grammar does not generate exactly (or
    whose onboard form differs from the grammar's): run beside it by
    attribution.analyse, those with `families` only when one of them is among
    the best screened grammar pairs. Relaxation, load sensitivity and the
    sensor bias / scale / delay are grammar instances (grammar.ALIASES)."""
    return [Thermal(), SlipVelocity(), Camber(), Pressure(), AeroLoad(), Bank(), SteerLag(), MeasuringPoint()]


def all_effects():
    return [Thermal(), Relaxation(), SteerLag(), MeasuringPoint(), SlipVelocity(), LoadSensitivity(), Camber(), Pressure(),
            AeroLoad(), Bank(), VThermal(), VRelaxation(), VBank(), VAero(), Bias(), Scale(), Delay()]
