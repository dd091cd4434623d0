"""grip-replay on untrusted input (docs/guarantees.md, "grip-replay"):

1. the bad-input corpus (tests/badinput/cases.tsv, 100+ cases: candump
   logs, CSV input, signal tables, vehicle files, options) through
   run_badinput.py on every host build present: each case ends with its
   exit code and a message naming file, line and field;
2. bounded memory: the RAV4 drive, the same drive five times over (12 MB)
   and its --reorder replay under a 64 MiB address-space limit, where
   /dev/zero and a 1 GiB sparse file end with a message (those are corpus
   cases);
3. what must keep working: --reorder gives the sorted log's rows; the -e
   output has no two columns of one name (yaw_rate_in is the measured
   input, yaw_rate the estimate) and --units names carry units; grip-replay's
   own output is valid --csv input; comment / --ignore-columns columns, a
   byte order mark and CRLF line ends are accepted.

Binaries: build/<arith>-gcc/bin/grip-replay; an absent build is skipped.
"""
import csv
import io
import os
import resource
import subprocess
import sys
import tempfile
import unittest

from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
BIN = {a: os.path.join(ROOT, "build", f"{a}-gcc", "bin") for a in ("float", "fixed")}
LOG = os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log")
TIR = os.path.join(ROOT, "tests", "data", "mfeval-tir", "PacejkaBook_Defaults.tir")
INPUTS = os.path.join(ROOT, "tests", "badinput", "inputs")
MEM = 64 << 20


def limit():
    resource.setrlimit(resource.RLIMIT_AS, (MEM, MEM))


def replay(*args, stdin=None, mem=False, arith="float"):
    p = subprocess.run([os.path.join(BIN[arith], "grip-replay"), *args], capture_output=True, text=True,
                       input=stdin, timeout=120, preexec_fn=limit if mem else None)
    return p.returncode, p.stdout, p.stderr


def header(text):
    return next(csv.reader(io.StringIO(text)))


class Corpus(unittest.TestCase):
    def check(self, arith):
        if not os.path.exists(os.path.join(BIN[arith], "grip-replay")):
            self.skipTest(f"build/{arith}-gcc not built")
        p = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "badinput", "run_badinput.py"),
                            "--bin", BIN[arith], "--only", "grip-replay"], capture_output=True, text=True,
                           timeout=300)
        lines = p.stdout.splitlines()
        bad = [l for l in lines if l.startswith("not ok")]
        n = sum(1 for l in lines if l.startswith("ok "))
        print(f"\n  bad-input corpus, {arith} build: {n} cases ok, {len(bad)} not ok; {lines[-1] if lines else ''}")
        self.assertEqual(p.returncode, 0, "\n".join(bad + [l for l in lines if l.startswith("#")][:20]) + p.stderr)
        self.assertGreaterEqual(n, 60)

    def test_float(self):
        self.check("float")

    def test_fixed(self):
        self.check("fixed")


