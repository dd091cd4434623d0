"""The estimator's error bounds and what its validity flags promise
(grip_tools.reference.est, bound_lateral; grip_tools.evaluate.integrity;
docs/estimator/integrity.md)."""
import os
import tempfile
import unittest
from unittest import mock

import numpy as np

from grip_tools.reference import est as est_ref
from python import sim_runs

DEG = 180.0 / np.pi


class StatsTests(unittest.TestCase):
    """integrity.stats counts what it says."""

    def test_counts_and_longest_run(self):
        from grip_tools.evaluate import integrity
        t = np.arange(10) * 0.01
        err = np.array([0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 2.0, 0.5, 2.0, np.nan])
        sd = np.array([0.1] * 8 + [1.0, 0.1])
        ok = np.array([True] * 9 + [False])
        s = integrity.stats(t, err, sd, ok, floor=1.0)
        # bad: 1, 2, 4, 5, 6 (8 is within 3 sd, 9 not valid)
        self.assertEqual(s["violations"], 5)
        self.assertEqual(s["valid_steps"], 9)
        self.assertAlmostEqual(s["longest_s"], 0.03)
        # a NaN error on a valid step is a violation, not a pass
        s = integrity.stats(t, err, sd, np.ones(10, bool), floor=1.0)
        self.assertEqual(s["violations"], 6)


    def test_kinematic_drift(self):
        from grip_tools.evaluate import integrity
        t = np.arange(301) * 0.01
        dvy = np.full(301, 0.2 * 0.01)          # drifts 0.2 m/s per s
        dsd = np.full(301, 0.1 * 0.01)          # its deviation grows 0.1 m/s per s
        ok = np.ones(301, bool)
        k = integrity.kinematic_drift(t, dvy, dsd, np.zeros(301), ok)
        # windows of 100 steps starting every 10: k0 = 0 .. 200
        self.assertEqual(k["windows"], 21)
        self.assertAlmostEqual(k["ratio_med"], 2.0)
        self.assertEqual((k["over_1"], k["over_k"]), (1.0, 0.0))
        # the truth moving as the kinematic vy does: no drift
        k = integrity.kinematic_drift(t, dvy, dsd, np.cumsum(dvy), ok)
        self.assertAlmostEqual(k["ratio_med"], 0.0)
        # a step off (or without the trace) leaves out every window over it
        ok[150] = False
        dvy2 = dvy.copy()
        dvy2[250] = np.nan
        k = integrity.kinematic_drift(t, dvy2, dsd, np.zeros(301), ok)
        self.assertEqual(k["windows"], 5)       # k0 = 0 .. 40: from 50 every window holds step 150 or 250
        self.assertIsNone(integrity.kinematic_drift(t[:50], dvy[:50], dsd[:50], np.zeros(50), ok[:50]))

    def test_ceiling_and_withheld(self):
        # the ceiling counts the steps whose error a bound within
        # beta_sd_max could cover (3 deg with 1 deg), valid or not; the
        # withheld ones with their errors and the filter's own deviation
        from grip_tools.evaluate import integrity
        n = 8
        t = np.arange(n) * 0.01
        err = np.array([0.5, 2.9, 3.1, 5.0, 0.2, 2.0, 4.0, 0.0]) / DEG
        valid = np.array([1, 0, 0, 0, 1, 0, 0, 1]) * est_ref.V_BETA
        est = dict(beta=err, beta_sd=np.full(n, 0.5 / DEG), valid=valid, flags=np.zeros(n, np.int64),
                   vx=np.full(n, 20.0), filter_vy_sd=np.array([0.1, 0.1, 0.5, 0.5, 0.1, 0.5, 0.1, 0.1]))
        moving = np.ones(n, bool)
        outside = np.array([True] * 7 + [False])            # the last step: a spin
        r = integrity.judge_run(t, est, {"beta": np.zeros(n)}, moving, outside)
        self.assertEqual(r["share_steps"], 7)
        self.assertEqual(r["ceiling_steps"], 4)             # 0.5, 2.9, 0.2, 2.0 deg
        w = r["withheld"]
        self.assertEqual((w["steps"], w["err_over"]), (5, 3))
        self.assertAlmostEqual(w["err_med_deg"], 3.1)
        # 0.5 m/s at 20 m/s: 1.43 deg of beta, beyond 1 deg (0.1: 0.29 deg)
        self.assertEqual(w["filter_over"], 3)
        self.assertNotIn("kin_drift", r)                    # no true vy


