"""DBC file(s) + map file -> the CAN signal table of lib/can (grip_can.h).

    grip can-table MAP.toml [--c OUT.c] [--text OUT.sigtab]
    grip can-table --from-dbc FILE.dbc --map MAP.toml [--c OUT.c] [--text OUT.sigtab]

The DBC files are read by dbcfile.py (a tolerant reader: opendbc's comment
and attribute forms, generator IMPORTs). The map file (TOML, docs/can.md,
docs/can-families.md) says which DBC signal feeds which estimator input
(grip_signals.h), in which unit, with which sign, range, qualifier ("valid
only if this flag is 0"), and each message's period, checksum and rolling
counter. A message of a DBC whose car family is known (opendbc's file
names: honda_*, toyota_*, hyundai_canfd*, vw_mqb*, ...) gets that family's
checksum and counter checks without a word in the map (checksums.py).
Every mismatch between map and DBC (a message or signal that does not
exist, a unit that differs from the DBC's, a checksum the message has no
field for, ...) is an error naming both, as FILE:LINE: FIELD: message.

Scaling is turned into integers here, so that the fixed-point build applies
it without floating point: for every signal the SI value is

    (raw * K + C) / 2^s,   K = round(k 2^s), C = round(c 2^s),

with k = factor x unit conversion x gain and c = offset x unit conversion x
gain computed exactly (DBC numbers are decimal, taken as exact fractions;
deg -> rad uses the float64 value of pi/180). s is the largest shift with
|K| < 2^30, |C| < 2^61 and, summed over an input's terms,
2^length |K| + |C| < 2^62 (no 64-bit overflow in the decoder); all terms of
one input share s. The range check is done on the raw integer, with bounds
ceil/floor((lo - c) / k) computed exactly, so the float and fixed builds flag
the same values, and a DBC range such as [-0.7|0.7] for a 0.1 factor
includes raw -7 (cantools' float64 -7 * 0.1 would fall just outside).
"""
import argparse
import hashlib
import math
import os
import re
import sys
import tomllib
from dataclasses import dataclass, field
from fractions import Fraction

from grip_tools.can import checksums, dbcfile
from grip_tools.errors import DataError

# Estimator inputs, in the order of grip_input_id_t (grip_signals.h), with
# their SI unit and fixed-point format (QS: 16 fractional bits, QL: 8).
INPUTS = [
    ("wheel_speed_fl", "m/s", 16), ("wheel_speed_fr", "m/s", 16),
    ("wheel_speed_rl", "m/s", 16), ("wheel_speed_rr", "m/s", 16),
    ("steer_angle", "rad", 16), ("yaw_rate", "rad/s", 16),
    ("ax", "m/s^2", 16), ("ay", "m/s^2", 16), ("vehicle_speed", "m/s", 16),
    ("brake_pressure_fl", "Pa", 8), ("brake_pressure_fr", "Pa", 8),
    ("brake_pressure_rl", "Pa", 8), ("brake_pressure_rr", "Pa", 8),
    ("brake_torque_fl", "N m", 8), ("brake_torque_fr", "N m", 8),
    ("brake_torque_rl", "N m", 8), ("brake_torque_rr", "N m", 8),
    ("rear_steer_angle", "rad", 16),
]
INPUT_INDEX = {name: i for i, (name, _, _) in enumerate(INPUTS)}

DEG = Fraction(math.pi / 180.0)
# unit as written in a DBC or map -> (SI unit, exact factor to SI)
UNITS = {
    "m/s": ("m/s", Fraction(1)), "km/h": ("m/s", Fraction(5, 18)), "kph": ("m/s", Fraction(5, 18)),
    "mph": ("m/s", Fraction(1609344, 3600000)),
    "rad": ("rad", Fraction(1)), "deg": ("rad", DEG),
    "rad/s": ("rad/s", Fraction(1)), "deg/s": ("rad/s", DEG),
    "m/s^2": ("m/s^2", Fraction(1)), "m/s2": ("m/s^2", Fraction(1)), "g": ("m/s^2", Fraction("9.80665")),
    "Pa": ("Pa", Fraction(1)), "kPa": ("Pa", Fraction(1000)), "MPa": ("Pa", Fraction(10**6)),
    "bar": ("Pa", Fraction(10**5)), "mbar": ("Pa", Fraction(100)),
    "N m": ("N m", Fraction(1)), "Nm": ("N m", Fraction(1)),
}
# other spellings seen in DBC files (opendbc's among them) -> a UNITS key
UNIT_ALIASES = {
    "km / h": "km/h", "kmh": "km/h", "km/hr": "km/h", "kmph": "km/h", "unit_kilometerperhour": "km/h",
    "unit_kilometreperhour": "km/h", "m/sec": "m/s", "unit_meterpersecond": "m/s", "unit_meterpersecon": "m/s",
    "degree": "deg", "degrees": "deg", "\u00b0": "deg", "unit_degreofarc": "deg",
    "deg/sec": "deg/s", "degree/s": "deg/s", "degrees/s": "deg/s", "degree/sec": "deg/s", "\u00b0/s": "deg/s",
    "unit_degreofarcpersecon": "deg/s", "rad/sec": "rad/s",
    "m/s/s": "m/s^2", "m/s\u00b2": "m/s^2", "m/sec^2": "m/s^2", "m/sec2": "m/s^2", "unit_meterpersecondsquar": "m/s^2",
    "unit_meterpersecondsquare": "m/s^2", "unit_meterpersecsquar": "m/s^2", "unit_meterpersecsquare": "m/s^2",
    "unit_meterperseconsquar": "m/s^2",
    "hpa": "Pa*100", "unit_bar": "bar", "unit_millibar": "mbar", "unit_kilopascal": "kPa",
    "n*m": "N m", "n.m": "N m", "unit_newtometer": "N m", "unit_newtometre": "N m", "unit_newtonmeter": "N m",
}
UNITS["Pa*100"] = ("Pa", Fraction(100))
# case-folded spellings that name two units: refused, the map must say which
AMBIGUOUS_UNITS = {"mpa": "MPa (mega) or mPa (milli)", "mbar": "mbar (milli) or Mbar (mega)",
                   "nm": "Nm (newton metre) or nm (nanometre)"}
