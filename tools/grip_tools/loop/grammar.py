"""The candidate grammar: effects generated as (target x driver), not listed.

A grammar candidate changes one part of the tyre model, its *target*, by a
modulation m that is linear in fitted coefficients theta over the columns
of a *driver*:

    m_j(t) = sum_c theta_jc g_c(t)          (j: target column, c: driver column)

and the model is evaluated again with the change (the Magic Formula of
reference/mf.py through effects.TireModel; never a curve fitted to the
residual). Targets (TARGETS):

  Magic Formula scaling factors, lambda x (1 + m) (lambda >= 0.05):
    mu (LMUX, LMUY), mux, muy, k (LKX, LKY), kx, ky, grip (mu and k, two
    columns), c (LCX, LCY), e (LEX, LEY), trail (LTR), kyc (LKYC), comb
    (LXAL, LYKA: the combined-slip weighting)
  additive shifts: svy (Fy += m Fz), svx (Fx += m Fz), mres (Mz += m Fz R0)
  input channels: in:p (p + m NOMPRES), in:fz (Fz (1 + m)), in:alpha
    (alpha + m), in:kappa (kappa + m), in:gamma (gamma + m)
  input lag: lag:relax (alpha, kappa through a first-order relaxation of
    length sigma = m; sigma = 0 is the base model exactly)
  output (sensor) faults: out:scale (each output x (1 + m_o)), out:offset
    (each output + m_o), out:scale:<o>, out:offset:<o> (one output),
    out:delay (every output delayed by m seconds)

Drivers (DRIVERS): const; dfz, dfz2 (dfz, dfz^2), dfz = (Fz - FNOMIN) / FNOMIN;
gamma, gamma2; dpi, dpi2 (p - NOMPRES) / NOMPRES; vs, vs2 (slip speed /
LONGVL); v, v2 ((|vx| - LONGVL) / LONGVL); fx, fy (the base model's forces
/ FNOMIN); time ((t - t0) / 1000 s); and first-order states state:<source>
of a source u normalised by its training mean u_ref,

    x_0 = 0,  x_i = x_{i-1} + (1 - exp(-dt_i / tau)) (u_i / u_ref - x_{i-1}),
    tau = tau_heat when u_i / u_ref > x_{i-1} (heating), tau_rec otherwise,

or two of them (state2:<source>, tau1 < tau2: either node of a linear
two-node thermal model). Sources: energy (|F| Vs, the friction power, with
the measured forces where measured), slip (sqrt(kappa^2 + tan^2 alpha)),
load (Fz / FNOMIN) and run (1 while the tyre rolls loaded: |vx| > 1 m/s
and Fz > 0.1 FNOMIN). The time constants are fitted, at least TAU_MIN (a
faster state is its source: a static dependence, not a state).

Search (screen(), refine(); attribution._tyre_search drives them): every
applicable (target x driver) pair is first fitted linearly: the model's
sensitivity to each target column at m = 0 (one finite difference per
column over the whole record) times the driver columns, least squares on
the training rows, for states over a grid of time constants (TAU_GRID,
TAU_GRID2); the lags and the output delay are screened on their exact
prediction over a grid of lengths and delays. The best pairs by the
held-out criterion are then fitted with the full model (scipy
least_squares on at most FIT_ROWS training rows; states and lags run over
the whole record), starting from the linear estimate.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

V_MIN = 0.5                   # m/s: speed floor of the relaxation lag (lib/relax's v_min)
A_MAX = 16.0                  # |vx| dt / sigma beyond this is a full step (lib/relax)
TAU_GRID = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0)  # s: state time constants screened
TAU_GRID2 = (0.5, 2.0, 8.0, 32.0, 128.0, 512.0)  # s: the pairs (tau1 < tau2) screened for two-node states
TAU_MIN = TAU_GRID[0]         # s: the fastest state time constant (screened and fitted)
FIT_ROWS = 4000               # training rows the nonlinear fit uses at most (evenly strided)
SCREEN_ROWS = 20000           # rows the linear screening uses at most (every k-th row)
REFINE = 10                   # pairs refined with the full model
REFINE_PER = 3                # ... at most this many with one target, and with one driver (plus the
                              # constant change of every target among them)
LAMBDA_MIN = 0.05             # a modulated scaling factor is kept above this


# ---------------------------------------------------------------------------
# filters

def relax_series(x, vx, t, sigma, v_min=V_MIN):
    """First-order relaxation of x with length sigma [m], stepped as
    lib/relax steps it (exact for the input held over the step) with the
    CURRENT sample as the step's input:
        y_0 = x_0,  y_i = y_{i-1} + phi_i (x_i - y_{i-1}),
        phi_i = 1 - exp(-max(|vx_i|, v_min) dt_i / sigma)  (1 beyond A_MAX).
    sigma <= 0, and sigma -> 0, give x itself: the zero-lag limit is the
    base model, not a one-sample delay."""
    x = np.asarray(x, dtype=float)
    if sigma <= 0.0:
        return x.copy()
    v = np.maximum(np.abs(np.asarray(vx, dtype=float)), v_min)
    dt = np.diff(np.asarray(t, dtype=float), prepend=t[0])
    a = v * dt / sigma
    g = np.where(a >= A_MAX, 1.0, -np.expm1(-np.minimum(a, A_MAX))).tolist()
    xl = x.tolist()
    y = [0.0] * len(xl)
    s = xl[0]
    for i in range(len(xl)):
        s = xl[i] if g[i] >= 1.0 else s + g[i] * (xl[i] - s)    # a full step is the input itself
        y[i] = s
    return np.array(y)


def state_series(u, t, tau_heat, tau_rec):
    """First-order state of the source u (already normalised), starting at 0:
    x_i = x_{i-1} + (1 - exp(-dt_i / tau)) (u_i - x_{i-1}), tau = tau_heat
    while u_i > x_{i-1}, tau_rec otherwise."""
    dt = np.diff(np.asarray(t, dtype=float), prepend=t[0])
    u = np.asarray(u, dtype=float)
    if tau_heat == tau_rec and len(dt) > 2 and np.ptp(dt[1:]) <= 1e-9 * dt[1]:
        # one time constant, a constant step: the same recurrence as a filter
        from scipy.signal import lfilter
        g = -math.expm1(-dt[1] / max(tau_heat, 1e-6))
        v = u.copy()
        v[0] = 0.0                  # dt_0 = 0: x_0 = 0
        return lfilter([g], [1.0, g - 1.0], v)
    gh = (-np.expm1(-dt / max(tau_heat, 1e-6))).tolist()
    gr = (-np.expm1(-dt / max(tau_rec, 1e-6))).tolist()
    ul = np.asarray(u, dtype=float).tolist()
    y = [0.0] * len(ul)
    s = 0.0
    for i in range(len(ul)):
        d = ul[i] - s
        s += (gh[i] if d > 0.0 else gr[i]) * d
        y[i] = s
    return np.array(y)


def delay_series(y, t, d):
    """y delayed by d seconds (linear interpolation, held at the ends); d = 0 is y."""
    if d == 0.0:
        return np.asarray(y, dtype=float).copy()
    return np.interp(np.asarray(t) - d, t, y)


# ---------------------------------------------------------------------------
# evaluation context: one model, one data set, cached base prediction

class Context:
    """The base model on one data set: the base prediction, the driver
    sources, the normalisation of the states (u_ref, from the training rows
    or from an update being applied), and cached row subsets."""

    def __init__(self, model, ds, base=None, train=None, u_ref=None):
        self.model, self.ds = model, ds
        self.n = len(ds)
        self.t = np.asarray(ds.t, dtype=float)
        self.base = base if base is not None else model.predict(ds.ch)
        P = model.params
        self.fz0 = float(model.fnomin)
        self.nompres = float(model.nompres)
        self.longvl = float(P.get("longvl", 16.7) or 16.7)
        self.r0 = float(P.get("unloaded_radius", 0.3) or 0.3)
        self.mf6 = int(P.get("fittyp", 61)) in (61, 62)
        ch = ds.ch
        z = np.zeros(self.n)
        self.alpha = np.asarray(ch.get("alpha", z), dtype=float)
        self.kappa = np.asarray(ch.get("kappa", z), dtype=float)
        self.gamma = np.asarray(ch.get("gamma", z), dtype=float)
        self.fz = np.asarray(ch.get("fz", z), dtype=float)
        self.vx = np.asarray(ch.get("vx", z + 10.0), dtype=float)
        self.p = np.asarray(ch["p"], dtype=float) if "p" in ch else np.full(self.n, self.nompres)
        self.train = np.ones(self.n, bool) if train is None else train
        self._cols = {}
        self._states = {}
        self._sym = {}
        self.ones = np.ones(self.n)
        self._rows = {}
        self.sources = self._sources()
        if u_ref is None:
            u_ref = {}
            for k, u in self.sources.items():
                m = float(np.mean(u[self.train])) if np.any(self.train) else float(np.mean(u))
                u_ref[k] = m if m > 1e-12 else 1.0
        self.u_ref = dict(u_ref)

    def _sources(self):
        vs = np.abs(self.vx) * np.hypot(self.kappa, np.tan(self.alpha))
        # the friction power of the forces the tyre produced: measured where
        # measured, the base model's otherwise
        fo = {o: np.asarray(self.ds.ch[o], dtype=float) if o in self.ds.outputs and o in self.ds.ch
              else self.base.get(o, 0.0 * vs) for o in ("fx", "fy")}
        f = np.hypot(fo["fx"], fo["fy"])
        run = ((np.abs(self.vx) > 1.0) & (self.fz > 0.1 * self.fz0)).astype(float)
        return {"energy": f * vs, "slip": np.hypot(self.kappa, np.tan(self.alpha)),
                "load": self.fz / self.fz0, "run": run}

    def lag(self, source, tau):
        """the symmetric first-order state of a normalised source (cached)"""
        key = (source, float(tau))
        if key not in self._sym:
            if len(self._sym) >= 64:
                del self._sym[next(iter(self._sym))]
            self._sym[key] = state_series(self.sources[source] / self.u_ref[source], self.t, tau, tau)
        return self._sym[key]

    def ch_at(self, rows):
        if rows is None:
            return self.ds.ch
        key = id(rows)
        if key not in self._rows:
            self._rows[key] = (rows, {k: (v[rows] if isinstance(v, np.ndarray) and v.shape == (self.n,) else v)
                                      for k, v in self.ds.ch.items()})
        return self._rows[key][1]

    def base_at(self, rows, o):
        return self.base[o] if rows is None else self.base[o][rows]

    def at(self, a, rows):
        return a if rows is None else a[rows]


# ---------------------------------------------------------------------------
# targets

class Target:
    """grid(ctx): None (screened linearly), or the values of the single
    modulation at which the target is screened exactly."""
    name = "?"
    label = ""
    cols = ("m",)              # one modulation per column
    needs = ()                 # outputs of which at least one must be measured
    drivers = None             # allowed driver names (None: all)
    exact_linear = False       # the prediction is linear in m (no nonlinear refit of theta needed)
    onboard = ""

    def grid(self, ctx):
        return None

    def applicable(self, ctx):
        if self.needs and not any(o in ctx.ds.outputs for o in self.needs):
            return False, f"needs a measured {' or '.join(self.needs)}"
        return True, ""

    def predict(self, ctx, m, rows=None):
        raise NotImplementedError

    def jacobian(self, ctx):
        """per column: {output: d output / d m at m = 0} (whole record)."""
        h = 1e-4
        out = []
        for j in range(len(self.cols)):
            m = [np.zeros(ctx.n) for _ in self.cols]
            m[j] = m[j] + h
            up = self.predict(ctx, m)
            m[j] = m[j] - 2 * h
            dn = self.predict(ctx, m)
            out.append({o: (up[o] - dn[o]) / (2 * h) for o in ctx.ds.outputs})
        return out


class ScaleTarget(Target):
    """Magic Formula scaling factors: each column's lambdas x (1 + m)."""

    def __init__(self, name, groups, label, needs=(), requires=None):
        self.name, self.groups, self.label, self.needs = name, groups, label, needs
        self.cols = tuple(g[0] for g in groups)
        self.requires = requires
        self.onboard = ("lib/mf: " + ", ".join("/".join(k.upper() for k in g[1]) for g in groups)
                        + " x (1 + m), m from the driver (a constant driver is a .tir value)")

    def applicable(self, ctx):
        ok, why = Target.applicable(self, ctx)
        if ok and self.requires is not None:
            ok, why = self.requires(ctx)
        return ok, why

    def predict(self, ctx, m, rows=None):
        over = {}
        for (_, lams), mj in zip(self.groups, m):
            f = np.maximum(1.0 + mj, LAMBDA_MIN)
            for lam in lams:
                over[lam] = f
        return ctx.model.predict(ctx.ch_at(rows), over)