class CommandLineTests(unittest.TestCase):
    """grip est-eval --integrity refuses what it cannot run with (and an
    option of another mode, which it would ignore) with exit 2 and the
    option named, before any judge runs."""

    def test_bad_options_are_refused(self):
        import contextlib
        import io
        from grip_tools.evaluate import est_eval
        for args, said in ((["--judges", "own,bogus"], "--judges: bogus"), (["--judges", ","], "--judges"),
                           (["--const", "NO_SUCH=1"], "--const NO_SUCH=1"),
                           (["--const", "TIRE_TOL=x"], "'x' is not a number"),
                           (["--const", "TIRE_TOL"], "--const TIRE_TOL"),
                           (["--road-friction", "0"], "--road-friction 0.0"),
                           (["--road-friction", "nan"], "--road-friction nan"),
                           (["--manoeuvres", "step-steer"], "--manoeuvres: only with --independent"),
                           (["--independent"], "one at a time"),
                           (["--bank-est", "--no-bank-est"], "--no-bank-est: one at a time")):
            err = io.StringIO()
            with tempfile.TemporaryDirectory() as d, contextlib.redirect_stderr(err):
                with self.assertRaises(SystemExit) as cm:
                    est_eval.main(["--integrity", "--out", d] + args)
                self.assertEqual(os.listdir(d), [], args)       # nothing written
            self.assertEqual(cm.exception.code, 2, args)
            self.assertIn(said, err.getvalue(), args)

    def test_table_header_names_the_estimator_options(self):
        # a table written with --bank-est says so (the header named only the
        # set and the judges)
        from grip_tools.evaluate import est_eval, integrity
        self.assertEqual(integrity.table_command(True, ["fitted"]), "grip est-eval --integrity --full --judges fitted")
        with mock.patch.dict(est_eval.EXTRA, {"bank_est": 1}):
            self.assertEqual(integrity.table_command(False, list(integrity.JUDGES)),
                             "grip est-eval --integrity --bank-est")
        with mock.patch.dict(est_eval.EXTRA, {"bank_est": 0}):
            self.assertEqual(integrity.table_command(True, ["fitted"]),
                             "grip est-eval --integrity --full --judges fitted --no-bank-est")


