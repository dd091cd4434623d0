"""grip analyze --holdout and grip analyze apply: an update fitted on one
record predicts another record of the same tyre (the state effect runs over
the whole new history), and both hold-out splits are reported."""
import contextlib
import io
import json
import os
import tempfile
import unittest

import numpy as np

from grip_tools import cli
from grip_tools.loop import datasets
from grip_tools.loop import io as loop_io


def grip(*args):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli.main(list(args))
        except SystemExit as e:          # argparse's usage errors
            code = e.code
    return code, out.getvalue(), err.getvalue()


class ApplyUpdate(unittest.TestCase):
    def test_thermal_update_predicts_a_new_record(self):
        with tempfile.TemporaryDirectory() as d:
            fit_ds, _ = datasets.make("thermal", seed=1)
            new_ds, _ = datasets.make("thermal", seed=2)
            fit_csv, new_csv = os.path.join(d, "fit.csv"), os.path.join(d, "new.csv")
            loop_io.write_csv(fit_csv, fit_ds)
            loop_io.write_csv(new_csv, new_ds)
            code, verdict, _ = grip("analyze", fit_csv, "--tir", datasets.TIR, "--holdout", "forward:0.3",
                                    "-o", os.path.join(d, "a"))
            print(f"\n# thermal, forward hold-out: {verdict.strip()[-220:]}")
            self.assertEqual(code, 0)
            self.assertIn("hold-out forward:0.3", verdict)
            self.assertIn("on hold-out blocks:8", verdict)
            with open(os.path.join(d, "a", "update.json")) as f:
                self.assertEqual(json.load(f)["effect"], "thermal")
            out_csv = os.path.join(d, "pred.csv")
            code, text, _ = grip("analyze", "apply", os.path.join(d, "a", "update.json"), new_csv,
                                 "--tir", datasets.TIR, "-o", out_csv)
            print("# apply on a new record: " + "; ".join(text.strip().splitlines()))
            self.assertEqual(code, 0)
            back = loop_io.read_csv(out_csv)
            for o in new_ds.outputs:
                before = np.sqrt(np.mean((back.ch[o] - back.ch[f"{o}_model"]) ** 2))
                after = np.sqrt(np.mean((back.ch[o] - back.ch[f"{o}_updated"]) ** 2))
                self.assertLess(after, 0.5 * before, o)

    def test_bad_holdout_and_update(self):
        with tempfile.TemporaryDirectory() as d:
            code, _, err = grip("analyze", "--generate", "none", "--holdout", "forward:2", "-o", d)
            self.assertEqual(code, 2)
            bad = os.path.join(d, "u.json")
            with open(bad, "w") as f:
                f.write('{"effect": "no_such_effect", "params": {}}')
            ds, _ = datasets.make("none", seed=1)
            csv_path = os.path.join(d, "x.csv")
            loop_io.write_csv(csv_path, ds)
            code, _, err = grip("analyze", "apply", bad, csv_path, "--tir", datasets.TIR)
            self.assertEqual(code, 3)
            self.assertIn("unknown effect 'no_such_effect'", err)


if __name__ == "__main__":
    unittest.main()
