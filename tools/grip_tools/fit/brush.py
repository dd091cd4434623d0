"""Identify Neo-FIALA parameters from force and moment sweeps.

  grip fit-brush --csv sweeps.csv [--out DIR]
      sweeps: CSV with columns kappa, alpha, gamma, fz, vx, fx, fy, mz (SI,
      ISO-W, radians; an optional column `weight`); one parameter set is
      identified per distinct fz (the seed's Table 5.4 is per load too).
  grip fit-brush --g275 [--tir FILE] [--loads 13000,21674,30000] [--out DIR]
      the demonstration: sweeps generated from the Magic Formula of a
      Goodyear G275 .tir file (tools/grip_tools/reference/mf.py, tir.py) at three
      loads, pure slip (Fx(kappa), Fy(alpha), Mz(alpha)) and combined slip
      (kappa sweeps at alpha = 2 and 5 deg), fitted per load; prints and
      writes the RMS error of Fx, Fy and Mz in pure and combined slip.

Identified per load: mu_s, mu_d0, a_v, Kx, Ky, l, n (integer 2..8, the best
of a fit per n), q0, c_q, c_xc, eps, G_mz, Ax. The parameters are fitted in
normalized form with bounds that keep the set inside the library's valid
range (brush.validate), by scipy.optimize.least_squares (trust-region
reflective, robust soft-L1 loss off). Residuals: forces / Fz, moments /
(Fz * 0.05 m). Writes one parameter file per load (brush.write_params; the
C reader port/linux/brush_params.c and grip-tire read it) and report.md.
Method and the G275 results: docs/brush-models.md, "Fitting".
"""
import argparse
import csv
import math
import os
import sys

import numpy as np
from scipy import optimize

from grip_tools.errors import DataError
from grip_tools.paths import TEST_DATA
from grip_tools.reference import brush as B

MZ_SCALE = 0.05                   # m: residual of Mz is Mz / (Fz * MZ_SCALE)
DEG = math.pi / 180.0

# normalized parameter vector: name, lower, upper, start
PARAMS = [
    ("mu_s", 0.3, 2.0, 1.0),
    ("rd", 0.5, 1.0, 0.85),       # mu_d0 / mu_s (>= 0.5: physically plausible sets)
    ("a_v", 0.0, 0.05, 0.002),    # s/m
    ("kx_n", 2.0, 60.0, 10.0),    # Kx / Fz
    ("ky_n", 1.0, 40.0, 8.0),     # Ky / Fz [1/rad]
    ("l", 0.04, 0.6, 0.2),        # m
    ("q0", -0.45, 0.45, 0.0),
    ("cq_n", -0.13, 0.13, 0.0),   # c_q mu_s Fz
    ("cxc_n", -0.06, 0.06, 0.0),  # c_xc mu_s Fz
    ("eps_n", 0.0, 1.4, 0.2),     # eps l Ky
    ("g_n", 0.0, 1.4, 0.2),       # Ky l / G_mz
    ("ax_n", -0.045, 0.045, 0.0), # Ax / (mu_s Fz l)
]
FZ_MIN_FACTOR = 0.5               # parameter file: fz_min = 0.5 Fz, fz_max = 1.5 Fz
FZ_MAX_FACTOR = 1.5


def _g_mz(kyl, g_n):
    """G_mz from Ky l / G_mz; a twist too small for the fixed-point format
    (G_mz > 2e6 N m/rad, i.e. g_n < Ky l / 2e6) is the rigid tread base, 0."""
    return kyl / g_n if g_n > kyl / 2.0e6 else 0.0


def params_from_vector(theta, fz, n, vx_max=60.0):
    d = dict(zip([p[0] for p in PARAMS], theta))
    mu_s = d["mu_s"]
    f0 = mu_s * fz
    ky = d["ky_n"] * fz
    l = d["l"]
    return B.NeoFiala(
        l=l, w=0.3, kx=d["kx_n"] * fz, ky=ky, mu_s=mu_s, mu_d0=mu_s * d["rd"], a_v=d["a_v"], n=int(n),
        q0=d["q0"], c_q=d["cq_n"] / f0, c_qm=0.0, c_xc=d["cxc_n"] / f0, xi=0.0,
        eps=d["eps_n"] / (l * ky), g_mz=_g_mz(ky * l, d["g_n"]),
        a_x=d["ax_n"] * f0 * l, c_gamma=0.0, h=0.0, g_my=0.0,
        fz_min=FZ_MIN_FACTOR * fz, fz_max=FZ_MAX_FACTOR * fz, alpha_max=1.0, kappa_max=1.0,
        gamma_max=0.2, v_max=max(vx_max, 1.0))


