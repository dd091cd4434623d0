"""Property tests of the float64 Magic Formula reference (grip_tools.reference.mf) and
of its golden vectors (grip_tools.golden.mf).

Tolerances (stated with the figure measured when they were set):
  slope at zero slip = B*C*D (Kxk, Kya): central difference, h = 1e-7;
      rel 1e-6 (measured worst 1.5e-9 over all shared files, 4 loads, 2 cambers)
  peak = D: dense scan + bounded refinement of max |F0 - SV|; rel 1e-6
      (measured 0.0: near the optimum sin() rounds to exactly 1.0)
  symmetry / mirror / conventions: rel 1e-12 + abs 1e-9 N (measured 0: the
      same float operations on negated inputs)
"""
import math
import os
import re
import sys
import tempfile
import unittest

import numpy as np
from scipy.optimize import minimize_scalar

from grip_tools.golden import io as golden_io, mf as golden_mf
from grip_tools.reference import mf, tir

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")

SLOPE_REL = 1e-6
PEAK_REL = 1e-6


def all_params():
    return [(os.path.basename(p), tir.load_params(p)) for p in golden_mf.tir_files()]


def by_name(name):
    for n, P in all_params():
        if n == name:
            return dict(P)
    raise KeyError(name)


def close(tc, a, b, rel=1e-12, abs_=1e-9, msg=None):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    err = np.abs(a - b)
    tol = abs_ + rel * np.abs(b)
    tc.assertTrue(np.all(err <= tol), f"{msg}: max err {np.max(err):.3e}")


class SlopeAndPeak(unittest.TestCase):
    def test_slope_at_zero_slip_is_bcd(self):
        worst = 0.0
        for name, P in all_params():
            R = golden_mf.ranges(P)
            for fz in np.linspace(max(R["fz"][0], 0.2 * P["fnomin"]), R["fz"][1], 4):
                for g in (0.0, R["gamma"][1]):
                    d = mf.evaluate(P, 0.0, 0.0, g, fz, mirror=False, details=True)["details"]
                    h = 1e-7
                    k0 = -float(d["SHx"])
                    fp = mf.evaluate(P, k0 + h, 0.0, g, fz, mirror=False)["fx0"]
                    fm = mf.evaluate(P, k0 - h, 0.0, g, fz, mirror=False)["fx0"]
                    slope = (fp - fm) / (2 * h)
                    bcd = d["Bx"] * d["Cx"] * d["Dx"]
                    rel = abs(slope - d["Kxk"]) / abs(d["Kxk"])
                    worst = max(worst, rel, abs(bcd - d["Kxk"]) / abs(d["Kxk"]))
                    self.assertLess(rel, SLOPE_REL, f"{name} Fx fz={fz}")
                    a0 = -float(d["SHy"])
                    fp = mf.evaluate(P, 0.0, a0 + h, g, fz, mirror=False)["fy0"]
                    fm = mf.evaluate(P, 0.0, a0 - h, g, fz, mirror=False)["fy0"]
                    slope = (fp - fm) / (2 * h)
                    rel = abs(slope - d["Kya"]) / abs(d["Kya"])
                    worst = max(worst, rel)
                    self.assertLess(rel, SLOPE_REL, f"{name} Fy fz={fz} gamma={g}")
        print(f"\n# slope = BCD: worst relative error {worst:.2e} (tolerance {SLOPE_REL:g})")

    def _peak(self, f, sv, d, lo, hi):
        """max |f(x) - sv| on [lo, hi] (dense scan, then bounded refinement)."""
        xs = np.linspace(lo, hi, 4001)
        ys = np.abs(f(xs) - sv)
        i = int(np.argmax(ys))
        a, b = xs[max(i - 1, 0)], xs[min(i + 1, xs.size - 1)]
        r = minimize_scalar(lambda x: -abs(float(f(x)) - sv), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-12})
        return max(-r.fun, ys[i])

    def test_peak_is_d(self):
        worst = 0.0
        checked = 0
        for name, P in all_params():
            fz = P["fnomin"]
            d = mf.evaluate(P, 0.0, 0.0, 0.0, fz, mirror=False, details=True)["details"]
            for sgn in (1.0, -1.0):
                # Fx: C > 1 and E <= 1 reach the peak at B*kx = ...; search far enough
                span = 60.0 / abs(float(d["Bx"]))
                lo, hi = (0.0, span) if sgn > 0 else (-span, 0.0)
                fx = lambda k: mf.evaluate(P, k - float(d["SHx"]), 0.0, 0.0, fz, mirror=False)["fx0"]
                peak = self._peak(fx, float(d["SVx"]), d, lo, hi)
                D = abs(float(d["Dx"]))
                if d["Cx"] > 1.0:
                    worst = max(worst, abs(peak - D) / D)
                    self.assertLess(abs(peak - D) / D, PEAK_REL, f"{name} Fx peak {sgn}")
                    checked += 1
                else:
                    self.assertLessEqual(peak, D * (1 + 1e-12), f"{name} Fx peak {sgn}")
                span = min(60.0 / abs(float(d["By"])), 1.5)
                lo, hi = (0.0, span) if sgn > 0 else (-span, 0.0)
                fy = lambda a: mf.evaluate(P, 0.0, a - float(d["SHy"]), 0.0, fz, mirror=False)["fy0"]
                peak = self._peak(fy, float(d["SVy"]), d, lo, hi)
                D = abs(float(d["Dy"]))
                arg_max = abs(float(d["By"])) * span
                reaches = d["Cy"] > 1.0 and arg_max > math.tan(math.pi / (2 * d["Cy"])) * 4
                if reaches:
                    worst = max(worst, abs(peak - D) / D)
                    self.assertLess(abs(peak - D) / D, PEAK_REL, f"{name} Fy peak {sgn}")
                    checked += 1
                else:   # e.g. G275 95 psi: Cy < 1, Fy has no peak
                    self.assertLessEqual(peak, D * (1 + 1e-12), f"{name} Fy no peak {sgn}")
        self.assertGreaterEqual(checked, 30)
        print(f"\n# peak = D: {checked} curves, worst relative error {worst:.2e} (tolerance {PEAK_REL:g})")

    def test_g275_95psi_has_no_lateral_peak(self):
        P = by_name("335_65R22_5_G275MSA_95psi.tir")
        self.assertLess(P["pcy1"] * P["lcy"], 1.0)
        a = np.linspace(0.0, P["alpmax"], 200)
        fy = mf.evaluate(P, 0.0, a, 0.0, P["fnomin"])["fy0"]
        self.assertTrue(np.all(np.diff(np.abs(fy)[a > 0.02]) > 0))   # still rising at ALPMAX


SYMMETRIC_ZERO = ("phx1", "phx2", "pvx1", "pvx2", "pex4", "phy1", "phy2", "phy3", "pvy1", "pvy2",
                  "pey3", "qbz4", "qdz3", "qez4", "qhz1", "qhz2", "qdz6", "qdz7", "ssz1",
                  "rhx1", "rby3", "rvy1", "rvy2", "rhy1", "rhy2")


