"""Write every golden-vector file and the compiled-in parameter sets the C
tests use, into one folder (build/golden by default). `make golden` runs
this before every test run, so the vectors always come from the current
reference models.

Every module grip_tools/golden/<name>.py that defines write_golden(outdir)
is a generator and is run here. A generator whose files are independent
also names them (golden_jobs() and write_job(outdir, name)); the jobs run
in parallel processes (-j, default: the machine's CPUs, at most 4), each
writing its own files, so the output does not depend on the order.
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


def _run_job(job):
    """Worker: one generator, or one job of a generator that has them."""
    outdir, name, part = job
    module = importlib.import_module(f"grip_tools.golden.{name}")
    if part is None:
        module.write_golden(outdir)
    else:
        module.write_job(outdir, part)
    return name, part


def jobs(outdir):
    """(outdir, generator, job or None), the generators' own jobs first
    (they are listed slowest first)."""
    split, whole = [], []
    for name, _ in generators():
        module = importlib.import_module(f"grip_tools.golden.{name}")
        if hasattr(module, "golden_jobs"):
            split += [(outdir, name, part) for part in module.golden_jobs()]
        else:
            whole.append((outdir, name, None))
    return split + whole


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip golden-all", description=__doc__)
    ap.add_argument("-o", "--outdir", default="build/golden")
    ap.add_argument("-j", "--jobs", type=int, default=min(os.cpu_count() or 1, 4),
                    help="processes (default: the CPUs, at most 4; 1: in this process, in order)")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        ap.error(f"--jobs: {args.jobs} is not a count of processes (1 or more)")
    os.makedirs(args.outdir, exist_ok=True)
    todo = jobs(args.outdir)
    if args.jobs == 1:
        for job in todo:
            _run_job(job)
    else:
        import concurrent.futures
        import multiprocessing
        with concurrent.futures.ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("fork")) as pool:
            # list(): a worker's exception is raised here, and the run fails
            list(pool.map(_run_job, todo))
    if not os.path.exists(os.path.join(args.outdir, "mf_params.c")):
        # No Magic Formula emitter yet: an empty table keeps the tests linkable.
        write_if_changed(os.path.join(args.outdir, "mf_params.c"),
                         '#include "mf_params.h"\n'
                         "const grip_test_tire grip_test_tires[1] = { { 0, 0, 0, 0 } };\n"
                         "const int grip_test_tire_count = 0;\n")
    print(f"golden-all: wrote {args.outdir}", file=sys.stderr)
    return 0