_FOLDED = {k.lower(): k for k in UNITS}


def unit_key(text):
    """The UNITS key of a unit as written: exact, else a known alias, else
    the same letters in another case where that is unambiguous. Returns
    (key or None, why-not)."""
    t = " ".join(text.split())
    if t in UNITS:
        return t, ""
    low = t.lower()
    if low in AMBIGUOUS_UNITS:
        return None, f"'{text}' could be {AMBIGUOUS_UNITS[low]}"
    if low in UNIT_ALIASES:
        return UNIT_ALIASES[low], ""
    if low in _FOLDED:
        return _FOLDED[low], ""
    return None, f"unit '{text}' unknown"


K_LIMIT = 1 << 30
C_LIMIT = 1 << 61
SUM_LIMIT = 1 << 62
MAX_MESSAGES = 32
MAX_SIGNALS = 64
MAX_TERMS = 4


class MapError(DataError):
    """The map file and the DBC do not fit together (or the map is malformed).
    MapError(file, line, field, message); MapError(message) where no place is known."""

    def __init__(self, file, line=None, field=None, message=None):
        if message is None and line is None and field is None:
            file, message = "-", file
        super().__init__(file, line, field, message)


class MapText:
    """Line numbers of a map file's sections and keys (tomllib gives none)."""

    def __init__(self, path):
        self.path = path
        try:
            with open(path, encoding="utf-8") as f:
                self.lines = f.read(MAX_MAP_BYTES + 1).split("\n")
        except (OSError, UnicodeDecodeError):
            self.lines = []

    @staticmethod
    def _header(line):
        m = re.match(r"\s*\[\s*([^\]]+?)\s*\]\s*(#.*)?$", line)
        if not m:
            return None
        return ".".join(p.strip().strip('"').strip("'") for p in m.group(1).split("."))

    def line(self, section=None, key=None):
        """1-based line of [section] (dotted, e.g. 'inputs.ax'), or of `key`
        inside it (or at the top when section is None); None if not found."""
        cur = ""
        sec_line = None
        for i, ln in enumerate(self.lines):
            h = self._header(ln)
            if h is not None:
                cur = h
                if section is not None and h == section:
                    sec_line = i + 1
                    if key is None:
                        return sec_line
                continue
            if key is not None and cur == (section or ""):
                if re.match(rf"\s*\"?{re.escape(key)}\"?\s*=", ln):
                    return i + 1
        return sec_line

    def err(self, section, key, field, message):
        return MapError(self.path, self.line(section, key), field, message)


def exact(x):
    """A DBC number (cantools gives float or int) as the exact decimal it was written as."""
    if isinstance(x, Fraction):
        return x
    if isinstance(x, int):
        return Fraction(x)
    return Fraction(repr(float(x)))


def ceil_frac(x):
    return -((-x.numerator) // x.denominator)


def floor_frac(x):
    return x.numerator // x.denominator


@dataclass
class Term:
    """One DBC signal of the table (a VALUE term or a QUALIFIER)."""
    name: str
    input: int
    role: str          # "value" | "qualifier"
    start: int
    length: int
    order: str         # "intel" | "motorola"
    signed: int
    k: Fraction = Fraction(0)   # exact SI per raw LSB
    c: Fraction = Fraction(0)   # exact SI offset
    shift: int = 0
    K: int = 0
    C: int = 0
    raw_min: int = 0
    raw_max: int = 0
    unit: str = ""
    dbc_signal: object = None

    def raw_limits(self):
        if self.signed:
            return -(1 << (self.length - 1)), (1 << (self.length - 1)) - 1
        return 0, (1 << self.length) - 1

    def si_exact(self, raw):
        """SI value of a raw integer, exactly (Fraction)."""
        return raw * self.k + self.c


@dataclass
class Message:
    name: str
    id: int            # table key: 11-bit, or 29-bit | 0x80000000
    length: int
    period_us: int
    checksum: str = "none"
    checksum_start: int = 0
    checksum_length: int = 0
    checksum_order: str = "intel"
    counter_start: int = 0
    counter_length: int = 0
    counter_order: str = "intel"
    magic: list = field(default_factory=lambda: [0] * checksums.MAGIC_LEN)
    terms: list = field(default_factory=list)
    dbc_message: object = None
    checksum_signal: str = ""
    counter_signal: str = ""

    @property
    def checksum_byte(self):
        """The (first) byte of the checksum field."""
        return checksums.Field(self.checksum_start, self.checksum_length, self.checksum_order).byte \
            if self.checksum_length else 0

    @property
    def frame_id(self):
        return self.id & 0x1FFFFFFF

    @property
    def extended(self):
        return bool(self.id & 0x80000000)

    def field(self):
        return checksums.Field(self.checksum_start, self.checksum_length, self.checksum_order)


@dataclass
class Table:
    name: str
    messages: list
    source: str = ""
    gains: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)

    @property
    def signals(self):
        return [t for m in self.messages for t in m.terms]