class CoefTarget(ScaleTarget):
    """Magic Formula coefficients x (1 + m) (through TireModel's "cmul"):
    the slip stiffnesses alone (PKY1, PKX1), without the trail and residual
    moment slopes that LKY also scales."""

    def __init__(self, name, groups, label, needs=(), requires=None):
        ScaleTarget.__init__(self, name, groups, label, needs, requires)
        self.onboard = ("lib/mf: " + ", ".join("/".join(k.upper() for k in g[1]) for g in groups)
                        + " x (1 + m) (a constant driver is a .tir value)")

    def predict(self, ctx, m, rows=None):
        cm = {}
        for (_, keys), mj in zip(self.groups, m):
            f = 1.0 + mj
            for k in keys:
                cm[k] = f
        return ctx.model.predict(ctx.ch_at(rows), {"cmul": cm})


class ShiftTarget(Target):
    """An additive shift of one output proportional to the load: y += m Fz w."""

    def __init__(self, name, output, label, arm=False):
        self.name, self.output, self.label, self.arm = name, output, label, arm
        self.needs = (output,)
        self.exact_linear = True
        self.onboard = f"caller-side: {output} + m Fz" + (" R0" if arm else "") + " (no single .tir value)"

    def predict(self, ctx, m, rows=None):
        out = {o: ctx.base_at(rows, o) for o in ctx.base}
        w = ctx.at(ctx.fz, rows) * (ctx.r0 if self.arm else 1.0)
        out[self.output] = out[self.output] + m[0] * w
        return out


