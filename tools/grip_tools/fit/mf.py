"""fit-mf: identify Magic Formula coefficients from measured sweeps.

Models (--model):
  mf89  the 1989-style lateral Magic Formula a0..a17 of seed 000, eqs.
        (3.1)-(3.9), with the seed's identification constraints (3.10)-(3.16)
        (the model and the constraints are grip_tools.reference.mf89's; nothing is
        repeated here)
  fy    MF 5.2 / 6.1 pure lateral force group (PCY1, PDY*, PEY*, PKY*, PHY*,
        PVY*, PPY*) with the same constraints carried over (below)
  fx    MF 5.2 / 6.1 pure longitudinal force group (PCX1, PDX*, PEX*, PKX*,
        PHX*, PVX*, PPX*)
  mz    MF 5.2 / 6.1 pure aligning moment group (QBZ*, QCZ1, QDZ*, QEZ*,
        QHZ*, PPZ*); needs the Fy group (from --tir) because Mz0 uses Fy0
The MF groups use grip_tools.reference.mf (the float64 reference model of the library)
as the model function, so a fitted set means in the C library what it means
here.

Data: CSV with a header; columns kappa, alpha, gamma [rad], fz [N] (p [Pa],
vx [m/s] optional) and the measured fx, fy or mz [N, N m]; ISO-W signs for
the MF groups (the seed's own signs for mf89: Fy has the sign of alpha).
Missing kappa, alpha, gamma columns are taken as 0.

Seed constraints (--constraints seed, the default), chapter 3:
  (3.10) 1.0 < C < 1.65          mf89: a0;  fy: PCY1 (LCY = 1)
  (3.11) E < 1                   a penalty on E at every corner of the
                                 data's load/camber range, both signs of slip
  (3.12) a17 = 0                 fy: PEY3 = 0 (the same asymmetry term)
  (3.13) Sh = Sv = 0 at gamma=0  fy: PHY1 = PHY2 = PVY1 = PVY2 = 0
  (3.14) |dSh/dgamma| <= 0.1     mf89 only (a10 bound)
  (3.15) |dSv/dgamma| < 25 Fz    mf89 only (linear inequality)
  (3.16) a15 > 0                 fy: PDY3 >= 0 (peak falls with camber)
fx and mz: E < 1 only. --constraints none: plain bounded least squares.

Solvers (--method): trf = scipy.optimize.least_squares trust-region
reflective with the bounds; lm = Levenberg-Marquardt (the seed's Fig. 3.10
flow) with the bounds mapped by a smooth change of variables. The
inequality constraints enter both as penalty residuals.

Outputs: the fit error (RMS and max, absolute and relative to the largest
measured value), the constraint report, --json (coefficients and figures),
--tir-out (a .tir fragment for the MF groups), --plot (PNG, measured vs
fitted per load and camber). --synthetic writes sweep data from known
coefficients (with noise) for trials and tests.
"""
import argparse
import csv
import json
import math
import os
import sys
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from grip_tools.channels import CHANNELS, read_table
from grip_tools.errors import DataError
from grip_tools.reference import mf89

DEG = math.pi / 180.0

# ---------------------------------------------------------------------------
# Data.


def read_csv(path, required=()):
    """{column: float array} of a measured-sweep CSV, validated by
    grip_tools.channels (names, SI units, finite numbers, physical ranges:
    a DataError names file, line and column)."""
    return read_table(path, required=required).columns


def write_csv(path, cols, order=None):
    order = order or list(cols)
    n = len(next(iter(cols.values())))
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([f"{k}[{CHANNELS[k].unit}]" if k in CHANNELS else k for k in order])
        for i in range(n):
            w.writerow([repr(float(cols[k][i])) for k in order])


def _column(data, name, n, default=0.0):
    v = data.get(name)
    return np.full(n, default) if v is None else np.asarray(v, dtype=float)


def _levels(x, tol):
    """Distinct levels of x (values within tol merged)."""
    xs = np.sort(np.unique(np.round(np.asarray(x) / tol) * tol))
    return xs


# ---------------------------------------------------------------------------
# Result.

