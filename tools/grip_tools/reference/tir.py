"""Magic Formula property files (.tir): reader, validator and C emitter.

The coefficients grip uses (key, section, fixed-point format, default,
required flag) are read from include/grip/grip_mf_coefs.h, the one list the C
struct, the C host reader and this module share. Nothing here repeats it.

The rules that are data (the MF-Tyre keys grip knows but does not read,
the plausibility range of every coefficient family, the bounds of the
reader) are port/linux/tir_rules.h, the table the C reader compiles; this
module reads it, so both readers apply the same rules in the same order and
report the same first error and the same warnings.

File grammar (one line at a time, LF or CRLF):
  blank line, or a comment starting with '$' or '!' (after optional blanks)
  [SECTION]            section header (a comment may follow)
  {text}               column names of a table section (kept as text)
  KEY = value          value: number (Fortran 'D' exponents accepted), quoted
                       string ('..' or ".."), a bare word, or nothing (an
                       empty value); '$' or '!' starts an inline comment
  numbers only         a row of a table section such as [SHAPE] or
                       [DEFLECTION_LOAD_CURVE] (kept in Tir.tables)
Anything else is an error. Every error is a TirError naming file, line and
key: "FILE:LINE: KEY: message"; every warning (a TirWarning: an unknown
key, a coefficient in another section, an empty value) has the same form.
Bounds: 4 MiB a file, 4096 bytes a line, 4096 keys, 4096 table rows.

Command line:
  grip tir2c FILE.tir --name NAME -o OUT.c [--header OUT.h]
                                 [--side left|right] [--strict] [--no-range-check]
"""
import argparse
import math
import os
import re
import stat
import sys
import tempfile

from grip_tools.errors import EXIT_HELP, DataError
from grip_tools.paths import REPO_ROOT
COEFS_HEADER = os.path.join(REPO_ROOT, "include", "grip", "grip_mf_coefs.h")
RULES_HEADER = os.path.join(REPO_ROOT, "port", "linux", "tir_rules.h")

# The FITTYP values grip evaluates (Tir.fittyp); 52 in a file (MF 5.2, as
# later MF-Tool exports write it) is read as 21 (Tir.fittyp_file keeps 52).
SUPPORTED_FITTYP = (5, 6, 21, 61, 62)
FILE_FITTYP = {5: 5, 6: 6, 21: 21, 52: 21, 61: 61, 62: 62}
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


class TirWarning:
    """Something a reader reads past: str() 'FILE:LINE: KEY: message'
    (.file, .line, .key, .message). Under strict reading it is a TirError."""

    def __init__(self, file, line, key, message):
        self.file, self.line, self.key, self.message = file, line, key, message

    def __str__(self):
        return f"{self.file}:{self.line}: {self.key or '-'}: {self.message}"

    def __repr__(self):
        return f"TirWarning({str(self)!r})"


def _print_warning(w):
    print(f"warning: {w}", file=sys.stderr)


# How read_tir reads when its caller does not say (the tools' --strict and
# --no-range-check set these), and where warnings go (the grip command
# prefixes them with its name).
POLICY = {"strict": False, "range_check": True}
_WARNING_HANDLER = [_print_warning]


def set_policy(strict=None, range_check=None):
    """The defaults of read_tir for this process (None: unchanged)."""
    if strict is not None:
        POLICY["strict"] = bool(strict)
    if range_check is not None:
        POLICY["range_check"] = bool(range_check)


def set_warning_handler(fn):
    """fn(TirWarning) receives every warning (default: 'warning: ...' on
    stderr); returns the previous handler."""
    old = _WARNING_HANDLER[0]
    _WARNING_HANDLER[0] = fn
    return old


def add_reader_options(ap):
    """--strict and --no-range-check for a command that reads .tir files."""
    ap.add_argument("--strict", action="store_true",
                    help=".tir: every warning is an error (an unknown key, a key in another section, an empty value)")
    ap.add_argument("--no-range-check", action="store_true",
                    help=".tir: accept coefficients outside their plausible ranges (docs/tools.md); the hard checks stay")