def _err(where, message):
    """MapError at `where`: a (file, line, field) tuple, or a text prefix."""
    if isinstance(where, tuple):
        return MapError(where[0], where[1], where[2], message)
    return MapError(f"{where}: {message}")


def load_dbc(paths):
    """The DBC files (and what they IMPORT) as one dbcfile.Database."""
    return dbcfile.load(paths)


# A map file is a few kB; a larger file or a device is not one.
MAX_MAP_BYTES = 1 << 20


def load_map(path):
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_MAP_BYTES + 1)
        if len(data) > MAX_MAP_BYTES:
            raise MapError(path, None, "map", f"larger than {MAX_MAP_BYTES} bytes: not a map file")
        z = data.find(b"\0")
        if z >= 0:
            raise MapError(path, data.count(b"\n", 0, z) + 1, "map", f"NUL byte at byte offset {z}: not a map file")
        m = tomllib.loads(data.decode("utf-8"))
    except OSError as e:
        raise MapError(path, None, "map", f"cannot read map file: {e.strerror}") from e
    except UnicodeDecodeError as e:
        raise MapError(path, None, "map", f"not UTF-8 text (byte offset {e.start})") from e
    except tomllib.TOMLDecodeError as e:
        ln = re.search(r"line (\d+)", str(e))
        raise MapError(path, int(ln.group(1)) if ln else None, "toml", f"not valid TOML: {e}") from e
    base = os.path.dirname(os.path.abspath(path))
    dbcs = m.get("dbc", [])
    if isinstance(dbcs, str):
        dbcs = [dbcs]
    m["dbc"] = [os.path.join(base, p) for p in dbcs]
    m.setdefault("_path", path)
    return m


def _order(sig):
    return "intel" if sig.byte_order == "little_endian" else "motorola"


def _find_signal(db, ref, where):
    if not isinstance(ref, str) or ref.count(".") != 1:
        raise _err(where, f"signal reference '{ref}' must be MESSAGE.SIGNAL")
    mname, sname = ref.split(".")
    try:
        msg = db.get_message_by_name(mname)
    except KeyError:
        raise _err(where, f"DBC/map mismatch: message '{mname}' is not in the DBC files") from None
    try:
        sig = msg.get_signal_by_name(sname)
    except KeyError:
        raise _err(where, f"DBC/map mismatch: message '{mname}' (0x{msg.frame_id:X}) has no signal '{sname}' "
                          f"(it has: {', '.join(s.name for s in msg.signals)}; {msg.file}:{msg.line})") from None
    if sig.multiplexer_ids:
        raise _err(where, f"{ref} is multiplexed ({sig.file}:{sig.line}); multiplexed signals are not supported")
    if sig.is_float:
        raise _err(where, f"{ref} is an IEEE float signal (SIG_VALTYPE_); the decoder takes integers")
    return msg, sig


def _term_of(sig, input_index, role):
    return Term(name=sig.name, input=input_index, role=role, start=sig.start, length=sig.length,
                order=_order(sig), signed=1 if sig.is_signed else 0, dbc_signal=sig)


def choose_shift(terms, frac_bits, where):
    """The largest common shift s (<= 62) meeting the overflow bounds."""
    for s in range(62, frac_bits - 1, -1):
        total = 0
        ok = True
        for t in terms:
            K = round(t.k * (1 << s))
            C = round(t.c * (1 << s))
            if abs(K) >= K_LIMIT or abs(C) >= C_LIMIT:
                ok = False
                break
            total += (1 << t.length) * abs(K) + abs(C)
        if ok and total < SUM_LIMIT:
            for t in terms:
                t.shift = s
                t.K = round(t.k * (1 << s))
                t.C = round(t.c * (1 << s))
                if t.K == 0:
                    raise _err(where, f"factor {float(t.k)!r} SI per bit is too small for the integer decoder")
            return s
    raise _err(where, f"factor too large for the integer decoder (more than 2^{30 - frac_bits} SI units per bit)")


def raw_range(term, lo, hi, where):
    """Raw bounds [raw_min, raw_max] of the SI range [lo, hi] (None: unbounded)."""
    rmin, rmax = term.raw_limits()
    if term.k == 0:
        raise _err(where, "zero factor")
    a = rmin
    b = rmax
    if lo is not None:
        x = (lo - term.c) / term.k
        if term.k > 0:
            a = max(a, ceil_frac(x))
        else:
            b = min(b, floor_frac(x))
    if hi is not None:
        x = (hi - term.c) / term.k
        if term.k > 0:
            b = min(b, floor_frac(x))
        else:
            a = max(a, ceil_frac(x))
    if a > b:
        raise _err(where, f"range [{lo}, {hi}] contains no raw value of the signal")
    return a, b


