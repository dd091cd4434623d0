"""Float64 reference of the Magic Formula steady-state tyre model.

Written from the equations (Pacejka, Tyre and Vehicle Dynamics, 3rd ed.,
ch. 4.3.2 / App. 3; Besselink, Schmeitz, Pacejka 2010, "An improved Magic
Formula/Swift tyre model that can handle inflation pressure changes"; the
MF-Tyre departures from the book as measured in /work/shared/GUIDE.md). The
full description, the sign conventions and every choice are in
docs/magic-formula.md; keep the two in step.

Variants (params['fittyp']):
  5, 6, 21  MF 5.2 / PAC2002: no pressure terms, camber scaled by LGAX/LGAY/LGAZ,
            SHy/SVy with PHY3/PVY3/PVY4, aligning moment with Fy' = Fy - SVyk,
            SVyk with mu_y at gamma = 0 (MFeval's calculateMz)
  61, 62    MF 6.1 / 6.2: inflation pressure (NOMPRES, PP*), camber stiffness
            PKY6/PKY7, PEY5, RBX3, RBY4, QDZ10/QDZ11, aligning moment with
            Fy' = Gyk * Fy0(gamma = 0)
Forms: form='mftyre' (default, what TNO MF-Tyre / MFeval compute) or
form='book' (the Pacejka-book forms: alpha* = tan(alpha), gamma* = sin(gamma),
A_mu = 10, QBZ5/QBZ6 in Bt, |gamma*| in Dt, square-root equivalent slip
angles, Fy' with gamma = 0 in Gyk, cos(alpha) in the combined Mzr, Fz0' in s,
trail not scaled by LFZO).
Use modes (MFeval's useMode digits, docs/magic-formula.md section 10):
limits=True is MFeval's 1xx (the low-speed model, the curvature factors
E <= 1, |mu_y| as the output; the file's *_RANGE clamps and MFeval's FZMIN
floor of the aligning moment are not applied), limits=False its 2xx;
turn_slip=True its xx2: the spin phi from the turn slip phit [1/m] and the
camber (with the wheel's spin omega [rad/s], or MFeval's estimate from the
effective rolling radius when omega is 0 or None) and the zeta factors of
MFeval's Solver (calculateFx0, calculateFy0, calculateMz0, calculateFy,
calculateMz). Left out: transient relaxation dynamics; vx < 0 is handled
with |vx| (slips must be defined with |vx|).
evaluate_ext() adds MFeval's other output channels (effective rolling
radius, loaded radius and vertical stiffness with the MF 5.2/6.1 and MF 6.2
vertical models, contact patch, trail, residual moment, friction, slip
stiffnesses, structural stiffnesses, relaxation lengths, Mx, My), written
from MFeval's Solver (calculateRe, calculateRhoRl61/62, calculateFz62,
calculateContactPatch, calculateRelax, calculateMx, calculateMy);
docs/magic-formula.md section 9.

Native convention: ISO-W as MF-Tyre / MFeval (kappa > 0 driving, Fx > 0
forward, alpha > 0 gives Fy < 0 for a normal tyre, Fz > 0 loaded).
"""
import math

import numpy as np

EPS = 1e-6           # the book's epsilon (MFeval uses 1e-6 too): B and Kya' denominators
KAPPA_LIMIT = 1e4    # |kappa| beyond this is clamped (only to keep outputs finite)
ANGLE_LIMIT = math.pi / 2
VX_LIMIT = 1e3       # |vx| beyond this is clamped (slip-speed term only)
FZ_CAP = 10.0        # Fz is limited to FZ_CAP * FNOMIN
P_CAP = 10.0         # p is limited to [0, P_CAP * NOMPRES]

MF5 = (5, 6, 21)
MF6 = (61, 62)

# Sign of each quantity in SAE (J670: x forward, y right, z down) per ISO-W
# (x forward, y left, z up): value_sae = SAE_SIGN[q] * value_iso.
SAE_SIGN = {"kappa": 1, "alpha": -1, "gamma": 1, "fz": -1,
            "fx": 1, "fy": -1, "fz_out": -1, "mx": 1, "my": -1, "mz": -1}


def _sgn1(x):
    """sign with sgn(0) = +1 (epsilon terms, equivalent slip angles)."""
    return np.where(x < 0.0, -1.0, 1.0)


def _nz(x, tiny=1e-12):
    """x with exact or near zeros replaced by +-tiny (finite divisions only)."""
    return np.where(np.abs(x) < tiny, tiny * _sgn1(x), x)


def _mf(B, C, D, E, x):
    """D sin(C atan(B x - E (B x - atan(B x))))."""
    bx = B * x
    return D * np.sin(C * np.arctan(bx - E * (bx - np.arctan(bx))))


def _weight(B, C, E, x, shift):
    """cos(C atan(B x - E(B x - atan B x))) / the same at x = shift."""
    def g(u):
        bu = B * u
        return np.cos(C * np.arctan(bu - E * (bu - np.arctan(bu))))
    return g(x) / _nz(g(shift))


class _Ctx:
    pass


def _emax(c, e):
    """A curvature factor E limited to <= 1: MFeval does it in its limits
    mode (1xx) only (Ex, Ey, Et, Exa, Eyk, EHyp)."""
    return np.minimum(e, 1.0) if c.limits else e


def use_mode(code):
    """MFeval's useMode (three digits) -> dict(limits, alpha_star, turn_slip).
    Hundreds 1 = limits check, 2 = none; tens 1 = alpha as it is, 2 =
    alpha* = tan(alpha), gamma* = sin(gamma); units 1 = combined, 2 = combined
    + turn slip. ValueError for anything else."""
    code = int(code)
    h, t, u = code // 100, (code // 10) % 10, code % 10
    if not (100 <= code <= 999) or h not in (1, 2) or t not in (1, 2) or u not in (1, 2):
        raise ValueError(f"useMode {code}: not one of MFeval's (1|2)(1|2)(1|2)")
    return dict(limits=h == 1, alpha_star=t == 2, turn_slip=u == 2)


def turn_slip_usable(P):
    """The set has what the turn-slip equations divide by: PHYP1 > 0 (C_Hyp)
    and 0 < QDRP1 < 2 (C_Drp, sin(pi/2 C_Drp) > 0). Absent keys are 0."""
    return P.get("phyp1", 0.0) > 0.0 and 0.0 < P.get("qdrp1", 0.0) < 2.0


# The individual book-vs-MF-Tyre choices; form='book' sets all of them,
# form='mftyre' none. A dict form={flag: bool} switches single ones (for
# studies of each difference; not a supported model).
BOOK_FLAGS = (
    "alpha_star",   # alpha* = tan(alpha)                     (MF-Tyre: alpha)
    "gamma_star",   # gamma* = sin(gamma)                     (MF-Tyre: gamma)
    "amu10",        # A_mu = 10 in lambda'                    (MF-Tyre: 1)
    "bt_book",      # Bt camber: QBZ5|g| + QBZ6 g^2 (MF 6.x)  (MF-Tyre: QBZ4 g + QBZ5|g|)
    "dt_book",      # Dt camber: QDZ3|g| (MF 6.x)             (MF-Tyre: QDZ3 g)
    "eq_sqrt",      # alpha_eq = sqrt(alpha^2 + ...)          (MF-Tyre: atan(sqrt(tan^2 + ...)))
    "fyp_gamma0",   # Fy' weighting Gyk at gamma = 0 (MF 6.x) (MF-Tyre: Gyk keeps RBY4 gamma^2)
    "mzr_cos",      # combined Mzr times cos(alpha)           (MF-Tyre: no)
    "s_fz0p",       # s uses Fy / Fz0' (LFZO * FNOMIN)        (MF-Tyre: Fy / FNOMIN)
    "trail_nolfzo",  # trail not scaled by LFZO                (MF-Tyre: t * LFZO)
)


