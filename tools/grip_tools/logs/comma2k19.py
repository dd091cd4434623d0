"""comma2k19 raw CAN arrays (numpy .npy) -> a candump log.

    grip comma2k19 [--data DIR] [--bus 0] [--iface vcan0] [-o OUT.log]

A comma2k19 segment stores every CAN frame in processed_log/CAN/raw_can/ as
four parallel numpy arrays (files without extension): t (boot time, s,
float64), src (bus: 0, 1, 2 received, 128+ sent by the logger), address
(id, int64) and data (payload, dtype |S8). The output is the log format of
`candump -l`, one frame a line:

    (0000046408.584930) vcan0 024#01FE01D541F980BB

Payload lengths: numpy's |S8 strips trailing zero bytes, so the arrays
cannot tell an 8-byte payload ending in 00 from a shorter one. The length is
restored as the DBC's length for ids the DBC files define, and as the
longest payload seen in the segment for the other ids (an estimate; it only
matters for ids no table decodes). An id whose stored payloads are longer
than its DBC length (the DBC's message does not fit this car; 0x365 on the
RAV4) gets the longest stored length, with a warning.

Timestamps: the logger's boot-time seconds, rounded to microseconds.
"""
import argparse
import glob
import os
import re
import sys

import numpy as np

from grip_tools.errors import DataError, UsageError
from grip_tools.paths import SHARED_DATA

DEFAULT_DATA = os.path.join(SHARED_DATA, "comma2k19-rav4")


def load_raw_can(data_dir):
    base = os.path.join(data_dir, "processed_log", "CAN", "raw_can")
    try:
        arrays = {k: np.load(os.path.join(base, k)) for k in ("t", "src", "address", "data")}
    except OSError as e:
        raise UsageError(f"cannot read {base}/{{t,src,address,data}}: {e}") from None
    n = len(arrays["t"])
    if any(len(a) != n for a in arrays.values()):
        raise DataError(base, None, "t, src, address, data",
                        f"the arrays differ in length ({', '.join(str(len(a)) for a in arrays.values())})")
    return arrays


def dbc_lengths(dbc_paths):
    """{frame id: payload length} of every message in the DBC files."""
    import cantools
    db = cantools.database.Database(strict=False)
    for p in dbc_paths:
        db.add_dbc_file(p)
    return {m.frame_id: m.length for m in db.messages}


def payload_lengths(address, data, known):
    """Length of each id's payload: the DBC's, else the longest stored one."""
    longest = {}
    for a, d in zip(address.tolist(), data.tolist()):
        if len(d) > longest.get(a, -1):
            longest[a] = len(d)
    lengths = {}
    for a, n in longest.items():
        if a in known:
            if n > known[a]:
                # the DBC's message of this id does not match this car: trust the data
                print(f"comma2k19: warning: id 0x{a:X} has {n}-byte payloads, the DBC says {known[a]}: "
                      f"using {n}", file=sys.stderr)
                lengths[a] = n
            else:
                lengths[a] = known[a]
        else:
            lengths[a] = n
    return lengths


def candump_lines(arrays, bus, iface, lengths):
    t, src, address, data = arrays["t"], arrays["src"], arrays["address"], arrays["data"]
    sel = np.nonzero(src == bus)[0]
    order = sel[np.argsort(t[sel], kind="stable")]
    for i in order.tolist():
        us = int(round(float(t[i]) * 1e6))
        a = int(address[i])
        payload = bytes(data[i]).ljust(lengths[a], b"\0")
        ident = f"{a:08X}" if a > 0x7FF else f"{a:03X}"
        yield f"({us // 1000000:010d}.{us % 1000000:06d}) {iface} {ident}#{payload.hex().upper()}\n"


def convert(data_dir, out, bus=0, iface="vcan0", dbc_paths=None):
    arrays = load_raw_can(data_dir)
    if dbc_paths is None:
        dbc_paths = sorted(glob.glob(os.path.join(data_dir, "dbc", "*.dbc")))
    known = dbc_lengths(dbc_paths) if dbc_paths else {}
    lengths = payload_lengths(arrays["address"], arrays["data"], known)
    n = 0
    with open(out, "w") as f:
        for line in candump_lines(arrays, bus, iface, lengths):
            f.write(line)
            n += 1
    return n


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip comma2k19", description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=DEFAULT_DATA, help="segment folder holding processed_log/ and dbc/")
    ap.add_argument("--bus", type=int, default=0, help="bus (src) to convert (default 0)")
    ap.add_argument("--iface", default="vcan0", help="interface name written in the log")
    ap.add_argument("--dbc", action="append", help="DBC file(s) for payload lengths (default: DATA/dbc/*.dbc)")
    ap.add_argument("-o", "--output", default="-", help="output log (default stdout)")
    args = ap.parse_args(argv)
    if not 0 <= args.bus <= 255:
        ap.error(f"--bus {args.bus}: a bus number in [0, 255]")
    if not re.fullmatch(r"[A-Za-z0-9_.-]{1,15}", args.iface):
        ap.error(f"--iface {args.iface!r}: an interface name of 1 - 15 letters, digits, '_', '.', '-' "
                 "(the candump format separates fields by spaces)")
    out = "/dev/stdout" if args.output == "-" else args.output
    n = convert(args.data, out, args.bus, args.iface, args.dbc)
    if n == 0:
        if args.output != "-":
            os.remove(args.output)          # no log rather than an empty one
        raise DataError(os.path.join(args.data, "processed_log", "CAN", "raw_can", "src"), None, "src",
                        f"no frame on bus {args.bus}")
    print(f"comma2k19: wrote {n} frames of bus {args.bus} to {args.output}", file=sys.stderr)
    return 0