def _overrides(mp, mt):
    """[signals.MESSAGE.SIGNAL] tables (or [signals."MESSAGE.SIGNAL"]):
    {"MESSAGE.SIGNAL": {unit, scale, offset, min, max}}."""
    out = {}
    for k, v in (mp.get("signals") or {}).items():
        if not isinstance(v, dict):
            raise mt.err("signals", k, f"signals.{k}", "must be a table: [signals.MESSAGE.SIGNAL]")
        if "." in k:
            out[k] = (v, f"signals.{k}")
            continue
        for sname, ov in v.items():
            if not isinstance(ov, dict):
                raise mt.err(f"signals.{k}", sname, f"signals.{k}.{sname}",
                             "must be a table of unit, scale, offset, min, max")
            out[f"{k}.{sname}"] = (ov, f"signals.{k}.{sname}")
    allowed = {"unit", "scale", "offset", "min", "max"}
    for ref, (ov, sec) in out.items():
        bad = set(ov) - allowed
        if bad:
            raise mt.err(sec, sorted(bad)[0], sec, f"unknown key '{sorted(bad)[0]}' (known: {', '.join(sorted(allowed))})")
    return out


class SignalView:
    """A DBC signal with the map's overrides applied (unit, scale, offset, min, max)."""

    def __init__(self, sig, ov):
        self.sig = sig
        self.ov = ov or {}
        self.unit = self.ov.get("unit", sig.unit)
        self.scale = exact(self.ov["scale"]) if "scale" in self.ov else exact(sig.scale)
        self.offset = exact(self.ov["offset"]) if "offset" in self.ov else exact(sig.offset)
        self.minimum = exact(self.ov["min"]) if "min" in self.ov else sig.minimum
        self.maximum = exact(self.ov["max"]) if "max" in self.ov else sig.maximum

    def __getattr__(self, name):
        return getattr(self.sig, name)


