"""A tolerant DBC reader: what the signal-table generator needs from a DBC
file (messages, signals, units, ranges, cycle times), with the file and line
of everything it reads.

Why not cantools alone: DBC files in the wild (opendbc's among them) use
forms cantools refuses although they change nothing a decoder needs:

  - comment forms: `CM_ 145 "..."` (a message comment without BO_),
    `CM_ SG_ 304 "..."` (no signal name), a CM_ without its `;`
  - value tables (VAL_) of signals that do not exist
  - numbers written `.25`, names that start with a digit (`0_COUNTER`)
  - ids above 0x7FF without the extended-frame bit (taken as 29-bit ids,
    as opendbc does)
  - opendbc's generator templates: `CM_ "IMPORT file.dbc";` lines, which
    are followed (the imported file is read first, from the same folder)

Comments and attributes other than GenMsgCycleTime are skipped, whatever
their form. Anything this reader cannot use (a malformed BO_ or SG_ line,
a signal before any message, a length beyond 64 bytes) raises DataError
with the file, line and what is wrong; it never guesses a signal.

Numbers are kept as the exact decimals they are written as (Fraction).
"""
import os
import re
from fractions import Fraction

from grip_tools.errors import DataError

NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
NAME = r"[A-Za-z0-9_]+"
BO_RE = re.compile(rf"BO_\s+(\d+)\s+({NAME})\s*:\s*(\d+)(?:\s+(\S+))?\s*$")
SG_RE = re.compile(
    rf"SG_\s+({NAME})\s*(M|m\d*M?)?\s*:\s*(\d+)\s*\|\s*(\d+)\s*@\s*([01])\s*([+-])\s*"
    rf"\(\s*({NUM})\s*,\s*({NUM})\s*\)\s*\[\s*({NUM})\s*\|\s*({NUM})\s*\]\s*\"((?:[^\"\\]|\\.)*)\"(.*)$")
# statements that are one line (no `;`)
LINE_KEYWORDS = ("BO_", "SG_", "BU_", "VERSION", "BS_", "NS_")
# statements that end with `;` (skipped unless listed in _statement)
SEMI_KEYWORDS = ("CM_", "BA_DEF_", "BA_DEF_DEF_", "BA_", "VAL_", "VAL_TABLE_", "SIG_VALTYPE_",
                 "SG_MUL_VAL_", "BO_TX_BU_", "EV_", "ENVVAR_DATA_", "SGTYPE_", "SGTYPE_VAL_",
                 "SIG_GROUP_", "SIG_TYPE_REF_", "SIGTYPE_VALTYPE_", "BA_DEF_SGTYPE_", "BA_SGTYPE_",
                 "BA_DEF_REL_", "BA_REL_", "BA_DEF_DEF_REL_", "BU_SG_REL_", "BU_EV_REL_", "BU_BO_REL_",
                 "CAT_DEF_", "CAT_", "FILTER", "EV_DATA_")
KEYWORD_RE = re.compile(r"([A-Z][A-Z_]*)\b")
INDEPENDENT_SIG_MSG = "VECTOR__INDEPENDENT_SIG_MSG"   # Vector's pseudo message for unassigned signals


class Signal:
    """One SG_ line (attribute names as cantools', so code can take either)."""

    def __init__(self, name, start, length, byte_order, is_signed, scale, offset, minimum, maximum,
                 unit, mux, file, line):
        self.name = name
        self.start = start
        self.length = length
        self.byte_order = byte_order          # "little_endian" | "big_endian"
        self.is_signed = is_signed
        self.scale = scale                    # Fraction
        self.offset = offset                  # Fraction
        self.minimum = minimum                # Fraction
        self.maximum = maximum
        self.unit = unit
        self.mux = mux                        # None, "M" (multiplexer), "m3" / "m3M" (multiplexed)
        self.is_float = False                 # SIG_VALTYPE_ 1 or 2
        self.file = file
        self.line = line

    @property
    def multiplexer_ids(self):
        if self.mux and self.mux.startswith("m"):
            sel = self.mux[1:].rstrip("M")
            return [int(sel) if sel else None]
        return None

    @property
    def is_multiplexer(self):
        return bool(self.mux) and self.mux.endswith("M")

    def __repr__(self):
        return f"Signal({self.name} {self.start}|{self.length} {self.byte_order} {self.file}:{self.line})"