class RunAwayTests(unittest.TestCase):
    """The generic-tire run-away: the car's rear tire much stiffer than the
    estimator's (the estimator's rear LKY at 0.4 x the car's), a steady turn
    near the limit (step steer 90 deg at 65 km/h on dry, ay 7.5 m/s^2, true
    beta -2.4 deg). Without the bounds the only state the filter can make
    consistent is both axles saturated: beta runs to -16 deg, flagged valid,
    mu confident. With them the kinematic vy carries beta while its bound
    allows, then V_BETA is withheld; no valid step is wrong beyond
    max(1 deg, 3 beta_sd)."""

    @classmethod
    def setUpClass(cls):
        try:
            from grip_tools.evaluate import est_eval, integrity
            from grip_tools.sim import cli  # noqa: F401 - importable, or skip
        except ImportError as e:       # pragma: no cover - scipy-less machine
            raise unittest.SkipTest(f"simulator not importable: {e}")
        with tempfile.TemporaryDirectory() as d:
            sim_runs.run(["-m", "step-steer", "-s", "dry", "--speed", "65", "--duration", "5", "--amplitude", "90",
                          "--no-plot"], d)
            cols = est_eval.read_csv(os.path.join(d, "sensors.csv"))
            cls.t, cls.value, cls.valid = est_ref.inputs_from_sensors(cols)
            cls.truth, _ = integrity.own_truth(d, cls.t)
        cls.cfg = integrity.mismatch_config()
        cls.integrity = integrity

    def _run(self, on):
        with mock.patch.object(est_ref, "INTEGRITY", on):
            est = self.integrity.reference_run(self.cfg, self.value, self.valid)
        if not on:
            # the old estimator gave no bound: its valid flag promised
            # beta itself, judged at the 1 deg floor
            est["beta_sd"] = np.zeros_like(est["beta_sd"])
        moving = self.truth["vx"] > 5.0
        return est, self.integrity.judge_run(self.t, est, self.truth, moving)

    def test_run_away_is_not_flagged_valid(self):
        old, r_old = self._run(False)
        new, r_new = self._run(True)
        vb_old = (old["valid"] & est_ref.V_BETA) != 0
        err_old = np.abs(old["beta"] - self.truth["beta"])[vb_old]
        print(f"\n# run-away: without the bounds beta valid in {r_old['beta']['valid_steps']} steps, "
              f"{r_old['beta']['violations']} beyond max(1 deg, 3 sd) (worst {err_old.max() * DEG:.1f} deg); "
              f"with them valid in {r_new['beta']['valid_steps']}, {r_new['beta']['violations']} beyond, "
              f"kinematic in {r_new['kin_steps']} steps", flush=True)
        # the old behaviour: the run-away flagged valid (measured: 5 deg and more)
        self.assertGreater(err_old.max() * DEG, 5.0)
        self.assertGreater(r_old["beta"]["violations"], 100)
        # the bounds: nothing valid beyond its bound, and beta still valid
        # where the kinematic estimate is young
        self.assertEqual(r_new["beta"]["violations"], 0)
        self.assertGreater(r_new["beta"]["valid_steps"], 100)
        self.assertGreater(r_new["kin_steps"], 0)
        # the carried beta stays near the truth while the filter's runs away
        late = self.t > 4.0
        self.assertLess(np.max(np.abs(new["beta"] - self.truth["beta"])[late]) * DEG, 2.0)
        self.assertGreater(np.max(np.abs(old["beta"] - self.truth["beta"])[late]) * DEG, 5.0)

    def test_bound_grows_after_the_last_observed_instant(self):
        new, _ = self._run(True)
        kin = (new["flags"] & est_ref.F_BETA_KIN) != 0
        late = self.t >= 3.5
        # both axles near saturation from ~2 s: the kinematic estimate
        # carries, and its deviation grows at least at kin_acc_sd per second
        self.assertTrue(np.all(kin[late]))
        i0, i1 = int(np.argmax(late)), len(self.t) - 1
        growth = (new["vy_sd"][i1] - new["vy_sd"][i0]) / (self.t[i1] - self.t[i0])
        print(f"\n# run-away: vy_sd grows {growth:.3f} m/s per s while carried (kin_acc_sd "
              f"{self.cfg['kin_acc_sd']})", flush=True)
        self.assertGreaterEqual(growth, self.cfg["kin_acc_sd"])
        self.assertGreater(new["beta_sd"][-1], self.cfg["beta_sd_max"])
        self.assertEqual(int(new["valid"][-1] & est_ref.V_BETA), 0)

    def test_consumer_limits(self):
        # vx_sd_max, fy_sd_max: 0 sets no limit; a limit below the
        # deviations withholds V_VX, V_AXLE and V_MARGIN and nothing else
        base = self.integrity.reference_run(self.cfg, self.value, self.valid)
        vx_med = float(np.median(base["vx_sd"][base["vx_sd"] > 0]))
        fy_med = float(np.median(base["fy_axle_sd"][base["fy_axle_sd"] > 0]))
        cfg = dict(self.cfg, vx_sd_max=0.5 * vx_med, fy_sd_max=0.5 * fy_med)
        lim = self.integrity.reference_run(cfg, self.value, self.valid)
        wide = ((base["vx_sd"] > cfg["vx_sd_max"]), np.max(base["fy_axle_sd"], axis=1) > cfg["fy_sd_max"])
        self.assertTrue(wide[0].any() and wide[1].any())
        self.assertFalse(((lim["valid"] & est_ref.V_VX) != 0)[wide[0]].any())
        self.assertFalse(((lim["valid"] & (est_ref.V_AXLE | est_ref.V_MARGIN)) != 0)[wide[1]].any())
        # the estimate and every other bit as without limits
        np.testing.assert_array_equal(lim["beta"], base["beta"])
        other = ~np.int64(est_ref.V_VX | est_ref.V_AXLE | est_ref.V_MARGIN)
        np.testing.assert_array_equal(lim["valid"] & other, base["valid"] & other)
        print(f"\n# consumer limits at half the median deviations (vx {vx_med:.3f} m/s, Fy {fy_med:.0f} N): "
              f"V_VX withheld on {int(wide[0].sum())}, V_AXLE on {int(wide[1].sum())} of {len(self.t)} steps",
              flush=True)

    def test_c_builds(self):
        # the same run-away through the C builds (grip-replay --csv, the rear
        # tire from the vehicle file's rear_tire key)
        from grip_tools.evaluate import est_eval
        from grip_tools.golden import est as golden_est
        from grip_tools.paths import REPO_ROOT
        bins = {a: os.path.join(REPO_ROOT, "build", f"{a}-gcc", "bin", "grip-replay") for a in ("float", "fixed")}
        if not all(os.path.exists(b) for b in bins.values()):
            self.skipTest("grip-replay builds absent (make; make ARITH=fixed)")
        moving = self.truth["vx"] > 5.0
        res = {}
        with tempfile.TemporaryDirectory() as d:
            rear = os.path.join(d, "rear.tir")
            with open(golden_est.tire_path()) as f, open(rear, "w") as g:
                for line in f:
                    g.write(f"LKY = {self.integrity.MISMATCH_LKY}\n" if line.split("=")[0].strip() == "LKY" else line)
            csv_path = os.path.join(d, "in.csv")
            n = len(est_eval.IN_COLS)
            est_eval.write_input_csv(csv_path, self.t, self.value[:, :n], self.valid[:, :n])
            lines = est_eval.est_vehicle_lines() + [f"rear_tire = {rear}"]
            for arith, b in bins.items():
                o = est_eval.run_c(b, golden_est.tire_path(), csv_path, vehicle="generic", vehicle_lines=lines)
                res[arith] = o
                r = self.integrity.judge_run(self.t, o, self.truth, moving)
                print(f"\n# run-away, C {arith}: beta valid in {r['beta']['valid_steps']} steps, "
                      f"{r['beta']['violations']} beyond max(1 deg, 3 sd)", flush=True)
                self.assertEqual(r["beta"]["violations"], 0)
                self.assertGreater(r["beta"]["valid_steps"], 100)
        self.assertLess(float(np.max(np.abs(res["fixed"]["beta_sd"] - res["float"]["beta_sd"]))), 3e-3)


