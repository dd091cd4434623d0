"""grip.est, grip.monitor and grip.calib against the C programs, both
builds.

1. `grip-replay -e TIR --csv FILE` (port/linux/grip_replay.c) on the golden
   input sequence of the estimator (grip_tools.golden.est.bicycle_inputs,
   with cells blanked as tests/python/programs/test_grip_replay_csv.py
   does): status, valid and flags equal, every other column equal as
   grip-replay prints it (%.6g: it prints no more digits, so this part is
   not a bit-for-bit check).
2. Bit for bit: driver.c (beside this file), built against the Makefile's
   build/<arith>-gcc/libgrip.a, runs calibration -> monitor -> estimator ->
   gate on exactly the samples the binding passes (their grip_real_t
   values) and prints every field of every output as its bits; grip.est.run
   must give the same bits, on the golden sequence and on the golden fault
   sequence (NaN, infinity, saturation, lost signals, standstill,
   reversing), with and without calibration and monitor.
3. The stand-alone objects (Estimator.step, Calib.apply) give what the
   chain gives.
"""
import csv
import io
import os
import subprocess
import tempfile
import unittest

import numpy as np

import grip
from grip_tools.golden import est as golden_est
from grip_tools.reference import est as est_ref
from grip_tools.reference import tir
from . import common
from .common import ARITHS, ROOT

TIR = golden_est.tire_path()
COLS = ["wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle", "yaw_rate", "ax", "ay"]
DRIVER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "driver.c")
CALIB = {"offset": {"yaw_rate": 0.002, "ax": -0.05, "steer_angle": 0.01},
         "gain": {"ay": 0.97, "wheel_speed_fl": 1.01}, "delay": {"steer_angle": 2, "ax": 1}}


def golden_inputs():
    t, value, valid, _ = golden_est.bicycle_inputs(duration=5.0)
    value, valid = value.copy(), valid.copy()
    for k in range(150, 158):
        valid[k, est_ref.AY], value[k, est_ref.AY] = 0, 0.0
    for k in range(300, 303):
        valid[k, est_ref.YAW], value[k, est_ref.YAW] = 0, 0.0
    return t, value, valid


def fault_inputs():
    t, v, ok, _ = golden_est.bicycle_inputs(dt=0.01, duration=8.0, seed=golden_est.SEED + 1)
    fv, fok = golden_est.inject_faults(t, v, ok)
    return t, fv, fok


def samples(t, value, valid):
    return grip.signals.Samples(value, valid != 0, t_us=np.floor(t * 1e6 + 0.5).astype(np.int64))


class TestAgainstGripReplay(common.BindingTest):
    def test_csv(self):
        t, value, valid = golden_inputs()
        tyre = grip.mf.load(TIR)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "in.csv")
            with open(path, "w") as f:
                f.write(",".join(["t_s"] + COLS) + "\n")
                for k in range(len(t)):
                    f.write(",".join([repr(float(t[k]))] + [repr(float(value[k, i])) if valid[k, i] else ""
                                                            for i in range(8)]) + "\n")
            cols = {c: np.where(valid[:, i] != 0, value[:, i], np.nan) for i, c in enumerate(COLS)}
            s = grip.signals.Samples.from_columns(cols, t_s=t)
            for arith in ARITHS:
                with self.subTest(arith=arith):
                    exe = common.need_program(self, arith, "grip-replay")
                    rc, out, err = common.run([exe, "-e", TIR, "--vehicle", "generic", "--csv", path, "-q"])
                    self.assertEqual(rc, 0, err)
                    rows = list(csv.DictReader(io.StringIO(out)))
                    self.assertEqual(len(rows), len(t))
                    o = grip.est.Estimator({"tire": tyre, "rate_hz": 100}, arith=arith).step(s)
                    exact = {"est_status": o["status"], "est_valid": o["valid"], "est_flags": o["flags"]}
                    for c, v in exact.items():
                        np.testing.assert_array_equal([int(r[c]) for r in rows], v, c)
                    printed = {c: o[c] for c in ("vx", "beta", "yaw_rate", "yaw_rate_ref", "delta", "mu", "mu_conf",
                                                  "fy_margin_front", "yaw_rate_bias")}
                    printed.update(fy_front=o["fy_axle"][:, 0], fy_rear=o["fy_axle"][:, 1],
                                   util_front=o["util_axle"][:, 0], util_rear=o["util_axle"][:, 1])
                    for c, v in printed.items():
                        mine = ["%.6g" % x for x in v]
                        theirs = [r[c] for r in rows]
                        bad = [k for k in range(len(t)) if mine[k] != theirs[k]]
                        self.assertEqual(bad, [], f"{c}: first rows {bad[:3]}: "
                                         f"{[(mine[k], theirs[k]) for k in bad[:3]]}")
                    self.assertGreater(int(np.count_nonzero(o["valid"] & 0x2)), 0)   # beta valid somewhere