@dataclass
class FitResult:
    model: str
    names: list                 # every coefficient name of the model
    values: dict                # name -> fitted (or fixed) value
    free: list                  # names that were fitted
    fixed: dict                 # name -> value held fixed
    channel: str                # 'fx', 'fy' or 'mz'
    measured: np.ndarray
    predicted: np.ndarray
    inputs: dict
    rms: float = 0.0
    max_abs: float = 0.0
    rms_rel: float = 0.0        # rms / max |measured|
    max_rel: float = 0.0
    nfev: int = 0
    success: bool = False
    message: str = ""
    constraints: list = field(default_factory=list)   # (eq, text, ok, value)
    method: str = "trf"
    params: dict = None          # full MF parameter dict (MF groups)

    def report(self):
        lines = [f"fit-mf {self.model} ({self.method}): {len(self.measured)} points, "
                 f"{len(self.free)} free coefficients, {self.nfev} evaluations, "
                 f"{'converged' if self.success else 'NOT converged'}: {self.message}",
                 f"  error {self.channel}: RMS {self.rms:.4g}, max {self.max_abs:.4g} "
                 f"({100 * self.rms_rel:.3f} % / {100 * self.max_rel:.3f} % of max |measured| "
                 f"{np.max(np.abs(self.measured)):.4g})"]
        for eq, text, ok, val in self.constraints:
            lines.append(f"  ({eq}) {'ok  ' if ok else 'FAIL'} {text}: {val:.6g}")
        lines.append("  coefficients:")
        for n in self.names:
            tag = "" if n in self.free else "  (fixed)"
            lines.append(f"    {n:6s} = {self.values[n]: .8g}{tag}")
        return "\n".join(lines)

    def to_json(self):
        return {
            "model": self.model,
            "method": self.method,
            "coefficients": {n: float(self.values[n]) for n in self.names},
            "free": list(self.free),
            "fixed": {k: float(v) for k, v in self.fixed.items()},
            "fit": {"channel": self.channel, "n": int(len(self.measured)), "rms": self.rms,
                    "max_abs": self.max_abs, "rms_rel": self.rms_rel, "max_rel": self.max_rel,
                    "nfev": self.nfev, "success": self.success, "message": self.message},
            "constraints": [{"eq": e, "text": t, "ok": bool(o), "value": float(v)}
                            for e, t, o, v in self.constraints],
        }


def _finish(res, measured, predicted):
    err = predicted - measured
    res.measured = measured
    res.predicted = predicted
    res.rms = float(np.sqrt(np.mean(err ** 2)))
    res.max_abs = float(np.max(np.abs(err)))
    top = float(np.max(np.abs(measured))) or 1.0
    res.rms_rel = res.rms / top
    res.max_rel = res.max_abs / top
    return res


# ---------------------------------------------------------------------------
# Solver: bounded least squares (trf) or Levenberg-Marquardt with bounds by
# a change of variables; inequality constraints as penalty residuals.

PENALTY_WEIGHT = 1e3


def _to_x(u, lb, ub):
    x = np.array(u, dtype=float)
    two = np.isfinite(lb) & np.isfinite(ub)
    lo = np.isfinite(lb) & ~np.isfinite(ub)
    hi = ~np.isfinite(lb) & np.isfinite(ub)
    x[two] = lb[two] + (ub[two] - lb[two]) * (np.sin(u[two]) + 1.0) / 2.0
    x[lo] = lb[lo] - 1.0 + np.sqrt(u[lo] ** 2 + 1.0)
    x[hi] = ub[hi] + 1.0 - np.sqrt(u[hi] ** 2 + 1.0)
    return x


def _to_u(x, lb, ub):
    x = np.array(x, dtype=float)
    u = x.copy()
    two = np.isfinite(lb) & np.isfinite(ub)
    lo = np.isfinite(lb) & ~np.isfinite(ub)
    hi = ~np.isfinite(lb) & np.isfinite(ub)
    t = np.clip(2.0 * (x[two] - lb[two]) / (ub[two] - lb[two]) - 1.0, -1.0, 1.0)
    u[two] = np.arcsin(t)
    a = np.maximum(x[lo] - lb[lo] + 1.0, 1.0)
    u[lo] = np.sqrt(a ** 2 - 1.0)
    b = np.maximum(ub[hi] - x[hi] + 1.0, 1.0)
    u[hi] = np.sqrt(b ** 2 - 1.0)
    return u


def _solve(resid, penalty, x0, lb, ub, method, max_nfev):
    """Minimize |resid(x)|^2 + |penalty(x)|^2 within lb <= x <= ub."""
    lb = np.asarray(lb, dtype=float)
    ub = np.asarray(ub, dtype=float)
    x0 = np.clip(np.asarray(x0, dtype=float), lb, ub)
    # keep x0 strictly inside for trf
    span = np.where(np.isfinite(ub - lb), ub - lb, 1.0)
    x0 = np.clip(x0, lb + 1e-9 * span, ub - 1e-9 * span)

    def full(x):
        r = resid(x)
        p = penalty(x) if penalty is not None else np.zeros(0)
        return np.concatenate([r, p])

    if method == "trf":
        sol = least_squares(full, x0, bounds=(lb, ub), method="trf", x_scale="jac",
                            max_nfev=max_nfev, xtol=1e-12, ftol=1e-12, gtol=1e-12)
        return sol.x, sol
    if method == "lm":
        u0 = _to_u(x0, lb, ub)
        sol = least_squares(lambda u: full(_to_x(u, lb, ub)), u0, method="lm", x_scale="jac",
                            max_nfev=max_nfev, xtol=1e-12, ftol=1e-12, gtol=1e-12)
        return _to_x(sol.x, lb, ub), sol
    raise ValueError(f"method must be 'trf' or 'lm', not {method!r}")


# ---------------------------------------------------------------------------
# The 1989-style lateral model (seed 000, ch. 3) through grip_tools.reference.mf89.

MF89_NAMES = [f"a{i}" for i in range(mf89.N_COEF)]