class InputTarget(Target):
    """An input channel the tyre really ran differs from the recorded one."""

    def __init__(self, name, channel, label, requires=None):
        self.name, self.channel, self.label, self.requires = name, channel, label, requires
        self.onboard = f"the input {channel} as the tyre saw it (a sensor or rig correction, not a .tir value)"

    def applicable(self, ctx):
        if self.requires is not None:
            return self.requires(ctx)
        return True, ""

    def value(self, ctx, m, rows):
        c = self.channel
        if c == "p":
            return ctx.at(ctx.p, rows) + m * ctx.nompres
        if c == "fz":
            return ctx.at(ctx.fz, rows) * (1.0 + m)
        return ctx.at(getattr(ctx, c), rows) + m

    def predict(self, ctx, m, rows=None):
        return ctx.model.predict(ctx.ch_at(rows), {self.channel: self.value(ctx, m[0], rows)})


class LagTarget(Target):
    """alpha and kappa through a first-order relaxation of length sigma = m
    [m] (relax_series: sigma = 0 is the base model): one length for both
    (lag:relax), or sigma_alpha and sigma_kappa (lag:relax2, two columns)."""
    drivers = ("const",)
    onboard = "lib/relax (grip_relax.h): sigma_alpha, sigma_kappa, stepped with the current sample"

    def __init__(self, two=False):
        self.two = two
        self.name = "lag:relax2" if two else "lag:relax"
        self.cols = ("sigma_alpha", "sigma_kappa") if two else ("sigma",)
        self.label = ("slip angle and slip ratio through first-order relaxation lengths sigma_alpha, sigma_kappa"
                      if two else "slip (alpha, kappa) through a first-order relaxation length sigma")

    def applicable(self, ctx):
        if np.std(ctx.alpha) < 1e-5 and np.std(ctx.kappa) < 1e-5:
            return False, "slips constant"
        if self.two and (np.std(ctx.alpha) < 1e-5 or np.std(ctx.kappa) < 1e-5):
            return False, "alpha or kappa constant"
        return True, ""

    def grid(self, ctx):
        """screened on the exact lag (a first-order expansion in sigma fails
        for lags of several samples); lag:relax2 on lag:relax's grid with
        sigma_kappa = sigma_alpha / 2"""
        g = (0.03, 0.1, 0.2, 0.4, 0.8, 1.6, 3.2)
        return tuple((v, 0.5 * v) for v in g) if self.two else g

    def sigmas(self, m):
        sa = max(float(np.ravel(m[0])[0]), 0.0)
        sk = max(float(np.ravel(m[1])[0]), 0.0) if self.two else sa
        return sa, sk

    def predict(self, ctx, m, rows=None):
        sa, sk = self.sigmas(m)
        a = relax_series(ctx.alpha, ctx.vx, ctx.t, sa)
        k = relax_series(ctx.kappa, ctx.vx, ctx.t, sk)
        return ctx.model.predict(ctx.ch_at(rows), {"alpha": ctx.at(a, rows), "kappa": ctx.at(k, rows)})

    def jacobian(self, ctx):
        # first order in sigma of the continuous lag: x' ~ x - sigma / |vx| dx/dt
        h = 1e-5
        v = np.maximum(np.abs(ctx.vx), V_MIN)
        dt = np.maximum(np.diff(ctx.t, prepend=ctx.t[0] - (ctx.t[1] - ctx.t[0])), 1e-9)
        da = np.diff(ctx.alpha, prepend=ctx.alpha[0]) / dt
        dk = np.diff(ctx.kappa, prepend=ctx.kappa[0]) / dt
        ja = _input_fd(ctx, "alpha", h)
        jk = _input_fd(ctx, "kappa", h)
        if self.two:
            return [{o: -ja[o] * da / v for o in ctx.ds.outputs}, {o: -jk[o] * dk / v for o in ctx.ds.outputs}]
        return [{o: -(ja[o] * da + jk[o] * dk) / v for o in ctx.ds.outputs}]


