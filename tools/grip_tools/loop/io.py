"""Measured-data CSV schema.

One header line of comma-separated `name[unit]` fields, then numeric rows
(lines starting with '#' are comments). Tire level: t[s], kappa[-],
alpha[rad], gamma[rad], fz[N], p[Pa], vx[m/s] (inputs) and any of fx[N],
fy[N], mz[Nm] (measured outputs), plus extra channels with their unit (e.g.
t_road[degC]). Missing inputs get defaults (kappa 0, gamma 0, p = the tire's
nominal pressure). Names, units and physical ranges are checked by
grip_tools.channels (a wrong unit is an error, not a silent conversion).
"""
from dataclasses import dataclass, field

import numpy as np

from grip_tools.channels import CHANNELS, read_table
from grip_tools.errors import DataError

UNITS = {n: c.unit for n, c in CHANNELS.items()}
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


def read_csv(path, outputs=None):
    """A tire-level CSV as a Dataset: validated by grip_tools.channels (units,
    ranges, time order; DataError names file, line and column)."""
    table = read_table(path, required=("t",))
    ch = dict(table.columns)
    outs = list(outputs) if outputs else [o for o in TIRE_OUTPUTS if o in ch]
    if not outs:
        raise DataError(path, table.header_line, None, "no measured output column (fx, fy or mz)")
    return Dataset(ch["t"], ch, dict(table.units), outs, {"source": str(path)})


def write_csv(path, ds, names=None):
    names = names or ["t"] + [n for n in ds.ch if n != "t"]
    header = ",".join(f"{n}[{ds.units.get(n, UNITS.get(n, ''))}]" for n in names)
    cols = np.column_stack([ds.t if n == "t" else ds.ch[n] for n in names])
    np.savetxt(path, cols, delimiter=",", header=header, comments="", fmt="%.9g")
