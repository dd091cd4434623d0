"""`grip-replay -e TIR --csv FILE` (port/linux/grip_replay.c, CSV input of
the onboard estimator) against the float64 reference est_ref.

A 5 s run of the internal single-track generator (golden_est.bicycle_inputs:
steer steps, slalom, braking in a turn, mu 1.0 then 0.5), with a few cells
blanked or NaN (ay, yaw rate: the validity path), is written as CSV, run
through the float and the fixed build, and compared row by row with est_ref
on the same inputs. Tolerances are the golden tolerances of
docs/estimator.md ("Golden tests"), float / fixed:
  vx 2e-4 / 3e-3 m/s, beta 5e-5 / 3e-3 rad, yaw rate 5e-6 / 2e-4 rad/s,
  yaw-rate bias 5e-6 / 2e-4 rad/s, yaw-rate reference 1e-4 / 3e-3 rad/s,
  mu 2e-4 / 6e-3, axle Fy 0.1 % / 0.3 % of the run's peak,
plus the output print resolution (%.6g: 1e-6 relative).
Also: every output finite, exit codes and messages for malformed input,
the vehicle file, and the av21 preset.

Binaries: build/<arith>-gcc/bin/grip-replay; a build that is absent is
skipped with the reason.
"""
import csv
import io
import math
import os
import struct
import subprocess
import tempfile
import unittest

import numpy as np

from grip_tools.reference import est as est_ref
from grip_tools.golden import est as golden_est
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
TIR = golden_est.tire_path()
BINS = {a: os.path.join(ROOT, "build", f"{a}-gcc", "bin", "grip-replay") for a in ("float", "fixed")}
COLS = ["wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle", "yaw_rate",
        "ax", "ay"]
TOL = {"float": dict(vx=2e-4, beta=5e-5, yaw_rate=5e-6, yaw_rate_bias=5e-6, yaw_rate_ref=1e-4, mu=2e-4, fy=1e-3),
       "fixed": dict(vx=3e-3, beta=3e-3, yaw_rate=2e-4, yaw_rate_bias=2e-4, yaw_rate_ref=3e-3, mu=6e-3, fy=3e-3)}


def inputs():
    t, value, valid, _ = golden_est.bicycle_inputs(duration=5.0)
    value, valid = value.copy(), valid.copy()
    # validity through the file: ay NaN for 8 steps (beyond the 50 ms hold),
    # yaw rate empty for 3 steps (within the hold)
    for k in range(150, 158):
        valid[k, est_ref.AY], value[k, est_ref.AY] = 0, 0.0
    for k in range(300, 303):
        valid[k, est_ref.YAW], value[k, est_ref.YAW] = 0, 0.0
    return t, value, valid


def write_csv(path, t, value, valid, nan_cells=True):
    with open(path, "w") as f:
        f.write("# test input\n")
        f.write(",".join(["t_s"] + COLS + ["comment"]) + "\n")
        for k in range(len(t)):
            cells = [repr(float(t[k]))]
            for i in range(8):
                if valid[k, i]:
                    cells.append(repr(float(value[k, i])))
                else:
                    cells.append("nan" if (nan_cells and i == est_ref.AY) else "")
            cells.append("x")
            f.write(",".join(cells) + "\n")


