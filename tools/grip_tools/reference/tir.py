"""Magic Formula property files (.tir): reader, validator and C emitter.

The coefficients grip uses (key, section, fixed-point format, default,
required flag) are read from include/grip/grip_mf_coefs.h, the one list the C
struct, the C host reader and this module share. Nothing here repeats it.

File grammar (one line at a time, LF or CRLF):
  blank line, or a comment starting with '$' or '!' (after optional blanks)
  [SECTION]            section header (a comment may follow)
  {text}               column names of a table section (kept as text)
  KEY = value          value: number (Fortran 'D' exponents accepted), quoted
                       string ('..' or ".."), or a bare word; '$' or '!'
                       starts an inline comment
  numbers only         a row of a table section such as [SHAPE] or
                       [DEFLECTION_LOAD_CURVE] (kept in Tir.tables)
Anything else is an error. Every error is a TirError naming file, line and
key: "FILE:LINE: KEY: message".

Command line:
  grip tir2c FILE.tir --name NAME -o OUT.c [--header OUT.h]
                                 [--side left|right]
"""
import argparse
import math
import os
import re
import sys
import tempfile

from grip_tools.errors import DataError
from grip_tools.paths import REPO_ROOT
COEFS_HEADER = os.path.join(REPO_ROOT, "include", "grip", "grip_mf_coefs.h")

SUPPORTED_FITTYP = (5, 6, 21, 61, 62)
MF5_FITTYP = (5, 6, 21)
MF6_FITTYP = (61, 62)

# Largest magnitudes the fixed-point formats hold with margin (grip_types.h):
# QS = Q15.16 (|v| < 32768), QL = Q23.8 (|v| < 8388608).
FORMAT_LIMIT = {"QS": 32767.0, "QL": 8.3e6}

# FITTYP when the file has none: from PROPERTY_FILE_FORMAT (upper case).
FITTYP_FROM_FORMAT = {
    "PAC2002": 6, "MF_05": 5, "MF05": 5, "MF_52": 6, "MF52": 6,
    "MF_61": 61, "MF61": 61, "MF_62": 62, "MF62": 62,
}


class TirError(DataError):
    """A .tir file that cannot be used. str(): 'FILE:LINE: KEY: message'
    (.file, .line, .key, .message)."""

    @property
    def key(self):
        return self.field


# ---------------------------------------------------------------------------
# The coefficient list, parsed from the C header.

class Coef:
    __slots__ = ("field", "key", "section", "fmt", "default", "required")

    def __init__(self, field, key, section, fmt, default, required):
        self.field, self.key, self.section = field, key, section
        self.fmt, self.default, self.required = fmt, default, required

    def __repr__(self):
        return f"Coef({self.key} in [{self.section}] {self.fmt} default={self.default} required={self.required})"


_X_RE = re.compile(r"X\(\s*(\w+)\s*,\s*(\w+)\s*,\s*(\w+)\s*,\s*(QS|QL)\s*,\s*([-+0-9.eE]+)\s*,\s*([01])\s*\)")
_COEFS = None


def coefficients(header=COEFS_HEADER):
    """The GRIP_MF_COEFFICIENTS list, in struct order (list of Coef)."""
    global _COEFS
    if _COEFS is not None and header == COEFS_HEADER:
        return _COEFS
    with open(header) as f:
        text = f.read()
    start = text.find("#define GRIP_MF_COEFFICIENTS(X)")
    if start < 0:
        raise RuntimeError(f"{header}: GRIP_MF_COEFFICIENTS not found")
    body = []
    for line in text[start:].splitlines():
        body.append(line)
        if not line.rstrip().endswith("\\"):
            break
    out = [Coef(m.group(1), m.group(2), m.group(3), m.group(4), float(m.group(5)), m.group(6) == "1")
           for m in _X_RE.finditer("\n".join(body))]
    if not out:
        raise RuntimeError(f"{header}: empty coefficient list")
    for c in out:
        if c.field != c.key.lower():
            raise RuntimeError(f"{header}: field {c.field} is not the lower-case key {c.key}")
    if header == COEFS_HEADER:
        _COEFS = out
    return out


# ---------------------------------------------------------------------------
# Units.