def model_outputs(p, data):
    """The model on every sweep point: the C library's algorithm (fixed
    iteration, float64, vectorized: brush.neofiala_vec)."""
    r = B.neofiala_vec(p, data["kappa"], data["alpha"], data["gamma"], data["fz"], data["vx"])
    return np.stack([r["fx"], r["fy"], r["mz"]], axis=1)


def _residuals(theta, n, data, fz, use):
    p = params_from_vector(theta, fz, n, float(np.max(data["vx"])) + 1.0)
    m = model_outputs(p, data)
    r = []
    w = data["weight"]
    if use[0]:
        r.append(w * (m[:, 0] - data["fx"]) / fz)
    if use[1]:
        r.append(w * (m[:, 1] - data["fy"]) / fz)
    if use[2]:
        r.append(w * (m[:, 2] - data["mz"]) / (fz * MZ_SCALE))
    return np.concatenate(r)


def fit_load(data, fz, ns=range(B.N_MIN, B.N_MAX + 1), max_nfev=800, verbose=False, fit_groups=None):
    """Best parameter set for one load over the exponents ns. data: dict of
    arrays (kappa, alpha, gamma, fz, vx, fx, fy, mz, weight, group); only the
    rows whose group is in fit_groups (None: all) enter the fit. Returns
    (NeoFiala, cost, n)."""
    if fit_groups is not None:
        sel = np.isin(data["group"], list(fit_groups))
        data = {k: v[sel] for k, v in data.items()}
    lo = np.array([p[1] for p in PARAMS])
    hi = np.array([p[2] for p in PARAMS])
    x0 = np.array([p[3] for p in PARAMS])
    # a start from the data: friction from the largest force, stiffness from small slips
    fmax = max(np.max(np.abs(data["fx"])), np.max(np.abs(data["fy"])))
    x0[0] = np.clip(1.05 * fmax / fz, lo[0], hi[0])
    small_a = (np.abs(data["alpha"]) > 1e-4) & (np.abs(data["alpha"]) < 0.02) & (data["kappa"] == 0)
    if np.any(small_a):
        x0[4] = np.clip(np.median(np.abs(data["fy"][small_a] / np.tan(data["alpha"][small_a]))) / fz, lo[4], hi[4])
    small_k = (np.abs(data["kappa"]) > 1e-4) & (np.abs(data["kappa"]) < 0.02) & (data["alpha"] == 0)
    if np.any(small_k):
        x0[3] = np.clip(np.median(np.abs(data["fx"][small_k] / data["kappa"][small_k])) / fz, lo[3], hi[3])
    small_m = small_a & (np.abs(data["fy"]) > 1.0)
    if np.any(small_m):
        trail = np.median(np.abs(data["mz"][small_m] / data["fy"][small_m]))
        x0[5] = np.clip(6.0 * trail, lo[5], hi[5])
    best = None
    for n in ns:
        res = optimize.least_squares(_residuals, x0, bounds=(lo, hi), args=(n, data, fz, (1, 1, 1)),
                                     max_nfev=max_nfev, x_scale="jac", diff_step=1e-4)
        if verbose:
            print(f"#   n = {n}: cost {res.cost:.5g}", file=sys.stderr)
        if best is None or res.cost < best[1]:
            best = (res.x, res.cost, n)
    p = params_from_vector(best[0], fz, best[2], float(np.max(data["vx"])) + 1.0)
    bad = B.validate("neofiala", p)
    if bad:
        raise RuntimeError(f"fit left the valid range: {bad}")
    return p, best[1], best[2]


def rms_report(p, data, groups):
    """RMS of (model - data) per group name -> (rms_fx, rms_fy, rms_mz)."""
    m = model_outputs(p, data)
    out = {}
    for name in groups:
        sel = data["group"] == name
        if not np.any(sel):
            continue
        e = m[sel] - np.stack([data["fx"][sel], data["fy"][sel], data["mz"][sel]], axis=1)
        out[name] = tuple(float(np.sqrt(np.mean(e[:, j] ** 2))) for j in range(3))
    return out


# ---------------------------------------------------------------------------
# Magic Formula sweeps (G275 demonstration)