class Rav4JudgeTests(unittest.TestCase):
    """The README's main job as an integrity judge: the RAV4 highway drive
    through the C float build against the drive's GNSS/IMU pose."""

    def test_highway(self):
        try:
            import grip.replay
            from grip_tools.evaluate import integrity
        except ImportError as e:       # pragma: no cover - binding not built
            raise unittest.SkipTest(f"binding not importable: {e}")
        why = grip.replay.available("float")
        if why:
            raise unittest.SkipTest(why)
        r = integrity.judge_rav4()["highway, 60 s (pose sideslip)"]
        b = r["beta"]
        print(f"\n# rav4 highway: beta valid {b['valid_steps']} steps ({100 * r['beta_valid_share']:.1f} %), "
              f"{b['violations']} beyond max(1 deg, 3 sd), worst true error {b['true_err_max_deg']:.2f} deg; "
              f"vx {r['vx']['valid_steps']} valid, {r['vx']['violations']} beyond max(0.1 m/s, 3 sd)", flush=True)
        self.assertGreater(b["valid_steps"], 5000)
        self.assertEqual(b["violations"], 0)
        self.assertEqual(r["vx"]["violations"], 0)
        self.assertGreaterEqual(r["beta_valid_share"], integrity.TARGET_VALID)


def _simulator_judges():
    """grip_tools.evaluate.integrity, or the test skipped where the
    independent simulator (scipy, CommonRoad's models) does not import."""
    try:
        from grip_tools.evaluate import integrity
    except ImportError as e:       # pragma: no cover - scipy-less machine
        raise unittest.SkipTest(f"simulator not importable: {e}")
    return integrity


