"""grip.mf against `grip-tire` (port/linux/grip_tire.c), both builds: the
same parameter struct (every coefficient as stored, `--dump-params`), and
the same forces, moment and status at every point, bit for bit.

grip-tire prints forces with %.9g: that recovers every float32 exactly,
and every Q23.8 value below 1e6 N exactly (common.decode); the points stay
below. Each file is evaluated on a grid through the clamping limits, on
random points (including Fz <= 0, vx < 0, p = 0), combined and pure slip,
and with the side, SAE and kappa-braking options.
"""
import csv
import glob
import io
import os

import numpy as np

import grip
from . import common
from .common import ARITHS, ROOT

TIRS = sorted(glob.glob(os.path.join(ROOT, "tests", "data", "mfeval-tir", "*.tir"))) + \
    [os.path.join(ROOT, "tests", "data", "tir", n) for n in ("minimal.tir", "units.tir", "crlf_bar.tir")]
COLS = ("kappa", "alpha", "gamma", "fz", "p", "vx")


def points(params, seed=0, n=1500):
    rng = np.random.default_rng(seed)
    fnom = params.values["fnomin"]
    nom = params.values["nompres"] or 2e5
    k = np.concatenate([np.linspace(-1.6, 1.6, 33), rng.uniform(-1.6, 1.6, n)])
    m = k.size
    a = np.concatenate([np.linspace(-1.7, 1.7, 33), rng.uniform(-1.7, 1.7, n)])
    g = np.concatenate([np.linspace(-0.6, 0.6, 33), rng.uniform(-0.6, 0.6, n)])
    fz = np.concatenate([np.linspace(-0.1, 4.5, 33) * fnom, rng.uniform(-0.05, 4.2, n) * fnom])
    p = np.concatenate([np.zeros(33), rng.uniform(0.4, 2.2, n) * nom])
    p[rng.random(m) < 0.2] = 0.0
    vx = np.concatenate([np.linspace(-310, 310, 33), rng.uniform(-40, 60, n)])
    return dict(kappa=k, alpha=a, gamma=g, fz=fz, p=p, vx=vx)


def grip_tire(test, arith, tir, pts, args=()):
    exe = common.need_program(test, arith, "grip-tire")
    lines = [",".join(COLS)] + [",".join(repr(float(pts[c][i])) for c in COLS) for i in range(len(pts["kappa"]))]
    # the points cover the clamped domain beyond the plausible ranges (a slip
    # angle of 1.7 rad): --no-unit-check evaluates them as the library does
    rc, out, err = common.run([exe, "--tir", tir, "--no-unit-check"] + list(args), "\n".join(lines) + "\n")
    test.assertIn(rc, (0, 1), err)
    rows = list(csv.reader(io.StringIO(out)))
    test.assertEqual(rows[0][-4:], ["fx", "fy", "mz", "status"])
    return rows[1:]


