"""The brush-model family (tools/grip_tools/reference/brush.py):

* the closed forms the C library implements equal the full-precision
  quadrature reference to 1e-9 (of mu_s Fz, mu_s Fz l) for every supported
  pressure exponent n, with every coupling active;
* the pressure-integral closed forms equal direct quadrature;
* the fixed iteration count of the C library converges over the valid range
  (measured worst case printed), and the adhesion-boundary residual has one
  sign change;
* the committed inverse table (lib/brush/brush_table.h) matches its generator;
* parameter files round-trip and bad files are rejected with the line.
"""
import math
import os
import tempfile
import unittest

import numpy as np
from scipy import integrate

from grip_tools.reference import brush as B
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
TOL_PROOF = 1e-9


def _norm_err(a, b, f0, l):
    return max(abs(a["fx"] - b["fx"]) / f0, abs(a["fy"] - b["fy"]) / f0, abs(a["mz"] - b["mz"]) / (f0 * l))


class PressureIntegralTest(unittest.TestCase):
    def test_integral_carries_the_load(self):
        for n in range(B.N_MIN, B.N_MAX + 1):
            for q in (-0.5, 0.0, 0.3):
                i00, i01, *_ = B.pint(0.0, n)
                self.assertAlmostEqual(i00 + q * i01, n / (n + 1.0), places=14)
                num = integrate.quad(lambda x: float(B.dgsp(x, n, q)), 0.0, 1.0, points=[0.5], epsabs=1e-14)[0]
                self.assertAlmostEqual(num, n / (n + 1.0), places=12)

    def test_closed_forms_equal_quadrature(self):
        worst = 0.0
        for n in range(B.N_MIN, B.N_MAX + 1):
            for rh in (0.0, 0.07, 0.31, 0.5, 0.62, 0.93, 0.9995):
                i00, i01, i10, i11, it0, it1 = B.pint(rh, n)
                for q in (-0.6, 0.0, 0.45):
                    d = lambda x: float(B.dgsp(x, n, q))
                    opt = dict(points=[0.5] if rh < 0.5 else None, epsabs=1e-15, epsrel=1e-13, limit=200)
                    ref0 = integrate.quad(d, rh, 1.0, **opt)[0]
                    ref1 = integrate.quad(lambda x: d(x) * x, rh, 1.0, **opt)[0]
                    worst = max(worst, abs(i00 + q * i01 - ref0), abs(i10 + q * i11 - ref1))
                    if 1.0 - rh >= B.IT_EPS:
                        reft = integrate.quad(lambda x: d(x) * (1.0 - x) / (1.0 - rh), rh, 1.0, **opt)[0]
                        worst = max(worst, abs(it0 + q * it1 - reft))
                lm = B.lmax(rh, n, 0.25) if rh > 0 else None
                if lm is not None:
                    self.assertAlmostEqual(lm, (n + 1.0) / n * float(B.dgsp(rh, n, 0.25)) / (2.0 * rh), places=12)
        print(f"# pressure integrals, closed form vs quad: max |err| = {worst:.2e}")
        self.assertLess(worst, 1e-12)


class ProofAgainstQuadratureTest(unittest.TestCase):
    """The closed forms (exact root) vs the independent quadrature reference."""

    def test_neofiala_every_n(self):
        rng = np.random.default_rng(404)
        rows = []
        for n in range(B.N_MIN, B.N_MAX + 1):
            worst = 0.0
            cases = 0
            for i in range(6):
                p = B.random_neofiala(rng, n, couplings=(i != 0))
                kappa, alpha, gamma, fz, vx = B.random_inputs(rng, p)
                if i == 1:
                    kappa, alpha = -0.03, 0.04         # combined, partial adhesion
                if i == 2:
                    kappa, alpha = 0.02, -0.02
                a = B.neofiala_cf(p, kappa, alpha, gamma, fz, vx)
                b = B.neofiala_ref(p, kappa, alpha, gamma, fz, vx)
                self.assertLess(b["resid"], 1e-12)
                f0 = p.mu_s * min(max(fz, p.fz_min), p.fz_max)
                worst = max(worst, _norm_err(a, b, f0, p.l))
                cases += 1
            rows.append((n, cases, worst))
            self.assertLess(worst, TOL_PROOF, f"n = {n}")
        for n, c, w in rows:
            print(f"# neofiala n={n}: {c} cases, closed form vs quadrature max |err| = {w:.2e} (mu Fz)")

    def test_brush_every_n(self):
        worst = 0.0
        for n in range(B.N_MIN, B.N_MAX + 1):
            p = B.Brush(n=n, a_v=0.008)
            for kappa in (-1.0, -0.2, -0.04, -0.01, 0.0, 0.005, 0.03, 0.3):
                a = B.brush_cf(p, kappa, 3500.0, 25.0)
                b = B.brush_ref(p, kappa, 3500.0, 25.0)
                worst = max(worst, abs(a["fx"] - b["fx"]) / (p.mu_s * 3500.0))
        print(f"# brush n=2..{B.N_MAX}: closed form vs quadrature max |err| = {worst:.2e} (mu Fz)")
        self.assertLess(worst, TOL_PROOF)

    def test_fiala_and_sakai(self):
        pf = B.Fiala()
        wf = max(_norm_err(B.fiala_cf(pf, a, 4000.0), B.fiala_ref(pf, a, 4000.0), 4000.0, pf.l)
                 for a in np.linspace(-0.5, 0.5, 41))
        ps = B.Sakai()
        ws = 0.0
        for kappa in (-1.0, -0.3, -0.03, -0.005, 0.0, 0.01, 0.1, 0.8):
            for alpha in (-0.2, -0.01, 0.0, 0.004, 0.05, 0.3):
                ws = max(ws, _norm_err(B.sakai_cf(ps, kappa, alpha, 4000.0), B.sakai_ref(ps, kappa, alpha, 4000.0),
                                       ps.mu_s * 4000.0, ps.l))
        print(f"# fiala: max |err| = {wf:.2e}; sakai (Table 2.1): max |err| = {ws:.2e}")
        self.assertLess(wf, TOL_PROOF)
        self.assertLess(ws, TOL_PROOF)

    def test_fiala_seed_polynomials(self):
        """(2.65)-(2.66) and the seed's stated extremes: full sliding at
        phi = 3, Mz maximum 27/512 at phi = 3/4."""
        p = B.Fiala(ky=40000.0, mu=1.0)
        fz = 4000.0
        phi = lambda a: p.ky * math.tan(a) / (p.mu * fz)
        a34 = math.atan(0.75 * p.mu * fz / p.ky)
        r = B.fiala_cf(p, a34, fz)
        self.assertAlmostEqual(r["mz"] / (p.mu * fz * p.l), 27.0 / 512.0, places=12)
        a3 = math.atan(3.0 * p.mu * fz / p.ky)
        self.assertAlmostEqual(-B.fiala_cf(p, a3, fz)["fy"], p.mu * fz, places=9)
        for a in (0.01, 0.05, 0.2):
            f = phi(a)
            if f < 3:
                self.assertAlmostEqual(-B.fiala_cf(p, a, fz)["fy"] / (p.mu * fz), f - f * f / 3 + f ** 3 / 27, places=12)