def _flags(form):
    if form == "mftyre":
        return {f: False for f in BOOK_FLAGS}
    if form == "book":
        return {f: True for f in BOOK_FLAGS}
    if isinstance(form, dict) and set(form) <= set(BOOK_FLAGS):
        return {f: bool(form.get(f, False)) for f in BOOK_FLAGS}
    raise ValueError(f"form must be 'mftyre', 'book' or a dict of {BOOK_FLAGS}, not {form!r}")


def _prepare(P, kappa, alpha, gamma, fz, p, vx, form, limits=True):
    """Inputs sanitized, low-speed factors, the basic quantities."""
    c = _Ctx()
    c.P = P
    c.f = _flags(form)
    c.limits = bool(limits)
    c.fittyp = int(P["fittyp"])
    if c.fittyp not in MF5 + MF6:
        raise ValueError(f"unsupported FITTYP {c.fittyp}")
    c.mf6 = c.fittyp in MF6
    if vx is None:
        vx = P["longvl"]
    if c.fittyp in MF6 and p is None:
        p = P["inflpres"] if P["inflpres"] > 0 else P["nompres"]
    if p is None:
        p = 0.0
    kappa, alpha, gamma, fz, vx, p = np.broadcast_arrays(*(np.asarray(v, dtype=float)
                                                           for v in (kappa, alpha, gamma, fz, vx, p)))
    shape = kappa.shape
    c.loaded = fz > 0.0
    Fz0 = P["fnomin"]
    c.Fz = np.clip(np.where(c.loaded, fz, 1.0), 0.0, FZ_CAP * Fz0)
    c.kappa_in = np.clip(kappa, -KAPPA_LIMIT, KAPPA_LIMIT)
    c.alpha_in = np.clip(alpha, -ANGLE_LIMIT, ANGLE_LIMIT)
    c.gamma = np.clip(gamma, -ANGLE_LIMIT, ANGLE_LIMIT)
    # speed and the low-speed reduction
    vabs = np.minimum(np.abs(vx), VX_LIMIT)
    c.vx = np.clip(vx, -VX_LIMIT, VX_LIMIT)   # signed (extended outputs only)
    vxlow = P["vxlow"]
    c.vabs = vabs
    if vxlow > 0 and c.limits:
        r = np.clip(vabs / vxlow, 0.0, 1.0)
        # the slip angle fades with the sum of the speeds |Vx| + |Vsy|,
        # Vsy = tan(alpha) |Vx| (MF-Tyre / MFeval low-speed model)
        ra = np.clip(vabs * (1.0 + np.abs(np.tan(c.alpha_in))) / vxlow, 0.0, 1.0)
    else:
        r = ra = np.ones(shape)
    c.r = r                                   # linear factor on kappa
    c.ra = ra                                 # linear factor on alpha
    c.w = 0.5 * (1.0 - np.cos(math.pi * r))   # smooth factor on shifts, trail, Mzr
    c.kappa = c.kappa_in * r
    c.alpha = c.alpha_in * ra
    # pressure
    if c.mf6:
        nom = P["nompres"]
        c.dpi = (np.clip(p, 0.0, P_CAP * nom) - nom) / nom
    else:
        c.dpi = np.zeros(shape)
    c.Fz0 = Fz0
    c.Fz0p = P["lfzo"] * Fz0
    c.dfz = (c.Fz - c.Fz0p) / c.Fz0p
    # slip and camber as they enter the equations
    c.a_s = np.tan(c.alpha) if c.f["alpha_star"] else c.alpha
    c.g_s = np.sin(c.gamma) if c.f["gamma_star"] else c.gamma
    c.cosa = np.cos(c.alpha)
    if not c.limits:
        # cos(alpha') = Vcx / (Vc + eps): 0 at Vx = 0, where MFeval's 2xx
        # (no low-speed model) also has sgn(Vcx) = 0 in Dr
        c.cosa = np.where(vabs == 0.0, 0.0, c.cosa)
    # camber per group: MF 5.2 scales it with LGAX/LGAY/LGAZ
    if c.mf6:
        c.gx, c.gy, c.gz = c.gamma, c.g_s, c.g_s
    else:
        c.gx, c.gy, c.gz = c.gamma * P["lgax"], c.g_s * P["lgay"], c.g_s * P["lgaz"]
    # friction scaling with slip speed (LMUV) and the degressive factor A_mu
    vs = vabs * np.sqrt(c.kappa ** 2 + np.tan(c.alpha) ** 2)
    den = 1.0 + P["lmuv"] * vs / P["longvl"]
    c.lmux_s = P["lmux"] / _nz(den)
    c.lmuy_s = P["lmuy"] / _nz(den)
    amu = 10.0 if c.f["amu10"] else 1.0
    c.lmux_p = amu * c.lmux_s / _nz(1.0 + (amu - 1.0) * c.lmux_s)
    c.lmuy_p = amu * c.lmuy_s / _nz(1.0 + (amu - 1.0) * c.lmuy_s)
    return c


def _fx0(c, ts=None):
    P, Fz, dfz, dpi = c.P, c.Fz, c.dfz, c.dpi
    Cx = P["pcx1"] * P["lcx"]
    mux = ((P["pdx1"] + P["pdx2"] * dfz) * (1.0 + P["ppx3"] * dpi + P["ppx4"] * dpi ** 2)
           * (1.0 - P["pdx3"] * c.gx ** 2) * c.lmux_s)
    Dx = mux * Fz
    if ts is not None:
        Dx = Dx * ts.z1                                        # 4.E12 with zeta1
    Kxk = (Fz * (P["pkx1"] + P["pkx2"] * dfz) * np.exp(P["pkx3"] * dfz)
           * (1.0 + P["ppx1"] * dpi + P["ppx2"] * dpi ** 2) * P["lkx"])
    Bx = Kxk / (Cx * Dx + EPS * _sgn1(Dx))
    SHx = (P["phx1"] + P["phx2"] * dfz) * P["lhx"] * c.w
    SVx = Fz * (P["pvx1"] + P["pvx2"] * dfz) * P["lvx"] * c.lmux_p * c.w
    if ts is not None:
        SVx = SVx * ts.z1                                      # 4.E18 with zeta1
    kx = c.kappa + SHx
    Ex = _emax(c, (P["pex1"] + P["pex2"] * dfz + P["pex3"] * dfz ** 2)
               * (1.0 - P["pex4"] * _sgn1(kx)) * P["lex"])
    Fx0 = _mf(Bx, Cx, Dx, Ex, kx) + SVx
    return dict(Fx0=Fx0, mux=mux, Dx=Dx, Cx=Cx, Bx=Bx, Ex=Ex, Kxk=Kxk, SHx=SHx, SVx=SVx)


