"""grip axle-stiffness (tools/grip_tools/fit/axle_stiffness.py): per-axle
cornering stiffness from an understeer gradient or a steady-state ramp."""
import math
import os
import tempfile
import unittest

import numpy as np

from grip_tools.errors import DataError
from grip_tools.fit import axle_stiffness as ax
from grip_tools.golden import est as golden_est
from grip_tools.reference import tir

CAR = dict(mass=1450.0, lf=1.1, lr=1.6)


class AxleStiffnessTests(unittest.TestCase):
    def test_written_rear_tire_gives_the_gradient(self):
        # the gradient recomputed from the written file (read back by the
        # .tir reader, evaluated by the reference) is the one asked for
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "rear.tir")
            for k_us in (0.0005, 0.002, 0.004):
                self.assertEqual(ax.main(["--tir", golden_est.tire_path(), "--mass", "1450", "--lf", "1.1",
                                          "--lr", "1.6", "--understeer-gradient", repr(k_us), "-o", out]), 0)
                front, rear = golden_est.tire_params(), tir.load_params(out)
                _, cf, cr, k = ax.rear_scale(front, CAR["mass"], CAR["lf"], CAR["lr"], 0.0, params_rear=rear)
                print(f"# K asked {k_us:.4g}, from the written file {k:.6g} rad/(m/s^2)")
                self.assertAlmostEqual(k, k_us, delta=1e-6)

    def test_gradient_from_ramp(self):
        # a linear single-track ramp at 20 m/s with K = 0.0025 and noise:
        # the fit recovers K within its standard error's few sigma
        rng = np.random.default_rng(3)
        l, v, k_true, ratio = 2.7, 20.0, 0.0025, 15.5
        ay = np.linspace(0.2, 6.0, 600)
        yaw = ay / v
        delta = l * yaw / v + k_true * ay + np.where(ay > 4.0, 0.01 * (ay - 4.0) ** 2, 0.0)   # nonlinear above 4
        steer = ratio * delta + rng.normal(0, 0.002, ay.size)
        k, se, n = ax.gradient_from_ramp(steer, yaw + rng.normal(0, 0.001, ay.size), ay, np.full(ay.size, v),
                                         1.1, 1.6, ratio)
        print(f"# ramp: K {k:.6g} +- {se:.2g} (true {k_true}) over {n} rows")
        self.assertLess(abs(k - k_true), 4 * se + 1e-5)
        self.assertLess(n, ay.size)            # the nonlinear part left out

    def test_refusals(self):
        with self.assertRaises(DataError) as cm:            # no tire can be that oversteering
            ax.rear_scale(golden_est.tire_params(), 1450.0, 1.1, 1.6, 0.05)
        self.assertEqual(cm.exception.field, "understeer_gradient")
        with self.assertRaises(DataError):                  # a ramp without linear range
            ax.gradient_from_ramp(np.zeros(10), np.zeros(10), np.zeros(10), np.full(10, 20.0), 1.1, 1.6, 15.5)
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, "ramp.csv")
            with open(p, "w") as f:
                f.write("steer_angle,yaw_rate,ay,vx\n0.1,0.05,1.0,20\n0.1,nan,1.0,20\n")
            with self.assertRaises(DataError) as cm:
                ax.read_ramp(p)
            self.assertEqual((cm.exception.line, cm.exception.field), (3, "yaw_rate"))


if __name__ == "__main__":
    unittest.main()