def _input_fd(ctx, name, h):
    x = getattr(ctx, name)
    up = ctx.model.predict(ctx.ds.ch, {name: x + h})
    dn = ctx.model.predict(ctx.ds.ch, {name: x - h})
    return {o: (up[o] - dn[o]) / (2 * h) for o in ctx.ds.outputs}


class OutputTarget(Target):
    """A sensor fault on the measured outputs: scale (y (1 + m_o)) or offset
    (y + m_o [output unit]), on every output (one column each) or one."""

    def __init__(self, mode, output=None):
        self.mode, self.output = mode, output
        self.name = f"out:{mode}" + (f":{output}" if output else "")
        self.exact_linear = True
        what = "x (1 + m)" if mode == "scale" else "+ m"
        self.label = f"{'every measured output' if output is None else output} {what} (a sensor {mode})"
        self.onboard = ("lib/calib grip_calib_config_t." + ("gain = 1 / (1 + m)" if mode == "scale" else "offset")
                        + " (vehicle-level ESC inputs); at tyre level a correction of the measurement")

    def applicable(self, ctx):
        if self.output is not None and self.output not in ctx.ds.outputs:
            return False, f"{self.output} not measured"
        if self.output is None and len(ctx.ds.outputs) < 2:
            return False, "one output: the single-output form covers it"
        return True, ""

    def outs(self, ctx):
        return [self.output] if self.output else list(ctx.ds.outputs)

    @property
    def cols(self):
        return ("m",) if self.output else ("m_o",)

    def ncols(self, ctx):
        return len(self.outs(ctx))

    def predict(self, ctx, m, rows=None):
        out = {o: ctx.base_at(rows, o) for o in ctx.base}
        for mj, o in zip(m, self.outs(ctx)):
            out[o] = out[o] * (1.0 + mj) if self.mode == "scale" else out[o] + mj
        return out

    def jacobian(self, ctx):
        res = []
        for o in self.outs(ctx):
            j = {q: np.zeros(ctx.n) for q in ctx.ds.outputs}
            j[o] = ctx.base[o].copy() if self.mode == "scale" else np.ones(ctx.n)
            res.append(j)
        return res


class DelayTarget(Target):
    name = "out:delay"
    label = "every measured output delayed by d = m seconds"
    drivers = ("const",)
    exact_linear = False
    onboard = "lib/calib grip_calib_config_t.delay (whole steps, <= 32; vehicle level)"

    def grid(self, ctx):
        dt = float(np.median(np.diff(ctx.t))) if ctx.n > 1 else 0.01
        ks = [1, 2, 4, 8, 16, 32, 64]
        return tuple(sorted(sg * k * dt for k in ks for sg in (-1, 1) if k * dt <= 0.5))

    def predict(self, ctx, m, rows=None):
        d = float(np.ravel(m[0])[0])
        out = {}
        for o in ctx.base:
            y = delay_series(ctx.base[o], ctx.t, d)
            out[o] = ctx.at(y, rows)
        return out

    def jacobian(self, ctx):
        return [{o: -np.gradient(ctx.base[o], ctx.t) for o in ctx.ds.outputs}]


def _mf6(ctx):
    return (ctx.mf6, "no pressure terms in MF 5.2")


def _kappa_fx(ctx):
    return ("fx" in ctx.ds.outputs and float(np.std(ctx.kappa)) > 1e-4, "no fx or kappa constant")


def _lat(ctx):
    return (any(o in ctx.ds.outputs for o in ("fy", "mz")), "no fy or mz")


def _combined(ctx):
    return (_kappa_fx(ctx)[0] and _lat(ctx)[0] and float(np.std(ctx.alpha)) > 1e-4,
            "needs fx with kappa varying and fy or mz with alpha varying")


def _gamma_varies(ctx):
    return (float(np.std(ctx.gamma)) > 1e-4 and any(o in ctx.ds.outputs for o in ("fy", "mz")),
            "gamma constant or no fy/mz")


def targets():
    mu = ("mu", ("lmux", "lmuy"))
    k = ("k", ("lkx", "lky"))
    return [
        ScaleTarget("mu", [mu], "friction LMUX, LMUY"),
        ScaleTarget("mux", [("mux", ("lmux",))], "longitudinal friction LMUX", requires=_kappa_fx),
        ScaleTarget("muy", [("muy", ("lmuy",))], "lateral friction LMUY", requires=_lat),
        ScaleTarget("k", [k], "slip stiffness LKX, LKY"),
        ScaleTarget("kx", [("kx", ("lkx",))], "longitudinal slip stiffness LKX", requires=_kappa_fx),
        ScaleTarget("ky", [("ky", ("lky",))], "cornering stiffness LKY", requires=_lat),
        ScaleTarget("grip", [mu, k], "friction LMUX, LMUY and slip stiffness LKX, LKY (two columns)"),
        ScaleTarget("mu2", [("mux", ("lmux",)), ("muy", ("lmuy",))], "friction LMUX and LMUY (two columns)",
                    requires=_kappa_fx),
        ScaleTarget("k2", [("kx", ("lkx",)), ("ky", ("lky",))], "slip stiffness LKX and LKY (two columns)",
                    requires=_kappa_fx),
        CoefTarget("kya", [("kya", ("pky1",))], "cornering stiffness PKY1 (not the trail slopes)", requires=_lat),
        CoefTarget("kxk", [("kxk", ("pkx1",))], "longitudinal slip stiffness PKX1", requires=_kappa_fx),
        CoefTarget("kc", [("kc", ("pkx1", "pky1"))], "slip stiffnesses PKX1, PKY1"),
        CoefTarget("kc2", [("kxk", ("pkx1",)), ("kya", ("pky1",))], "slip stiffnesses PKX1 and PKY1 (two columns)",
                   requires=_kappa_fx),
        ScaleTarget("c", [("c", ("lcx", "lcy"))], "shape factors LCX, LCY"),
        ScaleTarget("e", [("e", ("lex", "ley"))], "curvature factors LEX, LEY"),
        ScaleTarget("trail", [("trail", ("ltr",))], "pneumatic trail LTR", needs=("mz",)),
        ScaleTarget("kyc", [("kyc", ("lkyc",))], "camber stiffness LKYC", requires=_gamma_varies),
        ScaleTarget("comb", [("comb", ("lxal", "lyka"))],
                    "combined-slip weighting LXAL, LYKA (how fast one slip takes the other force away)",
                    requires=_combined),
        ShiftTarget("svy", "fy", "lateral force shift Fy + m Fz (vertical shift, ply steer / conicity)"),
        ShiftTarget("svx", "fx", "longitudinal force shift Fx + m Fz (vertical shift)"),
        ShiftTarget("mres", "mz", "residual moment Mz + m Fz R0", arm=True),
        InputTarget("in:p", "p", "inflation pressure p + m NOMPRES (the pressure the tyre ran)", requires=_mf6),
        InputTarget("in:fz", "fz", "load Fz (1 + m)"),
        InputTarget("in:alpha", "alpha", "slip angle alpha + m [rad]", requires=_lat),
        InputTarget("in:kappa", "kappa", "slip ratio kappa + m", requires=_kappa_fx),
        InputTarget("in:gamma", "gamma", "camber gamma + m [rad]", requires=_lat),
        LagTarget(), LagTarget(two=True),
        OutputTarget("scale"), OutputTarget("offset"),
        OutputTarget("scale", "fx"), OutputTarget("scale", "fy"), OutputTarget("scale", "mz"),
        OutputTarget("offset", "fx"), OutputTarget("offset", "fy"), OutputTarget("offset", "mz"),
        DelayTarget(),
    ]


