"""Temperature-dependent Magic Formula with a tire surface temperature state:
float64 reference and identification of its temperature coefficients.

Source: seed 000, chapter 4 (the extracted text lost minus signs and some
symbols; re-derived forms and every choice are in docs/mf89-thermal.md).

Thermal state (4.1)-(4.6):
    W dT/dt = q - lambda A (T - T_R),   kappa = lambda A / W
    dT/dt   = q / W - kappa (T - T_R)
    q  = F Vs,  F = sqrt(Fx^2 + Fy^2)
    Vs = sqrt((V cos(alpha) - re omega)^2 + V^2 sin^2(alpha))
       = V sqrt((S cos(alpha))^2 + sin^2(alpha))   with re omega = V cos(alpha) (1 - S)

Forces, pure slip with temperature (4.9)-(4.14), i = x (p = S + Shx) or
i = y (p = alpha + Shy):
    F_i0(p, T) = D_i(T) sin[C_i atan{B_i(T) p - E_i (B_i(T) p - atan(B_i(T) p))}] + Sv_i
    D_i(T) = D_i0 (1 + a_i (T - T0)),  K_i(T) = K_i0 (1 + b_i (T - T0))
    B_i(T) = K_i(T) / (C_i D_i(T))
Combined slip (4.15)-(4.18) with the cosine weighting functions (2.139)-(2.144):
    Fx = Fx0(S, T) G_xa(alpha),       Fy = Fy0(alpha, T) G_yS(S) + Sv_yS
    G_xa = cos[C_xa atan{B_xa a_s - E_xa (B_xa a_s - atan(B_xa a_s))}] / (same at a_s = Sh_xa),
           a_s = alpha + Sh_xa
    G_yS = cos[C_yS atan{B_yS S_s - E_yS (B_yS S_s - atan(B_yS S_s))}] / (same at S_s = Sh_yS),
           S_s = S + Sh_yS
Load: the seed identifies the chapter-4 coefficients at one load (4600 N);
D_i0, K_i0, Sv_x, Sv_y, Sv_yS are taken as proportional to Fz / Fz0 (our
choice; at Fz = Fz0 the model is exactly the seed's).

Sign conventions: the seed's S = (Vr - Vb) / Vr (positive braking) and Fx > 0
is the braking force for S > 0; Fy has the sign of alpha + Shy.

Time step (the C library's scheme, reproduced exactly here): forces and q
at the temperature at the start of the step; q held constant over dt, for
which the linear ODE has the exact solution
    T(t + dt) = T + phi (q / W - kappa (T - T_R)),  phi = (1 - exp(-kappa dt)) / kappa
(phi = dt for kappa = 0). The result is limited to [t_min, t_max].
"""
from dataclasses import dataclass, fields, replace

import numpy as np

DEG = np.pi / 180.0


@dataclass
class ThermalParams:
    """Coefficients (SI, temperatures in degC). The seed's identified values
    did not survive extraction (only the test load 4600 N and the axes of
    Figs. 4.7-4.12 did); these are plausible passenger-car values."""
    fz0: float = 4600.0     # N, load of the coefficients (seed: 4600 N)
    t0: float = 30.0        # degC, mean surface temperature of the force tests
    # longitudinal, pure slip
    dx0: float = 4800.0     # N
    kx0: float = 92000.0    # N per unit slip
    cx: float = 1.65
    ex: float = -0.2
    shx: float = 0.0005     # slip
    svx: float = 15.0       # N
    ax: float = -0.004      # 1/K
    bx: float = -0.006      # 1/K
    # lateral, pure slip
    dy0: float = 4500.0     # N
    ky0: float = 68000.0    # N/rad
    cy: float = 1.35
    ey: float = -0.6
    shy: float = 0.0015     # rad
    svy: float = 25.0       # N
    ay: float = -0.003      # 1/K
    by: float = -0.008      # 1/K
    # combined slip weighting
    bxa: float = 13.0       # 1/rad
    cxa: float = 1.0
    exa: float = -0.3
    shxa: float = 0.001     # rad
    bys: float = 9.0        # per unit slip
    cys: float = 1.0
    eys: float = -0.2
    shys: float = 0.002     # slip
    svys: float = 0.0       # N
    # thermal
    w: float = 1500.0       # J/K, heat capacity of the surface layer
    kappa: float = 0.08     # 1/s, lambda A / W
    # valid ranges (the C library clamps inputs to them)
    fz_max: float = 10000.0  # N
    alpha_max: float = 0.5   # rad
    slip_max: float = 1.0    # -
    v_max: float = 60.0      # m/s
    t_min: float = -30.0     # degC
    t_max: float = 130.0     # degC

    def as_dict(self):
        return {f.name: getattr(self, f.name) for f in fields(self)}


