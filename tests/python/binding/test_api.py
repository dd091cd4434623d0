"""The Python side of the binding: shapes and broadcasting, the raw
number formats, threads, statuses and exceptions, the sample conversion."""
import numpy as np

import grip
import grip_tools
from grip_tools.golden import est as golden_est
from . import common
from .common import ARITHS

TIR = golden_est.tire_path()


class TestArrays(common.BindingTest):
    def setUp(self):
        self.tyre = grip.mf.load(TIR)

    def test_broadcasting_and_shapes(self):
        k = np.linspace(-0.2, 0.2, 3)[:, None]
        a = np.linspace(-0.1, 0.1, 4)[None, :]
        for arith in ARITHS:
            r = grip.mf.evaluate(self.tyre, k, a, 0.0, 4000.0, arith=arith)
            self.assertEqual(r["fx"].shape, (3, 4))
            kk, aa = np.broadcast_arrays(k, a)
            flat = grip.mf.evaluate(self.tyre, kk.ravel(), aa.ravel(), np.zeros(12), np.full(12, 4000.0),
                                    np.zeros(12), np.full(12, self.tyre.values["longvl"]), arith=arith)
            for c in ("fx", "fy", "mz", "status"):
                np.testing.assert_array_equal(r[c].ravel(), flat[c])
            s = grip.mf.evaluate(self.tyre, 0.05, 0.02, 0.0, 4000.0, arith=arith)
            self.assertEqual(s["fx"].shape, ())
            e = grip.mf.evaluate(self.tyre, np.array([]), 0.0, 0.0, 4000.0, arith=arith)
            self.assertEqual(e["fx"].shape, (0,))

    def test_raw_formats(self):
        k = np.linspace(-0.3, 0.3, 101)
        f = grip.mf.evaluate(self.tyre, k, 0.05, 0.0, 4000.0, arith="float", raw=True)
        self.assertEqual(f["fx"].dtype, np.float32)
        q = grip.mf.evaluate(self.tyre, k, 0.05, 0.0, 4000.0, arith="fixed", raw=True)
        self.assertEqual(q["fx"].dtype, np.int32)
        si = grip.mf.evaluate(self.tyre, k, 0.05, 0.0, 4000.0, arith="fixed")
        np.testing.assert_array_equal(si["fx"], q["fx"] / 256.0)   # exact
        # the two arithmetics agree to the library's documented accuracy
        self.assertLess(np.max(np.abs(si["fx"] - f["fx"])), 2e-3 * 4000.0)

    def test_threads_do_not_change_results(self):
        rng = np.random.default_rng(3)
        k, a = rng.uniform(-0.5, 0.5, 20000), rng.uniform(-0.5, 0.5, 20000)
        for arith in ARITHS:
            one = grip.mf.evaluate(self.tyre, k, a, 0.01, 3000.0, arith=arith, raw=True, threads=1)
            two = grip.mf.evaluate(self.tyre, k, a, 0.01, 3000.0, arith=arith, raw=True, threads=3)
            for c in one:
                np.testing.assert_array_equal(one[c], two[c])

    def test_point_errors(self):
        for arith in ARITHS:
            r = grip.mf.evaluate(self.tyre, [0.1, np.nan, 0.1, 0.1], 0.0, 0.0, [4000.0, 4000.0, np.inf, -10.0],
                                 arith=arith)
            self.assertEqual(r["status"].tolist()[:3], [grip.OK, grip.ERR_INPUT, grip.ERR_INPUT])
            self.assertEqual(r["status"][3], grip.OK)          # Fz <= 0: zero forces, GRIP_OK
            self.assertEqual([r["fx"][1], r["fy"][2], r["fx"][3]], [0.0, 0.0, 0.0])
            with self.assertRaises(grip.GripError) as cm:
                grip.mf.evaluate(self.tyre, [0.1, np.nan], 0.0, 0.0, 4000.0, arith=arith, errors="raise")
            self.assertEqual(cm.exception.status, grip.ERR_INPUT)
            self.assertEqual(cm.exception.status_name, "GRIP_ERR_INPUT")
            self.assertIn("kappa=nan", str(cm.exception))
        r = grip.mf.evaluate(self.tyre, 1e6, 0.0, 0.0, 4000.0, arith="fixed")    # beyond Q15.16
        self.assertEqual(r["status"], grip.ERR_INPUT)
        r = grip.mf.evaluate(self.tyre, 1e6, 0.0, 0.0, 4000.0, arith="float")    # clamped by the library
        self.assertEqual(r["status"], grip.WARN_CLAMPED)


