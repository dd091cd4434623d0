"""Polynomial kernels of the float build's math functions
(lib/arith/f32_kernels_coefs.h, used by lib/arith/f32_kernels.h when
GRIP_FLOAT_KERNELS = 1).

Each kernel is a minimax polynomial (Remez exchange in float64) for the
RELATIVE error of the function on its reduced range, written in the form the
C code evaluates (a leading term kept exact: t + t^3 P(t^2), 1 - z/2 +
z^2 P(z), 1 + r + r^2 P(r)), then rounded to float. The fit error printed is
the polynomial's own, in float64; the end-to-end error of each float
function (reduction, rounding of every operation) is measured by
tests/unit/test_f32_kernels.c against double-precision libm, over the whole
float domain (docs/numerics.md, "Float kernels").

    grip kernels-f32 [-o lib/arith/f32_kernels_coefs.h]
"""
import numpy as np


def remez(g, w, lo, hi, n, iters=40, grid=200001):
    """Coefficients c[0..n-1] of the polynomial P minimizing
    max |w(x) (g(x) - P(x))| over [lo, hi], and that maximum (on a grid of
    `grid` points)."""
    xs = np.linspace(lo, hi, grid)
    gx, wx = g(xs), w(xs)
    k = np.arange(n + 1)
    # start at the Chebyshev zeros, inside the interval: the sine's weight
    # vanishes at z = 0, so a reference point there levels nothing, the first
    # error curve has one sign run too few and the exchange stopped at once
    # (kept going only where the last bits of the error near 0 happened to
    # change sign, which differs between numpy builds)
    ref = (lo + hi) / 2 - (hi - lo) / 2 * np.cos(np.pi * (k + 0.5) / (n + 1))
    best = None
    for _ in range(iters):
        a = np.zeros((n + 1, n + 1))
        a[:, :n] = ref[:, None] ** np.arange(n)
        a[:, n] = (-1.0) ** np.arange(n + 1) / w(ref)
        c = np.linalg.solve(a, g(ref))[:n]
        err = wx * (gx - np.polyval(c[::-1], xs))
        emax = float(np.max(np.abs(err)))
        if best is None or emax < best[1]:
            best = (c, emax)
        # one extremum per run of equal sign, then keep n + 1 alternating
        sign = np.signbit(err)
        cuts = np.flatnonzero(sign[1:] != sign[:-1]) + 1
        idx = np.array([s[np.argmax(np.abs(err[s]))] for s in np.split(np.arange(grid), cuts)])
        while len(idx) > n + 1:
            idx = idx[1:] if abs(err[idx[0]]) < abs(err[idx[-1]]) else idx[:-1]
        if len(idx) < n + 1:
            break
        ref = xs[idx]
    return best


def _safe(z):
    return np.maximum(z, 1e-300)


def _series(z, coefs):
    return sum(c * z ** i for i, c in enumerate(coefs))


# atan(t) = t + t^3 P(t^2), t in [0, 1]
def _g_atan(z):
    t = np.sqrt(_safe(z))
    return np.where(z > 1e-3, (np.arctan(t) - t) / _safe(z) ** 1.5,
                    _series(z, [-1 / 3, 1 / 5, -1 / 7, 1 / 9, -1 / 11, 1 / 13, -1 / 15]))


def _w_atan(z):
    return _safe(z) ** 1.5 / np.arctan(np.sqrt(_safe(z)))


# sin(r) = r + r^3 P(r^2), |r| <= pi/2 (and a little: the rounding of m);
# cos(x) is sin(r) of x - m pi/2 with m odd, so no cosine polynomial.
# The target (sin(r) - r) / r^3 is its Taylor series in z = r^2, summed by
# Horner in float64 (+ and * only): np.sin's last bits differ between numpy
# builds, and the cancellation in sin(r) - r made the fit, and so the
# committed coefficients, depend on them.
_SIN_TERMS = 14


def _sin_tail(z):
    """(sin(r) - r) / r^3 at z = r^2: sum of (-1)^(k+1) z^k / (2k + 3)!."""
    acc = np.zeros_like(np.asarray(z, dtype=float))
    for k in range(_SIN_TERMS - 1, -1, -1):
        fact = float(np.prod(np.arange(1, 2 * k + 4, dtype=float)))
        acc = acc * z + ((-1.0) ** (k + 1)) / fact
    return acc


