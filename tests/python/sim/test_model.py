"""Reference vehicle simulator (grip_tools.sim): physics checks.

Every check compares the simulation with something computed independently
(linear bicycle model, rolling-resistance and drag balance, an energy
integral, a finer step, the FMVSS 126 criteria). Tolerances are stated with
the figure measured when they were set (docs/simulator.md, 'Accuracy').
Steps of 2 ms keep the runtime low; the step-halving test shows the error
at 2 ms is below 1e-7 rad/s in yaw rate.
"""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

from grip_tools.sim import canlog, manoeuvres as M, model, vehicles
from grip_tools.sim.tires import MFTire
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
H = 2e-3
DEG = math.pi / 180.0
G = 9.80665


class TyreAdapterTest(unittest.TestCase):
    def test_force_opposes_lateral_sliding_on_both_sides(self):
        # a contact centre moving to the left (Vcy > 0, alpha > 0 in ISO-W) is pushed right
        t = MFTire("PacejkaBook_Defaults.tir")
        out = t.evaluate(0.0, 0.02, 4000.0, 20.0, mirror=np.array([False, True]))
        self.assertTrue(np.all(out["fy"] < 0.0), out["fy"])
        # mirroring changes only the asymmetric part (shifts): same magnitude within 10 %
        self.assertLess(abs(out["fy"][0] / out["fy"][1] - 1.0), 0.10)
        # driving slip gives a forward force
        self.assertGreater(float(t.evaluate(0.05, 0.0, 4000.0, 20.0)["fx"]), 0.0)

    def test_mu_scales_peak_force(self):
        t = MFTire("PacejkaBook_Defaults.tir")
        a = np.linspace(0.0, 0.4, 81)
        dry = np.abs(t.evaluate(0.0, a, 4000.0, 20.0, 1.0, 1.0)["fy"]).max()
        snow = np.abs(t.evaluate(0.0, a, 4000.0, 20.0, 0.3, 0.3)["fy"]).max()
        self.assertAlmostEqual(snow / dry, 0.3, delta=0.01)   # measured 0.300


class SteadyStateBicycleTest(unittest.TestCase):
    """Seed 000 eqs 2.17-2.18: r/delta = (V/l) / (1 + A V^2)."""

    @classmethod
    def setUpClass(cls):
        v = vehicles.passenger()
        cls.v = v
        # effects that the linear bicycle model does not have are off: aligning
        # moments in the yaw balance, rolling resistance (with load transfer
        # it makes an understeering yaw moment), drag. Load transfer stays on.
        eff = model.Effects(aligning_moment=False, aero=False, rolling_resistance=False)
        speeds = np.array([10.0, 20.0, 30.0, 40.0])
        swa = np.array([M.linear_swa(v, s, 0.5) for s in speeds])
        cls.speeds = speeds
        sc = M.step_steer(v, np.concatenate([speeds, speeds]), swa_deg=np.concatenate([swa, -swa]) / DEG,
                          t0=0.2, duration=3.0)
        cls.res = model.simulate(v, sc, eff, h=H)

    def test_yaw_rate_gain_matches_stability_factor(self):
        v, res, n = self.v, self.res, len(self.speeds)
        tire = res.model.tire
        fzf, fzr = v.static_loads()
        kf = float(tire.cornering_stiffness(fzf))
        kr = float(tire.cornering_stiffness(fzr))
        A = M.stability_factor(v.m, v.lf, v.lr, kf, kr)
        self.assertGreater(A, 0.0)      # the passenger car understeers
        r, d, vx = res["r"][-1], res["delta"][-1], res["vx"][-1]
        worst = 0.0
        for i in range(n):
            # +/- steer difference removes the tyres' offsets (conicity, ply steer)
            gain = (r[i] - r[i + n]) / (d[i] - d[i + n])
            V = 0.5 * (vx[i] + vx[i + n])
            ref = (V / v.l) / (1.0 + A * V * V)
            worst = max(worst, abs(gain / ref - 1.0))
            self.assertLess(abs(res["ay"][-1, i]), 0.6)                       # small ay
            drdt = abs(res["r"][-1, i] - res["r"][-26, i]) / (25 * H)
            self.assertLess(drdt, 1e-3, "not settled")                        # steady state
        print(f"\n# bicycle yaw-rate gain: max relative deviation {worst:.2e} (A = {A:.3e} s^2/m^2)")
        # measured 1.15e-3 (at 40 m/s; curvature of Ky(Fz) under load transfer); tolerance 5e-3
        self.assertLess(worst, 5e-3)


