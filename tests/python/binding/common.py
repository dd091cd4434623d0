"""What the binding's tests share: the binding itself (a test fails, not
skips, when it is not built: `make setup` builds it), the programs and
libraries of the Makefile's builds (absent: the test is skipped with the
reason), and the bit-exact comparison of printed numbers."""
import os
import subprocess
import unittest

import numpy as np

from grip_tools.paths import REPO_ROOT

from grip import _core

ROOT = REPO_ROOT
ARITHS = ("float", "fixed")
BUILD = {a: os.path.join(ROOT, "build", f"{a}-gcc") for a in ARITHS}


def program(arith, name):
    return os.path.join(BUILD[arith], "bin", name)


def need_program(test, arith, name):
    path = program(arith, name)
    if not os.path.exists(path):
        test.skipTest(f"{os.path.relpath(path, ROOT)} not built (make{' ARITH=fixed' if arith == 'fixed' else ''} progs)")
    return path


def run(cmd, stdin_text=None, timeout=300):
    p = subprocess.run(cmd, input=stdin_text, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def decode(arith, text, fmt="QL"):
    """A number printed by a grip program as the build's grip_real_t value it
    came from: float: the float32 (%.9g round-trips every float32); fixed:
    the Q integer (exact while |value| < 1e6: %.9g keeps 3 decimals there,
    finer than half of 2^-8; checked)."""
    v = float(text)
    if arith == "float":
        return np.float32(v)
    if abs(v) >= 1e6:
        raise AssertionError(f"{text}: too large to recover a Q value from 9 digits")
    s = 256.0 if fmt == "QL" else 65536.0
    return np.int32(round(v * s))


def same_bits(arith, a, b):
    """Element-wise: the same grip_real_t (float: the same value, so +0 and
    -0 compare equal: grip-tire prints -0 as 0)."""
    a = np.asarray(a)
    b = np.asarray(b)
    if arith == "float":
        return (a.astype(np.float32) == b.astype(np.float32)) | (np.isnan(a) & np.isnan(b))
    return a.astype(np.int64) == b.astype(np.int64)


def binding_ok():
    for a in ARITHS:
        _core.backend(a)


class BindingTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        binding_ok()
