"""Golden vectors of the CAN decoder, decoded by cantools (the reference):

  can_raw.txt     raw extraction: every byte order x signedness x length
                  1..64, several start bits, 8- and 64-byte payloads
  can_scale.txt   scaling and range checks of synthetic signals (factors,
                  offsets, unit conversions, gains, QS and QL inputs)
  can_rav4.txt    every frame of the table's ids in the bundled RAV4 log,
                  one row per (frame, input), with the compiled-in table
  can_rav4_steps.txt  the samples a zero-order-hold assembler must produce
                  from the RAV4 log (10 ms step, staleness 3 periods)
  can_checksums.txt   checksum families (checksums.py, integers only): real
                  frames (opendbc's test frames, RAV4 SPEED frames), frames
                  made for the families without real ones, and every
                  single-bit error of each, with the verdict the reference
                  gives

Expected physical values are cantools' float64 decode times the unit
conversion and gain of dbc.py; range flags come from the exact decimal
range (dbc.py's docstring says why not from float64).
"""
import bisect
import os
import random

import cantools
from cantools.database.can import Message, Signal
from cantools.database.conversion import LinearConversion

from grip_tools.can import checksums, dbc, dbcfile
from grip_tools.golden.io import header
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
RAV4_DIR = os.path.join(ROOT, "tests", "data", "comma2k19-rav4")
RAV4_MAP = os.path.join(RAV4_DIR, "rav4_map.toml")
RAV4_LOG = os.path.join(RAV4_DIR, "rav4_bus0.log")

STEP_US = 10000
STALE_PERIODS = 3
SEED = 6


def reference_raw(order, signed, length, start, paylen, data):
    """cantools' raw decode of one signal (None if cantools rejects the layout)."""
    sig = Signal(name="S", start=start, length=length,
                 byte_order="little_endian" if order == "intel" else "big_endian", is_signed=bool(signed))
    try:
        msg = Message(frame_id=1, name="M", length=paylen, signals=[sig], strict=True, is_fd=paylen > 8)
    except Exception:
        return None
    return msg.decode(data, decode_choices=False, scaling=False)["S"]


def write_raw(path, rng):
    rows = []
    for order in ("intel", "motorola"):
        for signed in (0, 1):
            for length in range(1, 65):
                for paylen in (8, 64):
                    tried = 0
                    starts = set()
                    # edges and random positions; invalid Motorola layouts are skipped
                    candidates = [0, 7, 8 * paylen - length, 8 * paylen - 1] + \
                        [rng.randrange(8 * paylen) for _ in range(12)]
                    for start in candidates:
                        if start < 0 or start >= 8 * paylen or start in starts or len(starts) >= 4:
                            continue
                        tried += 1
                        payloads = [bytes(paylen), bytes([0xFF] * paylen)] + \
                            [bytes(rng.randrange(256) for _ in range(paylen)) for _ in range(3)]
                        got = []
                        for data in payloads:
                            raw = reference_raw(order, signed, length, start, paylen, data)
                            if raw is None:
                                break
                            got.append((data, raw))
                        if not got:
                            continue
                        starts.add(start)
                        for data, raw in got:
                            rows.append(f"{0 if order == 'intel' else 1} {signed} {length} {start} {paylen} "
                                        f"{data.hex()} {raw}")
    with open(path, "w") as f:
        f.write(header("golden_can.raw", reference_raw, SEED,
                       ["order(0=intel,1=motorola)", "signed", "length", "start", "paylen", "data_hex", "raw"]))
        f.write("\n".join(rows) + "\n")
    return len(rows)


SCALES = ["1", "0.01", "0.03589", "1.5", "0.244", "0.1", "0.00390625", "0.0573", "40", "0.5", "2",
          "10", "0.001", "0.78125", "0.025", "-0.5", "0.0002"]
OFFSETS = ["0", "-67.67", "-125", "-18.375", "12.5", "-30", "100", "-6.5536", "0.1"]
# (input, unit) pairs: QS speeds/angles/rates/accelerations and QL pressures/torques
CASE_UNITS = [("wheel_speed_fl", "km/h"), ("wheel_speed_rr", "m/s"), ("vehicle_speed", "mph"),
              ("steer_angle", "deg"), ("steer_angle", "rad"), ("yaw_rate", "deg/s"),
              ("ax", "m/s^2"), ("ay", "g"), ("brake_pressure_fl", "bar"), ("brake_pressure_rr", "kPa"),
              ("brake_torque_fl", "N m")]


