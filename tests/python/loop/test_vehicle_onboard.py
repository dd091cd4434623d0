"""The vehicle-level effects of the analysis tool run onboard: for the bank,
aero and yaw-rate-bias data sets of datasets.vehicle_sets (as in
test_residual_vehicle.py) the tool analyses the data without being told the
effect, writes its update (report.updated_params -> "onboard_config"), and
the updated configuration is run through the estimator's float64 reference
(est_ref, the same steps as lib/est; test_est_golden.c checks C against it
with aero and bank on) and the calibration stage's reference (calib_ref, =
lib/calib bit for bit in the fixed build, test_calib.c).

Inputs of the estimator: the simulator run behind each data set measured by
the same ESC sensor models and seeds (all 17 estimator inputs, 100 Hz).
Checked against the simulator's truth after 1 s (docs/measured-data-loop.md):
  aero:     Fz error RMS (4 wheels) and vy error RMS at least halved
  yaw_bias: yaw-rate error RMS at least halved; and the tool's own held-out
            residual of r with the calibration applied to the data at least
            halved (as the tool's sensor_bias fit)
  bank:     the friction estimate's largest deviation from the true 1.0 and
            the largest vy error smaller (the estimator's ay update already
            absorbs most of a bank: its gain is small, see the doc)
Runtime: one batched simulator run (~10-25 s CPU), three analyses, six
estimator runs (~2 s each).
"""
import time
import unittest

import numpy as np

from grip_tools.reference import calib as calib_ref, est as est_ref
from grip_tools.loop import datasets
from grip_tools.golden import est as golden_est
from grip_tools.loop import attribution, report, vehicle
from grip_tools.sim import sensors

SEED = 3


def est_inputs(sim, seed, yaw_bias_deg=0.0):
    sd = sensors.measure(sim, datasets._sensor_config(seed, yaw_bias_deg))
    cols = sd.wide_columns()
    return est_ref.inputs_from_sensors(cols)


def run_est(P, sim, t, v, ok, **cfg_kw):
    """Errors of the estimator against the simulator's truth after 1 s."""
    outs = est_ref.run(est_ref.config(P, **cfg_kw), v, ok)
    ts = sim["time"]
    m = t > 1.0
    vy = np.interp(t, ts, sim["vy"])
    r = np.interp(t, ts, sim["r"])
    fz = np.stack([np.interp(t, ts, sim[f"fz_{w}"]) for w in ("fl", "fr", "rl", "rr")], 1)
    e_vy = np.array([o["vy"] for o in outs]) - vy
    return {"vy_rms": float(np.sqrt(np.mean(e_vy[m] ** 2))), "vy_max": float(np.max(np.abs(e_vy[m]))),
            "r_rms": float(np.sqrt(np.mean((np.array([o["yaw_rate"] for o in outs]) - r)[m] ** 2))),
            "fz_rms": float(np.sqrt(np.mean((np.array([o["fz"] for o in outs]) - fz)[m] ** 2))),
            "mu_dev": float(np.max(np.abs(np.array([o["mu"] for o in outs])[m] - 1.0)))}


def calibrate(cal, t, v, ok):
    cv, cok = calib_ref.run(cal, np.round(t * 1e6).astype(np.int64), v, ok)
    v2, ok2 = v.copy(), ok.copy()
    v2[:, :calib_ref.N] = cv
    ok2[:, :calib_ref.N] = cok
    return v2, ok2