def build_table(db, mp, name=None, dbc_paths=None):
    """Builds the Table from a loaded DBC database and a parsed map."""
    where0 = mp.get("_path", "map")
    mt = MapText(where0)
    name = name or mp.get("name")
    if not name or not isinstance(name, str) or not re.fullmatch(r"[a-z][a-z0-9_]{0,30}", name):
        raise mt.err(None, "name", "name", "must be a lower-case C identifier (it names grip_can_table_<name>)")
    msg_cfg = mp.get("messages", {})
    inputs = mp.get("inputs", {})
    if not inputs:
        raise MapError(where0, None, "inputs", "no [inputs.*] section")
    overrides = _overrides(mp, mt)
    used_overrides = set()
    family_all = mp.get("checksum_family")
    if family_all is not None:
        family_all = _family_name(family_all, (where0, mt.line(None, "checksum_family"), "checksum_family"))
    messages = {}
    gains = {}
    for iname, spec in inputs.items():
        sec = f"inputs.{iname}"

        def where(key=None, _sec=sec):
            return (where0, mt.line(_sec, key), _sec + (f".{key}" if key else ""))
        if iname not in INPUT_INDEX:
            raise _err(where(), f"unknown estimator input (known: {', '.join(INPUT_INDEX)})")
        if not isinstance(spec, dict):
            raise _err(where(), "must be a table: [inputs.NAME]")
        idx = INPUT_INDEX[iname]
        si_unit, frac_bits = INPUTS[idx][1], INPUTS[idx][2]
        refs = spec.get("signals")
        if isinstance(refs, str):
            refs = [refs]
        if not refs or len(refs) > MAX_TERMS:
            raise _err(where("signals"), f"'signals' must list 1..{MAX_TERMS} MESSAGE.SIGNAL names")
        gain = exact(spec.get("gain", 1))
        if gain == 0:
            raise _err(where("gain"), "gain 0")
        gains[iname] = gain
        terms = []
        msg = None
        for ref in refs:
            m, raw_sig = _find_signal(db, ref, where("signals"))
            if msg is not None and m is not msg:
                raise _err(where("signals"), f"all signals of one input must be in one message "
                                             f"({msg.name} vs {m.name})")
            msg = m
            ov, ov_sec = overrides.get(ref, ({}, None))
            if ov_sec:
                used_overrides.add(ref)
            sig = SignalView(raw_sig, ov)
            dbc_unit = raw_sig.unit or ""
            if "unit" in ov:
                unit_text, uw = ov["unit"], (where0, mt.line(ov_sec, "unit"), f"{ov_sec}.unit")
            elif dbc_unit and unit_key(dbc_unit)[0] is not None:
                unit_text, uw = dbc_unit, (raw_sig.file, raw_sig.line, f"SG_ {raw_sig.name}")
                if "unit" in spec:
                    mk, why = unit_key(spec["unit"])
                    if mk is None:
                        raise _err(where("unit"), why)
                    if UNITS[mk] != UNITS[unit_key(dbc_unit)[0]]:
                        raise _err(where("unit"), f"DBC/map mismatch: {ref} is in '{dbc_unit}' in the DBC, the map "
                                                  f"says '{spec['unit']}' ({raw_sig.file}:{raw_sig.line}); to "
                                                  f"override the DBC, set unit in [signals.{ref}]")
            elif "unit" in spec:
                unit_text, uw = spec["unit"], where("unit")
            elif dbc_unit:
                raise _err((raw_sig.file, raw_sig.line, f"SG_ {raw_sig.name}"),
                           f"{unit_key(dbc_unit)[1]} (known: {', '.join(k for k in UNITS if k != 'Pa*100')}); "
                           f"give the unit in the map: unit in [{sec}] or [signals.{ref}]")
            else:
                raise _err(where(), f"{ref} has no unit in the DBC ({raw_sig.file}:{raw_sig.line}): give 'unit' "
                                    f"in [{sec}] (known: {', '.join(k for k in UNITS if k != 'Pa*100')})")
            unit, why = unit_key(unit_text)
            if unit is None:
                raise _err(uw, f"{why} (known: {', '.join(k for k in UNITS if k != 'Pa*100')}); "
                               "set the unit in the map")
            if UNITS[unit][0] != si_unit:
                raise _err(uw, f"{ref} is in '{unit_text}' ({UNITS[unit][0]}), input {iname} needs {si_unit}")
            if sig.length > 32:
                raise _err(where("signals"), f"{ref} is {sig.length} bits; the decoder takes values of up to 32 bits")
            t = _term_of(raw_sig, idx, "value")
            t.dbc_signal = sig
            conv = UNITS[unit][1] * gain
            t.unit = unit
            t.k = sig.scale * conv
            t.c = sig.offset * conv
            terms.append(t)
        choose_shift(terms, frac_bits, where("signals"))
        rng = spec.get("range")
        for t in terms:
            if rng is not None:
                if len(terms) > 1:
                    raise _err(where("range"), "'range' applies to one-signal inputs; the terms use their DBC ranges")
                if not isinstance(rng, list) or len(rng) != 2:
                    raise _err(where("range"), "'range' must be [LO, HI]")
                lo, hi = (exact(rng[0]), exact(rng[1]))
                rw = where("range")
            else:
                s = t.dbc_signal
                conv = UNITS[t.unit][1] * gain
                if s.minimum is not None and s.maximum is not None and s.minimum < s.maximum:
                    lo, hi = exact(s.minimum) * conv, exact(s.maximum) * conv
                    if lo > hi:
                        lo, hi = hi, lo
                else:
                    lo, hi = None, None
                rw = (s.file, s.line, f"SG_ {s.name} [min|max]")
            t.raw_min, t.raw_max = raw_range(t, lo, hi, rw)
        quals = []
        for qref, qval in (spec.get("valid_if") or {}).items():
            full = qref if "." in qref else f"{msg.name}.{qref}"
            m, sig = _find_signal(db, full, where("valid_if"))
            if m is not msg:
                raise _err(where("valid_if"), f"qualifier {full} must be in message {msg.name}")
            if sig.length > 32:
                raise _err(where("valid_if"), f"qualifier {full} longer than 32 bits")
            q = _term_of(sig, idx, "qualifier")
            q.raw_min = q.raw_max = int(qval)
            lo, hi = q.raw_limits()
            if not lo <= int(qval) <= hi:
                raise _err(where("valid_if"), f"qualifier value {qval} does not fit {full}")
            quals.append(q)
        if msg.name not in messages:
            cfg = dict(msg_cfg.get(msg.name, {}))
            if "period_ms" not in cfg and "period_ms" in mp and not msg.cycle_time:
                cfg["period_ms"] = mp["period_ms"]     # the map's default period
            messages[msg.name] = _message_of(msg, cfg, mt, f"messages.{msg.name}", family_all, sec)
        messages[msg.name].terms.extend(terms + quals)
    for mname in msg_cfg:
        if mname not in messages:
            w = (where0, mt.line(f"messages.{mname}"), f"messages.{mname}")
            try:
                db.get_message_by_name(mname)
            except KeyError:
                raise _err(w, f"DBC/map mismatch: [messages.{mname}] is not in the DBC files") from None
            raise _err(w, f"[messages.{mname}] feeds no input")
    for ref, (ov, sec) in overrides.items():
        if ref not in used_overrides:
            raise mt.err(sec, None, sec, f"{ref} feeds no input (an override of a signal the map does not use)")
    msgs = sorted(messages.values(), key=lambda m: m.id)
    for m in msgs:
        m.terms.sort(key=lambda t: (t.input, t.role != "value"))
    if len(msgs) > MAX_MESSAGES or sum(len(m.terms) for m in msgs) > MAX_SIGNALS:
        raise MapError(where0, None, "inputs", f"more than {MAX_MESSAGES} messages or {MAX_SIGNALS} signals")
    paths = dbc_paths if dbc_paths is not None else mp.get("dbc", [])
    src = " + ".join(os.path.basename(p) for p in paths)
    return Table(name=name, messages=msgs, source=src, gains=gains, notes=list(getattr(db, "notes", [])))


def _family_name(text, where):
    if not isinstance(text, str):
        raise _err(where, "a checksum family name is a string")
    fam = checksums.ALIASES.get(text, text)
    if fam not in checksums.FAMILIES:
        raise _err(where, f"checksum '{text}' unknown (known: {', '.join(checksums.FAMILIES)})")
    return fam