class Message:
    def __init__(self, dbc_id, name, length, sender, file, line, root):
        self.dbc_id = dbc_id
        self.name = name
        self.length = length
        self.sender = sender
        self.file = file
        self.line = line
        self.root = root                      # the DBC file named by the user that brought it in
        self.signals = []
        self.cycle_time = None
        self.implied_extended = False
        if dbc_id & 0x80000000:
            self.frame_id = dbc_id & 0x1FFFFFFF
            self.is_extended_frame = True
        elif dbc_id > 0x7FF:
            self.frame_id = dbc_id & 0x1FFFFFFF
            self.is_extended_frame = True
            self.implied_extended = True
        else:
            self.frame_id = dbc_id
            self.is_extended_frame = False

    def get_signal_by_name(self, name):
        for s in self.signals:
            if s.name == name:
                return s
        raise KeyError(name)

    def __repr__(self):
        return f"Message({self.name} 0x{self.frame_id:X} {self.file}:{self.line})"


class Database:
    def __init__(self):
        self.messages = []
        self.files = []          # every file read, in order (imports first)
        self.notes = []          # things worth telling the user (not errors)
        self._by_dbc_id = {}

    def get_message_by_name(self, name):
        found = [m for m in self.messages if m.name == name]
        if not found:
            raise KeyError(name)
        if len(found) > 1:
            raise DataError(found[1].file, found[1].line, f"BO_ {name}",
                            f"message name defined twice (also {found[0].file}:{found[0].line})")
        return found[0]

    def get_message_by_frame_id(self, frame_id):
        for m in self.messages:
            if m.frame_id == frame_id:
                return m
        raise KeyError(frame_id)

    def _add_message(self, msg):
        old = self._by_dbc_id.get(msg.dbc_id)
        if old is not None:
            self.messages.remove(old)
            self.notes.append(f"{msg.file}:{msg.line}: BO_ {msg.dbc_id}: redefines {old.name} of "
                              f"{old.file}:{old.line} (the later one is used)")
        self._by_dbc_id[msg.dbc_id] = msg
        self.messages.append(msg)


def _frac(text):
    return Fraction(text)


# The largest DBC of opendbc is 0.8 MB; a reader holds a file and its lines
# (about 20 bytes a line more), so 2 MiB keeps it well under 64 MiB.
MAX_DBC_BYTES = 2 << 20


def _read_text(path):
    with open(path, "rb") as f:
        raw = f.read(MAX_DBC_BYTES + 1)
    if len(raw) > MAX_DBC_BYTES:
        raise DataError(path, None, "dbc", f"larger than {MAX_DBC_BYTES} bytes: not a DBC file this reader takes")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("cp1252", errors="replace")


# The longest statement (a `;` statement over several lines: a comment, a
# value table); real ones are a few kB.
MAX_STATEMENT_BYTES = 1 << 16


