"""The measured-data loop on real logs: AV-21 axle forces (tests/data/iac-av21,
GPL-3.0 subset) and, when a grip-replay binary is built, the RAV4 CAN log."""
import os
import unittest

import numpy as np

from grip_tools.logs import av21 as av21_log
from grip_tools.reference import tir
from grip_tools.loop import attribution, av21, candidates, vehicle
from grip_tools.paths import REPO_ROOT

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = REPO_ROOT
SUBSET = av21_log.SUBSET
REPLAY = os.environ.get("GRIP_REPLAY", os.path.join(ROOT, "build", "float-gcc", "bin", "grip-replay"))


class AV21(unittest.TestCase):
    """The AV-21 subset read as loop/av21.py reads it (vy in the log's own
    sign, moved from the INS to the CG)."""
    @classmethod
    def setUpClass(cls):
        raw, _ = av21.read(SUBSET)
        cls.data = av21.axle_data(raw)

    def test_slip_angles_plausible_with_iso_sign(self):
        """A slick at <= 0.5 g runs a few degrees of slip, not the +-10 deg
        the turned-over vy gave; and more slip gives force the other way
        (ISO: alpha > 0 -> Fy < 0) on both axles."""
        for name, ds in self.data.items():
            a, fy = ds.ch["alpha"], ds.ch["fy"]
            r = np.corrcoef(a, fy)[0, 1]
            a99 = float(np.degrees(np.percentile(np.abs(a), 99)))
            print(f"\n  AV-21 {name}: corr(alpha_iso, Fy) = {r:+.2f}, |alpha| 99th percentile {a99:.2f} deg")
            self.assertLess(r, 0.0)
            self.assertLess(a99, 3.0)

    def test_calibrated_model_and_loop(self):
        """The loop's best candidate on this data is the kinematics of the
        slip angle (where vy is measured), not a tyre effect, and it lowers
        the held-out error."""
        ds = self.data["front"]
        model, x = av21.calibrate(ds, tir.load_params(av21.TIR))
        res = attribution.analyse(model, ds)
        _, test = attribution.block_masks(len(ds))
        sig = attribution.rms(ds.ch["fy"][test])
        print(f"\n  AV-21 front (subset): Fy RMS {sig:.0f} N, model held-out RMS {res.base_ho_rms['fy']:.0f} N; "
              f"{attribution.verdict(res)}")
        self.assertLess(res.base_ho_rms["fy"], sig)
        self.assertTrue(len(res.ranked) >= 8)
        self.assertIsNotNone(res.chosen)
        self.assertEqual(res.chosen.name, "measuring_point")
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
