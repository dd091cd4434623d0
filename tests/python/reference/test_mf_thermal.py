"""Tests of the temperature-dependent Magic Formula reference
(grip_tools.reference.mf_thermal): temperature scaling of D and K, reduction of the
combined model to pure slip, load scaling, the exact time step, the
discretization error against the continuous ODE, and identification of
kappa, W, a and b from synthetic noisy data with known values."""
import unittest

import numpy as np

from grip_tools.golden import mf89 as golden_mf89
from grip_tools.reference import mf_thermal as m

P = m.DEFAULT


class ForceModelTests(unittest.TestCase):
    def test_combined_reduces_to_pure(self):
        a = np.linspace(-0.3, 0.3, 61)
        s = np.linspace(-0.5, 1.0, 61)
        for t in (0.0, 30.0, 90.0):
            fy0 = m.pure_force(P.dy0, P.ky0, P.cy, P.ey, P.shy, P.svy, P.ay, P.by, a, t, P.t0)
            fx0 = m.pure_force(P.dx0, P.kx0, P.cx, P.ex, P.shx, P.svx, P.ax, P.bx, s, t, P.t0)
            _, fy = m.forces(P, a, 0.0, P.fz0, t)            # S = 0: G_yS = 1
            fx, _ = m.forces(P, 0.0, s, P.fz0, t)            # alpha = 0: G_xa = 1
            np.testing.assert_allclose(fy, fy0 + P.svys, rtol=1e-12, atol=1e-9)
            np.testing.assert_allclose(fx, fx0, rtol=1e-12, atol=1e-9)

    def test_combined_slip_reduces_forces(self):
        fx_pure, _ = m.forces(P, 0.0, 0.1, P.fz0, 30.0)
        fx_comb, _ = m.forces(P, 0.1, 0.1, P.fz0, 30.0)
        _, fy_pure = m.forces(P, 0.1, 0.0, P.fz0, 30.0)
        _, fy_comb = m.forces(P, 0.1, 0.1, P.fz0, 30.0)
        self.assertLess(abs(fx_comb), abs(fx_pure))
        self.assertLess(abs(fy_comb), abs(fy_pure))
        self.assertGreater(fx_comb, 0.0)

    def test_peak_and_stiffness_follow_temperature(self):
        # (4.13): peak D(T); (4.14): slope at the shifted origin K(T)
        a = np.linspace(-0.6, 0.6, 120001)
        for t in (0.0, 30.0, 60.0, 110.0):
            fy0 = m.pure_force(P.dy0, P.ky0, P.cy, P.ey, P.shy, 0.0, P.ay, P.by, a, t, P.t0)
            self.assertAlmostEqual(np.max(fy0) / (P.dy0 * (1 + P.ay * (t - P.t0))), 1.0, places=6)
            h = 1e-7
            k = (m.pure_force(P.dy0, P.ky0, P.cy, P.ey, P.shy, 0.0, P.ay, P.by, -P.shy + h, t, P.t0)
                 - m.pure_force(P.dy0, P.ky0, P.cy, P.ey, P.shy, 0.0, P.ay, P.by, -P.shy - h, t, P.t0)) / (2 * h)
            self.assertAlmostEqual(k / (P.ky0 * (1 + P.by * (t - P.t0))), 1.0, places=5)

    def test_forces_scale_with_load(self):
        fx1, fy1 = m.forces(P, 0.07, 0.05, 2300.0, 40.0)
        fx2, fy2 = m.forces(P, 0.07, 0.05, 6900.0, 40.0)
        self.assertAlmostEqual(fx2 / fx1, 3.0, places=12)
        self.assertAlmostEqual(fy2 / fy1, 3.0, places=12)
        self.assertEqual(m.forces(P, 0.07, 0.05, 0.0, 40.0), (0.0, 0.0))

    def test_slip_speed_matches_seed_form(self):
        # (4.5) with re*omega = V cos(alpha) (1 - S)
        v, a, s = 20.0, 0.1, 0.08
        re_omega = v * np.cos(a) * (1 - s)
        want = np.sqrt((v * np.cos(a) - re_omega) ** 2 + v ** 2 * np.sin(a) ** 2)
        self.assertAlmostEqual(float(m.slip_speed(v, a, s)), want, places=12)


