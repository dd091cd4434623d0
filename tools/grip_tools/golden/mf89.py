"""Golden vectors for the 1989-style lateral Magic Formula (mf89.py) and the
temperature-dependent Magic Formula with its thermal state (mf_thermal.py).

Writes build/golden/mf89.txt and build/golden/mf_thermal.txt. Inputs lie on
the fixed-point grids (QS = 2^-16 for angles, slip, speeds, temperatures and
time steps, QL = 2^-8 for loads), so both C builds see exactly the inputs
the float64 reference evaluated; the parameters are written in full
precision (their rounding is part of the fixed build's measured error).

mf89.txt rows (SI: rad, N):
  P a0..a17 fz_max alpha_max gamma_max          the parameter set
  V alpha fz gamma fy peak                      valid range; peak = |D| + |Sv|
  C alpha fz gamma fy peak                      out of range: fy at the clamped inputs
  K label mask fz_lo fz_hi gamma_max a0..a17    constraint check, expected bit mask
mf_thermal.txt rows:
  P <every ThermalParams field in PARAM_ORDER>
  F alpha slip fz T fx fy peak                  forces at fixed temperature
  S scen v alpha slip fz t_road dt t_before fx fy q vs t_after peak
                                                time series, one scenario per scen id;
                                                t_before of its first row is T_init
"""
import os

import numpy as np

from grip_tools.reference import mf89, mf_thermal
from grip_tools.golden.io import header

SEED = 20260589
DEG = np.pi / 180.0


def qs(x):
    return np.round(np.asarray(x, dtype=float) * 65536.0) / 65536.0


def ql(x):
    return np.round(np.asarray(x, dtype=float) * 256.0) / 256.0


def _fmt(v):
    return repr(float(v))


# ---------------------------------------------------------------------------
# mf89
# ---------------------------------------------------------------------------

def _mf89_peak(p, fz, gamma):
    f = mf89.factors(p, 0.0, np.asarray(fz) / 1000.0, np.asarray(gamma) / DEG)
    return np.abs(f["D"]) + np.abs(f["Sv"])


def _mf89_constraint_sets(p):
    """(label, params) pairs: the valid default and one violation of each
    constraint (plus a double violation)."""
    sets = [("valid", p.copy())]

    def mod(label, **changes):
        q = p.copy()
        for k, v in changes.items():
            q[int(k[1:])] = v
        sets.append((label, q))

    mod("C_high", a0=1.7)
    mod("C_low", a0=0.95)
    mod("E_ge_1", a7=1.2, a6=0.0)
    mod("E_camber", a16=0.5)                          # E = E0 (1 -+ 4), E0 < 0: > 1 at high load
    mod("a17", a17=0.05)
    mod("Sh0", a9=0.01)
    mod("Sv0", a12=5.0)
    mod("Sh_camber", a10=0.02)
    mod("Sv_camber", a14=30.0)
    mod("Sv_camber_hi", a13=-5.0)                      # |a13 Fz + a14| = 32 at 10 kN
    mod("a15_neg", a15=-0.001)
    mod("two", a0=1.8, a15=0.0)
    return sets


def _mask(results):
    bit = {"3.10": 0, "3.11": 1, "3.12": 2, "3.13": 3, "3.14": 4, "3.15": 5, "3.16": 6}
    m = 0
    for r in results:
        if not r.ok:
            m |= 1 << bit[r.eq]
    return m