def reference_scaled(sig_obj, msg, data, conv):
    """cantools' float64 physical value times the unit conversion and gain."""
    return msg.decode(data, decode_choices=False, scaling=True)[sig_obj.name] * conv


def write_scale(path, rng):
    rows = []
    ncase = 0
    while ncase < 400:
        order = rng.choice(["little_endian", "big_endian"])
        signed = rng.random() < 0.5
        length = rng.choice([1, 2, 4, 8, 10, 12, 15, 16, 20, 24, 31, 32]) if rng.random() < 0.7 \
            else rng.randint(1, 32)
        scale = rng.choice(SCALES)
        offset = rng.choice(OFFSETS)
        iname, unit = rng.choice(CASE_UNITS)
        gain = rng.choice([1, 1, 1, -1])
        start = rng.randrange(64)
        sig = Signal(name="S", start=start, length=length, byte_order=order, is_signed=signed,
                     conversion=LinearConversion(float(scale), float(offset), is_float=False), unit=unit)
        try:
            msg = Message(frame_id=1, name="M", length=8, signals=[sig], strict=True)
        except Exception:
            continue
        idx = dbc.INPUT_INDEX[iname]
        frac = dbc.INPUTS[idx][2]
        t = dbc.Term(name="S", input=idx, role="value", start=start, length=length,
                     order="intel" if order == "little_endian" else "motorola", signed=int(signed))
        conv = dbc.UNITS[unit][1] * gain
        t.k = dbc.exact(scale) * conv
        t.c = dbc.exact(offset) * conv
        try:
            dbc.choose_shift([t], frac, "case")
        except dbc.MapError:
            continue   # factor beyond the decoder's reach: the generator refuses it (tested in Python)
        rmin, rmax = t.raw_limits()
        if rng.random() < 0.5:
            a, b = sorted(rng.randint(rmin, rmax) for _ in range(2))
            lo, hi = sorted([t.si_exact(a) - t.k / 3, t.si_exact(b) + t.k / 3])
            t.raw_min, t.raw_max = dbc.raw_range(t, lo, hi, "case")
        else:
            lo = hi = None
            t.raw_min, t.raw_max = rmin, rmax
        ncase += 1
        payloads = [bytes(8), bytes([0xFF] * 8)] + [bytes(rng.randrange(256) for _ in range(8)) for _ in range(6)]
        for data in payloads:
            raw = msg.decode(data, decode_choices=False, scaling=False)["S"]
            want = reference_scaled(sig, msg, data, float(conv))
            exact_si = t.si_exact(raw)
            in_range = (lo is None or lo <= exact_si) and (hi is None or exact_si <= hi)
            fits = dbc.fixed_value([(t, raw)], t.shift, frac) is not None
            rows.append(f"{idx} {t.shift} {t.K} {t.C} {t.raw_min} {t.raw_max} {t.start} {length} "
                        f"{0 if t.order == 'intel' else 1} {int(signed)} 8 {data.hex()} {raw} {want!r} "
                        f"{int(in_range)} {int(fits)}")
    with open(path, "w") as f:
        f.write(header("golden_can.scale", reference_scaled, SEED,
                       ["input", "shift", "K", "C", "raw_min", "raw_max", "start", "length", "order", "signed",
                        "paylen", "data_hex", "raw", "si_cantools", "in_range", "fits_fixed"]))
        f.write("\n".join(rows) + "\n")
    return len(rows)


def read_candump(path):
    """(t_us, id, data) of every frame of a candump -l log (classic frames)."""
    frames = []
    with open(path) as f:
        for line in f:
            ts, _, fr = line.split()
            sec, usec = ts.strip("()").split(".")
            ident, payload = fr.split("#")
            frames.append((int(sec) * 1000000 + int(usec), int(ident, 16), bytes.fromhex(payload)))
    return frames


