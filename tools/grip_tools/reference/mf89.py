"""1989-style lateral Magic Formula with coefficients a0..a17: float64 reference.

Source: seed 000 (the doctoral thesis), chapter 3.4, eqs. (3.1)-(3.9) for the
model and (3.10)-(3.16) for the identification constraints. The extracted
text lost minus signs and absolute-value bars; the forms below are the
seed's own coefficient numbering with the signs re-derived from the
Bakker-Nyborg-Pacejka lateral form and from the seed's constraints (see
docs/mf89-thermal.md for every choice):

    Fy(alpha) = D sin[C atan{B x - E (B x - atan(B x))}] + Sv       (3.1, 3.2)
    x   = alpha + Sh                                                 (3.3)
    C   = a0                                                         (3.4)
    D   = (a1 Fz^2 + a2 Fz) (1 - a15 gamma^2)                        (3.5)
    BCD = a3 sin(2 atan(Fz / a4)) (1 - a5 |gamma|)                   (3.6)
    E   = (a6 Fz + a7) (1 - (a16 gamma + a17) sgn(alpha + Sh))       (3.7)
    Sh  = (a8 Fz + a9 + a10 gamma) Fz                                (3.8)
    Sv  = a11 Fz^2 + a12 Fz + (a13 Fz^2 + a14 Fz) gamma              (3.9)
    B   = BCD / (C D)

Units of the coefficients are the seed's: Fz in kN, alpha, gamma and Sh in
degrees, D, Sv and Fy in N, BCD in N/deg, B in 1/deg. The public function
`fy89(params, alpha, fz, gamma)` takes SI inputs (rad, N, rad) like the C
library and converts; `fy89_seed_units` takes the seed's units directly.

Sign convention: the seed's (3.1)-(3.3): Fy has the sign of alpha + Sh
(positive cornering stiffness); JASO axes (seed Fig. 1).
"""
from dataclasses import dataclass, field

import numpy as np

N_COEF = 18
DEG = np.pi / 180.0

# name, meaning, unit (Fz in kN, angles in deg)
COEF_INFO = [
    ("a0", "shape factor C", "-"),
    ("a1", "peak factor, quadratic load term", "N/kN^2"),
    ("a2", "peak factor, linear load term (~ friction x 1000)", "N/kN"),
    ("a3", "maximum cornering stiffness", "N/deg"),
    ("a4", "load at maximum cornering stiffness", "kN"),
    ("a5", "camber reduction of the cornering stiffness", "1/deg"),
    ("a6", "curvature factor, load term", "1/kN"),
    ("a7", "curvature factor, constant", "-"),
    ("a8", "horizontal shift, quadratic load term", "deg/kN^2"),
    ("a9", "horizontal shift, linear load term", "deg/kN"),
    ("a10", "horizontal shift, camber term", "deg/(deg kN)"),
    ("a11", "vertical shift, quadratic load term", "N/kN^2"),
    ("a12", "vertical shift, linear load term", "N/kN"),
    ("a13", "vertical shift, camber x quadratic load term", "N/(deg kN^2)"),
    ("a14", "vertical shift, camber x linear load term", "N/(deg kN)"),
    ("a15", "camber reduction of the peak factor", "1/deg^2"),
    ("a16", "curvature asymmetry, camber term", "1/deg"),
    ("a17", "curvature asymmetry, constant", "-"),
]

# A plausible passenger-car set (the seed's identified values did not survive
# extraction; its figures show Fz = 3..9 kN, gamma = -4..4 deg, peak
# friction ~1). It satisfies every constraint (3.10)-(3.16) over
# DEFAULT_FZ_RANGE_KN and +-DEFAULT_LIMITS["gamma_max_deg"].
DEFAULT_PARAMS = np.array([
    1.45,      # a0  C
    -30.0,     # a1  N/kN^2
    1200.0,    # a2  N/kN     -> mu = 1.11 at 3 kN, 1.02 at 6 kN, 0.93 at 9 kN
    1400.0,    # a3  N/deg    -> BCD ~ 1284 N/deg (74 kN/rad) at 4.6 kN
    7.0,       # a4  kN
    0.01,      # a5  1/deg
    -0.05,     # a6  1/kN
    -0.2,      # a7
    0.0,       # a8  (3.13)
    0.0,       # a9  (3.13)
    0.006,     # a10 deg/(deg kN)
    0.0,       # a11 (3.13)
    0.0,       # a12 (3.13)
    -0.5,      # a13 N/(deg kN^2)
    18.0,      # a14 N/(deg kN)
    0.0015,    # a15 1/deg^2
    0.02,      # a16 1/deg
    0.0,       # a17 (3.12)
])

