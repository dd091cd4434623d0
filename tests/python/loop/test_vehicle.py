"""Vehicle-level undeclared-effect data sets (datasets.vehicle_sets: the
reference simulator tools/grip_tools/sim with one effect on, measured by
its ESC sensor models with noise) against the analyze tool's vehicle model
(residual.vehicle.VehicleModel), which declares none of them. The tool is
NOT told which effect is present: it must name it, halve the held-out error
(score <= 0.5 and the most affected output's held-out RMS at least halved),
and name nothing on the clean set.

Runtime: two batched simulator runs (6 s of driving, RK4 at 5 ms) and six
analyses; about 25 s of CPU on one core (docs/measured-data-loop.md).
"""
import time
import unittest

import numpy as np

from grip_tools.loop import datasets
from grip_tools.loop import attribution, vehicle

EXPECT = {"relaxation": "relaxation", "bank": "road_bank", "aero": "aero_load", "thermal": "thermal",
          "yaw_bias": "sensor_bias"}


class VehicleUndeclaredEffects(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        t0 = time.process_time()
        cls.sets = datasets.vehicle_sets(seed=3)
        t1 = time.process_time()
        cls.model = vehicle.VehicleModel(datasets.vehicle_base())
        cls.results = {k: attribution.analyse(cls.model, ds) for k, (ds, _) in cls.sets.items()}
        print(f"\n  vehicle sets: simulation {t1 - t0:.1f} s CPU, analyses {time.process_time() - t1:.1f} s CPU")

    def _check(self, kind):
        ds, truth = self.sets[kind]
        res = self.results[kind]
        c = res.chosen
        self.assertIsNotNone(c, f"{kind}: {attribution.verdict(res)}")
        print(f"\n  vehicle {kind}: named {c.name} {c.params}, score {c.score:.3f}, "
              + ", ".join(f"{o} held-out RMS {res.base_ho_rms[o]:.4g} -> {c.ho_rms[o]:.4g}" for o in ds.outputs))
        self.assertEqual(c.name, EXPECT[kind], attribution.verdict(res))
        self.assertLessEqual(c.score, 0.5)
        o = max(ds.outputs, key=lambda q: res.base_ho_rms[q] / attribution.rms(ds.ch[q]))
        self.assertLessEqual(c.ho_rms[o], 0.5 * res.base_ho_rms[o])
        return c, truth

    def test_relaxation(self):
        c, truth = self._check("relaxation")
        # truth: sim's sigma = Ky / C_lat, 0.38..0.49 m over the wheels
        self.assertAlmostEqual(c.params["sigma_m"], truth["sigma_alpha_m"], delta=0.1)

    def test_bank(self):
        c, truth = self._check("bank")
        self.assertAlmostEqual(c.params["tan_bank"], truth["tan_bank"], delta=0.01)

    def test_aero(self):
        c, truth = self._check("aero")
        self.assertAlmostEqual(c.params["cla_add_m2"], truth["cla"], delta=0.75)

    def test_thermal(self):
        c, _ = self._check("thermal")
        self.assertLess(c.params["b_k_per_K"], 0.0)          # hot tyre: lower cornering stiffness

    def test_yaw_rate_bias(self):
        c, truth = self._check("yaw_bias")
        self.assertAlmostEqual(c.params["sensor_bias_r"], truth["bias_rad_s"], delta=0.0015)

    def test_clean_names_nothing(self):
        res = self.results["none"]
        print(f"\n  vehicle none: best {res.ranked[0].name} score {res.ranked[0].score:.4f}; "
              f"{attribution.verdict(res)}")
        self.assertIsNone(res.chosen)

    def test_model_matches_clean_truth(self):
        """The model under test reproduces the simulator without effects:
        the clean set's residual is the sensor noise (0.1 deg/s, 0.03 m/s^2)."""
        ds, _ = self.sets["none"]
        pr = self.model.predict(ds.ch)
        r_rms = attribution.rms(ds.ch["r"] - pr["r"])
        ay_rms = attribution.rms(ds.ch["ay"] - pr["ay"])
        print(f"\n  vehicle none: residual RMS r {r_rms:.5f} rad/s, ay {ay_rms:.4f} m/s^2")
        self.assertLess(r_rms, 1.3 * np.radians(0.1))
        self.assertLess(ay_rms, 1.3 * 0.03)


if __name__ == "__main__":
    unittest.main()