G275_DEFAULT = os.path.join(TEST_DATA, "chrono-tir", "335_65R22_5_G275MSA_60psi.tir")


def mf_sweeps(tir_path, fz):
    from grip_tools.reference import mf, tir
    params = tir.load_params(tir_path)
    vx = float(params.get("longvl", 16.5))
    k_lo = max(float(params.get("kpumin", -0.8)), -0.99)
    a_hi = float(params.get("alpmax", 0.2))
    rows = []
    # pure longitudinal (the G275 files are fitted in braking only: KPUMAX = 0)
    for k in np.concatenate([np.linspace(k_lo, -0.1, 15), np.linspace(-0.09, -0.005, 18)]):
        rows.append(("pure_fx", k, 0.0))
    # pure lateral
    for a in np.concatenate([-np.linspace(0.004, a_hi, 12)[::-1], np.linspace(0.004, a_hi, 12)]):
        rows.append(("pure_fy_mz", 0.0, a))
    # combined: braking at alpha = 2 and 5 deg
    for a in (2.0 * DEG, 5.0 * DEG):
        for k in np.linspace(max(k_lo, -0.5), -0.005, 16):
            rows.append(("combined", k, a))
    kap = np.array([r[1] for r in rows])
    alp = np.array([r[2] for r in rows])
    out = mf.evaluate(params, kap, alp, np.zeros_like(kap), np.full_like(kap, fz), vx=np.full_like(kap, vx))
    data = dict(kappa=kap, alpha=alp, gamma=np.zeros_like(kap), fz=np.full_like(kap, fz), vx=np.full_like(kap, vx),
                fx=np.asarray(out["fx"], float), fy=np.asarray(out["fy"], float), mz=np.asarray(out["mz"], float),
                group=np.array([r[0] for r in rows]), weight=np.ones_like(kap))
    # pure_fx rows carry no lateral information and pure_fy_mz rows no longitudinal:
    # both are fitted on all three outputs (the model's Fy = Mz = 0 at alpha = 0 and
    # Fx = 0 at kappa = 0 match the MF there to within its small offsets)
    return data


