"""Golden vectors of the sensor calibration stage (lib/calib) from the
float64 reference tools/grip_tools/reference/calib.py: calib.txt.

Row 1 (after the header): the configuration, offset[9] gain[9] delay[9].
Then one row per step (100 Hz, 600 steps): t_us, the 9 raw inputs, their
valid mask (bit i), the reference's calibrated values (float64), the output
valid mask, and the fixed build's exact Q15.16 results (integers, raw values
rounded to QS as the C test does). Inputs: sines and noise in the ranges of
the ESC signals, random dropouts (10 % of samples per input, some runs of
several steps) so that the delayed validity is exercised; delays 0 .. 32
(GRIP_CALIB_DELAY_MAX) steps.
"""
import os

import numpy as np

from grip_tools.reference import calib as calib_ref
from grip_tools.golden import io as golden_io

SEED = 20261123
CONFIG = {
    "offset": [0.05, -0.03, 0.0, 0.12, 0.02, 0.0070, -0.15, 0.31, -0.4],
    "gain": [1.01, 0.99, 1.0, 1.03, 1.0, 1.0 / 1.04, 0.97, 1.0 / 0.95, 1.5],
    "delay": [3, 3, 0, 32, 3, 0, 1, 0, 7],
}


def inputs(n=600, dt=0.01, seed=SEED):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    v = np.zeros((n, calib_ref.N))
    for i in range(4):
        v[:, i] = 25.0 + 5.0 * np.sin(0.3 * t + i) + 0.05 * rng.standard_normal(n)
    v[:, 4] = 1.5 * np.sin(2 * np.pi * 0.7 * t)
    v[:, 5] = 0.3 * np.sin(2 * np.pi * 0.7 * t - 0.3) + 0.002 * rng.standard_normal(n)
    v[:, 6] = -2.0 + 1.5 * np.sin(0.9 * t) + 0.05 * rng.standard_normal(n)
    v[:, 7] = 6.0 * np.sin(2 * np.pi * 0.7 * t - 0.4) + 0.05 * rng.standard_normal(n)
    v[:, 8] = 24.0 + 3.0 * np.sin(0.2 * t)
    ok = (rng.random((n, calib_ref.N)) > 0.1).astype(np.uint8)
    ok[100:140, 5] = 0                   # a 0.4 s yaw-rate loss
    ok[300:305, :] = 0                   # every input lost for 5 steps
    v[ok == 0] = 0.0                     # the signal contract: 0 where invalid
    t_us = np.round(t * 1e6).astype(np.int64)
    return t_us, v, ok


def write_golden(outdir):
    t_us, v, ok = inputs()
    fv, fok = calib_ref.run(CONFIG, t_us, v, ok)
    qv, qok = calib_ref.run(CONFIG, t_us, v, ok, q16_mode=True)
    assert np.array_equal(fok, qok)
    n = calib_ref.N
    cols = (["t_us"] + [f"in{i}" for i in range(n)] + ["valid_mask"] + [f"out{i}" for i in range(n)]
            + ["out_mask"] + [f"q{i}" for i in range(n)])
    text = golden_io.header("golden_calib", calib_ref.Calib, SEED, cols,
                            params={k: repr(vv) for k, vv in CONFIG.items()})
    rows = [" ".join("%.17g" % x for x in CONFIG["offset"]) + " " +
            " ".join("%.17g" % x for x in CONFIG["gain"]) + " " + " ".join(str(d) for d in CONFIG["delay"])]
    for k in range(len(t_us)):
        m_in = sum(int(ok[k, i]) << i for i in range(n))
        m_out = sum(int(fok[k, i]) << i for i in range(n))
        rows.append(f"{int(t_us[k])} " + " ".join("%.17g" % x for x in v[k]) + f" {m_in} "
                    + " ".join("%.17g" % x for x in fv[k]) + f" {m_out} " + " ".join(str(int(x)) for x in qv[k]))
    path = os.path.join(outdir, "calib.txt")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text + "\n".join(rows) + "\n")
    os.replace(tmp, path)
    return path
