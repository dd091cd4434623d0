"""Measured channels: the one table of names, SI units and physical ranges
for every tool that reads tire- or vehicle-level data (`grip analyze`,
`grip fit-mf`), and the CSV reader that enforces it.

A file that is read but cannot be used raises DataError naming file, line
and column: a cell that is not a finite number, a row with the wrong number
of fields, a duplicate or unknown column, a unit that is not the channel's
SI unit, time going backwards, NUL or non-UTF-8 bytes, or values outside the
channel's physical range (the message says what the values look like: an
angle in degrees, a load in kN, a pressure in bar). Nothing is converted
silently.

CSV form: one header line of comma-separated `name[unit]` fields (or bare
names; a known channel without a unit is taken in its SI unit, and the tool
says so on stderr), then numeric rows. Lines starting with '#' are comments.
A column that is not a known channel is kept as an extra channel only if its
header declares a unit.
"""
import array
import difflib
import os
import re
import sys
from dataclasses import dataclass

import numpy as np

from grip_tools.errors import DataError
from grip_tools.paths import REPO_ROOT

# Resource caps: a reader never holds more than this (docs/guarantees.md).
MAX_FILE_BYTES = 64 * 1024 * 1024
MAX_LINE_BYTES = 8192
MAX_FIELDS = 256
# Values held while reading (8 bytes each, then once more as the columns):
# 3e6 keeps the reader under 64 MiB whatever the file (a 64 MiB file of
# one-digit cells would be 32 million values).
MAX_VALUES = 3000000


@dataclass(frozen=True)
class Channel:
    unit: str
    lo: float            # physical range in the SI unit (inclusive)
    hi: float
    what: str
    hint: str = ""       # what values outside the range probably are ...
    hint_max: float = 0.0  # ... when the column's largest |value| is at most this


# The table is port/linux/channel_rules.h, which grip-tire compiles: one
# rule for the C program and the Python tools.
RULES_HEADER = os.path.join(REPO_ROOT, "port", "linux", "channel_rules.h")
_CHANNEL_RE = re.compile(r'X\(\s*(\w+)\s*,\s*"([^"]*)"\s*,\s*([-+0-9.eE]+)\s*,\s*([-+0-9.eE]+)\s*,'
                         r'\s*"([^"]*)"\s*,\s*"([^"]*)"\s*,\s*([-+0-9.eE]+)\s*\)')
_DEFINE_RE = re.compile(r"#define\s+GRIP_CHANNEL_(FZ_KN_N|FZ_KN_FNOMIN|P_BAR_PA)\s+([-+0-9.eE]+)")


def _read_rules(path=RULES_HEADER):
    with open(path) as f:
        text = f.read()
    table = {m.group(1): Channel(m.group(2), float(m.group(3)), float(m.group(4)), m.group(5), m.group(6),
                                 float(m.group(7)))
             for m in _CHANNEL_RE.finditer(text)}
    consts = {m.group(1): float(m.group(2)) for m in _DEFINE_RE.finditer(text)}
    if not table or len(consts) != 3:
        raise RuntimeError(f"{path}: the channel table or its constants were not found")
    return table, consts


CHANNELS, _CONSTS = _read_rules()
FZ_KN_N = _CONSTS["FZ_KN_N"]              # a largest load below this [N] is kN labelled N
FZ_KN_FNOMIN = _CONSTS["FZ_KN_FNOMIN"]    # ... or below this fraction of FNOMIN, when known
P_BAR_PA = _CONSTS["P_BAR_PA"]            # a largest pressure below this [Pa] is bar, psi or kPa

# Spellings of the same SI unit.
UNIT_SYNONYMS = {"nm": "Nm", "n m": "Nm", "n.m": "Nm", "m/s^2": "m/s2", "m/s²": "m/s2", "°c": "degC",
                 "degc": "degC", "1": "-", "": ""}