class TestErrors(common.BindingTest):
    def test_status_text_is_the_librarys(self):
        self.assertEqual(grip.status_str(grip.ERR_PARAM), "invalid or unsupported parameter set")
        self.assertEqual(grip.status_name(-4), "GRIP_ERR_STATE")
        self.assertEqual(grip.version(), grip_tools.__version__)

    def test_parameter_errors_name_the_key(self):
        tyre = grip.mf.load(TIR)
        with self.assertRaises(grip.GripError) as cm:
            tyre.replace(fnomin=-1.0).struct("float")
        self.assertEqual(cm.exception.status, grip.ERR_PARAM)
        self.assertIn("grip_mf_check_params", str(cm.exception))
        with self.assertRaises(grip.GripError) as cm:
            tyre.replace(pcx1=40000.0).struct("fixed")
        self.assertEqual(cm.exception.param, "PCX1")
        with self.assertRaises(grip.GripError) as cm:
            tyre.replace(nosuch=1.0)
        self.assertEqual(cm.exception.param, "nosuch")
        for arith in ARITHS:
            with self.assertRaises(grip.GripError) as cm:
                grip.est.Estimator({"tire": tyre, "lf": 12.0, "mass": 1500.0}, arith=arith)
            self.assertEqual(cm.exception.status, grip.ERR_PARAM)
            self.assertEqual(cm.exception.param, "lf = 12.0")
            with self.assertRaises(grip.GripError) as cm:
                grip.est.Estimator({"tire": tyre, "masss": 1500.0}, arith=arith)
            self.assertEqual(cm.exception.param, "masss")
            with self.assertRaises(grip.GripError) as cm:
                grip.monitor.Monitor({"rate_hz": 5}, arith=arith)
            self.assertEqual(cm.exception.param, "rate_hz = 5")
            with self.assertRaises(grip.GripError) as cm:
                grip.calib.Calib({"gain": {"ay": 3.0}}, arith=arith)
            self.assertIn("gain[ay]", cm.exception.param)
            with self.assertRaises(grip.GripError) as cm:
                grip.calib.Calib({"delay": {"brake_torque_rr": 1}}, arith=arith)
            self.assertEqual(cm.exception.param, "delay")
        with self.assertRaises(grip.GripError) as cm:
            grip.est.Estimator({"tire": tyre, "mass": 1e7}, arith="fixed")
        self.assertIn("Q23.8", str(cm.exception))
        with self.assertRaises(grip.GripError):
            grip.est.Estimator({"mass": 1500.0})
        with self.assertRaises(ValueError):
            grip.mf.evaluate(tyre, 0.0, 0.0, 0.0, 4000.0, arith="double")

    def test_configs_read_back(self):
        tyre = grip.mf.load(TIR)
        for arith in ARITHS:
            est = grip.est.Estimator({"tire": tyre, "mass": 1640.0, "rate_hz": 200, "steer_lag": 0.05}, arith=arith)
            c = est.config
            self.assertEqual((c["mass"], c["rate_hz"]), (1640.0, 200))
            self.assertAlmostEqual(c["steer_lag"], 0.05, places=4)
            self.assertEqual(grip.est.config_default(tyre, arith)["mass"], 1450.0)
            self.assertGreater(est.stability_factor(), 0.0)
            mon = grip.monitor.Monitor(est=est, driven=2)
            self.assertEqual(mon.config["driven"], 2)
            self.assertAlmostEqual(mon.config["stab_factor_x100"], est.stability_factor(), places=9)


class TestSamples(common.BindingTest):
    def test_conversion(self):
        s = grip.signals.Samples.from_columns(t_s=[0.0, 0.01, 0.02], yaw_rate=[0.1, np.nan, 1e6],
                                              ax=[np.inf, 0.5, -0.25])
        self.assertEqual(s.t_us.tolist(), [0, 10000, 20000])
        i_r, i_ax = grip.signals.index("yaw_rate"), grip.signals.index("ax")
        self.assertEqual(s.valid[:, i_r].tolist(), [True, False, True])
        self.assertEqual(s.fault[1, i_r], grip.signals.MISSING)
        self.assertEqual(s.fault[0, grip.signals.index("ay")], grip.signals.UNMAPPED)
        q = s.to_struct("fixed")
        # beyond Q15.16 and infinite: not valid, fault "range", value 0
        self.assertEqual(q["valid"][2, i_r], 0)
        self.assertEqual(q["fault"][2, i_r], grip.signals.RANGE)
        self.assertEqual(q["valid"][0, i_ax], 0)
        self.assertEqual(q["value"][0, i_r], round(0.1 * 65536))
        self.assertEqual(q["value"][2, i_ax], -16384)
        f = s.to_struct("float")
        # the float build passes a valid infinity on (the library judges it)
        self.assertEqual(f["valid"][0, i_ax], 1)
        self.assertTrue(np.isinf(f["value"][0, i_ax]))
        back = grip.signals.Samples.from_struct("fixed", q)
        self.assertEqual(back.column("ax")[1], 0.5)
        self.assertTrue(np.isnan(back.column("ax")[0]))
        with self.assertRaises(KeyError):
            grip.signals.Samples.from_columns(yawrate=[0.0])
        self.assertEqual(grip.signals.INPUTS, grip._core.backend("fixed").input_names)
