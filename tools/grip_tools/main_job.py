"""The README's main job until the estimator replays the RAV4 log: evaluate
the Magic Formula of a real tire with grip's C library (grip-tire, float and
fixed builds) and with the float64 reference, print the error table and plot
the curves.

Tire: Goodyear G275 MSA 335/65R22.5 at 60 psi, an MF-Tyre 5.x (PAC2002) file
fitted to Calspan flat-belt measurements (tests/data/chrono-tir).
"""
import argparse
import csv
import io
import os
import subprocess
import sys

import numpy as np

from . import golden_mf, mf, tir

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TIRE = os.path.join(golden_mf.shared_data_dir(), "chrono-tir", "335_65R22_5_G275MSA_60psi.tir")
COLS = ["kappa", "alpha", "gamma", "fz", "p", "vx"]


def sweeps(params):
    """Pure longitudinal, pure lateral and combined sweeps at three loads."""
    fnom = params["fnomin"]
    vx = params["longvl"]
    rows = []
    for load in (0.5, 1.0, 1.5):
        fz = load * fnom
        for k in np.linspace(-0.5, 0.5, 201):
            rows.append(("pure_kappa", load, k, 0.0, 0.0, fz, 0.0, vx))
        for a in np.radians(np.linspace(-15, 15, 201)):
            rows.append(("pure_alpha", load, 0.0, a, 0.0, fz, 0.0, vx))
        for k in np.linspace(-0.5, 0.5, 201):
            rows.append(("combined_alpha4", load, k, np.radians(4.0), 0.0, fz, 0.0, vx))
    return rows


def run_grip_tire(binary, tire, rows):
    text = io.StringIO()
    w = csv.writer(text)
    w.writerow(["case", "load"] + COLS)
    for r in rows:
        w.writerow([r[0], r[1]] + [repr(float(v)) for v in r[2:]])
    run = subprocess.run([binary, "--tir", tire], input=text.getvalue(), capture_output=True,
                         text=True)
    if run.returncode != 0:
        raise SystemExit(f"main job: {binary} failed ({run.returncode}): {run.stderr.strip()}")
    out = list(csv.DictReader(io.StringIO(run.stdout)))
    return {k: np.array([float(o[k]) for o in out]) for k in ("fx", "fy", "mz")}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip_tools main-job", description=__doc__)
    ap.add_argument("--outdir", default=os.path.join(ROOT, "build", "main-job"))
    ap.add_argument("--tir", default=TIRE)
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    params = tir.load_params(args.tir)
    rows = sweeps(params)
    inputs = np.array([r[2:] for r in rows], dtype=float)
    ref = mf.evaluate(params, *[inputs[:, i] for i in range(5)], vx=inputs[:, 5])
    c_out = {a: run_grip_tire(os.path.join(ROOT, f"build/{a}-gcc/bin/grip-tire"), args.tir, rows)
             for a in ("float", "fixed")}

    fz = inputs[:, 3]
    print(f"grip main job: Magic Formula of {os.path.basename(args.tir)} "
          f"(FITTYP {params['fittyp']}, FNOMIN {params['fnomin']:.0f} N), {len(rows)} evaluations")
    print(f"{'build':6s} {'output':4s} {'max |err|':>12s} {'max |err|/Fz':>13s} {'max |err|/peak':>15s}")
    for a in ("float", "fixed"):
        for k in ("fx", "fy", "mz"):
            err = np.abs(c_out[a][k] - ref[k])
            peak = np.max(np.abs(ref[k]))
            unit = "N m" if k == "mz" else "N"
            print(f"{a:6s} {k:4s} {np.max(err):9.3g} {unit:3s} {np.max(err / fz):12.2e} "
                  f"{np.max(err) / peak:14.2e}")

    with open(os.path.join(args.outdir, "mf_curves.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "load"] + COLS + ["fx_ref", "fy_ref", "mz_ref", "fx_float", "fy_float",
                                              "mz_float", "fx_fixed", "fy_fixed", "mz_fixed"])
        for i, r in enumerate(rows):
            w.writerow(list(r) + [ref[k][i] for k in ("fx", "fy", "mz")]
                       + [c_out[a][k][i] for a in ("float", "fixed") for k in ("fx", "fy", "mz")])
    plot(rows, inputs, ref, c_out, os.path.join(args.outdir, "mf_curves.png"), args.tir)
    print(f"wrote {args.outdir}/mf_curves.csv and mf_curves.png")
    return 0


def plot(rows, inputs, ref, c_out, path, tire):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = np.array([r[0] for r in rows])
    loads = np.array([r[1] for r in rows])
    panels = [("pure_kappa", 0, "fx", "slip ratio [-]", "Fx [kN]"),
              ("pure_alpha", 1, "fy", "slip angle [deg]", "Fy [kN]"),
              ("pure_alpha", 1, "mz", "slip angle [deg]", "Mz [kN m]"),
              ("combined_alpha4", 0, "fx", "slip ratio at alpha = 4 deg [-]", "Fx [kN] (combined)")]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    for ax, (case, col, out, xl, yl) in zip(axes.flat, panels):
        for load in (0.5, 1.0, 1.5):
            m = (cases == case) & (loads == load)
            x = inputs[m, col] * (180 / np.pi if col == 1 else 1)
            ax.plot(x, ref[out][m] / 1e3, "k-", lw=1)
            ax.plot(x[::8], c_out["float"][out][m][::8] / 1e3, "o", color="tab:blue", ms=4, mfc="none")
            ax.plot(x[::8], c_out["fixed"][out][m][::8] / 1e3, "x", color="tab:red", ms=4)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(["float64 reference", "grip float", "grip fixed"], fontsize=8)
    fig.suptitle(f"grip Magic Formula vs reference: {os.path.basename(tire)} at 0.5/1.0/1.5 FNOMIN")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    sys.exit(main())
