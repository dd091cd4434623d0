"""Golden vectors for the Q15.16 primitives (include/grip/grip_q16.h).

Inputs cover each function's whole int32 domain: log-uniform magnitudes from
1 LSB to the format's limit with both signs, uniform raw values, and the edge
cases (0, +-1 LSB, +-MAX, INT32_MIN, saturation thresholds). Expected values
are float64 numpy evaluations of the exact function at the exact input
value, clamped to the representable range (the saturating semantics).
"""
import argparse
import os
import sys

import numpy as np

from grip_tools.golden.io import header

SCALE = 65536.0
QMAX = 2**31 - 1
QMIN = -(2**31 - 1)
SEED = 20261122
N = 20000


def _clamp(v):
    return np.clip(v, QMIN / SCALE, QMAX / SCALE)


def _raw_domain(rng, n, lo_exp=0, hi_exp=31, signed=True):
    """Raw int32 values with log-uniform magnitude in [2^lo_exp, 2^hi_exp)."""
    mag = np.floor(2.0 ** rng.uniform(lo_exp, hi_exp, n)).astype(np.int64)
    mag = np.minimum(mag, QMAX)
    if signed:
        mag = mag * rng.choice([-1, 1], n)
    uni = rng.integers(QMIN, QMAX, n // 4, endpoint=True)
    edges = np.array([0, 1, -1, 2, -2, 65535, 65536, 65537, -65536, QMAX, QMIN, -2**31,
                      32768, -32768, 205887, -205887, 102944, -102944], dtype=np.int64)
    return np.concatenate([edges, mag, uni])


def reference(name, a, b):
    """float64 value of the primitive at raw inputs a (and b)."""
    x = a / SCALE
    y = None if b is None else b / SCALE
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if name == "mul":
            return _clamp(x * y)
        if name == "div":
            r = np.where(b == 0, np.sign(a) * np.inf, x / np.where(b == 0, 1, y))
            return _clamp(np.nan_to_num(r, nan=0.0, posinf=np.inf, neginf=-np.inf))
        if name == "sqrt":
            return np.sqrt(np.maximum(x, 0.0))
        if name == "atan":
            return np.arctan(x)
        if name == "atan2":
            return np.where((a == 0) & (b == 0), 0.0, np.arctan2(x, y))
        if name == "sin":
            return np.sin(x)
        if name == "cos":
            return np.cos(x)
        if name == "exp":
            return _clamp(np.exp(x))
        if name == "log":
            return np.where(a > 0, np.log(np.where(a > 0, x, 1.0)), QMIN / SCALE)
    raise ValueError(name)


def vectors(rng):
    out = []
    unary = {
        "sqrt": _raw_domain(rng, N, signed=True),
        "atan": _raw_domain(rng, N),
        "sin": _raw_domain(rng, N),
        "cos": _raw_domain(rng, N),
        # exp: all of int32; the interesting part is |x| < 12
        "exp": np.concatenate([_raw_domain(rng, N),
                               rng.integers(-12 * 65536, 12 * 65536, N)]),
        "log": _raw_domain(rng, N, signed=True),
    }
    for name, a in unary.items():
        out.append((name, a, None))
    for name in ("mul", "div", "atan2"):
        a = _raw_domain(rng, N)
        b = _raw_domain(rng, N)
        rng.shuffle(b)
        if name == "mul":
            # keep many products inside the range, not just saturated ones
            a = np.concatenate([a, _raw_domain(rng, N, 0, 23)])
            b = np.concatenate([b, _raw_domain(rng, N, 0, 23)])
        out.append((name, a, b))
    return out


def write_golden(outdir):
    return main(["-o", os.path.join(outdir, "q16.txt")])


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip golden-q16", description=__doc__)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(SEED)
    rows = 0
    with open(args.output, "w") as f:
        f.write(header("golden_q16", reference, SEED, ["func", "a_raw", "b_raw", "expected"]))
        for name, a, b in vectors(rng):
            exp = reference(name, a, b)
            bb = np.zeros_like(a) if b is None else b
            for ai, bi, ei in zip(a.tolist(), bb.tolist(), exp.tolist()):
                f.write(f"{name} {ai} {bi} {ei!r}\n")
                rows += 1
    print(f"golden-q16: {rows} vectors -> {args.output}", file=sys.stderr)
    return 0