class SplitMuAndCoastTest(unittest.TestCase):
    """One batch: split-mu braking with low mu on the left, the mirror case,
    a car coasting straight on a dry road, and braking to standstill (all
    effects on)."""

    @classmethod
    def setUpClass(cls):
        v = vehicles.passenger()
        cls.v = v
        t_brake, p = 0.3, M.brake_pressure_for(v, 0.9 * G)
        cls.t_brake = t_brake
        roads = [model.Road.mu_split(0.3, 1.0), model.Road.mu_split(1.0, 0.3), model.Road.uniform(1.0),
                 model.Road.uniform(1.0)]

        def brake(t):
            pb = min(400.0 * max(t - t_brake, 0.0), p)
            return np.array([pb, pb, 0.0, pb])
        sc = model.Scenario(4, [22.0, 22.0, 30.0, 6.0], 1.3, model.Road.batch(roads), brake=brake,
                            controllers=[M.ABS()], name="split-mu+coast")
        cls.res = model.simulate(v, sc, model.Effects(), h=H)

    def test_split_mu_yaw_moment_turns_towards_high_mu(self):
        res, t = self.res, self.res.t
        w = (t > self.t_brake) & (t < self.t_brake + 0.5)
        # low mu left: the right (high-mu) wheels brake harder -> clockwise (negative) yaw
        self.assertLess(res["mz_total"][w, 0].mean(), 0.0)
        self.assertLess(res["r"][np.searchsorted(t, self.t_brake + 0.5), 0], 0.0)
        self.assertGreater(res["mz_total"][w, 1].mean(), 0.0)
        self.assertGreater(res["r"][np.searchsorted(t, self.t_brake + 0.5), 1], 0.0)
        # the two cases mirror each other (tyre asymmetry only): |r| within 10 %
        k = np.searchsorted(t, self.t_brake + 0.5)
        r0, r1 = res["r"][k, 0], res["r"][k, 1]
        print(f"\n# split-mu yaw rate 0.5 s after brake: {r0 / DEG:.2f} / {r1 / DEG:.2f} deg/s")
        self.assertLess(abs(abs(r0) / abs(r1) - 1.0), 0.10)
        # braking force on the high-mu side exceeds the low-mu side
        fx = res["fx"][w, 0, :]
        self.assertLess(fx[:, 1].mean(), fx[:, 0].mean())

    def test_coasting_decelerates_by_rolling_resistance_and_drag_only(self):
        res, v, i = self.res, self.v, 2
        m = res.model
        t = res.t
        w = t > 0.2                                       # after the start transient
        # no lateral motion
        self.assertLess(np.abs(res["r"][:, i]).max(), 1e-3)
        self.assertLess(np.abs(res["Y"][:, i]).max(), 0.01)
        # deceleration: (sum M_rr / Re + drag) / (m + sum J / Re^2)
        vx = res["vx"][w, i]
        a_sim = np.gradient(vx, t[w])
        m_eff = v.m + (m.j / m.re ** 2).sum()
        a_ref = -((res["m_rr"][w, i, :] / m.re).sum(axis=1) + res["drag"][w, i]) / m_eff
        err = np.abs(a_sim[5:-5] / a_ref[5:-5] - 1.0).max()
        print(f"\n# coasting: decel {-a_sim.mean():.4f} m/s^2, max rel. deviation from the resistance "
              f"balance {err:.2e}")
        self.assertLess(err, 1e-3)     # measured 1.3e-5 (tyre slip losses are not in a_ref)

    def test_braking_to_standstill_has_no_low_speed_blow_up(self):
        res, i = self.res, 3
        vx = res["vx"][:, i]
        self.assertTrue(np.all(np.isfinite(res["kappa"][:, i, :])))
        self.assertLess(vx[-1], 0.1)                      # stopped (measured 0.007 m/s)
        self.assertGreater(vx.min(), -0.01)               # never rolls backwards
        self.assertGreater(res["omega"][:, i, :].min(), -0.1)
        self.assertLess(np.abs(res["kappa"][-1, i, :]).max(), 0.05)   # relaxed slips stay bounded
        self.assertLess(np.abs(res["ax"][:, i]).max(), 1.2 * G)

    def test_energy_balance(self):
        """Kinetic energy change = integral of the modelled power terms."""
        res, i = self.res, 2
        m = res.model
        v = self.v
        d = {k: res[k][:, i] for k in ("vx", "vy", "r", "drag", "mz_total")}
        om = res["omega"][:, i, :]
        e = (0.5 * v.m * (d["vx"] ** 2 + d["vy"] ** 2) + 0.5 * v.iz * d["r"] ** 2
             + 0.5 * (m.j * om ** 2).sum(axis=1)
             + 0.5 * v.ixs * res["phid"][:, i] ** 2 + 0.5 * v.k_roll * res["phi"][:, i] ** 2)
        fx, fy = res["fx"][:, i, :], res["fy"][:, i, :]
        sgn = np.tanh(om / v.omega_eps)
        p_slip = (fx * (res["vcx"][:, i, :] - res["re_omega"][:, i, :]) + fy * res["vcy"][:, i, :]).sum(axis=1)
        p = (p_slip + (res["mz"][:, i, :].sum(axis=1)) * d["r"] - (res["m_rr"][:, i, :] * sgn * om).sum(axis=1)
             - d["drag"] * d["vx"])
        t = res.t
        de = e[-1] - e[0]
        integ = np.trapezoid(p, t) if hasattr(np, "trapezoid") else np.trapz(p, t)
        rel = abs(de - integ) / abs(de)
        print(f"\n# energy: dE = {de:.2f} J, integral of power {integ:.2f} J, rel. diff {rel:.1e}")
        self.assertLess(de, 0.0)
        self.assertLess(rel, 1e-6)     # measured 8.8e-9 (trapezoid rule on the 2 ms record)


