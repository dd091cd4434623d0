"""Reference vehicle simulator: sensor models and CAN logs.

Synthetic truth signals (no vehicle simulation) so each property is tested
in isolation: delay, bias, noise, scale error, quantization, deadband,
reproducibility, and the CAN round trip through the project's DBC
(tools/grip_tools/vehicle_dbc/grip_sim.dbc) with cantools.
"""
import copy
import os
import re
import tempfile
import unittest

import numpy as np

from grip_tools.sim import canlog, sensors

RAD2DEG = 180.0 / np.pi


def synthetic_truth(t_end=4.0, dt=1e-3):
    t = np.arange(0.0, t_end + dt / 2, dt)
    c = {"time": t}
    c["swa"] = 1.2 * np.sin(2 * np.pi * 0.7 * t)                    # rad
    c["yaw_imu"] = 0.4 * np.sin(2 * np.pi * 0.9 * t + 0.3)           # rad/s
    c["ay_imu"] = 6.0 * np.sin(2 * np.pi * 0.5 * t)
    c["ax_imu"] = -3.0 + 2.0 * np.cos(2 * np.pi * 0.3 * t)
    c["p_master"] = np.clip(60.0 * (t - 0.5), 0.0, 90.0)
    for k, w in enumerate(("fl", "fr", "rl", "rr")):
        c[f"re_omega_{w}"] = 20.0 + 3.0 * np.sin(2 * np.pi * 0.6 * t + k) - 4.0 * t
    return c


def clean(cfg):
    """Everything off, including quantization."""
    cfg = copy.deepcopy(cfg)
    for g in cfg.groups.values():
        for c in g.channels:
            c.noise = c.bias = c.scale_error = c.delay = c.tau = c.deadband = c.quant = 0.0
    return cfg


class SensorModelTest(unittest.TestCase):
    def setUp(self):
        self.truth = synthetic_truth()

    def test_ideal_channel_reproduces_truth_at_the_sample_times(self):
        sd = sensors.measure(self.truth, clean(sensors.SensorConfig()))
        t, y = sd.series("YawRate")
        self.assertAlmostEqual(t[1] - t[0], 0.010)
        ref = np.interp(t, self.truth["time"], self.truth["yaw_imu"]) * RAD2DEG
        self.assertLess(np.abs(y - ref).max(), 1e-9)

    def test_delay_is_recovered_by_shift_search(self):
        cfg = clean(sensors.SensorConfig())
        cfg.channel("LatAcc").delay = 0.037
        t, y = sensors.measure(self.truth, cfg).series("LatAcc")
        shifts = np.arange(0.0, 0.080, 0.0005)
        cost = [np.abs(y - np.interp(t - s, self.truth["time"], self.truth["ay_imu"])).max() for s in shifts]
        best = shifts[int(np.argmin(cost))]
        self.assertAlmostEqual(best, 0.037, delta=0.0005)
        self.assertLess(min(cost), 1e-9)

    def test_bias_and_noise_statistics(self):
        cfg = clean(sensors.SensorConfig())
        ch = cfg.channel("YawRate")
        ch.bias, ch.noise, ch.quant = 0.5, 0.2, 0.01
        cfg.seed = 11
        t, y = sensors.measure(self.truth, cfg).series("YawRate")
        e = y - np.interp(t, self.truth["time"], self.truth["yaw_imu"]) * RAD2DEG
        n = len(e)                                   # 401 samples
        # mean within 4 standard errors of the bias, std within 15 % (4 sigma of
        # the std estimate is 14 % for n = 401); quantization adds q^2/12
        self.assertLess(abs(e.mean() - 0.5), 4 * 0.2 / np.sqrt(n))
        self.assertLess(abs(e.std() / np.hypot(0.2, 0.01 / np.sqrt(12)) - 1.0), 0.15)
        # white: lag-1 autocorrelation near 0 (|rho| < 4 / sqrt(n))
        d = e - e.mean()
        rho = (d[1:] * d[:-1]).sum() / (d * d).sum()
        self.assertLess(abs(rho), 4 / np.sqrt(n))

    def test_scale_error_lowpass_and_deadband(self):
        cfg = clean(sensors.SensorConfig())
        fl = cfg.channel("WheelSpeed_FL")
        fl.scale_error = 0.02
        fl.deadband = 1.5
        t, y = sensors.measure(self.truth, cfg).series("WheelSpeed_FL")
        ref = np.interp(t, self.truth["time"], self.truth["re_omega_fl"]) * 3.6 * 1.02
        ref = np.where(np.abs(ref) < 1.5, 0.0, ref)
        ref = np.maximum(ref, 0.0)                   # clip at the DBC minimum (unsigned)
        self.assertLess(np.abs(y - ref).max(), 1e-9)
        # low-pass: a step settles to 1 - exp(-1) after one time constant
        tr = dict(self.truth, p_master=(self.truth["time"] >= 1.0) * 100.0)
        cfg2 = clean(sensors.SensorConfig())
        cfg2.channel("BrakePressure").tau = 0.1
        t2, p = sensors.measure(tr, cfg2).series("BrakePressure")
        k = np.searchsorted(t2, 1.1 - 1e-9)
        self.assertAlmostEqual(p[k] / 100.0, 1.0 - np.exp(-1.0), delta=0.01)   # 1 ms truth grid

    def test_quantization_step_and_error(self):
        cfg = clean(sensors.SensorConfig())
        cfg.channel("SteeringAngle").quant = 0.1
        t, y = sensors.measure(self.truth, cfg).series("SteeringAngle")
        self.assertLess(np.abs(y / 0.1 - np.round(y / 0.1)).max(), 1e-6)
        ref = np.interp(t, self.truth["time"], self.truth["swa"]) * RAD2DEG
        self.assertLessEqual(np.abs(y - ref).max(), 0.05 + 1e-9)

    def test_seeded_and_channel_independent(self):
        a = sensors.measure(self.truth, sensors.SensorConfig(seed=3))
        b = sensors.measure(self.truth, sensors.SensorConfig(seed=3))
        c = sensors.measure(self.truth, sensors.SensorConfig(seed=4))
        self.assertTrue(np.array_equal(a.series("LatAcc")[1], b.series("LatAcc")[1]))
        self.assertFalse(np.array_equal(a.series("LatAcc")[1], c.series("LatAcc")[1]))
        cfg = sensors.SensorConfig(seed=3)
        cfg.channel("YawRate").noise = 1.0            # other channels keep their noise
        d = sensors.measure(self.truth, cfg)
        self.assertTrue(np.array_equal(a.series("LatAcc")[1], d.series("LatAcc")[1]))
        self.assertFalse(np.array_equal(a.series("YawRate")[1], d.series("YawRate")[1]))


