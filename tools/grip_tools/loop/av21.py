"""Dallara AV-21 (IAC, Putnam Park 2023 run 4_2; deep-dynamics repository,
GPL-3.0): axle lateral forces derived from the measured motion, modelled by
a Magic Formula from the slip angles, fed to the residual loop.

  vy_cg, ay = av21_log.lateral_at_cg(...)          (vx, vy, r from the INS;
              vy in the log's own sign, moved from the INS 0.49 m ahead of
              the CG to the CG; ay = vx r + d(vy_cg)/dt)
  Fyf = (m lr ay + Iz dr/dt) / l,   Fyr = (m lf ay - Iz dr/dt) / l
  alpha_f = delta - atan((vy_cg + lf r) / vx),  alpha_r = -atan((vy_cg - lr r) / vx)
  Fz per tyre = axle static load / 2 -+ m ax h / (2 l)   (no aero: a candidate)

vy is read in the log's own sign and moved from the INS to the CG; vy
turned over, or left at the INS, contradicts the kinematics of the slow
corners (logs/av21.py, docs/measured-data-loop.md, "AV-21"). The logged delta is a steering command the road wheels
follow about 0.28 s late (est_eval.steer_lag_fit): that is NOT corrected
here, it is what the loop should find.

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

from grip_tools.logs import av21 as av21_log
from grip_tools.paths import TEST_DATA
from grip_tools.reference import tir
from grip_tools.loop.attribution import block_masks
from grip_tools.loop.effects import TireModel
from grip_tools.loop.io import Dataset

TIR = os.path.join(TEST_DATA, "mfeval-tir", "MagicFormula61_Paramerters.tir")
M, LF, LR, IZ, H, G = av21_log.MASS, av21_log.LF, av21_log.LR, 1000.0, 0.3, 9.81


def read(path=None):
    """The log from the first time vx > 10 m/s, vy at the CG (log's sign) and
    the lateral acceleration there."""
    path = path or av21_log.LOG
    d = av21_log.read(path)
    vy, ay, _ = av21_log.lateral_at_cg(d["t"], d["vx"], d["vy"], d["r"], av21_log.INS_X)
    i0 = int(np.argmax(d["vx"] > 10.0))
    s = slice(i0, None)
    return {"t": d["t"][s], "vx": d["vx"][s], "vy": vy[s], "ay": ay[s], "delta": d["delta"][s], "r": d["r"][s],
            "ax": d["ax"][s]}, path


def axle_data(raw):
    t, vx, vy, r, delta, ay = raw["t"], raw["vx"], raw["vy"], raw["r"], raw["delta"], raw["ay"]
    rdot = av21_log.smooth(np.gradient(r, t))
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
        out[name] = Dataset(t, ch, units, ["fy"], {"axle": name, "derived": ("fy", "fz", "alpha")})
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