# ---------------------------------------------------------------------------
# drivers

class Driver:
    name = "?"
    label = ""
    cols = ("1",)
    pnames = ()

    def applicable(self, ctx):
        return True, ""

    def columns(self, ctx, p=()):
        raise NotImplementedError

    def grid(self, ctx):
        return [()]

    def to_fit(self, p):
        return list(p)

    def from_fit(self, z):
        return tuple(float(v) for v in z)

    def fit_bounds(self, ctx):
        return [], []


class SimpleDriver(Driver):
    def __init__(self, name, cols, fn, label, requires=None):
        self.name, self.cols, self.fn, self.label, self.requires = name, cols, fn, label, requires

    def applicable(self, ctx):
        if self.requires is not None:
            return self.requires(ctx)
        return True, ""

    def columns(self, ctx, p=()):
        key = (self.name,)
        if key not in ctx._cols:
            ctx._cols[key] = self.fn(ctx)
        return ctx._cols[key]


class StateDriver(Driver):
    """A first-order state of a source with heating / recovery time
    constants, with an offset: m = th0 + th1 x."""
    cols = ("1", "x")
    pnames = ("tau_heat_s", "tau_rec_s")

    def __init__(self, source, label):
        self.source, self.name, self.label = source, f"state:{source}", label

    def applicable(self, ctx):
        u = ctx.sources[self.source]
        return (float(np.std(u)) > 1e-9 * max(1.0, float(np.mean(np.abs(u)))) or self.source == "run",
                f"source {self.source} constant")

    def columns(self, ctx, p):
        th, tr = float(p[0]), float(p[1])
        if th == tr:
            return [ctx.ones, ctx.lag(self.source, th)]
        key = (self.name, th, tr)
        if key not in ctx._states:
            if len(ctx._states) >= 32:               # a small FIFO: the fit asks for new taus each step
                del ctx._states[next(iter(ctx._states))]
            u = ctx.sources[self.source] / ctx.u_ref[self.source]
            ctx._states[key] = [ctx.ones, state_series(u, ctx.t, th, tr)]
        return ctx._states[key]

    def tau_max(self, ctx):
        return max(5.0 * (ctx.t[-1] - ctx.t[0]), 10.0)

    def grid(self, ctx):
        dur = ctx.t[-1] - ctx.t[0]
        dt = float(np.median(np.diff(ctx.t))) if ctx.n > 1 else 1.0
        return [(tau, tau) for tau in TAU_GRID if 2 * dt <= tau <= 2.0 * dur]

    def to_fit(self, p):
        return [math.log(p[0]), math.log(p[1])]

    def from_fit(self, z):
        return (math.exp(z[0]), math.exp(z[1]))

    def fit_bounds(self, ctx):
        # a state is at least as slow as the screening grid's fastest (and 2
        # samples): a time constant going to 0 turns the state into its
        # source, a static dependence on load, slip or friction power that
        # is not a state (and that the static drivers cover)
        dt = float(np.median(np.diff(ctx.t))) if ctx.n > 1 else 0.01
        lo, hi = math.log(max(2.0 * dt, TAU_MIN)), math.log(self.tau_max(ctx))
        return [lo, lo], [hi, hi]


class TwoNodeDriver(StateDriver):
    """Two first-order states of the same source with time constants tau1 <
    tau2, both columns of the modulation (with an offset): m = th0 + th1 x1
    + th2 x2. The temperature of either node of a linear two-node thermal
    model (surface and carcass, or carcass and inflation gas) driven by the
    source is such a sum (its transfer function's partial fractions)."""
    cols = ("1", "x1", "x2")
    pnames = ("tau1_s", "tau2_s")

    def __init__(self, source, label):
        StateDriver.__init__(self, source, label)
        self.name = f"state2:{source}"

    def columns(self, ctx, p):
        return [ctx.ones, ctx.lag(self.source, float(p[0])), ctx.lag(self.source, float(p[1]))]

    def grid(self, ctx):
        g = [a for a, _ in StateDriver.grid(self, ctx) if a in TAU_GRID2]
        return [(a, b) for a in g for b in g if b > a]


def _has_fx(ctx):
    return (float(np.std(ctx.base["fx"])) > 1e-6 * ctx.fz0, "the model's Fx constant")


def _has_fy(ctx):
    return (float(np.std(ctx.base["fy"])) > 1e-6 * ctx.fz0, "the model's Fy constant")


def _dfz(ctx):
    return (ctx.fz - ctx.fz0) / ctx.fz0


def _dpi(ctx):
    return (ctx.p - ctx.nompres) / ctx.nompres