class TimeStepTests(unittest.TestCase):
    def test_cooling_exact_for_any_step(self):
        for dt in (0.01, 0.5, 5.0):
            n = int(round(30.0 / dt))
            out = m.simulate(P, 90.0, 0.0, 0.05, 0.1, 4600.0, 20.0, np.full(n, dt))
            tt = dt * np.arange(1, n + 1)
            np.testing.assert_allclose(out["t_after"], 20.0 + 70.0 * np.exp(-P.kappa * tt), rtol=0, atol=1e-10)
            self.assertTrue(np.all(out["q"] == 0.0))

    def test_kappa_zero_is_pure_heating(self):
        prm = m.with_params(kappa=0.0)
        fx, fy, q, vs, t1 = m.step(prm, 30.0, 20.0, 0.05, 0.02, 4600.0, 10.0, 0.1)
        self.assertAlmostEqual(t1, 30.0 + q / prm.w * 0.1, places=12)
        self.assertAlmostEqual(q, np.hypot(fx, fy) * vs, places=9)

    def test_large_step_stable(self):
        # exact for constant q; with q(T) lagged by one step a large step
        # overshoots by up to about |dq/dT| / (kappa W) of the rise
        for kappa in (0.08, 2.0, 5.0):
            prm = m.with_params(kappa=kappa)
            out = m.simulate(prm, 25.0, 20.0, 0.05, 0.05, 4600.0, 25.0, np.full(200, 10.0))
            t_eq = 25.0 + out["q"][-1] / (prm.kappa * prm.w)
            self.assertAlmostEqual(out["t_after"][-1], t_eq, places=6)
            h = 1e-3
            dq = abs(m.heat_flux(prm, 20.0, 0.05, 0.05, 4600.0, t_eq + h)[0]
                     - m.heat_flux(prm, 20.0, 0.05, 0.05, 4600.0, t_eq - h)[0]) / (2 * h)
            overshoot = np.max(out["t_after"]) - t_eq
            self.assertLessEqual(overshoot, 1.2 * dq / (kappa * prm.w) * (t_eq - 25.0) + 1e-9)
        self.assertTrue(np.all(out["t_after"] > 25.0))

    def test_temperature_limited(self):
        out = m.simulate(P, 120.0, 50.0, 0.45, 1.0, 9000.0, 45.0, np.full(200, 0.01))
        self.assertEqual(np.max(out["t_after"]), P.t_max)

    def test_discretization_error_vs_continuous_ode(self):
        # the scheme lags the forces by one step: first order in dt; measured on
        # the golden scenarios that stay inside the temperature limits
        for name, t0, d in golden_mf89.thermal_scenarios():
            if name == "extreme":
                continue
            sim = m.simulate(P, t0, d["v"], d["alpha"], d["slip"], d["fz"], d["t_road"], d["dt"])
            time = np.concatenate([[0.0], np.cumsum(d["dt"])])
            ext = {k: np.append(d[k], d[k][-1]) for k in ("v", "alpha", "slip", "fz", "t_road")}
            tc = m.simulate_continuous(P, t0, time, ext["v"], ext["alpha"], ext["slip"], ext["fz"], ext["t_road"])
            err = float(np.max(np.abs(sim["t_after"] - tc[1:])))
            rise = float(np.max(sim["t_after"]) - t0)
            print(f"\n    {name}: max |T_step - T_ode| = {err:.4f} K (rise {rise:.1f} K)")
            self.assertLess(err, 0.005 * abs(rise) + 0.01)


