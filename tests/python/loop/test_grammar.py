"""The candidate grammar (tools/grip_tools/loop/grammar.py): its filters and
limits, the level restriction of the named vehicle effects, the two cases
a fixed list missed (a load dependence quadratic in dfz; inflation pressure
that heats in blocks and recovers in rests, on rig data with measured Fz),
the .tir update of a constant scaling change, `grip analyze apply` with a
state-driven update on another record of the same tyre, and the
non-parametric correction when no candidate explains the residual (a
hysteresis over the sweep direction)."""
import contextlib
import io
import json
import os
import tempfile
import unittest

import numpy as np

from grip_tools import cli
from grip_tools.loop import attribution, benchmark, datasets, effects, grammar, report
from grip_tools.loop import io as loop_io
from grip_tools.loop.effects import TireModel
from grip_tools.reference import tir


def model():
    return TireModel(datasets.base_params(), "MagicFormula61_Paramerters.tir (as fitted)", datasets.TIR)


def grip(*args):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(list(args))
    return code, out.getvalue(), err.getvalue()


class Filters(unittest.TestCase):
    def test_relaxation_zero_lag_is_the_base_model(self):
        """sigma = 0 and sigma -> 0 return the input itself (not a one-sample
        delay), so lag:relax at sigma -> 0 is the base model exactly."""
        ds, _ = datasets.make("relaxation", seed=2)
        x, v, t = ds.ch["alpha"], ds.ch["vx"], ds.t
        for s in (0.0, 1e-9, 1e-6):
            np.testing.assert_array_equal(grammar.relax_series(x, v, t, s), x)
        m = model()
        ctx = grammar.Context(m, ds)
        base = m.predict(ds.ch)
        for name in ("lag:relax~const", "lag:relax2~const"):
            sp = grammar.spec(name)
            for s in (0.0, 1e-7):
                pr = sp.predict(ctx, [s] * sp.k(ctx))
                for o in ds.outputs:
                    np.testing.assert_array_equal(pr[o], base[o])
        pr = effects.Relaxation().predict(m, ds, [1e-7])
        np.testing.assert_array_equal(pr["fy"], base["fy"])
        # and a real lag: sigma = 0.5 m at 8 m/s lags alpha
        y = grammar.relax_series(x, v, t, 0.5)
        self.assertGreater(np.max(np.abs(y - x)), 1e-3)

    def test_state_heating_and_recovery(self):
        """The first-order state rises with tau_heat and falls with tau_rec."""
        dt = 0.01
        t = np.arange(3000) * dt
        u = (t < 15.0).astype(float)
        x = grammar.state_series(u, t, 2.0, 8.0)
        k = np.arange(1, 1500)
        np.testing.assert_allclose(x[k], 1 - np.exp(-k * dt / 2.0), rtol=0, atol=1e-12)
        top = x[1499]
        j = np.arange(1500, 3000)
        np.testing.assert_allclose(x[j], top * np.exp(-(j - 1499) * dt / 8.0), rtol=1e-9, atol=1e-12)

    def test_every_pair_is_counted_and_nothing_is_applied_at_zero(self):
        """Every applicable pair predicts the base model at zero modulation
        (the grammar adds a change, it never replaces the model)."""
        ds, _ = benchmark.generate("null", seed=3, duration=40.0, rate=20.0)
        m = model()
        train, _ = attribution.holdout_masks(len(ds), "forward:0.3")
        ctx = grammar.Context(m, ds, train=train)
        specs = grammar.pairs(ctx)
        self.assertGreater(len(specs), 300)
        base = m.predict(ds.ch)
        for sp in specs:
            x = np.zeros(sp.k(ctx))
            p = sp.driver.grid(ctx)[0] if sp.driver.pnames else ()
            x[sp.n_theta(ctx):] = p
            pr = sp.predict(ctx, x)
            for o in ds.outputs:
                np.testing.assert_allclose(pr[o], base[o], rtol=0, atol=1e-9 * max(1.0, np.max(np.abs(base[o]))),
                                           err_msg=sp.name)


class Level(unittest.TestCase):
    def test_no_lift_force_on_measured_load(self):
        """Rig data with a measured Fz get no downforce (aero_load) and no road
        bank candidate; declared derived, they do."""
        ds, _ = benchmark.generate("pressure_heating", seed=1, duration=60.0, rate=20.0)
        for e in (effects.AeroLoad(), effects.Bank()):
            ok, why = e.applicable(ds)
            self.assertFalse(ok)
            self.assertIn("measured", why)
        ds.meta["derived"] = ("fz", "fy")
        self.assertTrue(effects.AeroLoad().applicable(ds)[0])
        self.assertTrue(effects.Bank().applicable(ds)[0])


class IssueCases(unittest.TestCase):
    """The cases of the report against the fixed list, blind, forward hold-out."""
    @classmethod
    def setUpClass(cls):
        cls.model = model()
        cls.res = {}
        for kind in ("load_peaked", "pressure_heating"):
            ds, truth = benchmark.generate(kind, seed=1)
            res = attribution.analyse(cls.model, ds, holdout="forward:0.3")
            cls.res[kind] = (ds, truth, res, benchmark.assess(ds, truth, res))

    def test_quadratic_load_dependence(self):
        ds, truth, res, out = self.res["load_peaked"]
        print(f"\n  friction x (1 - {truth.params['c']:.3f} ln(Fz/Fz0)^2): {attribution.verdict(res)[:240]}")
        self.assertEqual(res.chosen.family[1], "dfz2")
        self.assertIn(res.chosen.family[0], benchmark.FRICTION)
        self.assertTrue(out.named and out.halved)

    def test_pressure_heating_in_blocks(self):
        ds, truth, res, out = self.res["pressure_heating"]
        print(f"\n  pressure heating {100 * truth.params['p_rise']:.1f} %: {attribution.verdict(res)[:240]}")
        self.assertEqual(res.chosen.family[0], "in:p")
        self.assertIn(res.chosen.family[1], benchmark.ENERGY)
        self.assertTrue(out.named and out.halved)
        self.assertNotIn("aero_load", [c.name for c in res.ranked])
        self.assertIn("aero_load", [n for n, _ in res.skipped])


