"""Tests of the 1989-style lateral Magic Formula reference (grip_tools.reference.mf89):
the equations' defining properties, the constraint checker on valid and
invalid coefficient sets, the fitter-facing constraint object, and a
constrained fit that recovers a known set from noisy synthetic data."""
import os
import tempfile
import unittest

import numpy as np

from grip_tools.golden import mf89 as golden_mf89
from grip_tools.reference import mf89

P = mf89.DEFAULT_PARAMS
DEG = np.pi / 180.0


class EquationTests(unittest.TestCase):
    def test_factors_by_hand(self):
        # Fz = 6 kN, gamma = 0: evaluate (3.4)-(3.9) by hand
        f = mf89.factors(P, 0.0, 6.0, 0.0)
        self.assertAlmostEqual(float(f["C"]), P[0])
        self.assertAlmostEqual(float(f["D"]), P[1] * 36.0 + P[2] * 6.0)
        self.assertAlmostEqual(float(f["BCD"]), P[3] * np.sin(2.0 * np.arctan(6.0 / P[4])))
        self.assertAlmostEqual(float(f["E"]), P[6] * 6.0 + P[7])
        self.assertAlmostEqual(float(f["B"]), float(f["BCD"] / (f["C"] * f["D"])))
        self.assertEqual(float(f["Sh"]), 0.0)
        self.assertEqual(float(f["Sv"]), 0.0)
        # with camber: the camber terms of D, BCD, Sh, Sv
        g = 4.0
        f = mf89.factors(P, 1.0, 6.0, g)
        self.assertAlmostEqual(float(f["D"]), (P[1] * 36.0 + P[2] * 6.0) * (1.0 - P[15] * g * g))
        self.assertAlmostEqual(float(f["BCD"]), P[3] * np.sin(2.0 * np.arctan(6.0 / P[4])) * (1.0 - P[5] * g))
        self.assertAlmostEqual(float(f["Sh"]), P[10] * g * 6.0)
        self.assertAlmostEqual(float(f["Sv"]), (P[13] * 36.0 + P[14] * 6.0) * g)
        self.assertAlmostEqual(float(f["E"]), (P[6] * 6.0 + P[7]) * (1.0 - P[16] * g))

    def test_si_wrapper_matches_seed_units(self):
        a = np.linspace(-20, 20, 41)
        np.testing.assert_allclose(mf89.fy89(P, a * DEG, 4600.0, 3.0 * DEG),
                                   mf89.fy89_seed_units(P, a, 4.6, 3.0), rtol=1e-12, atol=1e-9)

    def test_slope_at_origin_is_bcd(self):
        for fz in (2.0, 4.6, 9.0):
            h = 1e-6
            slope = (mf89.fy89_seed_units(P, h, fz, 0.0) - mf89.fy89_seed_units(P, -h, fz, 0.0)) / (2 * h)
            self.assertAlmostEqual(float(slope) / float(mf89.factors(P, 0, fz, 0)["BCD"]), 1.0, places=6)

    def test_peak_is_d(self):
        a = np.linspace(0.0, 40.0, 40001)
        for fz in (3.0, 6.0, 9.0):
            d = float(mf89.factors(P, 0, fz, 0)["D"])
            self.assertAlmostEqual(float(np.max(mf89.fy89_seed_units(P, a, fz, 0.0))) / d, 1.0, places=6)

    def test_antisymmetric_at_zero_camber(self):
        a = np.linspace(0.0, 25.0, 51)
        for fz in (1.0, 5.0, 10.0):
            np.testing.assert_allclose(mf89.fy89_seed_units(P, a, fz, 0.0),
                                       -mf89.fy89_seed_units(P, -a, fz, 0.0), atol=1e-9)

    def test_camber_shifts(self):
        # at alpha = -Sh the sine term vanishes and Fy = Sv
        fz, g = 5.0, 4.0
        f = mf89.factors(P, 0.0, fz, g)
        self.assertAlmostEqual(float(mf89.fy89_seed_units(P, -f["Sh"], fz, g)), float(f["Sv"]), places=9)
        # camber thrust: positive camber pushes Fy up at alpha = 0 (a10, a14 > 0)
        self.assertGreater(float(mf89.fy89_seed_units(P, 0.0, fz, g)), 100.0)

    def test_zero_load_zero_force(self):
        self.assertEqual(float(mf89.fy89(P, 0.2, 0.0, 0.1)), 0.0)
        self.assertTrue(np.all(np.isfinite(mf89.fy89(P, np.linspace(-1, 1, 11), 0.0, 0.1))))