def g275_demo(tir_path, loads, outdir, ns=range(B.N_MIN, B.N_MAX + 1), max_nfev=800, verbose=True,
              fit_groups=("pure_fx", "pure_fy_mz")):
    os.makedirs(outdir, exist_ok=True)
    lines = ["# Neo-FIALA fitted to the Magic Formula of " + os.path.basename(tir_path), "",
             "RMS error of Neo-FIALA against the MF curves (N, N m; in brackets % of Fz, "
             "% of Fz x 0.05 m for Mz). Pure: Fx(kappa) at alpha = 0; Fy(alpha), Mz(alpha) "
             "at kappa = 0. Combined: kappa sweeps (braking) at alpha = 2 and 5 deg.", "",
             f"Fitted to: {'all sweeps' if fit_groups is None else ', '.join(fit_groups)}.", "",
             "| Fz [N] | n | mu_s | mu_d0 | Kx [kN] | Ky [kN/rad] | l [m] | pure Fx | pure Fy | pure Mz "
             "| comb. Fx | comb. Fy | comb. Mz |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    results = []
    for fz in loads:
        data = mf_sweeps(tir_path, fz)
        if verbose:
            print(f"# fitting Fz = {fz:g} N ({len(data['kappa'])} points)", file=sys.stderr)
        p, cost, n = fit_load(data, fz, ns=ns, max_nfev=max_nfev, verbose=verbose, fit_groups=fit_groups)
        rep = rms_report(p, data, ("pure_fx", "pure_fy_mz", "combined"))
        pure = (rep["pure_fx"][0], rep["pure_fy_mz"][1], rep["pure_fy_mz"][2])
        comb = rep["combined"]
        results.append(dict(fz=fz, n=n, params=p, pure=pure, combined=comb, cost=cost))
        B.write_params(os.path.join(outdir, f"neofiala_g275_{int(round(fz))}N.txt"), "neofiala", p,
                       comment=f"fitted by grip_tools fit-brush to the MF of {os.path.basename(tir_path)} at Fz = {fz:g} N")

        def cell(v, scale):
            return f"{v:.0f} ({100.0 * v / scale:.1f} %)"
        lines.append(f"| {fz:.0f} | {n} | {p.mu_s:.3f} | {p.mu_d0:.3f} | {p.kx / 1000:.0f} | {p.ky / 1000:.0f} "
                     f"| {p.l:.3f} | {cell(pure[0], fz)} | {cell(pure[1], fz)} | {cell(pure[2], fz * MZ_SCALE)} "
                     f"| {cell(comb[0], fz)} | {cell(comb[1], fz)} | {cell(comb[2], fz * MZ_SCALE)} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "report.md"), "w") as f:
        f.write(text)
    return results, text


# ---------------------------------------------------------------------------

def read_sweeps_csv(path):
    """The sweeps CSV: a header row naming at least NEED, one number per
    cell; anything else is a DataError naming the file, line and column."""
    need = ("kappa", "alpha", "gamma", "fz", "vx", "fx", "fy", "mz")
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames or []
        missing = [k for k in need if k not in header]
        if missing:
            raise DataError(path, 1, missing[0], f"missing column (need {', '.join(need)})")
        cols = {k: [] for k in need + ("weight",)}
        for i, r in enumerate(reader, start=2):
            for k in need + ("weight",):
                cell = r.get(k)
                if k == "weight" and not cell:
                    cols[k].append(1.0)
                    continue
                try:
                    v = float(cell)
                except (TypeError, ValueError):
                    raise DataError(path, i, k, f"{cell!r} is not a number") from None
                if not math.isfinite(v):
                    raise DataError(path, i, k, f"{cell!r} is not finite")
                cols[k].append(v)
    if not cols["fz"]:
        raise DataError(path, 2, "-", "no data rows")
    out = {k: np.array(v) for k, v in cols.items()}
    out["group"] = np.array(["all"] * len(out["fz"]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip fit-brush", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", help="sweeps to fit (see above)")
    ap.add_argument("--g275", action="store_true", help="run the G275 Magic Formula demonstration")
    ap.add_argument("--tir", default=G275_DEFAULT)
    ap.add_argument("--loads", default="13000,21674,30000", help="loads of the demonstration [N]")
    ap.add_argument("--n", default=None, help="fit only these exponents, e.g. 3,4")
    ap.add_argument("--max-nfev", type=int, default=800)
    ap.add_argument("--fit-combined", action="store_true",
                    help="G275: fit pure and combined sweeps together (default: pure slip only, as the seed's "
                         "Table 5.4; combined slip is then a prediction)")
    ap.add_argument("--out", default="build/fit_brush")
    args = ap.parse_args(argv)
    try:
        ns = [int(v) for v in args.n.split(",")] if args.n else list(range(B.N_MIN, B.N_MAX + 1))
    except ValueError:
        ns = []
    if not ns or any(not B.N_MIN <= n <= B.N_MAX for n in ns):
        ap.error(f"--n {args.n!r}: comma-separated exponents in [{B.N_MIN}, {B.N_MAX}]")
    if args.max_nfev < 1:
        ap.error(f"--max-nfev {args.max_nfev}: at least 1")
    if args.g275:
        try:
            loads = [float(v) for v in args.loads.split(",")]
        except ValueError:
            loads = []
        if not loads or any(not (math.isfinite(v) and 0.0 < v <= 1.0e5) for v in loads):
            ap.error(f"--loads {args.loads!r}: comma-separated loads in (0, 100000] N")
        groups = None if args.fit_combined else ("pure_fx", "pure_fy_mz")
        _, text = g275_demo(args.tir, loads, args.out, ns=ns, max_nfev=args.max_nfev, fit_groups=groups)
        print(text)
        print(f"parameter files and report.md in {args.out}", file=sys.stderr)
        return 0
    if not args.csv:
        ap.error("give --csv FILE or --g275")
    data = read_sweeps_csv(args.csv)
    os.makedirs(args.out, exist_ok=True)
    for fz in sorted(set(np.round(data["fz"], 6))):
        sel = np.abs(data["fz"] - fz) < 1e-6
        d = {k: v[sel] for k, v in data.items()}
        p, cost, n = fit_load(d, fz, ns=ns, max_nfev=args.max_nfev)
        rep = rms_report(p, d, ("all",))["all"]
        path = os.path.join(args.out, f"neofiala_{int(round(fz))}N.txt")
        B.write_params(path, "neofiala", p, comment=f"fitted by grip_tools fit-brush to {args.csv} at Fz = {fz:g} N")
        print(f"Fz = {fz:g} N: n = {n}, RMS Fx {rep[0]:.1f} N, Fy {rep[1]:.1f} N, Mz {rep[2]:.2f} N m -> {path}")
    return 0