def build_driver(arith, outdir):
    b = common.BUILD[arith]
    libs = [os.path.join(b, "libgrip_port.a"), os.path.join(b, "libgrip.a")]
    if not all(os.path.exists(x) for x in libs):
        return None
    exe = os.path.join(outdir, f"driver_{arith}")
    cmd = ["cc", "-std=c99", "-O2", "-Wall", "-Werror", f"-DGRIP_ARITH_FIXED={int(arith == 'fixed')}",
           "-DGRIP_DEBUG_SATURATION=0", "-D_POSIX_C_SOURCE=200809L", "-I" + os.path.join(ROOT, "include"),
           "-I" + os.path.join(ROOT, "port", "linux"), DRIVER] + libs + ["-lm", "-o", exe]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return exe


def as_int(arith, a):
    """grip_real_t array -> its bits as integers (as driver.c prints them)."""
    a = np.ascontiguousarray(a)
    return a.view(np.uint32).astype(np.int64) if arith == "float" else a.astype(np.int64)


def binding_rows(arith, r, use_cal, use_mon):
    """The binding's outputs laid out as driver.c prints them."""
    s = r["samples"].raw
    rep = r["report"].raw if use_mon else None
    o = r["out"].raw
    g = r["gated"].raw
    n = len(o)
    parts = [r["status_calib"] if use_cal else np.zeros(n, np.int64),
             r["status_monitor"] if use_mon else np.zeros(n, np.int64),
             r["out"]["status"],
             as_int(arith, s["value"]), s["valid"], s["fault"], s["age_us"]]
    if use_mon:
        parts += [rep["code"], as_int(arith, rep["resid"]), rep["faulty"], rep["dropped"], rep["detected"],
                  rep["degraded"]]
    else:
        parts += [np.zeros((n, 9)), np.zeros((n, 9)), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)]
    for f in ("vx", "vy", "beta", "yaw_rate", "yaw_rate_ref", "yaw_error", "delta", "kappa", "alpha", "fz", "fx",
              "fy", "mz", "util", "fy_axle", "util_axle", "mu", "mu_conf", "yaw_rate_bias", "fy_margin_front"):
        parts.append(as_int(arith, o[f]))
    parts += [o["steer_char"], o["valid"], o["flags"], g["valid"], g["flags"]]
    cols = [np.asarray(p, np.int64).reshape(n, -1) for p in parts]
    return np.hstack(cols)


class TestBitForBit(common.BindingTest):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.tmp = tempfile.TemporaryDirectory()
        cls.drivers = {a: build_driver(a, cls.tmp.name) for a in ARITHS}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def run_both(self, arith, t, value, valid, use_cal, use_mon):
        exe = self.drivers[arith]
        if exe is None:
            self.skipTest(f"build/{arith}-gcc/libgrip.a not built (make{' ARITH=fixed' if arith == 'fixed' else ''})")
        tyre = grip.mf.load(TIR)
        est = grip.est.Estimator({"tire": tyre, "rate_hz": 100}, arith=arith)
        mon = grip.monitor.Monitor(est=est, driven=1) if use_mon else None
        cal = grip.calib.Calib(CALIB, arith=arith) if use_cal else None
        s = samples(t, value, valid)
        r = grip.est.run(s, est, mon, cal)
        mine = binding_rows(arith, r, use_cal, use_mon)
        # the driver gets exactly the samples and calibration the binding
        # gave the library
        raw = s.to_struct(arith)
        ccfg = grip.calib.Calib(CALIB, arith=arith)._cfg
        head = [int(x) for x in as_int(arith, np.array([ccfg.offset[i] for i in range(9)], grip._core.backend(arith).real))]
        head += [int(x) for x in as_int(arith, np.array([ccfg.gain[i] for i in range(9)], grip._core.backend(arith).real))]
        head += [int(ccfg.delay[i]) for i in range(9)]
        lines = [" ".join(map(str, head))]
        vals = as_int(arith, raw["value"])
        for k in range(len(raw)):
            lines.append(" ".join(map(str, [int(raw["t_us"][k]), int(raw["step"][k])] + vals[k].tolist()
                                      + raw["valid"][k].tolist() + raw["fault"][k].tolist()
                                      + raw["age_us"][k].tolist())))
        rc, out, err = common.run([exe, TIR, "100", str(int(use_cal)), str(int(use_mon)), "1",
                                   str(int(grip._core.backend(arith).lib.GRIP_MON_GATE_DEFAULT))],
                                  "\n".join(lines) + "\n")
        self.assertEqual(rc, 0, err)
        theirs = np.array([[int(x) for x in ln.split()] for ln in out.splitlines()], np.int64)
        self.assertEqual(theirs.shape, mine.shape)
        diff = np.argwhere(theirs != mine)
        self.assertEqual(len(diff), 0, f"first differences (row, column): {diff[:5].tolist()}")
        return r

    def test_golden_sequence(self):
        t, value, valid = golden_inputs()
        for arith in ARITHS:
            for use_cal, use_mon in ((False, False), (True, True), (False, True)):
                with self.subTest(arith=arith, calib=use_cal, monitor=use_mon):
                    r = self.run_both(arith, t, value, valid, use_cal, use_mon)
                    self.assertTrue((r["out"]["status"] == 0).all())

    def test_fault_sequence(self):
        t, value, valid = fault_inputs()
        for arith in ARITHS:
            for use_cal, use_mon in ((False, False), (True, True)):
                with self.subTest(arith=arith, calib=use_cal, monitor=use_mon):
                    r = self.run_both(arith, t, value, valid, use_cal, use_mon)
                    if use_mon:
                        self.assertGreater(int(np.count_nonzero(r["report"]["detected"])), 0)