LENGTH_UNITS = {"meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0, "m": 1.0,
                "millimeter": 1e-3, "millimeters": 1e-3, "mm": 1e-3,
                "centimeter": 1e-2, "centimeters": 1e-2, "cm": 1e-2,
                "kilometer": 1e3, "kilometers": 1e3, "km": 1e3,
                "inch": 0.0254, "inches": 0.0254, "in": 0.0254,
                "foot": 0.3048, "feet": 0.3048, "ft": 0.3048}
FORCE_UNITS = {"newton": 1.0, "newtons": 1.0, "n": 1.0,
               "kilonewton": 1e3, "kilonewtons": 1e3, "kn": 1e3,
               "pound_force": 4.4482216152605, "lbf": 4.4482216152605,
               "kilogram_force": 9.80665, "kgf": 9.80665}
ANGLE_UNITS = {"radian": 1.0, "radians": 1.0, "rad": 1.0,
               "degree": math.pi / 180.0, "degrees": math.pi / 180.0, "deg": math.pi / 180.0}
MASS_UNITS = {"kg": 1.0, "kilogram": 1.0, "kilograms": 1.0,
              "gram": 1e-3, "grams": 1e-3, "g": 1e-3,
              "tonne": 1e3, "tonnes": 1e3,
              "lb": 0.45359237, "lbs": 0.45359237, "pound_mass": 0.45359237, "lbm": 0.45359237}
TIME_UNITS = {"second": 1.0, "seconds": 1.0, "sec": 1.0, "s": 1.0,
              "millisecond": 1e-3, "milliseconds": 1e-3, "ms": 1e-3,
              "minute": 60.0, "minutes": 60.0, "min": 60.0,
              "hour": 3600.0, "hours": 3600.0, "h": 3600.0}
PRESSURE_UNITS = {"pascal": 1.0, "pascals": 1.0, "pa": 1.0, "n/m2": 1.0, "n/m^2": 1.0,
                  "kilopascal": 1e3, "kpa": 1e3, "megapascal": 1e6, "mpa": 1e6,
                  "bar": 1e5, "mbar": 1e2, "psi": 6894.757293168361}
QUANTITIES = {"LENGTH": LENGTH_UNITS, "FORCE": FORCE_UNITS, "ANGLE": ANGLE_UNITS,
              "MASS": MASS_UNITS, "TIME": TIME_UNITS, "PRESSURE": PRESSURE_UNITS}

# Physical dimension of the coefficients that have one; every other
# coefficient is a dimensionless Magic Formula factor (angles in radians, as
# MF-Tyre defines them) and is never scaled.
DIMENSIONS = {
    "LONGVL": "speed", "VXLOW": "speed",
    "UNLOADED_RADIUS": "length", "WIDTH": "length",
    "INFLPRES": "pressure", "NOMPRES": "pressure", "PRESMIN": "pressure", "PRESMAX": "pressure",
    "FNOMIN": "force", "FZMIN": "force", "FZMAX": "force",
    "VERTICAL_STIFFNESS": "stiffness", "LONGITUDINAL_STIFFNESS": "stiffness",
    "LATERAL_STIFFNESS": "stiffness",
    "ALPMIN": "angle", "ALPMAX": "angle", "CAMMIN": "angle", "CAMMAX": "angle",
}

# min/max pairs checked for min < max (when both are given in the file)
RANGES = (("FZMIN", "FZMAX"), ("KPUMIN", "KPUMAX"), ("ALPMIN", "ALPMAX"),
          ("CAMMIN", "CAMMAX"), ("PRESMIN", "PRESMAX"))
# > 0 (strict) or >= 0
POSITIVE = {"FNOMIN": True, "UNLOADED_RADIUS": True, "LONGVL": True, "VXLOW": True,
            "WIDTH": False, "INFLPRES": False, "NOMPRES": False, "VERTICAL_STIFFNESS": False,
            "LONGITUDINAL_STIFFNESS": False, "LATERAL_STIFFNESS": False,
            "PRESMIN": False, "PRESMAX": False, "FZMIN": False, "FZMAX": False}


# ---------------------------------------------------------------------------
# Parsing.

_KEY_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_NUM_RE = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")


