"""Foundation checks: the committed kernel header matches its generator, the
stack tool finds recursion and sums call paths, golden headers carry their
provenance."""
import os
import tempfile
import unittest

from grip_tools.golden import io as golden_io, q16 as golden_q16, q16_kernels as kernels
from grip_tools.golden import f32_kernels
from grip_tools.evaluate import stack
from grip_tools.paths import REPO_ROOT

ROOT = REPO_ROOT


class KernelsTest(unittest.TestCase):
    def test_committed_header_matches_generator(self):
        with open(os.path.join(ROOT, "lib", "arith", "q16_kernels.h")) as f:
            self.assertEqual(f.read(), kernels.render_header(),
                             "lib/arith/q16_kernels.h is stale: run grip kernels")

    def test_sine_kernel_limit_is_enforced(self):
        """The C sine returns its kernel unclamped: the generator refuses a
        table that rises above 1 anywhere, and accepts the committed one."""
        import numpy as np
        name, func, bits, _, limit = kernels.SEGMENTED[0]
        self.assertEqual(name, "SIN")
        rows = kernels.segment_table(func, bits)
        self.assertLessEqual(kernels.check_limit(rows, bits, limit), limit)
        bad = rows.copy()
        bad[(1 << bits) - 1, 0] += 64     # the last segment 64 LSB higher
        with self.assertRaises(ValueError):
            kernels.check_limit(bad, bits, limit)
        bad = rows.copy()
        bad[3, 1] = limit                 # a low segment rising to the limit
        with self.assertRaises(ValueError):
            kernels.check_limit(bad, bits, limit)
        self.assertTrue(np.all(rows[:, 0] <= limit))

    def test_committed_float_header_matches_generator(self):
        with open(os.path.join(ROOT, "lib", "arith", "f32_kernels_coefs.h")) as f:
            self.assertEqual(f.read(), f32_kernels.render_header(),
                             "lib/arith/f32_kernels_coefs.h is stale: run grip kernels-f32")


class ConfigCheckTest(unittest.TestCase):
    """grip_config_check.h refuses what it documents (GRIP_FLOAT_KERNELS
    here: 0, 1, 2 in the float build, 0 in the fixed build), and the float
    kernels compile with the library's strict flags at every level."""

    def cc(self, *defs, src=None):
        import subprocess
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "t.c")
            with open(path, "w") as f:
                f.write(src or '#include "grip/grip_types.h"\nint grip_t;\n')
            return subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-Wconversion",
                                   "-Wdouble-promotion", "-fsyntax-only", "-I" + os.path.join(ROOT, "include"),
                                   "-I" + os.path.join(ROOT, "lib", "arith")] + list(defs) + [path],
                                  capture_output=True, text=True)

    def test_float_kernels_levels(self):
        for lvl in (0, 1, 2):
            r = self.cc("-DGRIP_ARITH_FIXED=0", f"-DGRIP_FLOAT_KERNELS={lvl}",
                        src='#include "arith.h"\nfloat t(float x);\nfloat t(float x) '
                            '{ return r_atan(x) + r_atan2(x, 1.0f) + r_sin(x) + r_cos(x) + r_exp(x); }\n')
            self.assertEqual(r.returncode, 0, r.stderr)
        r = self.cc("-DGRIP_ARITH_FIXED=0", "-DGRIP_FLOAT_KERNELS=3")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("GRIP_FLOAT_KERNELS must be 0", r.stderr)
        r = self.cc("-DGRIP_ARITH_FIXED=1", "-DGRIP_FLOAT_KERNELS=1")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("needs GRIP_ARITH_FIXED=0", r.stderr)
        self.assertEqual(self.cc("-DGRIP_ARITH_FIXED=1").returncode, 0)


class StackTest(unittest.TestCase):
    def _ci(self, text):
        d = tempfile.mkdtemp()
        with open(os.path.join(d, "a.ci"), "w") as f:
            f.write(text)
        return d

    def test_sums_deepest_path_and_charges_externals(self):
        d = self._ci('node: { title: "grip_a" label: "grip_a\\nx.c:1:1\\n16 bytes (static)" }\n'
                     'node: { title: "b" label: "b\\nx.c:2:1\\n32 bytes (static)" }\n'
                     'node: { title: "c" label: "c\\nx.c:3:1\\n8 bytes (static)" }\n'
                     'node: { title: "__aeabi_ldivmod" label: "__aeabi_ldivmod" }\n'
                     'edge: { sourcename: "grip_a" targetname: "b" }\n'
                     'edge: { sourcename: "grip_a" targetname: "c" }\n'
                     'edge: { sourcename: "c" targetname: "__aeabi_ldivmod" }\n')
        frames, _, edges = stack.load([os.path.join(d, "a.ci")])
        total, ext = stack.worst_case(frames, edges)
        self.assertEqual(total["grip_a"], 16 + max(32, 8 + 64))
        self.assertIn("__aeabi_ldivmod", ext)

    def test_recursion_is_an_error(self):
        d = self._ci('node: { title: "f" label: "f\\nx.c:1:1\\n8 bytes (static)" }\n'
                     'node: { title: "g" label: "g\\nx.c:1:1\\n8 bytes (static)" }\n'
                     'edge: { sourcename: "f" targetname: "g" }\n'
                     'edge: { sourcename: "g" targetname: "f" }\n')
        frames, _, edges = stack.load([os.path.join(d, "a.ci")])
        with self.assertRaises(SystemExit):
            stack.worst_case(frames, edges)


class GoldenHeaderTest(unittest.TestCase):
    def test_header_records_generator_seed_and_reference_hash(self):
        h = golden_io.header("golden_q16", golden_q16.reference, 7, ["a", "b"], {"p": 1})
        self.assertIn("# seed: 7", h)
        self.assertRegex(h, r"# reference: reference sha256:[0-9a-f]{16}")
        self.assertIn("# param p: 1", h)
        self.assertTrue(h.endswith("# columns: a b\n"))


if __name__ == "__main__":
    unittest.main()
