"""The worked example of docs/can-families.md: a short candump log of a
Hyundai/Kia classic CAN bus, made from opendbc's hyundai_can.dbc with
grip's packer and checksum reference (no real Hyundai log is bundled).

    python -m grip_tools.can.example DBC OUT.log

One second of WHL_SPD11 (20 ms, wheel speeds, counter and checksum),
SAS11 (10 ms, steering angle) and ESP12 (20 ms, yaw rate, lateral
acceleration): a car at 50 km/h turning into a left curve. The WHL_SPD11
frame at 0.5 s carries a one-bit error, which the checksum must catch.
"""
import sys

from grip_tools.can import checksums, dbc, dbcfile

T0_US = 1_000_000_000


def _put(msg, values, data):
    for name, phys in values.items():
        s = msg.get_signal_by_name(name)
        raw = round((dbc.exact(phys) - s.offset) / s.scale)
        dbc.pack_raw(data, s.start, s.length, "intel" if s.byte_order == "little_endian" else "motorola", raw)
    return data


def frames(dbc_path, seconds=1.0):
    db = dbcfile.load([dbc_path])
    whl = db.get_message_by_name("WHL_SPD11")
    sas = db.get_message_by_name("SAS11")
    esp = db.get_message_by_name("ESP12")
    out = []
    n10 = int(seconds * 100)
    for k in range(n10):
        t = k * 10000
        x = k / n10                       # 0 .. 1 over the log
        steer = round(30 * x, 1)          # deg, left-positive
        if k % 2 == 0:
            c = (k // 2) % 16
            v = 50 + 2 * x                # km/h
            d = _put(whl, {"WHL_SPD_FL": v - 0.5 * x, "WHL_SPD_FR": v + 0.5 * x, "WHL_SPD_RL": v - 0.4 * x,
                           "WHL_SPD_RR": v + 0.4 * x, "WHL_SPD_AliveCounter_LSB": c & 3,
                           "WHL_SPD_AliveCounter_MSB": c >> 2}, bytearray(8))
            cs = checksums.compute("hyundai_whl_spd", whl.frame_id, False, d, None)
            d[5] = (d[5] & 0x3F) | ((cs & 3) << 6)
            d[7] = (d[7] & 0x3F) | ((cs >> 2) << 6)
            if k == n10 // 2:
                d[2] ^= 0x04              # a one-bit error on the bus
            out.append((t, whl.frame_id, bytes(d)))
            d = _put(esp, {"YAW_RATE": round(8 * x, 2), "LAT_ACCEL": round(1.5 * x, 2), "LONG_ACCEL": 0.1,
                           "ESP12_AliveCounter": c}, bytearray(8))
            out.append((t + 2000, esp.frame_id, bytes(d)))
        d = _put(sas, {"SAS_Angle": steer, "MsgCount": k % 16}, bytearray(5))
        out.append((t + 5000, sas.frame_id, bytes(d)))
    return out


def write_log(dbc_path, out_path, seconds=1.0):
    rows = frames(dbc_path, seconds)
    with open(out_path, "w") as f:
        for t, ident, data in rows:
            us = T0_US + t
            f.write(f"({us // 1000000:010d}.{us % 1000000:06d}) vcan0 {ident:03X}#{data.hex().upper()}\n")
    return len(rows)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    n = write_log(argv[0], argv[1])
    print(f"{n} frames -> {argv[1]}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