def parse_number(word):
    """float of a strict decimal number (Fortran D exponents allowed) or None."""
    if not _NUM_RE.match(word):
        return None
    try:
        v = float(word.replace("d", "e").replace("D", "e"))
    except ValueError:
        return None
    return v if math.isfinite(v) else None


class Entry:
    """One KEY = value line."""
    __slots__ = ("key", "raw", "quoted", "line")

    def __init__(self, key, raw, quoted, line):
        self.key, self.raw, self.quoted, self.line = key, raw, quoted, line

    @property
    def number(self):
        return None if self.quoted else parse_number(self.raw)


class Tir:
    """A parsed and validated .tir file.

    sections: {SECTION: {KEY: Entry}} (upper-case names, every section kept)
    section_line: {SECTION: line of its header}
    tables: {SECTION: {"header": str or None, "rows": [[float, ...], ...]}}
    values: {KEY: float} SI value of every grip coefficient (defaults filled)
    lines: {KEY: line} (0: default used)
    fittyp, tyreside (+1 LEFT/unknown, -1 RIGHT), units {QUANTITY: factor}
    """

    def __init__(self, path):
        self.path = path
        self.sections = {}
        self.section_line = {}
        self.tables = {}
        self.values = {}
        self.lines = {}
        self.fittyp = None
        self.fittyp_inferred = False
        self.tyreside = 1
        self.tyreside_name = None
        self.units = {}
        self.nlines = 0

    # convenience
    def get(self, section, key, default=None):
        e = self.sections.get(section.upper(), {}).get(key.upper())
        return default if e is None else (e.raw if e.quoted or e.number is None else e.number)

    def params(self, side=None):
        """dict for the reference model and the emitter: every coefficient
        field (lower case, SI) plus fittyp, tyreside, options, name/path.

        side: where the tyre is mounted. None (or 'fitted'): as the file was
        fitted, the way MFeval and MF-Tyre evaluate a property file: never
        mirrored. 'left' or 'right': mounted there; a file fitted for the
        other side (TYRESIDE) is mirrored. tyreside is always the file's;
        the mounting is the GRIP_MF_OPT_RIGHT_SIDE bit of options, as in C."""
        p = {c.field: self.values[c.key] for c in coefficients()}
        p["fittyp"] = self.fittyp
        p["tyreside"] = self.tyreside
        p["options"] = mount_options(side, self.tyreside)
        p["path"] = self.path
        return p


# include/grip/grip_mf.h: the tyre is mounted on the right
OPT_RIGHT_SIDE = 1 << 3
SIDES = ("fitted", "left", "right")


def mount_options(side, file_side=1):
    """The options bit for a mounting side (None or 'fitted': the side the
    file was fitted for, so nothing is mirrored)."""
    if side is None or side == "fitted":
        return OPT_RIGHT_SIDE if file_side == -1 else 0
    if side == "left":
        return 0
    if side == "right":
        return OPT_RIGHT_SIDE
    raise ValueError(f"side must be fitted, left or right, not {side!r}")


def side_description(params):
    """'fitted for RIGHT, mounted right: as fitted' and the like, for reports."""
    fitted = {1: "LEFT", -1: "RIGHT"}[int(params["tyreside"])]
    mount = "right" if int(params.get("options", 0)) & OPT_RIGHT_SIDE else "left"
    return f"fitted for {fitted}, mounted {mount}: {'mirrored' if mirrored(params) else 'as fitted'}"


def mirrored(params):
    """True when params are evaluated mirrored: the mounting side (options)
    differs from the side the file was fitted for (tyreside)."""
    right_mount = bool(int(params.get("options", 0)) & OPT_RIGHT_SIDE)
    return (int(params.get("tyreside", 1)) == -1) != right_mount


def _strip_comment(s):
    """Text before an inline '$' or '!' comment (outside quotes)."""
    q = None
    for i, ch in enumerate(s):
        if q:
            if ch == q:
                q = None
        elif ch in "'\"":
            q = ch
        elif ch in "$!":
            return s[:i]
    return s


