"""Write every golden-vector file and the compiled-in parameter sets the C
tests use, into one folder (build/golden by default). `make golden` runs
this before every test run, so the vectors always come from the current
reference models.

Every module grip_tools/golden/<name>.py that defines write_golden(outdir)
is a generator and is run here, in name order.
"""
import argparse
import importlib
import os
import pkgutil
import sys

from grip_tools import golden

SKIP = {"all", "io"}


def generators():
    names = sorted(m.name for m in pkgutil.iter_modules(golden.__path__)
                   if m.name not in SKIP)
    for name in names:
        module = importlib.import_module(f"grip_tools.golden.{name}")
        if hasattr(module, "write_golden"):
            yield name, module.write_golden


def write_if_changed(path, text):
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
    ap = argparse.ArgumentParser(prog="grip golden-all", description=__doc__)
    ap.add_argument("-o", "--outdir", default="build/golden")
    args = ap.parse_args(argv)
    os.makedirs(args.outdir, exist_ok=True)
    for name, write in generators():
        write(args.outdir)
    if not os.path.exists(os.path.join(args.outdir, "mf_params.c")):
        # No Magic Formula emitter yet: an empty table keeps the tests linkable.
        write_if_changed(os.path.join(args.outdir, "mf_params.c"),
                         '#include "mf_params.h"\n'
                         "const grip_test_tire grip_test_tires[1] = { { 0, 0, 0, 0 } };\n"
                         "const int grip_test_tire_count = 0;\n")
    print(f"golden-all: wrote {args.outdir}", file=sys.stderr)
    return 0