def _field_sig(msg, sname, w, what):
    try:
        return msg.get_signal_by_name(sname)
    except KeyError:
        raise _err(w, f"DBC/map mismatch: {what} but {msg.name} has no {sname} signal "
                      f"(BO_ at {msg.file}:{msg.line}; name it with checksum_signal / counter)") from None


def _message_of(msg, cfg, mt, sec, family_all=None, user=None):
    key = msg.frame_id | (0x80000000 if msg.is_extended_frame else 0)
    where0 = mt.path

    def w(k=None):
        ln = mt.line(sec, k)
        if ln is None and user is not None:
            return (where0, mt.line(user, "signals"), sec + (f".{k}" if k else ""))
        return (where0, ln, sec + (f".{k}" if k else ""))
    if "period_ms" in cfg:
        period_us = int(round(float(cfg["period_ms"]) * 1000))
    elif msg.cycle_time:
        period_us = int(msg.cycle_time) * 1000
    else:
        raise _err(w(), f"the DBC gives no cycle time for {msg.name}: set period_ms in [{sec}] "
                        f"(or a default period_ms at the top of the map; BO_ at {msg.file}:{msg.line})")
    if period_us <= 0:
        raise _err(w("period_ms"), "period must be > 0")
    m = Message(name=msg.name, id=key, length=msg.length, period_us=period_us, dbc_message=msg)
    names = {s.name for s in msg.signals}
    auto = checksums.auto_check(family_all or checksums.family_of_dbc(msg.root), msg.frame_id, names)
    if "checksum" in cfg:
        fam = _family_name(cfg["checksum"], w("checksum"))
        if fam == "none":
            csig = None
        elif "checksum_signal" in cfg:
            csig = cfg["checksum_signal"]
        elif auto and auto[0] == fam:
            csig = auto[1]
        elif fam == "hyundai_whl_spd":
            csig = "WHL_SPD_Checksum_LSB"
        else:
            csig = "CHECKSUM"
        cw = w("checksum")
    elif auto:
        fam, csig = auto[0], auto[1]
        cw = (msg.file, msg.line, f"BO_ {msg.name}")
    else:
        fam, csig, cw = "none", None, None
    if fam != "none":
        sig = _field_sig(msg, csig, cw, f"checksum '{fam}'")
        f = checksums.Field(sig.start, sig.length, _order(sig))
        need, ok = checksums.expected_field(fam, msg.frame_id, msg.length)
        if not ok(f):
            raise _err(cw, f"checksum '{fam}' of {msg.name} must be {need}; {sig.name} is "
                           f"{sig.start}|{sig.length}@{'1' if f.order == 'intel' else '0'} "
                           f"({sig.file}:{sig.line})")
        bits = f.bits
        if len(bits) == 8 and min(bits) % 8 == 0 and bits == set(range(min(bits), min(bits) + 8)):
            f = checksums.Field(min(bits), 8, "intel")     # one whole byte: one canonical form
        m.checksum = fam
        m.checksum_start, m.checksum_length, m.checksum_order = f.start, f.length, f.order
        m.checksum_signal = sig.name
        magic = cfg.get("checksum_magic")
        if magic is not None:
            if not isinstance(magic, list) or not magic or len(magic) > checksums.MAGIC_LEN or \
                    not all(isinstance(x, int) and 0 <= x <= 255 for x in magic):
                raise _err(w("checksum_magic"), f"checksum_magic must list 1..{checksums.MAGIC_LEN} bytes (0..255)")
            if fam == "volkswagen_mqb" and len(magic) != 16:
                raise _err(w("checksum_magic"), "volkswagen_mqb needs 16 magic bytes, one per counter value")
            m.magic = list(magic) + [0] * (checksums.MAGIC_LEN - len(magic))
        else:
            d = checksums.default_magic(fam, msg.frame_id)
            if d is None:
                raise _err(cw, f"checksum '{fam}' of {msg.name} (0x{msg.frame_id:X}) needs the message's 16 magic "
                               f"bytes and none are known for this id: set checksum_magic in [{sec}] (or "
                               "checksum = \"none\")")
            m.magic = d
    counter = cfg.get("counter")
    if counter is None and "checksum" not in cfg and auto and auto[2]:
        counter = auto[2]
    if counter:
        if not isinstance(counter, str):
            raise _err(w("counter"), "counter must name a signal (or be false)")
        sig = _field_sig(msg, counter, w("counter") if "counter" in cfg else cw, "counter")
        if sig.length > 8:
            raise _err(w("counter"), f"counter {sig.name} longer than 8 bits")
        m.counter_start, m.counter_length = sig.start, sig.length
        m.counter_order = _order(sig)
        m.counter_signal = sig.name
    return m


# ---- integer decoder mirror (what the C code computes) -------------------------

def extract(data, start, length, order, signed):
    """Raw value per DBC bit numbering (Intel: start = LSB; Motorola: start = MSB)."""
    if order == "intel":
        if start + length > 8 * len(data):
            raise ValueError("signal beyond payload")
        v = int.from_bytes(data, "little") >> start & ((1 << length) - 1)
    else:
        pos, v = start, 0
        for _ in range(length):
            byte, bit = divmod(pos, 8)
            if byte >= len(data):
                raise ValueError("signal beyond payload")
            v = (v << 1) | (data[byte] >> bit & 1)
            pos = pos - 1 if bit else pos + 15
    if signed and v >> (length - 1) & 1:
        v -= 1 << length
    return v