def _split_assignment(s):
    """(key, raw, quoted) of 'KEY = value [comment]' or (None, why)."""
    m = _KEY_RE.match(s)
    if not m:
        return None, "expected KEY = value"
    key = m.group(0)
    rest = s[m.end():].lstrip(" \t")
    if not rest.startswith("="):
        return None, "expected '=' after the key"
    v = rest[1:].lstrip(" \t")
    if v[:1] in ("'", '"'):
        close = v.find(v[0], 1)
        if close < 0:
            return None, "unterminated quoted string"
        after = v[close + 1:].strip(" \t")
        if after and after[0] not in "$!":
            return None, "unexpected text after the value"
        return (key, v[1:close], True), None
    v = _strip_comment(v).strip(" \t")
    if " " in v or "\t" in v:
        return None, "unexpected text after the value"
    return (key, v, False), None


def _table_row(s):
    words = _strip_comment(s).split()
    if not words:
        return None
    vals = [parse_number(w) for w in words]
    return None if any(v is None for v in vals) else vals


def parse_text(text, path="<text>"):
    """Parse (no validation): a Tir with sections and tables filled."""
    t = Tir(path)
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    section = None
    for n, raw in enumerate(lines, start=1):
        if "\0" in raw:
            raise TirError(path, n, None, "binary data (NUL byte): not a text .tir file")
        s = raw.rstrip("\r\n \t\f\v").lstrip(" \t\f\v")
        if not s or s[0] in "$!":
            continue
        if s[0] == "[":
            close = s.find("]")
            name = s[1:close].strip() if close > 0 else ""
            after = s[close + 1:].strip() if close > 0 else "x"
            if close < 0 or not name or (after and after[0] not in "$!"):
                raise TirError(path, n, None, f"malformed section header '{s}'")
            section = name.upper()
            # a section may appear twice (some exporters repeat table
            # sections): its keys are merged, a repeated key is an error
            t.section_line.setdefault(section, n)
            t.sections.setdefault(section, {})
            continue
        if s[0] == "{":
            if section is not None:
                t.tables.setdefault(section, {"header": None, "rows": []})["header"] = s
            continue
        if "=" in s and (s[0].isalpha() or s[0] == "_"):
            res, why = _split_assignment(s)
            m = _KEY_RE.match(s)
            if res is None:
                raise TirError(path, n, m.group(0) if m else None, why)
            key, value, quoted = res
            if section is None:
                raise TirError(path, n, key, "key outside any [SECTION]")
            key = key.upper()
            sec = t.sections[section]
            if key in sec:
                raise TirError(path, n, key, f"duplicate key (first on line {sec[key].line})")
            sec[key] = Entry(key, value, quoted, n)
            continue
        row = _table_row(s)
        if row is not None:
            if section is None:
                raise TirError(path, n, None, "table row outside any [SECTION]")
            t.tables.setdefault(section, {"header": None, "rows": []})["rows"].append(row)
            continue
        raise TirError(path, n, None, f"cannot read line '{s[:60]}' (expected KEY = value)")
    t.nlines = len(lines)
    if t.nlines == 0:
        raise TirError(path, 0, None, "empty file")
    return t


def _missing_line(t, section):
    return t.section_line.get(section, t.nlines)