def _vs(ctx):
    return ctx.sources["slip"] * np.abs(ctx.vx) / ctx.longvl


def _dv(ctx):
    return (np.abs(ctx.vx) - ctx.longvl) / ctx.longvl


def drivers():
    var = lambda name, tol: (lambda ctx: (bool(np.std(getattr(ctx, name)) > tol), f"{name} constant"))  # noqa: E731
    return [
        SimpleDriver("const", ("1",), lambda c: [c.ones], "a constant change"),
        SimpleDriver("dfz", ("dfz",), lambda c: [_dfz(c)], "load dfz = (Fz - FNOMIN) / FNOMIN",
                     var("fz", 1.0)),
        SimpleDriver("dfz2", ("1", "dfz", "dfz^2"), lambda c: [c.ones, _dfz(c), _dfz(c) ** 2],
                     "load, a quadratic in dfz", var("fz", 1.0)),
        SimpleDriver("gamma", ("gamma",), lambda c: [c.gamma], "camber [rad]", var("gamma", 1e-4)),
        SimpleDriver("gamma2", ("1", "gamma", "gamma^2"), lambda c: [c.ones, c.gamma, c.gamma ** 2],
                     "camber, a quadratic", var("gamma", 1e-4)),
        SimpleDriver("dpi", ("dpi",), lambda c: [_dpi(c)], "inflation pressure dpi = (p - NOMPRES) / NOMPRES",
                     var("p", 100.0)),
        SimpleDriver("dpi2", ("1", "dpi", "dpi^2"), lambda c: [c.ones, _dpi(c), _dpi(c) ** 2],
                     "pressure, a quadratic", var("p", 100.0)),
        SimpleDriver("vs", ("vs",), lambda c: [_vs(c)], "slip speed Vs / LONGVL"),
        SimpleDriver("vs2", ("1", "vs", "vs^2"), lambda c: [c.ones, _vs(c), _vs(c) ** 2],
                     "slip speed, a quadratic"),
        SimpleDriver("v", ("dv",), lambda c: [_dv(c)], "speed (|vx| - LONGVL) / LONGVL", var("vx", 0.3)),
        SimpleDriver("v2", ("1", "dv", "dv^2"), lambda c: [c.ones, _dv(c), _dv(c) ** 2], "speed, a quadratic",
                     var("vx", 0.3)),
        SimpleDriver("fx", ("fx",), lambda c: [c.base["fx"] / c.fz0],
                     "the base model's Fx / FNOMIN (compliance, cross-talk)", _has_fx),
        SimpleDriver("fy", ("fy",), lambda c: [c.base["fy"] / c.fz0],
                     "the base model's Fy / FNOMIN (compliance, cross-talk)", _has_fy),
        SimpleDriver("time", ("1", "t_ks"), lambda c: [c.ones, (c.t - c.t[0]) / 1000.0],
                     "time since the record's start [ks], with an offset"),
        StateDriver("energy", "first-order state of the friction power |F| Vs (heating / recovery)"),
        StateDriver("slip", "first-order state of the combined slip sqrt(kappa^2 + tan^2 alpha)"),
        StateDriver("load", "first-order state of the load Fz / FNOMIN"),
        StateDriver("run", "first-order state of running (1 while rolling loaded, 0 at rest)"),
        TwoNodeDriver("energy", "two first-order states (fast, slow) of the friction power |F| Vs"),
        TwoNodeDriver("slip", "two first-order states (fast, slow) of the combined slip"),
        TwoNodeDriver("load", "two first-order states (fast, slow) of the load"),
        TwoNodeDriver("run", "two first-order states (fast, slow) of running"),
    ]


TARGETS = {t.name: t for t in targets()}
DRIVERS = {d.name: d for d in drivers()}

# grammar instances that are one of the named effects, exactly (name, parameter names)
ALIASES = {("mu", "dfz"): ("load_sensitivity", ("c_dfz",)),
           ("lag:relax2", "const"): ("relaxation2", ("sigma_alpha_m", "sigma_kappa_m")),
           ("lag:relax", "const"): ("relaxation", ("sigma_m",)),
           ("out:delay", "const"): ("sensor_delay", ("delay_s",))}


# ---------------------------------------------------------------------------
# a grammar candidate

@dataclass
class Spec:
    target: Target
    driver: Driver

    @property
    def family(self):
        return (self.target.name, self.driver.name)

    @property
    def name(self):
        a = ALIASES.get(self.family)
        if a:
            return a[0]
        if isinstance(self.target, OutputTarget) and self.target.output is None and self.driver.name == "const":
            return "sensor_bias" if self.target.mode == "offset" else "sensor_scale"
        return f"{self.target.name}~{self.driver.name}"

    def tcols(self, ctx):
        if isinstance(self.target, OutputTarget):
            return [f"{self.target.mode}_{o}" for o in self.target.outs(ctx)]
        return list(self.target.cols)

    def n_theta(self, ctx):
        return len(self.tcols(ctx)) * len(self.driver.cols)

    def k(self, ctx):
        return self.n_theta(ctx) + len(self.driver.pnames)

    def pnames(self, ctx):
        a = ALIASES.get(self.family)
        if a:
            return list(a[1])
        if isinstance(self.target, OutputTarget) and self.target.output is None and self.driver.name == "const":
            return [f"{self.name}_{o}" for o in self.target.outs(ctx)]
        th = [f"{tc}*{dc}" if dc != "1" else tc for tc in self.tcols(ctx) for dc in self.driver.cols]
        return th + list(self.driver.pnames)

    def description(self):
        if self.driver.name == "const":
            return self.target.label
        return f"{self.target.label}, modulated by {self.driver.label}"

    def predict(self, ctx, x, rows=None):
        x = np.asarray(x, dtype=float)
        nt = len(self.tcols(ctx))
        nd = len(self.driver.cols)
        th = x[:nt * nd].reshape(nt, nd)
        g = self.driver.columns(ctx, tuple(x[nt * nd:]))
        if rows is not None:
            g = [gi[rows] for gi in g]
        m = [sum(th[j, c] * g[c] for c in range(nd)) for j in range(nt)]
        m = [mj if np.ndim(mj) else np.full(ctx.n if rows is None else len(rows), float(mj)) for mj in m]
        return self.target.predict(ctx, m, rows)