class StepHalvingTest(unittest.TestCase):
    def test_rk4_converges_at_fourth_order(self):
        v = vehicles.passenger()
        sc = M.sine_dwell(v, [60.0], t0=0.2)
        sc.duration = 0.8       # up to the first steering peak: smooth inputs after the start
        runs = {h: model.simulate(v, sc, h=h, record_every=int(round(4e-3 / h))) for h in (4e-3, 2e-3, 1e-3)}
        e1 = np.abs(runs[4e-3]["r"] - runs[2e-3]["r"]).max()
        e2 = np.abs(runs[2e-3]["r"] - runs[1e-3]["r"]).max()
        w1 = np.abs(runs[4e-3]["omega"] - runs[2e-3]["omega"]).max()
        w2 = np.abs(runs[2e-3]["omega"] - runs[1e-3]["omega"]).max()
        print(f"\n# step halving: yaw rate |r(4ms)-r(2ms)| = {e1:.2e}, |r(2ms)-r(1ms)| = {e2:.2e} rad/s "
              f"(ratio {e1 / e2:.1f}); wheel speed ratio {w1 / w2:.1f}")
        self.assertGreater(e1 / e2, 12.0)     # 4th order: 16; measured 17.7
        self.assertGreater(w1 / w2, 12.0)     # measured 17.9
        self.assertLess(e2, 1e-7)             # measured 1.3e-9 rad/s


