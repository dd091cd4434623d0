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
Left out: turn slip (phi_t = 0, all zeta = 1), Mx, My, relaxation, the
vertical model; vx < 0 is handled with |vx| (slips must be defined with |vx|).

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


def _prepare(P, kappa, alpha, gamma, fz, p, vx, form):
    """Inputs sanitized, low-speed factors, the basic quantities."""
    c = _Ctx()
    c.P = P
    c.f = _flags(form)
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
    vxlow = P["vxlow"]
    if vxlow > 0:
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


def _fx0(c):
    P, Fz, dfz, dpi = c.P, c.Fz, c.dfz, c.dpi
    Cx = P["pcx1"] * P["lcx"]
    mux = ((P["pdx1"] + P["pdx2"] * dfz) * (1.0 + P["ppx3"] * dpi + P["ppx4"] * dpi ** 2)
           * (1.0 - P["pdx3"] * c.gx ** 2) * c.lmux_s)
    Dx = mux * Fz
    Kxk = (Fz * (P["pkx1"] + P["pkx2"] * dfz) * np.exp(P["pkx3"] * dfz)
           * (1.0 + P["ppx1"] * dpi + P["ppx2"] * dpi ** 2) * P["lkx"])
    Bx = Kxk / (Cx * Dx + EPS * _sgn1(Dx))
    SHx = (P["phx1"] + P["phx2"] * dfz) * P["lhx"] * c.w
    SVx = Fz * (P["pvx1"] + P["pvx2"] * dfz) * P["lvx"] * c.lmux_p * c.w
    kx = c.kappa + SHx
    Ex = np.minimum((P["pex1"] + P["pex2"] * dfz + P["pex3"] * dfz ** 2)
                    * (1.0 - P["pex4"] * _sgn1(kx)) * P["lex"], 1.0)
    Fx0 = _mf(Bx, Cx, Dx, Ex, kx) + SVx
    return dict(Fx0=Fx0, mux=mux, Dx=Dx, Cx=Cx, Bx=Bx, Ex=Ex, Kxk=Kxk, SHx=SHx, SVx=SVx)


def _fy0(c, gy):
    """Pure lateral force at lateral camber gy (the model's gamma variable)."""
    P, Fz, dfz, dpi = c.P, c.Fz, c.dfz, c.dpi
    if c.mf6:
        den = (P["pky2"] + P["pky5"] * gy ** 2) * (1.0 + P["ppy2"] * dpi)
        Kya = (P["pky1"] * c.Fz0p * (1.0 + P["ppy1"] * dpi) * (1.0 - P["pky3"] * np.abs(gy))
               * np.sin(P["pky4"] * np.arctan((Fz / c.Fz0p) / _nz(den))) * P["lky"])
        Kyg0 = Fz * (P["pky6"] + P["pky7"] * dfz) * (1.0 + P["ppy5"] * dpi) * P["lkyc"]
        SVyg = Fz * (P["pvy3"] + P["pvy4"] * dfz) * gy * P["lkyc"] * c.lmuy_p
        Kya_p = Kya + EPS * _sgn1(Kya)
        SHy = ((P["phy1"] + P["phy2"] * dfz) * P["lhy"] + (Kyg0 * gy - SVyg) / Kya_p) * c.w
        SVy = (Fz * (P["pvy1"] + P["pvy2"] * dfz) * P["lvy"] * c.lmuy_p + SVyg) * c.w
        muy = ((P["pdy1"] + P["pdy2"] * dfz) * (1.0 + P["ppy3"] * dpi + P["ppy4"] * dpi ** 2)
               * (1.0 - P["pdy3"] * gy ** 2) * c.lmuy_s)
    else:
        Kya = (P["pky1"] * c.Fz0p * np.sin(P["pky4"] * np.arctan(Fz / _nz(P["pky2"] * c.Fz0p)))
               * (1.0 - P["pky3"] * np.abs(gy)) * P["lky"])
        SHy = ((P["phy1"] + P["phy2"] * dfz) * P["lhy"] + P["phy3"] * gy) * c.w
        SVy = (Fz * ((P["pvy1"] + P["pvy2"] * dfz) * P["lvy"] + (P["pvy3"] + P["pvy4"] * dfz) * gy)
               * c.lmuy_p * c.w)
        muy = (P["pdy1"] + P["pdy2"] * dfz) * (1.0 - P["pdy3"] * gy ** 2) * c.lmuy_s
    ay = c.a_s + SHy
    Cy = P["pcy1"] * P["lcy"]
    Dy = muy * Fz
    if c.mf6:
        Ey = (P["pey1"] + P["pey2"] * dfz) * (1.0 + P["pey5"] * gy ** 2
                                              - (P["pey3"] + P["pey4"] * gy) * _sgn1(ay)) * P["ley"]
    else:
        Ey = (P["pey1"] + P["pey2"] * dfz) * (1.0 - (P["pey3"] + P["pey4"] * gy) * _sgn1(ay)) * P["ley"]
    Ey = np.minimum(Ey, 1.0)
    By = Kya / (Cy * Dy + EPS * _sgn1(Dy))
    Fy0 = _mf(By, Cy, Dy, Ey, ay) + SVy
    return dict(Fy0=Fy0, muy=muy, Dy=Dy, Cy=Cy, By=By, Ey=Ey, Kya=Kya, SHy=SHy, SVy=SVy)