def reference_inputs(table, db, msg, data):
    """{input: (si_value, fault)} of one frame, from cantools' decode."""
    phys = db.decode_message(msg.id & 0x1FFFFFFF, data, decode_choices=False, scaling=True)
    raw = db.decode_message(msg.id & 0x1FFFFFFF, data, decode_choices=False, scaling=False)
    out = {}
    for t in msg.terms:
        v, f = out.get(t.input, (0.0, 0))
        r = raw[t.name]
        if t.role == "qualifier":
            if not t.raw_min <= r <= t.raw_max and f == 0:
                f = 5
        else:
            conv = float(dbc.UNITS[t.unit][1] * table.gains[dbc.INPUTS[t.input][0]])
            v += phys[t.name] * conv
            if not t.raw_min <= r <= t.raw_max:
                f = 4
        out[t.input] = (v, f)
    return out


def reference_db(paths):
    """The DBC files as cantools reads them: the independent reference decoder."""
    db = cantools.database.Database(strict=False)
    for p in paths:
        db.add_dbc_file(p)
    return db


def write_rav4(outdir):
    table, _, mp = dbc.table_from_map(RAV4_MAP)
    db = reference_db(mp["dbc"])
    by_id = {m.id: m for m in table.messages}
    frames = read_candump(RAV4_LOG)
    rows = []
    series = {}
    for t_us, ident, data in frames:
        m = by_id.get(ident)
        if m is None:
            continue
        csum_ok = 1
        if m.checksum == "toyota":
            csum_ok = int(dbc.toyota_checksum(ident, data, m.checksum_byte) == data[m.checksum_byte])
        for inp, (v, f) in sorted(reference_inputs(table, db, m, data).items()):
            rows.append(f"{t_us} {ident} {len(data)} {data.hex()} {inp} {v!r} {f} {csum_ok}")
            if csum_ok and len(data) == m.length:
                series.setdefault(inp, []).append((t_us, v if f == 0 else 0.0, f))
    with open(os.path.join(outdir, "can_rav4.txt"), "w") as f:
        f.write(header("golden_can.rav4", reference_inputs, SEED,
                       ["t_us", "id", "len", "data_hex", "input", "si_cantools", "fault", "checksum_ok"],
                       {"log": os.path.relpath(RAV4_LOG, ROOT), "map": os.path.relpath(RAV4_MAP, ROOT)}))
        f.write("\n".join(rows) + "\n")
    nsteps = write_steps(os.path.join(outdir, "can_rav4_steps.txt"), table, frames, series, by_id)
    return len(rows), nsteps