class TestMagicFormula(common.BindingTest):
    def compare(self, arith, tir, options, pure=False, lanes=False):
        params = grip.mf.load(tir, **options)
        pts = points(params, seed=len(tir) + 7 * pure)
        args = (["--pure"] if pure else []) + (["--side", options["side"]] if options.get("side") else []) \
            + (["--sae"] if options.get("sae") else []) + (["--kappa-braking"] if options.get("kappa_braking") else []) \
            + (["--lanes"] if lanes else [])
        rows = grip_tire(self, arith, tir, pts, args)
        r = grip.mf.evaluate(params, pts["kappa"], pts["alpha"], pts["gamma"], pts["fz"], pts["p"], pts["vx"],
                             arith=arith, pure=pure, raw=True, lanes=lanes)
        self.assertEqual(len(rows), len(pts["kappa"]))
        for j, name in enumerate(("fx", "fy", "mz")):
            printed = np.array([common.decode(arith, row[6 + j]) for row in rows])
            ok = common.same_bits(arith, printed, r[name])
            self.assertTrue(ok.all(), f"{os.path.basename(tir)} {arith} {options} pure={pure}: {name} differs at "
                            f"{np.flatnonzero(~ok)[:5]}: grip-tire {printed[~ok][:3]} binding {r[name][~ok][:3]}")
        st = np.array([int(row[9]) for row in rows])
        np.testing.assert_array_equal(st, r["status"])
        return r["status"]

    def test_against_grip_tire(self):
        seen = set()
        for arith in ARITHS:
            for tir in TIRS:
                for pure in (False, True):
                    with self.subTest(arith=arith, tir=os.path.basename(tir), pure=pure):
                        seen.update(self.compare(arith, tir, {}, pure).tolist())
        # the points reach the clamp warning as well as plain results
        self.assertTrue({grip.OK, grip.WARN_CLAMPED} <= seen, seen)

    def test_lanes_against_grip_tire_lanes(self):
        """evaluate(lanes=True) and `grip-tire --lanes` (one row per lane
        call, the block padded with copies of it): the same lane code, bit
        for bit, every shared file, combined and pure, both builds."""
        for arith in ARITHS:
            for tir in TIRS:
                for pure in (False, True):
                    with self.subTest(arith=arith, tir=os.path.basename(tir), pure=pure):
                        self.compare(arith, tir, {}, pure, lanes=True)
            self.compare(arith, TIRS[0], {"side": "right", "sae": True, "kappa_braking": True}, lanes=True)

    def test_lanes_against_the_default_path(self):
        """evaluate(lanes=True) (grip_mf_eval_prepared_lanes): every status
        the default path's; outputs within 2e-5 Fz (Mz: Fz R0, Fz after the
        clamp) in float (grip's kernels against libm), bit for bit in fixed
        (no lane form there). The largest difference is printed."""
        for arith in ARITHS:
            worst = 0.0
            for tir in TIRS:
                for opts in ({}, {"sae": True, "side": "right"}):
                    params = grip.mf.load(tir, **opts)
                    for pure in (False, True):
                        pts = points(params, seed=3 + pure)
                        args = (pts["kappa"], pts["alpha"], pts["gamma"], pts["fz"], pts["p"], pts["vx"])
                        r0 = grip.mf.evaluate(params, *args, arith=arith, pure=pure)
                        r1 = grip.mf.evaluate(params, *args, arith=arith, pure=pure, lanes=True)
                        np.testing.assert_array_equal(r0["status"], r1["status"])
                        if arith == "fixed":
                            for name in ("fx", "fy", "mz"):
                                np.testing.assert_array_equal(r0[name], r1[name])
                            continue
                        fz = np.minimum(np.abs(pts["fz"]), 4.0 * params.values["fnomin"])
                        loaded = (r0["status"] >= 0) & (fz > 0)
                        scale = {"fx": fz, "fy": fz, "mz": fz * params.values["unloaded_radius"]}
                        for name in ("fx", "fy", "mz"):
                            d = np.abs(r0[name] - r1[name])
                            self.assertTrue((d[~loaded] == 0).all())
                            if loaded.any():
                                worst = max(worst, float(np.max(d[loaded] / scale[name][loaded])))
            print(f"# {arith}: lanes=True against the default path: max |diff| / (Fz, Fz R0) = {worst:.2e}",
                  flush=True)
            self.assertLessEqual(worst, 2e-5 if arith == "float" else 0.0)

    def test_options_against_grip_tire(self):
        tir = os.path.join(ROOT, "tests", "data", "mfeval-tir", "MagicFormula61_Paramerters.tir")
        for arith in ARITHS:
            for opts in ({"side": "right"}, {"side": "left"}, {"sae": True}, {"kappa_braking": True},
                         {"side": "right", "sae": True, "kappa_braking": True}):
                with self.subTest(arith=arith, **opts):
                    self.compare(arith, tir, opts)

    def test_parameters_as_grip_tire_stores_them(self):
        for arith in ARITHS:
            exe = common.need_program(self, arith, "grip-tire")
            for tir in TIRS:
                rc, out, err = common.run([exe, "--tir", tir, "--dump-params"])
                self.assertEqual(rc, 0, err)
                theirs = {k.strip(): float(v) for k, v in (ln.split("=") for ln in out.splitlines())}
                p = grip.mf.load(tir)
                mine = p.stored(arith)
                self.assertEqual(theirs.pop("FITTYP"), p.fittyp)
                self.assertEqual(theirs.pop("TYRESIDE"), p.tyreside)
                theirs.pop("OPTIONS")
                self.assertEqual(set(theirs), set(mine))
                bad = {k: (theirs[k], mine[k]) for k in mine if theirs[k] != mine[k]}
                self.assertEqual(bad, {}, f"{tir} {arith}")

    def test_c_reader_gives_the_same_struct(self):
        for tir in TIRS:
            a = grip.mf.load(tir, reader="tools")
            c = grip.mf.load(tir, reader="c")
            self.assertEqual(a.values, c.values, tir)
            self.assertEqual((a.fittyp, a.tyreside), (c.fittyp, c.tyreside))
            for arith in ARITHS:
                ffi = grip._core.backend(arith).ffi
                self.assertEqual(ffi.buffer(a.struct(arith))[:], ffi.buffer(c.struct(arith))[:], (tir, arith))

    def test_coefficient_list_is_the_tools_list(self):
        from grip_tools.reference import tir
        for arith in ARITHS:
            mine = [(f, k, s, fmt, d, r) for f, k, s, fmt, d, r in grip.mf.coefficients(arith)]
            theirs = [(c.field, c.key, c.section, c.fmt, c.default, c.required) for c in tir.coefficients()]
            self.assertEqual(mine, theirs)