def _mf89_initial(alpha, fz, gamma, fy):
    """Data-driven start: peak and cornering stiffness per load level."""
    fz_kn = fz / 1000.0
    a_deg = alpha / DEG
    zero_cam = np.abs(gamma) < 1e-3
    sel = zero_cam if np.sum(zero_cam) >= 10 else np.ones_like(zero_cam)
    levels = _levels(fz_kn[sel], 0.05)
    D, K, F = [], [], []
    for lv in levels:
        m = sel & (np.abs(fz_kn - lv) < 0.05)
        if np.sum(m) < 5:
            continue
        D.append(np.max(np.abs(fy[m])))
        near = m & (np.abs(a_deg) <= max(1.0, np.sort(np.abs(a_deg[m]))[min(4, np.sum(m) - 1)]))
        if np.sum(near) >= 2:
            K.append(abs(np.polyfit(a_deg[near], fy[near], 1)[0]))
        else:
            K.append(D[-1] / 5.0)
        F.append(lv)
    D, K, F = map(np.array, (D, K, F))
    p0 = np.zeros(mf89.N_COEF)
    p0[0] = 1.3
    if len(F) >= 2:
        a1, a2 = np.linalg.lstsq(np.stack([F ** 2, F], axis=1), D, rcond=None)[0]
    else:
        a1, a2 = 0.0, D[0] / F[0]
    p0[1], p0[2] = a1, a2
    # BCD(Fz) = a3 sin(2 atan(Fz / a4)): a small fit of two numbers
    if len(F) >= 2:
        s = least_squares(lambda q: q[0] * np.sin(2 * np.arctan(F / q[1])) - K,
                          [1.2 * np.max(K), 1.5 * np.max(F)], bounds=([0, 1e-3], [np.inf, np.inf]))
        p0[3], p0[4] = s.x
    else:
        p0[3], p0[4] = K[0], 2.0 * F[0]
    p0[7] = -0.5
    p0[15] = 1e-4
    return p0


def fit_mf89(data, constraints="seed", method="trf", x0=None, fz_range_kn=None,
             gamma_max_deg=None, max_nfev=4000):
    """Fit a0..a17 to data {alpha, fz, gamma, fy} (SI). Returns a FitResult."""
    n = len(data["fy"])
    alpha = _column(data, "alpha", n)
    fz = _column(data, "fz", n)
    gamma = _column(data, "gamma", n)
    fy = np.asarray(data["fy"], dtype=float)
    if fz_range_kn is None:
        fz_range_kn = (float(np.min(fz)) / 1000.0, float(np.max(fz)) / 1000.0)
    if gamma_max_deg is None:
        gamma_max_deg = max(float(np.max(np.abs(gamma))) / DEG, 1e-6)
    p0 = _mf89_initial(alpha, fz, gamma, fy) if x0 is None else np.asarray(x0, dtype=float)
    scale = float(np.max(np.abs(fy))) or 1.0

    if constraints == "seed":
        con = mf89.constraints(fz_range_kn=fz_range_kn, gamma_max_deg=gamma_max_deg)
        idx = con.free_index()
        lb, ub = con.free_bounds()
        fixed = {MF89_NAMES[i]: float(v) for i, v in con.fixed.items()}

        def expand(x):
            return con.expand(x)

        def penalty(x):
            m = con.margins(expand(x))
            return PENALTY_WEIGHT * np.minimum(m, 0.0) / max(1.0, np.max(np.abs(con.linear_b)))
    elif constraints == "none":
        idx = np.arange(mf89.N_COEF)
        lb = np.full(mf89.N_COEF, -np.inf)
        ub = np.full(mf89.N_COEF, np.inf)
        lb[4] = 1e-6            # a4 divides Fz
        fixed = {}

        def expand(x):
            return np.asarray(x, dtype=float)

        penalty = None
    else:
        raise ValueError(f"constraints must be 'seed' or 'none', not {constraints!r}")

    def resid(x):
        return (mf89.fy89(expand(x), alpha, fz, gamma) - fy) / scale

    x, sol = _solve(resid, penalty, p0[idx], lb, ub, method, max_nfev)
    p = expand(x)
    res = FitResult("mf89", MF89_NAMES, {MF89_NAMES[i]: float(p[i]) for i in range(mf89.N_COEF)},
                    [MF89_NAMES[i] for i in idx], fixed, "fy", fy, None,
                    {"alpha": alpha, "fz": fz, "gamma": gamma}, nfev=int(sol.nfev),
                    success=bool(sol.success), message=str(sol.message), method=method)
    res.constraints = [(r.eq, r.text, r.ok, r.value) for r in
                       mf89.check_constraints(p, fz_range_kn=fz_range_kn, gamma_max_deg=gamma_max_deg)]
    res.params = p
    return _finish(res, fy, mf89.fy89(p, alpha, fz, gamma))


# ---------------------------------------------------------------------------
# MF 5.2 / 6.1 pure-slip groups through grip_tools.reference.mf.

