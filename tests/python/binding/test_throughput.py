"""Throughput of grip.mf.evaluate (numpy arrays in, arrays out), printed
as TAP comments; no assertion on time (the machine may be busy).

Measured: N combined-slip points (MF 6.1, PacejkaBook_Defaults.tir, random
kappa in [-0.3, 0.3] and alpha in [-0.2, 0.2] rad, gamma 0, Fz 4000 N),
best of 3 runs, in each arithmetic with one thread and with one thread per
CPU; and, for reference, the same work in C (bench_mf.c, linked to the
Makefile's libgrip.a) when the build is there: one grip_mf_eval per point,
grip_mf_eval_batch in blocks of 128 points (what the binding calls), and
that with one POSIX thread per CPU (the machine's own scaling, without
Python). The same with lanes=True (grip_mf_eval_prepared_lanes: the C
loop "lanes"). Also checked: the binding and the C loops give the same
checksum, and lanes=True the default path's statuses and forces within
2e-5 Fz.
Wall clock and CPU time per point are both printed: on a machine that runs
other work the CPU time is the figure that does not depend on it.

    .venv/bin/python tests/python/run.py test_throughput.py binding
    GRIP_BENCH_POINTS=1000000 .venv/bin/python tests/python/run.py test_throughput.py binding
"""
import os
import subprocess
import tempfile
import time

import numpy as np

import grip
from grip_tools.golden import est as golden_est
from . import common
from .common import ARITHS, ROOT

TIR = golden_est.tire_path()
N = int(os.environ.get("GRIP_BENCH_POINTS", "200000"))
REPEAT = 3


def best_of(fn):
    best, cpu = 1e30, 1e30
    for _ in range(REPEAT):
        w, c = time.perf_counter(), time.process_time()
        fn()
        best = min(best, time.perf_counter() - w)
        cpu = min(cpu, time.process_time() - c)
    return best, cpu


def c_build(arith, tmp):
    b = common.BUILD[arith]
    libs = [os.path.join(b, "libgrip_port.a"), os.path.join(b, "libgrip.a")]
    if not all(os.path.exists(x) for x in libs):
        return None
    exe = os.path.join(tmp, f"bench_{arith}")
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench_mf.c")
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Werror", "-pthread", f"-DGRIP_ARITH_FIXED={int(arith == 'fixed')}",
                    "-DGRIP_DEBUG_SATURATION=0", "-D_POSIX_C_SOURCE=200809L", "-I" + os.path.join(ROOT, "include"),
                    "-I" + os.path.join(ROOT, "port", "linux"), src] + libs + ["-lm", "-o", exe],
                   check=True, capture_output=True)
    return exe


def c_reference(exe, pts, threads=1, batch=False):
    # batch: False (one call per point), True (grip_mf_eval_batch) or "lanes"
    args = [exe, TIR, str(len(pts)), str(REPEAT), str(threads)] + \
        (["lanes"] if batch == "lanes" else (["batch"] if batch else []))
    p = subprocess.run(args, input=pts.tobytes(), capture_output=True, check=True, timeout=600)
    secs, cpu, checksum = p.stdout.split()
    return float(secs), float(cpu), float(checksum)


def line(what, wall, cpu):
    return (f"# {what:38s}: {N / wall / 1e6:6.2f} M points/s ({wall / N * 1e9:6.0f} ns/point wall, "
            f"{cpu / N * 1e9:6.0f} ns/point CPU)")


class TestThroughput(common.BindingTest):
    def test_mf_points_per_second(self):
        tyre = grip.mf.load(TIR)
        rng = np.random.default_rng(11)
        k = rng.uniform(-0.3, 0.3, N)
        a = rng.uniform(-0.2, 0.2, N)
        cpus = os.cpu_count() or 1
        print(f"# grip.mf.evaluate, {N} combined-slip points, best of {REPEAT}, {cpus} CPUs, "
              f"load average {os.getloadavg()[0]:.1f}", flush=True)
        with tempfile.TemporaryDirectory() as tmp:
            for arith in ARITHS:
                res = {}
                for lanes in (False, True):
                    for threads in (1, 0):
                        wall, cpu = best_of(lambda: res.__setitem__((lanes, threads), grip.mf.evaluate(
                            tyre, k, a, 0.0, 4000.0, arith=arith, threads=threads, lanes=lanes)))
                        label = ("1 thread" if threads == 1 else f"{cpus} threads") + (", lanes" if lanes else "")
                        print(line(f"{arith} binding, {label}", wall, cpu), flush=True)
                r = res[(False, 1)]
                self.assertTrue((r["status"] == 0).all())
                np.testing.assert_array_equal(res[(False, 0)]["fx"], r["fx"])
                np.testing.assert_array_equal(res[(True, 0)]["fx"], res[(True, 1)]["fx"])
                np.testing.assert_array_equal(res[(True, 1)]["status"], r["status"])
                for name in ("fx", "fy"):
                    self.assertLessEqual(float(np.max(np.abs(res[(True, 1)][name] - r[name]))), 2e-5 * 4000.0)
                exe = c_build(arith, tmp)
                if exe is None:
                    print(f"# {arith:5s} C loop: build/{arith}-gcc/libgrip.a not built", flush=True)
                    continue
                pts = np.column_stack([k, a]).astype(np.float64)
                mine = float(np.sum(r["fx"]) + np.sum(r["fy"]) + np.sum(r["mz"]))
                lane = res[(True, 1)]
                mine_lanes = float(np.sum(lane["fx"]) + np.sum(lane["fy"]) + np.sum(lane["mz"]))
                for threads, batch, what in ((1, False, "C, grip_mf_eval per point, 1 thread"),
                                             (1, True, "C, grip_mf_eval_batch, 1 thread"),
                                             (cpus, True, f"C, grip_mf_eval_batch, {cpus} threads"),
                                             (1, "lanes", "C, _prepared_lanes, 1 thread"),
                                             (cpus, "lanes", f"C, _prepared_lanes, {cpus} threads")):
                    secs, cpu, checksum = c_reference(exe, pts, threads, batch)
                    print(line(f"{arith} {what}", secs, cpu), flush=True)
                    want = mine_lanes if batch == "lanes" else mine
                    self.assertAlmostEqual(want, checksum, delta=1e-9 * abs(checksum) + 1e-6)