class VehicleEffectsOnboard(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        t0 = time.process_time()
        cls.sets = datasets.vehicle_sets(seed=SEED, kinds=("none", "bank", "aero", "yaw_bias"))
        cls.model = vehicle.VehicleModel(datasets.vehicle_base())
        cls.P = golden_est.tire_params()     # the passenger car's tyre (PacejkaBook_Defaults)
        cls.upd = {}
        for k in ("bank", "aero", "yaw_bias"):
            ds = cls.sets[k][0]
            res = attribution.analyse(cls.model, ds)
            cls.upd[k] = (res, report.updated_params(res, cls.model, ds))
        print(f"\n  simulation + analyses {time.process_time() - t0:.1f} s CPU")

    def _onboard(self, kind, effect):
        res, upd = self.upd[kind]
        self.assertEqual(upd["effect"], effect, attribution.verdict(res))
        oc = upd["onboard_config"]
        self.assertTrue(oc["representable"], oc)
        print(f"\n  {kind}: update.json onboard_config {oc}")
        return oc

    def _report(self, kind, before, after):
        print(f"  {kind}: estimator vs truth, before -> after: "
              + ", ".join(f"{q} {before[q]:.4g} -> {after[q]:.4g}" for q in before))

    def test_aero(self):
        oc = self._onboard("aero", "aero_load")
        ec = oc["grip_est_config"]
        self.assertAlmostEqual(ec["cla"], 2.5, delta=0.75)
        sim = self.sets["aero"][1]["sim"]
        t, v, ok = est_inputs(sim, SEED)
        b = run_est(self.P, sim, t, v, ok)
        a = run_est(self.P, sim, t, v, ok, cla=ec["cla"], aero_front=ec["aero_front"],
                    air_density=ec["air_density"])
        self._report("aero", b, a)
        self.assertLessEqual(a["fz_rms"], 0.5 * b["fz_rms"])
        self.assertLessEqual(a["vy_rms"], 0.5 * b["vy_rms"])

    def test_bank(self):
        oc = self._onboard("bank", "road_bank")
        ec = oc["grip_est_config"]
        self.assertAlmostEqual(ec["tan_bank"], 0.04, delta=0.01)
        sim = self.sets["bank"][1]["sim"]
        t, v, ok = est_inputs(sim, SEED)
        b = run_est(self.P, sim, t, v, ok)
        a = run_est(self.P, sim, t, v, ok, tan_bank=ec["tan_bank"], tan_grade=ec["tan_grade"])
        self._report("bank", b, a)
        self.assertLess(a["mu_dev"], b["mu_dev"])
        self.assertLess(a["vy_max"], b["vy_max"])

    def test_yaw_bias(self):
        oc = self._onboard("yaw_bias", "sensor_bias")
        cal = oc["grip_calib_config"]
        self.assertAlmostEqual(cal["offset"][5], np.radians(0.4), delta=0.0015)
        # the tool's own residual with the calibration applied to the recorded r
        ds = self.sets["yaw_bias"][0]
        _, test = attribution.block_masks(len(ds), 8)
        base = self.model.predict(ds.ch)
        r_cal = (ds.ch["r"] - cal["offset"][5]) * cal["gain"][5]
        ho_b = attribution.rms((ds.ch["r"] - base["r"])[test])
        ho_a = attribution.rms((r_cal - base["r"])[test])
        print(f"  yaw_bias: tool model held-out r residual {ho_b:.4g} -> {ho_a:.4g} rad/s with calib")
        self.assertLessEqual(ho_a, 0.5 * ho_b)
        # the estimator on the calibrated sensor inputs
        sim = self.sets["none"][1]["sim"]
        t, v, ok = est_inputs(sim, SEED + 1000, yaw_bias_deg=0.4)   # the data set's own realisation
        b = run_est(self.P, sim, t, v, ok)
        v2, ok2 = calibrate(cal, t, v, ok)
        a = run_est(self.P, sim, t, v2, ok2)
        self._report("yaw_bias", b, a)
        self.assertLessEqual(a["r_rms"], 0.5 * b["r_rms"])


class OnboardMapping(unittest.TestCase):
    """report.onboard_config without data: ranges and directions."""

    def test_sensor_mapping(self):
        m = vehicle.VehicleModel.__new__(vehicle.VehicleModel)
        m.kind = "vehicle"
        oc = report.onboard_config("sensor_scale", {"sensor_scale_r": 0.04, "sensor_scale_ay": -0.05}, m)
        self.assertAlmostEqual(oc["grip_calib_config"]["gain"][5], 1 / 1.04)
        self.assertAlmostEqual(oc["grip_calib_config"]["gain"][7], 1 / 0.95)
        self.assertTrue(oc["representable"])
        # the RAV4 finding (s = -0.906) is not a sensor gain the stage accepts
        oc = report.onboard_config("sensor_scale", {"sensor_scale_r": -0.906, "sensor_scale_ay": -0.964}, m)
        self.assertFalse(oc["representable"])
        # outputs lagging the model by 30 ms at 100 Hz: the model's inputs are delayed 3 steps
        oc = report.onboard_config("sensor_delay", {"delay_s": 0.03}, m, dt=0.01)
        self.assertEqual(oc["grip_calib_config"]["delay"], [3, 3, 3, 3, 3, 0, 3, 0, 3])
        oc = report.onboard_config("sensor_delay", {"delay_s": -0.02}, m, dt=0.01)
        self.assertEqual(oc["grip_calib_config"]["delay"], [0, 0, 0, 0, 0, 2, 0, 2, 0])
        oc = report.onboard_config("sensor_delay", {"delay_s": 0.5}, m, dt=0.01)
        self.assertFalse(oc["representable"])


if __name__ == "__main__":
    unittest.main()