def _fy0(c, gy, ts=None):
    """Pure lateral force at lateral camber gy (the model's gamma variable);
    with the turn-slip factors of ts (MFeval's calculateFy0) when given."""
    P, Fz, dfz, dpi = c.P, c.Fz, c.dfz, c.dpi
    z2 = 1.0 if ts is None else ts.z2
    if c.mf6:
        den = (P["pky2"] + P["pky5"] * gy ** 2) * (1.0 + P["ppy2"] * dpi)
        Kya = (P["pky1"] * c.Fz0p * (1.0 + P["ppy1"] * dpi) * (1.0 - P["pky3"] * np.abs(gy))
               * np.sin(P["pky4"] * np.arctan((Fz / c.Fz0p) / _nz(den))) * P["lky"])
        if ts is not None:
            Kya = Kya * ts.z3                                  # 4.E25 with zeta3
        Kyg0 = Fz * (P["pky6"] + P["pky7"] * dfz) * (1.0 + P["ppy5"] * dpi) * P["lkyc"]
        SVyg = Fz * (P["pvy3"] + P["pvy4"] * dfz) * gy * P["lkyc"] * c.lmuy_p
        if ts is not None:
            SVyg = SVyg * z2                                   # 4.E28 with zeta2
        Kya_p = Kya + EPS * _sgn1(Kya)
        if ts is None:
            SHy = ((P["phy1"] + P["phy2"] * dfz) * P["lhy"] + (Kyg0 * gy - SVyg) / Kya_p) * c.w
        else:
            # 4.E27 with zeta0 = 0 and zeta4 = 1 + SHyp - SVyg / Kya' (4.84)
            SHy = ((P["phy1"] + P["phy2"] * dfz) * P["lhy"] + _shyp(c, ts) - SVyg / Kya_p) * c.w
        SVy = (Fz * (P["pvy1"] + P["pvy2"] * dfz) * P["lvy"] * c.lmuy_p * z2 + SVyg) * c.w
        muy = ((P["pdy1"] + P["pdy2"] * dfz) * (1.0 + P["ppy3"] * dpi + P["ppy4"] * dpi ** 2)
               * (1.0 - P["pdy3"] * gy ** 2) * c.lmuy_s)
    else:
        Kya = (P["pky1"] * c.Fz0p * np.sin(P["pky4"] * np.arctan(Fz / _nz(P["pky2"] * c.Fz0p)))
               * (1.0 - P["pky3"] * np.abs(gy)) * P["lky"])
        if ts is not None:
            Kya = Kya * ts.z3
        # MF 5.2 (MFeval): the turn slip shift SHyp does not enter SHy
        SHy = ((P["phy1"] + P["phy2"] * dfz) * P["lhy"] + P["phy3"] * gy) * c.w
        SVy = (Fz * ((P["pvy1"] + P["pvy2"] * dfz) * P["lvy"] + (P["pvy3"] + P["pvy4"] * dfz) * gy)
               * c.lmuy_p * z2 * c.w)
        muy = (P["pdy1"] + P["pdy2"] * dfz) * (1.0 - P["pdy3"] * gy ** 2) * c.lmuy_s
    ay = c.a_s + SHy
    Cy = P["pcy1"] * P["lcy"]
    Dy = muy * Fz * z2                                         # 4.E22 (zeta2)
    if c.mf6:
        Ey = (P["pey1"] + P["pey2"] * dfz) * (1.0 + P["pey5"] * gy ** 2
                                              - (P["pey3"] + P["pey4"] * gy) * _sgn1(ay)) * P["ley"]
    else:
        Ey = (P["pey1"] + P["pey2"] * dfz) * (1.0 - (P["pey3"] + P["pey4"] * gy) * _sgn1(ay)) * P["ley"]
    Ey = _emax(c, Ey)
    By = Kya / (Cy * Dy + EPS * _sgn1(Dy))
    Fy0 = _mf(By, Cy, Dy, Ey, ay) + SVy
    return dict(Fy0=Fy0, muy=muy, Dy=Dy, Cy=Cy, By=By, Ey=Ey, Kya=Kya, SHy=SHy, SVy=SVy)


def _gyk(c, gy, muy, z2=1.0):
    """Combined-slip weighting of Fy and the kappa-induced side force (z2:
    the turn-slip factor zeta2 of DVyk)."""
    P, Fz, dfz = c.P, c.Fz, c.dfz
    rby4 = P["rby4"] if c.mf6 else 0.0
    Byk = (P["rby1"] + rby4 * gy ** 2) * np.cos(np.arctan(P["rby2"] * (c.a_s - P["rby3"]))) * P["lyka"]
    Cyk = P["rcy1"]
    Eyk = _emax(c, P["rey1"] + P["rey2"] * dfz)
    SHyk = P["rhy1"] + P["rhy2"] * dfz
    Gyk = _weight(Byk, Cyk, Eyk, c.kappa + SHyk, SHyk)
    DVyk = (muy * Fz * (P["rvy1"] + P["rvy2"] * dfz + P["rvy3"] * gy) * np.cos(np.arctan(P["rvy4"] * c.a_s))
            * z2)
    SVyk = DVyk * np.sin(P["rvy5"] * np.arctan(P["rvy6"] * c.kappa)) * P["lvyka"] * c.w
    return Gyk, SVyk


# ---------------------------------------------------------------------------
# Turn slip (MFeval's useMode xx2).

TS_RATIO_LIMIT = 1000.0  # |R0 omega / Vc'| beyond this is limited (VXLOW = 0 and Vx = 0 only)


def _spin(c, phit, omega, camber=False):
    """The turn-slip context of MFeval's parseInputs: the processed turn slip
    phit_e and the spin phi (both times R0), eps_gamma, and the zeta factors
    that depend on them alone.

    phit [1/m] is MFeval's input column 5 (psi_dot = -phit Vc'); in the
    limits mode (1xx) it is multiplied by cos(alpha) and the low-speed factor
    |Vx| / VXLOW, as MFeval does. omega [rad/s] is the wheel's spin; 0 or None:
    MFeval's estimate (1 + kappa) Vx / Re with Re its effective rolling radius
    (R0 when the set has no VERTICAL_STIFFNESS or Re has no root). With grip's
    |Vx| convention Vx < 0 is evaluated as |Vx|: the estimate uses |Vx| and a
    given omega changes sign.

    camber=True: the camber's spin with the opposite sign, -phit + (1 -
    eps_gamma) omega sin(gamma) / Vc', which at phit = 0 keeps the camber
    thrust of the model without turn slip (MFeval's sign reverses it);
    GRIP_MF_OPT_TS_CAMBER, docs/magic-formula.md section 10."""
    P = c.P
    R0 = P["unloaded_radius"]
    ts = _Ctx()
    shape = c.kappa.shape
    phit = np.broadcast_to(np.asarray(0.0 if phit is None else phit, dtype=float), shape)
    pt = phit * np.cos(c.alpha_in) * c.r if c.limits else phit
    ts.ut = R0 * pt                                            # R0 phit (processed)
    ts.eps_g = P["pecp1"] * (1.0 + P["pecp2"] * c.dfz)         # 4.90
    vabs = c.vabs
    # Vc' = sqrt(Vcx^2 + Vsy^2) = |Vx| / cos(alpha) (alpha after the
    # low-speed scaling), VXLOW when |Vx| < VXLOW (MFeval: singularity
    # protected velocity)
    cos_a = np.abs(np.cos(c.alpha))
    vcp = np.where(vabs < P["vxlow"], P["vxlow"], vabs / np.where(cos_a > 0.0, cos_a, 1e-300))
    om = np.broadcast_to(np.asarray(0.0 if omega is None else omega, dtype=float), shape)
    given = om != 0.0
    r = _rolling(P, c, None)[0]
    r = np.where(np.isfinite(r), r, 1.0)
    w_est = (1.0 + c.kappa_in) * vabs / (r * R0)
    w = np.where(given, np.where(c.vx < 0.0, -om, om), w_est)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(vcp > 0.0, R0 * w / np.where(vcp > 0.0, vcp, 1.0),
                     np.sign(w) * TS_RATIO_LIMIT)
    q = np.clip(q, -TS_RATIO_LIMIT, TS_RATIO_LIMIT)
    # phi = (psi_dot - (1 - eps_gamma) omega sin(gamma)) / Vc', psi_dot = -phit Vc'
    # (MFeval's 4.76 without the book's minus sign: z up)
    ts.camber = camber
    ts.u = -ts.ut + (1.0 if camber else -1.0) * (1.0 - ts.eps_g) * np.sin(c.gamma) * q
    u = ts.u
    dfz = c.dfz
    bxp = P["pdxp1"] * (1.0 + P["pdxp2"] * dfz) * np.cos(np.arctan(P["pdxp3"] * c.kappa))   # 4.106
    ts.z1 = np.cos(np.arctan(bxp * u))                                                    # 4.105
    byp = P["pdyp1"] * (1.0 + P["pdyp2"] * dfz) * np.cos(np.arctan(P["pdyp3"] * np.tan(c.alpha)))  # 4.78
    ts.z2 = np.cos(np.arctan(byp * (np.abs(u) + P["pdyp4"] * np.sqrt(np.abs(u)))))        # 4.77
    ts.z3 = np.cos(np.arctan(P["pkyp1"] * u ** 2))                                        # 4.79
    ts.z5 = np.cos(np.arctan(P["qdtp1"] * u))                                             # 4.91
    ts.z6 = np.cos(np.arctan(P["qbrp1"] * u))                                             # 4.102
    return ts