class Symmetry(unittest.TestCase):
    def test_odd_symmetry_with_symmetric_parameters(self):
        rng = np.random.default_rng(1)
        for name, P in all_params():
            S = dict(P)
            for k in SYMMETRIC_ZERO:
                S[k] = 0.0
            R = golden_mf.ranges(S)
            n = 400
            k = rng.uniform(-0.5, 0.5, n)
            a = rng.uniform(-0.4, 0.4, n)
            g = rng.uniform(*R["gamma"], n)
            fz = rng.uniform(0.3, 1.8, n) * S["fnomin"]
            for form in ("mftyre", "book"):
                # pure, gamma = 0: odd in the slip
                o = mf.evaluate(S, k, a, 0.0, fz, mirror=False, form=form)
                m = mf.evaluate(S, -k, -a, 0.0, fz, mirror=False, form=form)
                close(self, m["fx0"], -o["fx0"], msg=f"{name} {form} fx0")
                close(self, m["fy0"], -o["fy0"], msg=f"{name} {form} fy0")
                close(self, m["mz0"], -o["mz0"], msg=f"{name} {form} mz0")
                # combined: Fx even in alpha, Fy and Mz odd in (alpha, gamma)
                o = mf.evaluate(S, k, a, g, fz, mirror=False, form=form)
                m = mf.evaluate(S, k, -a, -g, fz, mirror=False, form=form)
                close(self, m["fx"], o["fx"], msg=f"{name} {form} fx")
                close(self, m["fy"], -o["fy"], msg=f"{name} {form} fy")
                close(self, m["mz"], -o["mz"], msg=f"{name} {form} mz")
                # hence a symmetric tyre is its own mirror image
                mm = mf.evaluate(S, k, a, g, fz, mirror=True, form=form)
                for q in ("fx0", "fy0", "mz0", "fx", "fy", "mz"):
                    close(self, mm[q], o[q], msg=f"{name} {form} mirror {q}")

    def test_asymmetric_file_is_not_its_own_mirror(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        o = mf.evaluate(P, 0.0, 0.0, 0.0, P["fnomin"], mirror=False)
        m = mf.evaluate(P, 0.0, 0.0, 0.0, P["fnomin"], mirror=True)
        self.assertNotAlmostEqual(float(o["fy"]), float(m["fy"]), delta=1.0)
        self.assertAlmostEqual(float(m["fy"]), -float(o["fy"]), delta=1e-9)


class Combined(unittest.TestCase):
    def test_combined_within_pure_envelope(self):
        """With the combined-slip shifts RHX1, RHY1, RHY2 zero the weights
        Gxa, Gyk are cosines <= 1: |Fx| <= |Fx0|, |Fy - SVyk| <= |Fy0|."""
        rng = np.random.default_rng(2)
        for name, P in all_params():
            S = dict(P)
            S["rhx1"] = S["rhy1"] = S["rhy2"] = 0.0
            R = golden_mf.ranges(S)
            n = 2000
            k = rng.uniform(*R["kappa"], n)
            a = rng.uniform(*R["alpha"], n)
            g = rng.uniform(*R["gamma"], n)
            fz = rng.uniform(max(R["fz"][0], 1.0), R["fz"][1], n)
            o = mf.evaluate(S, k, a, g, fz, mirror=False, details=True)
            d = o["details"]
            self.assertTrue(np.all(np.abs(o["fx"]) <= np.abs(o["fx0"]) * (1 + 1e-12) + 1e-9), name)
            self.assertTrue(np.all(np.abs(o["fy"] - d["SVyk"]) <= np.abs(o["fy0"]) * (1 + 1e-12) + 1e-9), name)
            # no combined slip: the pure values
            z = mf.evaluate(S, k, 0.0, g, fz, mirror=False)
            close(self, z["fx"], z["fx0"], msg=f"{name} fx at alpha=0")

    def test_kappa_reduces_fy(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        o = mf.evaluate(P, [0.0, 0.2], 0.1, 0.0, P["fnomin"], mirror=False)
        self.assertLess(abs(o["fy"][1]), 0.8 * abs(o["fy"][0]))

    def test_fe_method_files_kappa_does_not_reduce_fy(self):
        for psi in (40, 60, 70, 95):
            P = by_name(f"335_65R22_5_G275MSA_{psi}psi.tir")
            self.assertEqual((P["rby1"], P["rcy1"], P["rvy1"]), (0.0, 0.0, 0.0))
            k = np.linspace(P["kpumin"], P["kpumax"], 41)
            for a in (-0.1, 0.05, 0.15):
                o = mf.evaluate(P, k, a, 0.02, P["fnomin"])
                np.testing.assert_array_equal(o["fy"], o["fy0"])
                self.assertTrue(np.all(np.abs(o["fx"]) <= np.abs(o["fx0"]) + 1e-9))


class Robustness(unittest.TestCase):
    def test_finite_everywhere(self):
        ks = [-1e3, -1.0, -0.1, 0.0, 0.1, 1.0, 1e3]
        als = [-math.pi / 2, -0.3, 0.0, 0.3, math.pi / 2]
        gs = [-0.5, 0.0, 0.5]
        vxs = [0.0, 0.3, 16.0, -16.0]
        for name, P in all_params():
            fzs = [-100.0, 0.0, 1e-6, P["fnomin"], 5 * P["fnomin"]]
            K, A, G, F, V = np.meshgrid(ks, als, gs, fzs, vxs, indexing="ij")
            for form in ("mftyre", "book"):
                o = mf.evaluate(P, K, A, G, F, vx=V, form=form)
                for q, v in o.items():
                    self.assertTrue(np.all(np.isfinite(v)), f"{name} {form} {q}")
                    self.assertTrue(np.all(v[F <= 0] == 0.0), f"{name} {form} {q} at Fz <= 0")
                    self.assertTrue(np.all(v[V == 0] == 0.0), f"{name} {form} {q} at vx = 0")

    def test_low_speed_is_smooth_and_complete_at_vxlow(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        v = np.linspace(0.0, 2.0 * P["vxlow"], 401)
        o = mf.evaluate(P, 0.1, 0.1, 0.02, P["fnomin"], vx=v, mirror=False)
        full = mf.evaluate(P, 0.1, 0.1, 0.02, P["fnomin"], mirror=False)
        for q in ("fx", "fy", "mz"):
            self.assertEqual(o[q][0], 0.0)
            np.testing.assert_allclose(o[q][v >= P["vxlow"]], full[q], rtol=1e-12)
            jump = np.max(np.abs(np.diff(o[q])))
            self.assertLess(jump, 0.05 * np.max(np.abs(o[q])), q)   # 401 steps: no jump

    def test_vx_sign_does_not_matter(self):
        P = by_name("PacejkaBook_Defaults.tir")
        a = mf.evaluate(P, 0.05, 0.05, 0.01, 4000.0, vx=10.0)
        b = mf.evaluate(P, 0.05, 0.05, 0.01, 4000.0, vx=-10.0)
        for q in a:
            self.assertEqual(float(a[q]), float(b[q]))


class Conventions(unittest.TestCase):
    def setUp(self):
        self.P = by_name("MagicFormula61_Paramerters.tir")
        rng = np.random.default_rng(3)
        n = 300
        self.k = rng.uniform(-0.5, 0.5, n)
        self.a = rng.uniform(-0.4, 0.4, n)
        self.g = rng.uniform(-0.1, 0.1, n)
        self.fz = rng.uniform(0.3, 2.0, n) * self.P["fnomin"]

    def test_sae_sign_table(self):
        self.assertEqual(mf.SAE_SIGN, {"kappa": 1, "alpha": -1, "gamma": 1, "fz": -1, "fx": 1, "fy": -1,
                                       "fz_out": -1, "mx": 1, "my": -1, "mz": -1})

    def test_sae_round_trip(self):
        iso = mf.evaluate(self.P, self.k, self.a, self.g, self.fz)
        k, a, g, f = -1 * 0 + self.k, -self.a, self.g, -self.fz   # the same state in SAE
        sae = mf.evaluate(self.P, k, a, g, f, convention="sae")
        for q in iso:
            sign = 1 if q.startswith("fx") else -1
            close(self, sae[q], sign * iso[q], msg=q)
        back = mf.from_iso(mf.from_iso(iso, "sae"), "sae")   # the sign flips are involutions
        for q in iso:
            np.testing.assert_array_equal(back[q], iso[q])
        ki, ai, gi, fi = mf.to_iso(k, a, g, f, "sae")
        np.testing.assert_array_equal(ai, self.a)
        np.testing.assert_array_equal(fi, self.fz)
        np.testing.assert_array_equal(ki, self.k)
        np.testing.assert_array_equal(gi, self.g)

    def test_kappa_braking_option(self):
        a = mf.evaluate(self.P, self.k, self.a, self.g, self.fz)
        b = mf.evaluate(self.P, -self.k, self.a, self.g, self.fz, kappa_braking=True)
        for q in a:
            np.testing.assert_array_equal(a[q], b[q])
        # braking (kappa < 0 in ISO) gives Fx < 0
        o = mf.evaluate(self.P, 0.1, 0.0, 0.0, self.P["fnomin"], kappa_braking=True)
        self.assertLess(float(o["fx"]), 0.0)

    def test_tyreside_mirror(self):
        # mirrored exactly when the mounting side (options) differs from the
        # side the file was fitted for (tyreside), as in the C library
        path = os.path.join(golden_mf.shared_data_dir(), "mfeval-tir", "MagicFormula61_Paramerters.tir")
        t = tir.read_tir(path)
        self.assertEqual(t.tyreside, -1)               # TYRESIDE = 'RIGHT' in the file
        fitted = t.params()                            # default: as fitted
        self.assertFalse(tir.mirrored(fitted))
        self.assertFalse(tir.mirrored(t.params("right")))
        left = t.params("left")
        self.assertTrue(tir.mirrored(left))
        asfit = mf.evaluate(fitted, self.k, self.a, self.g, self.fz)
        plain = mf.evaluate(fitted, self.k, self.a, self.g, self.fz, mirror=False)
        mounted_left = mf.evaluate(left, self.k, self.a, self.g, self.fz)
        mirrored_in = mf.evaluate(fitted, self.k, -self.a, -self.g, self.fz, mirror=False)
        for q in asfit:
            np.testing.assert_array_equal(asfit[q], plain[q])
            sign = 1 if q.startswith("fx") else -1
            np.testing.assert_array_equal(mounted_left[q], sign * mirrored_in[q])
        self.assertGreater(np.max(np.abs(mounted_left["fy"] - asfit["fy"])), 1.0)

    def test_iso_force_signs(self):
        """ISO-W: driving slip -> Fx > 0; the lateral force opposes the slip
        angle (alpha > 0 -> Fy < 0) for a tyre with Kya < 0."""
        for name, P in all_params():
            if P["kpumax"] > 0:
                self.assertGreater(float(mf.evaluate(P, 0.1, 0.0, 0.0, P["fnomin"])["fx"]), 0.0, name)
            self.assertLess(float(mf.evaluate(P, -0.1, 0.0, 0.0, P["fnomin"])["fx"]), 0.0, name)
            d = mf.evaluate(P, 0.0, 0.0, 0.0, P["fnomin"], mirror=False, details=True)["details"]
            fy = float(mf.evaluate(P, 0.0, 0.1, 0.0, P["fnomin"], mirror=False)["fy0"]
                       - mf.evaluate(P, 0.0, -0.1, 0.0, P["fnomin"], mirror=False)["fy0"])
            self.assertEqual(np.sign(fy), np.sign(float(d["Kya"])), name)


class Forms(unittest.TestCase):
    def test_book_and_mftyre_differ_where_documented(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        K, A, G, F = np.meshgrid(np.linspace(-0.3, 0.3, 13), np.linspace(-0.3, 0.3, 13),
                                 np.linspace(P["cammin"], P["cammax"], 5),
                                 np.linspace(0.5, 1.5, 3) * P["fnomin"], indexing="ij")
        base = mf.evaluate(P, K, A, G, F, mirror=False)
        scale = F * P["unloaded_radius"]
        # only Mz changes with the Bt camber form (TNO QBZ4*g vs book QBZ5|g| + QBZ6 g^2)
        bt = mf.evaluate(P, K, A, G, F, mirror=False, form={"bt_book": True})
        np.testing.assert_array_equal(bt["fy"], base["fy"])
        d = np.max(np.abs(bt["mz"] - base["mz"]) / scale)
        self.assertGreater(d, 1e-3)       # measured 3.4e-2 on the full range, GUIDE: ~1e-2
        self.assertLess(d, 1e-1)
        # at small slip alpha* = tan(alpha) ~ alpha: the forms agree closely
        o = mf.evaluate(P, 0.0, 0.005, 0.0, P["fnomin"], mirror=False)
        b = mf.evaluate(P, 0.0, 0.005, 0.0, P["fnomin"], mirror=False, form={"alpha_star": True})
        self.assertLess(abs(float(b["fy0"] - o["fy0"])) / abs(float(o["fy0"])), 1e-4)

    def test_mf52_uses_fy_minus_svyk(self):
        P = by_name("MagicFormula52_Paramerters.tir")
        o = mf.evaluate(P, 0.1, 0.05, 0.02, P["fnomin"], mirror=False, details=True)
        d = o["details"]
        # MFeval's calculateMz: SVyk with mu_y at gamma = 0 (muy_sub0), i.e.
        # the Fy's SVyk scaled by mu_y(0) / mu_y(gamma)
        svyk0 = d["SVyk"] * d["muy_gamma0"] / d["muy"]
        np.testing.assert_allclose(d["Fy_prime"], o["fy"] - svyk0, rtol=1e-14)
        np.testing.assert_allclose(o["mz"], -d["t"] * d["Fy_prime"] + d["Mzr"] + d["s"] * o["fx"],
                                   rtol=1e-12)
        # grip's earlier form (GRIP_MF_OPT_MZ52_SVYK_CAMBER): the SVyk of Fy itself
        c = mf.evaluate(P, 0.1, 0.05, 0.02, P["fnomin"], mirror=False, details=True, mz52_svyk_camber=True)
        np.testing.assert_allclose(c["details"]["Fy_prime"], c["fy"] - c["details"]["SVyk"], rtol=1e-15)
        for q in ("fx", "fy", "fx0", "fy0", "mz0"):
            self.assertEqual(float(c[q]), float(o[q]), q)
        self.assertGreater(abs(float(c["mz"] - o["mz"])), 1e-4)      # measured 3.1e-4 N m
        big = [mf.evaluate(P, 0.4, 0.05, 0.23, P["fnomin"], mz52_svyk_camber=f)["mz"] for f in (False, True)]
        self.assertGreater(abs(float(big[1] - big[0])), 1.0)        # measured 9.3 N m = 2.5e-3 Fz R0 (13 deg)
        # equal at gamma = 0, where mu_y(gamma) = mu_y(0)
        a = mf.evaluate(P, 0.1, 0.05, 0.0, P["fnomin"])
        b = mf.evaluate(P, 0.1, 0.05, 0.0, P["fnomin"], mz52_svyk_camber=True)
        self.assertEqual(float(a["mz"]), float(b["mz"]))

    def test_mz52_option_size_and_no_effect_on_mf6(self):
        # the two MF 5.2 forms: max |dMz| / (Fz R0) over the file's range
        # (31 x 31 x 9 x 5 grid; measured 9.2e-3 at kappa -0.2, gamma 15 deg;
        # 3.8e-3 at gamma 13 deg, kappa 0.4, Fz = FNOMIN)
        P = by_name("MagicFormula52_Paramerters.tir")
        R = golden_mf.ranges(P)
        K, A, G, F = np.meshgrid(np.linspace(*R["kappa"], 31), np.linspace(*R["alpha"], 31),
                                 np.linspace(*R["gamma"], 9), np.linspace(*R["fz"], 5), indexing="ij")
        a = mf.evaluate(P, K, A, G, F)
        b = mf.evaluate(P, K, A, G, F, mz52_svyk_camber=True)
        d = np.max(np.abs(a["mz"] - b["mz"]) / (F * P["unloaded_radius"]))
        self.assertGreater(d, 5e-3)
        self.assertLess(d, 2e-2)
        P6 = by_name("MagicFormula61_Paramerters.tir")
        a = mf.evaluate(P6, K[..., 0], A[..., 0], G[..., 0], P6["fnomin"])
        b = mf.evaluate(P6, K[..., 0], A[..., 0], G[..., 0], P6["fnomin"], mz52_svyk_camber=True)
        np.testing.assert_array_equal(a["mz"], b["mz"])

    def test_mf61_fy_prime_at_zero_camber(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        o = mf.evaluate(P, 0.1, 0.05, 0.05, P["fnomin"], mirror=False, details=True)
        d = o["details"]
        z = mf.evaluate(P, 0.1, 0.05, 0.0, P["fnomin"], mirror=False)
        np.testing.assert_allclose(d["Fy_prime"], d["Gyk"] * z["fy0"], rtol=1e-15)

    def test_pressure_matters_only_for_mf6(self):
        P6 = by_name("MagicFormula61_Paramerters.tir")
        a = mf.evaluate(P6, 0.05, 0.05, 0.0, P6["fnomin"], p=200000.0)
        b = mf.evaluate(P6, 0.05, 0.05, 0.0, P6["fnomin"], p=300000.0)
        self.assertGreater(abs(float(a["fy"] - b["fy"])), 10.0)
        P5 = by_name("MagicFormula52_Paramerters.tir")
        a = mf.evaluate(P5, 0.05, 0.05, 0.0, P5["fnomin"], p=200000.0)
        b = mf.evaluate(P5, 0.05, 0.05, 0.0, P5["fnomin"], p=300000.0)
        self.assertEqual(float(a["fy"]), float(b["fy"]))


class Extended(unittest.TestCase):
    """evaluate_ext: MFeval's other channels (docs/magic-formula.md section 9).
    Tolerances: the equations solved at the result to rel 1e-9 (measured
    <= 1e-12); Re equal to MFeval's own fixed-point iteration to 1e-9 m."""

    def _mfeval_re(self, P, kappa, vx, fz, dpi=0.0):
        """MFeval's calculateRe loop, as written there (scalar)."""
        R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
        cz = P["vertical_stiffness"] * (1.0 + P["pfz1"] * dpi)
        re, old = R0 * 0.965, R0
        while abs(old - re) > 1e-9:
            old = re
            omega = (kappa * vx + vx) / re
            romega = R0 * (P["q_re0"] + P["q_v1"] * (omega * R0 / V0) ** 2)
            re = romega - (Fz0 / cz) * (P["dreff"] * math.atan(P["breff"] * fz / Fz0) + P["freff"] * fz / Fz0)
        return re

    def test_re_is_mfevals_fixed_point(self):
        P = by_name("MagicFormula61_Paramerters.tir")          # Q_V1 = 7e-4
        worst = 0.0
        for k in (-0.5, 0.0, 0.3, 1.0):
            for vx in (1.0, 16.6, 60.0):
                for fz in (500.0, 6752.0, 15000.0):
                    o = mf.evaluate_ext(P, k, 0.0, 0.0, fz, vx=vx, mirror=False)
                    want = self._mfeval_re(P, k, vx, fz)
                    worst = max(worst, abs(float(o["re"]) - want))
                    self.assertAlmostEqual(float(o["omega"]), (1.0 + k) * vx / float(o["re"]), places=9)
        self.assertLess(worst, 1e-8)

    def test_vertical_mf61_solves_its_load_equation(self):
        for name in ("MagicFormula61_Paramerters.tir", "MagicFormula52_Paramerters.tir", "FSAE_Defaults.tir"):
            P = by_name(name)
            R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
            fz = np.linspace(0.1, 2.0, 9) * Fz0
            o = mf.evaluate_ext(P, 0.1, 0.1, 0.0, fz, mirror=False)
            x = o["rho"] / R0
            qfz1 = math.sqrt((P["vertical_stiffness"] * R0 / Fz0) ** 2 - 4.0 * P["q_fz2"])
            ext = (1.0 + P["q_v2"] * R0 / V0 * np.abs(o["omega"]) - (P["q_fcx"] * o["fx"] / Fz0) ** 2
                   - (P["q_fcy"] * o["fy"] / Fz0) ** 2)
            np.testing.assert_allclose((qfz1 * x + P["q_fz2"] * x ** 2) * ext * Fz0, fz, rtol=1e-9)
            np.testing.assert_allclose(o["cz"], fz / o["rho"], rtol=1e-12)
            b = P["q_v1"] * (1.1 * V0 / V0) ** 2
            romega = R0 * (P["q_re0"] + b / (o["re"] / R0) ** 2)
            np.testing.assert_allclose(o["rl"], romega - o["rho"], rtol=1e-12)

    def test_vertical_mf62_solves_fz62(self):
        P = by_name("MagicFormula62_Paramerters.tir")
        R0 = P["unloaded_radius"]
        fz = np.array([100.0, 300.0, 3000.0, 6752.0, 15000.0, 6752.0, 6752.0])
        gam = np.array([0.1, 0.0, 0.05, -0.05, 0.1, 0.0, 0.08])
        alpha = np.array([0.0, 0.0, 0.1, -0.2, 0.05, 0.3, 0.1])
        o = mf.evaluate_ext(P, 0.05, alpha, gam, fz, mirror=False)
        out, det = mf._core(P, 0.05, alpha, gam, fz, None, None, "mftyre")
        b = P["q_v1"] * (1.05 * P["longvl"] / P["longvl"]) ** 2
        romega = R0 * (P["q_re0"] + b / (o["re"] / R0) ** 2)
        f62, rho = mf._fz62(P, o["rl"], romega, gam, np.abs(o["omega"]), det["dpi"], out["fx"], out["fy"])
        top = o["rl"] == romega
        self.assertTrue(top[0])                     # camber deflection carries 100 N at gamma 0.1
        self.assertTrue(np.all(f62[top] >= fz[top]))
        np.testing.assert_allclose(f62[~top], fz[~top], rtol=1e-9)
        np.testing.assert_allclose(o["rho"], rho, rtol=1e-12)
        np.testing.assert_allclose(o["cz"], fz / rho, rtol=1e-12)

    def test_missing_parameters_are_nan(self):
        P = by_name("335_65R22_5_G275MSA_60psi.tir")
        o = mf.evaluate_ext(P, 0.1, 0.1, 0.0, P["fnomin"])
        self.assertTrue(np.isnan(o["cx"]) and np.isnan(o["cy"]))
        self.assertTrue(np.isfinite(o["sigmax"]) and np.isfinite(o["re"]))
        Q = dict(by_name("MagicFormula61_Paramerters.tir"), vertical_stiffness=0.0, lateral_stiffness=0.0)
        o = mf.evaluate_ext(Q, 0.1, 0.1, 0.0, Q["fnomin"])
        for k in ("re", "omega", "rl", "rho", "cz", "2a", "2b", "cy", "sigmay"):
            self.assertTrue(np.isnan(o[k]), k)
        for k in ("t", "mzr", "mux", "muy", "kxk", "kya", "cx", "sigmax", "mx", "my"):
            self.assertTrue(np.isfinite(o[k]), k)

    def test_unloaded(self):
        P = by_name("PacejkaBook_Defaults.tir")
        for fz in (0.0, -100.0):
            o = mf.evaluate_ext(P, 0.1, 0.1, 0.02, fz, vx=10.0)
            self.assertEqual(float(o["re"]), P["unloaded_radius"] * P["q_re0"])
            self.assertEqual(float(o["rl"]), float(o["re"]))
            for k in ("fx", "fy", "mz", "rho", "cz", "2a", "2b", "t", "mzr", "mux", "muy", "kxk", "kya",
                      "sigmax", "sigmay", "mx", "my"):
                self.assertEqual(float(o[k]), 0.0, k)

    def test_conventions(self):
        P = dict(by_name("MagicFormula61_Paramerters.tir"), tyreside=1, options=0)   # a left tyre, mounted left
        k, a, g, f = 0.05, np.linspace(-0.3, 0.3, 7), 0.04, 6000.0
        iso = mf.evaluate_ext(P, k, a, g, f)
        mir = mf.evaluate_ext(P, k, -a, -g, f, mirror=True)
        sae = mf.evaluate_ext(P, k, -a, g, -f, convention="sae")
        for name, _u, msign, ssign in mf.EXT_CHANNELS:
            np.testing.assert_array_equal(mir[name], msign * iso[name], name)
            np.testing.assert_array_equal(sae[name], ssign * iso[name], name)
        self.assertEqual([n for n, _u, m, _s in mf.EXT_CHANNELS if m < 0], ["mzr", "mx"])
        self.assertEqual([n for n, _u, _m, s in mf.EXT_CHANNELS if s < 0], ["mzr", "my"])

    def test_my_follows_the_rolling_direction(self):
        P = by_name("MagicFormula61_Paramerters.tir")
        f = P["fnomin"]
        fwd = float(mf.evaluate_ext(P, 0.0, 0.0, 0.0, f, vx=20.0)["my"])
        self.assertLess(fwd, 0.0)                                   # ISO: My < 0 rolling forward
        self.assertEqual(float(mf.evaluate_ext(P, 0.0, 0.0, 0.0, f, vx=-20.0)["my"]), -fwd)
        self.assertEqual(float(mf.evaluate_ext(P, 0.0, 0.0, 0.0, f, vx=0.0)["my"]), 0.0)
        # a wheel spinning backwards (kappa < -1 - VXLOW / |vx|) flips it,
        # the locked wheel (kappa = -1) has none
        self.assertGreater(float(mf.evaluate_ext(P, -1.3, 0.0, 0.0, f, vx=20.0)["my"]), 0.0)
        self.assertEqual(float(mf.evaluate_ext(P, -1.0, 0.0, 0.0, f, vx=20.0)["my"]), 0.0)

    def test_relaxation_lengths(self):
        P6 = by_name("MagicFormula61_Paramerters.tir")
        o = mf.evaluate_ext(P6, 0.1, 0.1, 0.02, 5000.0, mirror=False)
        self.assertAlmostEqual(float(o["sigmax"]), abs(float(o["kxk"] / o["cx"])), places=12)
        self.assertAlmostEqual(float(o["sigmay"]), abs(float(o["kya"] / o["cy"])), places=12)
        P5 = by_name("MagicFormula52_Paramerters.tir")
        fz = P5["fnomin"]
        o = mf.evaluate_ext(P5, 0.1, 0.1, 0.0, fz, mirror=False)
        self.assertAlmostEqual(float(o["sigmax"]), P5["ptx1"] * P5["unloaded_radius"], places=12)
        want = P5["pty1"] * math.sin(2.0 * math.atan(1.0 / P5["pty2"])) * P5["unloaded_radius"]
        self.assertAlmostEqual(float(o["sigmay"]), want, places=12)

    def test_c_header_has_every_channel(self):
        with open(os.path.join(tir.REPO_ROOT, "include", "grip", "grip_mf.h")) as f:
            h = f.read()
        bits = re.findall(r"#define GRIP_MF_EXT_(\w+)\s+0x([0-9A-F]+)u /\*", h)
        self.assertEqual(len(bits), len(mf.EXT_NAMES))
        self.assertEqual([int(b, 16) for _n, b in bits], [1 << i for i in range(len(mf.EXT_NAMES))])


class Golden(unittest.TestCase):
    def test_write_golden(self):
        with tempfile.TemporaryDirectory() as d:
            golden_mf.write_golden(d)
            files = golden_mf.tir_files()
            with open(os.path.join(d, "mf_params.c")) as f:
                c = f.read()
            self.assertIn(f"const int grip_test_tire_count = {len(files)};", c)
            stamps = {}
            for path in files:
                name = golden_mf.tire_name(path)
                self.assertIn(f"static const grip_mf_params grip_tire_{name} = {{", c)
                g = os.path.join(d, f"mf_{name}.txt")
                stamps[g] = os.stat(g).st_mtime_ns
                with open(g) as f:
                    head = [ln for ln in f if ln.startswith("#")]
                self.assertIn("# columns: " + " ".join(golden_mf.COLUMNS) + "\n", head)
                rows = np.loadtxt(g, comments="#")
                self.assertEqual(rows.shape[1], 12)
                self.assertGreaterEqual(rows.shape[0], 2500)
                self.assertLessEqual(rows.shape[0], 4000)
                self.assertTrue(np.all(np.isfinite(rows)))
                # rows reproduce: the reference evaluated on the written inputs
                P = tir.load_params(path, "left")      # the golden files mount every tyre left
                p = rows[:, 4] if P["fittyp"] in mf.MF6 else None
                o = mf.evaluate(P, rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], p=p, vx=rows[:, 5])
                for j, q in enumerate(golden_mf.COLUMNS[6:]):
                    np.testing.assert_allclose(rows[:, 6 + j], o[q], rtol=1e-15, atol=1e-12)
                R = golden_mf.ranges(P)
                self.assertGreaterEqual(rows[:, 0].min(), R["kappa"][0])
                self.assertLessEqual(rows[:, 0].max(), R["kappa"][1])
                self.assertLessEqual(np.abs(rows[:, 1]).max(), max(map(abs, R["alpha"])))
                self.assertTrue(np.any(rows[:, 5] == 0.0))
                self.assertTrue(np.any(rows[:, 5] < P["vxlow"]))
                # the extended file: the same input rows, the other outputs
                ext = os.path.join(d, f"mf_ext_{name}.txt")
                stamps[ext] = os.stat(ext).st_mtime_ns
                with open(ext) as f:
                    head = [ln for ln in f if ln.startswith("#")]
                self.assertIn("# columns: " + " ".join(golden_mf.EXT_COLUMNS) + "\n", head)
                xr = np.loadtxt(ext, comments="#")
                np.testing.assert_array_equal(xr[:, :6], rows[:, :6])
                np.testing.assert_array_equal(xr[:, 6:9], rows[:, 9:12])
                alt = mf.evaluate(P, rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], p=p, vx=rows[:, 5],
                                  mz52_svyk_camber=True)
                j = golden_mf.EXT_COLUMNS.index("mz_svyk_camber")
                np.testing.assert_allclose(xr[:, j], alt["mz"], rtol=1e-15, atol=1e-12)
                # the use modes: every mode row reproduces, turn slip only
                # where the file has the coefficients, inside the domain
                md = os.path.join(d, f"mf_mode_{name}.txt")
                stamps[md] = os.stat(md).st_mtime_ns
                with open(md) as f:
                    head = [ln for ln in f if ln.startswith("#")]
                self.assertIn("# columns: " + " ".join(golden_mf.MODE_COLUMNS) + "\n", head)
                mr = np.loadtxt(md, comments="#")
                modes = set(int(m) for m in mr[:, 0])
                ts_modes = {m for m in modes if m & golden_mf.OPT_TURN_SLIP}
                self.assertEqual(bool(ts_modes), mf.turn_slip_usable(P), name)
                self.assertIn(golden_mf.OPT_NO_LIMITS, modes)
                self.assertTrue(np.all(np.abs(mr[:, 7]) <= golden_mf.PHIT_MAX))
                rr = {c: mr[:, k] for k, c in enumerate(golden_mf.MODE_COLUMNS[:9])}
                out = golden_mf.mode_outputs(P, rr, P["fittyp"] in mf.MF6)
                for k, col in enumerate(golden_mf.MODE_COLUMNS[9:]):
                    np.testing.assert_allclose(mr[:, 9 + k], out[col], rtol=1e-15, atol=1e-12, equal_nan=True)
            # a second run keeps unchanged files (their timestamps)
            golden_mf.write_golden(d)
            for g, st in stamps.items():
                self.assertEqual(os.stat(g).st_mtime_ns, st, g)

    def test_bad_tir_fails_generation(self):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "chrono-tir"))
            with open(os.path.join(DATA, "bad_fittyp.tir")) as f:
                bad = f.read()
            with open(os.path.join(d, "chrono-tir", "bad.tir"), "w") as f:
                f.write(bad)
            old = os.environ.get("GRIP_SHARED_DATA")
            os.environ["GRIP_SHARED_DATA"] = d
            try:
                with self.assertRaises(tir.TirError):
                    golden_mf.write_golden(os.path.join(d, "out"))
            finally:
                if old is None:
                    del os.environ["GRIP_SHARED_DATA"]
                else:
                    os.environ["GRIP_SHARED_DATA"] = old
            self.assertFalse(os.path.exists(os.path.join(d, "out", "mf_params.c")))

    def test_header_hash_covers_the_reference(self):
        h = golden_io.header("x", mf, 1, ["a"])
        self.assertIn("# reference: grip_tools.reference.mf sha256:", h)



# ---------------------------------------------------------------------------
# Turn slip and the use modes.

def mfeval_turn_slip_point(P, Fz, kappa, alpha, gamma, phit, Vcx, omega=None):
    """MFeval's useMode 112 at one point, MF 6.1 equations, transcribed
    scalar by scalar in the order of its Solver (parseInputs, calculateRe,
    calculateBasic, calculateFx0, calculateFy0, calculateMz0, calculateFx,
    calculateFy, calculateMz), with its epsilons and its Re iteration: a
    second formulation, independent of the reference's array code. Valid for
    inputs inside the file's ranges, Vcx > VXLOW, p = INFLPRES (no limit of
    MFeval's acts). Returns (Fx, Fy, Mz, internals)."""
    g = lambda k: P[k.lower()]
    eps = 1e-6
    sgn = lambda v: (v > 0) - (v < 0)
    sgn1 = lambda v: -1.0 if v < 0 else 1.0
    R0, Fz0, V0, LFZO = g("UNLOADED_RADIUS"), g("FNOMIN"), g("LONGVL"), g("LFZO")
    p = g("INFLPRES")
    # parseInputs, limits check: turn slip times cos(alpha); Vx above VXLOW
    phit = phit * math.cos(alpha)
    dpi = (p - g("NOMPRES")) / g("NOMPRES")
    Cz = g("VERTICAL_STIFFNESS") * (1 + g("PFZ1") * dpi)
    if omega is None:
        Re, Re_old = R0 * 0.965, R0
        while abs(Re_old - Re) > 1e-9:
            Re_old = Re
            omega = (kappa * Vcx + Vcx) / Re
            Romega = R0 * (g("Q_RE0") + g("Q_V1") * ((omega * R0) / V0) ** 2)
            Re = Romega - (Fz0 / Cz) * (g("DREFF") * math.atan(g("BREFF") * Fz / Fz0) + g("FREFF") * Fz / Fz0)
    Fz0p = LFZO * Fz0
    dfz = (Fz - Fz0p) / Fz0p
    Vsy = -math.tan(alpha) * abs(Vcx)
    V = math.sqrt(Vcx ** 2 + Vsy ** 2)
    epsg = g("PECP1") * (1 + g("PECP2") * dfz)
    Vcp = V
    psi_dot = -phit * Vcp
    phi = (1 / Vcp) * (psi_dot - (1 - epsg) * omega * math.sin(gamma))
    # calculateBasic (useAlphaStar off, LMUV = 0, Amu = 1)
    Vc = math.sqrt(Vcx ** 2 + (math.tan(alpha) * abs(Vcx)) ** 2)
    alpha_prime = math.acos(Vcx / (Vc + eps))
    a_s, g_s = alpha, gamma
    LMUX, LMUY = g("LMUX"), g("LMUY")
    # calculateFx0
    Bxp = g("PDXP1") * (1 + g("PDXP2") * dfz) * math.cos(math.atan(g("PDXP3") * kappa))
    z1 = math.cos(math.atan(Bxp * R0 * phi))
    Cx = g("PCX1") * g("LCX")
    mux = (g("PDX1") + g("PDX2") * dfz) * (1 + g("PPX3") * dpi + g("PPX4") * dpi ** 2) * (1 - g("PDX3") * gamma ** 2) * LMUX
    Dx = mux * Fz * z1
    Kxk = Fz * (g("PKX1") + g("PKX2") * dfz) * math.exp(g("PKX3") * dfz) * (1 + g("PPX1") * dpi + g("PPX2") * dpi ** 2) * g("LKX")
    Bx = Kxk / (Cx * Dx + eps * sgn1(Dx))
    kx = kappa + (g("PHX1") + g("PHX2") * dfz) * g("LHX")
    SVx = Fz * (g("PVX1") + g("PVX2") * dfz) * g("LVX") * LMUX * z1
    Ex = min((g("PEX1") + g("PEX2") * dfz + g("PEX3") * dfz ** 2) * (1 - g("PEX4") * sgn(kx)) * g("LEX"), 1.0)
    Fx0 = Dx * math.sin(Cx * math.atan(Bx * kx - Ex * (Bx * kx - math.atan(Bx * kx)))) + SVx

    def fy0(gs, turn):
        z2 = z3 = 1.0
        if turn:
            z3 = math.cos(math.atan(g("PKYP1") * R0 ** 2 * phi ** 2))
            Byp = g("PDYP1") * (1 + g("PDYP2") * dfz) * math.cos(math.atan(g("PDYP3") * math.tan(alpha)))
            z2 = math.cos(math.atan(Byp * (R0 * abs(phi) + g("PDYP4") * math.sqrt(R0 * abs(phi)))))
        Kya = (g("PKY1") * Fz0p * (1 + g("PPY1") * dpi) * (1 - g("PKY3") * abs(gs))
               * math.sin(g("PKY4") * math.atan((Fz / Fz0p) / ((g("PKY2") + g("PKY5") * gs ** 2) * (1 + g("PPY2") * dpi))))
               * z3 * g("LKY"))
        SVyg = Fz * (g("PVY3") + g("PVY4") * dfz) * gs * g("LKYC") * LMUY * z2
        Kyg0 = Fz * (g("PKY6") + g("PKY7") * dfz) * (1 + g("PPY5") * dpi) * g("LKYC")
        if turn:
            Kya0 = (g("PKY1") * Fz0p * (1 + g("PPY1") * dpi)
                    * math.sin(g("PKY4") * math.atan((Fz / Fz0p) / (g("PKY2") * (1 + g("PPY2") * dpi)))) * z3 * g("LKY"))
            Kyap = Kya + eps * sgn1(Kya)
            Kya0p = Kya0 + eps * sgn1(Kya0)
            CHyp, DHyp, EHyp = g("PHYP1"), (g("PHYP2") + g("PHYP3") * dfz) * sgn(Vcx), min(g("PHYP4"), 1.0)
            BHyp = Kyg0 / (1 - epsg) / (CHyp * DHyp * Kya0p)
            u = BHyp * R0 * phi
            SHyp = DHyp * math.sin(CHyp * math.atan(u - EHyp * (u - math.atan(u)))) * sgn(Vcx)
            z0, z4 = 0.0, 1 + SHyp - SVyg / Kyap
        else:
            z0, z4 = 1.0, 1.0
        SHy = (g("PHY1") + g("PHY2") * dfz) * g("LHY") + ((Kyg0 * gs - SVyg) / (Kya + eps * sgn1(Kya))) * z0 + z4 - 1
        SVy = Fz * (g("PVY1") + g("PVY2") * dfz) * g("LVY") * LMUY * z2 + SVyg
        ay = a_s + SHy
        Cy = g("PCY1") * g("LCY")
        muy = (g("PDY1") + g("PDY2") * dfz) * (1 + g("PPY3") * dpi + g("PPY4") * dpi ** 2) * (1 - g("PDY3") * gs ** 2) * LMUY
        Dy = muy * Fz * z2
        Ey = min((g("PEY1") + g("PEY2") * dfz) * (1 + g("PEY5") * gs ** 2 - (g("PEY3") + g("PEY4") * gs) * sgn1(ay))
                 * g("LEY"), 1.0)
        By = Kya / (Cy * Dy + eps * sgn1(Dy))
        F = Dy * math.sin(Cy * math.atan(By * ay - Ey * (By * ay - math.atan(By * ay)))) + SVy
        return dict(Fy0=F, muy=muy, Kya=Kya, SHy=SHy, SVy=SVy, By=By, Cy=Cy, z2=z2, z3=z3)

    y = fy0(g_s, True)
    # calculateFy (Gyk at gamma*)
    Byk = (g("RBY1") + g("RBY4") * g_s ** 2) * math.cos(math.atan(g("RBY2") * (a_s - g("RBY3")))) * g("LYKA")
    Eyk = min(g("REY1") + g("REY2") * dfz, 1.0)
    SHyk = g("RHY1") + g("RHY2") * dfz
    G = lambda xx: math.cos(g("RCY1") * math.atan(Byk * xx - Eyk * (Byk * xx - math.atan(Byk * xx))))
    Gyk = G(kappa + SHyk) / G(SHyk)
    DVyk = y["muy"] * Fz * (g("RVY1") + g("RVY2") * dfz + g("RVY3") * g_s) * math.cos(math.atan(g("RVY4") * a_s)) * y["z2"]
    Fy = Gyk * y["Fy0"] + DVyk * math.sin(g("RVY5") * math.atan(g("RVY6") * kappa)) * g("LVYKA")
    # calculateMz0
    Kyap = y["Kya"] + eps * sgn1(y["Kya"])
    ar = a_s + y["SHy"] + y["SVy"] / Kyap
    at = a_s + g("QHZ1") + g("QHZ2") * dfz + (g("QHZ3") + g("QHZ4") * dfz) * g_s
    z5 = math.cos(math.atan(g("QDTP1") * R0 * phi))
    Dt = ((g("QDZ1") + g("QDZ2") * dfz) * (1 - g("PPZ1") * dpi) * (1 + g("QDZ3") * gamma + g("QDZ4") * gamma ** 2)
          * Fz * (R0 / Fz0p) * g("LTR") * z5)
    Bt = (g("QBZ1") + g("QBZ2") * dfz + g("QBZ3") * dfz ** 2) * (1 + g("QBZ4") * gamma + g("QBZ5") * abs(gamma)) * g("LKY") / LMUY
    Ct = g("QCZ1")
    Et = min((g("QEZ1") + g("QEZ2") * dfz + g("QEZ3") * dfz ** 2)
             * (1 + (g("QEZ4") + g("QEZ5") * g_s) * (2 / math.pi) * math.atan(Bt * Ct * at)), 1.0)
    z6 = math.cos(math.atan(g("QBRP1") * R0 * phi))
    Mzp_inf = g("QCRP1") * abs(y["muy"]) * R0 * Fz * math.sqrt(Fz / Fz0p) * g("LMP")
    CDrp = g("QDRP1")
    DDrp = Mzp_inf / math.sin(0.5 * math.pi * CDrp)
    Kzgr0 = Fz * R0 * (g("QDZ8") * g("QDZ9") * dfz + (g("QDZ10") + g("QDZ11") * dfz * abs(gamma))) * g("LKZC")
    BDrp = Kzgr0 / (CDrp * DDrp * (1 - epsg))
    Drp = DDrp * math.sin(CDrp * math.atan(BDrp * R0 * phit))
    Mzp90 = Mzp_inf * (2 / math.pi) * math.atan(g("QCRP2") * R0 * abs(phit)) * Gyk
    # MATLAB: Mzp90 / 0 = Inf and acos(Inf) is complex: Mz is not finite
    z7 = (2 / math.pi) * math.acos(Mzp90 / abs(Drp)) if Drp != 0.0 and abs(Mzp90 / Drp) <= 1.0 else math.nan
    Dr = (Fz * R0 * ((g("QDZ6") + g("QDZ7") * dfz) * g("LRES") * y["z2"]) * LMUY * sgn(Vcx) * math.cos(a_s) + Drp)
    Br = (g("QBZ9") * g("LKY") / LMUY + g("QBZ10") * y["By"] * y["Cy"]) * z6
    # calculateFx
    Bxa = (g("RBX1") + g("RBX3") * g_s ** 2) * math.cos(math.atan(g("RBX2") * kappa)) * g("LXAL")
    Exa = min(g("REX1") + g("REX2") * dfz, 1.0)
    Gx = lambda xx: math.cos(g("RCX1") * math.atan(Bxa * xx - Exa * (Bxa * xx - math.atan(Bxa * xx))))
    Fx = Gx(a_s + g("RHX1")) / Gx(g("RHX1")) * Fx0
    # calculateMz
    ratio = (Kxk / Kyap) ** 2 * kappa ** 2
    ar_eq = math.atan(math.sqrt(math.tan(ar) ** 2 + ratio)) * sgn(ar)
    at_eq = math.atan(math.sqrt(math.tan(at) ** 2 + ratio)) * sgn(at)
    s = R0 * (g("SSZ1") + g("SSZ2") * (Fy / Fz0) + (g("SSZ3") + g("SSZ4") * dfz) * gamma) * g("LS")
    Mzr = Dr * math.cos(z7 * math.atan(Br * ar_eq))
    Fyp = Gyk * fy0(0.0, True)["Fy0"]
    t = Dt * math.cos(Ct * math.atan(Bt * at_eq - Et * (Bt * at_eq - math.atan(Bt * at_eq)))) * math.cos(alpha_prime) * LFZO
    Mz = -t * Fyp + Mzr + s * Fx
    return Fx, Fy, Mz, dict(phi=phi, z1=z1, z2=y["z2"], z3=y["z3"], z5=z5, z6=z6, z7=z7, Drp=Drp)


class TurnSlip(unittest.TestCase):
    """Turn slip (MFeval's useMode xx2): the reference against a scalar
    transcription of MFeval's Solver (mfeval_turn_slip_point) on worked
    points, and the properties that do not need MFeval."""

    # worked points (Fz / FNOMIN, kappa, alpha, gamma, phit [1/m], Vx / LONGVL, omega)
    POINTS = [(1.0, 0.0, 0.0, 0.0, 0.5, 1.0, None), (1.0, 0.05, 0.05, 0.03, 1.0, 1.0, None),
              (0.6, -0.1, -0.08, -0.05, -2.0, 1.2, None), (1.4, 0.2, 0.15, 0.08, 4.0, 0.8, None),
              (0.8, -0.03, 0.1, -0.02, -0.7, 1.0, 40.0)]

    def test_worked_points_match_mfevals_equations(self):
        # MF 6.1 and 6.2 (the same forces); the two other files have
        # MFeval's Kzgr0 = 0 (QDZ9 = QDZ10 = QDZ11 = 0): Drp = 0 and MFeval's
        # Mz is not finite, so only Fx, Fy are compared there
        worst = 0.0
        for name in ("MagicFormula61_Paramerters.tir", "MagicFormula62_Paramerters.tir",
                     "FSAE_Defaults.tir", "PacejkaBook_Defaults.tir"):
            P = by_name(name)
            P["tyreside"], P["options"] = 1, 0
            for fzr, k, a, gm, ph, vr, om in self.POINTS:
                Fz, V = fzr * P["fnomin"], vr * P["longvl"]
                o = mf.evaluate(P, k, a, gm, Fz, vx=V, turn_slip=True, phit=ph, omega=om, details=True)
                with np.errstate(all="ignore"):
                    fx, fy, mz, d = mfeval_turn_slip_point(P, Fz, k, a, gm, ph, V, om)
                scale = Fz
                self.assertLessEqual(abs(float(o["fx"]) - fx), 1e-9 * scale, (name, k, a, gm, ph))
                self.assertLessEqual(abs(float(o["fy"]) - fy), 1e-9 * scale, (name, k, a, gm, ph))
                worst = max(worst, abs(float(o["fx"]) - fx) / scale, abs(float(o["fy"]) - fy) / scale)
                ts = o["details"]["ts"]
                R0 = P["unloaded_radius"]
                self.assertAlmostEqual(float(ts.u), R0 * d["phi"], delta=1e-9)
                for z in ("z1", "z2", "z3", "z5", "z6"):
                    # MFeval iterates Re to 1e-9 m, the reference solves it: 1e-9
                    self.assertAlmostEqual(float(getattr(ts, z)), d[z], delta=1e-9, msg=z)
                if "Magic" in name:
                    self.assertLessEqual(abs(float(o["mz"]) - mz), 1e-9 * scale * R0, (name, k, a, gm, ph))
                    worst = max(worst, abs(float(o["mz"]) - mz) / (scale * R0))
                else:
                    self.assertEqual(d["Drp"], 0.0)
                    self.assertFalse(math.isfinite(mz))
        print(f"# turn slip vs MFeval's equations (scalar transcription): worst |err| / Fz = {worst:.2e}")

    def test_hand_derivation_of_the_spin(self):
        # MF 6.1 at gamma = 0, alpha = 0: phi = -phit (MFeval's sign), so
        # R0 phi = -R0 phit and, with PKYP1 = 1, zeta3 = cos(atan((R0 phit)^2))
        # = 1 / sqrt(1 + (R0 phit)^4); PDXP1 = 0.4, PDXP2 = PDXP3 = 0:
        # zeta1 = 1 / sqrt(1 + (0.4 R0 phit)^2); QDTP1 = 10: zeta5 = 1 /
        # sqrt(1 + (10 R0 phit)^2)
        P = by_name("MagicFormula61_Paramerters.tir")
        P["tyreside"], P["options"] = 1, 0
        R0 = P["unloaded_radius"]
        ts = mf.evaluate(P, 0.0, 0.0, 0.0, P["fnomin"], turn_slip=True, phit=1.0, details=True)["details"]["ts"]
        u = R0 * 1.0
        self.assertAlmostEqual(float(ts.u), -u, places=14)
        self.assertAlmostEqual(float(ts.z3), 1.0 / math.sqrt(1.0 + u ** 4), places=14)
        self.assertAlmostEqual(float(ts.z1), 1.0 / math.sqrt(1.0 + (0.4 * u) ** 2), places=14)
        self.assertAlmostEqual(float(ts.z5), 1.0 / math.sqrt(1.0 + (10.0 * u) ** 2), places=14)
        # camber alone: phi = -(1 - PECP1) Omega sin(gamma) / Vc', Omega = Vx / Re at kappa = 0
        g = 0.05
        V = P["longvl"]
        o = mf.evaluate_ext(P, 0.0, 0.0, g, P["fnomin"], vx=V, turn_slip=True, phit=0.0)
        ts = mf.evaluate(P, 0.0, 0.0, g, P["fnomin"], vx=V, turn_slip=True, phit=0.0, details=True)["details"]["ts"]
        self.assertAlmostEqual(float(ts.u), -R0 * (1.0 - 0.5) * (V / o["re"]) * math.sin(g) / V, places=12)

    def test_turn_slip_off_is_the_plain_model(self):
        for n, P in all_params():
            a = mf.evaluate(P, 0.1, 0.05, 0.02, P["fnomin"])
            b = mf.evaluate(P, 0.1, 0.05, 0.02, P["fnomin"], turn_slip=False, phit=3.0, omega=0.0)
            for q in a:
                self.assertEqual(float(a[q]), float(b[q]), (n, q))

    def test_sets_without_coefficients_are_refused(self):
        for n, P in all_params():
            if mf.turn_slip_usable(P):
                continue
            with self.assertRaises(ValueError):
                mf.evaluate(P, 0.0, 0.0, 0.0, P["fnomin"], turn_slip=True, phit=1.0)

    def test_phit_zero_is_the_limit(self):
        # MFeval's zeta7 = 2/pi acos(Mzp90 / |Drp|) is 0/0 at phit = 0; the
        # reference takes the limit: continuous from both sides
        P = by_name("MagicFormula61_Paramerters.tir")
        k, a, g, fz = 0.02, 0.05, 0.03, P["fnomin"]
        m0 = float(mf.evaluate(P, k, a, g, fz, turn_slip=True, phit=0.0)["mz"])
        for h in (1e-6, -1e-6):
            mh = float(mf.evaluate(P, k, a, g, fz, turn_slip=True, phit=h)["mz"])
            self.assertLess(abs(mh - m0), 1e-4 * fz * P["unloaded_radius"], h)

    def test_mirror_and_sae(self):
        # phit is a rate about z: it flips with alpha in the mirror image and in SAE
        P = by_name("MagicFormula61_Paramerters.tir")
        args = dict(turn_slip=True, phit=1.5)
        fz = P["fnomin"]
        o = mf.evaluate(P, 0.05, 0.04, 0.03, fz, mirror=False, **args)
        m = mf.evaluate(P, 0.05, -0.04, -0.03, fz, mirror=True, turn_slip=True, phit=-1.5)
        for q, sg in (("fx", 1), ("fy", -1), ("mz", -1)):
            self.assertAlmostEqual(float(m[q]), sg * float(o[q]), delta=1e-9 * fz)
        s = mf.evaluate(P, 0.05, -0.04, 0.03, -fz, mirror=False, convention="sae", turn_slip=True, phit=-1.5)
        for q, sg in (("fx", 1), ("fy", -1), ("mz", -1)):
            self.assertAlmostEqual(float(s[q]), sg * float(o[q]), delta=1e-9 * fz)

    def test_camber_form_keeps_the_camber_thrust(self):
        # At phit = 0 the turn slip model's Fy should be the camber thrust of
        # the model without turn slip (the spin of the camber replaces the
        # camber shift); MFeval's sign of the camber's spin reverses it, the
        # camber form (GRIP_MF_OPT_TS_CAMBER) keeps it within 3 % of the
        # camber thrust (measured 1.1 % MF 6.1, 0.6 % FSAE, 2.4 % PacejkaBook:
        # zeta2, zeta3 and eps_gamma act too)
        for name in ("MagicFormula61_Paramerters.tir", "FSAE_Defaults.tir", "PacejkaBook_Defaults.tir"):
            P = by_name(name)
            fz, V, g = P["fnomin"], P["longvl"], 0.05
            off = float(mf.evaluate(P, 0.0, 0.0, g, fz, vx=V)["fy"])
            z = float(mf.evaluate(P, 0.0, 0.0, 0.0, fz, vx=V)["fy"])
            mfe = float(mf.evaluate(P, 0.0, 0.0, g, fz, vx=V, turn_slip=True, phit=0.0)["fy"])
            cam = float(mf.evaluate(P, 0.0, 0.0, g, fz, vx=V, turn_slip=True, phit=0.0, ts_camber=True)["fy"])
            self.assertLess(abs(cam - off), 0.03 * abs(off - z) + 1e-6 * fz, name)
            self.assertLess((mfe - z) * (off - z), 0.0, name)     # MFeval's sign: the other side of Fy(gamma = 0)
            print(f"# {name}: Fy at gamma = 0.05, phit = 0: no turn slip {off:.1f} N, MFeval {mfe:.1f} N, "
                  f"camber form {cam:.1f} N (gamma = 0: {z:.1f} N)")


class UseModes(unittest.TestCase):
    def test_use_mode_codes(self):
        self.assertEqual(mf.use_mode(111), dict(limits=True, alpha_star=False, turn_slip=False))
        self.assertEqual(mf.use_mode(212), dict(limits=False, alpha_star=False, turn_slip=True))
        self.assertEqual(mf.use_mode(121), dict(limits=True, alpha_star=True, turn_slip=False))
        for bad in (0, 11, 113, 131, 311, 1111, 100):
            with self.assertRaises(ValueError):
                mf.use_mode(bad)

    def test_no_limits_is_the_model_without_low_speed_and_e_limits(self):
        for n, P in all_params():
            fz = P["fnomin"]
            # above VXLOW and with every E below 1 the modes agree
            a = mf.evaluate(P, 0.05, 0.03, 0.0, fz, vx=P["longvl"], details=True)
            b = mf.evaluate(P, 0.05, 0.03, 0.0, fz, vx=P["longvl"], limits=False, details=True)
            if all(float(a["details"][e]) < 1.0 for e in ("Ex", "Ey", "Et")):
                for q in ("fx", "fy", "mz"):
                    self.assertAlmostEqual(float(a[q]), float(b[q]), delta=1e-9 * fz, msg=(n, q))
            # below VXLOW 2xx has no low-speed model: the slips act in full
            lo = mf.evaluate(P, 0.05, 0.03, 0.0, fz, vx=0.5 * P["vxlow"], limits=False)
            self.assertAlmostEqual(float(lo["fx"]), float(b["fx"]), delta=1e-6 * fz, msg=n)
            z = mf.evaluate(P, 0.05, 0.03, 0.0, fz, vx=0.0)
            self.assertEqual(float(z["fx"]), 0.0)

    def test_given_omega_is_mfevals_input(self):
        # MFeval's input column 8: Re = Romega(omega) - deflection, Omega = omega
        P = by_name("MagicFormula61_Paramerters.tir")
        R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
        fz, om = 0.8 * Fz0, 35.0
        e = mf.evaluate_ext(P, 0.0, 0.0, 0.0, fz, omega=om)
        cz = P["vertical_stiffness"]
        re = (R0 * (P["q_re0"] + P["q_v1"] * (om * R0 / V0) ** 2)
              - Fz0 / cz * (P["dreff"] * math.atan(P["breff"] * fz / Fz0) + P["freff"] * fz / Fz0))
        self.assertAlmostEqual(float(e["re"]), re, places=12)
        self.assertEqual(float(e["omega"]), om)
        self.assertLess(abs(float(mf.evaluate_ext(P, 0.0, 0.0, 0.0, fz)["omega"]) - V0 / re), 1.0)

    def test_no_limits_reports_signed_muy(self):
        P = by_name("FSAE_Defaults.tir")     # PDY1 < 0 with LMUY = 1? sign of mu_y as fitted
        a = mf.evaluate_ext(P, 0.0, 0.1, 0.0, P["fnomin"])
        b = mf.evaluate_ext(P, 0.0, 0.1, 0.0, P["fnomin"], limits=False)
        self.assertEqual(float(a["muy"]), abs(float(b["muy"])))


if __name__ == "__main__":
    unittest.main()