def apply_reader_options(args):
    """Sets the policy from add_reader_options' options."""
    set_policy(strict=getattr(args, "strict", False), range_check=not getattr(args, "no_range_check", False))


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
# The rules of port/linux/tir_rules.h.

class Rules:
    __slots__ = ("line_max", "size_max", "keys_max", "rows_max", "sections_max", "sections", "read_keys",
                 "known_keys", "ranges")


_RULES = None
_DEFINE_RE = re.compile(r"#define\s+GRIP_TIR_(LINE_MAX|SIZE_MAX|KEYS_MAX|ROWS_MAX|SECTIONS_MAX)\s+(\d+)L?\b")
_RANGE_RE = re.compile(r'X\(\s*"([A-Z0-9_]+\*?)"\s*,\s*(VAL0|VAL|ABS)\s*,\s*([-+0-9.eE]+)\s*,\s*([-+0-9.eE]+)\s*,'
                       r'\s*"([^"]*)"\s*\)')


def _macro_body(text, name):
    start = text.find(f"#define {name}(X)")
    if start < 0:
        raise RuntimeError(f"{RULES_HEADER}: {name} not found")
    body = []
    for line in text[start:].splitlines():
        body.append(line)
        if not line.rstrip().endswith("\\"):
            break
    return "\n".join(body)[len(f"#define {name}(X)"):]


def rules():
    """The tables and bounds of tir_rules.h (a Rules)."""
    global _RULES
    if _RULES is not None:
        return _RULES
    with open(RULES_HEADER) as f:
        text = f.read()
    r = Rules()
    defs = dict((m.group(1), int(m.group(2))) for m in _DEFINE_RE.finditer(text))
    r.line_max, r.size_max, r.keys_max = defs["LINE_MAX"], defs["SIZE_MAX"], defs["KEYS_MAX"]
    r.rows_max, r.sections_max = defs["ROWS_MAX"], defs["SECTIONS_MAX"]
    r.sections = re.findall(r"X\((\w+)\)", _macro_body(text, "GRIP_TIR_SECTIONS"))
    r.read_keys = re.findall(r"X\((\w+),\s*(\w+)\)", _macro_body(text, "GRIP_TIR_READ_KEYS"))
    r.known_keys = re.findall(r"X\((\w+)\)", _macro_body(text, "GRIP_TIR_KNOWN_KEYS"))
    r.ranges = [(m.group(1), m.group(2), float(m.group(3)), float(m.group(4)), m.group(5))
                for m in _RANGE_RE.finditer(_macro_body(text, "GRIP_TIR_RANGES"))]
    if not (r.sections and r.read_keys and r.known_keys and r.ranges):
        raise RuntimeError(f"{RULES_HEADER}: a table is empty")
    _RULES = r
    return r


def range_of(key):
    """(pattern, kind, lo, hi, what) of the plausibility range of KEY, or None."""
    for rg in rules().ranges:
        pat = rg[0]
        if (key.startswith(pat[:-1]) if pat.endswith("*") else key == pat):
            return rg
    return None


def _edit_distance(a, b):
    if len(a) >= 64 or len(b) >= 64:
        return 99
    row = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        diag, row[0] = row[0], i
        for j in range(1, len(b) + 1):
            up = row[j]
            row[j] = min(diag + (a[i - 1] != b[j - 1]), up + 1, row[j - 1] + 1)
            diag = up
    return row[len(b)]