def _shyp(c, ts):
    """The turn-slip shift SHyp of Fy (4.80-4.89, MF 6.x), with Kya0 (the
    cornering stiffness at gamma = 0, times zeta3) and Kyg0 (4.E30). Zero at
    Vx = 0 (MFeval: D_Hyp carries sgn(Vcx) = 0)."""
    P, Fz, dfz, dpi = c.P, c.Fz, c.dfz, c.dpi
    kya0 = (P["pky1"] * c.Fz0p * (1.0 + P["ppy1"] * dpi)
            * np.sin(P["pky4"] * np.arctan((Fz / c.Fz0p) / _nz(P["pky2"] * (1.0 + P["ppy2"] * dpi))))
            * ts.z3 * P["lky"])
    kya0p = kya0 + EPS * _sgn1(kya0)
    kyg0 = Fz * (P["pky6"] + P["pky7"] * dfz) * (1.0 + P["ppy5"] * dpi) * P["lkyc"]
    chyp = P["phyp1"]
    dhyp = P["phyp2"] + P["phyp3"] * dfz
    ehyp = _emax(c, np.asarray(P["phyp4"], dtype=float))
    kyrp0 = kyg0 / _nz(1.0 - ts.eps_g)                                                   # 4.89
    bhyp = kyrp0 / _nz(chyp * dhyp * kya0p)                                              # 4.88
    shyp = _mf(bhyp, chyp, dhyp, ehyp, ts.u)                                             # 4.80
    return np.where(c.vabs == 0.0, 0.0, shyp)


# |Mzp90 / Drp| is limited to 1 (zeta7 in [0, 2]): MFeval takes acos of
# the unlimited ratio, a complex Cr beyond 1, and reports the real part of
# Mz, Dr cosh(2/pi acosh(x) atan(Br a)), which grows without bound (and is
# Inf/NaN where Drp = 0: Kzgr0 = 0, e.g. FSAE_Defaults, PacejkaBook_Defaults)
TS_X_LIMIT = 1.0


def _turn_moment(c, ts, muy, gyk):
    """MFeval's turn-slip parts of the residual moment (calculateMz0): Drp
    [N m] (zeta8 - 1) and the shape factor Cr = zeta7, returned as Drp and
    x = Mzp90 / |Drp| (Cr = 2/pi acos(x)). Kzgr0 as MFeval writes it:
    Fz R0 (QDZ8 QDZ9 dfz + QDZ10 + QDZ11 dfz |gamma|) LKZC."""
    P, Fz, dfz = c.P, c.Fz, c.dfz
    R0 = P["unloaded_radius"]
    mzp_inf = P["qcrp1"] * np.abs(muy) * R0 * Fz * np.sqrt(Fz / c.Fz0p) * P["lmp"]       # 4.95
    mzp_inf = np.where(mzp_inf < 0.0, 1e-6, mzp_inf)
    cdrp = P["qdrp1"]                                                                   # 4.96
    ddrp = mzp_inf / math.sin(0.5 * math.pi * cdrp)                                     # 4.94
    qdz10 = P["qdz10"] if c.mf6 else 0.0
    qdz11 = P["qdz11"] if c.mf6 else 0.0
    lkzc = P["lkzc"] if c.mf6 else 1.0
    if ts.camber:
        # the camber stiffness of Dr (4.E47 at gamma -> 0), of the spin phi
        kzgr0 = Fz * R0 * (P["qdz8"] + P["qdz9"] * dfz + (qdz10 + qdz11 * dfz) * np.abs(c.gamma)) * lkzc
        arg = ts.u
    else:
        kzgr0 = Fz * R0 * (P["qdz8"] * P["qdz9"] * dfz + (qdz10 + qdz11 * dfz * np.abs(c.gamma))) * lkzc  # 4.99
        arg = ts.ut
    one_eg = _nz(1.0 - ts.eps_g)
    # BDrp R0 phi = Kzgr0 R0 phi / (CDrp DDrp (1 - eps_gamma)) as an angle:
    # atan2 keeps DDrp -> 0 (Fz -> 0) finite
    num = kzgr0 * arg / one_eg
    den = cdrp * ddrp
    ang = np.arctan2(num * np.sign(den), np.abs(den))
    drp = ddrp * np.sin(cdrp * ang)
    mzp90 = mzp_inf * (2.0 / math.pi) * np.arctan(P["qcrp2"] * np.abs(ts.ut)) * gyk      # 4.103
    # x = Mzp90 / |Drp|; at phit = 0 both vanish and x is their limit
    # (slopes Mzp_inf 2/pi QCRP2 Gyk and |Kzgr0 / (1 - eps_gamma)|)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_lim = mzp_inf * (2.0 / math.pi) * P["qcrp2"] * gyk / np.abs(kzgr0 / one_eg)
        x = np.where((ts.ut == 0.0) & (arg == 0.0), x_lim, mzp90 / np.abs(drp))
    x = np.where(np.isnan(x), 0.0, x)
    return drp, np.clip(x, -TS_X_LIMIT, TS_X_LIMIT), x


def _cr_cos(x, y):
    """cos(Cr y) with Cr = zeta7 = 2/pi acos(x), -1 <= x <= 1."""
    return np.cos((2.0 / math.pi) * np.arccos(x) * y)


