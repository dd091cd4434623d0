"""Every tyre effect the analyze tool adds runs in the C library with the
tool's fitted parameters, and the C output matches the tool's updated model.

For each effect the tool fits its parameters on the undeclared-effect data
set (datasets.make), writes the update (report.effect_update / write_tir),
and tests/python/onboard_driver.c — built here against
build/<variant>/libgrip.a and libgrip_port.a for each built variant
(float-gcc, fixed-gcc; a variant not built is skipped) — runs it:

  slip_velocity_friction  updated .tir with LMUV -> grip_mf_eval
  relaxation              grip_relax (sigma), stepped with the current row -> grip_mf_eval
  thermal                 grip_mf_thermal state (grip_mf_thermal_params from
                          update.json) + grip_mf_eval with LMUX/LMUY, LKX/LKY
                          scaled by the state's temperature
  load_sensitivity        updated .tir with PDY2/PDX2 -> grip_mf_eval
  camber                  updated .tir with PKY6/PVY3 -> grip_mf_eval with the
                          rows' gamma and p (driver mode mfgp)
  inflation_pressure      updated .tir with PPX1/PPY1/PPX3/PPY3 -> grip_mf_eval
                          with the rows' gamma and p (mfgp)
(camber and pressure are fitted on test_residual.make_gp, the data sets with
gamma and p varying; the tool's prediction is mf.evaluate of the updated set)

Tolerance on |C - tool| per force: float 1e-4 Fz, fixed 2e-3 Fz (those of
grip-tire against mf.py, docs/tools.md: the composition adds no error beyond
the library's own). Relaxation adds, per row, the relaxed slips' own error
(checked against lib/relax's documented budget: fixed 2e-4 + 5.6e-6/dt
|x - x'_prev|, float 1e-4 max(|x|, 0.01) + 1e-7) times the MF's slip
stiffnesses. The measured maxima are printed and documented in
docs/measured-data-loop.md.
"""
import os
import subprocess
import tempfile
import unittest

import numpy as np

from grip_tools.loop import datasets
from grip_tools.reference import mf_thermal
from grip_tools.loop import attribution, effects, grammar, report
from grip_tools.loop.effects import TireModel
from .test_attribution import make_gp
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT
DRIVER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "onboard_driver.c")
TOL = {"float": 1e-4, "fixed": 2e-3}
VARIANTS = [v for v in ("float-gcc", "fixed-gcc")
            if os.path.exists(os.path.join(ROOT, "build", v, "libgrip.a"))
            and os.path.exists(os.path.join(ROOT, "build", v, "libgrip_port.a"))]


def build_driver(variant, outdir):
    exe = os.path.join(outdir, f"loop_driver_{variant}")
    fixed = "1" if variant.startswith("fixed") else "0"
    b = os.path.join(ROOT, "build", variant)
    cmd = ["cc", "-std=c99", "-O2", "-Wall", "-Werror", f"-DGRIP_ARITH_FIXED={fixed}",
           "-DGRIP_DEBUG_SATURATION=0", "-D_POSIX_C_SOURCE=200809L",
           "-I" + os.path.join(ROOT, "include"), "-I" + os.path.join(ROOT, "port", "linux"),
           DRIVER, os.path.join(b, "libgrip_port.a"), os.path.join(b, "libgrip.a"), "-lm", "-o", exe]
    subprocess.run(cmd, check=True, capture_output=True)
    return exe