def validate(t):
    """Units, FITTYP, TYRESIDE, coefficients, physical sense, fixed-point
    range. Fills t.values/t.lines/t.fittyp/t.tyreside; raises TirError."""
    path = t.path
    # units
    t.units = {q: 1.0 for q in QUANTITIES}
    units = t.sections.get("UNITS", {})
    for q, table in QUANTITIES.items():
        e = units.get(q)
        if e is None:
            continue
        f = table.get(e.raw.strip().lower())
        if f is None:
            raise TirError(path, e.line, q, f"unit '{e.raw}' cannot be converted to SI")
        t.units[q] = f
    if "PRESSURE" not in units:
        t.units["PRESSURE"] = t.units["FORCE"] / t.units["LENGTH"] ** 2
    factor = {"length": t.units["LENGTH"], "force": t.units["FORCE"], "angle": t.units["ANGLE"],
              "pressure": t.units["PRESSURE"], "speed": t.units["LENGTH"] / t.units["TIME"],
              "stiffness": t.units["FORCE"] / t.units["LENGTH"]}

    # FITTYP
    model = t.sections.get("MODEL", {})
    e = model.get("FITTYP")
    if e is not None:
        v = e.number
        if v is None:
            raise TirError(path, e.line, "FITTYP", f"value '{e.raw}' is not a number")
        if v not in SUPPORTED_FITTYP:
            raise TirError(path, e.line, "FITTYP",
                           f"unsupported Magic Formula version {e.raw} (supported: 5, 6, 21, 61, 62)")
        t.fittyp = int(v)
    else:
        fmt = model.get("PROPERTY_FILE_FORMAT")
        guess = FITTYP_FROM_FORMAT.get(fmt.raw.strip().upper()) if fmt is not None else None
        if guess is None:
            raise TirError(path, _missing_line(t, "MODEL"), "FITTYP",
                           "missing required key in [MODEL] (and no PROPERTY_FILE_FORMAT "
                           "that names the version: PAC2002, MF_05, MF_52, MF_61, MF_62)")
        t.fittyp = guess
        t.fittyp_inferred = True

    # TYRESIDE
    e = model.get("TYRESIDE")
    if e is not None:
        name = e.raw.strip().upper()
        if name == "RIGHT":
            t.tyreside = -1
        elif name in ("LEFT", "UNKNOWN", "SYMMETRIC", ""):
            t.tyreside = 1
        else:
            raise TirError(path, e.line, "TYRESIDE", f"unknown tyre side '{e.raw}' (LEFT, RIGHT, UNKNOWN)")
        t.tyreside_name = name

    # coefficients
    for c in coefficients():
        e = t.sections.get(c.section, {}).get(c.key)
        if e is None:
            if c.required:
                raise TirError(path, _missing_line(t, c.section), c.key,
                               f"missing required key in [{c.section}]")
            t.values[c.key] = c.default
            t.lines[c.key] = 0
            continue
        v = e.number
        if v is None:
            raise TirError(path, e.line, c.key, f"value '{e.raw}' is not a number")
        dim = DIMENSIONS.get(c.key)
        x = v * factor[dim] if dim else v
        if not math.isfinite(x):
            raise TirError(path, e.line, c.key, "value overflows after unit conversion")
        t.values[c.key] = x
        t.lines[c.key] = e.line

    # physical sense
    for key, strict in POSITIVE.items():
        v = t.values[key]
        if (strict and not v > 0.0) or (not strict and not v >= 0.0):
            raise TirError(path, t.lines[key] or _missing_line(t, _section_of(key)), key,
                           f"value {v:g} must be {'> 0' if strict else '>= 0'}")
    for lo, hi in RANGES:
        if t.lines[lo] and t.lines[hi] and not t.values[lo] < t.values[hi]:
            raise TirError(path, t.lines[hi], hi,
                           f"value {t.values[hi]:g} must be greater than {lo} = {t.values[lo]:g}")
    if t.fittyp in MF6_FITTYP and not t.values["NOMPRES"] > 0.0:
        raise TirError(path, t.lines["NOMPRES"] or _missing_line(t, "OPERATING_CONDITIONS"), "NOMPRES",
                       f"FITTYP {t.fittyp} needs a nominal pressure > 0 (got {t.values['NOMPRES']:g})")

    # fixed-point range
    for c in coefficients():
        v = t.values[c.key]
        lim = FORMAT_LIMIT[c.fmt]
        if not abs(v) < lim:
            what = "Q15.16" if c.fmt == "QS" else "Q23.8"
            raise TirError(path, t.lines[c.key] or _missing_line(t, c.section), c.key,
                           f"value {v:g} (SI) does not fit the fixed-point format {c.fmt} = {what} "
                           f"(|v| < {lim:g})")
    return t


def _section_of(key):
    for c in coefficients():
        if c.key == key:
            return c.section
    return None