class TestStandAlone(common.BindingTest):
    def test_step_equals_chain(self):
        t, value, valid = golden_inputs()
        s = samples(t, value, valid)
        tyre = grip.mf.load(TIR)
        for arith in ARITHS:
            with self.subTest(arith=arith):
                a = grip.est.Estimator(tyre, arith=arith)
                one = a.step(s)
                b = grip.est.Estimator(tyre, arith=arith)
                half = len(s) // 2
                two = [b.step(s[:half]), b.step(s[half:])]       # the state carries over
                np.testing.assert_array_equal(one.raw, np.concatenate([x.raw for x in two]))
                c = grip.est.Estimator(tyre, arith=arith)
                np.testing.assert_array_equal(one.raw, grip.est.run(s, c)["out"].raw)
                cal1 = grip.calib.Calib(CALIB, arith=arith)
                cal2 = grip.calib.Calib(CALIB, arith=arith)
                corrected, st = cal1.apply(s)
                self.assertTrue((st == 0).all())
                chained = grip.est.run(s, grip.est.Estimator(tyre, arith=arith), calib=cal2)["samples"]
                np.testing.assert_array_equal(corrected.raw, chained.raw)
                a.reset()
                np.testing.assert_array_equal(a.step(s[:50]).raw, one.raw[:50])


class TestFrictionFromOutside(common.BindingTest):
    """grip_est_measure_friction (Estimator.step's friction rows) against
    est_ref's measure_friction on the golden bicycle run, whose road is mu
    1.0 then 0.5: a source saying so once a second, one at a wrong value.
    Tolerances: the estimator's golden ones (tests/unit/test_est_golden.c);
    mu_conf's, mu_sd's over mu_conf's 0.1 of deviation per unit."""

    TOL = {"float": {"beta": 5e-5, "mu": 2e-4, "vx": 2e-4, "mu_conf": 2e-3},
           "fixed": {"beta": 3e-3, "mu": 6e-3, "vx": 3e-3, "mu_conf": 6e-2}}

    def test_against_reference(self):
        t, value, valid = golden_inputs()
        half = len(t) // 2
        rows = [(k, 1.0 if k < half else 0.5, 0.05) for k in range(0, len(t), 100)] + [(len(t) - 30, 1.6, 0.02)]
        cfg = est_ref.config(tir.load_params(TIR), rate_hz=100)
        ref = est_ref.run(cfg, value, valid, friction=rows)
        base = est_ref.run(cfg, value, valid)
        r = {k: np.array([o[k] for o in ref]) for k in ("beta", "mu", "vx", "mu_sd", "mu_conf")}
        b = {k: np.array([o[k] for o in base]) for k in ("mu", "mu_sd")}
        # the source moves mu and its deviation: not a no-op
        self.assertGreater(float(np.max(np.abs(r["mu"] - b["mu"]))), 0.05)
        self.assertLess(float(np.median(r["mu_sd"])), float(np.median(b["mu_sd"])))
        tyre = grip.mf.load(TIR)
        for arith in ARITHS:
            with self.subTest(arith=arith):
                o = grip.est.Estimator(tyre, arith=arith).step(samples(t, value, valid), friction=rows)
                for k, tol in self.TOL[arith].items():
                    err = float(np.max(np.abs(o[k] - r[k])))
                    print(f"# measure_friction {arith}: {k} max |C - reference| {err:.2e} (tolerance {tol:g})")
                    self.assertLessEqual(err, tol)
                with self.assertRaises(grip.GripError):
                    grip.est.Estimator(tyre, arith=arith).measure_friction(2.5, 0.05)


