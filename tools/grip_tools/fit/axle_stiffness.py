"""Per-axle cornering stiffness without tire data: a rear-axle .tir whose
cornering stiffness gives the car's measured understeer gradient.

The linear single-track model (seed 000, eqs 2.13-2.19) ties the
understeer gradient K [rad per m/s^2] to the axles' cornering stiffnesses:

    delta = l / R + K ay,        K = (m / l) (lr / Cf - lf / Cr)

Cf, Cr [N/rad]: both tires of an axle at its static load. One gradient
fixes the balance of the two axles, not their level: this tool keeps the
front axle's tire as given (its stiffness sets the steering's yaw gain)
and scales the rear tire's cornering stiffness (LKY) so that the pair has
the measured K. The level comes from a tire fitted to the car (a ramp steer
fitted by `grip fit-mf`, docs/independent-judge.md) or from the tire file.

K from a steady-state ramp (constant speed, steering rising slowly): the
slope of the road-wheel angle less l r / vx against ay, over ay below
--ay-max (the linear range):

    grip axle-stiffness --tir FRONT.tir --mass 1450 --lf 1.1 --lr 1.6 \\
        --understeer-gradient 0.0025 -o rear.tir
    grip axle-stiffness --tir FRONT.tir --mass 1450 --lf 1.1 --lr 1.6 \\
        --ramp ramp.csv --steer-ratio 15.5 -o rear.tir

The ramp CSV needs a header row naming the columns steer_angle [rad, at
the steering wheel], yaw_rate [rad/s], ay [m/s^2] and vx [m/s] (others are
ignored); lines of at most 8 KiB, at most 1,000,000 rows. The rear file is grip-replay's --estimate-rear and
grip_est_config_t.tire[1].
"""
import argparse
import math
import os

import numpy as np

from grip_tools.errors import DataError, UsageError
from grip_tools.loop.report import write_tir
from grip_tools.reference import mf, tir

G = 9.80665


def axle_stiffness(params, fz):
    """Cornering stiffness of one tire at load fz [N/rad] (the slope of Fy
    at alpha = 0, central difference of +-0.01 rad)."""
    o = mf.evaluate(params, np.zeros(2), np.array([0.01, -0.01]), 0.0, np.full(2, fz), None, 20.0)
    return abs(float(o["fy"][1] - o["fy"][0]) / 0.02)


def understeer_gradient(mass, lf, lr, cf, cr):
    """K [rad per m/s^2] of axle stiffnesses cf, cr [N/rad, whole axle]."""
    l = lf + lr
    return mass / l * (lr / cf - lf / cr)


def rear_scale(params, mass, lf, lr, k_us, params_rear=None):
    """The factor on the rear tire's cornering stiffness that gives the
    understeer gradient k_us with params on the front axle (and params_rear,
    default the same tire, on the rear). Returns (scale, cf, cr, k_tire)."""
    l = lf + lr
    fzf, fzr = G * mass * lr / l / 2.0, G * mass * lf / l / 2.0
    pr = params if params_rear is None else params_rear
    cf, cr = 2.0 * axle_stiffness(params, fzf), 2.0 * axle_stiffness(pr, fzr)
    k_tire = understeer_gradient(mass, lf, lr, cf, cr)
    den = lr / cf - k_us * l / mass
    if den <= 0.0:
        raise DataError(None, None, "understeer_gradient",
                        f"{k_us:.6g} rad/(m/s^2) needs a rear axle stiffer than any tire with this front axle "
                        f"({cf:.0f} N/rad): lr / Cf = {lr / cf:.3g} is at most K l / m = {k_us * l / mass:.3g}")
    cr_needed = lf / den
    # LKY scales Kya; the slope at +-0.01 rad also carries the curve's
    # shape, which moves with B = Kya / (C D): a few fixed-point steps on
    # the scale make the slope itself the one needed
    scale = cr_needed / cr
    for _ in range(4):
        p2 = dict(pr)
        p2["lky"] = float(pr.get("lky", 1.0)) * scale
        scale *= cr_needed / (2.0 * axle_stiffness(p2, fzr))
    return scale, cf, cr, k_tire


def gradient_from_ramp(steer, yaw, ay, vx, lf, lr, steer_ratio, ay_max=4.0, v_min=5.0):
    """K [rad per m/s^2] from a steady-state ramp: least squares of
    delta - l r / vx = K ay (+ an offset) over |ay| <= ay_max, vx >= v_min.
    Returns (K, its standard error, rows used)."""
    l = lf + lr
    steer, yaw, ay, vx = (np.asarray(a, float) for a in (steer, yaw, ay, vx))
    ok = np.isfinite(steer) & np.isfinite(yaw) & np.isfinite(ay) & np.isfinite(vx) & (vx >= v_min) & (np.abs(ay) <= ay_max)
    n = int(ok.sum())
    if n < 20 or np.ptp(ay[ok]) < 1.0:
        raise DataError(None, None, "ay",
                        f"the ramp has {n} usable rows (speed >= {v_min} m/s, |ay| <= {ay_max} m/s^2) spanning "
                        f"{float(np.ptp(ay[ok])) if n else 0.0:.2f} m/s^2 of ay: at least 20 rows over 1 m/s^2 "
                        "are needed")
    y = steer[ok] / steer_ratio - l * yaw[ok] / vx[ok]
    a = np.column_stack([ay[ok], np.ones(n)])
    coef, res, _, _ = np.linalg.lstsq(a, y, rcond=None)
    resid = y - a @ coef
    cov = np.linalg.inv(a.T @ a) * float(resid @ resid) / max(n - 2, 1)
    return float(coef[0]), float(math.sqrt(cov[0, 0])), n