# Each coefficient: (name, what varies in the data so that it can be
# identified: '' always, 'fz' two or more loads, 'fz3' three or more loads,
# 'gamma' camber, 'p' pressure, 'mf6' only in MF 6.x, 'mf5' only in MF 5.2).
GROUPS = {
    "fx": [("pcx1", ""), ("pdx1", ""), ("pdx2", "fz"), ("pdx3", "gamma"),
           ("pex1", ""), ("pex2", "fz"), ("pex3", "fz3"), ("pex4", ""),
           ("pkx1", ""), ("pkx2", "fz"), ("pkx3", "fz3"), ("phx1", ""), ("phx2", "fz"),
           ("pvx1", ""), ("pvx2", "fz"),
           ("ppx1", "p mf6"), ("ppx2", "p mf6"), ("ppx3", "p mf6"), ("ppx4", "p mf6")],
    "fy": [("pcy1", ""), ("pdy1", ""), ("pdy2", "fz"), ("pdy3", "gamma"),
           ("pey1", ""), ("pey2", "fz"), ("pey3", ""), ("pey4", "gamma"), ("pey5", "gamma mf6"),
           ("pky1", ""), ("pky2", "fz"), ("pky3", "gamma"), ("pky4", "fz3 mf6"), ("pky5", "gamma mf6"),
           ("pky6", "gamma mf6"), ("pky7", "gamma fz mf6"),
           ("phy1", ""), ("phy2", "fz"), ("phy3", "gamma mf5"),
           ("pvy1", ""), ("pvy2", "fz"), ("pvy3", "gamma"), ("pvy4", "gamma fz"),
           ("ppy1", "p mf6"), ("ppy2", "p mf6"), ("ppy3", "p mf6"), ("ppy4", "p mf6"), ("ppy5", "p mf6 gamma")],
    "mz": [("qbz1", ""), ("qbz2", "fz"), ("qbz3", "fz3"), ("qbz4", "gamma"), ("qbz5", "gamma"),
           ("qbz10", ""), ("qcz1", ""), ("qdz1", ""), ("qdz2", "fz"), ("qdz3", "gamma"), ("qdz4", "gamma"),
           ("qdz6", ""), ("qdz7", "fz"), ("qdz8", "gamma"), ("qdz9", "gamma fz"),
           ("qdz10", "gamma mf6"), ("qdz11", "gamma fz mf6"),
           ("qez1", ""), ("qez2", "fz"), ("qez3", "fz3"), ("qez4", ""), ("qez5", "gamma"),
           ("qhz1", ""), ("qhz2", "fz"), ("qhz3", "gamma"), ("qhz4", "gamma fz"),
           ("ppz1", "p mf6"), ("ppz2", "p mf6 gamma")],
}
GROUP_SECTION = {"fx": "LONGITUDINAL_COEFFICIENTS", "fy": "LATERAL_COEFFICIENTS",
                 "mz": "ALIGNING_COEFFICIENTS"}
GROUP_OUTPUT = {"fx": "fx0", "fy": "fy0", "mz": "mz0"}
# seed constraints carried over to the MF lateral group
FY_SEED_FIXED = {"pey3": 0.0, "phy1": 0.0, "phy2": 0.0, "pvy1": 0.0, "pvy2": 0.0}
FY_SEED_BOUNDS = {"pcy1": (mf89.C_MIN, mf89.C_MAX), "pdy3": (0.0, np.inf)}
# general bounds that keep the model defined (all groups)
GENERAL_BOUNDS = {"pcx1": (0.3, 3.0), "pcy1": (0.3, 3.0), "qcz1": (0.3, 3.0),
                  "pdx1": (0.0, 5.0), "pdy1": (0.0, 5.0), "pkx1": (0.0, np.inf),
                  "pky4": (0.5, 4.0), "qbz1": (0.0, np.inf)}


def _base_params(tir_path, fittyp, fnomin, r0, side="fitted"):
    """A parameter dict to start from: a .tir file (mounted as fitted unless
    side says otherwise), or MF defaults."""
    from grip_tools.reference import tir
    if tir_path:
        return tir.read_tir(tir_path).params(side)
    p = {c.field: c.default for c in tir.coefficients()}
    p.update(fittyp=int(fittyp), tyreside=1, options=0, path="(defaults)")
    p["fnomin"] = float(fnomin)
    p["unloaded_radius"] = float(r0)
    if int(fittyp) in (61, 62):
        p["nompres"] = p["inflpres"] = 2.0e5
    # neutral starting shapes
    p.update(pcx1=1.6, pdx1=1.0, pex1=0.0, pkx1=20.0, pcy1=1.3, pdy1=1.0, pey1=-0.5,
             pky1=-15.0, pky2=1.5, qbz1=10.0, qcz1=1.1, qdz1=0.1, qez1=-1.0)
    return p


def _usable(tags, varies, mf6):
    t = tags.split()
    if "mf6" in t and not mf6:
        return False
    if "mf5" in t and mf6:
        return False
    return all(varies.get(x, True) for x in t if x not in ("mf6", "mf5"))


