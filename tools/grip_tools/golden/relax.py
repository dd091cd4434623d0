"""Golden vectors of the relaxation-length transient (lib/relax) from the
float64 reference tools/grip_tools/reference/relax.py: relax.txt.

Scenarios (one row per step; the C test runs its own state through them):
  id 0  step steer at 20 m/s, dt 0.01 s
  id 1  sine steer + brake pulse at varying speed (5..40 m/s), dt 0.005 s
  id 2  long steps (dt 0.1 s) at 60 m/s: full steps
  id 3  creeping (vx 0..0.3 m/s, below v_min) and reversing
  id 4  random inputs, dt in [0, 0.05] s, v in [-50, 90] m/s
"""
import os

import numpy as np

from grip_tools.golden import io as golden_io
from grip_tools.reference import relax as relax_ref

PARAMS = relax_ref.RelaxParams(sigma_kappa=0.25, sigma_alpha=0.55, v_min=0.5, v_max=100.0,
                               kappa_max=1.0, alpha_max=0.5)
SEED = 20261122


def scenarios():
    rng = np.random.default_rng(SEED)
    out = []
    n = 300
    t = np.arange(n) * 0.01
    out.append((0, np.where(t > 0.5, 0.02, 0.0), np.where(t > 0.3, 0.05, 0.0), np.full(n, 20.0),
                np.full(n, 0.01)))
    n = 600
    t = np.arange(n) * 0.005
    out.append((1, 0.15 * np.exp(-((t - 1.5) / 0.3) ** 2), 0.08 * np.sin(2 * np.pi * 1.3 * t),
                5.0 + 35.0 * t / t[-1], np.full(n, 0.005)))
    n = 40
    out.append((2, rng.uniform(-0.3, 0.3, n), rng.uniform(-0.3, 0.3, n), np.full(n, 60.0),
                np.full(n, 0.1)))
    n = 200
    out.append((3, rng.uniform(-0.1, 0.1, n), rng.uniform(-0.2, 0.2, n),
                0.3 * np.sin(np.arange(n) * 0.05), np.full(n, 0.02)))
    n = 500
    out.append((4, rng.uniform(-1.2, 1.2, n), rng.uniform(-0.6, 0.6, n), rng.uniform(-50, 90, n),
                rng.uniform(0.0, 0.05, n)))
    return out


def write_golden(outdir):
    cols = ["id", "step", "kappa", "alpha", "vx", "dt", "kappa_t", "alpha_t"]
    text = golden_io.header("golden_relax", relax_ref.step, SEED, cols,
                            params={k: repr(v) for k, v in PARAMS.as_dict().items()})
    rows = []
    for sid, k, a, v, dt in scenarios():
        kt, at = relax_ref.simulate(PARAMS, 0.0, 0.0, k, a, v, dt)
        for i in range(len(k)):
            rows.append(f"{sid} {i} " + " ".join("%.17g" % float(x) for x in (k[i], a[i], v[i], dt[i], kt[i], at[i])))
    text += "\n".join(rows) + "\n"
    path = os.path.join(outdir, "relax.txt")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
    return path
