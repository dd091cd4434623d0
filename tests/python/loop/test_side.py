"""A .tir is evaluated as fitted unless told otherwise: a null data set taken
on a tyre whose file says TYRESIDE = 'RIGHT' (MagicFormula61_Paramerters.tir)
must name no effect; mounted left (mirrored) the same data no longer fit."""
import contextlib
import io
import os
import tempfile
import unittest

from grip_tools import cli
from grip_tools.loop import datasets
from grip_tools.loop import io as loop_io
from grip_tools.reference import tir


def analyze(*args):
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = cli.main(["analyze", *args])
    return code, out.getvalue()


class TyreAsFitted(unittest.TestCase):
    def test_null_set_from_a_right_side_file(self):
        self.assertEqual(tir.read_tir(datasets.TIR).tyreside, -1)
        ds, _ = datasets.make("none", seed=3)          # the tyre as its file describes it, plus noise
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "null.csv")
            loop_io.write_csv(path, ds)
            code, verdict = analyze(path, "--tir", datasets.TIR, "-o", os.path.join(d, "a"))
            print(f"\n# null set, RIGHT-side .tir as fitted: {verdict.strip()}")
            self.assertEqual(code, 0)
            self.assertIn("no effect found", verdict)
            with open(os.path.join(d, "a", "report.md")) as f:
                self.assertIn("fitted for RIGHT, mounted right: as fitted", f.read())
            code, verdict = analyze(path, "--tir", datasets.TIR, "--side", "left", "-o", os.path.join(d, "b"))
            print(f"# the same data with the tyre mounted left (mirrored): {verdict.strip()}")
            self.assertIn("looks like a tyre-side error", verdict)

    def test_sign_and_unit_errors_are_named_first(self):
        ds, _ = datasets.make("none", seed=4)
        with tempfile.TemporaryDirectory() as d:
            for change, words in ((-1.0, "a sign error"), (1e-3, "a unit error: kN (or kN m) labelled N")):
                bad = loop_io.Dataset(ds.t, dict(ds.ch, fy=change * ds.ch["fy"]), dict(ds.units), list(ds.outputs))
                path = os.path.join(d, "x.csv")
                loop_io.write_csv(path, bad)
                code, verdict = analyze(path, "--tir", datasets.TIR, "-o", os.path.join(d, "o"))
                print(f"# fy x {change:g}: {verdict.strip()[:160]}")
                self.assertTrue(verdict.startswith("the base model does not fit the data"), verdict)
                self.assertIn(words, verdict)


if __name__ == "__main__":
    unittest.main()