def reference_steps(table, frames, series, step_us, stale_periods):
    """Zero-order hold on the step grid: for each step t, each input's newest
    value with frame time <= t, stale if older than stale_periods x period."""
    ids = {m.id for m in table.messages}
    first = next(t for t, i, _ in frames if i in ids)
    last = frames[-1][0]
    t = -(-first // step_us) * step_us
    period = {}
    for m in table.messages:
        for term in m.terms:
            period[term.input] = m.period_us
    times = {i: [s[0] for s in v] for i, v in series.items()}
    steps = []
    while t <= last:
        row = []
        for i in range(len(dbc.INPUTS)):
            if i not in period:
                row.append((0.0, 1))
                continue
            k = bisect.bisect_right(times.get(i, []), t) - 1
            if k < 0:
                row.append((0.0, 2))
                continue
            ts, v, f = series[i][k]
            if t - ts > stale_periods * period[i]:
                row.append((0.0, 3))
            else:
                row.append((v if f == 0 else 0.0, f))
        steps.append((t, row))
        t += step_us
    return steps


def write_steps(path, table, frames, series, by_id):
    steps = reference_steps(table, frames, series, STEP_US, STALE_PERIODS)
    cols = ["step", "t_us"] + [f"{n}:value,fault" for n, _, _ in dbc.INPUTS]
    with open(path, "w") as f:
        f.write(header("golden_can.steps", reference_steps, SEED, cols,
                       {"step_us": STEP_US, "stale_periods": STALE_PERIODS, "reorder_us": 0}))
        for n, (t, row) in enumerate(steps):
            f.write(f"{n} {t} " + " ".join(f"{v!r} {fl}" for v, fl in row) + "\n")
    return len(steps)


OPENDBC_DIR = os.path.join(ROOT, "tests", "data", "opendbc")
OPENDBC_FRAMES = os.path.join(OPENDBC_DIR, "checksum_frames.txt")
OPENDBC_DBC = {
    "vw_mqb": "dbc/vw_mqb.dbc", "fca_giorgio": "dbc/fca_giorgio.dbc",
    "honda_civic_hatchback_ex_2017_can": "dbc/generator/honda/honda_civic_hatchback_ex_2017_can.dbc",
}


def real_checksum_frames():
    """(family, table Message, data, expect_ok, source) of the real frames:
    opendbc's test frames with the check their DBC selects, and the RAV4
    log's SPEED frames (Toyota)."""
    dbs = {}
    out = []
    with open(OPENDBC_FRAMES) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            name, mname, _, hexd, verdict = line.split()
            path = os.path.join(OPENDBC_DIR, OPENDBC_DBC[name])
            if name not in dbs:
                dbs[name] = dbcfile.load([path])
            msg = dbs[name].get_message_by_name(mname)
            m = dbc._message_of(msg, {"period_ms": 10}, dbc.MapText(path), f"messages.{mname}")
            out.append((m.checksum, m, bytes.fromhex(hexd), verdict == "ok", f"opendbc:{name}"))
    table, _, _ = dbc.table_from_map(RAV4_MAP)
    speed = next(m for m in table.messages if m.name == "SPEED")
    n = 0
    for _, ident, data in read_candump(RAV4_LOG):
        if ident == speed.id and n < 200:
            out.append(("toyota", speed, data, True, "rav4"))
            n += 1
    return out


def made_message(family, frame_id, length, start, nbits, order, ext=False, magic=None):
    m = dbc.Message(name="M", id=frame_id | (0x80000000 if ext else 0), length=length, period_us=10000)
    m.checksum, m.checksum_start, m.checksum_length, m.checksum_order = family, start, nbits, order
    m.magic = magic or checksums.default_magic(family, frame_id) or [0] * 16
    return m


def made_checksum_frames(rng):
    """Frames with the checksum the reference computes, for the families
    without real frames (and more lengths and ids for those with)."""
    specs = [("hkg_can_fd", 0x1A0, n, 0, 16, "intel") for n in (8, 12, 16, 20, 24, 32, 48, 64)] + \
        [("hkg_can_fd", 0xEA, 24, 0, 16, "intel"),
         ("hyundai", 0x260, 8, 56, 4, "intel"), ("hyundai", 0x421, 8, 60, 4, "intel"),
         ("hyundai", 0x2B0, 5, 36, 4, "intel"), ("hyundai", 0x220, 8, 59, 4, "motorola"),
         ("hyundai_whl_spd", 0x386, 8, 46, 2, "intel"),
         ("subaru", 0x13C, 8, 0, 8, "intel"), ("subaru", 0x119, 8, 0, 8, "intel"),
         ("chrysler", 0x1F4, 8, 56, 8, "intel"), ("chrysler", 0x2A6, 4, 24, 8, "intel"),
         ("nissan", 0x169, 8, 56, 8, "intel"), ("nissan", 0x2B1, 6, 40, 8, "intel"),
         ("ford", 0x415, 8, 24, 8, "intel"), ("ford", 0x91, 8, 32, 8, "intel"),
         ("xor", 0x1A0, 8, 0, 8, "intel"), ("xor", 0x3D0, 6, 40, 8, "intel"),
         ("honda", 0x1A6, 8, 59, 4, "motorola"), ("honda", 0x18DAB0F1, 8, 59, 4, "motorola"),
         ("honda", 0x33D, 5, 32, 4, "intel"),
         ("toyota", 0x260, 8, 56, 8, "intel"), ("toyota", 0x2E4, 5, 32, 8, "intel"),
         ("volkswagen_mqb", 0x9F, 8, 0, 8, "intel"), ("volkswagen_mqb", 0x3C0, 4, 0, 8, "intel"),
         ("fca_giorgio", 0xFE, 8, 56, 8, "intel"), ("fca_giorgio", 0x122, 4, 24, 8, "intel")]
    out = []
    for fam, fid, n, start, nbits, order in specs:
        m = made_message(fam, fid, n, start, nbits, order, ext=fid > 0x7FF)
        for _ in range(6):
            data = bytearray(rng.randrange(256) for _ in range(n))
            f = m.field()
            v = checksums.compute(fam, m.frame_id, m.extended, data, f, m.magic)
            if fam == "hyundai_whl_spd":
                data[5] = (data[5] & 0x3F) | ((v & 3) << 6)
                data[7] = (data[7] & 0x3F) | ((v >> 2) << 6)
            else:
                bits = checksums.field_bits(f.start, f.length, f.order)
                # write v into the field: bits in DBC order, most significant first for Motorola
                seq = bits if f.order == "intel" else list(reversed(bits))
                for i, b in enumerate(seq):
                    data[b // 8] = (data[b // 8] & ~(1 << (b % 8))) | (((v >> i) & 1) << (b % 8))
            assert dbc.check_frame(m, bytes(data)) == "ok", (fam, hex(fid))
            out.append((fam, m, bytes(data), True, "made"))
    return out


def reference_checksum(msg, data):
    """The reference's verdict: 1 if the frame's checksum field holds what the family computes."""
    return int(dbc.check_frame(msg, data) == "ok")


def write_checksums(path, rng):
    rows = []
    frames = real_checksum_frames() + made_checksum_frames(rng)
    for fam, m, data, expect_ok, source in frames:
        ok = reference_checksum(m, data)
        if ok != int(expect_ok):
            raise AssertionError(f"{source} {m.name} {data.hex()}: reference says {ok}")
        magic = bytes(m.magic).hex()
        order = 0 if m.checksum_order == "intel" else 1
        want = checksums.compute(fam, m.frame_id, m.extended, data, m.field(), m.magic)
        kind = 0 if source != "made" else 1
        rows.append(f"{checksums.FAMILY_INDEX[fam]} {m.id} {len(data)} {data.hex()} {m.checksum_start} "
                    f"{m.checksum_length} {order} {magic} {want} {ok} {kind}")
        if not expect_ok:
            continue
        for bit in range(8 * len(data)):
            d = bytearray(data)
            d[bit // 8] ^= 1 << (bit % 8)
            d = bytes(d)
            want = checksums.compute(fam, m.frame_id, m.extended, d, m.field(), m.magic)
            rows.append(f"{checksums.FAMILY_INDEX[fam]} {m.id} {len(d)} {d.hex()} {m.checksum_start} "
                        f"{m.checksum_length} {order} {magic} {want} {reference_checksum(m, d)} 2")
    with open(path, "w") as f:
        f.write(header("golden_can.checksums", reference_checksum, SEED,
                       ["family", "id_key", "len", "data_hex", "cs_start", "cs_length", "cs_order(0=intel)",
                        "magic_hex", "computed", "ok", "kind(0=real,1=made,2=one bit flipped)"],
                       {"families": " ".join(checksums.FAMILIES)}))
        f.write("\n".join(rows) + "\n")
    return len(rows)


def write_golden(outdir):
    rng = random.Random(SEED)
    write_raw(os.path.join(outdir, "can_raw.txt"), rng)
    write_scale(os.path.join(outdir, "can_scale.txt"), rng)
    write_rav4(outdir)
    write_checksums(os.path.join(outdir, "can_checksums.txt"), random.Random(SEED + 1))


if __name__ == "__main__":
    import sys
    import time
    out = sys.argv[1] if len(sys.argv) > 1 else "build/golden"
    os.makedirs(out, exist_ok=True)
    t0 = time.time()
    rng = random.Random(SEED)
    print("raw rows", write_raw(os.path.join(out, "can_raw.txt"), rng))
    print("scale rows", write_scale(os.path.join(out, "can_scale.txt"), rng))
    print("rav4 rows, steps", write_rav4(out))
    print("checksum rows", write_checksums(os.path.join(out, "can_checksums.txt"), random.Random(SEED + 1)))
    print(f"{time.time() - t0:.1f} s")