# Valid input range of the model (the C library clamps to it).
DEFAULT_LIMITS = {"fz_max_kn": 10.0, "alpha_max_deg": 25.0, "gamma_max_deg": 8.0}
# Load range over which the identification constraints are checked.
DEFAULT_FZ_RANGE_KN = (1.0, 10.0)

# Numeric limits of the seed's constraints.
C_MIN, C_MAX = 1.0, 1.65          # (3.10)
E_MAX = 1.0                        # (3.11)
SH_PER_GAMMA_MAX = 0.1             # (3.14) |dSh/dgamma| <= 0.1 deg/deg
SV_PER_GAMMA_PER_FZ_MAX = 25.0     # (3.15) |dSv/dgamma| < 25 Fz  (N/deg, Fz in kN)


def factors(params, alpha_deg, fz_kn, gamma_deg):
    """B, C, D, E, Sh, Sv of eqs. (3.4)-(3.9) (seed units), broadcast over inputs."""
    a = np.asarray(params, dtype=float)
    if a.shape != (N_COEF,):
        raise ValueError(f"params must have {N_COEF} entries, got shape {a.shape}")
    alpha = np.asarray(alpha_deg, dtype=float)
    fz = np.asarray(fz_kn, dtype=float)
    g = np.asarray(gamma_deg, dtype=float)
    C = a[0] + 0.0 * (alpha + fz + g)
    D = (a[1] * fz**2 + a[2] * fz) * (1.0 - a[15] * g**2)
    BCD = a[3] * np.sin(2.0 * np.arctan(fz / a[4])) * (1.0 - a[5] * np.abs(g))
    Sh = (a[8] * fz + a[9] + a[10] * g) * fz
    E = (a[6] * fz + a[7]) * (1.0 - (a[16] * g + a[17]) * np.sign(alpha + Sh))
    Sv = a[11] * fz**2 + a[12] * fz + (a[13] * fz**2 + a[14] * fz) * g
    CD = C * D
    with np.errstate(divide="ignore", invalid="ignore"):
        B = np.where(CD != 0.0, BCD / np.where(CD != 0.0, CD, 1.0), 0.0)
    return {"B": B, "C": C, "D": D, "E": E, "Sh": Sh, "Sv": Sv, "BCD": BCD}


def fy89_seed_units(params, alpha_deg, fz_kn, gamma_deg):
    """Lateral force [N] for alpha [deg], Fz [kN], gamma [deg] (eqs. 3.1-3.9)."""
    f = factors(params, alpha_deg, fz_kn, gamma_deg)
    x = np.asarray(alpha_deg, dtype=float) + f["Sh"]
    bx = f["B"] * x
    y = f["D"] * np.sin(f["C"] * np.arctan(bx - f["E"] * (bx - np.arctan(bx))))
    return y + f["Sv"]


def fy89(params, alpha, fz, gamma):
    """Lateral force [N] of the seed's 1989-style Magic Formula.

    params: 18 coefficients a0..a17 in the seed's units (COEF_INFO);
    alpha: slip angle [rad]; fz: vertical load [N]; gamma: camber [rad].
    Inputs broadcast (numpy). No clamping: this is the bare formula.
    """
    return fy89_seed_units(params, np.asarray(alpha, dtype=float) / DEG,
                           np.asarray(fz, dtype=float) / 1000.0,
                           np.asarray(gamma, dtype=float) / DEG)


# ---------------------------------------------------------------------------
# Identification constraints (3.10)-(3.16)
# ---------------------------------------------------------------------------