class CanRoundTripTest(unittest.TestCase):
    def test_candump_round_trip_through_dbc(self):
        truth = synthetic_truth()
        sd = sensors.measure(truth, sensors.SensorConfig(seed=5))
        frames = canlog.encode_frames(sd)
        path = os.path.join(tempfile.mkdtemp(), "can.log")
        canlog.write_candump(path, frames, t_base=1700000000.0)
        with open(path) as f:
            lines = f.read().splitlines()
        line_re = re.compile(r"^\(\d{10}\.\d{6}\) can0 [0-9A-F]{3}#([0-9A-F]{2})+$")
        self.assertTrue(all(line_re.match(ln) for ln in lines))
        dec, stats = canlog.decode_log(path, t_base=1700000000.0)
        self.assertEqual(stats["checksum_errors"], 0)
        self.assertEqual(stats["counter_jumps"], 0)
        self.assertEqual(stats["unknown"], 0)
        db = canlog.load_dbc()
        for gname, g in sd.config.groups.items():
            msg = db.get_message_by_name(g.message)
            d = dec[g.message]
            st = sd.groups[gname]
            self.assertEqual(len(d["time"]), len(st["time"]))
            # frame time = sample time + tx latency (microsecond resolution of the log)
            self.assertLess(np.abs(d["time"] - (st["time"] + g.tx_latency)).max(), 1e-6 + 1e-7)
            period = np.diff(d["time"])
            self.assertLess(np.abs(period - msg.cycle_time / 1000.0).max(), 2e-6)
            for c in g.channels:
                scale = msg.get_signal_by_name(c.name).scale
                err = np.abs(d[c.name] - st[c.name]).max()
                # the sensor already quantized to the DBC scale: exact up to float rounding
                self.assertLess(err, 1e-6 * scale, f"{c.name}: {err}")
        # the brake switch follows the decoded pressure
        b = dec["ESC_Brake"]
        self.assertTrue(np.array_equal(b["BrakeSwitch"] > 0.5, b["BrakePressure"] > canlog.BRAKE_SWITCH_BAR))

    def test_corrupted_frame_is_detected(self):
        truth = synthetic_truth(t_end=0.2)
        frames = canlog.encode_frames(sensors.measure(truth))
        t, fid, data = next(f for f in frames if f[1] == 0x130)
        bad = bytearray(data)
        bad[0] ^= 0x01
        _, stats = canlog.decode_log([(t, "can0", fid, bytes(bad))])
        self.assertEqual(stats["checksum_errors"], 1)

    def test_quantization_mismatch_with_dbc_is_an_error(self):
        cfg = sensors.SensorConfig()
        cfg.channel("LatAcc").quant = 0.05
        sd = sensors.measure(synthetic_truth(t_end=0.1), cfg)
        with self.assertRaises(ValueError):
            canlog.encode_frames(sd)


if __name__ == "__main__":
    unittest.main()