class ConstraintCheckerTests(unittest.TestCase):
    EXPECTED = {  # label of golden_mf89's sets -> equations that must fail
        "valid": set(), "C_high": {"3.10"}, "C_low": {"3.10"}, "E_ge_1": {"3.11"},
        "E_camber": {"3.11"}, "a17": {"3.12"}, "Sh0": {"3.13"}, "Sv0": {"3.13"},
        "Sh_camber": {"3.14"}, "Sv_camber": {"3.15"}, "Sv_camber_hi": {"3.15"},
        "a15_neg": {"3.16"}, "two": {"3.10", "3.16"},
    }

    def test_default_set_satisfies_all(self):
        res = mf89.check_constraints(P)
        self.assertEqual(len(res), 7)
        self.assertTrue(all(r.ok for r in res), mf89.constraints_report(P))
        self.assertTrue(mf89.constraints_ok(P))

    def test_each_violation_is_reported(self):
        sets = dict(golden_mf89._mf89_constraint_sets(P))
        self.assertEqual(set(sets), set(self.EXPECTED))
        for label, q in sets.items():
            failed = {r.eq for r in mf89.check_constraints(q) if not r.ok}
            self.assertEqual(failed, self.EXPECTED[label], label)
            self.assertEqual(mf89.constraints_ok(q), not self.EXPECTED[label])
            if self.EXPECTED[label]:
                self.assertIn("FAIL", mf89.constraints_report(q))

    def test_boundaries(self):
        q = P.copy()
        q[0] = 1.0                         # 3.10 is strict
        self.assertFalse(mf89.constraints_ok(q))
        q[0] = 1.0001
        self.assertTrue(mf89.constraints_ok(q))
        q = P.copy()
        q[10] = 0.1 / 10.0                 # 3.14 allows equality at the largest load
        self.assertTrue(mf89.constraints_ok(q))
        q[10] = 0.1 / 10.0 * 1.001
        self.assertFalse(mf89.constraints_ok(q))
        # the load range matters: a10 = 0.02 is fine up to 5 kN
        q[10] = 0.02
        self.assertTrue(mf89.constraints_ok(q, fz_range_kn=(1.0, 5.0)))
        self.assertFalse(mf89.constraints_ok(q, fz_range_kn=(1.0, 9.0)))

    def test_bad_shapes_raise(self):
        with self.assertRaises(ValueError):
            mf89.check_constraints(P[:17])
        with self.assertRaises(ValueError):
            mf89.constraints(fz_range_kn=(0.0, 5.0))


class ConstraintObjectTests(unittest.TestCase):
    def test_default_inside_bounds_and_margins(self):
        c = mf89.constraints()
        self.assertTrue(np.all(P >= c.lower) and np.all(P <= c.upper))
        self.assertTrue(np.all(c.margins(P) > 0))
        self.assertEqual(set(c.fixed), {8, 9, 11, 12, 17})
        lb, ub = c.free_bounds()
        self.assertEqual(len(lb), 13)
        self.assertTrue(np.all(lb < ub))
        np.testing.assert_array_equal(c.expand(P[c.free_index()]), P)

    def test_violations_show_in_margins_or_bounds(self):
        c = mf89.constraints()
        for label, q in golden_mf89._mf89_constraint_sets(P):
            outside = (np.any(q < c.lower) or np.any(q > c.upper) or np.any(c.margins(q) <= 0)
                       or any(q[i] != v for i, v in c.fixed.items()))
            self.assertEqual(outside, not mf89.constraints_ok(q), label)