DEFAULT = ThermalParams()
# Field order of the parameter struct in include/grip/grip_mf_thermal.h.
PARAM_ORDER = [f.name for f in fields(ThermalParams)]


def mf_sin(d, b, c, e, p):
    """D sin[C atan{B p - E (B p - atan(B p))}]."""
    bp = b * p
    return d * np.sin(c * np.arctan(bp - e * (bp - np.arctan(bp))))


def mf_cos(b, c, e, p):
    """cos[C atan{B p - E (B p - atan(B p))}]."""
    bp = b * p
    return np.cos(c * np.arctan(bp - e * (bp - np.arctan(bp))))


def pure_force(d0, k0, c, e, sh, sv, a, b, p, t, t0):
    """F_i0(p, T) of (4.11)-(4.14) at the nominal load."""
    d = d0 * (1.0 + a * (t - t0))
    k = k0 * (1.0 + b * (t - t0))
    return mf_sin(d, k / (c * d), c, e, p + sh) + sv


def forces(prm, alpha, slip, fz, t):
    """Combined-slip forces (Fx, Fy) [N] at surface temperature t [degC];
    alpha [rad], slip S [-] (positive braking), fz [N]. Broadcasts."""
    alpha = np.asarray(alpha, dtype=float)
    slip = np.asarray(slip, dtype=float)
    t = np.asarray(t, dtype=float)
    fzn = np.asarray(fz, dtype=float) / prm.fz0
    fx0 = pure_force(prm.dx0, prm.kx0, prm.cx, prm.ex, prm.shx, prm.svx, prm.ax, prm.bx, slip, t, prm.t0)
    fy0 = pure_force(prm.dy0, prm.ky0, prm.cy, prm.ey, prm.shy, prm.svy, prm.ay, prm.by, alpha, t, prm.t0)
    gxa = mf_cos(prm.bxa, prm.cxa, prm.exa, alpha + prm.shxa) / mf_cos(prm.bxa, prm.cxa, prm.exa, prm.shxa)
    gys = mf_cos(prm.bys, prm.cys, prm.eys, slip + prm.shys) / mf_cos(prm.bys, prm.cys, prm.eys, prm.shys)
    fx = fzn * fx0 * gxa
    fy = fzn * (fy0 * gys + prm.svys)
    return fx, fy


def slip_speed(v, alpha, slip):
    """Vs of (4.4)-(4.5) with re omega = V cos(alpha) (1 - S)."""
    return np.asarray(v, dtype=float) * np.sqrt((slip * np.cos(alpha))**2 + np.sin(alpha)**2)


def heat_flux(prm, v, alpha, slip, fz, t):
    """(q [W], Vs [m/s], Fx, Fy) of (4.2)-(4.5) at temperature t."""
    fx, fy = forces(prm, alpha, slip, fz, t)
    vs = slip_speed(v, alpha, slip)
    return np.hypot(fx, fy) * vs, vs, fx, fy


def phi(kappa, dt):
    """(1 - exp(-kappa dt)) / kappa, = dt at kappa = 0."""
    x = kappa * dt
    if x == 0.0:
        return dt
    return -np.expm1(-x) / kappa


