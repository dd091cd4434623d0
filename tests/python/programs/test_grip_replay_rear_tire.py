"""grip-replay's vehicle-file key `rear_tire = PATH` (port/linux/grip_replay.c):
the rear axle's .tir from the vehicle file gives the same estimator outputs
as --estimate-rear, a path relative to the vehicle file's folder, and a bad
value is refused with the file, line and key."""
import os
import subprocess
import tempfile
import unittest

import numpy as np

from grip_tools.evaluate import est_eval
from grip_tools.golden import est as golden_est
from grip_tools.paths import REPO_ROOT

BIN = os.path.join(REPO_ROOT, "build", "float-gcc", "bin", "grip-replay")
TIR = golden_est.tire_path()


def _soft_rear(path):
    """PacejkaBook_Defaults with its cornering stiffness scale LKY halved."""
    out = []
    with open(TIR) as f:
        for line in f:
            if line.split("=")[0].strip().upper() == "LKY":
                line = "LKY = 0.5\n"
            out.append(line)
    with open(path, "w") as f:
        f.writelines(out)


@unittest.skipUnless(os.path.exists(BIN), f"{BIN} not built")
class RearTireKeyTests(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        t, value, valid, _ = golden_est.bicycle_inputs(duration=4.0)
        self.csv = os.path.join(self.d, "in.csv")
        est_eval.write_input_csv(self.csv, t, value[:, :len(est_eval.IN_COLS)], valid[:, :len(est_eval.IN_COLS)])
        os.makedirs(os.path.join(self.d, "car", "tires"))
        self.rear = os.path.join(self.d, "car", "tires", "rear.tir")
        _soft_rear(self.rear)

    def tearDown(self):
        self.tmp.cleanup()

    def _run(self, *extra):
        args = [BIN, "-q", "-e", TIR, "--vehicle", "generic", "--step-ms", "10", "--csv", self.csv] + list(extra)
        return subprocess.run(args, capture_output=True, text=True)

    def _vehicle(self, text):
        p = os.path.join(self.d, "car", "vehicle.txt")
        with open(p, "w") as f:
            f.write(text)
        return p

    def test_same_as_estimate_rear(self):
        a = self._run("--estimate-rear", self.rear)
        b = self._run("--vehicle-file", self._vehicle("mass = 1450\nrear_tire = tires/rear.tir  # relative\n"))
        c = self._run()
        self.assertEqual(a.returncode, 0, a.stderr)
        self.assertEqual(b.returncode, 0, b.stderr)
        self.assertEqual(a.stdout, b.stdout)
        # and the key does something: the same tire on both axles differs
        ra, rc = est_eval.read_replay(a.stdout), est_eval.read_replay(c.stdout)
        self.assertGreater(float(np.nanmax(np.abs(ra["fyr"] - rc["fyr"]))), 10.0)

    def test_bad_values_name_file_line_key(self):
        for text, what in (("mass = 1450\nrear_tire = \n", "empty"),
                           ("rear_tire = tires/none.tir\n", "none.tir"),
                           ("rear_tire = tires/rear.tir\nrear_tire = tires/rear.tir\n", "given twice")):
            with self.subTest(text=text):
                p = self._vehicle(text)
                r = self._run("--vehicle-file", p)
                self.assertNotEqual(r.returncode, 0)
                self.assertIn(f"{p}:", r.stderr)
                self.assertIn("rear_tire", r.stderr)
                self.assertIn(what, r.stderr)
        p = self._vehicle("rear_tire = tires/rear.tir\n")
        r = self._run("--vehicle-file", p, "--estimate-rear", self.rear)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(f"{p}:1: rear_tire", r.stderr)


if __name__ == "__main__":
    unittest.main()