class ConstrainedFitTests(unittest.TestCase):
    def test_fit_recovers_curves_within_constraints(self):
        from scipy.optimize import least_squares
        rng = np.random.default_rng(3)
        n = 3000
        a = rng.uniform(-15, 15, n)
        fz = rng.choice([3.0, 6.0, 9.0], n)
        g = rng.choice([-4.0, 0.0, 4.0], n)
        sigma = 20.0
        y = mf89.fy89_seed_units(P, a, fz, g) + rng.normal(0, sigma, n)
        c = mf89.constraints(fz_range_kn=(3.0, 9.0), gamma_max_deg=4.0)
        idx = c.free_index()
        lb, ub = c.free_bounds()
        x0 = np.clip(P[idx] * rng.uniform(0.8, 1.2, len(idx)), lb + 1e-6, ub - 1e-6)
        x0[idx.tolist().index(13)] = 0.0      # start the small camber terms at zero
        scale = np.maximum(np.abs(P[idx]), 1e-3)

        def resid(x):
            p = c.expand(x)
            pen = np.minimum(c.margins(p), 0.0) * 1e3
            return np.concatenate([(mf89.fy89_seed_units(p, a, fz, g) - y) / sigma, pen])

        r = least_squares(resid, x0, bounds=(lb, ub), x_scale=scale, method="trf")
        pf = c.expand(r.x)
        self.assertTrue(mf89.constraints_ok(pf, fz_range_kn=(3.0, 9.0), gamma_max_deg=4.0),
                        mf89.constraints_report(pf, fz_range_kn=(3.0, 9.0), gamma_max_deg=4.0))
        at = np.linspace(-15, 15, 301)
        worst = 0.0
        for f in (3.0, 6.0, 9.0):
            for gg in (-4.0, 0.0, 4.0):
                worst = max(worst, float(np.max(np.abs(mf89.fy89_seed_units(pf, at, f, gg)
                                                       - mf89.fy89_seed_units(P, at, f, gg)))))
        resid_rms = float(np.sqrt(np.mean(r.fun[:n] ** 2))) * sigma
        print(f"\n    constrained fit: residual rms {resid_rms:.2f} N (noise {sigma} N), "
              f"max curve error {worst:.2f} N")
        # the fit explains the data down to the noise and the curves match the truth
        self.assertLess(resid_rms, 1.05 * sigma)
        self.assertLess(worst, 1.0 * sigma)


class GoldenFileTests(unittest.TestCase):
    def test_write_golden(self):
        with tempfile.TemporaryDirectory() as d:
            golden_mf89.write_golden(d)
            rows = {}
            with open(os.path.join(d, "mf89.txt")) as f:
                for line in f:
                    if not line.startswith("#"):
                        rows.setdefault(line.split()[0], []).append(line.split())
            self.assertEqual(len(rows["P"]), 1)
            self.assertEqual(len(rows["P"][0]), 22)
            self.assertGreater(len(rows["V"]), 10000)
            v = np.array([[float(x) for x in r[1:]] for r in rows["V"]])
            # inputs on the fixed-point grids, values from the reference
            np.testing.assert_array_equal(v[:, 0] * 65536.0, np.round(v[:, 0] * 65536.0))
            np.testing.assert_array_equal(v[:, 1] * 256.0, np.round(v[:, 1] * 256.0))
            np.testing.assert_allclose(v[:, 3], mf89.fy89(P, v[:, 0], v[:, 1], v[:, 2]), rtol=0, atol=1e-9)
            self.assertLessEqual(np.max(np.abs(v[:, 0])), mf89.DEFAULT_LIMITS["alpha_max_deg"] * DEG)
            self.assertTrue(os.path.exists(os.path.join(d, "mf_thermal.txt")))


if __name__ == "__main__":
    unittest.main()