def _e_values(group, P, dfz, gamma, mf6):
    """Curvature factor E (before the min(E, 1) of the model) at the given
    points, both signs of slip (the constraint (3.11) E < 1)."""
    out = []
    for s in (-1.0, 1.0):
        if group == "fy":
            if mf6:
                e = (P["pey1"] + P["pey2"] * dfz) * (1.0 + P["pey5"] * gamma ** 2
                                                     - (P["pey3"] + P["pey4"] * gamma) * s) * P["ley"]
            else:
                e = (P["pey1"] + P["pey2"] * dfz) * (1.0 - (P["pey3"] + P["pey4"] * gamma) * s) * P["ley"]
        elif group == "fx":
            e = (P["pex1"] + P["pex2"] * dfz + P["pex3"] * dfz ** 2) * (1.0 - P["pex4"] * s) * P["lex"]
        else:
            e = (P["qez1"] + P["qez2"] * dfz + P["qez3"] * dfz ** 2) * (
                1.0 + (P["qez4"] + P["qez5"] * gamma) * s)
        out.append(np.atleast_1d(e))
    return np.concatenate(out)


def _mf_initial(group, P, data, out):
    """Data-driven start of the main coefficients of a group (the rest from P)."""
    P = dict(P)
    fz = data["fz"]
    fz0 = P["fnomin"] * P["lfzo"]
    near_nom = np.abs(fz - fz0) <= np.min(np.abs(fz - fz0)) + 1e-6 * fz0
    m = near_nom & (np.abs(data["gamma"]) < 1e-3)
    if np.sum(m) < 5:
        m = near_nom
    fzn = float(np.mean(fz[m]))
    if group == "fx":
        x = data["kappa"][m]
        y = out[m]
        P["pdx1"] = float(np.max(np.abs(y)) / fzn)
        nz = np.abs(x) <= np.sort(np.abs(x))[min(4, len(x) - 1)]
        P["pkx1"] = float(abs(np.polyfit(x[nz], y[nz], 1)[0]) / fzn) if np.sum(nz) >= 2 else 20.0
    elif group == "fy":
        x = data["alpha"][m]
        y = out[m]
        P["pdy1"] = float(np.max(np.abs(y)) / fzn)
        nz = np.abs(x) <= np.sort(np.abs(x))[min(4, len(x) - 1)]
        slope = np.polyfit(x[nz], y[nz], 1)[0] if np.sum(nz) >= 2 else -P["pdy1"] * fzn * 10
        # MF 5.2: Kya(Fz0) = PKY1 Fz0 sin(2 atan(1/PKY2)); start with PKY2 = 1.5
        mf6 = int(P["fittyp"]) in (61, 62)
        shape = np.sin(P["pky4"] * np.arctan(1.0 / 1.5)) if mf6 else np.sin(2 * np.arctan(1.0 / 1.5))
        P["pky1"] = float(slope / (fz0 * shape))
        P["pky2"] = 1.5
        # the pure lateral force of a normal tyre falls with alpha in ISO-W
        if P["pdy1"] <= 0:
            P["pdy1"] = 1.0
    return P


def identifiable(group, data, base):
    """The coefficients of `group` that data can determine: those of the
    load, camber and pressure dependencies only where the data vary them."""
    fz = np.asarray(data["fz"], dtype=float)
    gamma = _column(data, "gamma", len(fz))
    p_in = data.get("p")
    mf6 = int(base["fittyp"]) in (61, 62)
    nload = len(_levels(fz, 0.02 * base["fnomin"]))
    varies = {"fz": nload >= 2, "fz3": nload >= 3,
              "gamma": bool(np.any(np.abs(gamma) > 1e-4)),
              "p": p_in is not None and mf6 and float(np.ptp(p_in)) > 1e-3 * base["nompres"]}
    return [nm for nm, tags in GROUPS[group] if _usable(tags, varies, mf6)]


# Points per free coefficient below which a fit is refused: with fewer the
# least-squares problem is (nearly) square and the fit reproduces noise.
MIN_POINTS_PER_COEF = 3


def check_fit_data(path, table, channel, slip, n_free):
    """Refuse data the fit cannot use, before it starts (DataError names file,
    line, column): a load that is not positive, or too few points for the
    coefficients asked."""
    fz = table.columns["fz"]
    bad = np.flatnonzero(fz <= 0.0)
    if bad.size:
        i = int(bad[0])
        raise DataError(path, int(table.row_lines[i]), "fz",
                        f"load {fz[i]:g} N: a fit needs loaded tires (fz > 0; ISO-W: positive when loaded)")
    n = len(table)
    if n < MIN_POINTS_PER_COEF * n_free:
        raise DataError(path, table.header_line, channel,
                        f"{n} rows for {n_free} free coefficients: at least {MIN_POINTS_PER_COEF * n_free} needed")
    if float(np.ptp(table.columns[slip])) <= 0.0:
        raise DataError(path, table.header_line, slip, f"{slip} does not vary: no slip sweep to fit")


