"""Tyre adapter of the vehicle simulator.

The simulator never evaluates Magic Formula equations itself: every force
comes from the project's float64 reference tools/grip_tools/reference/mf.py through the
small adapter class `MFTire` below (one call per model evaluation for all
wheels of all vehicles of a batch). Swapping the tyre model means replacing
this adapter only.

What the adapter adds on top of mf.evaluate:
  * per-wheel friction and stiffness scaling (road mu and tyre temperature
    enter as multipliers of LMUX/LMUY and LKX/LKY of the file),
  * per-wheel mounting side (a tyre fitted on one side is mirrored on the
    other: alpha -> -alpha, Fy -> -Fy, Mz -> -Mz),
  * relaxation lengths from the same file (MF 6.x: sigma = K / carcass
    stiffness; MF 5.2 / PAC2002: PTX1..3, PTY1..2),
  * rolling-resistance coefficient QSY1 and vertical stiffness from the file.

Axis system: ISO-W as mf.py (x forward, y left, z up; kappa > 0 driving;
alpha > 0 when the contact centre moves to the left of the wheel heading,
i.e. tan(alpha) = Vcy / |Vcx|, which gives Fy < 0 for a normal tyre).
"""
import os

import numpy as np

from grip_tools.golden import mf as golden_mf
from grip_tools.reference import mf, tir

DATA_DIR = os.path.join(golden_mf.shared_data_dir(), "mfeval-tir")

SIGMA_MIN = 0.04     # m, floor of relaxation lengths (lightly loaded tyre: K -> 0); see docs


def data_file(name):
    """Path of a bundled MF example tyre file (tests/data/mfeval-tir)."""
    return os.path.join(DATA_DIR, name)


class MFTire:
    """One .tir parameter set, evaluated through grip_tools.reference.mf.

    path: .tir file (a name without directory is looked up in tests/data/mfeval-tir).
    form: 'mftyre' (default) or 'book' (passed to mf.evaluate).
    """

    def __init__(self, path, form="mftyre"):
        if not os.path.dirname(path) and not os.path.exists(path):
            path = data_file(path)
        t = tir.read_tir(path)
        self.path = path
        self.name = os.path.basename(path)
        self.form = form
        self.P = t.params()                               # mirroring per wheel: mirror_for
        self.fittyp = int(self.P["fittyp"])
        self.tyreside = int(self.P["tyreside"])          # +1 fitted as LEFT, -1 as RIGHT
        self.r0 = float(self.P["unloaded_radius"])
        self.fnomin = float(self.P["fnomin"])
        self.cz = float(self.P["vertical_stiffness"]) or 2.0e5
        q = t.get("ROLLING_COEFFICIENTS", "QSY1")
        self.qsy1 = float(q) if isinstance(q, float) else 0.01
        self.vxlow = float(self.P["vxlow"]) if self.P["vxlow"] > 0 else 1.0
        self.c_long = float(self.P["longitudinal_stiffness"])
        self.c_lat = float(self.P["lateral_stiffness"])
        self._base = {k: float(self.P[k]) for k in ("lmux", "lmuy", "lkx", "lky")}

    # ------------------------------------------------------------------
    def mirror_for(self, wheel_left):
        """bool array: mirror the characteristic for wheels on the given
        side (True = mounted left). A file fitted as LEFT is mirrored on the
        right wheels and vice versa (grip's GRIP_MF_OPT_RIGHT_SIDE)."""
        wheel_left = np.asarray(wheel_left, dtype=bool)
        return np.where(wheel_left, self.tyreside == -1, self.tyreside == 1)

    def evaluate(self, kappa, alpha, fz, vx, lmux=1.0, lmuy=1.0, lkx=1.0, lky=1.0, mirror=False):
        """Forces of many wheels at once (arrays broadcast).

        kappa [-] (ISO: > 0 driving), alpha [rad] (ISO-W), fz [N], vx [m/s]
        (speed for the low-speed reduction and the slip speed of LMUV),
        l*: multipliers of the file's scaling factors, mirror: bool array.
        Returns dict fx, fy, mz [N, N m], kx = dFx/dkappa at kappa = 0,
        ky = |dFy/dalpha| at alpha = 0 (both >= 0), mux, muy (peak friction
        coefficients the model uses at this load and scaling).
        """
        P = dict(self.P)
        P["lmux"] = self._base["lmux"] * np.asarray(lmux, dtype=float)
        P["lmuy"] = self._base["lmuy"] * np.asarray(lmuy, dtype=float)
        P["lkx"] = self._base["lkx"] * np.asarray(lkx, dtype=float)
        P["lky"] = self._base["lky"] * np.asarray(lky, dtype=float)
        sign = np.where(np.asarray(mirror, dtype=bool), -1.0, 1.0)
        out = mf.evaluate(P, kappa, sign * alpha, 0.0, fz, vx=vx, form=self.form,
                          mirror=False, details=True)
        d = out["details"]
        loaded = np.asarray(fz) > 0.0
        return dict(fx=out["fx"], fy=sign * out["fy"], mz=sign * out["mz"],
                    kx=np.where(loaded, np.abs(d["Kxk"]), 0.0),
                    ky=np.where(loaded, np.abs(d["Kya"]), 0.0),
                    mux=np.where(loaded, np.abs(d["mux"]), 0.0),
                    muy=np.where(loaded, np.abs(d["muy"]), 0.0))

    # ------------------------------------------------------------------
    def relaxation_lengths(self, fz, kx, ky):
        """(sigma_kappa, sigma_alpha) [m] at load fz with slip stiffnesses kx, ky.

        MF 6.x with carcass stiffnesses in the file: sigma = K / C (the
        stretched-string relation MF-Tyre uses). Otherwise the MF 5.2 /
        PAC2002 forms:
          sigma_kappa = Fz (PTX1 + PTX2 dfz) exp(-PTX3 dfz) R0 / Fz0
          sigma_alpha = PTY1 sin(2 atan(Fz / (PTY2 Fz0'))) R0 LFZO
        Files with neither get 0.15 m and 0.45 m (typical passenger-car values).
        """
        P = self.P
        fz = np.maximum(np.asarray(fz, dtype=float), 0.0)
        fz0p = P["lfzo"] * self.fnomin
        dfz = (fz - fz0p) / fz0p
        if self.c_long > 0:
            s_k = kx / self.c_long
        elif P["ptx1"] != 0:
            s_k = fz * (P["ptx1"] + P["ptx2"] * dfz) * np.exp(-P["ptx3"] * dfz) * self.r0 / self.fnomin
        else:
            s_k = np.full_like(fz, 0.15)
        if self.c_lat > 0:
            s_a = ky / self.c_lat
        elif P["pty1"] != 0:
            s_a = P["pty1"] * np.sin(2.0 * np.arctan(fz / (P["pty2"] * fz0p))) * self.r0 * P["lfzo"]
        else:
            s_a = np.full_like(fz, 0.45)
        return np.maximum(np.abs(s_k), SIGMA_MIN), np.maximum(np.abs(s_a), SIGMA_MIN)

    def cornering_stiffness(self, fz, lmuy=1.0, lky=1.0):
        """|dFy/dalpha| at alpha = kappa = 0 [N/rad] (central difference of
        the model itself, so shifts and curvature terms are included)."""
        h = 1e-5
        fz = np.asarray(fz, dtype=float)
        a = self.evaluate(0.0, h, fz, self.P["longvl"], 1.0, lmuy, 1.0, lky)["fy"]
        b = self.evaluate(0.0, -h, fz, self.P["longvl"], 1.0, lmuy, 1.0, lky)["fy"]
        return np.abs(a - b) / (2 * h)
