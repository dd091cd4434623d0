"""Measured-data CSV schema.

One header line of comma-separated `name[unit]` fields, then numeric rows
(lines starting with '#' are comments). Tire level: t[s], kappa[-],
alpha[rad], gamma[rad], fz[N], p[Pa], vx[m/s] (inputs) and any of fx[N],
fy[N], mz[Nm] (measured outputs), plus free extra channels (e.g.
t_road[degC]). Missing inputs get defaults (kappa 0, gamma 0, p = the tire's
nominal pressure). The units in the header are checked for the known
channels (a wrong unit is an error, not a silent conversion).
"""
from dataclasses import dataclass, field

import numpy as np

UNITS = {"t": "s", "kappa": "-", "alpha": "rad", "gamma": "rad", "fz": "N", "p": "Pa",
         "vx": "m/s", "vy": "m/s", "fx": "N", "fy": "N", "mz": "Nm", "r": "rad/s", "ay": "m/s2",
         "delta": "rad", "t_road": "degC"}
TIRE_OUTPUTS = ("fx", "fy", "mz")


@dataclass
class Dataset:
    t: np.ndarray
    ch: dict                       # name -> array (inputs, outputs, extras)
    units: dict
    outputs: list                  # names of the measured outputs to explain
    meta: dict = field(default_factory=dict)

    def __len__(self):
        return len(self.t)


def parse_header(line):
    names, units = [], {}
    for f in line.strip().lstrip("#").split(","):
        f = f.strip()
        if "[" in f and f.endswith("]"):
            n, u = f[:-1].split("[", 1)
        else:
            n, u = f, ""
        n = n.strip()
        if n in UNITS and u and u != UNITS[n]:
            raise ValueError(f"channel {n}: unit [{u}], expected [{UNITS[n]}]")
        names.append(n)
        units[n] = u or UNITS.get(n, "")
    return names, units


def read_csv(path, outputs=None):
    with open(path) as f:
        header = f.readline()
        names, units = parse_header(header)
        data = np.loadtxt(f, delimiter=",", comments="#", ndmin=2)
    if data.shape[1] != len(names):
        raise ValueError(f"{path}: {data.shape[1]} columns, header names {len(names)}")
    ch = {n: data[:, i].astype(float) for i, n in enumerate(names)}
    if "t" not in ch:
        raise ValueError(f"{path}: no t[s] column")
    outs = list(outputs) if outputs else [o for o in TIRE_OUTPUTS if o in ch]
    if not outs:
        raise ValueError(f"{path}: no measured output column (fx, fy or mz)")
    return Dataset(ch["t"], ch, units, outs, {"source": str(path)})


def write_csv(path, ds, names=None):
    names = names or ["t"] + [n for n in ds.ch if n != "t"]
    header = ",".join(f"{n}[{ds.units.get(n, UNITS.get(n, ''))}]" for n in names)
    cols = np.column_stack([ds.t if n == "t" else ds.ch[n] for n in names])
    np.savetxt(path, cols, delimiter=",", header=header, comments="", fmt="%.9g")
