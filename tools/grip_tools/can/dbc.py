"""DBC file(s) + map file -> the CAN signal table of lib/can (grip_can.h).

    grip can-table MAP.toml [--c OUT.c] [--text OUT.sigtab]

The DBC files are read with cantools. The map file (TOML, docs/can.md) says
which DBC signal feeds which estimator input (grip_signals.h), in which unit,
with which sign, range, qualifier ("valid only if this flag is 0"), and each
message's period, checksum and rolling counter. Every mismatch between map
and DBC (a message or signal that does not exist, a unit that differs from
the DBC's, a checksum the message has no field for, ...) is an error naming
both.

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

import cantools

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

K_LIMIT = 1 << 30
C_LIMIT = 1 << 61
SUM_LIMIT = 1 << 62
MAX_MESSAGES = 32
MAX_SIGNALS = 64
MAX_TERMS = 4


class MapError(Exception):
    """The map file and the DBC do not fit together (or the map is malformed)."""


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
    checksum_byte: int = 0
    counter_start: int = 0
    counter_length: int = 0
    counter_order: str = "intel"
    terms: list = field(default_factory=list)
    dbc_message: object = None


@dataclass
class Table:
    name: str
    messages: list
    source: str = ""
    gains: dict = field(default_factory=dict)

    @property
    def signals(self):
        return [t for m in self.messages for t in m.terms]


def load_dbc(paths):
    db = cantools.database.Database(strict=False)
    for p in paths:
        try:
            db.add_dbc_file(p)
        except OSError as e:
            raise MapError(f"cannot read DBC file {p}: {e.strerror}") from e
        except Exception as e:  # cantools parse errors have several types
            raise MapError(f"{p}: not a readable DBC file: {e}") from e
    return db


def load_map(path):
    try:
        with open(path, "rb") as f:
            m = tomllib.load(f)
    except OSError as e:
        raise MapError(f"cannot read map file {path}: {e.strerror}") from e
    except tomllib.TOMLDecodeError as e:
        raise MapError(f"{path}: not valid TOML: {e}") from e
    base = os.path.dirname(os.path.abspath(path))
    m["dbc"] = [os.path.join(base, p) for p in m.get("dbc", [])]
    m.setdefault("_path", path)
    return m


def _find_signal(db, ref, where):
    if not isinstance(ref, str) or ref.count(".") != 1:
        raise MapError(f"{where}: signal reference '{ref}' must be MESSAGE.SIGNAL")
    mname, sname = ref.split(".")
    try:
        msg = db.get_message_by_name(mname)
    except KeyError:
        raise MapError(f"{where}: DBC/map mismatch: message '{mname}' is not in the DBC files") from None
    try:
        sig = msg.get_signal_by_name(sname)
    except KeyError:
        raise MapError(f"{where}: DBC/map mismatch: message '{mname}' (0x{msg.frame_id:X}) has no signal "
                       f"'{sname}' (it has: {', '.join(s.name for s in msg.signals)})") from None
    if sig.multiplexer_ids:
        raise MapError(f"{where}: {ref} is multiplexed; multiplexed signals are not supported")
    return msg, sig


def _term_of(sig, input_index, role):
    order = "intel" if sig.byte_order == "little_endian" else "motorola"
    return Term(name=sig.name, input=input_index, role=role, start=sig.start, length=sig.length,
                order=order, signed=1 if sig.is_signed else 0, dbc_signal=sig)


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
                    raise MapError(f"{where}: factor {float(t.k)!r} SI per bit is too small for the integer decoder")
            return s
    raise MapError(f"{where}: factor too large for the integer decoder "
                   f"(more than 2^{30 - frac_bits} SI units per bit)")


def raw_range(term, lo, hi, where):
    """Raw bounds [raw_min, raw_max] of the SI range [lo, hi] (None: unbounded)."""
    rmin, rmax = term.raw_limits()
    if term.k == 0:
        raise MapError(f"{where}: zero factor")
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
        raise MapError(f"{where}: range [{lo}, {hi}] contains no raw value of the signal")
    return a, b


def build_table(db, mp, name=None):
    """Builds the Table from a loaded DBC database and a parsed map."""
    where0 = mp.get("_path", "map")
    name = name or mp.get("name")
    if not name or not re.fullmatch(r"[a-z][a-z0-9_]{0,30}", name):
        raise MapError(f"{where0}: 'name' must be a lower-case C identifier (it names grip_can_table_<name>)")
    msg_cfg = mp.get("messages", {})
    inputs = mp.get("inputs", {})
    if not inputs:
        raise MapError(f"{where0}: no [inputs.*] section")
    messages = {}
    gains = {}
    for iname, spec in inputs.items():
        where = f"{where0}: inputs.{iname}"
        if iname not in INPUT_INDEX:
            raise MapError(f"{where}: unknown estimator input (known: {', '.join(INPUT_INDEX)})")
        idx = INPUT_INDEX[iname]
        si_unit, frac_bits = INPUTS[idx][1], INPUTS[idx][2]
        refs = spec.get("signals")
        if isinstance(refs, str):
            refs = [refs]
        if not refs or len(refs) > MAX_TERMS:
            raise MapError(f"{where}: 'signals' must list 1..{MAX_TERMS} MESSAGE.SIGNAL names")
        gain = exact(spec.get("gain", 1))
        if gain == 0:
            raise MapError(f"{where}: gain 0")
        gains[iname] = gain
        terms = []
        msg = None
        for ref in refs:
            m, sig = _find_signal(db, ref, where)
            if msg is not None and m is not msg:
                raise MapError(f"{where}: all signals of one input must be in one message ({msg.name} vs {m.name})")
            msg = m
            unit = spec.get("unit", sig.unit or "")
            if sig.unit and sig.unit != unit:
                raise MapError(f"{where}: DBC/map mismatch: {ref} is in '{sig.unit}' in the DBC, the map says '{unit}'")
            if unit not in UNITS:
                raise MapError(f"{where}: {ref}: unit '{unit}' unknown (known: {', '.join(UNITS)}); "
                               "give 'unit' in the map")
            if UNITS[unit][0] != si_unit:
                raise MapError(f"{where}: {ref} is in '{unit}' ({UNITS[unit][0]}), input {iname} needs {si_unit}")
            if sig.length > 32:
                raise MapError(f"{where}: {ref} is {sig.length} bits; the decoder takes values of up to 32 bits")
            t = _term_of(sig, idx, "value")
            conv = UNITS[unit][1] * gain
            t.unit = unit
            t.k = exact(sig.scale) * conv
            t.c = exact(sig.offset) * conv
            terms.append(t)
        choose_shift(terms, frac_bits, where)
        rng = spec.get("range")
        for t in terms:
            if rng is not None:
                if len(terms) > 1:
                    raise MapError(f"{where}: 'range' applies to one-signal inputs; the terms use their DBC ranges")
                lo, hi = (exact(rng[0]), exact(rng[1]))
            else:
                s = t.dbc_signal
                conv = UNITS[t.unit][1] * gain
                if s.minimum is not None and s.maximum is not None and s.minimum < s.maximum:
                    lo, hi = exact(s.minimum) * conv, exact(s.maximum) * conv
                    if lo > hi:
                        lo, hi = hi, lo
                else:
                    lo, hi = None, None
            t.raw_min, t.raw_max = raw_range(t, lo, hi, f"{where}: {t.name}")
        quals = []
        for qref, qval in (spec.get("valid_if") or {}).items():
            full = qref if "." in qref else f"{msg.name}.{qref}"
            m, sig = _find_signal(db, full, where)
            if m is not msg:
                raise MapError(f"{where}: qualifier {full} must be in message {msg.name}")
            if sig.length > 32:
                raise MapError(f"{where}: qualifier {full} longer than 32 bits")
            q = _term_of(sig, idx, "qualifier")
            q.raw_min = q.raw_max = int(qval)
            lo, hi = q.raw_limits()
            if not lo <= int(qval) <= hi:
                raise MapError(f"{where}: qualifier value {qval} does not fit {full}")
            quals.append(q)
        if msg.name not in messages:
            messages[msg.name] = _message_of(db, msg, msg_cfg.get(msg.name, {}), f"{where0}: messages.{msg.name}")
        messages[msg.name].terms.extend(terms + quals)
    for mname in msg_cfg:
        if mname not in messages:
            try:
                db.get_message_by_name(mname)
            except KeyError:
                raise MapError(f"{where0}: DBC/map mismatch: [messages.{mname}] is not in the DBC files") from None
            raise MapError(f"{where0}: [messages.{mname}] feeds no input")
    msgs = sorted(messages.values(), key=lambda m: m.id)
    for m in msgs:
        m.terms.sort(key=lambda t: (t.input, t.role != "value"))
    if len(msgs) > MAX_MESSAGES or sum(len(m.terms) for m in msgs) > MAX_SIGNALS:
        raise MapError(f"{where0}: more than {MAX_MESSAGES} messages or {MAX_SIGNALS} signals")
    src = " + ".join(os.path.basename(p) for p in mp.get("dbc", []))
    return Table(name=name, messages=msgs, source=src, gains=gains)


def _message_of(db, msg, cfg, where):
    key = msg.frame_id | (0x80000000 if msg.is_extended_frame else 0)
    if "period_ms" in cfg:
        period_us = int(round(float(cfg["period_ms"]) * 1000))
    elif msg.cycle_time:
        period_us = int(msg.cycle_time) * 1000
    else:
        raise MapError(f"{where}: the DBC gives no cycle time for {msg.name}: set period_ms in the map")
    if period_us <= 0:
        raise MapError(f"{where}: period must be > 0")
    m = Message(name=msg.name, id=key, length=msg.length, period_us=period_us, dbc_message=msg)
    cs = cfg.get("checksum", "none")
    if cs == "toyota":
        try:
            sig = msg.get_signal_by_name(cfg.get("checksum_signal", "CHECKSUM"))
        except KeyError:
            raise MapError(f"{where}: DBC/map mismatch: checksum 'toyota' but {msg.name} has no "
                           f"{cfg.get('checksum_signal', 'CHECKSUM')} signal") from None
        if sig.length != 8 or (sig.byte_order == "big_endian" and sig.start % 8 != 7) or \
           (sig.byte_order == "little_endian" and sig.start % 8 != 0):
            raise MapError(f"{where}: the checksum signal {sig.name} is not one whole byte")
        m.checksum = "toyota"
        m.checksum_byte = sig.start // 8
    elif cs != "none":
        raise MapError(f"{where}: checksum '{cs}' unknown (none, toyota)")
    if "counter" in cfg:
        try:
            sig = msg.get_signal_by_name(cfg["counter"])
        except KeyError:
            raise MapError(f"{where}: DBC/map mismatch: {msg.name} has no counter signal '{cfg['counter']}'") from None
        if sig.length > 8:
            raise MapError(f"{where}: counter {sig.name} longer than 8 bits")
        m.counter_start, m.counter_length = sig.start, sig.length
        m.counter_order = "intel" if sig.byte_order == "little_endian" else "motorola"
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


# ---- output ----------------------------------------------------------------------

def _c_str(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def render_text(table):
    out = [f"grip-can-table 1 {table.name}",
           f"# generated by python -m grip_tools can-table from {table.source}; do not edit",
           "# msg NAME ID LEN PERIOD_US CHECKSUM CHECKSUM_BYTE COUNTER_START COUNTER_LENGTH COUNTER_ORDER",
           "# sig NAME INPUT ROLE START LENGTH ORDER SIGNED SHIFT K C RAW_MIN RAW_MAX"]
    for m in table.messages:
        out.append(f"msg {m.name} 0x{m.id:X} {m.length} {m.period_us} {m.checksum} {m.checksum_byte} "
                   f"{m.counter_start} {m.counter_length} {m.counter_order}")
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
        f" * Signal table '{table.name}': generated by `python -m grip_tools can-table` from",
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
        cs = "GRIP_CAN_CSUM_TOYOTA" if m.checksum == "toyota" else "GRIP_CAN_CSUM_NONE"
        order = "GRIP_CAN_MOTOROLA" if m.counter_order == "motorola" else "GRIP_CAN_INTEL"
        lines.append(f"    {{ {_c_str(m.name)}, 0x{m.id:X}u, {m.period_us}u, {first}u, {len(m.terms)}u, {m.length}u, "
                     f"(uint8_t){cs}, {m.checksum_byte}u, {m.counter_length}u, (uint8_t){order}, {m.counter_start}u }},")
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


def table_from_map(map_path):
    mp = load_map(map_path)
    if not mp["dbc"]:
        raise MapError(f"{map_path}: 'dbc' lists no DBC file")
    db = load_dbc(mp["dbc"])
    return build_table(db, mp), db, mp


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip can-table", description=__doc__.split("\n\n")[0])
    ap.add_argument("map", help="map file (TOML)")
    ap.add_argument("--c", dest="c_out", help="write the table as C source here")
    ap.add_argument("--text", dest="text_out", help="write the table's text form (grip-replay -t) here")
    ap.add_argument("--map-label", help="map path to name in the C header comment (default: as given)")
    args = ap.parse_args(argv)
    try:
        table, _, mp = table_from_map(args.map)
    except MapError as e:
        print(f"can-table: {e}", file=sys.stderr)
        return 1
    if args.c_out:
        label = args.map_label or args.map
        dbcs = mp["dbc"]
        with open(args.c_out, "w") as f:
            f.write(render_c(table, label, dbcs))
    if args.text_out:
        with open(args.text_out, "w") as f:
            f.write(render_text(table))
    if not args.c_out and not args.text_out:
        sys.stdout.write(render_text(table))
    print(f"can-table: {table.name}: {len(table.messages)} messages, {len(table.signals)} signals",
          file=sys.stderr)
    return 0