class Updates(unittest.TestCase):
    def test_constant_scaling_is_a_tir_update(self):
        """Friction 8 % low everywhere: a constant change of LMUX/LMUY, written
        into updated.tir, which the Magic Formula evaluates to the tool's
        prediction."""
        ds, _ = benchmark.generate("null", seed=4, duration=60.0, rate=20.0)
        m = model()
        out = m.predict(ds.ch, {"lmux": 0.92, "lmuy": 0.92})
        rng = np.random.default_rng(4)
        for o in ds.outputs:
            ds.ch[o] = out[o] + 0.005 * np.max(np.abs(out[o])) * rng.standard_normal(len(ds))
        res = attribution.analyse(m, ds, holdout="forward:0.3")
        c = res.chosen
        print(f"\n  friction x 0.92: {attribution.verdict(res)[:200]}")
        self.assertIsNotNone(c)
        self.assertIn(c.family, {("mu", "const"), ("mu2", "const")})
        with tempfile.TemporaryDirectory() as d:
            _, upd = report.write(res, ds, m, d)
            self.assertEqual(upd["grammar"]["target"], c.family[0])
            P2 = tir.load_params(upd["tir_file"])
            self.assertAlmostEqual(P2["lmuy"], 0.92, delta=0.01)
            again = TireModel(P2).predict(ds.ch)
            for o in ds.outputs:
                np.testing.assert_allclose(again[o], res.chosen_pred[o], rtol=0, atol=1e-6)

    def test_apply_a_state_update_to_another_record(self):
        """A state-driven update (pneumatic trail falling as the tread heats)
        fitted on one test plan predicts another plan of the same tyre."""
        with tempfile.TemporaryDirectory() as d:
            fit_ds, truth = benchmark.generate("trail_temperature", seed=5, plan_seed=5)
            new_ds, _ = benchmark.generate("trail_temperature", seed=5, plan_seed=6)
            paths = []
            for name, ds in (("fit", fit_ds), ("new", new_ds)):
                p = os.path.join(d, f"{name}.csv")
                loop_io.write_csv(p, ds)
                paths.append(p)
            code, verdict, _ = grip("analyze", paths[0], "--tir", datasets.TIR, "--holdout", "forward:0.3",
                                    "-o", os.path.join(d, "a"))
            print(f"\n  trail temperature: {verdict.strip()[:200]}")
            self.assertEqual(code, 0)
            with open(os.path.join(d, "a", "update.json")) as f:
                upd = json.load(f)
            self.assertEqual(upd["grammar"]["target"], "trail")
            out_csv = os.path.join(d, "pred.csv")
            code, text, _ = grip("analyze", "apply", os.path.join(d, "a", "update.json"), paths[1],
                                 "--tir", datasets.TIR, "-o", out_csv)
            print("  apply on another plan: " + "; ".join(text.strip().splitlines()))
            self.assertEqual(code, 0)
            back = loop_io.read_csv(out_csv)
            before = np.sqrt(np.mean((back.ch["mz"] - back.ch["mz_model"]) ** 2))
            after = np.sqrt(np.mean((back.ch["mz"] - back.ch["mz_updated"]) ** 2))
            self.assertLess(after, 0.5 * before)


class Correction(unittest.TestCase):
    def test_no_physical_effect_gets_a_correction(self):
        """Friction higher while the slip angle grows than while it falls (a
        hysteresis: no grammar driver is the sweep direction): nothing is
        named, the verdict says so, and the non-parametric correction
        explains the held-out residual, is written to update.json and
        applied to the data again."""
        ds, truth = benchmark.generate("null", seed=3)
        m = model()
        a = ds.ch["alpha"]
        f = 1.0 + 0.08 * np.tanh(np.gradient(a, ds.t) * np.sign(a) / 0.02)
        out = m.predict(ds.ch, {"lmuy": f, "lmux": f})
        rng = np.random.default_rng(3)
        for o in ds.outputs:
            ds.ch[o] = out[o] + truth.floor[o] * rng.standard_normal(len(ds))
        res = attribution.analyse(m, ds, holdout="forward:0.3")
        verdict = attribution.verdict(res)
        print(f"\n  sweep-direction hysteresis: {verdict[-330:]}")
        self.assertIsNone(res.chosen)
        self.assertIn("no physical effect identified", verdict)
        k = res.correction
        self.assertTrue(k is not None and k.useful)
        self.assertLess(k.ho_rms["fy"], 0.6 * k.base_ho_rms["fy"])
        with tempfile.TemporaryDirectory() as d:
            _, upd = report.write(res, ds, m, d)
            self.assertIsNone(upd["effect"])
            self.assertEqual(upd["correction"]["drivers"], k.drivers)
            csv = os.path.join(d, "x.csv")
            loop_io.write_csv(csv, ds)
            code, text, _ = grip("analyze", "apply", os.path.join(d, "update.json"), csv, "--tir", datasets.TIR,
                                 "-o", os.path.join(d, "p.csv"))
            self.assertEqual(code, 0)
            back = loop_io.read_csv(os.path.join(d, "p.csv"))
            np.testing.assert_allclose(back.ch["fy_updated"], k.pred["fy"], rtol=1e-6, atol=1e-3)


if __name__ == "__main__":
    unittest.main()