def _core(P, kappa, alpha, gamma, fz, p, vx, form, mz52_svyk_camber=False, limits=True, turn_slip=False,
          phit=None, omega=None, ts_camber=False):
    """All forces and moments in ISO-W, no mirroring. Returns a dict.

    mz52_svyk_camber: MF 5.2 aligning moment with Fy' = Fy - SVyk(mu_y(gamma))
    (grip's earlier form) instead of MFeval's Fy - SVyk(mu_y(gamma = 0)).
    limits: MFeval's useMode 1xx (True) or 2xx (False); turn_slip: xx2 with
    the inputs phit [1/m] and omega [rad/s] (see _spin)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        c = _prepare(P, kappa, alpha, gamma, fz, p, vx, form, limits)
        c.omega_in = omega
        Fz, dfz, dpi, R0 = c.Fz, c.dfz, c.dpi, P["unloaded_radius"]
        ts = None
        if turn_slip:
            if not turn_slip_usable(P):
                raise ValueError("turn slip: the set has no usable [TURNSLIP_COEFFICIENTS] "
                                 "(PHYP1 > 0 and 0 < QDRP1 < 2)")
            ts = _spin(c, phit, omega, ts_camber)
        x0 = _fx0(c, ts)
        y0 = _fy0(c, c.gy, ts)
        y00 = _fy0(c, np.zeros_like(c.gy))                     # Fy0 at gamma = 0
        # MFeval's combined Mz takes Fy0 at gamma = 0 with the turn slip
        # (calculateMz), its pure Mz0 without (calculateMz0)
        y00ts = y00 if ts is None else _fy0(c, np.zeros_like(c.gy), ts)

        # ---- pure aligning moment
        gz = c.gz
        SHt = P["qhz1"] + P["qhz2"] * dfz + (P["qhz3"] + P["qhz4"] * dfz) * gz
        Kya_p = y0["Kya"] + EPS * _sgn1(y0["Kya"])
        SHf = y0["SHy"] + y0["SVy"] / Kya_p
        ar = c.a_s + SHf
        at = c.a_s + SHt
        bt_load = P["qbz1"] + P["qbz2"] * dfz + P["qbz3"] * dfz ** 2
        if c.f["bt_book"] and c.mf6:
            Bt = bt_load * (1.0 + P["qbz5"] * np.abs(gz) + P["qbz6"] * gz ** 2) * P["lky"] / _nz(c.lmuy_s)
        else:
            Bt = bt_load * (1.0 + P["qbz4"] * gz + P["qbz5"] * np.abs(gz)) * P["lky"] / _nz(c.lmuy_s)
        if c.f["dt_book"] and c.mf6:
            dt_cam = 1.0 + P["qdz3"] * np.abs(gz) + P["qdz4"] * gz ** 2
        else:
            dt_cam = 1.0 + P["qdz3"] * gz + P["qdz4"] * gz ** 2
        Ct = P["qcz1"]
        Dt = (Fz * (R0 / c.Fz0p) * (P["qdz1"] + P["qdz2"] * dfz) * (1.0 - P["ppz1"] * dpi)
              * dt_cam * P["ltr"])
        if ts is not None:
            Dt = Dt * ts.z5                                    # 4.E43 with zeta5
        Et = _emax(c, (P["qez1"] + P["qez2"] * dfz + P["qez3"] * dfz ** 2)
                   * (1.0 + (P["qez4"] + P["qez5"] * gz) * (2.0 / math.pi) * np.arctan(Bt * Ct * at)))
        trail_scale = c.cosa * c.w * (1.0 if c.f["trail_nolfzo"] else P["lfzo"])
        t0 = Dt * np.cos(Ct * np.arctan(Bt * at - Et * (Bt * at - np.arctan(Bt * at)))) * trail_scale
        if c.mf6:
            Dr = (Fz * R0 * ((P["qdz6"] + P["qdz7"] * dfz) * P["lres"]
                             + ((P["qdz8"] + P["qdz9"] * dfz) * (1.0 + P["ppz2"] * dpi)
                                + (P["qdz10"] + P["qdz11"] * dfz) * np.abs(gz)) * gz * P["lkzc"])
                  * c.lmuy_s * c.cosa)
        else:
            Dr = (Fz * R0 * ((P["qdz6"] + P["qdz7"] * dfz) * P["lres"] + (P["qdz8"] + P["qdz9"] * dfz) * gz)
                  * c.lmuy_s * c.cosa)
        Br = P["qbz9"] * P["lky"] / _nz(c.lmuy_s) + P["qbz10"] * y0["By"] * y0["Cy"]
        Gyk, SVyk = _gyk(c, c.gy, y0["muy"], 1.0 if ts is None else ts.z2)
        if ts is None:
            Mzr0 = Dr * np.cos(np.arctan(Br * ar)) * c.cosa * c.w
            Drp = x_cr = x_raw = None
        else:
            # 4.E47 with zeta0 = 0 (no camber term), zeta2 on the LRES term
            # and zeta8 - 1 = Drp; Br times zeta6 (4.E45); Cr = zeta7 (4.E46)
            Drp, x_cr, x_raw = _turn_moment(c, ts, y0["muy"], Gyk)
            Dr = Fz * R0 * (P["qdz6"] + P["qdz7"] * dfz) * P["lres"] * ts.z2 * c.lmuy_s * c.cosa + Drp
            Br = Br * ts.z6
            Mzr0 = Dr * _cr_cos(x_cr, np.arctan(Br * ar)) * c.cosa * c.w
        Mz0 = -t0 * (y00["Fy0"] if c.mf6 else y0["Fy0"]) + Mzr0

        # ---- combined longitudinal force
        rbx3 = P["rbx3"] if c.mf6 else 0.0
        gxa = c.g_s if c.mf6 else c.gx
        Bxa = (P["rbx1"] + rbx3 * gxa ** 2) * np.cos(np.arctan(P["rbx2"] * c.kappa)) * P["lxal"]
        Cxa = P["rcx1"]
        Exa = _emax(c, P["rex1"] + P["rex2"] * dfz)
        SHxa = P["rhx1"]
        Gxa = _weight(Bxa, Cxa, Exa, c.a_s + SHxa, SHxa)
        Fx = Gxa * x0["Fx0"]

        # ---- combined lateral force
        Fy = Gyk * y0["Fy0"] + SVyk

        # ---- combined aligning moment
        ratio2 = (x0["Kxk"] / Kya_p) ** 2 * c.kappa ** 2
        if c.f["eq_sqrt"]:
            at_eq = np.sqrt(at ** 2 + ratio2) * _sgn1(at)
            ar_eq = np.sqrt(ar ** 2 + ratio2) * _sgn1(ar)
        else:
            at_eq = np.arctan(np.sqrt(np.tan(at) ** 2 + ratio2)) * _sgn1(at)
            ar_eq = np.arctan(np.sqrt(np.tan(ar) ** 2 + ratio2)) * _sgn1(ar)
        fz0_s = c.Fz0p if c.f["s_fz0p"] else c.Fz0
        s = R0 * (P["ssz1"] + P["ssz2"] * (Fy / fz0_s) + (P["ssz3"] + P["ssz4"] * dfz) * gz) * P["ls"]
        if ts is None:
            Mzr = Dr * np.cos(np.arctan(Br * ar_eq)) * c.w * (c.cosa if c.f["mzr_cos"] else 1.0)
        else:
            Mzr = Dr * _cr_cos(x_cr, np.arctan(Br * ar_eq)) * c.w * (c.cosa if c.f["mzr_cos"] else 1.0)
        t = Dt * np.cos(Ct * np.arctan(Bt * at_eq - Et * (Bt * at_eq - np.arctan(Bt * at_eq)))) * trail_scale
        if not c.mf6:
            # MF 5.2 (MF-Tyre 5.2 manual, as MFeval): Fy' = Fy - SVyk, where
            # MFeval's calculateMz takes SVyk from the combined-slip evaluation
            # with mu_y at gamma = 0 (muy_sub0; RVY3 and RBY4 keep gamma)
            SVyk_mz = SVyk if mz52_svyk_camber else _gyk(c, c.gy, y00["muy"])[1]
            Fyp = Fy - SVyk_mz
        elif c.f["fyp_gamma0"]:
            Gyk0, _ = _gyk(c, np.zeros_like(c.gy), y00["muy"])
            Fyp = Gyk0 * y00ts["Fy0"]
        else:
            Fyp = Gyk * y00ts["Fy0"]
        Mz = -t * Fyp + Mzr + s * Fx

        out = dict(fx0=x0["Fx0"], fy0=y0["Fy0"], mz0=Mz0, fx=Fx, fy=Fy, mz=Mz)
        for k in out:
            out[k] = np.where(c.loaded, out[k], 0.0)
        det = dict(x0)
        det.update(y0)
        det.update(dict(Gxa=Gxa, Gyk=Gyk, SVyk=SVyk, t0=t0, t=t, Mzr0=Mzr0, Mzr=Mzr, s=s,
                        Bt=Bt, Ct=Ct, Dt=Dt, Et=Et, Br=Br, Dr=Dr, SHt=SHt, SHf=SHf,
                        alpha_t=at, alpha_r=ar, alpha_t_eq=at_eq, alpha_r_eq=ar_eq, Fy_prime=Fyp, ctx=c,
                        Fy0_gamma0=y00["Fy0"], muy_gamma0=y00["muy"], r=c.r, ra=c.ra, w=c.w, dfz=dfz, dpi=dpi,
                        ts=ts, Drp=Drp, x_cr=x_cr, x_raw=x_raw, Fy0_gamma0_ts=y00ts["Fy0"]))
        return out, det


def to_iso(kappa, alpha, gamma, fz, convention="iso", kappa_braking=False):
    """User inputs -> ISO-W inputs."""
    kappa = -np.asarray(kappa, dtype=float) if kappa_braking else np.asarray(kappa, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    gamma = np.asarray(gamma, dtype=float)
    fz = np.asarray(fz, dtype=float)
    if convention == "sae":
        return (SAE_SIGN["kappa"] * kappa, SAE_SIGN["alpha"] * alpha,
                SAE_SIGN["gamma"] * gamma, SAE_SIGN["fz"] * fz)
    if convention != "iso":
        raise ValueError(f"convention must be 'iso' or 'sae', not {convention!r}")
    return kappa, alpha, gamma, fz


def from_iso(out, convention="iso"):
    """ISO-W outputs {fx0, fy0, mz0, fx, fy, mz} -> the user's convention."""
    if convention == "iso":
        return dict(out)
    if convention != "sae":
        raise ValueError(f"convention must be 'iso' or 'sae', not {convention!r}")
    sign = {"fx0": SAE_SIGN["fx"], "fx": SAE_SIGN["fx"], "fy0": SAE_SIGN["fy"], "fy": SAE_SIGN["fy"],
            "mz0": SAE_SIGN["mz"], "mz": SAE_SIGN["mz"]}
    return {k: sign.get(k, 1) * v for k, v in out.items()}