def step(prm, t, v, alpha, slip, fz, t_road, dt):
    """One step of the C library's scheme. Returns (fx, fy, q, vs, t_next)."""
    q, vs, fx, fy = heat_flux(prm, v, alpha, slip, fz, t)
    t_next = t + phi(prm.kappa, dt) * (q / prm.w - prm.kappa * (t - t_road))
    t_next = min(max(t_next, prm.t_min), prm.t_max)
    return fx, fy, q, vs, t_next


def simulate(prm, t_init, v, alpha, slip, fz, t_road, dt):
    """Run `step` over input sequences (arrays of equal length; scalars
    broadcast). Returns dict of arrays: t_before, fx, fy, q, vs, t_after."""
    n = max(np.size(x) for x in (v, alpha, slip, fz, t_road, dt))
    seq = [np.broadcast_to(np.asarray(x, dtype=float), (n,)) for x in (v, alpha, slip, fz, t_road, dt)]
    out = {k: np.zeros(n) for k in ("t_before", "fx", "fy", "q", "vs", "t_after")}
    t = float(t_init)
    for i in range(n):
        vi, ai, si, fi, ri, di = (float(s[i]) for s in seq)
        fx, fy, q, vs, tn = step(prm, t, vi, ai, si, fi, ri, di)
        out["t_before"][i] = t
        out["fx"][i], out["fy"][i], out["q"][i], out["vs"][i] = fx, fy, q, vs
        out["t_after"][i] = tn
        t = tn
    return out


def simulate_continuous(prm, t_init, time, v, alpha, slip, fz, t_road, rtol=1e-10):
    """The ODE (4.6) with forces at the current temperature, inputs linearly
    interpolated in time, solved with scipy's adaptive integrator; for
    measuring the discretization error of `simulate`. Returns T(time)."""
    from scipy.integrate import solve_ivp
    time = np.asarray(time, dtype=float)

    def interp(x, tt):
        return np.interp(tt, time, np.broadcast_to(np.asarray(x, dtype=float), time.shape))

    def rhs(tt, y):
        q, _, _, _ = heat_flux(prm, interp(v, tt), interp(alpha, tt), interp(slip, tt), interp(fz, tt), y[0])
        return [q / prm.w - prm.kappa * (y[0] - interp(t_road, tt))]

    sol = solve_ivp(rhs, (time[0], time[-1]), [t_init], t_eval=time, rtol=rtol, atol=1e-9, max_step=0.01)
    return sol.y[0]


# ---------------------------------------------------------------------------
# Identification of the temperature coefficients
# ---------------------------------------------------------------------------

def _trajectory(kappa, w, t_init, time, q, t_road):
    """T at the sample times for q, t_road held over each sample interval
    (exact solution of the linear ODE (4.6) between samples)."""
    out = np.empty(len(time))
    out[0] = t_init
    t = t_init
    for i in range(len(time) - 1):
        dt = time[i + 1] - time[i]
        t = t + phi(kappa, dt) * (q[i] / w - kappa * (t - t_road[i]))
        out[i + 1] = t
    return out


def identify_kappa_w(time, temp, q, t_road, kappa0=None, w0=None):
    """Identify kappa [1/s] and W [J/K] of (4.6) from a measured surface
    temperature trace temp(time) [degC] with heat input q [W] (from (4.2)-(4.5):
    measured forces and slip speeds) and road temperature t_road [degC].

    Step 1 (the seed's (4.7)-(4.8) as one regression): dT/dt = q / W - kappa (T - T_R)
    is linear in (1/W, kappa); least squares on central differences gives a
    start. Step 2: output-error fit with scipy least_squares of the simulated
    trajectory (T(0) free too), robust to noise on T, where differentiation is not.
    Returns dict(kappa, w, t_init, rms, start=(kappa, w)).
    """
    from scipy.optimize import least_squares
    time = np.asarray(time, dtype=float)
    temp = np.asarray(temp, dtype=float)
    q = np.broadcast_to(np.asarray(q, dtype=float), time.shape)
    t_road = np.broadcast_to(np.asarray(t_road, dtype=float), time.shape)
    if kappa0 is None or w0 is None:
        dtdt = np.gradient(temp, time)
        A = np.column_stack([q, -(temp - t_road)])
        sol, *_ = np.linalg.lstsq(A, dtdt, rcond=None)
        inv_w, k = sol
        if kappa0 is None:
            kappa0 = k if k > 0 else 0.05
        if w0 is None:
            w0 = 1.0 / inv_w if inv_w > 0 else 1000.0
    start = (float(kappa0), float(w0))

    def resid(x):
        return _trajectory(np.exp(x[0]), np.exp(x[1]), x[2], time, q, t_road) - temp

    r = least_squares(resid, [np.log(kappa0), np.log(w0), temp[0]], method="lm", xtol=1e-12, ftol=1e-12)
    return {"kappa": float(np.exp(r.x[0])), "w": float(np.exp(r.x[1])), "t_init": float(r.x[2]),
            "rms": float(np.sqrt(np.mean(r.fun**2))), "start": start}