def _gyk(c, gy, muy):
    """Combined-slip weighting of Fy and the kappa-induced side force."""
    P, Fz, dfz = c.P, c.Fz, c.dfz
    rby4 = P["rby4"] if c.mf6 else 0.0
    Byk = (P["rby1"] + rby4 * gy ** 2) * np.cos(np.arctan(P["rby2"] * (c.a_s - P["rby3"]))) * P["lyka"]
    Cyk = P["rcy1"]
    Eyk = np.minimum(P["rey1"] + P["rey2"] * dfz, 1.0)
    SHyk = P["rhy1"] + P["rhy2"] * dfz
    Gyk = _weight(Byk, Cyk, Eyk, c.kappa + SHyk, SHyk)
    DVyk = muy * Fz * (P["rvy1"] + P["rvy2"] * dfz + P["rvy3"] * gy) * np.cos(np.arctan(P["rvy4"] * c.a_s))
    SVyk = DVyk * np.sin(P["rvy5"] * np.arctan(P["rvy6"] * c.kappa)) * P["lvyka"] * c.w
    return Gyk, SVyk


def _core(P, kappa, alpha, gamma, fz, p, vx, form, mz52_svyk_camber=False):
    """All forces and moments in ISO-W, no mirroring. Returns a dict.

    mz52_svyk_camber: MF 5.2 aligning moment with Fy' = Fy - SVyk(mu_y(gamma))
    (grip's earlier form) instead of MFeval's Fy - SVyk(mu_y(gamma = 0))."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        c = _prepare(P, kappa, alpha, gamma, fz, p, vx, form)
        Fz, dfz, dpi, R0 = c.Fz, c.dfz, c.dpi, P["unloaded_radius"]
        x0 = _fx0(c)
        y0 = _fy0(c, c.gy)
        y00 = _fy0(c, np.zeros_like(c.gy))                     # Fy0 at gamma = 0

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
        Et = np.minimum((P["qez1"] + P["qez2"] * dfz + P["qez3"] * dfz ** 2)
                        * (1.0 + (P["qez4"] + P["qez5"] * gz) * (2.0 / math.pi) * np.arctan(Bt * Ct * at)),
                        1.0)
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
        Mzr0 = Dr * np.cos(np.arctan(Br * ar)) * c.cosa * c.w
        Mz0 = -t0 * (y00["Fy0"] if c.mf6 else y0["Fy0"]) + Mzr0

        # ---- combined longitudinal force
        rbx3 = P["rbx3"] if c.mf6 else 0.0
        gxa = c.g_s if c.mf6 else c.gx
        Bxa = (P["rbx1"] + rbx3 * gxa ** 2) * np.cos(np.arctan(P["rbx2"] * c.kappa)) * P["lxal"]
        Cxa = P["rcx1"]
        Exa = np.minimum(P["rex1"] + P["rex2"] * dfz, 1.0)
        SHxa = P["rhx1"]
        Gxa = _weight(Bxa, Cxa, Exa, c.a_s + SHxa, SHxa)
        Fx = Gxa * x0["Fx0"]

        # ---- combined lateral force
        Gyk, SVyk = _gyk(c, c.gy, y0["muy"])
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
        Mzr = Dr * np.cos(np.arctan(Br * ar_eq)) * c.w * (c.cosa if c.f["mzr_cos"] else 1.0)
        t = Dt * np.cos(Ct * np.arctan(Bt * at_eq - Et * (Bt * at_eq - np.arctan(Bt * at_eq)))) * trail_scale
        if not c.mf6:
            # MF 5.2 (MF-Tyre 5.2 manual, as MFeval): Fy' = Fy - SVyk, where
            # MFeval's calculateMz takes SVyk from the combined-slip evaluation
            # with mu_y at gamma = 0 (muy_sub0; RVY3 and RBY4 keep gamma)
            SVyk_mz = SVyk if mz52_svyk_camber else _gyk(c, c.gy, y00["muy"])[1]
            Fyp = Fy - SVyk_mz
        elif c.f["fyp_gamma0"]:
            Gyk0, _ = _gyk(c, np.zeros_like(c.gy), y00["muy"])
            Fyp = Gyk0 * y00["Fy0"]
        else:
            Fyp = Gyk * y00["Fy0"]
        Mz = -t * Fyp + Mzr + s * Fx

        out = dict(fx0=x0["Fx0"], fy0=y0["Fy0"], mz0=Mz0, fx=Fx, fy=Fy, mz=Mz)
        for k in out:
            out[k] = np.where(c.loaded, out[k], 0.0)
        det = dict(x0)
        det.update(y0)
        det.update(dict(Gxa=Gxa, Gyk=Gyk, SVyk=SVyk, t0=t0, t=t, Mzr0=Mzr0, Mzr=Mzr, s=s,
                        Bt=Bt, Ct=Ct, Dt=Dt, Et=Et, Br=Br, Dr=Dr, SHt=SHt, SHf=SHf,
                        alpha_t=at, alpha_r=ar, alpha_t_eq=at_eq, alpha_r_eq=ar_eq, Fy_prime=Fyp,
                        Fy0_gamma0=y00["Fy0"], muy_gamma0=y00["muy"], r=c.r, ra=c.ra, w=c.w, dfz=dfz, dpi=dpi))
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


def evaluate(params, kappa, alpha, gamma, fz, p=None, vx=None, *, form="mftyre",
             convention="iso", kappa_braking=False, mirror=None, details=False,
             mz52_svyk_camber=False):
    """Forces and moments of one parameter set (array inputs broadcast).

    params: dict of grip_mf_params fields in SI (tir.Tir.params()).
    kappa [-], alpha [rad], gamma [rad], fz [N], p [Pa] (None: INFLPRES, or
    NOMPRES when INFLPRES is 0; ignored by MF 5.2), vx [m/s] (None: LONGVL).
    convention 'iso' (ISO-W, native) or 'sae'; kappa_braking=True: the given
    kappa is positive in braking. mirror: None = from params['tyreside']
    (-1 mirrors), or True/False to force.
    mz52_svyk_camber=True: MF 5.2 combined Mz with grip's earlier Fy' = Fy -
    SVyk(mu_y at gamma) (GRIP_MF_OPT_MZ52_SVYK_CAMBER) instead of MFeval's
    Fy - SVyk(mu_y at gamma = 0); no effect on MF 6.x.
    Returns {fx0, fy0, mz0, fx, fy, mz} (and the internals when details).
    """
    k, a, g, f = to_iso(kappa, alpha, gamma, fz, convention, kappa_braking)
    if mirror is None:
        mirror = int(params.get("tyreside", 1)) == -1
    if mirror:
        a, g = mirror_inputs(a, g)
    out, det = _core(params, k, a, g, f, p, vx, form, mz52_svyk_camber)
    if mirror:
        out = mirror_outputs(out)
    out = from_iso(out, convention)
    if details:
        out["details"] = det
    return out