def fixed_value(terms_raw, shift, frac_bits):
    """The fixed build's integer result (round half up) or None if not representable."""
    acc = sum(r * t.K + t.C for t, r in terms_raw)
    sh = shift - frac_bits
    v = (acc + (1 << (sh - 1))) >> sh if sh > 0 else acc
    return v if -(2**31 - 1) <= v <= 2**31 - 1 else None


def toyota_checksum(frame_id, data, csum_byte):
    s = (frame_id & 0xFF) + (frame_id >> 8 & 0xFF) + (frame_id >> 16 & 0xFF) + (frame_id >> 24 & 0xFF) + len(data)
    s += sum(b for i, b in enumerate(data) if i != csum_byte)
    return s & 0xFF


def pack_raw(data, start, length, order, raw):
    """Writes the raw integer of a DBC field into data (a bytearray): the
    inverse of extract()."""
    from grip_tools.can.checksums import field_bits
    bits = field_bits(start, length, order)
    seq = bits if order == "intel" else list(reversed(bits))   # least significant bit first
    raw &= (1 << length) - 1
    for i, b in enumerate(seq):
        data[b // 8] = (data[b // 8] & ~(1 << (b % 8))) | (((raw >> i) & 1) << (b % 8))
    return data


def check_frame(msg, data):
    """The frame check of the C decoder for a frame of table message msg:
    'ok', 'dlc' or 'checksum' (counters need history)."""
    if len(data) != msg.length:
        return "dlc"
    if msg.checksum != "none":
        f = msg.field()
        if checksums.compute(msg.checksum, msg.frame_id, msg.extended, data, f, msg.magic) != \
                checksums.received(msg.checksum, data, f):
            return "checksum"
    return "ok"


# ---- output ----------------------------------------------------------------------

def _c_str(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def text_version(table):
    """1 when every check is one version 1 can say (none, or a Toyota
    checksum byte), else 2."""
    for m in table.messages:
        if m.checksum not in ("none", "toyota"):
            return 2
    return 1


def render_text(table):
    v = text_version(table)
    if v == 1:
        msg_fields = "CHECKSUM CHECKSUM_BYTE COUNTER_START COUNTER_LENGTH COUNTER_ORDER"
    else:
        msg_fields = ("CHECKSUM CHECKSUM_START CHECKSUM_LENGTH CHECKSUM_ORDER COUNTER_START COUNTER_LENGTH "
                      "COUNTER_ORDER MAGIC")
    out = [f"grip-can-table {v} {table.name}",
           f"# generated by python -m grip_tools can-table from {table.source}; do not edit",
           f"# msg NAME ID LEN PERIOD_US {msg_fields}",
           "# sig NAME INPUT ROLE START LENGTH ORDER SIGNED SHIFT K C RAW_MIN RAW_MAX"]
    for m in table.messages:
        if v == 1:
            out.append(f"msg {m.name} 0x{m.id:X} {m.length} {m.period_us} {m.checksum} {m.checksum_byte} "
                       f"{m.counter_start} {m.counter_length} {m.counter_order}")
        else:
            magic = bytes(m.magic).hex() if any(m.magic) else "-"
            out.append(f"msg {m.name} 0x{m.id:X} {m.length} {m.period_us} {m.checksum} {m.checksum_start} "
                       f"{m.checksum_length} {m.checksum_order} {m.counter_start} {m.counter_length} "
                       f"{m.counter_order} {magic}")
        for t in m.terms:
            out.append(f"sig {t.name} {INPUTS[t.input][0]} {t.role} {t.start} {t.length} {t.order} {t.signed} "
                       f"{t.shift} {t.K} {t.C} {t.raw_min} {t.raw_max}")
    return "\n".join(out) + "\n"


def _i64(v):
    if v == -(1 << 63):
        return "INT64_MIN"
    return f"INT64_C({v})"


def render_c(table, map_path="", dbc_paths=()):
    digests = ", ".join(f"{os.path.basename(p)} sha256:{_sha(p)}" for p in dbc_paths)
    lines = [
        f"/*",
        f" * Signal table '{table.name}': generated by `grip can-table` from",
        f" * {map_path} and {table.source}. Do not edit; regenerate.",
        f" * DBC files: {digests}",
        f" * SI value = (raw * K + C) / 2^shift (grip_can.h).",
        f" */",
        f'#include "grip/grip_can.h"',
        f"",
        f"static const grip_can_message_t MESSAGES[{len(table.messages)}] = {{",
    ]
    first = 0
    for m in table.messages:
        cs = "GRIP_CAN_CSUM_" + m.checksum.upper()
        corder = "GRIP_CAN_MOTOROLA" if m.checksum_order == "motorola" else "GRIP_CAN_INTEL"
        order = "GRIP_CAN_MOTOROLA" if m.counter_order == "motorola" else "GRIP_CAN_INTEL"
        magic = "{ " + ", ".join(f"0x{b:02X}u" for b in m.magic) + " }"
        lines.append(f"    {{ {_c_str(m.name)}, 0x{m.id:X}u, {m.period_us}u, {first}u, {len(m.terms)}u, {m.length}u, "
                     f"(uint8_t){cs}, {m.checksum_length}u, (uint8_t){corder}, {m.checksum_start}u, "
                     f"{m.counter_length}u, (uint8_t){order}, {m.counter_start}u,")
        lines.append(f"      {magic} }},")
        first += len(m.terms)
    lines.append("};")
    lines.append("")
    lines.append(f"static const grip_can_signal_t SIGNALS[{max(first, 1)}] = {{")
    for mi, m in enumerate(table.messages):
        for t in m.terms:
            order = "GRIP_CAN_MOTOROLA" if t.order == "motorola" else "GRIP_CAN_INTEL"
            role = "GRIP_CAN_ROLE_QUALIFIER" if t.role == "qualifier" else "GRIP_CAN_ROLE_VALUE"
            inp = "GRIP_IN_" + INPUTS[t.input][0].upper()
            note = (f"{t.unit}; k = {float(t.k):.9g}, c = {float(t.c):.9g} SI" if t.role == "value"
                    else f"qualifier: raw must be {t.raw_min}")
            lines.append(f"    /* {m.name}.{t.name} -> {INPUTS[t.input][0]} ({note}) */")
            lines.append(f"    {{ {_c_str(t.name)}, {mi}u, {t.start}u, {t.length}u, (uint8_t){order}, {t.signed}u, "
                         f"(uint8_t){inp}, (uint8_t){role}, {t.shift}u, {t.K}, {_i64(t.C)}, "
                         f"{_i64(t.raw_min)}, {_i64(t.raw_max)} }},")
    if first == 0:
        lines.append("    { 0 }")
    lines.append("};")
    lines.append("")
    lines.append(f"const grip_can_table_t grip_can_table_{table.name} = {{")
    lines.append(f"    {_c_str(table.name)}, MESSAGES, SIGNALS, {len(table.messages)}u, {first}u")
    lines.append("};")
    return "\n".join(lines) + "\n"


def _sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()[:16]


def table_from_map(map_path, dbc_paths=None):
    """(Table, Database, map) from a map file; dbc_paths (e.g. --from-dbc)
    replace the map's `dbc` list."""
    mp = load_map(map_path)
    if dbc_paths:
        mp["dbc"] = list(dbc_paths)
    mt = MapText(map_path)
    if not mp["dbc"]:
        raise MapError(map_path, mt.line(None, "dbc"), "dbc",
                       "no DBC file: list them in dbc = [...] or give --from-dbc FILE")
    for p in mp["dbc"]:
        if not os.path.isfile(p):
            if dbc_paths:
                raise FileNotFoundError(2, "No such file or directory", p)
            raise MapError(map_path, mt.line(None, "dbc"), "dbc", f"no such DBC file: {p}")
    if "name" not in mp:
        stem = re.sub(r"[^a-z0-9_]", "_", os.path.splitext(os.path.basename(map_path))[0].lower())
        stem = re.sub(r"_map$", "", stem)
        mp["name"] = stem if re.fullmatch(r"[a-z][a-z0-9_]{0,30}", stem) else None
    db = load_dbc(mp["dbc"])
    return build_table(db, mp, dbc_paths=mp["dbc"]), db, mp


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip can-table", description=__doc__.split("\n\n")[0])
    ap.add_argument("map", nargs="?", help="map file (TOML)")
    ap.add_argument("--map", dest="map_opt", metavar="MAP", help="map file (TOML), as the positional argument")
    ap.add_argument("--from-dbc", action="append", metavar="FILE",
                    help="DBC file (repeat for several); replaces the map's dbc list. IMPORTs are followed")
    ap.add_argument("--c", dest="c_out", help="write the table as C source here")
    ap.add_argument("--text", dest="text_out", help="write the table's text form (grip-replay -t) here")
    ap.add_argument("--map-label", help="map path to name in the C header comment (default: as given)")
    args = ap.parse_args(argv)
    map_path = args.map_opt or args.map
    if args.map and args.map_opt and args.map != args.map_opt:
        ap.error("give the map once (positional or --map)")
    if not map_path:
        ap.error("a map file is needed (MAP or --map MAP)")
    table, _, mp = table_from_map(map_path, args.from_dbc)
    for note in table.notes:
        print(f"grip can-table: note: {note}", file=sys.stderr)
    if args.c_out:
        label = args.map_label or map_path
        with open(args.c_out, "w") as f:
            f.write(render_c(table, label, mp["dbc"]))
    if args.text_out:
        with open(args.text_out, "w") as f:
            f.write(render_text(table))
    if not args.c_out and not args.text_out:
        sys.stdout.write(render_text(table))
    checks = ", ".join(f"{m.name} {m.checksum}" + (f"+counter {m.counter_signal}" if m.counter_length else "")
                       for m in table.messages if m.checksum != "none" or m.counter_length)
    print(f"grip can-table: {table.name}: {len(table.messages)} messages, {len(table.signals)} signals"
          + (f"; checks: {checks}" if checks else ""), file=sys.stderr)
    return 0