class IdentificationTests(unittest.TestCase):
    def test_identify_kappa_w_from_noisy_trace(self):
        # heating pulses (slip-angle steps as in the seed's Fig. 4.6), then cooling
        rng = np.random.default_rng(11)
        dt = 0.1
        t = np.arange(0.0, 120.0, dt)
        q = (np.where((t > 5) & (t < 10), 8000.0, 0.0) + np.where((t > 40) & (t < 43), 12000.0, 0.0)
             + np.where((t > 75) & (t < 85), 5000.0, 0.0))
        kappa, w = 0.08, 1500.0
        temp = m._trajectory(kappa, w, 30.0, t, q, np.full_like(t, 25.0))
        temp_meas = temp + rng.normal(0.0, 0.2, t.size)          # 0.2 K sensor noise
        q_meas = q * (1.0 + rng.normal(0.0, 0.03, t.size))       # 3 % force/speed noise
        r = m.identify_kappa_w(t, temp_meas, q_meas, 25.0)
        print(f"\n    kappa {r['kappa']:.5f} (true {kappa}), W {r['w']:.1f} (true {w}), "
              f"start {r['start'][0]:.4f}/{r['start'][1]:.0f}, rms {r['rms']:.3f} K")
        self.assertLess(abs(r["kappa"] / kappa - 1.0), 0.02)
        self.assertLess(abs(r["w"] / w - 1.0), 0.02)
        self.assertLess(r["rms"], 0.25)

    def _force_data(self, rng, direction, sigma):
        temps = np.array([20.0, 30.0, 40.0, 50.0, 60.0])
        if direction == "x":
            p = np.linspace(-0.3, 0.6, 61)
            coef = (P.dx0, P.kx0, P.cx, P.ex, P.shx, P.svx, P.ax, P.bx)
        else:
            p = np.linspace(-0.3, 0.3, 61)
            coef = (P.dy0, P.ky0, P.cy, P.ey, P.shy, P.svy, P.ay, P.by)
        pp, tt = np.meshgrid(p, temps)
        pp, tt = pp.ravel(), tt.ravel()
        f = m.pure_force(*coef, pp, tt, P.t0) + rng.normal(0.0, sigma, pp.size)
        return pp, tt, f, coef

    def test_identify_a_b_from_force_data(self):
        rng = np.random.default_rng(5)
        for direction in ("x", "y"):
            pp, tt, f, (d0, k0, c, e, sh, sv, a, b) = self._force_data(rng, direction, 40.0)
            r = m.identify_temperature_coefficients(pp, tt, f, P.t0, c, e, sh, sv)
            print(f"\n    {direction}: a {r['a']:.5f} (true {a}), b {r['b']:.5f} (true {b}), "
                  f"D0 {r['d0']:.0f} ({d0}), K0 {r['k0']:.0f} ({k0}), rms {r['rms']:.1f} N")
            self.assertLess(abs(r["a"] - a), 0.1 * abs(a))
            self.assertLess(abs(r["b"] - b), 0.1 * abs(b))
            self.assertLess(abs(r["d0"] / d0 - 1.0), 0.01)
            self.assertLess(abs(r["k0"] / k0 - 1.0), 0.02)

    def test_identify_with_shape(self):
        rng = np.random.default_rng(6)
        pp, tt, f, (d0, k0, c, e, sh, sv, a, b) = self._force_data(rng, "x", 40.0)
        r = m.identify_temperature_coefficients(pp, tt, f, P.t0, 1.5, 0.0, sh, sv, fit_shape=True)
        self.assertLess(abs(r["a"] - a), 0.1 * abs(a))
        self.assertLess(abs(r["b"] - b), 0.1 * abs(b))
        self.assertLess(abs(r["c"] - c), 0.05)


class GoldenFileTests(unittest.TestCase):
    def test_param_row_matches_struct_order(self):
        # the C test maps the P row by this order (include/grip/grip_mf_thermal.h)
        self.assertEqual(len(m.PARAM_ORDER), 35)
        self.assertEqual(m.PARAM_ORDER[:2], ["fz0", "t0"])
        self.assertEqual(m.PARAM_ORDER[-6:], ["fz_max", "alpha_max", "slip_max", "v_max", "t_min", "t_max"])

    def test_scenarios_inside_valid_range(self):
        for name, t0, d in golden_mf89.thermal_scenarios():
            self.assertTrue(np.all(np.abs(d["alpha"]) <= P.alpha_max), name)
            self.assertTrue(np.all(np.abs(d["slip"]) <= P.slip_max), name)
            self.assertTrue(np.all((d["fz"] >= 0) & (d["fz"] <= P.fz_max)), name)
            self.assertTrue(np.all((d["v"] >= 0) & (d["v"] <= P.v_max)), name)
            self.assertTrue(P.t_min <= t0 <= P.t_max)


if __name__ == "__main__":
    unittest.main()