def _g_sin(z):
    return _sin_tail(z)


def _w_sin(z):
    # r^3 / sin(r) = z / (1 + z (sin(r) - r) / r^3)
    return z / (1.0 + z * _sin_tail(z))


R_TRIG = np.pi / 2 + 1e-3          # |r| after the reduction by m pi/2
R_EXP = np.log(2) / 2 * 1.01        # |r| after the reduction by k ln 2

# name, fit, what the C code evaluates
KERNELS = [
    ("ATAN", lambda: remez(_g_atan, _w_atan, 1e-9, 1.0, 8),
     "atan(t) = t + t^3 P(t^2), t in [0, 1]: coefficients of P, z^0 first"),
    ("SIN", lambda: _sin_fit(),
     "sin(r) = r + r^3 P(r^2), |r| <= pi/2: coefficients of P, z^0 first,\n * nudged in float so that cos(0) = 1 (f32_kernels.py, _sin_fit)"),
    # e^r: the full polynomial minimax for the relative error, whose first
    # two coefficients round to exactly 1 in float; the C code writes it as
    # 1 + r + r^2 P(r) with P the rest
    ("EXP", lambda: _exp_fit(),
     "exp(r) = 1 + r + r^2 P(r), |r| <= ln(2)/2: coefficients of P, r^0 first"),
]


def _f32_sin(r, c):
    """r + r^3 P(r^2) in float32, in the order of f32_kernels.h."""
    f = np.float32
    r = f(r)
    z = r * r
    p = (c[1] * z + c[0]) + (z * z) * (c[3] * z + c[2])
    return r + (r * z) * p


def _sin_fit():
    """The minimax sine, rounded to float, then the float coefficients
    nudged by a few units in the last place (a small search) to the set with
    the smallest float32 error on a dense grid among those for which the
    reduced argument of cos(0), -(pi/2 as the four parts), gives exactly 1:
    cos 0 = 1 and sin of the float nearest pi/2 = 1, as libm gives."""
    c, e = remez(_g_sin, _w_sin, 1e-9, R_TRIG ** 2, 4)
    f = np.float32
    c = [f(x) for x in c]
    parts = [f(float(v)) for v, in [(v,) for _n, v, _w in constants()[:4]]]
    r0 = -((((f(0) - parts[0]) - parts[1]) - parts[2]) - parts[3])
    rs = np.linspace(1e-4, R_TRIG, 200001).astype(np.float32)
    r64 = rs.astype(np.float64)
    exact = r64 + r64 * (r64 * r64) * _sin_tail(r64 * r64)

    def grid_error(k):
        return float(np.max(np.abs(_f32_sin(rs, k).astype(np.float64) - exact) / exact))

    def step(v, d):
        for _ in range(abs(d)):
            v = np.nextafter(v, f(np.inf) if d > 0 else f(-np.inf))
        return v

    best = None
    for d0 in range(-4, 5):
        for d1 in range(-12, 13, 2):
            for d2 in range(-6, 7, 2):
                k = [step(c[0], d0), step(c[1], d1), step(c[2], d2), c[3]]
                if _f32_sin(r0, k) != f(1.0):
                    continue
                err = grid_error(k)
                if best is None or err < best[0]:
                    best = (err, k)
    if best is None:
        raise RuntimeError("sin fit: no nudged coefficient set gives cos(0) = 1")
    return [float(x) for x in best[1]], e


def _exp_fit():
    c, e = remez(np.exp, lambda r: 1.0 / np.exp(r), -R_EXP, R_EXP, 7)
    if np.float32(c[0]) != 1.0 or np.float32(c[1]) != 1.0:
        raise RuntimeError("exp fit: the constant and linear coefficients do not round to 1")
    return c[2:], e


# 100 digits of pi and ln 2: the splits below are exact rational arithmetic.
PI = "3.141592653589793238462643383279502884197169399375105820974944592307816406286208998628034825342117068"
LN2 = "0.693147180559945309417232121458176568075500134360255254120680009493393621969694715605863326996418688"