class TestFrictionEllipse(common.BindingTest):
    """A tire whose lateral peak is 25 % above its braking peak (PDY1 x
    1.25) through an ABS stop onto a low road (the reference simulator's
    wet mu step): the utilization on the friction ellipse (mu_xy) in C
    against est_ref. Tolerances: the golden ones (TestFrictionFromOutside)."""

    TOL = TestFrictionFromOutside.TOL

    def test_against_reference(self):
        from python.reference.test_est import _simulated
        from grip_tools.evaluate import est_eval
        t, value, valid, t_limit, _ = _simulated(self, "mu-step", "wet")
        params = dict(tir.load_params(TIR))
        params["pdy1"] = 1.25 * params["pdy1"]
        cfg = est_ref.config(params, rate_hz=100, **est_eval.est_vehicle())
        tyre = grip.mf.load(TIR)
        tyre = tyre.replace(pdy1=1.25 * tyre.values["pdy1"])
        ref = est_ref.run(cfg, value, valid)
        r = {k: np.array([o[k] for o in ref]) for k in ("beta", "mu", "vx", "mu_conf")}
        self.assertLess(float(np.min(r["mu"][t >= t_limit + 1.0])), 0.5)   # the ellipse moved mu: the road is 0.3
        for arith in ARITHS:
            with self.subTest(arith=arith):
                o = grip.est.Estimator(dict(tire=tyre, rate_hz=100, **est_eval.est_vehicle()), arith=arith).step(
                    samples(t, value, valid))
                for k, tol in self.TOL[arith].items():
                    err = float(np.max(np.abs(o[k] - r[k])))
                    print(f"# friction ellipse {arith}: {k} max |C - reference| {err:.2e} (tolerance {tol:g})")
                    self.assertLessEqual(err, tol)


class TestLearned(common.BindingTest):
    """grip_est_learned_get / _set (stiff_est = 1, kx_est = 1 with a
    rear-wheel drive): the blob carries the learned stiffnesses to another
    instance bit for bit, and every kind of blob that is not this car's,
    tire's, drive layout's and build's is refused with the estimator
    unchanged."""

    def test_round_trip_and_refusals(self):
        t, value, valid, _ = golden_est.bicycle_inputs(duration=12.0)
        s = samples(t, value, valid)
        t2, value2, valid2, _ = golden_est.drive_inputs(lkx=golden_est.STIFF_LKX,
                                                        radius_front=golden_est.STIFF_RADIUS)
        s2 = samples(t2, value2, valid2)
        on = {"stiff_est": 1, "kx_est": 1, "drive_front": 0.0}
        tyre = grip.mf.load(TIR)
        other = grip.mf.load(os.path.join(ROOT, "tests", "data", "mfeval-tir", "MagicFormula61_Paramerters.tir"))
        blobs = {}
        for arith in ARITHS:
            with self.subTest(arith=arith):
                a = grip.est.Estimator({"tire": tyre, **on}, arith=arith)
                fresh = a.learned()
                self.assertEqual((fresh["k_front"], fresh["k_rear"], fresh["updates"]), (1.0, 1.0, 0))
                self.assertEqual((fresh["kx"], fresh["radius_mismatch"], fresh["kx_updates"]), (1.0, 0.0, 0))
                a.step(s)
                a.reset()
                a.step(s2)
                la = a.learned()
                self.assertGreater(la["updates"], 0)     # the generator's steering taught it
                self.assertGreater(la["kx_updates"], 0)  # ... and the drive its slip stiffness
                self.assertGreater(la["kx"], 1.25)
                self.assertLess(abs(la["radius_mismatch"] - golden_est.STIFF_RADIUS), 1e-3)
                a.reset()
                self.assertEqual(a.learned()["blob"], la["blob"])   # a reset keeps what was learned
                b = grip.est.Estimator({"tire": tyre, **on}, arith=arith)
                b.learned_set(la["blob"])
                self.assertEqual(b.learned(), la)
                c = grip.est.Estimator({"tire": tyre, **on}, arith=arith)
                before = c.learned()
                bad = bytearray(la["blob"])
                bad[20] ^= 0x01                          # one bit of the state
                for blob in (bytes(bad), la["blob"][:-1], b"", bytes(len(la["blob"]))):
                    with self.assertRaises(grip.GripError):
                        c.learned_set(blob)
                    self.assertEqual(c.learned(), before)
                d = grip.est.Estimator({"tire": other, **on}, arith=arith)
                with self.assertRaises(grip.GripError):   # another tire: another fingerprint
                    d.learned_set(la["blob"])
                e = grip.est.Estimator({"tire": tyre, **on, "drive_front": 1.0}, arith=arith)
                with self.assertRaises(grip.GripError):   # another drive layout: another fingerprint
                    e.learned_set(la["blob"])
                blobs[arith] = la["blob"]
        if len(blobs) == 2:
            with self.assertRaises(grip.GripError):       # the other build's blob
                grip.est.Estimator({"tire": tyre, **on}, arith="float").learned_set(blobs["fixed"])


if __name__ == "__main__":
    unittest.main()
