"""Copies the real frames with valid checksums out of opendbc's
can/tests/test_checksums.py into a data file (tests/data/opendbc/
checksum_frames.txt), one frame a line:

    DBC MESSAGE ID DATA_HEX VERDICT      (VERDICT: ok, or bad: see KNOWN_BAD)

    python -m grip_tools.can.opendbc_frames OPENDBC_DIR OUT

Honda's test builds its frames with opendbc's packer from a few signal
values and lists the checksums the car uses for them; those frames are
rebuilt here from the same values (counter 0..3) and checked against the
listed checksums before they are written.
"""
import ast
import os
import sys


# Frames of that test whose checksum does not hold: opendbc's parser drops
# a frame with a bad checksum and keeps the previous values, so its test,
# which repacks those values, passes on them all the same.
KNOWN_BAD = {("EPS_3", "7bf0026e"): "FCA Giorgio EPS_3, third frame: the CRC fits byte 1 = 0xED, not 0xF0"}


def frames_from_test(path):
    """(dbc, message, id, data) of every verify_* call with literal frames."""
    with open(path) as f:
        tree = ast.parse(f.read())
    out = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call) or not isinstance(node.func, ast.Attribute):
            continue
        fn = node.func.attr
        if fn not in ("verify_fca_giorgio_crc", "verify_volkswagen_mqb_crc"):
            continue
        dbc = "fca_giorgio" if "fca" in fn else "vw_mqb"
        name = ast.literal_eval(node.args[0])
        addr = ast.literal_eval(node.args[1])
        for d in ast.literal_eval(node.args[2]):
            out.append((dbc, name, addr, bytes(d)))
    return out


def honda_frames():
    """LKAS_HUD (0x33D) and LKAS_HUD_A (0x33DA, a 29-bit id) with
    LKAS_READY, LKAS_STATE_CHANGE, STEERING_REQUIRED, SOLID_LANES = 1 and
    counters 0..3: opendbc's test lists checksums 11, 10, 9, 8 and 4, 3, 2, 1."""
    out = []
    for addr, name, sums in ((0x33D, "LKAS_HUD", (11, 10, 9, 8)), (0x33DA, "LKAS_HUD_A", (4, 3, 2, 1))):
        for counter, cs in enumerate(sums):
            data = bytes([0x41, 0x05, 0x00, 0x00, (counter << 4) | cs])
            out.append(("honda_civic_hatchback_ex_2017_can", name, addr, data))
    return out


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    src, out = argv[0], argv[1]
    rows = frames_from_test(os.path.join(src, "opendbc", "can", "tests", "test_checksums.py")) + honda_frames()
    with open(out, "w") as f:
        f.write("# Frames with valid checksums from opendbc (MIT, see LICENSE and README.txt here):\n"
                "# opendbc/can/tests/test_checksums.py; Honda's rebuilt from the signal values and\n"
                "# checksums that test lists (tools/grip_tools/can/opendbc_frames.py).\n"
                "# DBC MESSAGE ID DATA_HEX VERDICT\n")
        for (name, hexd), why in KNOWN_BAD.items():
            f.write(f"# bad: {why}\n")
        for dbc, name, addr, data in rows:
            verdict = "bad" if (name, data.hex()) in KNOWN_BAD else "ok"
            f.write(f"{dbc} {name} 0x{addr:X} {data.hex()} {verdict}\n")
    print(f"{len(rows)} frames -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