def read_tir(path):
    """Read and validate a .tir file: a Tir (raises TirError)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as ex:
        raise TirError(path, 0, None, f"cannot open: {ex.strerror}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return validate(parse_text(text, path))


def load_params(path, side=None):
    """Shortcut: the params dict of a validated file."""
    return read_tir(path).params(side)


# ---------------------------------------------------------------------------
# C emitter.

def c_number(v):
    """repr() precision, always a valid C floating literal."""
    s = repr(float(v))
    if "e" not in s and "." not in s and "inf" not in s and "nan" not in s:
        s += ".0"
    return s


def emit_initializer(params, indent="    "):
    """The body '{ .fittyp = .., ... }' of a grip_mf_params initializer."""
    lines = ["{",
             f"{indent}.fittyp = {int(params['fittyp'])},",
             f"{indent}.tyreside = {int(params['tyreside'])},",
             f"{indent}.options = {int(params.get('options', 0))}u,"]
    for c in coefficients():
        macro = "GRIP_QS" if c.fmt == "QS" else "GRIP_QL"
        lines.append(f"{indent}.{c.field} = {macro}({c_number(params[c.field])}),")
    lines[-1] = lines[-1].rstrip(",")
    lines.append("}")
    return "\n".join(lines)


def emit_definition(params, name, storage="const"):
    src = params.get("path", "")
    side = side_description(params)
    return (f"/* {os.path.basename(src)}: FITTYP {params['fittyp']}, {side} */\n"
            f"{storage} grip_mf_params {name} = {emit_initializer(params)};\n")


def emit_c(params, name, header_name=None):
    head = ("/* Generated by `grip tir2c` from "
            f"{params.get('path', '?')}. Do not edit. */\n")
    inc = f'#include "{header_name}"\n' if header_name else '#include "grip/grip_mf.h"\n'
    return head + inc + "\n" + emit_definition(params, name)


def emit_h(name, header_name):
    guard = re.sub(r"[^A-Za-z0-9]", "_", os.path.basename(header_name)).upper()
    return ("/* Generated by `grip tir2c`. Do not edit. */\n"
            f"#ifndef {guard}\n#define {guard}\n\n#include \"grip/grip_mf.h\"\n\n"
            f"extern const grip_mf_params {name};\n\n#endif /* {guard} */\n")


def write_atomic(files):
    """Write {path: text} all-or-nothing: temp files first, then renames."""
    tmps = []
    try:
        for path, text in files.items():
            d = os.path.dirname(os.path.abspath(path))
            fd, tmp = tempfile.mkstemp(prefix=".tir2c-", dir=d)
            tmps.append((tmp, path))
            with os.fdopen(fd, "w") as f:
                f.write(text)
        for tmp, path in tmps:
            os.replace(tmp, path)
        tmps = []
    finally:
        for tmp, _ in tmps:
            if os.path.exists(tmp):
                os.unlink(tmp)


# C99 keywords and the names the emitted file itself uses.
C_RESERVED = frozenset(("auto break case char const continue default do double else enum extern float for goto if "
                        "inline int long register restrict return short signed sizeof static struct switch typedef "
                        "union unsigned void volatile while _Bool _Complex _Imaginary "
                        "grip_mf_params grip_real_t").split())


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip tir2c",
                                 description="Emit a grip_mf_params C definition from a .tir file.")
    ap.add_argument("tir")
    ap.add_argument("--name", required=True, help="C identifier of the parameter set")
    ap.add_argument("-o", "--output", required=True, help="the .c file to write")
    ap.add_argument("--header", help="also write a .h declaring NAME")
    ap.add_argument("--side", choices=SIDES, default="fitted",
                    help="where the tyre is mounted (default: as fitted, never mirrored); left or right "
                         "mirrors a file fitted for the other side (GRIP_MF_OPT_RIGHT_SIDE in .options)")
    args = ap.parse_args(argv)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", args.name) or args.name in C_RESERVED \
            or re.match(r"_[A-Z_]", args.name):
        ap.error(f"--name '{args.name}' is not a usable C identifier (a letter or '_' first, no C keyword, "
                 "no reserved '_X' or '__' prefix)")
    for out in (args.output, args.header):
        folder = os.path.dirname(os.path.abspath(out)) if out else None
        if folder and not os.path.isdir(folder):
            ap.error(f"the output folder {folder} does not exist")
    # a TirError names file, line and key; the grip command prints it (exit 3)
    params = read_tir(args.tir).params(args.side)
    files = {}
    hname = None
    if args.header:
        hname = os.path.basename(args.header)
        files[args.header] = emit_h(args.name, args.header)
    files[args.output] = emit_c(params, args.name, hname)
    write_atomic(files)
    return 0


if __name__ == "__main__":
    sys.exit(main())