def identify_temperature_coefficients(slip, temp, force, t0, c, e, sh=0.0, sv=0.0,
                                      d0=None, k0=None, fit_shape=False):
    """Identify D0, K0 and the temperature coefficients a, b of (4.13)-(4.14)
    from pure-slip force data at several temperatures (one direction, at the
    nominal load): force = D0 (1 + a (T - T0)) sin[C atan{B p - E (...)}] + Sv,
    B = K0 (1 + b (T - T0)) / (C D0 (1 + a (T - T0))), p = slip + sh.

    slip: S (or alpha [rad]); temp: surface temperature [degC] per sample;
    force [N]. c, e, sh, sv: the shape coefficients from the base identification
    (the seed keeps them temperature-independent); fit_shape=True fits C and E too.
    Returns dict(d0, k0, a, b[, c, e], rms, cost).
    """
    from scipy.optimize import least_squares
    slip = np.asarray(slip, dtype=float)
    temp = np.asarray(temp, dtype=float)
    force = np.asarray(force, dtype=float)
    if d0 is None:
        d0 = float(np.max(np.abs(force - sv)))
    if k0 is None:
        small = np.abs(slip + sh) < 0.25 * np.max(np.abs(slip + sh))
        k0 = float(np.sum((force[small] - sv) * (slip[small] + sh)) / np.sum((slip[small] + sh)**2))
        k0 = abs(k0) if k0 != 0 else 10.0 * d0
    x0 = [d0, k0, 0.0, 0.0] + ([c, e] if fit_shape else [])
    scale = [d0, k0, 1e-3, 1e-3] + ([1.0, 1.0] if fit_shape else [])

    def model(x):
        cc, ee = (x[4], x[5]) if fit_shape else (c, e)
        return pure_force(x[0], x[1], cc, ee, sh, sv, x[2], x[3], slip, temp, t0)

    # bounds keep the fit physical: D0, K0 > 0, |a|, |b| < 0.1 1/K, 0.3 < C < 2, E < 1
    lb = [1e-6 * d0, 1e-6 * k0, -0.1, -0.1] + ([0.3, -10.0] if fit_shape else [])
    ub = [100.0 * d0, 100.0 * k0, 0.1, 0.1] + ([2.0, 1.0] if fit_shape else [])
    if fit_shape:
        x0[4] = min(max(x0[4], 0.31), 1.99)
        x0[5] = min(max(x0[5], -9.9), 0.99)
    r = least_squares(lambda x: model(x) - force, x0, x_scale=scale, bounds=(lb, ub), method="trf",
                      xtol=1e-12, ftol=1e-12, gtol=1e-12)
    out = {"d0": float(r.x[0]), "k0": float(r.x[1]), "a": float(r.x[2]), "b": float(r.x[3]),
           "rms": float(np.sqrt(np.mean(r.fun**2))), "cost": float(r.cost)}
    if fit_shape:
        out["c"], out["e"] = float(r.x[4]), float(r.x[5])
    return out


def with_params(**kw):
    """DEFAULT with some fields replaced."""
    return replace(DEFAULT, **kw)