def _statements(text, path="-"):
    """(keyword, line, text) of every top-level statement. One-line
    statements end at the line's end; the others at their `;` (outside
    strings) or, when that is missing, before the next line that starts
    with a keyword."""
    lines = text.split("\n")
    i = 0
    n = len(lines)
    while i < n:
        line = lines[i].rstrip("\r")
        stripped = line.strip()
        if not stripped or stripped.startswith("//"):
            i += 1
            continue
        m = KEYWORD_RE.match(stripped)
        kw = m.group(1) if m else ""
        if kw == "NS_":
            # the NS_ block: indented names up to the next unindented line
            i += 1
            while i < n and (not lines[i].strip() or lines[i][:1] in (" ", "\t")):
                i += 1
            continue
        if kw == "BU_":
            # node names, possibly on the indented lines that follow
            i += 1
            while i < n and lines[i][:1] in (" ", "\t") and lines[i].strip():
                km = KEYWORD_RE.match(lines[i].strip())
                if km and (km.group(1) in LINE_KEYWORDS or km.group(1) in SEMI_KEYWORDS):
                    break
                i += 1
            continue
        if kw in LINE_KEYWORDS:
            yield kw, i + 1, stripped
            i += 1
            continue
        # a `;` statement, possibly spanning lines (strings may hold newlines)
        start = i
        buf = []
        size = 0
        in_str = False
        done = False
        while i < n and not done:
            cur = lines[i].rstrip("\r")
            if i > start and not in_str:
                km = KEYWORD_RE.match(cur.strip())
                if cur[:1] not in (" ", "\t") and km and (km.group(1) in SEMI_KEYWORDS or
                                                          km.group(1) in LINE_KEYWORDS):
                    break      # a new statement: the previous one lacked its `;`
            j = 0
            while j < len(cur):
                c = cur[j]
                if in_str:
                    if c == "\\" and j + 1 < len(cur):
                        j += 2
                        continue
                    if c == '"':
                        in_str = False
                elif c == '"':
                    in_str = True
                elif c == ";":
                    buf.append(cur[:j + 1])
                    rest = cur[j + 1:].strip()
                    if rest:
                        lines[i] = rest   # another statement on the same line
                        i -= 1
                    done = True
                    break
                j += 1
            if not done:
                buf.append(cur)
                size += len(cur) + 1
                if size > MAX_STATEMENT_BYTES:
                    raise DataError(path, start + 1, kw or "-", f"statement longer than {MAX_STATEMENT_BYTES} bytes "
                                                                "(a missing ';'?)")
            i += 1
        yield kw, start + 1, "\n".join(buf).strip()


STR_RE = re.compile(r'"((?:[^"\\]|\\.)*)"', re.S)


def _semi_statement(db, kw, text, path, line, pending_vt, cycle):
    """The few `;` statements that matter: IMPORT comments, GenMsgCycleTime,
    SIG_VALTYPE_. Returns an imported file name or None."""
    if kw == "CM_":
        if not STR_RE.search(text):
            raise DataError(path, line, "CM_", "comment without its quoted text")
        m = re.match(r'CM_\s+"IMPORT\s+(.*?)"\s*;?\s*$', text, re.S)
        return m.group(1).strip() if m else None
    if kw == "BA_DEF_DEF_":
        m = re.match(r'BA_DEF_DEF_\s+"GenMsgCycleTime"\s+(' + NUM + r')\s*;', text)
        if m:
            cycle["default"] = int(Fraction(m.group(1)))
    elif kw == "BA_DEF_":
        if re.match(r'BA_DEF_\s+BO_\s+"GenMsgCycleTime"', text):
            cycle["defined"] = True
    elif kw == "BA_":
        m = re.match(r'BA_\s+"GenMsgCycleTime"\s+BO_\s+(\d+)\s+(' + NUM + r')\s*;', text)
        if m:
            cycle["values"][int(m.group(1))] = int(Fraction(m.group(2)))
    elif kw == "SIG_VALTYPE_":
        m = re.match(r'SIG_VALTYPE_\s+(\d+)\s+(' + NAME + r')\s*:?\s*(\d)\s*;', text)
        if m and m.group(3) in ("1", "2"):
            pending_vt.append((int(m.group(1)), m.group(2)))
    return None