@unittest.skipUnless(os.path.exists(os.path.join(BIN["float"], "grip-replay")), "build/float-gcc not built")
class Behaviour(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def test_memory_bounded(self):
        # the drive five times over, each copy 70 s later: 269000 frames
        big = self.path("big.log")
        with open(LOG) as f:
            lines = f.read().splitlines()
        with open(big, "w") as f:
            for k in range(5):
                for l in lines:
                    sec, rest = l[1:].split(")", 1)
                    f.write(f"({float(sec) + 70 * k:017.6f}){rest}\n")
        for args in ((LOG,), (big,), ("--reorder", big), ("-e", TIR, big)):
            rc, out, err = replay("-q", *args, mem=True)
            self.assertEqual(rc, 0, f"{args}: {err}")
            self.assertGreater(len(out), 1000)
        print(f"\n  under a 64 MiB address-space limit: the drive, 5x the drive ({os.path.getsize(big) >> 20} MB), "
              "with --reorder and with -e: exit 0")

    def test_no_unit_check_takes_range_faults(self):
        # a steering angle in degrees: refused; with --no-unit-check every
        # cell is a range fault (not valid, no value), never used as radians
        path = os.path.join(INPUTS, "steer_degrees.csv")
        rc, _, err = replay("-e", TIR, "--csv", path)
        self.assertEqual(rc, 4)
        self.assertIn("column steer_angle: 45 is outside [-20, 20] rad (degrees?)", err)
        rc, out, err = replay("-q", "-e", TIR, "--no-unit-check", "--csv", path)
        self.assertEqual(rc, 0, err)
        rows = list(csv.DictReader(io.StringIO(out)))
        self.assertGreater(len(rows), 20)
        self.assertEqual({r["steer_angle_fault"] for r in rows}, {"range"})
        self.assertEqual({r["steer_angle"] for r in rows}, {""})
        self.assertEqual({r["wheel_speed_fl_fault"] for r in rows}, {"ok"})

    def test_reorder_sorts(self):
        shuffled = os.path.join(INPUTS, "shuffled.log")
        with open(shuffled) as f:
            lines = f.read().splitlines()
        sorted_log = self.path("sorted.log")
        with open(sorted_log, "w") as f:
            f.write("".join(l + "\n" for l in sorted(lines, key=lambda l: float(l[1:l.index(")")]))))
        rc, out_sorted, err = replay(sorted_log, "--all-inputs")
        self.assertEqual(rc, 0, err)
        rc, out, err = replay("--reorder", shuffled, "--all-inputs")
        self.assertEqual(rc, 0, err)
        self.assertEqual(out, out_sorted)
        self.assertRegex(err, r"log order +\d+ frames older than one before them .*sorted \(--reorder: 1000 ms window\)")
        rc, _, err = replay(shuffled)
        self.assertEqual(rc, 4)
        self.assertIn("--reorder", err)

    def test_output_columns(self):
        rc, out, err = replay("-e", TIR, "-n", "2000", LOG)
        self.assertEqual(rc, 0, err)
        names = header(out)
        self.assertEqual(len(names), len(set(names)), names)
        self.assertIn("yaw_rate_in", names)
        self.assertIn("yaw_rate_in_fault", names)
        self.assertLess(names.index("yaw_rate_in"), names.index("est_status"))
        self.assertGreater(names.index("yaw_rate"), names.index("est_status"))
        rows = list(csv.DictReader(io.StringIO(out)))
        self.assertEqual(len(rows[0]), len(names))   # DictReader keeps every column
        # without the estimator the input keeps its name
        rc, out, _ = replay("-n", "2000", LOG)
        self.assertIn("yaw_rate", header(out))
        self.assertNotIn("yaw_rate_in", header(out))
        # --units: a unit on every dimensional column, names still unique, values unchanged
        rc, out_u, err = replay("-e", TIR, "-n", "2000", "--units", LOG)
        self.assertEqual(rc, 0, err)
        nu = header(out_u)
        self.assertEqual(len(nu), len(set(nu)))
        for n in ("t_s", "wheel_speed_fl_m_s", "steer_angle_rad", "yaw_rate_in_rad_s", "ax_m_s2", "vx_m_s",
                  "beta_rad", "yaw_rate_rad_s", "yaw_rate_ref_rad_s", "delta_rad", "mu", "fy_front_N",
                  "fy_margin_front_N", "yaw_rate_bias_rad_s", "ay_model_m_s2", "yaw_rate_in_fault"):
            self.assertIn(n, nu)
        rc, out_e, _ = replay("-e", TIR, "-n", "2000", LOG)
        self.assertEqual(out_u.split("\n", 1)[1], out_e.split("\n", 1)[1])

    def test_own_output_is_csv_input(self):
        rc, out, err = replay("-n", "6000", LOG)
        self.assertEqual(rc, 0, err)
        p = self.path("inputs.csv")
        with open(p, "w") as f:
            f.write(out)
        rc, out2, err = replay("-e", TIR, "--csv", p)
        self.assertEqual(rc, 0, err)
        n_in = len(out.splitlines()) - 1
        self.assertEqual(len(out2.splitlines()) - 1, n_in)
        rc, out3, err = replay("-e", TIR, "-n", "6000", LOG)
        self.assertEqual(rc, 0, err)
        a = list(csv.DictReader(io.StringIO(out2)))
        b = list(csv.DictReader(io.StringIO(out3)))
        self.assertEqual([r["beta"] for r in a], [r["beta"] for r in b])

    def test_accepted_forms(self):
        good = os.path.join(INPUTS, "good.csv")
        with open(good, "rb") as f:
            data = f.read()
        lines = data.decode().splitlines()
        variants = {
            "bom_crlf.csv": b"\xef\xbb\xbf" + "\r\n".join(lines).encode() + b"\r\n",
            "comment.csv": "\n".join([lines[0] + ",comment"] + [l + ",caf\u00e9 ok" for l in lines[1:]]).encode(),
            "extra.csv": "\n".join([lines[0] + ",gps_lat,step"] + [l + f",47.{k},{k}" for k, l in
                                                                    enumerate(lines[1:])]).encode(),
            "empty_signal.csv": "\n".join([lines[0] + ",vehicle_speed"] + [l + "," for l in lines[1:]]).encode(),
        }
        ref = None
        for name, body in variants.items():
            p = self.path(name)
            with open(p, "wb") as f:
                f.write(body)
            extra = ["--ignore-columns", "gps_lat"] if name == "extra.csv" else []
            rc, out, err = replay("-e", TIR, *extra, "--csv", p)
            self.assertEqual(rc, 0, f"{name}: {err}")
            beta = [r["beta"] for r in csv.DictReader(io.StringIO(out))]
            self.assertEqual(len(beta), 30)
            ref = ref or beta
            self.assertEqual(beta, ref, name)


if __name__ == "__main__":
    unittest.main()
