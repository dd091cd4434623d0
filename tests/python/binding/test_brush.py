"""grip.brush against `grip-tire --model NAME --params FILE` (port/linux),
both builds, bit for bit (as test_mf: %.9g recovers float32 and Q23.8 below
1e6 N exactly): every model, its default set and a set with other values
(for Neo-FIALA every coupling on), files read by grip_tools and by
grip-tire's own reader compiled into the binding. Also: the field formats
and per-kN scales the binding reads from grip_brush.h agree with
grip_tools.reference.brush.C_UNITS, and errors name the value."""
import csv
import io
import os
import tempfile

import numpy as np

import grip
from grip_tools.reference import brush as ref
from . import common
from .common import ARITHS

SETS = {
    "fiala": dict(ky=72000.0, mu=0.93, l=0.17, fz_min=150.0, fz_max=9000.0, alpha_max=0.5),
    "brush": dict(kx=90000.0, mu_s=1.2, mu_d0=0.85, a_v=0.01, n=3, kappa_max=0.8, v_max=50.0),
    "sakai": dict(k=60000.0, g_y=200000.0, mu_s=1.1, mu_d=0.7, l=0.16, alpha_max=0.5, kappa_max=0.9),
    "neofiala": dict(n=5, q0=0.1, c_q=1.0e-5, c_qm=2.0e-5, c_xc=5.0e-6, xi=1.0e-6, eps=5.0e-5, g_mz=9000.0,
                     a_x=3.0, c_gamma=0.5, h=0.05, g_my=30000.0, a_v=0.006),
}


def points(seed, n=1200):
    rng = np.random.default_rng(seed)
    g = np.linspace(-1.0, 1.0, 41)
    return dict(kappa=np.concatenate([g * 1.2, rng.uniform(-1.1, 1.2, n)]),
                alpha=np.concatenate([g * 0.7, rng.uniform(-0.7, 0.7, n)]),
                gamma=np.concatenate([g * 0.25, rng.uniform(-0.25, 0.25, n)]),
                fz=np.concatenate([np.linspace(-100.0, 11000.0, 41), rng.uniform(100.0, 10500.0, n)]),
                p=np.zeros(41 + n),
                vx=np.concatenate([g * 70.0, rng.uniform(-40.0, 65.0, n)]))


class TestBrush(common.BindingTest):
    def test_against_grip_tire(self):
        with tempfile.TemporaryDirectory() as d:
            for model in grip.brush.MODELS:
                for which, values in (("default", {}), ("set", SETS[model])):
                    p = ref.MODELS[model](**values)
                    self.assertEqual(ref.validate(model, p), [], (model, which))
                    path = os.path.join(d, f"{model}_{which}.params")
                    ref.write_params(path, model, p)
                    pts = points(len(model) + len(which))
                    cols = ("kappa", "alpha", "gamma", "fz", "p", "vx")
                    text = ",".join(cols) + "\n" + "\n".join(
                        ",".join(repr(float(pts[c][i])) for c in cols) for i in range(len(pts["fz"]))) + "\n"
                    for arith in ARITHS:
                        exe = common.need_program(self, arith, "grip-tire")
                        rc, out, err = common.run([exe, "--model", model, "--params", path, "--no-unit-check"], text)
                        self.assertIn(rc, (0, 1), err)
                        rows = list(csv.reader(io.StringIO(out)))[1:]
                        for reader in ("tools", "c"):
                            with self.subTest(model=model, set=which, arith=arith, reader=reader):
                                bp = grip.brush.load(path, reader=reader)
                                r = grip.brush.evaluate(bp, pts["kappa"], pts["alpha"], pts["gamma"], pts["fz"],
                                                        pts["vx"], arith=arith, raw=True)
                                for j, name in enumerate(("fx", "fy", "mz")):
                                    printed = np.array([common.decode(arith, row[6 + j]) for row in rows])
                                    ok = common.same_bits(arith, printed, r[name])
                                    self.assertTrue(ok.all(), f"{name} differs at {np.flatnonzero(~ok)[:5]}")
                                np.testing.assert_array_equal([int(row[9]) for row in rows], r["status"])

    def test_formats_are_the_tools_formats(self):
        for arith in ARITHS:
            for model in grip.brush.MODELS:
                mine = [(n, f, s) for n, f, s, _u in grip.brush.fields(model, arith)]
                self.assertEqual(mine, [tuple(x) for x in ref.C_UNITS[model]], model)

    def test_errors_name_the_value(self):
        with self.assertRaises(grip.GripError) as cm:
            grip.brush.params("neofiala", mu_s=0.5, mu_d0=0.9).struct("fixed")
        self.assertEqual(cm.exception.status, grip.ERR_PARAM)
        self.assertIn("grip_neofiala_check_params", str(cm.exception))
        with self.assertRaises(grip.GripError) as cm:
            grip.brush.params("fiala", bogus=1.0).struct("float")
        self.assertEqual(cm.exception.param, "bogus")
        with self.assertRaises(grip.GripError) as cm:
            grip.brush.params("fiala", ky=1e7).struct("fixed")
        self.assertEqual(cm.exception.param, "ky")
        self.assertIn("Q23.8", str(cm.exception))