def fit_mf_group(data, group, base, constraints="seed", method="trf", free=None, fix=(),
                 max_nfev=3000, initial="data"):
    """Fit one pure-slip group of an MF parameter dict `base` to data.

    data: {kappa, alpha, gamma, fz, (p, vx), fx|fy|mz} SI, ISO-W.
    free: names to fit (default: the group's identifiable coefficients);
    fix: names to hold at base's values. initial: 'data' (data-driven start
    of the main coefficients) or 'base' (start from base as given).
    """
    from grip_tools.reference import mf
    if group not in GROUPS:
        raise ValueError(f"group must be one of {sorted(GROUPS)}")
    ch = {"fx": "fx", "fy": "fy", "mz": "mz"}[group]
    meas = np.asarray(data[ch], dtype=float)
    n = len(meas)
    inp = {k: _column(data, k, n) for k in ("kappa", "alpha", "gamma")}
    inp["fz"] = np.asarray(data["fz"], dtype=float)
    p_in = data.get("p")
    vx_in = data.get("vx")
    mf6 = int(base["fittyp"]) in (61, 62)
    names = identifiable(group, data, base) if free is None else list(free)
    fixed = {}
    if constraints == "seed" and group == "fy":
        for k, v in FY_SEED_FIXED.items():
            fixed[k] = v
    elif constraints not in ("seed", "none"):
        raise ValueError(f"constraints must be 'seed' or 'none', not {constraints!r}")
    for k in fix:
        fixed[k] = base[k]
    names = [nm for nm in names if nm not in fixed]
    P0 = dict(base)
    P0.update(fixed)
    if initial == "data":
        P0 = _mf_initial(group, P0, {**inp, "p": p_in}, meas)
    x0 = np.array([P0[nm] for nm in names], dtype=float)
    lb = np.full(len(names), -np.inf)
    ub = np.full(len(names), np.inf)
    for i, nm in enumerate(names):
        b = GENERAL_BOUNDS.get(nm)
        if constraints == "seed" and group == "fy" and nm in FY_SEED_BOUNDS:
            b = FY_SEED_BOUNDS[nm]
        if b is not None:
            lb[i], ub[i] = b
    scale = float(np.max(np.abs(meas))) or 1.0
    key = GROUP_OUTPUT[group]
    # corners of the data range for E < 1
    fz0p = base["fnomin"] * base["lfzo"]
    dfz_c = (np.array([np.min(inp["fz"]), np.max(inp["fz"])]) - fz0p) / fz0p
    g_c = np.array([-np.max(np.abs(inp["gamma"])), 0.0, np.max(np.abs(inp["gamma"]))])
    DF, GC = np.meshgrid(dfz_c, g_c)

    def params_of(x):
        P = dict(P0)
        P.update(zip(names, (float(v) for v in x)))
        return P

    def model(P):
        return mf.evaluate(P, inp["kappa"], inp["alpha"], inp["gamma"], inp["fz"], p_in, vx_in,
                           mirror=False)[key]

    def resid(x):
        r = (model(params_of(x)) - meas) / scale
        return np.where(np.isfinite(r), r, 1e3)

    def penalty(x):
        e = _e_values(group, params_of(x), DF.ravel(), GC.ravel(), mf6)
        return PENALTY_WEIGHT * np.minimum(1.0 - e, 0.0)

    x, sol = _solve(resid, penalty, x0, lb, ub, method, max_nfev)
    P = params_of(x)
    sect_names = [nm for nm, _ in GROUPS[group] if _usable(_, {"fz": True, "fz3": True, "gamma": True,
                                                               "p": True}, mf6)]
    values = {nm: float(P[nm]) for nm in sect_names}
    res = FitResult(group, sect_names, values, names, {k: float(v) for k, v in fixed.items()}, ch,
                    meas, None, inp, nfev=int(sol.nfev), success=bool(sol.success),
                    message=str(sol.message), method=method)
    e = _e_values(group, P, DF.ravel(), GC.ravel(), mf6)
    res.constraints.append(("3.11", "E < 1 over the data's load/camber range", bool(np.max(e) < 1.0),
                            float(np.max(e))))
    if group == "fy" and constraints == "seed":
        res.constraints.append(("3.10", "1.0 <= PCY1 <= 1.65 (C)", bool(1.0 <= P["pcy1"] <= 1.65),
                                float(P["pcy1"])))
        res.constraints.append(("3.12", "PEY3 = 0 (E symmetric at zero camber)", P["pey3"] == 0.0,
                                float(P["pey3"])))
        res.constraints.append(("3.13", "PHY1 = PHY2 = PVY1 = PVY2 = 0 (no shifts at zero camber)",
                                all(P[k] == 0.0 for k in ("phy1", "phy2", "pvy1", "pvy2")),
                                float(max(abs(P[k]) for k in ("phy1", "phy2", "pvy1", "pvy2")))))
        res.constraints.append(("3.16", "PDY3 >= 0 (peak falls with camber)", bool(P["pdy3"] >= 0.0),
                                float(P["pdy3"])))
    res.params = P
    return _finish(res, meas, model(P))


# ---------------------------------------------------------------------------
# Output: .tir fragment, JSON, plot.

def tir_fragment(res):
    """The fitted group as a .tir fragment (MF groups only)."""
    if res.model not in GROUP_SECTION:
        raise ValueError("a .tir fragment exists for the MF groups fx, fy, mz only")
    lines = [f"$ fitted by grip_tools fit-mf ({res.method}): {len(res.measured)} points, "
             f"RMS {res.rms:.4g}, max {res.max_abs:.4g}",
             f"[{GROUP_SECTION[res.model]}]"]
    for nm in res.names:
        tag = "" if nm in res.free else "   $ fixed"
        lines.append(f"{nm.upper():24s} = {res.values[nm]: .10g}{tag}")
    return "\n".join(lines) + "\n"


