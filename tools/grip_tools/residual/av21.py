"""Dallara AV-21 (IAC, Putnam Park 2023 run 4_2; deep-dynamics repository,
GPL-3.0): axle lateral forces derived from the measured motion, modelled by
a Magic Formula from the slip angles, fed to the residual loop.

  ay  = vx r + dvy/dt                              (vx, vy, r from the INS)
  Fyf = (m lr ay + Iz dr/dt) / l,   Fyr = (m lf ay - Iz dr/dt) / l
  alpha_f = delta - atan((vy + lf r) / vx),  alpha_r = -atan((vy - lr r) / vx)
  Fz per tyre = axle static load / 2 -+ m ax h / (2 l)   (no aero: a candidate)

Sign of vy: the log's vy is taken as positive to the RIGHT (VY_SIGN = -1).
With vy positive left the derived axle forces correlate with the slip
angles with the wrong sign (r = +0.26 rear, -0.22 front, and a calibrated MF
collapses to its bounds); with -vy both axles give r = -0.75..-0.77 with
the ISO sign (alpha > 0 -> Fy < 0). vy also correlates +0.93 with r, which
for a left turn at speed means the rear slides outward only if vy points right.

Assumptions (not published for the car): Iz = 1000 kg m^2 (the source
repository identifies 500-2000), CG height h = 0.3 m. Derivatives: central
differences smoothed by a 5-sample (0.2 s) moving average. Samples from the
first time vx > 10 m/s to the end of the log.

The tyre model under test: the MF 6.1 set MagicFormula61_Paramerters.tir
with LMUY and LKY calibrated per axle on the training blocks (2 parameters;
no real AV-21 tyre file is available), alpha in ISO (alpha_iso = -alpha),
one tyre = half the axle.
"""
import os

import numpy as np
from scipy.optimize import least_squares

from .. import tir
from .attribution import block_masks
from .effects import TireModel
from .io import Dataset

SHARED = "/work/shared/data/iac-av21-deepdynamics/Putnam_park2023_run4_2.csv"
SUBSET = os.path.join(os.path.dirname(__file__), "..", "..", "..", "tests", "data", "iac-av21",
                      "putnam_run4_2_subset.csv")
TIR = "/work/shared/data/mfeval-tir/MagicFormula61_Paramerters.tir"
M, LF, LR, IZ, H, G = 790.0, 1.248, 1.7328, 1000.0, 0.3, 9.81
VY_SIGN = -1.0


def smooth(x, n=5):
    return np.convolve(x, np.ones(n) / n, mode="same")


def read(path=None):
    path = path or SHARED
    d = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    if d.shape[1] == 17:
        t, vx, vy, delta, r, ax = d[:, 0], d[:, 3], d[:, 4], d[:, 6], d[:, 7], d[:, 8]
    else:  # the subset: t, vx, vy, delta, omega, ax
        t, vx, vy, delta, r, ax = (d[:, i] for i in range(6))
    t = t - t[0]
    i0 = int(np.argmax(vx > 10.0))
    s = slice(i0, None)
    return {"t": t[s], "vx": vx[s], "vy": VY_SIGN * vy[s], "delta": delta[s], "r": r[s], "ax": ax[s]}, path


def axle_data(raw):
    t, vx, vy, r, delta = raw["t"], raw["vx"], raw["vy"], raw["r"], raw["delta"]
    ay = vx * r + smooth(np.gradient(vy, t))
    rdot = smooth(np.gradient(r, t))
    L = LF + LR
    fyf = (M * LR * ay + IZ * rdot) / L
    fyr = (M * LF * ay - IZ * rdot) / L
    v = np.maximum(vx, 1.0)
    af = delta - np.arctan((vy + LF * r) / v)
    ar = -np.arctan((vy - LR * r) / v)
    dfz = M * raw["ax"] * H / (2 * L)
    fzf = M * G * LR / L / 2 - dfz
    fzr = M * G * LF / L / 2 + dfz
    out = {}
    for name, a, fy, fz in (("front", af, fyf, fzf), ("rear", ar, fyr, fzr)):
        ch = {"t": t, "alpha": -a, "kappa": np.zeros_like(t), "gamma": np.zeros_like(t),
              "fz": fz, "vx": vx, "fy": fy / 2, "delta": delta, "r": r}
        units = {"t": "s", "alpha": "rad", "kappa": "-", "gamma": "rad", "fz": "N", "vx": "m/s",
                 "fy": "N", "delta": "rad", "r": "rad/s"}
        out[name] = Dataset(t, ch, units, ["fy"], {"axle": name})
    return out


def calibrate(ds, params):
    """LMUY, LKY of the base set fitted on the training blocks."""
    train, _ = block_masks(len(ds))

    def res(x):
        m = TireModel(dict(params, lmuy=x[0], lky=x[1]))
        return (ds.ch["fy"] - m.predict(ds.ch)["fy"])[train]
    x = least_squares(res, [1.0, 1.0], bounds=([0.2, 0.05], [3.0, 5.0])).x
    return TireModel(dict(params, lmuy=x[0], lky=x[1]), f"MF61 LMUY={x[0]:.3f} LKY={x[1]:.3f}"), x


def load_all(path=None):
    raw, path = read(path)
    P = tir.load_params(TIR)
    res = {}
    for name, ds in axle_data(raw).items():
        ds.meta["source"] = f"{path} ({name} axle, derived lateral force per tyre)"
        model, _ = calibrate(ds, P)
        res[name] = (ds, model)
    return res


def load(path=None, axle="front"):
    ds, model = load_all(path)[axle]
    return ds, model