@dataclass
class Constraints:
    """The seed's identification constraints in a form a fitter can use.

    lower/upper: box bounds for a0..a17 (np.inf where none); a strict seed
      inequality (1.0 < C < 1.65) is given as its closed bound.
    fixed: {index: value} equalities (3.12, 3.13): remove these from the
      free vector, or pass lower == upper to a solver that accepts it.
    linear_A, linear_b: linear inequalities A @ params <= b (3.15 at both ends
      of the load range; exact because dSv/dgamma / Fz is linear in Fz).
    nonlinear: list of (label, g) with g(params) -> array, satisfied where
      every element is > 0 (3.11, E < 1 at every corner of the load/camber
      box and both signs of alpha + Sh; E is bilinear, so corners suffice).
    """
    fz_range_kn: tuple
    gamma_max_deg: float
    lower: np.ndarray
    upper: np.ndarray
    fixed: dict
    linear_A: np.ndarray
    linear_b: np.ndarray
    nonlinear: list = field(default_factory=list)

    def free_index(self):
        return np.array([i for i in range(N_COEF) if i not in self.fixed], dtype=int)

    def free_bounds(self):
        """(lb, ub) of the free coefficients, e.g. for scipy least_squares."""
        idx = self.free_index()
        return self.lower[idx], self.upper[idx]

    def expand(self, free_values):
        """Full 18-vector from the free coefficients and the fixed ones."""
        p = np.zeros(N_COEF)
        p[self.free_index()] = free_values
        for i, v in self.fixed.items():
            p[i] = v
        return p

    def margins(self, params):
        """All inequality margins (> 0 where satisfied), for penalty terms:
        b - A p for the linear set followed by every nonlinear g(p)."""
        p = np.asarray(params, dtype=float)
        parts = [self.linear_b - self.linear_A @ p]
        parts += [np.atleast_1d(g(p)) for _, g in self.nonlinear]
        return np.concatenate(parts)


def _e_corners(params, fz_range_kn, gamma_max_deg):
    a = np.asarray(params, dtype=float)
    vals = []
    for fz in fz_range_kn:
        for g in (-gamma_max_deg, gamma_max_deg):
            for s in (-1.0, 1.0):
                vals.append((a[6] * fz + a[7]) * (1.0 - (a[16] * g + a[17]) * s))
    return np.array(vals)


def constraints(fz_range_kn=DEFAULT_FZ_RANGE_KN, gamma_max_deg=DEFAULT_LIMITS["gamma_max_deg"]):
    """Bounds, equalities and inequalities of the seed's constraints (3.10)-(3.16)
    for identification data spanning fz_range_kn (kN) and |gamma| <= gamma_max_deg."""
    lo, hi = float(fz_range_kn[0]), float(fz_range_kn[1])
    if not (0.0 < lo <= hi):
        raise ValueError("fz_range_kn must satisfy 0 < lo <= hi")
    lower = np.full(N_COEF, -np.inf)
    upper = np.full(N_COEF, np.inf)
    lower[0], upper[0] = C_MIN, C_MAX                  # (3.10)
    lower[4] = 0.0                                     # a4 > 0: the load of max stiffness
    lower[15] = 0.0                                    # (3.16) a15 > 0
    # (3.14): with a8 = a9 = 0, dSh/dgamma = a10 Fz, |.| <= 0.1 over the range
    upper[10] = SH_PER_GAMMA_MAX / hi
    lower[10] = -SH_PER_GAMMA_MAX / hi
    fixed = {17: 0.0,                                  # (3.12)
             8: 0.0, 9: 0.0, 11: 0.0, 12: 0.0}         # (3.13)
    for i, v in fixed.items():
        lower[i] = upper[i] = v
    # (3.15): |a13 Fz + a14| < 25 at Fz = lo and hi
    A = np.zeros((4, N_COEF))
    b = np.full(4, SV_PER_GAMMA_PER_FZ_MAX)
    for k, fz in enumerate((lo, hi)):
        A[2 * k, 13], A[2 * k, 14] = fz, 1.0
        A[2 * k + 1, 13], A[2 * k + 1, 14] = -fz, -1.0
    nonlinear = [("3.11 E < 1", lambda p: E_MAX - _e_corners(p, (lo, hi), gamma_max_deg))]
    return Constraints((lo, hi), float(gamma_max_deg), lower, upper, fixed, A, b, nonlinear)


@dataclass
class ConstraintResult:
    eq: str
    text: str
    ok: bool
    value: float      # the worst value of the constrained quantity
    limit: str