def _parse_file(db, path, root, seen, depth=0):
    real = os.path.realpath(path)
    if real in seen:
        return
    seen.add(real)
    if depth > 8:
        raise DataError(path, None, "IMPORT", "imports nested more than 8 deep")
    text = _read_text(path)
    msg = None
    skipping = False
    pending_vt = []
    cycle = {"defined": False, "default": None, "values": {}}
    file_msgs = []
    for kw, line, stmt in _statements(text, path):
        if kw == "BO_":
            m = BO_RE.match(stmt)
            if not m:
                raise DataError(path, line, "BO_", f"malformed message line: {stmt[:80]!r} "
                                "(expected BO_ ID NAME: LENGTH SENDER)")
            dbc_id, length = int(m.group(1)), int(m.group(3))
            skipping = False
            if m.group(2) == INDEPENDENT_SIG_MSG:
                msg = None          # its signals belong to no frame
                skipping = True
                continue
            if dbc_id > 0xFFFFFFFF or (not dbc_id & 0x80000000 and dbc_id > 0x1FFFFFFF):
                db.notes.append(f"{path}:{line}: BO_ {m.group(2)}: id 0x{dbc_id:X} is not a CAN id "
                                "(more than 29 bits): message skipped")
                msg = None
                skipping = True
                continue
            if length > 64:
                raise DataError(path, line, f"BO_ {m.group(2)}", f"length {length} bytes > 64")
            msg = Message(dbc_id, m.group(2), length, m.group(4) or "", path, line, root)
            if msg.implied_extended:
                db.notes.append(f"{path}:{line}: BO_ {m.group(2)}: id 0x{dbc_id:X} is above 0x7FF without "
                                "the extended-frame bit: taken as a 29-bit id")
            file_msgs.append(msg)
            db._add_message(msg)
        elif kw == "SG_":
            m = SG_RE.match(stmt)
            if not m:
                raise DataError(path, line, "SG_", f"malformed signal line: {stmt[:80]!r} (expected "
                                "SG_ NAME : START|LENGTH@ORDER+/- (FACTOR,OFFSET) [MIN|MAX] \"UNIT\" RECEIVERS)")
            if msg is None:
                if skipping:
                    continue        # a signal of a skipped message
                raise DataError(path, line, f"SG_ {m.group(1)}", "signal before any BO_ message")
            start, length = int(m.group(3)), int(m.group(4))
            if length < 1 or length > 64:
                raise DataError(path, line, f"SG_ {m.group(1)}", f"length {length} bits (1..64)")
            sig = Signal(m.group(1), start, length, "little_endian" if m.group(5) == "1" else "big_endian",
                         m.group(6) == "-", _frac(m.group(7)), _frac(m.group(8)), _frac(m.group(9)),
                         _frac(m.group(10)), m.group(11).replace('\\"', '"'), m.group(2), path, line)
            if any(s.name == sig.name for s in msg.signals):
                raise DataError(path, line, f"SG_ {sig.name}", f"signal defined twice in {msg.name}")
            msg.signals.append(sig)
        elif kw in ("BU_", "VERSION", "BS_"):
            continue
        elif kw in SEMI_KEYWORDS:
            imp = _semi_statement(db, kw, stmt, path, line, pending_vt, cycle)
            if imp is not None:
                ipath = os.path.join(os.path.dirname(path), imp)
                if os.path.isfile(ipath):
                    _parse_file(db, ipath, root, seen, depth + 1)
                else:
                    db.notes.append(f"{path}:{line}: IMPORT {imp}: no such file beside it; skipped")
        else:
            raise DataError(path, line, kw or stmt.split()[0][:20], "not a DBC statement")
    if cycle["defined"]:
        for m in file_msgs:
            v = cycle["values"].get(m.dbc_id, 0) or cycle["default"] or 0
            m.cycle_time = v if v > 0 else None
    for dbc_id, sname in pending_vt:
        for m in file_msgs:
            if m.dbc_id == dbc_id:
                for s in m.signals:
                    if s.name == sname:
                        s.is_float = True
    db.files.append(path)


def load(paths):
    """Reads DBC files (and the files they IMPORT) into one Database."""
    db = Database()
    seen = set()
    for p in paths:
        if not os.path.isfile(p):
            raise DataError(p, None, "dbc", "no such DBC file")
        _parse_file(db, p, p, seen)
    return db