def spec(name_or_family):
    """The Spec of 'target~driver' (or an alias name with its family)."""
    if isinstance(name_or_family, tuple):
        tn, dn = name_or_family
    else:
        tn, _, dn = name_or_family.partition("~")
    return Spec(TARGETS[tn], DRIVERS[dn])


def pairs(ctx, skipped=None):
    """Every applicable (target, driver) pair."""
    out = []
    dok = {}
    for d in DRIVERS.values():
        ok, why = d.applicable(ctx)
        dok[d.name] = ok
        if not ok and skipped is not None:
            skipped.append((f"*~{d.name}", why))
    for t in TARGETS.values():
        ok, why = t.applicable(ctx)
        if not ok:
            if skipped is not None:
                skipped.append((f"{t.name}~*", why))
            continue
        for d in DRIVERS.values():
            if not dok[d.name] or (t.drivers is not None and d.name not in t.drivers):
                continue
            out.append(Spec(t, d))
    return out


# ---------------------------------------------------------------------------
# the search

@dataclass
class Screened:
    spec: Spec
    theta: np.ndarray
    p: tuple              # driver parameters (physical)
    s_test: float         # normalised held-out residual sum of squares (linear model)
    s_train: float
    k: int


def _norm_resid(ctx, scale):
    return {o: (ctx.ds.ch[o] - ctx.base[o]) / scale[o] for o in ctx.ds.outputs}


class _ColumnLibrary:
    """Every distinct driver column of the screening grid once, as rows of
    Gtr (training rows) and Gte (held-out rows); columns(driver, p) gives
    a pair's row indices (the offset column and a state of one time
    constant are shared by all drivers and grid points that use them)."""

    def __init__(self, ctx, specs, train, test):
        self.keys = {}
        self.map = {}
        arrays = []
        seen = set()
        for s in specs:
            d = s.driver
            if s.target.grid(ctx) is not None or d.name in seen:
                continue
            seen.add(d.name)
            for p in d.grid(ctx):
                idx = []
                for col in d.columns(ctx, p):
                    k = id(col)
                    if k not in self.keys:
                        self.keys[k] = len(arrays)
                        arrays.append(col)
                    idx.append(self.keys[k])
                self.map[(d.name, tuple(p))] = idx
        self.arrays = arrays                     # keeps the columns alive (their ids are the keys)
        A = np.array(arrays) if arrays else np.zeros((0, ctx.n))
        self.Gtr = A[:, train]
        self.Gte = A[:, test]

    def columns(self, driver, p):
        return self.map[(driver.name, tuple(p))]


def screen(ctx, specs, train, test, scale, progress=None):
    """The linear fit of every pair: returns Screened rows (best time
    constant of the grid for states), unsorted. Records longer than
    SCREEN_ROWS are screened on every k-th row (states, lags and model
    sensitivities still come from the whole record)."""
    outs = ctx.ds.outputs
    if ctx.n > SCREEN_ROWS:
        keep = np.zeros(ctx.n, bool)
        keep[::int(math.ceil(ctx.n / SCREEN_ROWS))] = True
        train, test = train & keep, test & keep
    r = _norm_resid(ctx, scale)
    rr_tr = sum(float(np.dot(r[o][train], r[o][train])) for o in outs)
    rr_te = sum(float(np.dot(r[o][test], r[o][test])) for o in outs)
    by_target = {}
    for s in specs:
        by_target.setdefault(s.target.name, []).append(s)
    rows = []
    lib = _ColumnLibrary(ctx, specs, train, test)
    for ti, (tname, specs_t) in enumerate(by_target.items()):
        if progress is not None:
            progress(tname)
        tgt = specs_t[0].target
        grid = tgt.grid(ctx)
        if grid is not None:                 # exact screening of a one-value target (const driver)
            for s in specs_t:
                best = None
                for v in grid:
                    v = np.atleast_1d(np.asarray(v, dtype=float))
                    pr = s.predict(ctx, v)
                    e = {o: (ctx.ds.ch[o] - pr[o]) / scale[o] for o in outs}
                    s_tr = sum(float(np.dot(e[o][train], e[o][train])) for o in outs)
                    s_te = sum(float(np.dot(e[o][test], e[o][test])) for o in outs)
                    if best is None or s_tr < best.s_train:
                        best = Screened(s, v, (), s_te, s_tr, s.k(ctx))
                rows.append(best)
            continue
        J = tgt.jacobian(ctx)
        nj = len(J)
        # W[j][j'] = sum_o Jn_j Jn_j', R[j] = sum_o Jn_j r_o  (per row)
        Jn = [{o: J[j][o] / scale[o] for o in outs} for j in range(nj)]
        W = [[sum(Jn[a][o] * Jn[b][o] for o in outs) for b in range(nj)] for a in range(nj)]
        R = [sum(Jn[a][o] * r[o] for o in outs) for a in range(nj)]
        # Gram matrices of every driver column of this target's pairs, for all
        # (a, a2) at once: M[a][a2][c, c2] = sum_rows W_aa2 g_c g_c2
        need = {}
        for s in specs_t:
            for p in s.driver.grid(ctx):
                for col in lib.columns(s.driver, p):
                    need[col] = True
        cols = sorted(need)
        pos = {c: k for k, c in enumerate(cols)}
        Gtr, Gte = lib.Gtr[cols], lib.Gte[cols]
        M, Mt, bv, bvt = {}, {}, [], []
        for a in range(nj):
            bv.append(Gtr @ R[a][train])
            bvt.append(Gte @ R[a][test])
            for a2 in range(a, nj):
                w = W[a][a2]
                if not np.any(w):
                    M[a, a2] = M[a2, a] = np.zeros((len(cols), len(cols)))
                    Mt[a, a2] = Mt[a2, a] = M[a, a2]
                    continue
                M[a, a2] = (Gtr * w[train]) @ Gtr.T
                Mt[a, a2] = (Gte * w[test]) @ Gte.T
                M[a2, a], Mt[a2, a] = M[a, a2].T, Mt[a, a2].T
        for s in specs_t:
            best = None
            for p in s.driver.grid(ctx):
                ci = [pos[c] for c in lib.columns(s.driver, p)]
                nd = len(ci)
                q = nj * nd
                A = np.empty((q, q))
                B = np.empty((q, q))
                b = np.empty(q)
                bt = np.empty(q)
                for a in range(nj):
                    b[a * nd:(a + 1) * nd] = bv[a][ci]
                    bt[a * nd:(a + 1) * nd] = bvt[a][ci]
                    for a2 in range(nj):
                        A[a * nd:(a + 1) * nd, a2 * nd:(a2 + 1) * nd] = M[a, a2][np.ix_(ci, ci)]
                        B[a * nd:(a + 1) * nd, a2 * nd:(a2 + 1) * nd] = Mt[a, a2][np.ix_(ci, ci)]
                reg = 1e-9 * (abs(np.trace(A)) / q + 1e-30)
                try:
                    th = np.linalg.solve(A + reg * np.eye(q), b)
                except np.linalg.LinAlgError:
                    continue
                s_tr = rr_tr - 2 * th @ b + th @ A @ th
                s_te = rr_te - 2 * th @ bt + th @ B @ th
                if best is None or s_tr < best.s_train:
                    best = Screened(s, th, tuple(p), float(max(s_te, 0.0)), float(s_tr), s.k(ctx))
            if best is not None:
                rows.append(best)
    return rows, rr_te