def plot(res, path, title=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    inp = res.inputs
    xname = "kappa" if res.channel == "fx" else "alpha"
    x = inp[xname]
    xs = x if xname == "kappa" else x / DEG
    fz = inp["fz"]
    gam = inp["gamma"]
    loads = _levels(fz, 0.02 * max(np.max(fz), 1.0))
    cams = _levels(gam, 1e-4)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [2, 1]})
    ax = axes[0]
    colors = plt.cm.viridis(np.linspace(0, 0.9, max(len(loads), 1)))
    styles = ["-", "--", ":", "-.", (0, (5, 1))]
    for i, lv in enumerate(loads):
        for j, g in enumerate(cams):
            m = (np.abs(fz - lv) < 0.02 * max(np.max(fz), 1.0)) & (np.abs(gam - g) < 1e-4)
            if not np.any(m):
                continue
            o = np.argsort(xs[m])
            lab = f"Fz {lv / 1000:.1f} kN" + (f", camber {g / DEG:+.1f} deg" if len(cams) > 1 else "")
            ax.plot(xs[m][o], res.measured[m][o], ".", color=colors[i], ms=3, alpha=0.6)
            ax.plot(xs[m][o], res.predicted[m][o], linestyle=styles[j % len(styles)], color=colors[i],
                    lw=1.2, label=lab)
    ax.set_xlabel("slip ratio kappa [-]" if xname == "kappa" else "slip angle alpha [deg]")
    unit = "N m" if res.channel == "mz" else "N"
    ax.set_ylabel(f"{res.channel} [{unit}]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title(title or f"fit-mf {res.model}: measured (dots) vs fitted (lines)")
    ax2 = axes[1]
    ax2.plot(xs, res.predicted - res.measured, ".", ms=2)
    ax2.set_xlabel(ax.get_xlabel())
    ax2.set_ylabel(f"fitted - measured [{unit}]")
    ax2.set_title(f"RMS {res.rms:.3g} {unit}, max {res.max_abs:.3g} {unit}")
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------------------
# Synthetic sweeps (known coefficients + noise).

def sweep_inputs(group, fz_levels, gammas, n_slip=41, slip_max=None, p=None, vx=None):
    """Inputs of a pure-slip sweep: every load x camber x slip point."""
    if group == "fx":
        slip = np.linspace(-(slip_max or 0.3), slip_max or 0.3, n_slip)
    else:
        slip = np.linspace(-(slip_max or 15 * DEG), slip_max or 15 * DEG, n_slip)
    F, G, S = np.meshgrid(np.asarray(fz_levels, float), np.asarray(gammas, float), slip, indexing="ij")
    d = {"fz": F.ravel(), "gamma": G.ravel(),
         "kappa": S.ravel() if group == "fx" else np.zeros(S.size),
         "alpha": np.zeros(S.size) if group == "fx" else S.ravel()}
    if p is not None:
        d["p"] = np.full(S.size, float(p)) if np.isscalar(p) else np.asarray(p, float)
    if vx is not None:
        d["vx"] = np.full(S.size, float(vx))
    return d


def synthetic_mf89(params=None, fz_kn=(3.0, 6.0, 9.0), gamma_deg=(-4.0, -2.0, 0.0, 2.0, 4.0),
                   alpha_max_deg=15.0, n_slip=41, noise=0.0, seed=0):
    params = mf89.DEFAULT_PARAMS if params is None else np.asarray(params, float)
    d = sweep_inputs("fy", np.asarray(fz_kn) * 1000.0, np.asarray(gamma_deg) * DEG, n_slip,
                     alpha_max_deg * DEG)
    rng = np.random.default_rng(seed)
    d["fy"] = mf89.fy89(params, d["alpha"], d["fz"], d["gamma"]) + noise * rng.standard_normal(d["fz"].size)
    return d


def synthetic_mf(params, group, fz_levels=None, gammas=(0.0,), n_slip=41, noise=0.0, seed=0, p=None):
    from grip_tools.reference import mf
    fz0 = params["fnomin"]
    fz_levels = fz_levels if fz_levels is not None else (0.5 * fz0, fz0, 1.5 * fz0)
    d = sweep_inputs(group, fz_levels, gammas, n_slip, p=p)
    out = mf.evaluate(params, d["kappa"], d["alpha"], d["gamma"], d["fz"], d.get("p"), None, mirror=False)
    rng = np.random.default_rng(seed)
    ch = {"fx": "fx", "fy": "fy", "mz": "mz"}[group]
    d[ch] = out[GROUP_OUTPUT[group]] + noise * rng.standard_normal(d["fz"].size)
    return d


# ---------------------------------------------------------------------------
# Command line.

# Exit status (also in --help): 0 fitted, 1 fitted but a seed constraint
# is violated, 2 usage, 3 data refused, 4 not converged (nothing written).
EXIT_NOT_CONVERGED = 4


def main(argv=None):
    from grip_tools.reference import tir
    ap = argparse.ArgumentParser(prog="grip fit-mf", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="exit status: 0 fitted; 1 fitted, a seed constraint violated; 2 usage; "
                                        "3 data refused (the message names file, line, column); "
                                        "4 the fit did not converge or its error is not finite (nothing written)")
    ap.add_argument("csv", nargs="?", help="measured sweeps (CSV with a header)")
    ap.add_argument("--model", choices=("mf89", "fx", "fy", "mz"), default="mf89")
    ap.add_argument("--tir", help="MF groups: start from (and keep the other coefficients of) this file")
    tir.add_reader_options(ap)
    ap.add_argument("--fittyp", type=int, default=61, help="MF groups without --tir: 5/6/21 or 61/62")
    ap.add_argument("--side", choices=("fitted", "left", "right"), default="fitted",
                    help="MF groups with --tir: where that tyre is mounted (default as fitted: measured data "
                         "are taken on the tyre as the file describes it)")
    ap.add_argument("--fnomin", type=float, help="MF groups without --tir: nominal load [N] "
                    "(default: the middle load level of the data)")
    ap.add_argument("--r0", type=float, default=0.3, help="MF groups without --tir: unloaded radius [m]")
    ap.add_argument("--constraints", choices=("seed", "none"), default="seed")
    ap.add_argument("--method", choices=("trf", "lm"), default="trf")
    ap.add_argument("--start", choices=("data", "tir"), default="data",
                    help="MF groups: data-driven start of the main coefficients, or the --tir values")
    ap.add_argument("--fix", default="", help="comma-separated coefficients to hold at their start value")
    ap.add_argument("--json", help="write the coefficients and fit figures as JSON")
    ap.add_argument("--tir-out", help="write the fitted group as a .tir fragment (MF groups)")
    ap.add_argument("--plot", help="write a PNG of measured vs fitted curves")
    ap.add_argument("--synthetic", metavar="OUT.csv",
                    help="instead of fitting: write synthetic sweeps of --model from known coefficients "
                         "(mf89: the documented default set; MF groups: --tir) with --noise")
    ap.add_argument("--noise", type=float, default=0.0, help="--synthetic: noise std [N or N m]")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    if not (math.isfinite(args.noise) and args.noise >= 0.0):
        ap.error(f"--noise {args.noise!r}: a standard deviation >= 0")
    tir.apply_reader_options(args)

    if args.synthetic:
        if args.model == "mf89":
            d = synthetic_mf89(noise=args.noise, seed=args.seed)
        else:
            if not args.tir:
                ap.error("--synthetic for an MF group needs --tir (the true coefficients)")
            from grip_tools.reference import tir
            P = tir.read_tir(args.tir).params(args.side)
            gam = (-0.05, 0.0, 0.05) if args.model != "fx" else (0.0,)
            d = synthetic_mf(P, args.model, gammas=gam, noise=args.noise, seed=args.seed)
        write_csv(args.synthetic, d)
        print(f"fit-mf: wrote {len(d['fz'])} rows to {args.synthetic}")
        return 0

    if not args.csv:
        ap.error("the measured CSV is required (or --synthetic)")
    ch = "fy" if args.model in ("mf89", "fy") else args.model
    slip = "kappa" if args.model == "fx" else "alpha"
    # the base .tir first: its FNOMIN tells a load in kN from a light load
    base_tir = _base_params(args.tir, args.fittyp, 0.0, args.r0, args.side) \
        if args.tir and args.model != "mf89" else None
    fz_nominal = base_tir["fnomin"] if base_tir is not None else args.fnomin
    table = read_table(args.csv, required=("fz", ch, slip), fz_nominal=fz_nominal)
    data = table.columns
    fix = [s.strip().lower() for s in args.fix.split(",") if s.strip()]
    if args.model == "mf89":
        check_fit_data(args.csv, table, ch, slip, len(MF89_NAMES))
        res = fit_mf89(data, constraints=args.constraints, method=args.method)
    else:
        fz_levels = _levels(data["fz"], 0.02 * float(np.max(data["fz"])))
        fnomin = args.fnomin or float(fz_levels[len(fz_levels) // 2])
        base = base_tir if base_tir is not None else _base_params(None, args.fittyp, fnomin, args.r0, args.side)
        n_free = len([nm for nm in identifiable(args.model, data, base) if nm not in fix])
        check_fit_data(args.csv, table, ch, slip, n_free)
        res = fit_mf_group(data, args.model, base, constraints=args.constraints, method=args.method,
                           fix=fix, initial="data" if args.start == "data" else "base")
    print(res.report())
    if not (res.success and math.isfinite(res.rms) and all(math.isfinite(float(v)) for v in res.values.values())):
        print(f"grip fit-mf: {args.csv}: the fit did not converge or its error is not finite: "
              "no coefficients written", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res.to_json(), f, indent=2)
    if args.tir_out:
        if args.model == "mf89":
            print("fit-mf: --tir-out applies to the MF groups (mf89 has no .tir keys); use --json",
                  file=sys.stderr)
        else:
            with open(args.tir_out, "w") as f:
                f.write(tir_fragment(res))
    if args.plot:
        plot(res, args.plot)
    return 0 if all(c[2] for c in res.constraints) else 1


if __name__ == "__main__":
    sys.exit(main())
