"""CAN logs of the simulated sensors: encode with the project's DBC
(tools/grip_tools/vehicle_dbc/grip_sim.dbc) through cantools, write and read
candump log files, decode them back.

candump log format (one frame per line, as `candump -l` writes it):
    (SSSSSSSSSS.UUUUUU) can0 1A0#0011223344556677
timestamp in seconds (t_base + sample time + the message's tx latency),
interface name, identifier in hex (3 digits for 11-bit ids), '#', data
bytes in hex.

Counter and checksum signals (names ending in _Counter / _Checksum) are
filled here: the counter rolls 0..15 per message; the checksum is
0xFF ^ ((sum of all other data bytes + (id & 0xFF) + (id >> 8)) & 0xFF).
A BrakeSwitch signal is 1 when BrakePressure > 2 bar.
"""
import os
import re

import numpy as np

from grip_tools.paths import PACKAGE

DBC_PATH = os.path.join(PACKAGE, "can", "vehicle_dbc", "grip_sim.dbc")
BRAKE_SWITCH_BAR = 2.0

_LINE = re.compile(r"^\((\d+\.\d+)\)\s+(\S+)\s+([0-9A-Fa-f]+)#([0-9A-Fa-f]*)\s*$")


def load_dbc(path=None):
    import cantools
    return cantools.database.load_file(path or DBC_PATH)


def checksum(frame_id, data, pos):
    """Checksum byte over every byte but `pos` plus the id bytes."""
    s = sum(b for i, b in enumerate(data) if i != pos) + (frame_id & 0xFF) + ((frame_id >> 8) & 0xFF)
    return 0xFF ^ (s & 0xFF)


def _checksum_byte(msg):
    for s in msg.signals:
        if s.name.endswith("_Checksum"):
            if s.length != 8 or s.start % 8 != 0 or s.byte_order != "little_endian":
                raise ValueError(f"{msg.name}: checksum must be a byte-aligned 8-bit signal")
            return s.name, s.start // 8
    return None, None


def encode_frames(sensor_data, db=None, check_periods=True):
    """[(t, frame_id, bytes)] for every sample of every group, time-ordered."""
    db = db or load_dbc()
    frames = []
    for gname, g in sensor_data.config.groups.items():
        msg = db.get_message_by_name(g.message)
        if check_periods and msg.cycle_time and abs(msg.cycle_time - g.period * 1000.0) > 1e-6:
            raise ValueError(f"{g.message}: sensor period {g.period * 1000:g} ms differs from the DBC "
                             f"cycle time {msg.cycle_time} ms")
        sigs = {s.name: s for s in msg.signals}
        for c in g.channels:
            if c.name not in sigs:
                raise ValueError(f"{g.message} has no signal {c.name}")
            if c.quant and abs(sigs[c.name].scale - c.quant) > 1e-12:
                raise ValueError(f"{c.name}: quantization {c.quant} differs from the DBC scale "
                                 f"{sigs[c.name].scale}")
        cs_name, cs_pos = _checksum_byte(msg)
        counter = [n for n in sigs if n.endswith("_Counter")]
        d = sensor_data.groups[gname]
        for k, t in enumerate(d["time"]):
            values = {c.name: float(d[c.name][k]) for c in g.channels}
            for n in counter:
                values[n] = k % 16
            if "BrakeSwitch" in sigs and "BrakeSwitch" not in values:
                values["BrakeSwitch"] = int(values.get("BrakePressure", 0.0) > BRAKE_SWITCH_BAR)
            if cs_name:
                values[cs_name] = 0
            data = bytearray(msg.encode(values, strict=True))
            if cs_name:
                data[cs_pos] = checksum(msg.frame_id, data, cs_pos)
            frames.append((float(t) + g.tx_latency, msg.frame_id, bytes(data)))
    frames.sort(key=lambda f: (f[0], f[1]))
    return frames


def write_candump(path, frames, interface="can0", t_base=0.0):
    with open(path, "w") as f:
        for t, fid, data in frames:
            ts = t_base + t
            sec = int(np.floor(ts))
            usec = int(round((ts - sec) * 1e6))
            if usec == 1000000:
                sec, usec = sec + 1, 0
            ident = f"{fid:03X}" if fid < 0x800 else f"{fid:08X}"
            f.write(f"({sec:010d}.{usec:06d}) {interface} {ident}#{data.hex().upper()}\n")


def read_candump(path):
    """[(t, interface, frame_id, bytes)] of a candump log (other lines are errors)."""
    out = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            if not line.strip():
                continue
            m = _LINE.match(line.strip())
            if not m:
                raise ValueError(f"{path}:{n}: not a candump log line: {line.strip()!r}")
            out.append((float(m.group(1)), m.group(2), int(m.group(3), 16), bytes.fromhex(m.group(4))))
    return out


def decode_log(frames_or_path, db=None, t_base=0.0):
    """Decode a candump log (path or read_candump list) with the DBC.
    Returns ({message: {'time': array, signal: array}}, stats) where stats
    counts frames, unknown ids, checksum errors and counter jumps."""
    db = db or load_dbc()
    frames = read_candump(frames_or_path) if isinstance(frames_or_path, str) else frames_or_path
    acc = {}
    stats = {"frames": 0, "unknown": 0, "checksum_errors": 0, "counter_jumps": 0}
    last_counter = {}
    for t, _iface, fid, data in frames:
        stats["frames"] += 1
        try:
            msg = db.get_message_by_frame_id(fid)
        except KeyError:
            stats["unknown"] += 1
            continue
        vals = msg.decode(data, decode_choices=False)
        cs_name, cs_pos = _checksum_byte(msg)
        if cs_name and data[cs_pos] != checksum(fid, data, cs_pos):
            stats["checksum_errors"] += 1
        for n, v in vals.items():
            if n.endswith("_Counter"):
                if n in last_counter and v != (last_counter[n] + 1) % 16:
                    stats["counter_jumps"] += 1
                last_counter[n] = v
        d = acc.setdefault(msg.name, {"time": []})
        d["time"].append(t - t_base)
        for n, v in vals.items():
            d.setdefault(n, []).append(float(v))
    return {m: {k: np.asarray(v) for k, v in d.items()} for m, d in acc.items()}, stats