def run_driver(exe, args, ds):
    ch = ds.ch
    if args[0] == "mfgp":
        rows = "\n".join(f"{t:.17g} {k:.17g} {a:.17g} {z:.17g} {v:.17g} {g:.17g} {p:.17g}" for t, k, a, z, v, g, p in
                         zip(ds.t, ch["kappa"], ch["alpha"], ch["fz"], ch["vx"], ch["gamma"], ch["p"]))
    else:
        rows = "\n".join(f"{t:.17g} {k:.17g} {a:.17g} {z:.17g} {v:.17g}" for t, k, a, z, v in
                         zip(ds.t, ch["kappa"], ch["alpha"], ch["fz"], ch["vx"]))
    p = subprocess.run([exe] + args, input=rows + "\n", capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    out = np.loadtxt(p.stdout.splitlines(), ndmin=2)
    return out[:, 0], out[:, 1], out[:, 2].astype(int), out[:, 3:]


@unittest.skipUnless(VARIANTS, "no build/float-gcc or build/fixed-gcc library (run make first)")
class OnboardMatchesTool(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.exe = {v: build_driver(v, cls.tmp.name) for v in VARIANTS}
        cls.model = TireModel(datasets.base_params(), "mf61", datasets.TIR)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def fit(self, effect, kind, every=1):
        ds, truth = make_gp(kind, seed=3) if kind in ("camber", "pressure") else datasets.make(kind, seed=3)
        fit_ds = ds
        if every > 1:                 # a shorter fit for speed; the comparison uses the whole record
            idx = np.arange(0, len(ds), every)
            fit_ds = type(ds)(ds.t[idx], {k: v[idx] for k, v in ds.ch.items()}, ds.units, ds.outputs, ds.meta)
        train, _ = attribution.block_masks(len(fit_ds))
        scale = {o: attribution.rms(fit_ds.ch[o][train]) for o in fit_ds.outputs}
        x = effect.fit(self.model, fit_ds, train, scale)
        return ds, x, dict(zip(effect.pnames, map(float, x)))

    def compare(self, name, ds, tool, args_of, extra_tol=None):
        """extra_tol(variant, extra columns) -> (tol_fx, tol_fy) in N per row,
        added to TOL * Fz (an upstream state's own documented error)."""
        for v, exe in self.exe.items():
            arith = v.split("-")[0]
            fx, fy, st, extra = run_driver(exe, args_of(v), ds)
            self.assertTrue(np.all(st >= 0), f"{name} {v}: C status {st.min()}")
            fz = ds.ch["fz"]
            tx = ty = TOL[arith] * fz
            if extra_tol is not None:
                ax, ay = extra_tol(v, extra)
                tx, ty = tx + ax, ty + ay
            ex = np.max(np.abs(fx - tool["fx"]) / fz)
            ey = np.max(np.abs(fy - tool["fy"]) / fz)
            print(f"\n  {name} ({v}): max |C - tool| / Fz: fx {ex:.2e}, fy {ey:.2e} "
                  f"(max abs {np.max(np.abs(fx - tool['fx'])):.3g} N, {np.max(np.abs(fy - tool['fy'])):.3g} N)")
            self.assertTrue(np.all(np.abs(fx - tool["fx"]) <= tx), f"{name} {v} fx")
            self.assertTrue(np.all(np.abs(fy - tool["fy"]) <= ty), f"{name} {v} fy")

    def test_slip_velocity_lmuv(self):
        e = effects.SlipVelocity()
        ds, x, prm = self.fit(e, "slip_velocity")
        self.assertGreater(prm["lmuv"], 0.0)
        upd = report.effect_update(e.name, prm, self.model)
        path = report.write_tir(datasets.TIR, upd["tir_update"], os.path.join(self.tmp.name, "lmuv.tir"))
        tool = e.predict(self.model, ds, x)
        self.compare(f"slip velocity LMUV={prm['lmuv']:.4g}", ds, tool, lambda v: ["mf", path])

    def test_load_sensitivity(self):
        e = effects.LoadSensitivity()
        ds, x, prm = self.fit(e, "load")
        upd = report.effect_update(e.name, prm, self.model)
        path = report.write_tir(datasets.TIR, upd["tir_update"], os.path.join(self.tmp.name, "load.tir"))
        # the tool's term (LMUY = LMUX = 1 + c dfz) equals the .tir update
        # (PDY2 += c PDY1) only to first order in c dfz^2 ... it is exact:
        # mu = (PDY1 + PDY2 dfz) (1 + c dfz) != PDY1 + (PDY2 + c PDY1) dfz by c PDY2 dfz^2.
        # So the C runs the .tir update, compared with the MF of the same update.
        P2 = dict(self.model.params, pdy2=upd["tir_update"]["PDY2"], pdx2=upd["tir_update"]["PDX2"])
        tool = TireModel(P2).predict(ds.ch)
        self.compare(f"load sensitivity PDY2={upd['tir_update']['PDY2']:.4g}", ds, tool, lambda v: ["mf", path])
        # and the .tir form keeps the fit: held-out error within 10 % of the tool's term
        _, test = attribution.block_masks(len(ds))
        term = e.predict(self.model, ds, x)
        for o in ds.outputs:
            a = attribution.rms((ds.ch[o] - term[o])[test])
            b = attribution.rms((ds.ch[o] - tool[o])[test])
            print(f"\n  load sensitivity {o}: held-out RMS tool term {a:.1f} N, .tir update {b:.1f} N")
            self.assertLess(b, 1.1 * a + 1.0)

    def gp_update(self, e, kind, fname, keys):
        """Fit effect e on make_gp(kind), write its .tir update, compare the C
        (mfgp: rows with gamma and p) with the tool's prediction."""
        ds, x, prm = self.fit(e, kind)
        upd = report.effect_update(e.name, prm, self.model)
        self.assertEqual(sorted(upd["tir_update"]), sorted(keys))
        path = report.write_tir(datasets.TIR, upd["tir_update"], os.path.join(self.tmp.name, fname))
        from grip_tools.reference import tir
        P2 = tir.load_params(path)
        for k in keys:
            self.assertAlmostEqual(P2[k.lower()], upd["tir_update"][k], places=12)
        tool = e.predict(self.model, ds, x)
        # the tool's prediction is the MF of the written file itself
        again = TireModel(P2).predict(ds.ch)
        for o in ("fx", "fy"):
            np.testing.assert_allclose(tool[o], again[o], rtol=0, atol=1e-9)
        # and it differs from the base model (the update is not a no-op)
        base = self.model.predict(ds.ch)
        self.assertGreater(np.max(np.abs(tool["fy"] - base["fy"]) / ds.ch["fz"]), 1e-2)
        self.compare(f"{e.name} " + " ".join(f"{k}={v:.5g}" for k, v in upd["tir_update"].items()), ds, tool,
                     lambda v: ["mfgp", path])
        return ds, prm

    def test_camber(self):
        self.gp_update(effects.Camber(), "camber", "camber.tir", ("PKY6", "PVY3"))

    def test_pressure(self):
        ds, _ = self.gp_update(effects.Pressure(), "pressure", "pressure.tir", ("PPX1", "PPY1", "PPX3", "PPY3"))
        # inside the C's pressure range (no dpi clamping): dpi in [-0.5, 1]
        dpi = (ds.ch["p"] - self.model.nompres) / self.model.nompres
        self.assertTrue(np.all(dpi > -0.5) and np.all(dpi < 1.0))

    def test_relaxation(self):
        e = effects.Relaxation()
        ds, x, prm = self.fit(e, "relaxation")
        tool = e.predict(self.model, ds, x)
        sigma = report.effect_update(e.name, prm, self.model)["grip_relax_params"]["sigma_alpha"]
        kt = grammar.relax_series(ds.ch["kappa"], ds.ch["vx"], ds.t, sigma)
        at = grammar.relax_series(ds.ch["alpha"], ds.ch["vx"], ds.t, sigma)
        # slip sensitivities of the MF at the relaxed slips (central differences)
        h = 1e-5
        d = {}
        for nm, base in (("kappa", kt), ("alpha", at)):
            up = self.model.predict(ds.ch, {"kappa": kt, "alpha": at, nm: base + h})
            dn = self.model.predict(ds.ch, {"kappa": kt, "alpha": at, nm: base - h})
            d[nm] = {o: np.abs(up[o] - dn[o]) / (2 * h) for o in ("fx", "fy")}

        def extra_tol(v, cols):
            # the relaxed slips' own error: lib/relax's documented fixed budget
            # (docs/measured-data-loop.md) 2e-4 + 5.6e-6 / dt |x - x'_prev| per
            # step, checked here, then carried into the forces by the slip
            # stiffnesses; float: 1e-4 max(|x|, 0.01) + 1e-7
            ek, ea = np.abs(cols[:, 0] - kt), np.abs(cols[:, 1] - at)
            dt = np.diff(ds.t, prepend=ds.t[0] - (ds.t[1] - ds.t[0]))
            if v.startswith("fixed"):
                # the step's input is the current row, its state the previous output
                kp = np.concatenate([[kt[0]], kt[:-1]])
                ap = np.concatenate([[at[0]], at[:-1]])
                bk = 2e-4 + 5.6e-6 / dt * np.abs(ds.ch["kappa"] - kp)
                ba = 2e-4 + 5.6e-6 / dt * np.abs(ds.ch["alpha"] - ap)
                bk, ba = np.maximum(bk, 2e-4), np.maximum(ba, 2e-4)
            else:
                bk = 1e-4 * np.maximum(np.abs(kt), 0.01) + 1e-7
                ba = 1e-4 * np.maximum(np.abs(at), 0.01) + 1e-7
            print(f"\n  relaxation ({v}): max |kappa' C - tool| {ek.max():.2e}, |alpha' C - tool| {ea.max():.2e} rad")
            self.assertTrue(np.all(ek <= bk) and np.all(ea <= ba), v)
            return (d["kappa"]["fx"] * ek + d["alpha"]["fx"] * ea, d["kappa"]["fy"] * ek + d["alpha"]["fy"] * ea)
        self.compare(f"relaxation sigma={sigma:.4g} m", ds, tool,
                     lambda v: ["relax", datasets.TIR, f"{float(sigma):.17g}"], extra_tol)

    def test_thermal(self):
        e = effects.Thermal()
        ds, x, prm = self.fit(e, "thermal", every=3)
        tool = e.predict(self.model, ds, x)
        th = report.effect_update(e.name, prm, self.model)["grip_mf_thermal_params"]
        path = os.path.join(self.tmp.name, "thermal.txt")
        with open(path, "w") as f:
            for k, v in th.items():
                f.write(f"{k} {float(v):.17g}\n")
        self.compare(f"thermal a={prm['a_mu_per_K']:.4g} b={prm['b_k_per_K']:.4g} kappa={prm['kappa_per_s']:.4g}",
                     ds, tool, lambda v: ["thermal", datasets.TIR, path, f"{prm['a_mu_per_K']:.17g}",
                                          f"{prm['b_k_per_K']:.17g}"])

    def test_thermal_recurrence_is_mf_thermal(self):
        """The tool's fast temperature loop equals mf_thermal.simulate (the
        float64 reference of grip_mf_thermal_step) on the same inputs."""
        ds, _ = datasets.make("thermal", seed=3)
        n = 400
        ch = {k: v[:n] for k, v in ds.ch.items()}
        prm = effects.thermal_params_from_mf(self.model.params, -0.02, -0.01, 0.05, 1500.0, 25.0)
        T = effects.thermal_temperature(prm, ch, ds.t[:n])
        alpha = ch["alpha"]
        ref = mf_thermal.simulate(prm, prm.t0, np.abs(ch["vx"]) / np.cos(alpha), -alpha, -ch["kappa"], ch["fz"],
                                  prm.t0, np.diff(ds.t[:n], append=ds.t[n - 1]))
        np.testing.assert_allclose(T, ref["t_before"], rtol=0, atol=1e-9)
        self.assertGreater(T.max() - T.min(), 1.0)


if __name__ == "__main__":
    unittest.main()
