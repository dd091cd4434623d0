"""Write every golden-vector file and the compiled-in parameter sets the C
tests use, into one folder (build/golden by default). `make golden` runs
this before every test run, so the vectors always come from the current
reference models.
"""
import argparse
import os

from . import golden_q16


def write_mf_params(outdir):
    """build/golden/mf_params.c: the grip_test_tires[] table (tests/support/mf_params.h).
    Filled by the Magic Formula emitter once it exists; empty until then."""
    path = os.path.join(outdir, "mf_params.c")
    text = ('#include "mf_params.h"\n'
            "const grip_test_tire grip_test_tires[1] = { { 0, 0, 0, 0 } };\n"
            "const int grip_test_tire_count = 0;\n")
    _write_if_changed(path, text)


def _write_if_changed(path, text):
    """Keep the file's timestamp when nothing changed, so make does not rebuild."""
    if os.path.exists(path):
        with open(path) as f:
            if f.read() == text:
                return
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip_tools golden-all", description=__doc__)
    ap.add_argument("-o", "--outdir", default="build/golden")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    golden_q16.main(["-o", os.path.join(args.outdir, "q16.txt")])
    write_mf_params(args.outdir)
    return 0