def fit_rows(train, limit=FIT_ROWS):
    idx = np.flatnonzero(train)
    if len(idx) > limit:
        idx = idx[np.linspace(0, len(idx) - 1, limit).round().astype(int)]
    return idx


def refine(ctx, sc, train, scale, x0=None, max_nfev=30):
    """Full-model least squares of one screened pair on (a stride of) the
    training rows, from the linear estimate; returns the physical x."""
    s = sc.spec
    outs = ctx.ds.outputs
    rows = fit_rows(train)
    y = {o: ctx.ds.ch[o][rows] for o in outs}
    nth = s.n_theta(ctx)
    if x0 is None:
        x0 = np.concatenate([sc.theta, np.asarray(sc.p, dtype=float)])
    th0 = np.asarray(x0[:nth], dtype=float)
    p0 = tuple(x0[nth:])
    if isinstance(s.target, LagTarget):
        th0 = np.maximum(th0, 0.02)
    zp0 = s.driver.to_fit(p0)
    lo_p, hi_p = s.driver.fit_bounds(ctx)
    zp0 = [min(max(v, lo + 1e-9), hi - 1e-9) for v, lo, hi in zip(zp0, lo_p, hi_p)]
    if isinstance(s.target, LagTarget):
        lo_t, hi_t = [0.0] * nth, [5.0] * nth
    elif isinstance(s.target, DelayTarget):
        lo_t, hi_t = [-0.5], [0.5]
    else:
        lo_t, hi_t = [-np.inf] * nth, [np.inf] * nth
    th0 = np.clip(th0, np.asarray(lo_t) + 1e-12, np.asarray(hi_t) - 1e-12)
    if s.target.exact_linear and not s.driver.pnames:
        return np.asarray(th0, dtype=float)     # the linear fit is the fit

    def unpack(z):
        return np.concatenate([z[:nth], np.asarray(s.driver.from_fit(z[nth:]), dtype=float)])

    def resid(z):
        pr = s.predict(ctx, unpack(z), rows)
        return np.concatenate([(y[o] - pr[o]) / scale[o] for o in outs])
    z0 = np.concatenate([th0, zp0])
    try:
        r = least_squares(resid, z0, bounds=(lo_t + lo_p, hi_t + hi_p), x_scale="jac", max_nfev=max_nfev)
        z = r.x
    except ValueError:
        z = z0
    return unpack(z)


def refit(model, ds, base, specs, train, scale):
    """Predictions of the given pairs fitted (screened, then refined) on
    another split's training rows (the states' u_ref from those rows)."""
    ctx = Context(model, ds, base, train)
    test = ~train if (~train).any() else train
    rows, _ = screen(ctx, specs, train, test, scale)
    by = {sc.spec.name: sc for sc in rows}
    out = []
    for sp in specs:
        sc = by.get(sp.name)
        out.append(sp.predict(ctx, refine(ctx, sc, train, scale)) if sc is not None else dict(base))
    return out


class GrammarEffect:
    """A grammar candidate behind the interface of effects.Effect (fit,
    predict, applicable), for the second hold-out split and `grip analyze
    apply`. u_ref: the states' source normalisation the parameters belong
    to (set by fit; read from update.json when applying)."""

    def __init__(self, sp, u_ref=None):
        self.spec = sp
        self.u_ref = dict(u_ref) if u_ref else None
        self.name = sp.name
        self.level = "any" if isinstance(sp.target, (OutputTarget, DelayTarget)) else "tire"
        self.families = (sp.family,)
        self.onboard = onboard_text(sp)

    def context(self, model, ds, train=None):
        return Context(model, ds, train=train, u_ref=self.u_ref)

    def applicable(self, ds, model=None):
        return True, ""

    def predict(self, model, ds, x):
        return self.spec.predict(self.context(model, ds), x)

    def fit(self, model, ds, mask, scale, x0=None):
        ctx = Context(model, ds, train=mask)
        self.u_ref = dict(ctx.u_ref)
        rows, _ = screen(ctx, [self.spec], mask, ~mask if (~mask).any() else mask, scale)
        if not rows:
            return np.asarray(x0, dtype=float) if x0 is not None else np.zeros(self.spec.k(ctx))
        return refine(ctx, rows[0], mask, scale)


def onboard_text(sp):
    d = sp.driver
    if d.name == "const":
        how = "constant"
    elif isinstance(d, StateDriver):
        how = (f"the caller runs the first-order state of {d.source} (tau_heat, tau_rec, u_ref from update.json) "
               "and sets the modulation every step")
    else:
        how = f"the caller computes m from {d.label} every step"
    return f"{sp.target.onboard}; m: {how}"
