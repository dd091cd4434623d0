"""grip faults (tools/grip_tools/evaluate/faults.py): options it cannot run
with are refused with exit 2 and the option named, before anything is
written or simulated."""
import contextlib
import io
import os
import tempfile
import unittest

from grip_tools.evaluate import faults


class CommandLineTests(unittest.TestCase):
    def test_bad_options_are_refused(self):
        for args, said in ((["--only", "("], "--only '('"), (["--jobs", "0"], "--jobs: 0")):
            err = io.StringIO()
            with tempfile.TemporaryDirectory() as d, contextlib.redirect_stderr(err):
                out = os.path.join(d, "out")
                with self.assertRaises(SystemExit) as cm:
                    faults.main(["--out", out, "--skip-suite"] + args)
                self.assertFalse(os.path.exists(out), args)
            self.assertEqual(cm.exception.code, 2, args)
            self.assertIn(said, err.getvalue(), args)


if __name__ == "__main__":
    unittest.main()
