"""The measured-data loop on real logs: AV-21 axle forces (tests/data/iac-av21,
GPL-3.0 subset) and, when a grip-replay binary is built, the RAV4 CAN log."""
import os
import unittest

import numpy as np

from grip_tools import tir
from grip_tools.residual import attribution, av21, candidates, vehicle

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SUBSET = os.path.join(ROOT, "tests", "data", "iac-av21", "putnam_run4_2_subset.csv")
REPLAY = os.environ.get("GRIP_REPLAY", os.path.join(ROOT, "build", "float-gcc", "bin", "grip-replay"))


class AV21(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        raw, _ = av21.read(SUBSET)
        cls.data = av21.axle_data(raw)

    def test_slip_force_sign_with_vy_right(self):
        for name, ds in self.data.items():
            r = np.corrcoef(ds.ch["alpha"], ds.ch["fy"])[0, 1]
            print(f"\n  AV-21 {name}: corr(alpha_iso, Fy) = {r:+.2f}")
            self.assertLess(r, -0.5)

    def test_calibrated_model_and_loop(self):
        ds = self.data["front"]
        model, x = av21.calibrate(ds, tir.load_params(av21.TIR))
        res = attribution.analyse(model, ds)
        _, test = attribution.block_masks(len(ds))
        sig = attribution.rms(ds.ch["fy"][test])
        print(f"\n  AV-21 front (subset): Fy RMS {sig:.0f} N, model held-out RMS {res.base_ho_rms['fy']:.0f} N; "
              f"{attribution.verdict(res)}")
        self.assertLess(res.base_ho_rms["fy"], 0.6 * sig)     # the calibrated MF explains most of Fy
        self.assertTrue(len(res.ranked) >= 8)
        if res.chosen is not None:
            self.assertLess(res.chosen.ho_rms["fy"], res.base_ho_rms["fy"])


@unittest.skipUnless(os.path.exists(REPLAY), "grip-replay not built (set GRIP_REPLAY)")
class RAV4(unittest.TestCase):
    def test_vehicle_level(self):
        ds, model = vehicle.load(os.path.join(ROOT, "tests", "data", "comma2k19-rav4", "rav4_bus0.log"), REPLAY)
        res = attribution.analyse(model, ds)
        print(f"\n  RAV4: {attribution.verdict(res)}")
        self.assertTrue(all(c.name.startswith("sensor_") for c in res.ranked))
        self.assertEqual(candidates.dependence(ds.ch["r"] - res.base_pred["r"], {"delta": ds.ch["delta"]})[0][0], "delta")


if __name__ == "__main__":
    unittest.main()