def check_constraints(params, fz_range_kn=DEFAULT_FZ_RANGE_KN,
                      gamma_max_deg=DEFAULT_LIMITS["gamma_max_deg"]):
    """Check a coefficient set against (3.10)-(3.16); one ConstraintResult per
    constraint, worst case over the load range and |gamma| <= gamma_max_deg."""
    a = np.asarray(params, dtype=float)
    if a.shape != (N_COEF,):
        raise ValueError(f"params must have {N_COEF} entries")
    lo, hi = float(fz_range_kn[0]), float(fz_range_kn[1])
    fz = np.linspace(lo, hi, 64)
    res = []
    c = a[0]
    res.append(ConstraintResult("3.10", "1.0 < C < 1.65", bool(C_MIN < c < C_MAX), float(c),
                                "(1.0, 1.65)"))
    e_max = float(np.max(_e_corners(a, (lo, hi), gamma_max_deg)))
    res.append(ConstraintResult("3.11", "E < 1 over the load/camber range", bool(e_max < E_MAX),
                                e_max, "< 1"))
    res.append(ConstraintResult("3.12", "a17 = 0 (E symmetric at zero camber)", bool(a[17] == 0.0),
                                float(a[17]), "= 0"))
    sh0 = np.max(np.abs((a[8] * fz + a[9]) * fz))
    sv0 = np.max(np.abs(a[11] * fz**2 + a[12] * fz))
    res.append(ConstraintResult("3.13", "Sh = Sv = 0 at zero camber (a8 = a9 = a11 = a12 = 0)",
                                bool(sh0 == 0.0 and sv0 == 0.0), float(max(sh0, sv0)), "= 0"))
    shg = float(np.max(np.abs(a[10] * fz)))
    res.append(ConstraintResult("3.14", "|dSh/dgamma| <= 0.1 deg/deg", bool(shg <= SH_PER_GAMMA_MAX),
                                shg, "<= 0.1"))
    svg = float(np.max(np.abs(a[13] * fz + a[14])))
    res.append(ConstraintResult("3.15", "|dSv/dgamma| < 25 Fz N/deg (Fz in kN)",
                                bool(svg < SV_PER_GAMMA_PER_FZ_MAX), svg, "< 25 N/(deg kN)"))
    res.append(ConstraintResult("3.16", "a15 > 0 (peak falls with camber)", bool(a[15] > 0.0),
                                float(a[15]), "> 0"))
    return res


def constraints_ok(params, **kw):
    return all(r.ok for r in check_constraints(params, **kw))


def constraints_report(params, **kw):
    lines = []
    for r in check_constraints(params, **kw):
        lines.append(f"({r.eq}) {'ok  ' if r.ok else 'FAIL'} {r.text}: {r.value:.6g} (limit {r.limit})")
    return "\n".join(lines)


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip mf89", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--params", help="18 comma-separated coefficients (default: the documented set)")
    ap.add_argument("--fz-range", default=f"{DEFAULT_FZ_RANGE_KN[0]},{DEFAULT_FZ_RANGE_KN[1]}",
                    help="load range in kN for the constraint check")
    ap.add_argument("--gamma-max", type=float, default=DEFAULT_LIMITS["gamma_max_deg"])
    args = ap.parse_args(argv)

    def numbers(opt, text, count):
        try:
            vals = [float(v) for v in text.split(",")]
        except ValueError:
            vals = []
        if len(vals) != count or not all(np.isfinite(vals)):
            ap.error(f"{opt} {text!r}: {count} comma-separated finite numbers")
        return vals
    p = DEFAULT_PARAMS if args.params is None else np.array(numbers("--params", args.params, 18))
    fr = tuple(numbers("--fz-range", args.fz_range, 2))
    if not 0.0 < fr[0] < fr[1]:
        ap.error(f"--fz-range {args.fz_range!r}: a load range LO,HI in kN with 0 < LO < HI")
    if not (np.isfinite(args.gamma_max) and 0.0 <= args.gamma_max <= 90.0):
        ap.error(f"--gamma-max {args.gamma_max!r}: a camber in [0, 90] deg")
    print(constraints_report(p, fz_range_kn=fr, gamma_max_deg=args.gamma_max))
    return 0 if constraints_ok(p, fz_range_kn=fr, gamma_max_deg=args.gamma_max) else 1


if __name__ == "__main__":
    import sys
    sys.exit(main())