RAMP_COLUMNS = ("steer_angle", "yaw_rate", "ay", "vx")
MAX_LINE, MAX_ROWS = 8192, 1000000


def read_ramp(path):
    """{column: array} of a ramp CSV (RAMP_COLUMNS); DataError naming the
    file, line and field of anything unusable."""
    if not os.path.isfile(path):
        raise UsageError(f"{path}: no such file")
    out, idx = {c: [] for c in RAMP_COLUMNS}, None
    with open(path, "rb") as f:
        for line_no, raw in enumerate(iter(lambda: f.readline(MAX_LINE + 1), b""), 1):
            if len(raw) > MAX_LINE:
                raise DataError(path, line_no, None, f"line longer than the cap of {MAX_LINE} bytes")
            try:
                text = raw.decode("utf-8").strip()
            except UnicodeDecodeError as e:
                raise DataError(path, line_no, None, f"not UTF-8 at byte {e.start}") from None
            if not text or text.startswith("#"):
                continue
            cells = [c.strip() for c in text.split(",")]
            if idx is None:
                missing = [c for c in RAMP_COLUMNS if c not in cells]
                if missing:
                    raise DataError(path, line_no, ",".join(missing), "column missing from the header")
                idx = {c: cells.index(c) for c in RAMP_COLUMNS}
                continue
            if line_no > MAX_ROWS:
                raise DataError(path, line_no, None, f"more than {MAX_ROWS} rows")
            for c, k in idx.items():
                try:
                    v = float(cells[k])
                except (IndexError, ValueError):
                    raise DataError(path, line_no, c, f"not a number: {cells[k] if k < len(cells) else ''!r}") from None
                if not math.isfinite(v):
                    raise DataError(path, line_no, c, f"not finite: {cells[k]}")
                out[c].append(v)
    if idx is None:
        raise DataError(path, None, None, "no header row")
    return {c: np.array(v) for c, v in out.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip axle-stiffness", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tir", required=True, help="the tire (front axle, and the rear's starting point)")
    ap.add_argument("--mass", type=float, required=True, help="kg")
    ap.add_argument("--lf", type=float, required=True, help="m, CG to front axle")
    ap.add_argument("--lr", type=float, required=True, help="m, CG to rear axle")
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--understeer-gradient", type=float, help="K [rad per m/s^2] (deg/g: divide by 562.4)")
    src.add_argument("--ramp", help="CSV of a steady-state ramp: steer_angle, yaw_rate, ay, vx")
    ap.add_argument("--steer-ratio", type=float, help="with --ramp: steering-wheel / road-wheel angle")
    ap.add_argument("--ay-max", type=float, default=4.0, help="with --ramp: linear range [m/s^2] (default 4)")
    ap.add_argument("--side", choices=("fitted", "left", "right"), default="fitted",
                    help="how the .tir is mounted (default: as fitted)")
    ap.add_argument("-o", "--output", required=True, help="the rear axle's .tir to write")
    a = ap.parse_args(argv)
    for name in ("mass", "lf", "lr"):
        v = getattr(a, name)
        if not (math.isfinite(v) and v > 0.0):
            raise UsageError(f"--{name} must be a positive number, not {v}")
    if not os.path.isfile(a.tir):
        raise UsageError(f"{a.tir}: no such file")
    params = tir.load_params(a.tir, side=a.side)
    if a.ramp is not None:
        if a.steer_ratio is None or not (a.steer_ratio >= 1.0):
            raise UsageError("--ramp needs --steer-ratio (>= 1)")
        cols = read_ramp(a.ramp)
        k_us, k_se, n = gradient_from_ramp(cols["steer_angle"], cols["yaw_rate"], cols["ay"], cols["vx"],
                                           a.lf, a.lr, a.steer_ratio, a.ay_max)
        print(f"understeer gradient from {a.ramp}: {k_us:.6g} +- {k_se:.2g} rad/(m/s^2) "
              f"({k_us * 180 / math.pi * G:.3f} deg/g) over {n} rows")
    else:
        k_us = a.understeer_gradient
        if not math.isfinite(k_us):
            raise UsageError("--understeer-gradient must be finite")
    scale, cf, cr, k_tire = rear_scale(params, a.mass, a.lf, a.lr, k_us)
    lky = float(params.get("lky", 1.0)) * scale
    write_tir(a.tir, {"LKY": lky}, a.output, note=f"grip axle-stiffness (K {k_us:.6g} rad/(m/s^2))")
    print(f"tire {os.path.basename(a.tir)} on both axles: Cf {cf:.0f}, Cr {cr:.0f} N/rad, K {k_tire:.6g} rad/(m/s^2); "
          f"rear x {scale:.4f} (LKY {lky:.6g}) gives K {k_us:.6g}: {a.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