def split(value, bits, parts):
    """value (a decimal string, > 0) as `parts` floats: each but the last
    truncated to `bits` significant bits (so that k * part is exact for
    |k| < 2^(24 - bits), and every part is positive: x - 0 * part keeps the
    sign of a zero x), the last rounded to float; and what is left over."""
    from fractions import Fraction
    rest = Fraction(value) if not isinstance(value, Fraction) else value
    out = []
    for i in range(parts):
        b = bits if i < parts - 1 else 24
        e = rest.numerator.bit_length() - rest.denominator.bit_length()
        # scale so that the value has b bits before the point
        scale = Fraction(2) ** (b - 1 - e)
        m = (rest * scale).__floor__() if i < parts - 1 else round(rest * scale)
        if abs(m) >= 2 ** b:
            scale /= 2
            m = (rest * scale).__floor__() if i < parts - 1 else round(rest * scale)
        part = Fraction(m) / scale
        out.append(part)
        rest -= part
    return out, rest


def _fmt(x):
    """x rounded to float, as a literal that reads back as that float."""
    return f"{float(np.float32(float(x))):.9g}f"


def constants():
    """(name, value, comment) of the reduction constants."""
    from fractions import Fraction
    pi = Fraction(PI)
    out = []
    # trigonometric reduction x - m pi/2 for |m| < 2^(24 - 17) = 128
    parts, rest = split(pi / 2, TRIG_PART_BITS, 4)
    for i, v in enumerate(parts):
        out.append((f"GRIP_KF_PIO2_{i + 1}", v, f"pi/2, part {i + 1}" +
                    (f" ({TRIG_PART_BITS} significant bits)" if i < 3 else f"; pi/2 - parts {float(rest):.2e}")))
    out.append(("GRIP_KF_2_OVER_PI", 2 / pi, "2/pi, rounded"))
    ln2 = Fraction(LN2)
    parts, rest = split(ln2, EXP_PART_BITS, 2)
    out.append(("GRIP_KF_LN2_HI", parts[0], f"ln 2, {EXP_PART_BITS} significant bits"))
    out.append(("GRIP_KF_LN2_LO", parts[1], f"ln 2 - LN2_HI, rounded; ln 2 - both {float(rest):.2e}"))
    out.append(("GRIP_KF_LOG2E", 1 / ln2, "1 / ln 2, rounded"))
    for name, v in (("PIO2", pi / 2), ("PI", pi)):
        hi = Fraction(float(np.float32(float(v))))
        lo = Fraction(float(np.float32(float(v - hi))))
        out.append((f"GRIP_KF_{name}_HI", hi, f"{name.lower().replace('o', '/')} rounded to float"))
        out.append((f"GRIP_KF_{name}_LO", lo, f"{name.lower().replace('o', '/')} - {name}_HI, rounded"))
    return out


TRIG_PART_BITS = 17
EXP_PART_BITS = 17


def render_header():
    out = [
        "/* Generated by `grip kernels-f32` (tools/grip_tools/golden/f32_kernels.py).",
        " * Do not edit: regenerate. Minimax coefficients (relative error), rounded",
        " * to float; used by f32_kernels.h (GRIP_FLOAT_KERNELS = 1). */",
        "#ifndef GRIP_F32_KERNELS_COEFS_H",
        "#define GRIP_F32_KERNELS_COEFS_H",
        "",
    ]
    for name, fit, what in KERNELS:
        coef, err = fit()
        out.append(f"/* {what}\n * polynomial fit error (relative, float64) {err:.2e} */")
        out.append(f"#define GRIP_KF_{name}_N {len(coef)}")
        for i, c in enumerate(coef):
            out.append(f"#define GRIP_KF_{name}_{i} ({_fmt(np.float32(c))})")
        out.append("")
    out.append("/* Constants of the argument reductions (exact splits of pi/2 and ln 2). */")
    for name, v, what in constants():
        out.append(f"#define {name} ({_fmt(v)}) /* {what} */")
    out.append("")
    out.append("#endif /* GRIP_F32_KERNELS_COEFS_H */")
    return "\n".join(out) + "\n"


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip kernels-f32", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", default="lib/arith/f32_kernels_coefs.h")
    args = ap.parse_args(argv)
    text = render_header()
    with open(args.output, "w") as f:
        f.write(text)
    print(text)
