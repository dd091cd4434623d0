"""Throughput of the host programs on their input readers (`make bench-io`):
grip-tire rows/s (CSV on stdin, the MF 6.1 example tyre) and grip-replay
frames/s (the RAV4 candump log, inputs only and with the estimator -e).
Each figure is the best of --repeat runs (wall clock of the whole
program, output to /dev/null), so it includes reading and checking every
byte. --baseline DIR runs the programs of another build folder (e.g. a
copy of build/float-gcc/bin from before a change) on the same inputs and
prints the ratio. Only a report: no test asserts a time
(docs/performance.md, "Host programs").

    python3 tests/bench/bench_io.py [--bin DIR] [--baseline DIR] [--repeat N] [--rows N] [--copies N]
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TIR = os.path.join(ROOT, "tests", "data", "mfeval-tir", "MagicFormula61_Paramerters.tir")
LOG = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log")


def make_rows(path, n):
    r = random.Random(1)
    with open(path, "w") as f:
        f.write("kappa,alpha,gamma,fz,p,vx\n")
        for _ in range(n):
            f.write(f"{r.uniform(-0.2, 0.2):.5f},{r.uniform(-0.2, 0.2):.5f},{r.uniform(-0.05, 0.05):.5f},"
                    f"{r.uniform(1000, 8000):.1f},0,{r.uniform(5, 30):.2f}\n")


def make_log(path, copies):
    """The RAV4 drive `copies` times over, each copy 70 s later; its frame count."""
    with open(LOG) as f:
        lines = f.read().splitlines()
    with open(path, "w") as f:
        for k in range(copies):
            for line in lines:
                sec, rest = line[1:].split(")", 1)
                f.write(f"({float(sec) + 70 * k:017.6f}){rest}\n")
    return copies * len(lines)


def best_time(argv, stdin_path, repeat):
    best = None
    for _ in range(repeat):
        with open(stdin_path, "rb") if stdin_path else open(os.devnull, "rb") as fin:
            t0 = time.perf_counter()
            p = subprocess.run(argv, stdin=fin, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            dt = time.perf_counter() - t0
        if p.returncode != 0:
            raise SystemExit(f"{' '.join(argv)}: exit {p.returncode}: {p.stderr.decode()[-300:]}")
        best = dt if best is None else min(best, dt)
    return best


def measure(bindir, rows_csv, nrows, log, nframes, repeat):
    tire = os.path.join(bindir, "grip-tire")
    replay = os.path.join(bindir, "grip-replay")
    out = {}
    out["grip-tire rows/s"] = nrows / best_time([tire, "--tir", TIR], rows_csv, repeat)
    out["grip-replay frames/s (inputs)"] = nframes / best_time([replay, "-q", log], None, repeat)
    out["grip-replay frames/s (-e)"] = nframes / best_time([replay, "-q", "-e", TIR, log], None, repeat)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "float-gcc", "bin"))
    ap.add_argument("--baseline", help="another folder of grip-tire and grip-replay to compare with")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--rows", type=int, default=200000)
    ap.add_argument("--copies", type=int, default=4, help="copies of the RAV4 drive in the log")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="grip-bench-io-") as d:
        rows = os.path.join(d, "rows.csv")
        make_rows(rows, a.rows)
        log = os.path.join(d, "drive.log")
        nframes = make_log(log, a.copies)
        runs = [("this build", a.bin)] + ([("baseline", a.baseline)] if a.baseline else [])
        # interleave the builds, so that a change of machine load hits both
        res = {name: {} for name, _ in runs}
        for _ in range(2):
            for name, b in runs:
                for k, v in measure(b, rows, a.rows, log, nframes, a.repeat).items():
                    res[name][k] = max(res[name].get(k, 0.0), v)
    print(f"# {a.rows} CSV rows, {nframes} CAN frames; best of {2 * a.repeat} runs")
    keys = list(res["this build"])
    head = f"{'':34s} {'this build':>14s}" + (f" {'baseline':>14s} {'ratio':>7s}" if a.baseline else "")
    print(head)
    for k in keys:
        line = f"{k:34s} {res['this build'][k]:14,.0f}"
        if a.baseline:
            line += f" {res['baseline'][k]:14,.0f} {res['this build'][k] / res['baseline'][k]:7.3f}"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