class IndependentJudgeTests(unittest.TestCase):
    """Out-of-family runs (CommonRoad's multi-body BMW 320i, its own tires;
    the estimator on the generic PacejkaBook_Defaults unless the test says
    otherwise): the integrity target met (measured:
    docs/estimator/integrity.md)."""

    def _assert_withheld_within_promise(self, integrity, r):
        """A run below the availability target whose estimate was within
        the promise throughout: no violation, the ceiling at the target,
        beta valid below it (what withholds it is the bound, not the
        estimate)."""
        self.assertEqual(r["beta"]["violations"], 0)
        self.assertGreaterEqual(r["beta_ceiling_share"], integrity.TARGET_VALID)
        self.assertLess(r["beta_valid_share"], integrity.TARGET_VALID)

    def test_step_steer_dry(self):
        # the integrity target met; beta's availability is what the friction
        # term costs: in the sustained turn (4.7 m/s^2, mu at its prior
        # 1.0 +- 0.3) the lowest friction not excluded is the one in use,
        # where the generic tire's axles are at their peak, and the bound
        # exceeds the default 1 deg (docs/estimator/integrity.md, "Friction
        # not yet known"); without the term beta is valid on every moving step
        integrity = _simulator_judges()
        with tempfile.TemporaryDirectory() as d:
            r = integrity.independent_run("bmw320i", "step-steer", "dry", d)
            with mock.patch.object(integrity.est_ref, "MU_HYP", False):
                r0 = integrity.independent_run("bmw320i", "step-steer", "dry", d)
        b = r["beta"]
        print(f"\n# independent bmw320i step-steer dry: beta valid {b['valid_steps']} steps "
              f"({100 * r['beta_valid_share']:.1f} %; {100 * r0['beta_valid_share']:.1f} % without the friction "
              f"term), {b['violations']} beyond max(1 deg, 3 sd), worst true error {b['true_err_max_deg']:.2f} deg, "
              f"median sd {b['sd_med_deg']:.2f} deg", flush=True)
        self.assertGreater(b["valid_steps"], 100)
        self.assertLessEqual(b["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(b["longest_s"], integrity.TARGET_RUN_S)
        self.assertGreaterEqual(r0["beta_valid_share"], integrity.TARGET_VALID)
        self.assertLess(r["beta_valid_share"], integrity.TARGET_VALID)

    def test_pitch_gradient_on_a_braking_run(self):
        # the BMW's straight stop across a friction step: its body pitches
        # under braking and its accelerometer reads g sin(pitch) more
        # deceleration. The car's pitch gradient (its pitch over its ax, the
        # simulator's truth: what K&C data or a ride-height sensor in a
        # braking run gives) configured removes it: vx nearer the truth
        # than without (measured: docs/independent-judge.md, "Pitch and the speed reference's braking test")
        integrity = _simulator_judges()
        from grip_tools.sim.independent import judge, mb
        veh = mb.Vehicle("bmw320i")
        with tempfile.TemporaryDirectory() as d:
            t, value, valid, tr = integrity._run_inputs("bmw320i", "mu-step", "dry", d)
        mov = tr["vx"] > 5.0
        # the line through the origin (no pitch without ax on a flat road):
        # the stop holds ax near one value, too narrow a range for an offset
        ax, pitch = tr["ax_kin"][mov], tr["pitch"][mov]
        kp = -float(np.sum(ax * pitch) / np.sum(ax * ax))
        values = {**judge.oem_vehicle(veh), **integrity.est_eval.EXTRA}
        rms = {}
        for name, g in (("without", 0.0), ("with", kp)):
            cfg = integrity.est_ref.config(integrity.tir.load_params(judge.GENERIC_TIR), rate_hz=100,
                                           pitch_gradient=g, **values)
            outs = integrity.est_ref.run(cfg, value, valid)
            vx = np.array([o["vx"] for o in outs])
            rms[name] = float(np.sqrt(np.mean((vx - tr["vx"])[mov] ** 2)))
        print(f"\n# independent bmw320i mu-step dry: pitch gradient {kp:.5f} rad/(m/s^2); vx RMS "
              f"{rms['with']:.3f} m/s with it, {rms['without']:.3f} m/s without", flush=True)
        self.assertGreater(kp, 0.002)
        self.assertLess(kp, 0.02)
        self.assertLess(rms["with"], 0.75 * rms["without"])

    def test_full_lock_turn_is_not_braking(self):
        # the BMW's turn at 4 m/s and 30 deg on wet: its body's ax is about
        # -0.8 m/s^2 at constant speed, the steered front wheels' lateral
        # force along the body's x axis. Read as braking, the wheels pulled
        # vx at K_SLIP only and vx followed ax and its offset (0.061 m/s
        # RMS); by the wheels' own longitudinal force (est_speed.c) the
        # wheels hold it (0.015 m/s)
        integrity = _simulator_judges()
        from grip_tools.sim.independent import judge, mb
        veh = mb.Vehicle("bmw320i")
        with tempfile.TemporaryDirectory() as d:
            t, value, valid, tr = integrity._run_inputs("bmw320i", "low-speed-lock", "wet", d)
        cfg = integrity.est_ref.config(integrity.tir.load_params(judge.GENERIC_TIR), rate_hz=100,
                                       **judge.oem_vehicle(veh), **integrity.est_eval.EXTRA)
        vx = np.array([o["vx"] for o in integrity.est_ref.run(cfg, value, valid)])
        mov = tr["vx"] > 2.0
        rms = float(np.sqrt(np.mean((vx - tr["vx"])[mov] ** 2)))
        print(f"\n# independent bmw320i low-speed-lock wet: vx RMS {rms:.3f} m/s", flush=True)
        self.assertLess(rms, 0.03)

    _fitted_dir = None

    @classmethod
    def tearDownClass(cls):
        if cls._fitted_dir is not None:
            cls._fitted_dir.cleanup()
            cls._fitted_dir = None

    def _fitted(self):
        """integrity, the BMW's ramp characterization (made once per class)
        and the directory that caches it and the runs."""
        integrity = _simulator_judges()
        cls = type(self)
        if cls._fitted_dir is None:
            cls._fitted_dir = tempfile.TemporaryDirectory()
        d = cls._fitted_dir.name
        return integrity, integrity.fitted_characterization("bmw320i", d), d

    def _fitted_run(self, manoeuvre, surface):
        """integrity, the characterization and one run of the BMW's fitted
        configuration."""
        integrity, c, d = self._fitted()
        return integrity, c, integrity.independent_run("bmw320i", manoeuvre, surface, d, fitted=c)

    def test_undriven_axle_at_zero_slip_circle_ramp_dry(self):
        # the rear-driven BMW at its limit on a dry circle ramp (fitted
        # configuration): its inner front wheel carries about 100 N and
        # reads 0.4 % slow, the slowest wheel is the speed reference while
        # driving, every other wheel's slip reads high, and the undriven
        # front wheels' false Fx (930 N on the outer one) took the axle's
        # lateral friction: mu 0.109 off 1 s after the limit. Worked at zero
        # slip while not braking (est_tires.c), the front axle leaves mu
        # within the 0.1 target (docs/independent-judge.md, "The undriven
        # axle's slip"); the old form is the braking branch forced on
        from grip_tools.evaluate import est_eval
        from grip_tools.reference import tir
        from grip_tools.sim.independent import judge, mb
        integrity, c, d = self._fitted()
        veh = mb.Vehicle("bmw320i")
        t, value, valid, tr = integrity._run_inputs("bmw320i", "circle-ramp", "dry", d)
        cfg = est_ref.config(tir.load_params(c["tir"]), rate_hz=100,
                             **judge.fitted_config_values(judge.oem_vehicle(veh), c, est_eval.EXTRA))
        mu_true = tr["mu_surface"] * judge.mu_norm(veh, c["tir"])
        t0 = est_eval._onset(t, judge.utilization(tr), tr["vx"], est_eval.EXC_LIMIT)
        k1 = int(np.searchsorted(t, t0 + 1.0))

        def mu_error():
            return abs(est_ref.run(cfg, value, valid)[k1]["mu"] - mu_true[k1])

        speed = est_ref.Estimator.estimate_speed

        def always_braking(est, s, *args):
            r = speed(est, s, *args)
            s.braking = True
            return r

        new = mu_error()
        with mock.patch.object(est_ref.Estimator, "estimate_speed", always_braking):
            old = mu_error()
        print(f"\n# fitted bmw320i circle-ramp dry: mu error 1 s after the limit {new:.3f} with the undriven "
              f"axle at zero slip, {old:.3f} with its measured slips", flush=True)
        self.assertLessEqual(new, 0.1)
        self.assertGreater(old, 0.1)

    def test_fitted_tire_declared_as_fitted(self):
        # the fitted configuration declares its tire's tolerance as fitted
        # (judge.FITTED_TIRE_TOL): the ramp's fit must reproduce the wheel
        # forces within it, and with it the sine with dwell on wet keeps
        # the promise. Without the friction term (MU_HYP), which withholds
        # a further 14 % of the run (mu not yet identified), beta is valid
        # on >= 90 % of its steps, and below that under the generic tire's
        # default tolerance (the configuration's declaration before). With
        # the term the larger tolerance gives more availability: it moves
        # the blend towards the kinematic vy, whose bound has no friction
        # term
        from grip_tools.sim.independent import judge
        integrity, c, r = self._fitted_run("sine-dwell", "wet")
        fit_max = c["fit_max_share"]
        b = r["beta"]
        print(f"\n# fitted bmw320i: fit max error {100 * fit_max:.2f} % of the peak, declared tire_tol "
              f"{judge.FITTED_TIRE_TOL}; sine-dwell wet: beta valid {b['valid_steps']} steps "
              f"({100 * r['beta_valid_share']:.1f} %), {b['violations']} beyond max(1 deg, 3 sd)", flush=True)
        self.assertEqual(judge.fitted_values(c)["tire_tol"], judge.FITTED_TIRE_TOL)
        self.assertLess(fit_max, judge.FITTED_TIRE_TOL)
        self.assertGreater(b["valid_steps"], 100)
        self.assertLessEqual(b["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(b["longest_s"], integrity.TARGET_RUN_S)
        with mock.patch.object(integrity.est_ref, "MU_HYP", False):
            _, _, r0 = self._fitted_run("sine-dwell", "wet")
            with mock.patch.object(judge, "FITTED_TIRE_TOL", integrity.est_ref.TIRE_TOL):
                _, _, r3 = self._fitted_run("sine-dwell", "wet")
        print(f"# ... without the friction term: beta valid {100 * r0['beta_valid_share']:.1f} %, declared "
              f"{integrity.est_ref.TIRE_TOL} {100 * r3['beta_valid_share']:.1f} %", flush=True)
        self.assertGreaterEqual(r0["beta_valid_share"], integrity.TARGET_VALID)
        self.assertLess(r3["beta_valid_share"], integrity.TARGET_VALID)

    def test_circle_ramp_wet_withheld_by_friction_not_yet_known(self):
        # why the fitted configuration withholds beta on a slow circle ramp
        # on wet (docs/estimator/integrity.md, "Availability at the limit"):
        # beta's true error stays within the promise on every step (the
        # ceiling), but friction is not identified before the limit, and
        # the largest part of the filter's deviation on most withheld steps
        # is mu's term. The lowest friction not excluded moves the two
        # axles' slip angles alike, and the steering and the yaw rate fix
        # only their difference: nothing in the step can exclude it, so the
        # bound is what the measurements leave, not a loose constant
        integrity, _, r = self._fitted_run("circle-ramp", "wet")
        w = r["withheld"]
        print(f"\n# fitted bmw320i circle-ramp wet: beta valid {100 * r['beta_valid_share']:.1f} %, ceiling "
              f"{100 * r['beta_ceiling_share']:.1f} %; withheld {w['steps']}, {w['filter_over']} with the filter's "
              f"deviation beyond the limit, {w['mu_term']} of them mostly mu's term; its hypothesis shifts the "
              f"axles by {w['mu_shift_med_deg']:.2f} deg (median), front and rear within "
              f"{100 * w['mu_shift_gap_med']:.0f} % of each other; {r['beta']['violations']} violations", flush=True)
        self._assert_withheld_within_promise(integrity, r)
        self.assertGreater(w["mu_term"], 0.5 * w["steps"])
        self.assertLess(w["mu_shift_gap_med"], 0.25)

    def test_fitted_tire_step_steer_snow(self):
        # the fitted configuration (a tire fitted to the car on a dry ramp
        # steer): on snow mu stays near 1 for 2 s after the step while the
        # truth's axles saturate, and the fitted tire's stiffness puts the
        # model in its linear range, where the covariance does not carry
        # mu's uncertainty: without mu's share of the bound (MU_HYP off)
        # beta is flagged valid 1.7 deg off with a bound of ~0.2 deg. With
        # it, the slip angles of the lowest friction not excluded bound it
        # (docs/estimator/integrity.md, "Friction not yet known")
        from grip_tools.reference import est as est_ref
        with mock.patch.object(est_ref, "MU_HYP", False):
            _, _, old = self._fitted_run("step-steer", "snow")
        ob = old["beta"]
        print(f"\n# fitted bmw320i step-steer snow without mu's share: beta valid {ob['valid_steps']} steps, "
              f"{ob['violations']} beyond max(1 deg, 3 sd), longest {ob['longest_s']:.2f} s", flush=True)
        self.assertGreater(ob["violations"], 100)
        integrity, _, r = self._fitted_run("step-steer", "snow")
        b = r["beta"]
        print(f"# fitted bmw320i step-steer snow: beta valid {b['valid_steps']} steps, {b['violations']} beyond "
              f"max(1 deg, 3 sd), longest {b['longest_s']:.2f} s, worst true error {b['true_err_max_deg']:.2f} deg",
              flush=True)
        self.assertGreater(b["valid_steps"], 100)
        self.assertLessEqual(b["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(b["longest_s"], integrity.TARGET_RUN_S)

    def _learned_run(self, manoeuvre, surface):
        """integrity, the learned configuration's values and blob (the BMW's
        learning drive), and its run of manoeuvre on surface; skipped
        without the binding, which the learned configuration needs."""
        integrity = _simulator_judges()
        try:
            import grip  # noqa: F401
        except ImportError:
            self.skipTest("the Python binding (grip) is not built")
        with tempfile.TemporaryDirectory() as d:
            values, learned = integrity.learned_values("bmw320i", d)
            r = integrity.learned_run("bmw320i", manoeuvre, surface, d, values, learned)
        return integrity, values, learned, r

    def test_learned_configuration_starts_from_the_learning_drive(self):
        # the learned judge restores the learning drive's blob: the roll
        # gradient it runs with is the learned one (the configured 0.0088
        # moved towards the car's 0.0159), and the step steer on dry meets
        # the integrity target from it
        integrity, values, learned, r = self._learned_run("step-steer", "dry")
        b = r["beta"]
        print(f"\n# learned bmw320i: roll gradient {learned['roll_gradient']:.4f} ({learned['roll_updates']} updates), "
              f"k {learned['k_front']:.3f} / {learned['k_rear']:.3f}; step-steer dry: beta valid {b['valid_steps']} "
              f"steps, {b['violations']} beyond max(1 deg, 3 sd)", flush=True)
        self.assertEqual(values["stiff_est"], 1)
        self.assertEqual(values["roll_est"], 1)
        self.assertGreater(learned["roll_updates"], 0)
        self.assertGreater(learned["roll_gradient"], 0.0088 * 1.2)
        self.assertGreater(b["valid_steps"], 100)
        self.assertLessEqual(b["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(b["longest_s"], integrity.TARGET_RUN_S)

    def test_learned_step_steer_snow(self):
        # the learned stiffness (1.5 / 1.4 of the generic tire's) keeps the
        # model in its linear range on snow while the truth's axles
        # saturate; the tire term at the better axle alone (the smaller of
        # the two axles' slip-angle errors) left 76 valid steps beyond the
        # bound, for 0.76 s. With the axles' errors weighted by their slopes
        # (the ay update fits their force sum) none
        integrity, _, _, r = self._learned_run("step-steer", "snow")
        b = r["beta"]
        print(f"\n# learned bmw320i step-steer snow: beta valid {b['valid_steps']} steps, {b['violations']} beyond "
              f"max(1 deg, 3 sd), longest {b['longest_s']:.2f} s", flush=True)
        self.assertLessEqual(b["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(b["longest_s"], integrity.TARGET_RUN_S)

    def test_circle_ramp_dry_is_limited_by_the_tire_term(self):
        # why beta is withheld at the limit (docs/estimator/integrity.md,
        # "Availability at the limit"): on the slow circle ramp beta's true
        # error stays within 3 deg nearly to the end, so a bound could in
        # principle flag >= 90 % valid; it is withheld because the filter's
        # own deviation (the generic tire's tolerance, the axles'
        # slope-weighted term) exceeds 1 deg, and the kinematic vy cannot
        # stand in for 10 s: it drifts faster than its bound grows (the
        # roll compensation's default gradient against this car's)
        integrity = _simulator_judges()
        with tempfile.TemporaryDirectory() as d:
            r = integrity.independent_run("bmw320i", "circle-ramp", "dry", d)
        w, k = r["withheld"], r["kin_drift"]
        print(f"\n# independent bmw320i circle-ramp dry: beta valid {100 * r['beta_valid_share']:.1f} %, "
              f"ceiling {100 * r['beta_ceiling_share']:.1f} %; withheld {w['steps']}, of them {w['filter_over']} "
              f"with the filter's deviation beyond the limit, {w['err_over']} beyond 3 deg; kinematic drift / "
              f"bound median {k['ratio_med']:.2f} over {k['windows']} windows of 1 s, "
              f"{100 * k['over_1']:.0f} % above 1, {100 * k['over_k']:.0f} % above 3", flush=True)
        self._assert_withheld_within_promise(integrity, r)
        self.assertGreater(w["filter_over"], 0.9 * w["steps"])
        self.assertGreater(k["over_1"], 0.5)
        self.assertEqual(k["over_k"], 0.0)

    def test_double_lane_change_snow(self):
        # the understeer bound's withdrawal: in this lane change the car's
        # yaw rate follows the linear reference while its rear slides
        # (sideslip growing at 0.76 m/s^2 of dvy/dt, true beta 1 -> 3.5
        # deg); withdrawn there, mu went from 0.49 to 0.63 on a 0.36 road
        # and beta was flagged valid 2.4 deg off with a bound of 0.7 deg.
        # "Steady" is |dvy/dt| within 3 kin_acc_sd; 1 m/s^2 let it through.
        # The two thresholds compared without the friction term (MU_HYP),
        # which withholds the steps where they differ; the promise with it
        integrity = _simulator_judges()
        res = {}
        with tempfile.TemporaryDirectory() as d:
            for k in (est_ref.STEADY_K, 1.0 / est_ref.KIN_ACC):
                with mock.patch.object(est_ref, "STEADY_K", k), mock.patch.object(est_ref, "MU_HYP", False):
                    res[k] = integrity.independent_run("bmw320i", "double-lane-change", "snow", d)
            full = integrity.independent_run("bmw320i", "double-lane-change", "snow", d)
        new, old = res[est_ref.STEADY_K]["beta"], res[1.0 / est_ref.KIN_ACC]["beta"]
        print(f"\n# independent bmw320i double lane change snow: beta valid beyond max(1 deg, 3 sd) "
              f"{new['violations']} of {new['valid_steps']} (longest {1000 * new['longest_s']:.0f} ms); "
              f"with |dvy/dt| < 1 m/s^2 as steady {old['violations']} of {old['valid_steps']} "
              f"(longest {1000 * old['longest_s']:.0f} ms)", flush=True)
        print(f"# ... worst true error where valid {new['true_err_max_deg']:.2f} deg, with 1 m/s^2 "
              f"{old['true_err_max_deg']:.2f} deg", flush=True)
        # with the tire term at the better axle alone the old threshold's
        # error broke the promise (39 of 497 valid steps); with the axles'
        # slope-weighted term its bound covers it, but beta is still 2.4
        # deg off where the new threshold keeps it within 1 deg
        self.assertGreater(old["true_err_max_deg"], 2.0)
        self.assertLess(new["true_err_max_deg"], 1.0)
        self.assertLessEqual(new["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(new["longest_s"], integrity.TARGET_RUN_S)
        # beta stays available on most of the run without the friction
        # term (291 of its 481 steps, 60.5 %: the slope-weighted tire term
        # withholds the rest); with it the promise holds too
        self.assertGreater(res[est_ref.STEADY_K]["beta_valid_share"], 0.5)
        f = full["beta"]
        print(f"# ... with the friction term: beta valid {f['valid_steps']} steps "
              f"({100 * full['beta_valid_share']:.1f} %), {f['violations']} beyond max(1 deg, 3 sd)", flush=True)
        self.assertLessEqual(f["rate"], integrity.TARGET_RATE)
        self.assertLessEqual(f["longest_s"], integrity.TARGET_RUN_S)


if __name__ == "__main__":
    unittest.main()


class FaultCampaignTests(unittest.TestCase):
    """The fault campaign as a judge of the bounds: a lateral accelerometer
    delayed by 0.2 s for 1 s from the first peak of a sine with dwell on a
    wet road (grip faults' "sine-dwell wet", "ay delay"). The estimator's
    bound does not see a sensor fault: on its own valid bits beta is wrong
    beyond max(1 deg, 3 beta_sd) for a third of a second. The monitor cannot
    check ay while the car is unstable (the UNVERIFIED hold); its gate,
    honoured with the default degraded bits, withholds beta there, and no
    step it passes is wrong beyond the bound."""

    def test_the_monitor_gate_keeps_the_promise(self):
        try:
            from grip_tools.evaluate import faults, integrity
        except ImportError as e:       # pragma: no cover - scipy-less machine
            raise unittest.SkipTest(f"simulator not importable: {e}")
        si = [s[0] for s in faults.SCENARIOS].index("sine-dwell wet")
        with tempfile.TemporaryDirectory() as cache:
            _, rows = integrity._faults_scenario((si, cache, ("ay delay",)))
        alone, gate = rows["estimator alone"]["beta"], rows["monitor gate"]["beta"]
        print(f"sine-dwell wet, ay delay: beta violations {alone['violations']} of {alone['valid_steps']} valid "
              f"steps on the estimator's bits, {gate['violations']} of {gate['valid_steps']} through the gate")
        self.assertGreater(alone["violations"], 10)
        self.assertGreater(alone["longest_s"], 0.1)
        self.assertEqual(gate["violations"], 0)
        self.assertGreater(gate["valid_steps"], 100)