def nearest_key(key):
    """The nearest key grip knows (edit distance <= 2, KEY of 4 or more
    characters, the first of equals in table order) or None."""
    if len(key) < 4:
        return None
    best, bd = None, 3
    r = rules()
    for cand in [c.key for c in coefficients()] + [k for _, k in r.read_keys] + r.known_keys:
        d = _edit_distance(key, cand)
        if d < bd:
            best, bd = cand, d
    return best


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
    if len(word) >= 128 or not _NUM_RE.match(word):
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
    entries: [(SECTION, Entry)] every KEY = value line in file order
    values: {KEY: float} SI value of every grip coefficient (defaults filled)
    lines: {KEY: line} (0: default used)
    fittyp (the version evaluated), fittyp_file (FITTYP as written, None if
    not given: 52 is read as 21), tyreside (+1 LEFT/unknown, -1 RIGHT),
    units {QUANTITY: factor}, use_mode (the file's USE_MODE, None if not
    given) and use_mode_line, warnings [TirWarning]
    """

    def __init__(self, path):
        self.path = path
        self.sections = {}
        self.section_line = {}
        self.tables = {}
        self.entries = []
        self.values = {}
        self.lines = {}
        self.fittyp = None
        self.fittyp_file = None
        self.fittyp_inferred = False
        self.tyreside = 1
        self.tyreside_name = None
        self.units = {}
        self.use_mode = None
        self.use_mode_line = 0
        self.warnings = []
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
        # the file's USE_MODE (None: not given); grip_mf_params has no field
        # for it: the reader accepts only what the evaluation implements
        p["tir_use_mode"] = self.use_mode
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


def _lines(text):
    """The lines of text (split at LF, a last empty line dropped), one at a
    time: a 4 MiB file of short lines is never held as a list."""
    pos, n = 0, len(text)
    while pos < n:
        nl = text.find("\n", pos)
        if nl < 0:
            yield text[pos:]
            return
        yield text[pos:nl]
        pos = nl + 1


def parse_text(text, path="<text>"):
    """Parse (no validation): a Tir with sections and tables filled."""
    r = rules()
    t = Tir(path)
    section = None
    n = 0
    rows = 0
    for n, raw in enumerate(_lines(text), start=1):
        if "\0" in raw:
            raise TirError(path, n, None, "binary data (NUL byte): not a text .tir file")
        if len(raw) > r.line_max:
            raise TirError(path, n, None, f"line longer than {r.line_max} characters: not a .tir file")
        if n == 1 and raw.startswith("\ufeff"):
            raw = raw[1:]        # UTF-8 byte order mark
        s = raw.rstrip("\r\n \t\f\v").lstrip(" \t\f\v")
        if not s or s[0] in "$!":
            continue
        if s[0] == "[":
            close = s.find("]")
            name = s[1:close].strip() if close > 0 else ""
            after = s[close + 1:].strip() if close > 0 else "x"
            if close < 0 or not name or close - 1 >= 128 or (after and after[0] not in "$!"):
                raise TirError(path, n, None, f"malformed section header '{s[:60]}'")
            section = name.upper()
            # a section may appear twice (some exporters repeat table
            # sections): its keys are merged, a repeated key is an error
            if section not in t.sections:
                if len(t.sections) >= r.sections_max:
                    raise TirError(path, n, None, f"more than {r.sections_max} sections: not a .tir file")
                t.section_line[section] = n
                t.sections[section] = {}
            continue
        if s[0] == "{":
            if section is not None:
                t.tables.setdefault(section, {"header": None, "rows": []})["header"] = s
            continue
        if "=" in s and (s[0].isalpha() or s[0] == "_"):
            res, why = _split_assignment(s)
            m = _KEY_RE.match(s)
            if res is None:
                raise TirError(path, n, m.group(0)[:63] if m else None, why)
            key, value, quoted = res
            if section is None:
                raise TirError(path, n, key, "key outside any [SECTION]")
            key = key.upper()
            sec = t.sections[section]
            if key in sec:
                raise TirError(path, n, key, f"duplicate key (first on line {sec[key].line})")
            if len(t.entries) >= r.keys_max:
                raise TirError(path, n, None, f"more than {r.keys_max} keys: not a .tir file")
            sec[key] = Entry(key, value, quoted, n)
            t.entries.append((section, sec[key]))
            continue
        row = _table_row(s)
        if row is not None:
            if section is None:
                raise TirError(path, n, None, "table row outside any [SECTION]")
            rows += 1
            if rows > r.rows_max:
                raise TirError(path, n, None, f"more than {r.rows_max} table rows: not a .tir file")
            t.tables.setdefault(section, {"header": None, "rows": []})["rows"].append(row)
            continue
        raise TirError(path, n, None, f"cannot read line '{s[:60]}' (expected KEY = value)")
    t.nlines = n
    if t.nlines == 0:
        raise TirError(path, 0, None, "empty file")
    return t


def _missing_line(t, section):
    return t.section_line.get(section, t.nlines)


def _check_keys(t, warn):
    """Every key in file order: one grip reads but in another section, or one
    no MF-Tyre file has in a known section, is a warning. Keys of unknown
    (vendor) sections are not checked, except for keys grip reads."""
    r = rules()
    own_section = {c.key: c.section for c in reversed(coefficients())}
    for sec, key in r.read_keys:
        own_section.setdefault(key, sec)
    known_sections = set(r.sections) | {c.section for c in coefficients()}
    known_keys = set(r.known_keys)
    coefs = {c.key: c for c in coefficients()}
    for section, e in t.entries:
        own = own_section.get(e.key)
        known_section = section in known_sections
        if own is not None:
            if own != section and e.key not in known_keys:
                warn(e.line, e.key, f"grip reads {e.key} from [{own}], not from "
                                    f"{'' if known_section else 'the unknown section '}[{section}]: "
                                    "this value is ignored")
        elif known_section and e.key not in known_keys:
            near = nearest_key(e.key)
            c = coefs.get(near)
            if c is not None and c.section == section and near not in t.sections.get(section, {}):
                # a misspelling of a coefficient the file does not give: its
                # value would be lost and the default read instead
                raise TirError(t.path, e.line, e.key,
                               f"unknown key in [{section}]: a misspelling of {near}? The file does not give "
                               f"{near}, which would take its default {c.default:g}: rename the key, or give {near}")
            warn(e.line, e.key, f"unknown key in [{section}]: ignored" + (f" (did you mean {near}?)" if near else ""))


def _is_empty(e):
    """`KEY =` with nothing after it (a quoted '' is a value: a string)."""
    return not e.quoted and e.raw == ""


def _check_use_mode(t, e, pure_slip):
    """USE_MODE (MF-Tyre): units digit the slip calculation (0 Fz only, 1
    Fx/My, 2 Fy/Mx/Mz, 3 uncombined, 4 combined, 5 combined + turn slip),
    tens digit the dynamics (0 steady state, 1 and 2 relaxation, 3 rigid
    ring), hundreds digit the road contact (0..5); MF-Tyre 5.x: negative =
    mirrored. grip evaluates the steady-state Magic Formula at the contact
    point, so the dynamics and contact digits do not change what it computes
    (relaxation is grip_relax, applied by the caller); of the slip digits it
    implements 4 (combined slip) and, for a caller that evaluates pure slip,
    3. Everything else is refused with the reason."""
    path = t.path
    v = e.number
    if v is None or v != math.floor(v):
        raise TirError(path, e.line, "USE_MODE", f"value '{e.raw}' is not an integer")
    if v < 0:
        raise TirError(path, e.line, "USE_MODE",
                       f"{e.raw}: a negative USE_MODE mirrors the tyre (MF-Tyre 5.x); grip mounts a tyre by "
                       f"TYRESIDE and the side option (--side): write USE_MODE = {-v:g} and give the side")
    if v > 999:
        raise TirError(path, e.line, "USE_MODE", f"{e.raw} is not a USE_MODE of MF-Tyre (at most three digits)")
    m = int(v)
    if m // 100 > 5:
        raise TirError(path, e.line, "USE_MODE",
                       f"{m}: hundreds digit {m // 100} is not a road contact of MF-Tyre (0..5)")
    if (m // 10) % 10 > 3:
        raise TirError(path, e.line, "USE_MODE",
                       f"{m}: tens digit {(m // 10) % 10} is not a dynamics mode of MF-Tyre (0 steady state, "
                       "1 and 2 relaxation, 3 rigid ring)")
    slip = m % 10
    if slip == 0:
        raise TirError(path, e.line, "USE_MODE", f"{m} asks for Fz only, no Magic Formula forces; grip evaluates "
                                                 "Fx, Fy and Mz (USE_MODE units digit 4)")
    if slip in (1, 2):
        raise TirError(path, e.line, "USE_MODE",
                       f"{m} asks for {'Fx and My' if slip == 1 else 'Fy, Mx and Mz'} only; grip evaluates Fx, Fy "
                       "and Mz together (USE_MODE units digit 4)")
    if slip == 3 and not pure_slip:
        raise TirError(path, e.line, "USE_MODE",
                       f"{m} asks for uncombined forces (pure slip); this evaluation is combined slip (USE_MODE "
                       f"units digit 4): evaluate pure slip (grip-tire --pure, grip_mf_eval_pure) or write "
                       f"USE_MODE = {m + 1}")
    if slip == 5:
        raise TirError(path, e.line, "USE_MODE",
                       f"{m} asks for combined slip with turn slip; grip takes turn slip per call, not from the "
                       f"file (grip_mf_eval_ext with GRIP_MF_USE_TURN_SLIP, grip-tire --turn-slip): write "
                       f"USE_MODE = {m - 1} and ask for it there")
    if slip > 5:
        raise TirError(path, e.line, "USE_MODE", f"{m}: units digit {slip} is not a slip calculation of MF-Tyre (0..5)")
    t.use_mode = m
    t.use_mode_line = e.line


def _range_text(kind, lo, hi):
    if kind == "VAL0":
        return f"0 or [{lo:g}, {hi:g}]"
    if kind == "ABS":
        return f"|v| in [{lo:g}, {hi:g}]"
    return f"[{lo:g}, {hi:g}]"


def _in_range(v, kind, lo, hi):
    if kind == "VAL0":
        return v == 0.0 or lo <= v <= hi
    if kind == "ABS":
        return lo <= abs(v) <= hi
    return lo <= v <= hi


def validate(t, strict=None, range_check=None, pure_slip=False):
    """Keys, units, FITTYP, USE_MODE, TYRESIDE, coefficients, physical sense,
    fixed-point range, plausibility (in this order, the C reader's).
    Fills t.values/t.lines/t.fittyp/t.tyreside/t.use_mode/t.warnings;
    raises TirError. strict: every warning is an error; range_check: the
    plausibility ranges of tir_rules.h (None: POLICY); pure_slip: the caller
    evaluates pure slip (USE_MODE units digit 3 accepted)."""
    path = t.path
    strict = POLICY["strict"] if strict is None else strict
    range_check = POLICY["range_check"] if range_check is None else range_check
    t.warnings = []

    def warn(line, key, message):
        if strict:
            raise TirError(path, line, key, f"{message} (refused: strict mode)")
        w = TirWarning(path, line, key, message)
        t.warnings.append(w)
        _WARNING_HANDLER[0](w)

    # keys grip does not know, or reads from another section
    _check_keys(t, warn)

    # units
    t.units = {q: 1.0 for q in QUANTITIES}
    units = t.sections.get("UNITS", {})
    for q, table in QUANTITIES.items():
        e = units.get(q)
        if e is not None and _is_empty(e):
            warn(e.line, q, "empty value: read as the SI unit")
            e = None
        if e is None:
            continue
        f = table.get(e.raw.strip().lower())
        if f is None:
            raise TirError(path, e.line, q, f"unit '{e.raw[:60]}' cannot be converted to SI")
        t.units[q] = f
    if "PRESSURE" not in units or _is_empty(units["PRESSURE"]):
        t.units["PRESSURE"] = t.units["FORCE"] / t.units["LENGTH"] ** 2
    factor = {"length": t.units["LENGTH"], "force": t.units["FORCE"], "angle": t.units["ANGLE"],
              "pressure": t.units["PRESSURE"], "speed": t.units["LENGTH"] / t.units["TIME"],
              "stiffness": t.units["FORCE"] / t.units["LENGTH"]}

    # FITTYP
    model = t.sections.get("MODEL", {})
    e = model.get("FITTYP")
    if e is not None and _is_empty(e):
        warn(e.line, "FITTYP", "empty value: read as not given")
        e = None
    if e is not None:
        v = e.number
        if v is None:
            raise TirError(path, e.line, "FITTYP", f"value '{e.raw[:60]}' is not a number")
        if v not in FILE_FITTYP:
            raise TirError(path, e.line, "FITTYP",
                           f"unsupported Magic Formula version {e.raw[:60]} (supported: 5, 6, 21, 52 = MF 5.x / "
                           "PAC2002; 61, 62 = MF 6.1, 6.2)")
        t.fittyp = FILE_FITTYP[int(v)]
        t.fittyp_file = int(v)
    else:
        fmt = model.get("PROPERTY_FILE_FORMAT")
        guess = FITTYP_FROM_FORMAT.get(fmt.raw.strip().upper()) if fmt is not None else None
        if guess is None:
            raise TirError(path, _missing_line(t, "MODEL"), "FITTYP",
                           "missing required key in [MODEL] (and no PROPERTY_FILE_FORMAT "
                           "that names the version: PAC2002, MF_05, MF_52, MF_61, MF_62)")
        t.fittyp = guess
        t.fittyp_inferred = True

    # USE_MODE
    e = model.get("USE_MODE")
    if e is not None and _is_empty(e):
        warn(e.line, "USE_MODE", "empty value: read as not given")
        e = None
    if e is not None:
        _check_use_mode(t, e, pure_slip)

    # TYRESIDE
    e = model.get("TYRESIDE")
    if e is not None:
        name = e.raw.strip().upper()
        if name == "RIGHT":
            t.tyreside = -1
        elif name in ("LEFT", "UNKNOWN", "SYMMETRIC", ""):
            t.tyreside = 1
        else:
            raise TirError(path, e.line, "TYRESIDE", f"unknown tyre side '{e.raw[:60]}' (LEFT, RIGHT, UNKNOWN)")
        t.tyreside_name = name

    # coefficients
    for c in coefficients():
        e = t.sections.get(c.section, {}).get(c.key)
        if e is not None and _is_empty(e):
            if c.required:
                raise TirError(path, e.line, c.key, "empty value for a required key")
            warn(e.line, c.key, f"empty value: the default {c.default:g} is used")
            e = None
        if e is None:
            if c.required:
                raise TirError(path, _missing_line(t, c.section), c.key,
                               f"missing required key in [{c.section}]")
            t.values[c.key] = c.default
            t.lines[c.key] = 0
            continue
        v = e.number
        if v is None:
            raise TirError(path, e.line, c.key, f"value '{e.raw[:60]}' is not a number")
        dim = DIMENSIONS.get(c.key)
        x = v * factor[dim] if dim else v
        if not math.isfinite(x):
            raise TirError(path, e.line, c.key, "value overflows after unit conversion")
        t.values[c.key] = x
        t.lines[c.key] = e.line

    # physical sense
    for key, strict_pos in POSITIVE.items():
        v = t.values[key]
        if (strict_pos and not v > 0.0) or (not strict_pos and not v >= 0.0):
            raise TirError(path, t.lines[key] or _missing_line(t, _section_of(key)), key,
                           f"value {v:g} must be {'> 0' if strict_pos else '>= 0'}")
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

    # plausibility (port/linux/tir_rules.h), of the values the file gives
    if range_check:
        for c in coefficients():
            if not t.lines[c.key]:
                continue
            rg = range_of(c.key)
            if rg is None:
                continue
            _, kind, lo, hi, what = rg
            v = t.values[c.key]
            if not _in_range(v, kind, lo, hi):
                raise TirError(path, t.lines[c.key], c.key,
                               f"value {v:g} (SI) is outside the plausible range {_range_text(kind, lo, hi)} "
                               f"({what}); --no-range-check accepts it")
    return t


def _section_of(key):
    for c in coefficients():
        if c.key == key:
            return c.section
    return None


def _check_bytes(data, path):
    """The C reader's first pass over at most GRIP_TIR_SIZE_MAX + 1 bytes:
    line by line, no NUL byte, no line longer than GRIP_TIR_LINE_MAX; then
    the size."""
    r = rules()
    lim = min(len(data), r.size_max)
    pos, line = 0, 1
    while pos < lim:
        nl = data.find(b"\n", pos, lim)
        end = lim if nl < 0 else nl
        z = data.find(b"\0", pos, end)
        if 0 <= z <= pos + r.line_max:
            raise TirError(path, line, None, f"NUL byte at byte offset {z} (byte {z - pos + 1} of the line): "
                                             "not a text .tir file")
        if end - pos > r.line_max:
            raise TirError(path, line, None, f"line longer than {r.line_max} bytes (at byte offset {pos}): "
                                             "not a .tir file")
        if nl < 0:
            break
        pos, line = nl + 1, line + 1
    if len(data) > r.size_max:
        raise TirError(path, 0, None, f"larger than {r.size_max} bytes: not a .tir file")


def read_tir(path, strict=None, range_check=None, pure_slip=False):
    """Read and validate a .tir file: a Tir (raises TirError). At most
    GRIP_TIR_SIZE_MAX bytes are read, whatever the file (a device, a huge
    sparse file). strict, range_check, pure_slip: as validate()."""
    r = rules()
    try:
        with open(path, "rb") as f:
            st = os.fstat(f.fileno())
            if stat.S_ISREG(st.st_mode) and st.st_size > r.size_max:
                raise TirError(path, 0, None, f"larger than {r.size_max} bytes: not a .tir file")
            data = f.read(r.size_max + 1)
    except OSError as ex:
        if ex.errno is not None and ex.filename is None:
            raise TirError(path, 1, None, f"read error: {ex.strerror}") from None
        raise TirError(path, 0, None, f"cannot open: {ex.strerror}") from None
    _check_bytes(data, path)
    if not data:
        raise TirError(path, 0, None, "empty file")
    bom = "\ufeff" if data.startswith(b"\xef\xbb\xbf") else ""   # skipped on line 1, as in C
    body = data[len(bom) * 3:]
    del data
    try:
        text = bom + body.decode("utf-8")
    except UnicodeDecodeError:
        text = bom + body.decode("latin-1")
    del body
    return validate(parse_text(text, path), strict, range_check, pure_slip)


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
                                 description="Emit a grip_mf_params C definition from a .tir file.",
                                 epilog=EXIT_HELP + "; nothing is written on any error")
    ap.add_argument("tir")
    ap.add_argument("--name", required=True, help="C identifier of the parameter set")
    ap.add_argument("-o", "--output", required=True, help="the .c file to write")
    ap.add_argument("--header", help="also write a .h declaring NAME")
    ap.add_argument("--side", choices=SIDES, default="fitted",
                    help="where the tyre is mounted (default: as fitted, never mirrored); left or right "
                         "mirrors a file fitted for the other side (GRIP_MF_OPT_RIGHT_SIDE in .options)")
    add_reader_options(ap)
    args = ap.parse_args(argv)
    apply_reader_options(args)
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