def write_mf89(path, rng):
    p = mf89.DEFAULT_PARAMS
    lim = mf89.DEFAULT_LIMITS
    fz_max = lim["fz_max_kn"] * 1000.0
    a_max = qs(lim["alpha_max_deg"] * DEG)
    g_max = qs(lim["gamma_max_deg"] * DEG)
    rows = []
    # grid over the valid range
    fzs = [0.0, 250.0, 500.0, 1000.0, 2000.0, 3000.0, 4600.0, 6000.0, 7000.0, 9000.0, 10000.0]
    alphas = np.linspace(-1.0, 1.0, 101) * a_max
    gammas = np.array([-8.0, -4.0, -1.0, 0.0, 1.0, 4.0, 8.0]) * DEG
    A, F, G = np.meshgrid(alphas, fzs, gammas, indexing="ij")
    A, F, G = qs(A.ravel()), ql(F.ravel()), qs(np.clip(G.ravel(), -g_max, g_max))
    # random inside the box, and small slip angles (linear region, sign changes)
    n = 4000
    A2 = qs(rng.uniform(-a_max, a_max, n))
    F2 = ql(rng.uniform(0.0, fz_max, n))
    G2 = qs(rng.uniform(-g_max, g_max, n))
    A3 = qs(rng.uniform(-1.0, 1.0, 1000) * DEG)
    F3 = ql(rng.uniform(500.0, fz_max, 1000))
    G3 = qs(rng.uniform(-g_max, g_max, 1000))
    A = np.concatenate([A, A2, A3])
    F = np.concatenate([F, F2, F3])
    G = np.concatenate([G, G2, G3])
    fy = mf89.fy89(p, A, F, G)
    peak = _mf89_peak(p, F, G)
    for a, f, g, y, pk in zip(A, F, G, fy, peak):
        rows.append("V " + " ".join(_fmt(v) for v in (a, f, g, y, pk)))
    # out of range inputs: expected value is the formula at the clamped input
    ext = [(0.8, 4600.0, 0.0), (-1.2, 4600.0, 0.02), (0.1, 15000.0, 0.0), (0.1, -500.0, 0.0),
           (0.05, 4600.0, 0.3), (-0.05, 4600.0, -0.3), (3.0, 20000.0, -0.4), (-0.3, 10001.0, 0.14)]
    for a, f, g in ext:
        a, f, g = float(qs(a)), float(ql(f)), float(qs(g))
        ac = float(np.clip(a, -a_max, a_max))
        fc = float(np.clip(f, 0.0, fz_max))
        gc = float(np.clip(g, -g_max, g_max))
        y = float(mf89.fy89(p, ac, fc, gc))
        rows.append("C " + " ".join(_fmt(v) for v in (a, f, g, y, _mf89_peak(p, fc, gc))))
    # constraint sets
    fz_range = mf89.DEFAULT_FZ_RANGE_KN
    for label, q in _mf89_constraint_sets(p):
        m = _mask(mf89.check_constraints(q, fz_range_kn=fz_range, gamma_max_deg=lim["gamma_max_deg"]))
        rows.append(f"K {label} {m} {fz_range[0] * 1000.0!r} {fz_range[1] * 1000.0!r} {float(g_max)!r} "
                    + " ".join(_fmt(v) for v in q))
    prow = "P " + " ".join(_fmt(v) for v in p) + f" {fz_max!r} {float(a_max)!r} {float(g_max)!r}"
    params = {f"a{i}": float(v) for i, v in enumerate(p)}
    params.update({"fz_max_N": fz_max, "alpha_max_rad": float(a_max), "gamma_max_rad": float(g_max)})
    with open(path, "w") as f:
        f.write(header("golden_mf89", mf89.fy89_seed_units, SEED,
                       ["tag", "alpha_rad", "fz_N", "gamma_rad", "fy_N", "peak_N"], params))
        f.write(prow + "\n")
        for r in rows:
            f.write(r + "\n")
    return len(rows)


# ---------------------------------------------------------------------------
# mf_thermal
# ---------------------------------------------------------------------------

def _ramp(t, t0, t1, v0, v1):
    """Smooth (cosine) transition from v0 at t0 to v1 at t1."""
    s = np.clip((t - t0) / (t1 - t0), 0.0, 1.0)
    return v0 + (v1 - v0) * 0.5 * (1.0 - np.cos(np.pi * s))


def _thermal_peak(prm, fz, t):
    fzn = np.asarray(fz) / prm.fz0
    dx = prm.dx0 * (1.0 + prm.ax * (t - prm.t0))
    dy = prm.dy0 * (1.0 + prm.ay * (t - prm.t0))
    return fzn * (np.maximum(np.abs(dx), np.abs(dy)) + np.abs(prm.svx) + np.abs(prm.svy) + np.abs(prm.svys))


