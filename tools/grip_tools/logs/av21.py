"""The Dallara AV-21 log (IAC, Putnam Park 2023 run 4_2, 25 Hz; deep-dynamics
repository, GPL-3.0): one reader for every tool that uses it (the estimator's
AV-21 run in est_eval, the measured-data loop in loop/av21.py).

Frame: vy, omega (yaw rate) and delta are taken in the log's own sign, one
frame: in slow corners (4 - 9 m/s) the log's vy is +2.0 omega, above
lr = 1.73 m, as the kinematics of a car turning about a point near its rear
axle require for a point ahead of the CG (docs/estimator.md, "Real
drives"). Reading vy turned over (positive to the
right) contradicts that kinematics (docs/measured-data-loop.md).

The INS does not measure at the CG: ins_offset finds it about 0.5 m
ahead from the steady-state bicycle over the whole log; lateral_at_cg moves
vy there and derives the lateral acceleration (the log has no ay channel).
Nor along the car's axis: on straight running its vy / vx is 0.61 deg
(ins_yaw_misalignment, INS_YAW), which the estimator's sideslip truth
removes (est_eval.av21_inputs).
"""
import os

import numpy as np

from grip_tools.paths import SHARED_DATA, TEST_DATA

LOG = os.path.join(SHARED_DATA, "iac-av21-deepdynamics", "Putnam_park2023_run4_2.csv")
SUBSET = os.path.join(TEST_DATA, "iac-av21",
                      "putnam_run4_2_subset.csv")
# published for the car; Iz and the CG height are not (assumptions, stated
# where used)
MASS, LF, LR = 790.0, 1.248, 1.7328
# ins_offset over the full log (vx > 5 m/s, 2026-11-22): the INS is 0.49 m
# ahead of the CG. A window of the log cannot always determine it (the
# bundled 240 s subset gives -0.03 m), so tools that read a part of the log
# use this value: the mounting does not change within a run.
INS_X = 0.49
# ins_yaw_misalignment over the full log (2026-11-27): on straight running
# the INS's vy / vx is 0.61 deg (std 0.09 deg over 1,498 samples) where a
# car's sideslip is ~0 (no lateral force): the INS's heading is turned
# against the car's x axis (antenna baseline or IMU mount). The sideslip
# truth is taken about the car's axis; the estimator's inputs are not
# changed (the lateral acceleration derived from vy moves by 0.01 ax).
INS_YAW = 0.0107


def read(path=None):
    """The log's columns as a dict of arrays (time from 0): t, vx, vy, delta,
    r, ax and, for the full log only, ws (N, 4) wheel speeds in m/s. Accepts
    the full log (17 columns) and the bundled subset (t, vx, vy, delta,
    omega, ax)."""
    path = path or LOG
    d = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    if d.shape[1] == 17:
        out = {"t": d[:, 0], "vx": d[:, 3], "vy": d[:, 4], "delta": d[:, 6], "r": d[:, 7], "ax": d[:, 8],
               "ws": d[:, 10:14] / 3.6}
    elif d.shape[1] == 6:
        out = {k: d[:, i] for i, k in enumerate(("t", "vx", "vy", "delta", "r", "ax"))}
    else:
        raise ValueError(f"{path}: {d.shape[1]} columns, expected 17 (full log) or 6 (subset)")
    out["t"] = out["t"] - out["t"][0]
    return out


def ins_offset(vx, vy, r, lr=LR):
    """Where the INS measures vy: the linear bicycle's steady state
    vy_cg = (lr - k vx^2) r seen at a point x ahead of the CG is
    vy = c0 + (x + lr) r - k r vx^2; least squares over vx > 5 m/s (vy in
    the log's own sign). Returns x [m] and the fit's c0, k."""
    s = vx > 5.0
    A = np.c_[np.ones(s.sum()), r[s], -r[s] * vx[s] ** 2]
    c0, xl, k = np.linalg.lstsq(A, vy[s], rcond=None)[0]
    return float(xl - lr), float(c0), float(k)


def ins_yaw_misalignment(vx, vy_cg, r, ay, vx_min=15.0, r_max=0.02, ay_max=0.5):
    """The INS's heading against the car's x axis [rad]: the median of
    vy / vx (vy at the CG) over straight running (vx > vx_min m/s,
    |r| < r_max rad/s, |ay| < ay_max m/s^2), where the car's own sideslip
    is ~0; None when fewer than 50 samples qualify."""
    s = (vx > vx_min) & (np.abs(r) < r_max) & (np.abs(ay) < ay_max)
    if s.sum() < 50:
        return None
    return float(np.median(vy_cg[s] / vx[s]))


def smooth(x, n=5):
    """n-sample centred moving average (the log's derivatives: 0.2 s at 25 Hz)."""
    return np.convolve(x, np.ones(n) / n, mode="same")


def lateral_at_cg(t, vx, vy, r, x_ins=None):
    """The INS's vy moved to the CG and the lateral acceleration there:
    vy_cg = vy - x r (x from ins_offset unless given), ay = vx r +
    d(vy_cg)/dt, d/dt smoothed over 5 samples (0.2 s at 25 Hz).
    Returns vy_cg, ay, x."""
    if x_ins is None:
        x_ins = ins_offset(vx, vy, r)[0]
    vy_cg = vy - x_ins * r
    ay = vx * r + smooth(np.gradient(vy_cg, t))
    return vy_cg, ay, x_ins
