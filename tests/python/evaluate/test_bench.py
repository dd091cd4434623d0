"""grip_tools.evaluate.bench: the split of callgrind's self costs into
inside and outside the math kernels (make bench's "in kernels" columns)."""
import unittest

from grip_tools.evaluate import bench

# A callgrind output in its compressed form: names given once as "(id) name"
# and later as "(id)"; the line after "calls=" is the call's inclusive cost,
# which must not be counted again; positions relative (+n, -n, *) or absolute.
CG = """\
# callgrind format
version: 1
positions: line
events: Ir

ob=(1) /work/build/bench_host
fl=(1) lib/mf/mf_eval.c
fn=(1) grip_mf_eval_f32
10 100
+2 50
cob=(2) /usr/lib/x86_64-linux-gnu/libm.so.6
cfl=(2) s_atanf.c
cfn=(2) atanf
calls=3 20
* 999
-1 7

ob=(2)
fl=(2)
fn=(2)
20 60
* 3

ob=(1)
fl=(3) lib/arith/q16.c
fn=(3) grip_q16_atan
5 40
fn=(4) grip_q16_mul
6 11
fn=(1)
12 4
totals: 275
"""


class CallgrindSplit(unittest.TestCase):
    def test_split(self):
        total, kern = bench.callgrind_split(CG.splitlines(True))
        # grip_mf_eval 100 + 50 + 7 + 4, atanf 60 + 3, grip_q16_atan 40, grip_q16_mul 11
        self.assertEqual(total, 275)
        self.assertEqual(kern, 63 + 40)

    def test_inlined_kernel_code(self):
        # a kernel inlined into the model: its lines arrive as an inline file
        # record (fi=, back with fe=), the function being the model's; a
        # later fi= may name that file by its id alone (given first by cfi=)
        cg = """\
events: Ir
ob=(1) /work/build/bench_host
fl=(1) lib/mf/mf_equations.h
fn=(1) mf_lat_pure
10 100
cfi=(3) lib/arith/q16_math_inline.h
cfn=(2) grip_q16_atan
calls=1 5
* 30
fi=(2) /src/grip/lib/arith/q16_math_inline.h
20 70
fe=(1)
11 5
fi=(3)
21 8
fe=(1)
12 2
"""
        total, kern = bench.callgrind_split(cg.splitlines(True))
        self.assertEqual(total, 185)
        self.assertEqual(kern, 78)

    def test_kernel_names(self):
        for name in ("grip_q16_atan", "grip_q16_atan2", "grip_q16_exp", "grip_q16_sqrt", "sin_of_phase",
                     "atan_poly_q30", "atan_mag_q30.isra.0", "grip_q16_sincos"):
            self.assertTrue(bench.MATH_KERNEL_FN.match(name), name)
        for name in ("grip_q16_mul", "grip_q16_div", "grip_mf_eval_f32", "mf_lat_pure", "grip_q16_sinx"):
            self.assertFalse(bench.MATH_KERNEL_FN.match(name), name)
        for name in ("atanf", "__ieee754_atan2f", "__kernel_sinf", "sin_of_phase", "grip_q16_cos"):
            self.assertTrue(bench.M_KERNEL_FN.match(name), name)
        for name in ("__aeabi_lmul", "__muldi3", "__clzsi2"):
            self.assertTrue(bench.M_HELPER_FN.match(name), name)
        self.assertFalse(bench.M_KERNEL_FN.match("grip_mf_eval_prepared_f32"))



DECODEDLINE = """Contents of the .debug_line section:

lib/mf/mf_eval.c:
File name                            Line number    Starting address    View    Stmt
mf_eval.c                                     10               0x100               x
lib/arith/f32_kernels.h:
f32_kernels.h                                175               0x104               x
f32_kernels.h                                176               0x108       1
lib/mf/mf_eval.c:
mf_eval.c                                     11               0x108       2       x
mf_eval.c                                     12               0x10c
lib/arith/f32_kernels.h:
f32_kernels.h                                 90               0x110
f32_kernels.h                                  -               0x114
"""


class InlineKernels(unittest.TestCase):
    def test_ranges_from_the_line_table(self):
        addrs, flags = bench.decodedline_ranges(DECODEDLINE)
        # 0x108: of the two rows at one address the last (mf_eval.c) counts;
        # 0x114: the end of the sequence
        self.assertEqual(addrs, [0x100, 0x104, 0x108, 0x10c, 0x110, 0x114])
        self.assertEqual(flags, [0, 1, 0, 0, 1, 0])


class Profile(unittest.TestCase):
    """grip bench --profile: a Cortex-M trace's instructions per call of a
    case, by the function whose address range holds each one."""

    # bench_mark at 0x10; three functions, one of size 0 (counted as 2 bytes)
    FNS = [(0x10, 4, "bench_mark"), (0x100, 0x20, "case_body"), (0x200, 0x10, "kernel"), (0x300, 0, "tiny")]

    def test_spans_by_function(self):
        m = 0x10
        # the image runs "empty" then "eval" twice each: mark, call, mark;
        # between calls the harness runs code outside every span
        pcs = [0x50, m, 0x100, m, 0x60,               # empty, call 1
               m, 0x104, m,                            # empty, call 2
               m, 0x100, 0x200, 0x204, 0x300, 0x400, m,  # eval, call 1
               m, 0x108, 0x200, m]                     # eval, call 2
        prof = bench.profile_spans(iter(pcs), m, self.FNS, ["empty", "eval"], "^eval$")
        self.assertEqual(list(prof), ["eval"])
        self.assertEqual(prof["eval"], {"case_body": 1.0, "kernel": 1.5, "tiny": 0.5, "?": 0.5})
        md = bench.profile_md("m4f", prof)
        self.assertIn("### eval (m4f): 4 instructions per call", md)
        # the most expensive function first
        self.assertLess(md.index("| kernel | 1.5 | 42.9 % |"), md.index("| case_body | 1.0 |"))

    def test_no_case_matches(self):
        self.assertEqual(bench.profile_spans(iter([0x10, 0x100, 0x10]), 0x10, self.FNS, ["a"], "^b$"), {})


class CommandLine(unittest.TestCase):
    def test_bad_options_are_refused_before_measuring(self):
        import contextlib
        import io
        for args, said in ((["--cases", "("], "--cases '('"), (["--targets", "m4f,m5x"], "--targets: m5x"),
                           (["--profile", "["], "--profile '['"),
                           (["--profile", "mf61", "--targets", ""], "--profile: needs a target")):
            err = io.StringIO()
            with contextlib.redirect_stderr(err), self.assertRaises(SystemExit) as cm:
                bench.main(args)
            self.assertEqual(cm.exception.code, 2, args)
            self.assertIn(said, err.getvalue(), args)


if __name__ == "__main__":
    unittest.main()