def _canonical_unit(u):
    return UNIT_SYNONYMS.get(u.strip().lower(), u.strip())


@dataclass
class Table:
    path: str
    names: list            # column names in file order (lower case)
    units: dict            # name -> unit
    columns: dict          # name -> float64 array
    header_line: int       # file line of the header
    row_lines: np.ndarray  # file line of every data row

    def __len__(self):
        return len(self.row_lines)


def _decode(path, raw, line_no, offset):
    if b"\0" in raw:
        col = raw.index(b"\0")
        raise DataError(path, line_no, None, f"NUL byte at byte offset {offset + col}: not a text file")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise DataError(path, line_no, None,
                        f"not UTF-8 text at byte offset {offset + e.start} ({e.reason})") from None


def _header(path, line_no, text, known_only):
    fields = [f.strip() for f in text.lstrip("#").split(",")]
    if len(fields) > MAX_FIELDS:
        raise DataError(path, line_no, None, f"{len(fields)} columns: more than the cap of {MAX_FIELDS}")
    names, units, assumed = [], {}, []
    for f in fields:
        if "[" in f and f.endswith("]"):
            n, u = f[:-1].split("[", 1)
            n, u, declared = n.strip().lower(), _canonical_unit(u), True
        else:
            n, u, declared = f.lower(), "", False
        if not n:
            raise DataError(path, line_no, None, "an empty column name in the header")
        if n in units:
            raise DataError(path, line_no, n, "duplicate column")
        ch = CHANNELS.get(n)
        if ch is None:
            if known_only or not declared:
                near = difflib.get_close_matches(n, CHANNELS, n=1)
                hint = f" (did you mean '{near[0]}'?)" if near else ""
                raise DataError(path, line_no, n,
                                f"unknown column{hint}; known: {', '.join(CHANNELS)}"
                                + ("" if known_only else "; an extra channel needs its unit, name[unit]"))
        elif declared and u != ch.unit:
            raise DataError(path, line_no, n, f"unit [{u}]: this channel ({ch.what}) is read in [{ch.unit}]")
        elif not declared:
            u = ch.unit
            assumed.append(f"{n}[{u}]")
        names.append(n)
        units[n] = u
    return names, units, assumed


def _looks_like(name, values):
    """What out-of-range values of a channel probably are."""
    ch = CHANNELS[name]
    m = float(np.max(np.abs(values)))
    return ch.hint if ch.hint_max > 0.0 and m <= ch.hint_max else ""


def check_ranges(path, table, fz_nominal=None):
    """Physical plausibility of every known channel; also catches a load in
    kN or a pressure in bar or psi labelled in SI units. fz_nominal: the
    tyre's FNOMIN [N] when the tool knows it (loads all below a tenth of it
    are kN labelled N, as grip-tire's rule)."""
    for n in table.names:
        ch = CHANNELS.get(n)
        if ch is None:
            continue
        v = table.columns[n]
        bad = np.flatnonzero((v < ch.lo) | (v > ch.hi))
        if bad.size:
            i = int(bad[0])
            raise DataError(path, int(table.row_lines[i]), n,
                            f"{v[i]:g} {ch.unit} is outside the plausible range of the {ch.what} "
                            f"[{ch.lo:g}, {ch.hi:g}] {ch.unit}{_looks_like(n, v)}")
    if "fz" in table.columns:
        fz = table.columns["fz"]
        top = float(np.max(fz))
        if 0.0 < top < FZ_KN_N:
            i = int(np.argmax(fz))
            raise DataError(path, int(table.row_lines[i]), "fz",
                            f"the largest load is {top:g} N: a tire load in kN labelled N?")
        if fz_nominal and 0.0 < top < FZ_KN_FNOMIN * fz_nominal:
            i = int(np.argmax(fz))
            raise DataError(path, int(table.row_lines[i]), "fz",
                            f"the largest load is {top:g} N, below a tenth of the tyre's FNOMIN = "
                            f"{fz_nominal:g} N: a tire load in kN labelled N?")
    if "p" in table.columns:
        p = table.columns["p"]
        pos = p[p > 0.0]
        if pos.size and float(np.max(pos)) < P_BAR_PA:
            i = int(np.flatnonzero(p == np.max(pos))[0])
            raise DataError(path, int(table.row_lines[i]), "p",
                            f"the largest pressure is {float(np.max(pos)):g} Pa: bar, psi or kPa labelled Pa?")
    if "t" in table.columns:
        t = table.columns["t"]
        back = np.flatnonzero(np.diff(t) <= 0.0)
        if back.size:
            i = int(back[0]) + 1
            raise DataError(path, int(table.row_lines[i]), "t",
                            f"time does not increase: {t[i]:g} s after {t[i - 1]:g} s")