def mirror_inputs(alpha, gamma):
    """Mirror image in the x-z plane: alpha and gamma change sign."""
    return -np.asarray(alpha, dtype=float), -np.asarray(gamma, dtype=float)


def mirror_outputs(out):
    """Fy and Mz change sign in the mirror image; Fx does not."""
    flip = {"fy0", "fy", "mz0", "mz"}
    return {k: (-v if k in flip else v) for k, v in out.items()}


def _turn_inputs(phit, omega, convention, mirror):
    """phit, omega in the model's frame: phit is a rate about z, so it
    changes sign in SAE (z down) and in the mirror image, as alpha does;
    omega, the wheel's spin, keeps its sign."""
    if phit is None:
        return None, omega
    ph = np.asarray(phit, dtype=float)
    if convention == "sae":
        ph = -ph
    if mirror:
        ph = -ph
    return ph, omega


def evaluate(params, kappa, alpha, gamma, fz, p=None, vx=None, *, form="mftyre",
             convention="iso", kappa_braking=False, mirror=None, details=False,
             mz52_svyk_camber=False, limits=True, turn_slip=False, phit=None, omega=None,
             ts_camber=False):
    """Forces and moments of one parameter set (array inputs broadcast).

    params: dict of grip_mf_params fields in SI (tir.Tir.params()).
    kappa [-], alpha [rad], gamma [rad], fz [N], p [Pa] (None: INFLPRES, or
    NOMPRES when INFLPRES is 0; ignored by MF 5.2), vx [m/s] (None: LONGVL).
    convention 'iso' (ISO-W, native) or 'sae'; kappa_braking=True: the given
    kappa is positive in braking. mirror: None = when the mounting side
    (options' RIGHT_SIDE bit) differs from the file's (tyreside), as the C
    library does, or True/False to force.
    mz52_svyk_camber=True: MF 5.2 combined Mz with grip's earlier Fy' = Fy -
    SVyk(mu_y at gamma) (GRIP_MF_OPT_MZ52_SVYK_CAMBER) instead of MFeval's
    Fy - SVyk(mu_y at gamma = 0); no effect on MF 6.x.
    limits (MFeval useMode 1xx: True, 2xx: False), turn_slip (xx2) with
    phit [1/m] and omega [rad/s] (0 or None: estimated): see _spin.
    Returns {fx0, fy0, mz0, fx, fy, mz} (and the internals when details).
    """
    k, a, g, f = to_iso(kappa, alpha, gamma, fz, convention, kappa_braking)
    if mirror is None:
        mirror = (int(params.get("tyreside", 1)) == -1) != bool(int(params.get("options", 0)) & (1 << 3))
    if mirror:
        a, g = mirror_inputs(a, g)
    ph, om = _turn_inputs(phit, omega, convention, mirror)
    out, det = _core(params, k, a, g, f, p, vx, form, mz52_svyk_camber, limits, turn_slip, ph, om, ts_camber)
    if mirror:
        out = mirror_outputs(out)
    out = from_iso(out, convention)
    if details:
        out["details"] = det
    return out


# ---------------------------------------------------------------------------
# Extended outputs (MFeval's other channels).

# name, unit, sign under mirroring (x-z plane), sign SAE per ISO-W
EXT_CHANNELS = (
    ("re", "m", 1, 1),          # effective rolling radius
    ("omega", "rad/s", 1, 1),   # wheel spin (1 + kappa) vx / Re
    ("rl", "m", 1, 1),          # loaded radius
    ("rho", "m", 1, 1),         # vertical deflection
    ("cz", "N/m", 1, 1),        # vertical stiffness Fz / rho
    ("2a", "m", 1, 1),          # contact patch length
    ("2b", "m", 1, 1),          # contact patch width
    ("t", "m", 1, 1),           # pneumatic trail (combined slip)
    ("mzr", "N m", -1, -1),     # residual aligning moment (combined slip)
    ("mux", "-", 1, 1),         # longitudinal friction coefficient
    ("muy", "-", 1, 1),         # lateral friction coefficient (|mu_y|, as MFeval)
    ("kxk", "N", 1, 1),         # longitudinal slip stiffness dFx0/dkappa
    ("kya", "N/rad", 1, 1),     # cornering stiffness dFy0/dalpha
    ("cx", "N/m", 1, 1),        # overall longitudinal stiffness
    ("cy", "N/m", 1, 1),        # overall lateral stiffness
    ("sigmax", "m", 1, 1),      # longitudinal relaxation length
    ("sigmay", "m", 1, 1),      # lateral relaxation length
    ("mx", "N m", -1, 1),       # overturning moment
    ("my", "N m", 1, -1),       # rolling resistance moment
)
EXT_NAMES = tuple(ch[0] for ch in EXT_CHANNELS)
RE_NEWTON_MAX = 60       # Newton steps of the rolling-radius cubic (converges in < 10)
RL62_SCAN = 500          # grid points of the MF 6.2 deflection scan
RL62_BISECT = 60         # bisection steps of the MF 6.2 loaded radius