def run(binary, args):
    p = subprocess.run([binary] + args, capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


def read_out(text):
    rows = list(csv.DictReader(io.StringIO(text)))
    return rows


def col(rows, k):
    return np.array([float(r[k]) if r[k] != "" else np.nan for r in rows])


class CsvModeTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.t, cls.value, cls.valid = inputs()
        cls.path = os.path.join(cls.tmp.name, "in.csv")
        write_csv(cls.path, cls.t, cls.value, cls.valid)
        cls.ref = est_ref.run(est_ref.config(golden_est.tire_params()), cls.value, cls.valid)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def binary(self, arith):
        b = BINS[arith]
        if not os.path.exists(b):
            self.skipTest(f"{b} not built (make ARITH={arith} progs)")
        return b

    def check_build(self, arith):
        rc, out, err = run(self.binary(arith), ["-e", TIR, "--vehicle", "generic", "--csv", self.path])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        self.assertEqual(len(rows), len(self.t))
        # the input columns as in CAN mode, ay invalid where the file said so
        self.assertEqual(rows[150]["ay"], "")
        self.assertEqual(rows[150]["ay_fault"], "missing")
        self.assertEqual(rows[0]["ay_fault"], "ok")
        ref = self.ref
        st = col(rows, "est_status")
        self.assertTrue(np.all(st >= 0))
        for k in ("vx", "beta", "yaw_rate", "yaw_rate_ref", "mu", "mu_conf", "fy_front", "fy_rear",
                  "yaw_rate_bias", "fy_margin_front"):
            self.assertTrue(np.all(np.isfinite(col(rows, k))), k)
        valid = np.array([int(r["est_valid"]) for r in rows])
        valid_ref = np.array([o["valid"] for o in ref])
        # validity follows the reference (ay lost for 80 ms -> beta invalid),
        # but for beta's limit: where beta_sd lies within the build's
        # tolerance of beta_sd_max the two may fall on either side of it, and
        # then V_BETA and the bits that follow it (the wheels', the margin)
        # differ, nothing else
        follows = est_ref.V_BETA | est_ref.V_MARGIN | sum(1 << (5 + i) for i in range(4))
        limit = est_ref.BETA_SD_MAX
        sd_ref = np.array([o["beta_sd"] for o in ref])
        differ = np.nonzero(valid != valid_ref)[0]
        for k in differ:
            self.assertEqual(int(valid[k] ^ valid_ref[k]) & ~follows, 0, f"row {k}")
            self.assertLessEqual(abs(sd_ref[k] - limit), TOL[arith]["beta"], f"row {k}")
        print(f"\n  grip-replay --csv {arith}: validity as the reference's on {len(valid) - len(differ)} of "
              f"{len(valid)} rows (beta_sd at its limit on the others)")
        self.assertTrue(np.any((valid & est_ref.V_BETA) == 0))
        tol = TOL[arith]
        report = []
        for k in ("vx", "beta", "yaw_rate", "yaw_rate_bias", "yaw_rate_ref", "mu"):
            c = col(rows, k)
            r = np.array([o[k] for o in ref])
            err = float(np.max(np.abs(c - r)))
            report.append(f"{k} {err:.2e}")
            self.assertLessEqual(err, tol[k] + 1e-6 * float(np.max(np.abs(r))), f"{arith} {k}")
        for ax_i, name in ((0, "fy_front"), (1, "fy_rear")):
            c = col(rows, name)
            r = np.array([o["fy_axle"][ax_i] for o in ref])
            peak = float(np.max(np.abs(r)))
            err = float(np.max(np.abs(c - r)))
            report.append(f"{name} {100 * err / peak:.4f} % of peak")
            self.assertLessEqual(err, tol["fy"] * peak, f"{arith} {name}")
        # the model lateral acceleration column: sum of the body-frame Fy / m,
        # empty exactly where the axle forces are not valid
        ay_m = col(rows, "ay_model")
        axle_ok = (valid & est_ref.V_AXLE) != 0
        self.assertTrue(np.all(np.isfinite(ay_m[axle_ok])))
        self.assertTrue(np.all(np.isnan(ay_m[~axle_ok])))
        fyf = col(rows, "fy_front")
        # at small steer angles sum Fy / m is close to (Fy_f + Fy_r) / m
        approx = (fyf + col(rows, "fy_rear")) / 1450.0
        self.assertLess(float(np.nanmax(np.abs(ay_m - approx)[axle_ok])), 0.3)
        print(f"\n  grip-replay --csv {arith}: max |C - est_ref|: " + ", ".join(report))

    def test_rear_axle_tire(self):
        # --estimate-rear: the rear axle's own tire (a stiffer copy written
        # by grip axle-stiffness for an understeer gradient of 0.003
        # rad/(m/s^2)) against the reference with that tire on the rear
        from grip_tools.fit import axle_stiffness
        from grip_tools.reference import tir
        rear = os.path.join(self.tmp.name, "rear.tir")
        self.assertEqual(axle_stiffness.main(["--tir", TIR, "--mass", "1450", "--lf", "1.1", "--lr", "1.6",
                                              "--understeer-gradient", "0.003", "-o", rear]), 0)
        rc, out, err = run(self.binary("float"), ["-e", TIR, "--estimate-rear", rear, "--vehicle", "generic",
                                                  "--csv", self.path])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        ref = est_ref.run(est_ref.config(golden_est.tire_params(), tir.load_params(rear)), self.value, self.valid)
        beta = col(rows, "beta")
        r = np.array([o["beta"] for o in ref])
        err_rear = float(np.max(np.abs(beta - r)))
        same = np.array([o["beta"] for o in self.ref])
        print(f"\n  grip-replay --estimate-rear: max |beta - est_ref| {err_rear:.2e} rad; "
              f"the rear tire moves beta by up to {float(np.max(np.abs(r - same))):.4f} rad")
        self.assertLessEqual(err_rear, TOL["float"]["beta"] + 1e-6 * float(np.max(np.abs(r))))
        # the tire was applied: the rear axle force moves (beta follows the
        # kinematic vy where the tire model's bound is the larger, so it
        # moves less: 0.00025 rad)
        # the yaw-rate reference takes the axles' stiffnesses directly
        yr, yr_same = (np.array([o["yaw_rate_ref"] for o in x]) for x in (ref, self.ref))
        print(f"  the rear tire moves the yaw-rate reference by up to {float(np.max(np.abs(yr - yr_same))):.4f} rad/s")
        self.assertGreater(float(np.max(np.abs(yr - yr_same))), 100 * TOL["float"]["yaw_rate_ref"])
        self.assertLessEqual(float(np.nanmax(np.abs(col(rows, "yaw_rate_ref") - yr))), TOL["float"]["yaw_rate_ref"])

    def test_float(self):
        self.check_build("float")

    def test_fixed(self):
        self.check_build("fixed")

    def test_vehicle_file_and_errors(self):
        b = self.binary("float")
        d = self.tmp.name
        veh = os.path.join(d, "car.txt")
        with open(veh, "w") as f:
            f.write("# passenger car, heavier\nmass = 1600   # kg\n\niz=2600\nspeed_ref_mu = 1\n")
        rc, out, err = run(b, ["-e", TIR, "--vehicle", "generic", "--vehicle-file", veh, "--csv", self.path])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        ref = est_ref.run(est_ref.config(golden_est.tire_params(), mass=1600.0, iz=2600.0, speed_ref_mu=1),
                          self.value, self.valid)
        err_beta = np.max(np.abs(col(rows, "beta") - np.array([o["beta"] for o in ref])))
        self.assertLessEqual(err_beta, TOL["float"]["beta"])
        # a different mass changes the estimate (the file was applied)
        base = np.array([o["fy_axle"][0] for o in self.ref])
        self.assertGreater(np.nanmax(np.abs(col(rows, "fy_front") - base)), 0.02 * np.max(np.abs(base)))
        # the vehicle-level keys: road plane, downforce, drag, rolling
        # resistance, sensor latency, steering lag
        veh2 = os.path.join(d, "car2.txt")
        kw = dict(cla=1.5, aero_front=0.45, air_density=1.1, cda=0.7, crr=0.012, tan_bank=0.03, tan_grade=-0.01,
                  latency=0.02, steer_lag=0.15)
        with open(veh2, "w") as f:
            f.write("".join(f"{k} = {v}\n" for k, v in kw.items()))
        rc, out, err = run(b, ["-e", TIR, "--vehicle", "generic", "--vehicle-file", veh2, "--csv", self.path])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        ref = est_ref.run(est_ref.config(golden_est.tire_params(), **kw), self.value, self.valid)
        for name in ("beta", "yaw_rate"):
            e = np.max(np.abs(col(rows, name) - np.array([o[name] for o in ref])))
            print(f"  vehicle file with {sorted(kw)}: max |C - est_ref| {name} {e:.2e}")
            self.assertLessEqual(e, TOL["float"][name])
        bad = os.path.join(d, "bad.txt")
        with open(bad, "w") as f:
            f.write("mass = 1600\nwheelbase = 2.7\n")
        rc, _, err = run(b, ["-e", TIR, "--vehicle-file", bad, "--csv", self.path])
        self.assertEqual(rc, 2)
        self.assertIn("bad.txt:2: unknown key 'wheelbase'", err)
        # malformed CSV: a cell that is not a number, a short row, no time column
        for text, msg in (("t_s,ay\n0.0,abc\n", "not a number 'abc'"), ("t_s,ay\n0.0\n", "1 cells, the header has 2"),
                          ("ay,yaw_rate\n1,2\n", "no time column")):
            p = os.path.join(d, "m.csv")
            with open(p, "w") as f:
                f.write(text)
            rc, _, err = run(b, ["-e", TIR, "--csv", p])
            self.assertEqual(rc, 4, err)
            self.assertIn(msg, err)
        rc, _, err = run(b, ["--csv", self.path])
        self.assertEqual(rc, 2)
        self.assertIn("needs the estimator", err)
        rc, out, _ = run(b, ["--help"])
        self.assertIn("--csv FILE", out)

    def test_learned_blob(self):
        """--learned-out writes what stiff_est and kx_est learned,
        --learned-in restores it (the run then starts from it: another
        estimate, and the same blob as the binding's after the same inputs);
        a blob of another size, a corrupt one, one of the other build, another
        tire or another drive layout exits 4 naming the file."""
        d = self.tmp.name
        t, v, ok, _ = golden_est.bicycle_inputs(dt=0.01, duration=12.0, mu_road=(1.0, 1.0), seed=golden_est.SEED + 4,
                                                steer_gain=0.5, brake_demand=0.5, lky=golden_est.STIFF_LKY)
        path = os.path.join(d, "stiff.csv")
        write_csv(path, t, v, ok)
        veh = os.path.join(d, "stiff.txt")
        with open(veh, "w") as f:
            f.write("stiff_est = 1\nkx_est = 1\nroll_est = 1\ndrive_front = 0\n")
        veh_fwd = os.path.join(d, "stiff_fwd.txt")
        with open(veh_fwd, "w") as f:
            f.write("stiff_est = 1\nkx_est = 1\ndrive_front = 1\n")
        blobs = {}
        for arith in ("float", "fixed"):
            if not os.path.exists(BINS[arith]):
                continue
            b = BINS[arith]
            learned = os.path.join(d, f"learned_{arith}.bin")
            base = ["-e", TIR, "--vehicle", "generic", "--vehicle-file", veh, "--csv", path]
            rc, out1, err = run(b, base + ["--learned-out", learned])
            self.assertEqual(rc, 0, err)
            with open(learned, "rb") as f:
                blob = f.read()
            blobs[arith] = learned
            self.assertEqual(len(blob), 92)            # version 3: with the roll gradient
            kx_updates, = struct.unpack_from("<I", blob, 44)
            self.assertGreater(kx_updates, 0)      # the straight start while coasting
            rc, out2, err = run(b, base + ["--learned-in", learned, "--learned-out", learned + ".2"])
            self.assertEqual(rc, 0, err)
            b1, b2 = col(read_out(out1), "beta"), col(read_out(out2), "beta")
            self.assertGreater(np.nanmax(np.abs(b2 - b1)), 1e-4, arith)   # it started from what was learned
            bad = bytearray(blob)
            bad[24] ^= 0x10
            for name, data in (("corrupt.bin", bytes(bad)), ("short.bin", blob[:-1]), ("long.bin", blob + b"\0")):
                p = os.path.join(d, name)
                with open(p, "wb") as f:
                    f.write(data)
                rc, _, err = run(b, base + ["--learned-in", p])
                self.assertEqual(rc, 4, (arith, name, err))
                self.assertIn(name, err)
            other = os.path.join(ROOT, "tests", "data", "mfeval-tir", "MagicFormula61_Paramerters.tir")
            rc, _, err = run(b, ["-e", other, "--vehicle", "generic", "--vehicle-file", veh, "--csv", path,
                                 "--learned-in", learned])
            self.assertEqual(rc, 4, err)
            self.assertIn("not a learned blob of this car, tire and arithmetic build", err)
            rc, _, err = run(b, ["-e", TIR, "--vehicle", "generic", "--vehicle-file", veh_fwd, "--csv", path,
                                 "--learned-in", learned])
            self.assertEqual(rc, 4, err)
            self.assertIn("not a learned blob of this car, tire and arithmetic build", err)
        if len(blobs) == 2:
            rc, _, err = run(BINS["float"], ["-e", TIR, "--vehicle", "generic", "--vehicle-file", veh, "--csv", path,
                                             "--learned-in", blobs["fixed"]])
            self.assertEqual(rc, 4, err)

    def test_av21_preset(self):
        b = self.binary("float")
        # straight running at 20 m/s: the preset is accepted, outputs finite
        p = os.path.join(self.tmp.name, "av21.csv")
        with open(p, "w") as f:
            f.write("t_s," + ",".join(COLS) + ",vehicle_speed\n")
            for k in range(300):
                f.write(f"{k * 0.01:.2f},20,20,20,20,0.01,0.0,0.0,0.0,20\n")
        rc, out, err = run(b, ["-e", TIR, "--vehicle", "av21", "--csv", p])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        self.assertAlmostEqual(float(rows[-1]["vx"]), 20.0, places=3)
        self.assertTrue(all(math.isfinite(float(r["beta"])) for r in rows))
        self.assertIn("vehicle_speed", rows[0])
        # the preset is est_eval.AV21_VEHICLE (steering lag included): the
        # generator's run with its steering as a road-wheel angle (ratio 1)
        from grip_tools.evaluate import est_eval
        value = self.value.copy()
        value[:, est_ref.STEER] /= 15.5
        p2 = os.path.join(self.tmp.name, "av21_dyn.csv")
        write_csv(p2, self.t, value, self.valid)
        rc, out, err = run(b, ["-e", TIR, "--vehicle", "av21", "--csv", p2])
        self.assertEqual(rc, 0, err)
        rows = read_out(out)
        ref = est_ref.run(est_ref.config(golden_est.tire_params(), **est_eval.AV21_VEHICLE), value, self.valid)
        for name in ("beta", "yaw_rate", "yaw_rate_ref", "delta"):
            e = np.max(np.abs(col(rows, name) - np.array([o[name] for o in ref])))
            print(f"  av21 preset vs est_eval.AV21_VEHICLE: max |C - est_ref| {name} {e:.2e}")
            self.assertLessEqual(e, TOL["float"].get(name, TOL["float"]["beta"]))

    def test_est_eval_c_path(self):
        """est_eval's writer and reader (the C columns of the accuracy table)
        give the same numbers as the direct run, and the fixed/float ratio
        ignores metrics whose float error is below its floor."""
        from grip_tools.evaluate import est_eval
        b = self.binary("float")
        p = os.path.join(self.tmp.name, "ee.csv")
        est_eval.write_input_csv(p, self.t, self.value[:, :13], self.valid[:, :13])
        r = np.array([x["beta"] for x in est_ref.run(est_ref.config(golden_est.tire_params()),
                                                     self.value, self.valid)])
        o = est_eval.run_c(b, TIR, p)   # vehicle generic: est_ref.config's car
        self.assertLessEqual(float(np.max(np.abs(o["beta"] - r))), TOL["float"]["beta"])
        q, which = est_eval.fixed_float_ratio({"beta_rms_deg": 0.5, "mu_err_1s": 0.001},
                                              {"beta_rms_deg": 0.6, "mu_err_1s": 0.01})
        self.assertAlmostEqual(q, 1.2)
        self.assertEqual(which, "beta_rms_deg")

    def test_est_eval_binding_is_grip_replay(self):
        """est_eval runs the C estimator through the binding (run_est with a
        ("binding", arith) build): the same statuses, validity and flags as
        grip-replay --csv on the same inputs and every other column equal as
        grip-replay prints it (%.6g), in both arithmetics, for the generic
        car with vehicle-file values and for the av21 preset."""
        from grip_tools.evaluate import est_eval
        if est_eval.binding_available() is not None:
            self.skipTest(est_eval.binding_available())
        t, value, valid = self.t, self.value[:, :13], self.valid[:, :13]
        av21_value = value.copy()
        av21_value[:, est_ref.STEER] /= 15.5
        cases = [("generic", {"latency": 0.02, "steer_latency": 0.01, "cda": 0.7, "crr": 0.012}, value),
                 ("av21", {}, av21_value)]
        for arith in ("float", "fixed"):
            b = self.binary(arith)
            for vehicle, values, v in cases:
                with self.subTest(arith=arith, vehicle=vehicle):
                    prog = est_eval.run_est(("program", b), TIR, t, v, valid, vehicle=vehicle, vehicle_values=values)
                    mine = est_eval.run_est(("binding", arith), TIR, t, v, valid, vehicle=vehicle,
                                            vehicle_values=values)
                    for k in ("est_status", "valid", "flags"):
                        np.testing.assert_array_equal(mine[k], prog[k], k)
                    for k in ("time", "beta", "mu", "mu_conf", "fyf", "fyr", "vx", "yaw_rate", "yaw_rate_ref",
                              "yaw_rate_bias", "ay_model"):
                        a = ["" if np.isnan(x) else "%.6g" % x for x in mine[k]]
                        c = ["" if np.isnan(x) else "%.6g" % x for x in prog[k]]
                        bad = [i for i in range(len(a)) if a[i] != c[i]]
                        self.assertEqual(bad, [], f"{k}: first rows {[(a[i], c[i]) for i in bad[:3]]}")


if __name__ == "__main__":
    unittest.main()