def read_table(path, required=(), known_only=False, check=True, quiet=False, fz_nominal=None):
    """Read a measured-data CSV into a Table, or raise DataError. required:
    columns that must be present; known_only: refuse columns that are not
    known channels (instead of keeping unit-declared extras); fz_nominal:
    the tyre's FNOMIN [N], if known (check_ranges)."""
    size = os.path.getsize(path) if os.path.isfile(path) else 0
    if size > MAX_FILE_BYTES:
        raise DataError(path, None, None, f"{size} bytes: larger than the cap of {MAX_FILE_BYTES} bytes")
    names = units = None
    header_line = None
    rows = array.array("d")          # every value, row after row (8 bytes each)
    row_lines = array.array("q")
    offset = 0
    with open(path, "rb") as f:
        line_no = 0
        while True:
            raw = f.readline(MAX_LINE_BYTES + 1)
            if not raw:
                break
            line_no += 1
            if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
                raise DataError(path, line_no, None, f"line longer than the cap of {MAX_LINE_BYTES} bytes")
            if offset + len(raw) > MAX_FILE_BYTES:
                raise DataError(path, line_no, None, f"more than the cap of {MAX_FILE_BYTES} bytes")
            text = _decode(path, raw, line_no, offset).strip()
            offset += len(raw)
            if not text:
                continue
            if names is None:
                names, units, assumed = _header(path, line_no, text, known_only)
                header_line = line_no
                if assumed and not quiet:
                    print(f"{path}: no unit in the header for {', '.join(assumed)}: read in these SI units",
                          file=sys.stderr)
                continue
            if text.startswith("#"):
                continue
            cells = text.split(",")
            if len(cells) != len(names):
                raise DataError(path, line_no, None, f"{len(cells)} fields, the header has {len(names)}")
            if len(rows) + len(cells) > MAX_VALUES:
                raise DataError(path, line_no, None, f"more than the cap of {MAX_VALUES} values")
            for n, c in zip(names, cells):
                try:
                    x = float(c)
                except ValueError:
                    raise DataError(path, line_no, n, f"'{c.strip()}' is not a number") from None
                if not np.isfinite(x):
                    raise DataError(path, line_no, n, f"'{c.strip()}' is not a finite number")
                rows.append(x)
            row_lines.append(line_no)
    if names is None:
        raise DataError(path, 1, None, "empty file: no header line")
    if not row_lines:
        raise DataError(path, line_no, None, "no data rows after the header")
    data = np.frombuffer(rows, dtype=float).reshape(len(row_lines), len(names))
    table = Table(path, names, units, {n: data[:, j].copy() for j, n in enumerate(names)},
                  header_line, np.asarray(row_lines, dtype=np.int64))
    del data, rows
    for n in required:
        if n not in table.columns:
            extra = [m for m in table.names if m not in CHANNELS]
            near = difflib.get_close_matches(n, extra, n=1)
            hint = f" (is '{near[0]}' meant to be '{n}'?)" if near else ""
            raise DataError(path, header_line, n, f"required column missing{hint}")
    if check:
        check_ranges(path, table, fz_nominal)
    return table