class IterationTest(unittest.TestCase):
    """The C library's fixed iteration (GRIP_BRUSH_ROOT_ITERS Anderson-Bjorck
    steps + secant interpolation) against the exact root, random valid sets."""

    def test_fixed_count_converges(self):
        rng = np.random.default_rng(99)
        worst = 0.0
        multi = 0
        min_slope = 9.0
        for i in range(1500):
            p = B.random_neofiala(rng, couplings=(i % 3 != 0))
            x = B.random_inputs(rng, p)
            kappa, alpha, gamma, fz, vx, _ = B._clamp_inputs(p, *x)
            K = B.kinematics(p, kappa, alpha, gamma, fz, vx)
            ex = B.nf_solve(K, "exact")
            fx = B.nf_solve(K, "fixed", B.ROOT_ITERS)
            worst = max(worst, abs(fx["fx"] - ex["fx"]), abs(fx["fy"] - ex["fy"]), abs(fx["mz"] - ex["mz"]))
            min_slope = min(min_slope, ex["slope"])
            self.assertLess(abs(ex["q"]), B.Q_MAX)
            if i % 15 == 0:
                r = [B.nf_state(t, K)[0] for t in np.linspace(0.0, 1.0, 101)]
                multi += int(np.sum(np.diff(np.sign(r)) != 0) > 1)
        print(f"# fixed iteration ({B.ROOT_ITERS} steps): max |err| = {worst:.2e} mu Fz over 1500 cases; "
              f"min slope of the Mz equation at the root {min_slope:.3f} (clamp {B.M_BMIN})")
        self.assertLess(worst, 1e-4)           # the float budget
        self.assertEqual(multi, 0)
        self.assertGreater(min_slope, 4 * B.M_BMIN)

    def test_brush_boundary(self):
        worst = 0.0
        for n in range(B.N_MIN, B.N_MAX + 1):
            for sx in np.geomspace(1e-4, n + 0.999, 60):
                K = B.brush_problem(n, sx)
                worst = max(worst, abs(B.nf_solve(K, "fixed")["rh"] - B.nf_solve(K, "exact")["rh"]))
        self.assertLess(worst, 1e-9)


class TableTest(unittest.TestCase):
    def test_committed_table_matches_generator(self):
        with open(os.path.join(ROOT, "lib", "brush", "brush_table.h")) as f:
            self.assertEqual(f.read(), B.render_table_header(),
                             "lib/brush/brush_table.h is stale: run grip brush-verify --write-table")


class ParamFileTest(unittest.TestCase):
    def test_round_trip_every_model(self):
        for model, cls in B.MODELS.items():
            p = cls()
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "p.txt")
                B.write_params(path, model, p, comment="test")
                m2, p2 = B.read_params(path)
            self.assertEqual(m2, model)
            self.assertEqual(p2, p)

    def test_bad_files(self):
        cases = [
            ("ky = 1\n", "model"),
            ("model = fiala\nky = abc\n", ":2: ky"),
            ("model = fiala\nzz = 1\n", ":2: zz: unknown key"),
            ("model = fiala\nky = 1\nky = 2\n", "given twice"),
            ("model = wheel\n", "not one of"),
            ("model = neofiala\nmu_s = 0.5\nmu_d0 = 0.9\n", "mu_d0 <= mu_s"),
            ("model = brush\nn = 9\n", "n must be"),
            ("model = neofiala\nl = 0\n", "l, w"),
            ("model = brush\nn = 4.5\n", "integer"),
            ("model = fiala\nmu = nan\n", "finite"),
        ]
        for text, what in cases:
            with self.assertRaises(B.ParamError) as cm:
                B.parse_params(text, "t.txt")
            self.assertIn(what, str(cm.exception))


if __name__ == "__main__":
    unittest.main()