def thermal_scenarios():
    """(name, t_init, dict of input arrays incl. dt) - fish-hook steering with
    braking, a brake-and-cool run, and a cold tire on a hot road in combined slip."""
    out = []
    # 1: fish hook at 80 km/h, load transfer, light braking in the hook
    dt = float(qs(0.01))
    t = np.arange(1000) * dt
    a_deg = _ramp(t, 0.5, 0.9, 0.0, 5.0) + _ramp(t, 1.9, 2.5, 0.0, -12.0) + _ramp(t, 5.5, 6.0, 0.0, 7.0)
    slip = _ramp(t, 2.0, 3.0, 0.0, 0.03) + _ramp(t, 5.0, 6.0, 0.0, -0.03)
    fz = 4600.0 - 1600.0 * a_deg / 7.0
    out.append(("fishhook", 35.0, {"v": np.full_like(t, 80.0 / 3.6), "alpha": a_deg * DEG, "slip": slip,
                                   "fz": fz, "t_road": np.full_like(t, 30.0), "dt": np.full_like(t, dt)}))
    # 2: braking at 60 km/h to S = 0.25, release, then cooling with a coarser step
    dt1, dt2 = float(qs(0.01)), float(qs(0.05))
    n1, n2 = 400, 200
    dts = np.concatenate([np.full(n1, dt1), np.full(n2, dt2)])
    t = np.concatenate([[0.0], np.cumsum(dts)[:-1]])
    slip = _ramp(t, 0.2, 1.7, 0.0, 0.25) + _ramp(t, 3.2, 3.7, 0.0, -0.25)
    out.append(("brake_cool", 30.0, {"v": np.full_like(t, 60.0 / 3.6), "alpha": np.zeros_like(t), "slip": slip,
                                     "fz": np.full_like(t, 4600.0), "t_road": np.full_like(t, 30.0), "dt": dts}))
    # 3: cold tire on a hot road, weaving with braking (combined slip)
    dt = float(qs(0.02))
    t = np.arange(400) * dt
    a = 4.0 * DEG * np.sin(2.0 * np.pi * 0.5 * t)
    slip = 0.06 * (0.5 + 0.5 * np.sin(2.0 * np.pi * 0.25 * t))
    fz = 4600.0 + 1500.0 * np.sin(2.0 * np.pi * 0.5 * t + 0.3)
    v = 25.0 - 1.0 * t
    out.append(("cold_combined", 5.0, {"v": v, "alpha": a, "slip": slip, "fz": fz,
                                      "t_road": np.full_like(t, 40.0), "dt": np.full_like(t, dt)}))
    # 4: hard cornering and locked-wheel braking: the upper valid corner
    dt = float(qs(0.01))
    t = np.arange(500) * dt
    a = _ramp(t, 0.2, 1.0, 0.0, 0.45) + _ramp(t, 3.0, 3.5, 0.0, -0.9)
    slip = _ramp(t, 1.5, 2.0, 0.0, 1.0) + _ramp(t, 4.0, 4.5, 0.0, -1.0)
    out.append(("extreme", 60.0, {"v": np.full_like(t, 50.0), "alpha": a, "slip": slip,
                                  "fz": np.full_like(t, 9000.0), "t_road": np.full_like(t, 45.0),
                                  "dt": np.full_like(t, dt)}))
    for name, t0, d in out:
        for k in ("v", "alpha", "slip", "t_road", "dt"):
            d[k] = qs(d[k])
        d["fz"] = ql(d["fz"])
    return [(name, float(qs(t0)), d) for name, t0, d in out]


def write_mf_thermal(path, rng):
    prm = mf_thermal.DEFAULT
    rows = []
    # forces at fixed temperatures over the valid box
    alphas = np.linspace(-0.35, 0.35, 29)
    slips = np.concatenate([np.linspace(-0.5, 1.0, 31), [0.0]])
    temps = [-30.0, 0.0, 30.0, 60.0, 100.0, 130.0]
    fzs = [0.0, 1000.0, 4600.0, 8000.0, 10000.0]
    A, S, F, T = np.meshgrid(alphas, slips, fzs, temps, indexing="ij")
    A, S, F, T = qs(A.ravel()), qs(S.ravel()), ql(F.ravel()), qs(T.ravel())
    n = 4000
    A = np.concatenate([A, qs(rng.uniform(-prm.alpha_max, prm.alpha_max, n))])
    S = np.concatenate([S, qs(rng.uniform(-prm.slip_max, prm.slip_max, n))])
    F = np.concatenate([F, ql(rng.uniform(0.0, prm.fz_max, n))])
    T = np.concatenate([T, qs(rng.uniform(prm.t_min, prm.t_max, n))])
    fx, fy = mf_thermal.forces(prm, A, S, F, T)
    pk = _thermal_peak(prm, F, T)
    for vals in zip(A, S, F, T, fx, fy, pk):
        rows.append("F " + " ".join(_fmt(v) for v in vals))
    # time series
    for k, (name, t_init, d) in enumerate(thermal_scenarios()):
        sim = mf_thermal.simulate(prm, t_init, d["v"], d["alpha"], d["slip"], d["fz"], d["t_road"], d["dt"])
        pk = _thermal_peak(prm, d["fz"], sim["t_before"])
        for i in range(len(d["dt"])):
            vals = (d["v"][i], d["alpha"][i], d["slip"][i], d["fz"][i], d["t_road"][i], d["dt"][i],
                    sim["t_before"][i], sim["fx"][i], sim["fy"][i], sim["q"][i], sim["vs"][i],
                    sim["t_after"][i], pk[i])
            rows.append(f"S {k} " + " ".join(_fmt(v) for v in vals))
    prow = "P " + " ".join(_fmt(getattr(prm, n)) for n in mf_thermal.PARAM_ORDER)
    with open(path, "w") as f:
        f.write(header("golden_mf89 (thermal)", mf_thermal.step, SEED,
                       ["tag", "see grip_tools/golden/mf89.py"], prm.as_dict()))
        f.write("# scenarios: " + " ".join(f"{k}={n}" for k, (n, _, _) in enumerate(thermal_scenarios())) + "\n")
        f.write(prow + "\n")
        for r in rows:
            f.write(r + "\n")
    return len(rows)


def write_golden(outdir):
    rng = np.random.default_rng(SEED)
    write_mf89(os.path.join(outdir, "mf89.txt"), rng)
    write_mf_thermal(os.path.join(outdir, "mf_thermal.txt"), rng)
    return 0


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip golden-mf89", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--outdir", default="build/golden")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    return write_golden(args.outdir)