def _re_root(a, b):
    """Root r > 0 of r = a + b / r^2 (the effective rolling radius / R0, with
    Omega from Re: MFeval iterates Re = Romega(Omega = (1 + kappa) Vx / Re) -
    deflection to 1e-9 m). Newton from r0 = a + b / a^2, which lies above
    the root, converges monotonically. NaN where there is no positive root."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    ok = (a > 0.0) & (b >= -4.0 * a ** 3 / 27.0)
    aa = np.where(ok, a, 1.0)
    bb = np.where(ok, b, 0.0)
    r = aa + bb / aa ** 2
    for _ in range(RE_NEWTON_MAX):
        f = r ** 3 - aa * r ** 2 - bb
        d = 3.0 * r ** 2 - 2.0 * aa * r
        r = r - f / np.where(d > 0.0, d, 1.0)
    ok &= np.abs(r ** 3 - aa * r ** 2 - bb) <= 1e-12 * np.maximum(1.0, np.abs(r) ** 3)
    return np.where(ok, r, np.nan)


def _fz62(P, rl, romega, gamma, omega_abs, dpi, fx, fy):
    """MF 6.2 vertical force at loaded radius rl and its deflection (MFeval's
    calculateFz62, MF-Tyre/MF-Swift 6.2 equation manual)."""
    R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
    qfz1 = np.sqrt((P["vertical_stiffness"] * R0 / Fz0) ** 2 - 4.0 * P["q_fz2"])
    u = rl / romega
    sfyg = (P["q_fys1"] + P["q_fys2"] * u + P["q_fys3"] * u ** 2) * gamma
    rho_fr = np.maximum(romega - rl, 0.0)
    rtw = (1.075 - 0.5 * P["aspect_ratio"]) * P["width"]
    num = P["q_cam1"] * rl + P["q_cam2"] * rl ** 2
    den = P["q_cam1"] * romega + P["q_cam2"] * romega ** 2
    # ((num gamma)^2 / (den gamma)^2) (rtw/8)|tan gamma| - Q_CAM3 rho_fr |gamma|;
    # MFeval turns the 0/0 of gamma = 0 (or den = 0) into 0: the whole term
    cam = (gamma != 0.0) & (den != 0.0)
    rho_g = np.where(cam, (num / np.where(cam, den, 1.0)) ** 2 * (rtw / 8.0) * np.abs(np.tan(gamma))
                     - P["q_cam3"] * rho_fr * np.abs(gamma), 0.0)
    rho = np.maximum(rho_fr + rho_g, 0.0)
    x = rho / R0
    pos = x > 0.0
    xp = np.where(pos, x, 1.0)
    fy_term = np.where(pos, xp ** P["q_fcy2"], 0.0) * P["q_fcy"] * (fy - sfyg) / Fz0
    fcorr = ((1.0 + P["q_v2"] * (R0 / V0) * omega_abs - (P["q_fcx"] * fx / Fz0) ** 2 - fy_term ** 2)
             * (1.0 + P["pfz1"] * dpi))
    return np.where(pos, fcorr * (qfz1 * x + P["q_fz2"] * x ** 2) * Fz0, 0.0), rho


def _rl62(P, fz, romega, gamma, omega_abs, dpi, fx, fy):
    """MF 6.2 loaded radius Rl = Romega - d: the smallest free-rolling
    deflection d in [0, R0] with Fz62(Romega - d) = Fz (MFeval minimizes
    (Fz62 - Fz)^2 with fminsearch from Rl = 0.3 m). Where even d = 0 gives
    Fz62 >= Fz (the camber deflection at a small load) the minimum is Rl =
    Romega, as MFeval's; NaN where no d reaches Fz. Inside the fitted range
    there is one root; at large camber (|gamma| > 0.45 rad on
    MagicFormula62) the camber term makes several, and the smallest
    deflection is the one continuous with the unloaded tyre."""
    R0 = P["unloaded_radius"]

    def g(d):
        return _fz62(P, romega - d, romega, gamma, omega_abs, dpi, fx, fy)[0] - fz

    at_top = g(np.zeros_like(romega)) >= 0.0
    # first sign change on a dense grid (quadratic spacing: fine at small d)
    grid = R0 * (np.arange(1, RL62_SCAN + 1) / RL62_SCAN) ** 2
    lo = np.zeros_like(romega)
    hi = np.full_like(romega, np.nan)
    prev = np.zeros_like(romega)
    for d in grid:
        found = np.isnan(hi) & (g(np.full_like(romega, d)) > 0.0)
        lo = np.where(found, prev, lo)
        hi = np.where(found, d, hi)
        prev = np.where(np.isnan(hi), d, prev)
    ok = at_top | ~np.isnan(hi)
    a, b = lo, np.where(np.isnan(hi), R0, hi)
    for _ in range(RL62_BISECT):
        m = 0.5 * (a + b)
        pos = g(m) > 0.0
        a = np.where(pos, a, m)
        b = np.where(pos, m, b)
    d = np.where(at_top, 0.0, 0.5 * (a + b))
    rl = romega - d
    rho = _fz62(P, rl, romega, gamma, omega_abs, dpi, fx, fy)[1]
    return np.where(ok, rl, np.nan), np.where(ok, rho, np.nan)


def _rolling(P, c, omega=None):
    """(Re / R0, Omega, Romega, Cz at the pressure, has Cz) of MFeval's
    calculateRe: Re = Romega(Omega) - Fz0 / Cz (DREFF atan(BREFF Fz/Fz0) +
    FREFF Fz/Fz0). Omega = (1 + kappa) Vx / Re (the fixed point MFeval
    iterates) or, where omega is given (non-zero), Omega = omega and Re
    follows from it directly (MFeval's input column 8). NaN where the set has
    no VERTICAL_STIFFNESS or there is no positive root."""
    R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
    fz = np.where(c.loaded, c.Fz, 0.0)
    kap = c.kappa_in
    vx = c.vx
    cz0 = P["vertical_stiffness"]
    czp = cz0 * (1.0 + P["pfz1"] * c.dpi)
    has_cz = (cz0 > 0.0) & (czp > 0.0)
    czs = np.where(has_cz, czp, 1.0)
    defl = Fz0 / czs * (P["dreff"] * np.arctan(P["breff"] * fz / Fz0) + P["freff"] * fz / Fz0)
    b = P["q_v1"] * ((1.0 + kap) * vx / V0) ** 2
    r = _re_root(P["q_re0"] - defl / R0, b)
    r = np.where(has_cz, r, np.nan)
    omega_out = (1.0 + kap) * vx / (r * R0)
    romega = R0 * (P["q_re0"] + b / r ** 2)
    if omega is not None:
        om = np.broadcast_to(np.asarray(omega, dtype=float), r.shape)
        given = om != 0.0
        a = P["q_re0"] - defl / R0
        rg = P["q_re0"] + P["q_v1"] * (om * R0 / V0) ** 2 - defl / R0
        rg = np.where(has_cz & (a > 0.0), rg, np.nan)
        r = np.where(given, rg, r)
        omega_out = np.where(given, om, omega_out)
        romega = np.where(given, R0 * (P["q_re0"] + P["q_v1"] * (om * R0 / V0) ** 2), romega)
    return r, omega_out, romega, czs, has_cz


def _ext(P, c, det, out):
    """MFeval's extra channels in ISO-W and the model's frame (before the
    un-mirroring). NaN marks a channel whose parameters are missing or whose
    equation has no solution (the C library clears its valid bit)."""
    R0, Fz0, V0 = P["unloaded_radius"], P["fnomin"], P["longvl"]
    Fz0p = P["lfzo"] * Fz0
    loaded = c.loaded
    fz = np.where(loaded, c.Fz, 0.0)
    kap = c.kappa_in
    vx = c.vx
    gam = c.gamma
    dpi = c.dpi
    fx = out["fx"]
    fy = out["fy"]
    shape = fz.shape
    nan = np.full(shape, np.nan)
    e = {}

    # effective rolling radius, the wheel's spin and its free radius
    r, e["omega"], romega, czs, has_cz = _rolling(P, c, getattr(c, "omega_in", None))
    cz0 = P["vertical_stiffness"]
    e["re"] = r * R0
    omega_abs = np.abs(e["omega"])

    # loaded radius, deflection and vertical stiffness
    qfz1_sq = (cz0 * R0 / Fz0) ** 2 - 4.0 * P["q_fz2"]
    vert_ok = has_cz & (qfz1_sq >= 0.0) & np.isfinite(romega)
    if c.fittyp == 62:
        rl, rho = _rl62(P, fz, romega, gam, omega_abs, dpi, fx, fy)
    else:
        # calculateRhoRl61 (MF 5.2 and 6.1): Fz = (Q_FZ1 x + Q_FZ2 x^2) * ext,
        # x = rho / R0, solved in the form that stays finite for Q_FZ2 = 0
        ext = ((1.0 + P["q_v2"] * (R0 / V0) * omega_abs - (P["q_fcx"] * fx / Fz0) ** 2
                - (P["q_fcy"] * fy / Fz0) ** 2) * (1.0 + P["pfz1"] * dpi))
        qfz1 = np.sqrt(np.maximum(qfz1_sq, 0.0))
        y = (fz / Fz0) / np.where(ext > 0.0, ext, 1.0)
        disc = qfz1 ** 2 + 4.0 * P["q_fz2"] * y
        den = qfz1 + np.sqrt(np.maximum(disc, 0.0))
        x = np.where(den > 0.0, 2.0 * y / np.where(den > 0.0, den, 1.0), 0.0)
        good = (ext > 0.0) & (disc >= 0.0) & (den > 0.0)
        rho = np.where(good, np.maximum(x * R0, 0.0), np.nan)
        rl = np.where(good, np.maximum(romega - rho, 0.0), np.nan)
    rho = np.where(loaded, rho, 0.0)
    rl = np.where(loaded, rl, romega)
    e["rl"] = np.where(vert_ok, rl, np.nan)
    e["rho"] = np.where(vert_ok, rho, np.nan)
    e["cz"] = np.where(vert_ok, np.where(rho > 0.0, fz / np.where(rho > 0.0, rho, 1.0), 0.0), np.nan)
    if c.fittyp == 62:
        e["cz"] = np.where(loaded & ~(rho > 0.0), np.nan, e["cz"])

    # contact patch (calculateContactPatch), with its bottoming limit
    fzc = np.where(R0 - fz / czs - (P["rim_radius"] + P["bottom_offst"]) < 0.0,
                   np.maximum((R0 - P["rim_radius"] - P["bottom_offst"]) * czs, 0.0), fz)
    w = P["width"]
    if c.mf6:
        q = fzc / (czs * R0)
        a = R0 * (P["q_ra2"] * q + P["q_ra1"] * np.sqrt(q))
        bb = w * (P["q_rb2"] * q + P["q_rb1"] * np.cbrt(q))
        a_ok = has_cz
        b_ok = has_cz & (w > 0.0)
    else:
        qa1, qa2 = P["q_a1"], P["q_a2"]
        a_ok = has_cz
        if qa1 == 0.0 and qa2 == 0.0:
            # MFeval's defaults from the vertical stiffness ("empirically discovered")
            yy = math.log10(R0 * cz0 / Fz0) if cz0 > 0.0 else 0.0
            qa1 = -0.0388 * yy ** 3 + 0.2509 * yy ** 2 - 0.6283 * yy + 0.6279
            qa2 = 1.693 * qa1 ** 2
        a = R0 * (qa2 * fzc / Fz0 + qa1 * np.sqrt(fzc / Fz0))
        bb = np.full(shape, 0.5 * w)
        b_ok = np.full(shape, w > 0.0)
    e["2a"] = np.where(a_ok, 2.0 * a, np.nan)
    e["2b"] = np.where(b_ok, 2.0 * bb, np.nan)

    # trail, residual moment, friction, slip stiffnesses (the model's own)
    e["t"] = np.where(loaded, det["t"], 0.0)
    e["mzr"] = np.where(loaded, det["Mzr"], 0.0)
    e["mux"] = np.where(loaded, det["mux"], 0.0)
    # MFeval reports |mu_y| in its limits mode (1xx), mu_y itself in 2xx
    e["muy"] = np.where(loaded, np.abs(det["muy"]) if c.limits else det["muy"], 0.0)
    e["kxk"] = np.where(loaded, det["Kxk"], 0.0)
    e["kya"] = np.where(loaded, det["Kya"], 0.0)

    # structural stiffnesses and relaxation lengths (calculateRelax)
    dfz = (fz - Fz0p) / Fz0p
    cx0, cy0 = P["longitudinal_stiffness"], P["lateral_stiffness"]
    cx = cx0 * (1.0 + P["pcfx1"] * dfz + P["pcfx2"] * dfz ** 2) * (1.0 + P["pcfx3"] * dpi)
    cy = cy0 * (1.0 + P["pcfy1"] * dfz + P["pcfy2"] * dfz ** 2) * (1.0 + P["pcfy3"] * dpi)
    e["cx"] = np.where(cx0 > 0.0, cx, np.nan)
    e["cy"] = np.where(cy0 > 0.0, cy, np.nan)
    if c.mf6:
        e["sigmax"] = np.where((cx0 > 0.0) & (cx != 0.0), np.abs(e["kxk"] / np.where(cx != 0.0, cx, 1.0)), np.nan)
        e["sigmay"] = np.where((cy0 > 0.0) & (cy != 0.0), np.abs(e["kya"] / np.where(cy != 0.0, cy, 1.0)), np.nan)
    else:
        e["sigmax"] = ((P["ptx1"] + P["ptx2"] * dfz) * np.exp(-P["ptx3"] * dfz) * P["lsgkp"] * R0 * fz / Fz0)
        e["sigmay"] = (P["pty1"] * np.sin(2.0 * np.arctan2(fz, P["pty2"] * Fz0p)) * (1.0 - P["pky3"] * np.abs(gam))
                       * R0 * P["lfzo"] * P["lsgal"])

    # overturning moment (calculateMx; MF-Tyre equation manual, QSX12-14)
    fzmin = P["fzmin"]
    fzr2 = fz * np.minimum(1.0, (fz / fzmin) ** 2) if fzmin > 0.0 else fz
    mx = (R0 * fzr2 * P["lmx"] * (P["qsx1"] * P["lvmx"] - P["qsx2"] * gam * (1.0 + P["ppmx1"] * dpi)
                                  - P["qsx12"] * gam * np.abs(gam) + P["qsx3"] * fy / Fz0
                                  + P["qsx4"] * np.cos(P["qsx5"] * np.arctan((P["qsx6"] * fzr2 / Fz0) ** 2))
                                  * np.sin(P["qsx7"] * gam + P["qsx8"] * np.arctan(P["qsx9"] * fy / Fz0))
                                  + P["qsx10"] * np.arctan(P["qsx11"] * fzr2 / Fz0) * gam)
          + R0 * fy * P["lmx"] * (P["qsx13"] + P["qsx14"] * np.abs(gam)))
    e["mx"] = np.where(loaded, mx, 0.0)

    # rolling resistance moment (calculateMy: MF 5.2 manual / paper A48)
    fzr1 = fz * np.minimum(1.0, fz / fzmin) if fzmin > 0.0 else fz
    u = vx / V0
    base = P["qsy1"] + P["qsy2"] * fx / Fz0 + P["qsy3"] * np.abs(u) + P["qsy4"] * u ** 4
    if c.mf6:
        my = (-R0 * Fz0 * P["lmy"] * (base + (P["qsy5"] + P["qsy6"] * fzr1 / Fz0) * gam ** 2)
              * (fzr1 / Fz0) ** P["qsy7"] * (1.0 + dpi) ** P["qsy8"])
    else:
        my = -R0 * fzr1 * P["lmy"] * base
    # the sign of the wheel's rolling: MFeval flips My for Vx < 0 and, in a
    # window |1 + kappa| |Vx| <= VXLOW around the locked wheel, multiplies it
    # by sin(pi/2 (1 + kappa) |Vx| / VXLOW) (flipped below the window)
    if P["vxlow"] > 0.0:
        roll = np.sin(0.5 * math.pi * np.clip((1.0 + kap) * np.abs(vx) / P["vxlow"], -1.0, 1.0))
    else:
        roll = np.sign(1.0 + kap)
    e["my"] = np.where(loaded, my * np.sign(vx) * roll, 0.0)
    return e


def evaluate_ext(params, kappa, alpha, gamma, fz, p=None, vx=None, *, form="mftyre",
                 convention="iso", kappa_braking=False, mirror=None, mz52_svyk_camber=False,
                 limits=True, turn_slip=False, phit=None, omega=None, ts_camber=False):
    """evaluate()'s combined outputs {fx, fy, mz} and MFeval's other output
    channels EXT_NAMES (units in EXT_CHANNELS), same arguments. A channel is
    NaN where the parameter set lacks what it needs (VERTICAL_STIFFNESS,
    WIDTH, LONGITUDINAL_/LATERAL_STIFFNESS = 0: not given) or its equation
    has no solution; grip_mf_eval_ext clears the channel's valid bit there.
    Fz <= 0: forces, moments, mu, stiffnesses Kxk, Kya, trail, Cz, rho, 2a
    are 0; Re, Omega and Rl are those of the unloaded wheel. A given omega
    (non-zero; MFeval's input column 8) is the Omega of Re, Rl, rho, Cz with
    or without turn slip."""
    k, a, g, f = to_iso(kappa, alpha, gamma, fz, convention, kappa_braking)
    if mirror is None:
        mirror = (int(params.get("tyreside", 1)) == -1) != bool(int(params.get("options", 0)) & (1 << 3))
    if mirror:
        a, g = mirror_inputs(a, g)
    ph, om = _turn_inputs(phit, omega, convention, mirror)
    out, det = _core(params, k, a, g, f, p, vx, form, mz52_svyk_camber, limits, turn_slip, ph, om, ts_camber)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        e = _ext(params, det["ctx"], det, out)
    res = {q: out[q] for q in ("fx", "fy", "mz")}
    if mirror:
        res = mirror_outputs(res)
    res = from_iso(res, convention)
    for name, _unit, msign, ssign in EXT_CHANNELS:
        v = e[name] * (msign if mirror else 1)
        res[name] = v * (ssign if convention == "sae" else 1)
    return res