class SineWithDwellTest(unittest.TestCase):
    def test_fmvss126_stable_car(self):
        v = vehicles.passenger()
        a03 = M.swa_at_03g(v, h=H)
        # measured 20.5 deg; the linear bicycle estimate is 16.9 deg (ramp lag + tyre nonlinearity)
        self.assertTrue(12.0 < a03 < 35.0, a03)
        scales = np.array([3.0, 5.0])
        sc = M.sine_dwell(v, scales * a03, settle=1.8)
        res = model.simulate(v, sc, h=H)
        for i, s in enumerate(scales):
            m = M.fmvss126_metrics(res, i)
            print(f"\n# sine-dwell {s:.1f} x {a03:.1f} deg: r_peak {m['r_peak'] / DEG:.1f} deg/s, "
                  f"ratio 1.00 s {m['ratio_1s']:.3f}, 1.75 s {m['ratio_175']:.3f}, "
                  f"lateral displacement {m['lat_disp_107']:.2f} m")
            self.assertLess(m["r_peak"], 0.0)                # dwell steers right -> clockwise peak
            self.assertLess(abs(m["ratio_1s"]), 0.35)        # FMVSS 126 S5.2.1
            self.assertLess(abs(m["ratio_175"]), 0.20)       # S5.2.2
            t = res.t
            late = t > sc.meta["t_cos"] + 1.0
            self.assertLess(np.abs(res["r"][late, i]).max(), 0.35 * abs(m["r_peak"]))
        self.assertGreaterEqual(M.fmvss126_metrics(res, 1)["lat_disp_107"], 1.83)   # S5.3, 5 x


class CommandLineTest(unittest.TestCase):
    def test_values_it_cannot_run_with_are_refused(self):
        import contextlib
        import io
        from grip_tools.sim import cli
        for args, said in ((["-s", "ice"], "--surface: 'ice'"), (["-s", "nan"], "--surface: 'nan'"),
                           (["--speed", "-5"], "--speed: -5.0"), (["--dt", "0"], "--dt: 0.0"),
                           (["--duration", "inf"], "--duration: inf"), (["--bank", "90"], "--bank: 90.0")):
            err = io.StringIO()
            with tempfile.TemporaryDirectory() as d, contextlib.redirect_stderr(err):
                out = os.path.join(d, "out")
                with self.assertRaises(SystemExit) as cm:
                    cli.main(["-m", "step-steer", "-o", out, "--no-plot"] + args)
                self.assertFalse(os.path.exists(out), args)
            self.assertEqual(cm.exception.code, 2, args)
            self.assertIn(said, err.getvalue(), args)

    def test_simulate_writes_truth_sensors_can_and_plot(self):
        out = tempfile.mkdtemp()
        env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "tools"))
        p = subprocess.run([sys.executable, "-m", "grip_tools", "simulate", "--manoeuvre", "step-steer",
                            "--surface", "wet", "--duration", "0.4", "--dt", "0.002", "--out", out],
                           capture_output=True, text=True, env=env, cwd=ROOT, timeout=120)
        self.assertEqual(p.returncode, 0, p.stderr)
        for f in ("truth.csv", "sensors.csv", "can.log", "overview.png", "summary.json"):
            self.assertTrue(os.path.getsize(os.path.join(out, f)) > 0, f)
        truth = model.read_csv(os.path.join(out, "truth.csv"))
        for col in ("time", "beta", "r", "ay", "ax", "kappa_fl", "alpha_rr", "fz_fr", "fx_rl", "fy_fl",
                    "mz_rr", "mu_road_fl", "muy_fl"):
            self.assertIn(col, truth)
        self.assertTrue(np.allclose(truth["mu_road_fl"], 0.6))
        with open(os.path.join(out, "can.log")) as f:
            first = f.readline()
        self.assertRegex(first, r"^\(\d{10}\.\d{6}\) can0 [0-9A-F]{3}#([0-9A-F]{2})+$")
        dec, stats = canlog.decode_log(os.path.join(out, "can.log"))
        self.assertEqual(stats["checksum_errors"], 0)
        self.assertEqual(stats["unknown"], 0)
        self.assertIn("ESC_WheelSpeeds", dec)


if __name__ == "__main__":
    unittest.main()
