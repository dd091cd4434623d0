"""Brush-model family: float64 closed forms and full-precision quadrature references.

Models (seed 000, ch. 2.3 and 5; derivations, sign conventions and every
choice in docs/brush-models.md - keep the two in step):

  fiala      classic FIALA lateral force and aligning moment, normalized
             cubic/quartic form (2.54-2.66), full sliding for phi >= 3
  brush      brush model in braking/driving with separate adhesive (mu_s) and
             sliding (mu_d) friction, n-th power pressure, sliding friction
             falling with the sliding speed (2.67-2.92)
  sakai      Sakai's combined-slip brush model, parabolic pressure, lateral
             carcass compliance G_y (2.93-2.125)
  neofiala   reduced Neo-FIALA, pure and combined slip (5.1-5.40):
             generalized skewed parabola pressure, tread-base deflection eps,
             tread-base twist G_mz, pressure skew q and pressure-centre shift
             x_c (from Fx and/or Mz), slip-speed dependent sliding friction,
             camber through gamma_e

Two implementations of each model live here:

* `*_cf`: the closed forms the C library implements (lib/brush/), in
  float64. Every contact-patch integral is analytic; the implicit couplings of
  Neo-FIALA are eliminated exactly for a given adhesion boundary r_h, which
  leaves one scalar root in r_h. solver="exact" solves it with brentq to
  1e-15, solver="fixed" runs the C library's fixed iteration (Anderson-Bjorck
  with ROOT_ITERS steps) so its truncation error can be measured.
* `*_ref`: the reference: the local adhesive stress and the friction limit
  are evaluated point by point, the adhesion boundary is found as the first
  crossing of the friction limit along the contact patch (brentq), every
  force and moment is an adaptive quadrature (scipy.integrate.quad), and
  the couplings are solved to convergence by scipy.optimize.root on the
  vector (Fx, Fy, Mz). It shares nothing with the closed forms except the
  kinematic definitions (`kinematics`).

Sign convention of every public function: ISO-W like grip's Magic Formula
(kappa > 0 driving, Fx > 0 forward; alpha > 0 gives Fy < 0 and, at small
slip, Mz > 0). Internally the models work in the seed's frame: alpha >= 0
after mirroring, lateral force and deflection positive along the force.
Normalized quantities: forces / (mu_s Fz), moments / (mu_s Fz l),
x = x1 / l measured from the leading edge.
"""
import math
import os
from dataclasses import dataclass, fields

import numpy as np
from scipy import integrate, optimize

N_MIN = 2
N_MAX = 8            # GRIP_BRUSH_N_MAX of include/grip/grip_brush.h
ROOT_ITERS = 6       # GRIP_BRUSH_ROOT_ITERS: Anderson-Bjorck steps for r_h
M_BMIN = 0.125       # lower clamp of the Mz-equation slope (1 - N1)
IT_EPS = 1.0 / 1024  # below this 1 - r_h the sliding tip-displacement moment is 0
W_MIN, W_MAX = -1.0, 2.0   # clamp of the final secant weight (never active in the sweep)
Q_MAX = 0.9         # |q| clamp inside the residual (never active at the root in the valid range)
VS_EPS = 1.0 / 64    # brush: lower bound of 1 - r_h in the sliding speed (2.86)


# ---------------------------------------------------------------------------
# Parameter sets (SI units). Field order = parameter-file order.

@dataclass
class Fiala:
    ky: float = 60000.0       # N/rad   cornering stiffness Ky (2.61)
    mu: float = 1.0           # -       friction coefficient
    l: float = 0.2            # m       contact length
    fz_min: float = 200.0     # N       loads below are clamped (warning)
    fz_max: float = 10000.0   # N
    alpha_max: float = 0.6    # rad


@dataclass
class Brush:
    kx: float = 80000.0       # N       Kx = Cx w l^2 / 2 (2.78)
    mu_s: float = 1.1         # -       adhesive (static) friction
    mu_d0: float = 0.9        # -       sliding friction at zero sliding speed
    a_v: float = 0.005        # s/m     mu_d = mu_d0 - a_v Vs (2.85-2.87)
    n: int = 4                # -       pressure exponent (2.88)
    fz_min: float = 200.0
    fz_max: float = 10000.0
    kappa_max: float = 1.0    # -       driving slip limit (braking down to -1)
    v_max: float = 60.0       # m/s


@dataclass
class Sakai:
    k: float = 57200.0        # N(/rad) K = C w l^2 / 2, x and y (2.115); Table 2.1
    g_y: float = 250000.0     # N/m     lateral carcass stiffness, y0 = Fy / G_y; Table 2.1
    mu_s: float = 1.0         # -       adhesive friction (value lost in the seed; chosen)
    mu_d: float = 0.8         # -       sliding friction (value lost in the seed; chosen)
    l: float = 0.18           # m       contact length (value lost in the seed; chosen)
    fz_min: float = 200.0
    fz_max: float = 10000.0
    alpha_max: float = 0.6
    kappa_max: float = 1.0


@dataclass
class NeoFiala:
    l: float = 0.18           # m       contact length
    w: float = 0.18           # m       contact width (camber geometry only)
    kx: float = 70000.0       # N       longitudinal stiffness Kx = Cx w l^2 / 2
    ky: float = 60000.0       # N/rad   lateral stiffness Ky = Cy w l^2 / 2 (5.8)
    mu_s: float = 1.1         # -       adhesive friction
    mu_d0: float = 0.9        # -       sliding friction at zero slip speed
    a_v: float = 0.004        # s/m     mu_d = mu_d0 - a_v Vs (5.35)
    n: int = 4                # -       pressure exponent (5.6)
    q0: float = 0.0           # -       pressure skew at zero force
    c_q: float = 0.0          # 1/N     q += c_q Fx (5.30)
    c_qm: float = 0.0         # 1/(N m) q += c_qm Mz (5.17)
    c_xc: float = 0.0         # 1/N     x_c/l += c_xc Fx (5.31)
    xi: float = 0.0           # m/N     x_c/l -= xi Mz / l^2 (5.18)
    eps: float = 0.0          # 1/(N m) tread-base deflection (5.10, 5.13)
    g_mz: float = 0.0         # N m/rad tread-base twist stiffness (5.11); 0 = rigid
    a_x: float = 0.0          # N m     Ax = fx w l^2 / 2 (5.28)
    c_gamma: float = 0.0      # -       camber: equivalent slope per rad of gamma_e
    h: float = 0.0            # m       camber: height in eta = 2 h w sin(gamma_e) / l^2 (5.40)
    g_my: float = 0.0         # N/rad   camber: gamma_e = gamma + eta Fy_gamma / G_my (5.39); 0 = off
    fz_min: float = 200.0
    fz_max: float = 10000.0
    alpha_max: float = 0.6
    kappa_max: float = 1.0
    gamma_max: float = 0.2
    v_max: float = 60.0


MODELS = {"fiala": Fiala, "brush": Brush, "sakai": Sakai, "neofiala": NeoFiala}
INT_FIELDS = {"n"}


def validate(model, p):
    """Return a list of problems (empty when the set is in the valid range the
    C library accepts: grip_*_check_params)."""
    bad = []

    def need(ok, what):
        if not ok:
            bad.append(what)

    for f in fields(p):
        v = getattr(p, f.name)
        need(isinstance(v, (int, float)) and math.isfinite(v), f"{f.name} must be finite")
    if bad:
        return bad
    need(0 < p.fz_min <= p.fz_max <= 100000.0, "need 0 < fz_min <= fz_max <= 100 kN")
    if bad:
        return bad
    for name, fmt, scale in C_UNITS[model]:
        lim = {"QS": 32767.0, "QL": 8388607.0, "int": 1000.0}[fmt]
        need(abs(getattr(p, name) * scale) <= lim,
             f"{name} = {getattr(p, name):g} does not fit the fixed-point format {fmt} of the C struct")
    if bad:
        return bad
    if model == "fiala":
        need(p.ky > 0 and p.mu > 0 and p.l > 0, "ky, mu, l must be > 0")
        if bad:
            return bad
        need(p.mu <= 3.0 and p.l <= 2.0, "mu <= 3, l <= 2 m")
        need(p.ky / (p.mu * p.fz_min) <= 1000.0, "ky / (mu fz_min) <= 1000")
        need(0 < p.alpha_max <= 1.0, "0 < alpha_max <= 1 rad")
        return bad
    if model == "sakai":
        need(p.k > 0 and p.g_y > 0 and p.l > 0, "k, g_y, l must be > 0")
        need(0 < p.mu_d <= p.mu_s <= 3.0, "0 < mu_d <= mu_s <= 3")
        if bad:
            return bad
        need(p.l <= 2.0, "l <= 2 m")
        need(p.k / (p.mu_s * p.fz_min) <= 1000.0, "k / (mu_s fz_min) <= 1000")
        need(p.mu_s * p.fz_max / (p.g_y * p.l) <= 4.0, "mu_s fz_max / (g_y l) <= 4")
        need(0 < p.alpha_max <= 1.0, "0 < alpha_max <= 1 rad")
        need(0 < p.kappa_max <= 10.0, "0 < kappa_max <= 10")
        return bad
    need(N_MIN <= p.n <= N_MAX and int(p.n) == p.n, f"n must be an integer in [{N_MIN}, {N_MAX}]")
    need(0 < p.mu_d0 <= p.mu_s <= 3.0, "0 < mu_d0 <= mu_s <= 3")
    if not (p.mu_s > 0 and p.fz_min > 0):
        return bad
    need(0 <= p.a_v <= 1.0, "0 <= a_v <= 1 s/m")
    need(0 < p.kappa_max <= 10.0, "0 < kappa_max <= 10")
    need(0 < p.v_max <= 150.0, "0 < v_max <= 150 m/s")
    if model == "brush":
        need(p.kx > 0, "kx must be > 0")
        need(p.kx / (p.mu_s * p.fz_min) <= 1000.0, "kx / (mu_s fz_min) <= 1000")
        return bad
    # neofiala
    need(0 < p.l <= 2.0 and 0 < p.w <= 2.0, "0 < l, w <= 2 m")
    need(p.kx > 0 and p.ky > 0, "kx, ky must be > 0")
    if bad:
        return bad
    need(max(p.kx, p.ky) / (p.mu_s * p.fz_min) <= 1000.0, "max(kx, ky) / (mu_s fz_min) <= 1000")
    need(0 < p.alpha_max <= 1.0, "0 < alpha_max <= 1 rad")
    need(0 <= p.gamma_max <= 0.35, "0 <= gamma_max <= 0.35 rad")
    fmax = p.mu_s * p.fz_max
    need(abs(p.q0) <= 0.5, "|q0| <= 0.5")
    need(abs(p.c_q) * fmax <= 0.2, "|c_q| mu_s fz_max <= 0.2")
    need(abs(p.c_qm) * fmax * p.l <= 0.2, "|c_qm| mu_s fz_max l <= 0.2")
    need(abs(p.c_xc) * fmax <= 0.1, "|c_xc| mu_s fz_max <= 0.1")
    need(abs(p.xi) * fmax / p.l <= 0.1, "|xi| mu_s fz_max / l <= 0.1")
    need(0 <= p.eps and p.eps * p.l * p.ky <= 1.5, "0 <= eps l ky <= 1.5")
    need(p.g_mz == 0 or (p.g_mz > 0 and p.ky * p.l / p.g_mz <= 1.5), "g_mz = 0 or ky l / g_mz <= 1.5")
    need(abs(p.a_x) / (p.mu_s * p.fz_min * p.l) <= 0.1, "|a_x| / (mu_s fz_min l) <= 0.1")
    need(abs(p.c_gamma) <= 2.0, "|c_gamma| <= 2")
    need(p.h >= 0 and p.g_my >= 0, "h, g_my >= 0")
    need(4.0 * abs(_camber_a(p)) * p.gamma_max <= 0.5, "4 |A_gamma| gamma_max <= 0.5")
    return bad


def _camber_a(p):
    """A_gamma of gamma_e = gamma + A_gamma gamma_e |gamma_e| (5.39-5.40, small angles)."""
    if p.g_my <= 0:
        return 0.0
    return 2.0 * p.h * p.w / (p.l * p.l) * p.ky * p.c_gamma / p.g_my


# ---------------------------------------------------------------------------
# Parameter file: "key = value" lines, SI units, '#' comments, one "model ="
# line first. Read and written by the Python tools and by
# port/linux/brush_params.c.

def write_params(path_or_file, model, p, comment=None):
    own = isinstance(path_or_file, str)
    f = open(path_or_file, "w") if own else path_or_file
    try:
        f.write(f"# grip brush-model parameter file (docs/brush-models.md), SI units\n")
        if comment:
            for line in str(comment).splitlines():
                f.write(f"# {line}\n")
        f.write(f"model = {model}\n")
        for fl in fields(p):
            v = getattr(p, fl.name)
            f.write(f"{fl.name} = {int(v) if fl.name in INT_FIELDS else repr(float(v))}\n")
    finally:
        if own:
            f.close()


class ParamError(Exception):
    pass


def parse_params(text, path="<text>"):
    """(model, params). Unknown keys, duplicates, bad numbers and missing
    model are errors; missing keys take the dataclass defaults."""
    model = None
    vals = {}
    for i, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if "=" not in line:
            raise ParamError(f"{path}:{i}: expected 'key = value'")
        k, v = (s.strip() for s in line.split("=", 1))
        if k == "model":
            if model is not None:
                raise ParamError(f"{path}:{i}: model: given twice")
            if v not in MODELS:
                raise ParamError(f"{path}:{i}: model: '{v}' is not one of {', '.join(MODELS)}")
            model = v
            continue
        if model is None:
            raise ParamError(f"{path}:{i}: the first entry must be 'model = ...'")
        names = {f.name for f in fields(MODELS[model])}
        if k not in names:
            raise ParamError(f"{path}:{i}: {k}: unknown key for model {model}")
        if k in vals:
            raise ParamError(f"{path}:{i}: {k}: given twice")
        try:
            x = float(v)
        except ValueError:
            raise ParamError(f"{path}:{i}: {k}: '{v}' is not a number") from None
        if not math.isfinite(x):
            raise ParamError(f"{path}:{i}: {k}: '{v}' is not finite")
        if k in INT_FIELDS:
            if x != int(x):
                raise ParamError(f"{path}:{i}: {k}: must be an integer")
            x = int(x)
        vals[k] = x
    if model is None:
        raise ParamError(f"{path}:0: no 'model = ...' entry")
    p = MODELS[model](**vals)
    bad = validate(model, p)
    if bad:
        raise ParamError(f"{path}:0: invalid parameter set: " + "; ".join(bad))
    return model, p


# The readers' bound (port/linux/brush_params.c): parameter files are a few
# hundred bytes; a larger file, a device or binary data is refused.
MAX_FILE_BYTES = 1000000


def read_params(path):
    """parse_params of a file: at most MAX_FILE_BYTES of text (no NUL)."""
    with open(path, "rb") as f:
        data = f.read(MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES:
        raise ParamError(f"{path}:0: cannot read (or larger than 1 MB)")
    z = data.find(b"\0")
    if z >= 0:
        line = data.count(b"\n", 0, z) + 1
        raise ParamError(f"{path}:{line}: NUL byte at byte offset {z}: not a text parameter file")
    return parse_params(data.decode("utf-8", "replace"), path)


# ---------------------------------------------------------------------------
# Pressure distribution (5.5, 5.6): D(x; n, q) = (1 - |2x - 1|^n)(1 - q (2x - 1)),
# normalized pressure c D with c = (n + 1) / n integrates to 1 over [0, 1].

def dgsp(x, n, q):
    u = 2.0 * np.asarray(x, dtype=float) - 1.0
    return (1.0 - np.abs(u) ** n) * (1.0 - q * u)


def _powgeo(a, n):
    """a^n and 1 + a + ... + a^(n-1) (float or array a). The C library forms
    the same by a product chain per n (pow_geo in lib/brush/brush_core.c)."""
    p = 1.0
    g = 0.0
    for _ in range(n):
        g += p
        p *= a
    return p, g


def lmax(rh, n, q):
    """c D(rh) / (2 rh): the largest adhesive stress gradient (in units of
    mu_s Fz) the friction limit admits at the boundary rh. Division-free form:
    1 - a^n = (1 - a)(1 + ... + a^(n-1)) with 1 - a = 2 min(rh, 1 - rh)."""
    u = 2.0 * rh - 1.0
    _, g = _powgeo(abs(u), n)
    fac = 1.0 if rh <= 0.5 else (1.0 - rh) / rh
    return (n + 1.0) / n * fac * g * (1.0 - q * u)


def pint(rh, n):
    """Closed-form integrals over the sliding region [rh, 1], split by q:
    int D = I00 + q I01, int D x = I10 + q I11, int D (1 - x) / (1 - rh) = It0 + q It1.
    With u0 = 2 rh - 1, P = |u0|^n:  int_u0^1 u^k du = (1 - u0^(k+1)) / (k+1) and
    int_u0^1 |u|^n u^k du = (1 - P u0^(k+1)) / (n+k+1) for either sign of u0."""
    u0 = 2.0 * rh - 1.0
    p, _ = _powgeo(abs(u0), n)
    ab = []
    uk = u0
    for k in range(3):
        ab.append((1.0 - uk) / (k + 1.0) - (1.0 - p * uk) / (n + k + 1.0))
        uk *= u0
    i00 = 0.5 * ab[0]
    i01 = -0.5 * ab[1]
    i10 = 0.25 * (ab[0] + ab[1])
    i11 = -0.25 * (ab[1] + ab[2])
    om = 1.0 - rh
    if om >= IT_EPS:
        it0 = 0.25 * (ab[0] - ab[1]) / om
        it1 = 0.25 * (ab[2] - ab[1]) / om
    else:
        it0 = it1 = 0.0
    return i00, i01, i10, i11, it0, it1


def _hypot(x, y):
    return math.hypot(x, y)


# ---------------------------------------------------------------------------
# Kinematics shared by closed forms and references (definitions only).

def _slip_split(kappa, ta):
    """Seed slip per regime. kappa < 0 braking: S = -kappa (2.70), deflection
    gradients in the road coordinate (gx, gy) = (-S, tan), tread-base
    coordinate factor k = 1 - S; kappa >= 0 driving: S = kappa / (1 + kappa)
    (2.84), (gx, gy) = (S, (1 - S) tan), k = 1. Returns gx (signed, ISO),
    kf (factor of tan alpha in gy), k."""
    if kappa < 0.0:
        s = -kappa
        return -s, 1.0, 1.0 - s
    s = kappa / (1.0 + kappa)
    return s, 1.0 - s, 1.0


def _clamp_inputs(p, kappa=0.0, alpha=0.0, gamma=0.0, fz=1.0, vx=0.0):
    """Clamped inputs and the warning flag, as the C library clamps them."""
    warn = False
    a_max = getattr(p, "alpha_max", math.pi / 2)
    if abs(alpha) > a_max:
        alpha = math.copysign(a_max, alpha)
        warn = True
    k_max = getattr(p, "kappa_max", 1.0)
    if kappa < -1.0:
        kappa, warn = -1.0, True
    elif kappa > k_max:
        kappa, warn = k_max, True
    g_max = getattr(p, "gamma_max", 0.0)
    if abs(gamma) > g_max:
        gamma = math.copysign(g_max, gamma)
        warn = True
    if fz < p.fz_min:
        fz, warn = p.fz_min, True
    elif fz > p.fz_max:
        fz, warn = p.fz_max, True
    v_max = getattr(p, "v_max", 1e9)
    vx = abs(vx)
    if vx > v_max:
        vx, warn = v_max, True
    return kappa, alpha, gamma, fz, vx, warn


def gamma_effective(p, gamma):
    """gamma_e = gamma + A gamma_e |gamma_e| (5.39-5.40 with the camber force
    taken at its linear value Ky c_gamma gamma_e and sin gamma_e ~ gamma_e),
    the root continuous at A = 0: 2 gamma / (1 + sqrt(1 - 4 A |gamma|))."""
    a = _camber_a(p)
    g = abs(gamma)
    return math.copysign(2.0 * g / (1.0 + math.sqrt(1.0 - 4.0 * a * g)), gamma) if g > 0 else 0.0


def kinematics(p, kappa, alpha, gamma, fz, vx):
    """Normalized, mirrored problem of one Neo-FIALA evaluation (dict)."""
    n = int(p.n)
    c = (n + 1.0) / n
    f0 = p.mu_s * fz
    ta = math.tan(alpha)
    ge = gamma_effective(p, gamma)
    teq = ta + p.c_gamma * ge
    sgn = -1.0 if teq < 0.0 else 1.0
    gx, kf, k = _slip_split(kappa, ta)
    gyk = kf * abs(teq)                 # camber acts as an equivalent slip angle, also in theta
    h = _hypot(gx, gyk)
    cth, sth = (gx / h, gyk / h) if h > 0.0 else (0.0, 0.0)
    vs = vx * math.sqrt(kappa * kappa + ta * ta)
    mud = max(p.mu_d0 - p.a_v * vs, 0.0)
    rd = mud / p.mu_s
    kx = p.kx / f0
    ky = p.ky / f0
    return dict(
        n=n, c=c, inv1=1.0 / (n + 1.0), inv2=1.0 / (n + 2.0), inv3=1.0 / (n + 3.0),
        sgn=sgn, kx=kx, ky=ky, gx=gx, sx=kx * gx, kf=kf, k=k,
        teq=abs(teq), cth=cth, sth=sth, rd=rd, mud=mud, rdcc=rd * c * cth, rdcs=rd * c * sth,
        en=p.eps * p.l * f0, eky=p.eps * p.l * p.ky, kyg=(p.ky * p.l / p.g_mz) if p.g_mz > 0 else 0.0,
        gn=(f0 * p.l / p.g_mz) if p.g_mz > 0 else 0.0,
        axn=p.a_x / (f0 * p.l), cqx=p.c_q * f0, cqm=p.c_qm * f0 * p.l, cxc=p.c_xc * f0,
        xin=p.xi * f0 / p.l, q0=p.q0, f0=f0, l=p.l, gamma_e=ge)


# ---------------------------------------------------------------------------
# Neo-FIALA closed form

TABLE_M = 32         # GRIP_BRUSH_TABLE_M: segments of the inverse table per n


def lmax_inverse_table(n, m=TABLE_M):
    """rh_j with lmax(rh_j; n, 0) = (n + 1) j / m, j = 0..m (rh_0 = 1, rh_m = 0):
    nodes of the piecewise-linear map y -> rh that makes the root problem
    nearly linear (lib/brush/brush_table.h)."""
    out = [1.0]
    for j in range(1, m):
        y = (n + 1.0) * j / m
        out.append(optimize.brentq(lambda r: lmax(r, n, 0.0) - y, 0.0, 1.0, xtol=1e-16, rtol=1e-15))
    out.append(0.0)
    return out


_TABLES = {}


def table_rh(n, y):
    """Piecewise-linear inverse: y in [0, 1] -> rh (y = 0 -> 1, y = 1 -> 0)."""
    tab = _TABLES.get(n)
    if tab is None:
        tab = _TABLES[n] = lmax_inverse_table(n)
    t = min(max(y, 0.0), 1.0) * TABLE_M
    j = min(int(t), TABLE_M - 1)
    return tab[j] + (t - j) * (tab[j + 1] - tab[j])


class _ScalarOps:
    """Operations of nf_state on Python floats."""
    where = staticmethod(lambda c, a, b: a if c else b)
    maximum = staticmethod(max)
    clip = staticmethod(lambda x, lo, hi: min(max(x, lo), hi))
    sqrt = staticmethod(math.sqrt)
    hypot = staticmethod(math.hypot)


class _ArrayOps:
    """The same on numpy arrays (elementwise, broadcast)."""
    where = staticmethod(np.where)
    maximum = staticmethod(np.maximum)
    clip = staticmethod(np.clip)
    sqrt = staticmethod(np.sqrt)
    hypot = staticmethod(np.hypot)


def nf_state(rh, K):
    """Everything at a trial boundary rh. For fixed rh the couplings
    q = q0 + c_q Fx + c_qm Mz, x_c/l = 1/2 + c_xc Fx - xi Mz / l^2,
    e = eps l Fy and tan(alpha_e) = tan(alpha) - Mz / G_mz are affine in
    m = Mz / (mu_s Fz l), and the moment equation m = N(m) is a quadratic in m,
    solved exactly. Returns the transformed friction-limit residual
    F(rh) = [Lmax(rh) - |adhesive stress gradient at rh|] / (1 - q u)
    (decreasing in rh, zero at the boundary) and the state. Stress
    gradients are carried as s = K g (units of mu_s Fz): sx = Kx gx,
    sy = Ky gy, as the fixed-point C code does.

    One implementation for both uses: rh a float and K of floats (the scalar
    closed form, brentq, the proof against quadrature), or rh a numpy array
    and K of arrays or floats (neofiala_vec, the fitting tool); every branch
    is a `where` whose both sides are finite."""
    xp = _ArrayOps if isinstance(rh, np.ndarray) else _ScalarOps
    n, c = K["n"], K["c"]
    sx, kf, k = K["sx"], K["kf"], K["k"]
    rdcc, rdcs = K["rdcc"], K["rdcs"]
    eky = K["eky"]
    u = 2.0 * rh - 1.0
    p, g = _powgeo(abs(u), n)
    u2 = u * u
    u3 = u2 * u
    ab0 = (1.0 - u) - (1.0 - p * u) * K["inv1"]
    ab1 = (1.0 - u2) * 0.5 - (1.0 - p * u2) * K["inv2"]
    ab2 = (1.0 - u3) / 3.0 - (1.0 - p * u3) * K["inv3"]
    i00 = 0.5 * ab0
    i01 = -0.5 * ab1
    i10 = 0.25 * (ab0 + ab1)
    i11 = -0.25 * (ab1 + ab2)
    om = 1.0 - rh
    ok = om >= IT_EPS
    som = xp.where(ok, om, 1.0)
    it0 = xp.where(ok, 0.25 * (ab0 - ab1) / som, 0.0)
    it1 = xp.where(ok, 0.25 * (ab2 - ab1) / som, 0.0)
    r2 = rh * rh
    r3 = r2 * rh
    # Fx = A + B q and q = q0 + cqx Fx + cqm m  ->  q = qa + qb m
    a_ = sx * r2 + rdcc * i00
    b_ = rdcc * i01
    dq = 1.0 - K["cqx"] * b_
    qa = (K["q0"] + K["cqx"] * a_) / dq
    qb = K["cqm"] / dq
    fxa = a_ + b_ * qa
    fxb = b_ * qb
    # tread-base twist: gy = kf (teq - gn m), sy = Ky gy = kf (ky teq - kyg m)
    ga = kf * K["teq"]
    gb = -kf * K["gn"]
    sya = kf * K["ky"] * K["teq"]
    syb = -kf * K["kyg"]
    ida, idb = i00 + i01 * qa, i01 * qb
    ixa, ixb = i10 + i11 * qa, i11 * qb
    ita, itb = it0 + it1 * qa, it1 * qb
    # Fy (1 + eky (k r^2 - 2/3 k^2 r^3)) = r^2 sy + rd c sth ID
    den = 1.0 + eky * (k * r2 - 2.0 / 3.0 * k * k * r3)
    fya = (r2 * sya + rdcs * ida) / den
    fyb = (r2 * syb + rdcs * idb) / den
    # first moment about the leading edge
    w2 = k * r3 / 3.0 - k * k * r3 * rh / 4.0
    m1a = 2.0 * (r3 / 3.0 * sya - eky * w2 * fya) + rdcs * ixa
    m1b = 2.0 * (r3 / 3.0 * syb - eky * w2 * fyb) + rdcs * ixb
    # moment reference x_c
    xca = 0.5 + K["cxc"] * fxa
    xcb = K["cxc"] * fxb - K["xin"]
    # longitudinal stresses at the tip's lateral position, and the Ax term
    za = 2.0 / 3.0 * sx * r3 + rdcc * rh * ita + K["axn"] * rh
    zb = rdcc * rh * itb
    # Mz = M1 - x_c Fy + gy Z = n0 + n1 m + n2 m^2
    n0 = m1a - xca * fya + ga * za
    n1 = m1b - (xca * fyb + xcb * fya) + (ga * zb + gb * za)
    n2 = -xcb * fyb + gb * zb
    bq = xp.maximum(1.0 - n1, M_BMIN)
    disc = xp.maximum(bq * bq - 4.0 * n2 * n0, 0.0)
    m = xp.where(n2 == 0.0, n0 / bq, 2.0 * n0 / (bq + xp.sqrt(disc)))
    q = qa + qb * m
    sy = sya + syb * m
    fy = fya + fyb * m
    fx = fxa + fxb * m
    syr = sy - eky * fy * k * (1.0 - k * rh)            # lateral stress gradient at rh
    fac = xp.where(rh <= 0.5, 1.0, om / xp.where(rh > 0.0, rh, 1.0))
    qc = xp.clip(q, -Q_MAX, Q_MAX)      # only active off the root (trial rh far from it)
    res = c * fac * g - xp.hypot(sx, syr) / (1.0 - qc * u)
    return res, dict(fx=fx, fy=fy, mz=m, q=q, gy=ga + gb * m, rh=rh, slope=bq)


_STATE_KEYS = ("fx", "fy", "mz", "q", "gy", "rh")


def _fixed_root(K, r0, s0, s_unc, iters):
    """The C library's fixed iteration (brush_core_solve in
    lib/brush/brush_core.c), elementwise on numpy arrays (0-d for one case):
    Anderson-Bjorck regula falsi on [0, 1] in y = lmax / (n + 1), rh =
    table_rh(n, y), from f(1) = r0 > 0 (the state at rh = 0, s0) and f(0)
    replaced by the uncoupled value -s_unc / (1 - q0) (always < 0; the true
    value is <= 0, so [0, 1] stays a bracket), `iters` steps. The result is
    not evaluated again: the states of the last two evaluated points are
    combined along their secant, weight w = f1 / (f1 - f2) (the outputs are
    smooth in y, so this is as accurate as a further step). Meaningful where
    r0 > 0 and s_unc > 0 (nf_solve, neofiala_vec select the other cases)."""
    n = K["n"]
    fa = np.array(r0, dtype=float)
    fb = -np.where(s_unc > 0, s_unc, 1.0) / (1.0 - K["q0"])
    ya, yb = np.ones_like(fa), np.zeros_like(fa)
    side = np.zeros_like(fa)
    s_prev = s_last = s0
    f1 = f2 = np.zeros_like(fa)
    for _ in range(iters):
        d = fb - fa
        t = np.where(d < 0.0, np.clip(fb / np.where(d < 0.0, d, -1.0), 0.0, 1.0), 0.5)
        y = yb + t * (ya - yb)
        fx, st = nf_state(_table_rh_vec(n, y), K)
        s_prev, s_last = s_last, st
        f1, f2 = f2, fx
        pos = fx > 0.0
        mfa = np.where(fa > 0.0, 1.0 - fx / np.where(fa > 0.0, fa, 1.0), 0.0)
        fb = np.where(pos & (side > 0), np.where(mfa > 0.0, mfa * fb, 0.5 * fb), fb)
        mfb = 1.0 - fx / np.where(fb < 0.0, fb, -1.0)
        fa_new = np.where(~pos & (side < 0) & (fb < 0.0), np.where(mfb > 0.0, mfb * fa, 0.5 * fa), fa)
        ya = np.where(pos, y, ya)
        yb = np.where(pos, yb, y)
        fa = np.where(pos, fx, fa_new)
        fb = np.where(pos, fb, fx)
        side = np.where(pos, 1.0, -1.0)
    dd = f1 - f2
    w = np.where(dd != 0.0, np.clip(f1 / np.where(dd != 0.0, dd, 1.0), W_MIN, W_MAX), 1.0)
    out = {k: s_prev[k] + w * (s_last[k] - s_prev[k]) for k in _STATE_KEYS}
    out["slope"] = s_last["slope"]
    return out


def nf_solve(K, solver="exact", iters=ROOT_ITERS):
    """The normalized state at the adhesion boundary."""
    r0, s0 = nf_state(0.0, K)
    if r0 <= 0.0:
        return s0                       # full sliding
    s_unc = _hypot(K["sx"], K["kf"] * K["ky"] * K["teq"])
    if s_unc <= 0.0:
        return nf_state(1.0, K)[1]      # no slip at all
    if solver == "exact":
        f = lambda r: nf_state(r, K)[0]
        if f(1.0) >= 0.0:
            return nf_state(1.0, K)[1]
        rh = optimize.brentq(f, 0.0, 1.0, xtol=1e-16, rtol=1e-15, maxiter=500)
        return nf_state(rh, K)[1]
    # Fixed iteration of the C library (the same code as neofiala_vec, on 0-d arrays)
    st = _fixed_root(K, r0, s0, s_unc, iters)
    return {k: float(v) for k, v in st.items()}


def _to_iso(K, st, warn):
    f0 = K["f0"]
    return dict(fx=st["fx"] * f0, fy=-K["sgn"] * st["fy"] * f0, mz=K["sgn"] * st["mz"] * f0 * K["l"],
                rh=st["rh"], q=st["q"], warn=warn)


def neofiala_cf(p, kappa, alpha, gamma, fz, vx, solver="exact", iters=ROOT_ITERS):
    """Neo-FIALA, closed forms. Returns dict fx, fy, mz [N, N m] (ISO-W), rh, q, warn."""
    kappa, alpha, gamma, fz, vx, warn = _clamp_inputs(p, kappa, alpha, gamma, fz, vx)
    K = kinematics(p, kappa, alpha, gamma, fz, vx)
    return _to_iso(K, nf_solve(K, solver, iters), warn)


# ---------------------------------------------------------------------------
# FIALA (2.60-2.66)

def fiala_cf(p, alpha, fz):
    """Normalized FIALA: phi = Ky |tan alpha| / (mu Fz) (2.64),
    Fy/(mu Fz) = phi - phi^2/3 + phi^3/27, Mz/(mu Fz l) = phi/6 - phi^2/6 +
    phi^3/18 - phi^4/162 for phi < 3; full sliding (1, 0) beyond."""
    _, alpha, _, fz, _, warn = _clamp_inputs(p, alpha=alpha, fz=fz)
    phi = p.ky * abs(math.tan(alpha)) / (p.mu * fz)
    if phi < 3.0:
        fy = phi - phi ** 2 / 3.0 + phi ** 3 / 27.0
        mz = phi / 6.0 - phi ** 2 / 6.0 + phi ** 3 / 18.0 - phi ** 4 / 162.0
        rh = 1.0 - phi / 3.0
    else:
        fy, mz, rh = 1.0, 0.0, 0.0
    s = -1.0 if alpha < 0 else 1.0
    return dict(fx=0.0, fy=-s * fy * p.mu * fz, mz=s * mz * p.mu * fz * p.l, rh=rh, warn=warn)


# ---------------------------------------------------------------------------
# Brush model, pure longitudinal slip (2.67-2.92)

def _brush_mud(p, kappa, vx, rh):
    """mu_d = mu_d0 - a_v Vs, Vs = |kappa| V / (1 - rh) (2.85-2.87: the slip
    speed plus the relaxation of the deflection over the sliding region)."""
    vs = abs(kappa) * vx / max(1.0 - rh, VS_EPS)
    return max(p.mu_d0 - p.a_v * vs, 0.0)


def brush_problem(n, sx):
    """The Neo-FIALA root problem reduced to the pure-longitudinal brush:
    no lateral slip, no couplings; its boundary solves lmax(rh) = |sx| (2.90)."""
    c = (n + 1.0) / n
    return dict(n=n, c=c, inv1=1.0 / (n + 1.0), inv2=1.0 / (n + 2.0), inv3=1.0 / (n + 3.0),
                sx=sx, kx=1.0, ky=1.0, kf=1.0, k=1.0, teq=0.0, rdcc=0.0, rdcs=0.0, eky=0.0, kyg=0.0,
                gn=0.0, axn=0.0, cqx=0.0, cqm=0.0, cxc=0.0, xin=0.0, q0=0.0)


def brush_cf(p, kappa, fz, vx, solver="exact", iters=ROOT_ITERS):
    kappa, _, _, fz, vx, warn = _clamp_inputs(p, kappa=kappa, fz=fz, vx=vx)
    n = int(p.n)
    c = (n + 1.0) / n
    f0 = p.mu_s * fz
    gx, _, _ = _slip_split(kappa, 0.0)
    kx = p.kx / f0
    # boundary (2.90): 2 Kx S rh = c mu_s Fz D(rh)  <=>  lmax(rh) = kx |gx|
    rh = nf_solve(brush_problem(n, kx * gx), solver, iters)["rh"]
    mud = _brush_mud(p, kappa, vx, rh)
    i00 = pint(rh, n)[0]
    sg = -1.0 if gx < 0 else (1.0 if gx > 0 else 0.0)
    fxn = kx * gx * rh * rh + sg * mud / p.mu_s * c * i00              # (2.92)
    return dict(fx=fxn * f0, fy=0.0, mz=0.0, rh=rh, mud=mud, warn=warn)


# ---------------------------------------------------------------------------
# Sakai (2.93-2.125)

def _sakai_kin(p, kappa, alpha):
    """Braking (kappa < 0, S = -kappa): gradients (S cos a, sin a) in the
    road coordinate x1 = V t (2.99-2.100); driving (S = kappa/(1+kappa)):
    (S, (1 - S) tan a) in the belt coordinate x1 = Vb t (2.101-2.102)."""
    a = abs(alpha)
    if kappa < 0.0:
        s = -kappa
        return -s * math.cos(a), math.sin(a)
    s = kappa / (1.0 + kappa)
    return s, (1.0 - s) * math.tan(a)


def sakai_cf(p, kappa, alpha, fz):
    kappa, alpha, _, fz, _, warn = _clamp_inputs(p, kappa=kappa, alpha=alpha, fz=fz)
    f0 = p.mu_s * fz
    kn = p.k / f0
    rd = p.mu_d / p.mu_s
    gx, gy = _sakai_kin(p, kappa, alpha)
    g = _hypot(gx, gy)
    cth, sth = (gx / g, gy / g) if g > 0 else (0.0, 0.0)
    rh = max(1.0 - kn * g / 3.0, 0.0)                         # (2.114), friction circle
    r2 = rh * rh
    om = 1.0 - rh
    j0 = om * om * (1.0 + 2.0 * rh)                            # int_rh^1 6x(1-x)
    fx = kn * gx * r2 + rd * cth * j0                          # (2.120), (2.123)
    fy = kn * gy * r2 + rd * sth * j0                          # (2.121), (2.124)
    y0 = fy * f0 / (p.g_y * p.l)                               # y0 / l, y0 = Fy / G_y
    # lateral stresses about the contact centre (arm x - 1/2)
    mzy = kn * gy * r2 * (4.0 * rh - 3.0) / 6.0 + 1.5 * rd * sth * r2 * om * om
    # longitudinal stresses at the tip's lateral position y0 + gy x (adhesion),
    # y0 + gy rh (1 - x)/(1 - rh) (sliding, Sakai's linear decay)
    mzx = kn * gx * (y0 * r2 + 2.0 / 3.0 * gy * r2 * rh) \
        + rd * cth * (y0 * j0 + gy * rh * om * om * (1.0 + 3.0 * rh) / 2.0)
    mz = mzy + mzx                                             # (2.122), (2.125)
    s = -1.0 if alpha < 0 else 1.0
    return dict(fx=fx * f0, fy=-s * fy * f0, mz=s * mz * f0 * p.l, rh=rh, warn=warn)


# ---------------------------------------------------------------------------
# Quadrature references

_QOPT = dict(epsabs=1e-14, epsrel=1e-13, limit=200)


def _quad(f, a, b, pts=None):
    if b <= a:
        return 0.0
    pts = [x for x in (pts or []) if a < x < b]
    return integrate.quad(f, a, b, points=pts or None, **_QOPT)[0]


def _first_crossing(stress_over_x, limit_over_x):
    """First x in (0, 1] where |adhesive stress| reaches the friction limit,
    both divided by x (finite at x -> 0). 0: sliding from the leading edge;
    1: adhesion everywhere."""
    h = lambda x: stress_over_x(x) - limit_over_x(x)
    x0 = 1e-12
    if h(x0) >= 0.0:
        return 0.0
    xs = np.linspace(x0, 1.0, 2001)
    prev = x0
    for x in xs[1:]:
        if h(x) >= 0.0:
            return optimize.brentq(h, prev, x, xtol=1e-16, rtol=1e-15, maxiter=500)
        prev = x
    return 1.0


def _pressure_over_x(x, n, q):
    """c D(x) / x by its definition (no geometric-series identity)."""
    return (n + 1.0) / n * float(dgsp(x, n, q)) / x


def nf_ref_map(z, K, return_rh=False):
    """One application of the coupled-model map (Fx, Fy, Mz) -> (Fx, Fy, Mz)
    with every integral by quadrature."""
    fx, fy, mz = z
    n, c = K["n"], K["c"]
    kx, ky, gx, kf, k = K["kx"], K["ky"], K["gx"], K["kf"], K["k"]
    rd, cth, sth = K["rd"], K["cth"], K["sth"]
    q = K["q0"] + K["cqx"] * fx + K["cqm"] * mz
    xc = 0.5 + K["cxc"] * fx - K["xin"] * mz
    e = K["en"] * fy
    gy = kf * (K["teq"] - K["gn"] * mz)
    sx = lambda x: 2.0 * kx * gx * x
    sy = lambda x: 2.0 * ky * (gy * x - e * k * x * (1.0 - k * x))
    rh = _first_crossing(lambda x: math.hypot(2.0 * kx * gx, 2.0 * ky * (gy - e * k * (1.0 - k * x))),
                         lambda x: _pressure_over_x(x, n, q))
    pr = lambda x: c * float(dgsp(x, n, q))
    pts = [0.5]
    ytip = lambda x: gy * x if x <= rh else gy * rh * (1.0 - x) / (1.0 - rh)
    fx_n = _quad(sx, 0.0, rh) + rd * cth * _quad(pr, rh, 1.0, pts)
    fy_n = _quad(sy, 0.0, rh) + rd * sth * _quad(pr, rh, 1.0, pts)
    mz_n = (_quad(lambda x: (x - xc) * sy(x), 0.0, rh)
            + rd * sth * _quad(lambda x: (x - xc) * pr(x), rh, 1.0, pts)
            + _quad(lambda x: ytip(x) * sx(x), 0.0, rh)
            + rd * cth * _quad(lambda x: ytip(x) * pr(x), rh, 1.0, pts)
            + 2.0 * K["axn"] * _quad(ytip, 0.0, 1.0, [rh]))
    out = np.array([fx_n, fy_n, mz_n])
    return (out, rh, q) if return_rh else out


def nf_solve_ref(K):
    z0 = nf_ref_map(np.zeros(3), K)
    sol = optimize.root(lambda z: nf_ref_map(z, K) - z, z0, method="hybr", options=dict(xtol=1e-14))
    z = sol.x
    # polish with plain fixed-point steps (contractive near the solution)
    for _ in range(3):
        z = nf_ref_map(z, K)
    zz, rh, q = nf_ref_map(z, K, return_rh=True)
    resid = float(np.max(np.abs(zz - z)))
    return dict(fx=zz[0], fy=zz[1], mz=zz[2], rh=rh, q=q, resid=resid)


def gamma_effective_ref(p, gamma):
    """gamma_e = gamma + A gamma_e |gamma_e| by fixed-point iteration."""
    a = _camber_a(p)
    ge = gamma
    for _ in range(200):
        ge = gamma + a * ge * abs(ge)
    return ge


def neofiala_ref(p, kappa, alpha, gamma, fz, vx):
    kappa, alpha, gamma, fz, vx, warn = _clamp_inputs(p, kappa, alpha, gamma, fz, vx)
    K = kinematics(p, kappa, alpha, gamma, fz, vx)
    ge = gamma_effective_ref(p, gamma)
    teq = math.tan(alpha) + p.c_gamma * ge
    K["teq"] = abs(teq)
    st = nf_solve_ref(K)
    out = _to_iso(K, st, warn)
    out["resid"] = st["resid"]
    return out


def fiala_ref(p, alpha, fz):
    """The brush with parabolic pressure (n = 2, q = 0) and one friction
    coefficient, integrated numerically."""
    _, alpha, _, fz, _, warn = _clamp_inputs(p, alpha=alpha, fz=fz)
    ky = p.ky / (p.mu * fz)
    ta = abs(math.tan(alpha))
    rh = _first_crossing(lambda x: 2.0 * ky * ta, lambda x: _pressure_over_x(x, 2, 0.0))
    pr = lambda x: 1.5 * float(dgsp(x, 2, 0.0))
    sy = lambda x: 2.0 * ky * ta * x
    fy = _quad(sy, 0.0, rh) + _quad(pr, rh, 1.0)
    mz = _quad(lambda x: (x - 0.5) * sy(x), 0.0, rh) + _quad(lambda x: (x - 0.5) * pr(x), rh, 1.0)
    s = -1.0 if alpha < 0 else 1.0
    return dict(fx=0.0, fy=-s * fy * p.mu * fz, mz=s * mz * p.mu * fz * p.l, rh=rh, warn=warn)


def brush_ref(p, kappa, fz, vx):
    kappa, _, _, fz, vx, warn = _clamp_inputs(p, kappa=kappa, fz=fz, vx=vx)
    n = int(p.n)
    f0 = p.mu_s * fz
    gx, _, _ = _slip_split(kappa, 0.0)
    kx = p.kx / f0
    rh = _first_crossing(lambda x: 2.0 * kx * abs(gx), lambda x: _pressure_over_x(x, n, 0.0))
    mud = _brush_mud(p, kappa, vx, rh)
    sg = -1.0 if gx < 0 else (1.0 if gx > 0 else 0.0)
    pr = lambda x: (n + 1.0) / n * float(dgsp(x, n, 0.0))
    fxn = _quad(lambda x: 2.0 * kx * gx * x, 0.0, rh) + sg * mud / p.mu_s * _quad(pr, rh, 1.0, [0.5])
    return dict(fx=fxn * f0, fy=0.0, mz=0.0, rh=rh, mud=mud, warn=warn)


def sakai_ref(p, kappa, alpha, fz):
    kappa, alpha, _, fz, _, warn = _clamp_inputs(p, kappa=kappa, alpha=alpha, fz=fz)
    f0 = p.mu_s * fz
    kn = p.k / f0
    rd = p.mu_d / p.mu_s
    gx, gy = _sakai_kin(p, kappa, alpha)
    g = math.hypot(gx, gy)
    cth, sth = (gx / g, gy / g) if g > 0 else (0.0, 0.0)
    rh = _first_crossing(lambda x: 2.0 * kn * g, lambda x: _pressure_over_x(x, 2, 0.0))
    pr = lambda x: 1.5 * float(dgsp(x, 2, 0.0))
    sx = lambda x: 2.0 * kn * gx * x
    sy = lambda x: 2.0 * kn * gy * x
    fx = _quad(sx, 0.0, rh) + rd * cth * _quad(pr, rh, 1.0)
    fy = _quad(sy, 0.0, rh) + rd * sth * _quad(pr, rh, 1.0)
    y0 = fy * f0 / (p.g_y * p.l)
    ytip = lambda x: y0 + (gy * x if x <= rh else gy * rh * (1.0 - x) / (1.0 - rh))
    mz = (_quad(lambda x: (x - 0.5) * sy(x), 0.0, rh) + rd * sth * _quad(lambda x: (x - 0.5) * pr(x), rh, 1.0)
          + _quad(lambda x: ytip(x) * sx(x), 0.0, rh) + rd * cth * _quad(lambda x: ytip(x) * pr(x), rh, 1.0))
    s = -1.0 if alpha < 0 else 1.0
    return dict(fx=fx * f0, fy=-s * fy * f0, mz=s * mz * f0 * p.l, rh=rh, warn=warn)


# ---------------------------------------------------------------------------
# Structural helpers (documented in docs/brush-models.md)

def ky_from_structure(c_tr, w, l, lam, k_y):
    """Cornering stiffness with belt deflection (2.61):
    Ky = (w Ctr l^2 / 2) / (1 + w Ctr lambda^3 l^3 / (12 k_y))."""
    return (w * c_tr * l * l / 2.0) / (1.0 + w * c_tr * lam ** 3 * l ** 3 / (12.0 * k_y))


def belt_lambda(k_y, ei_z):
    """lambda = (k_y / (4 EI_z))^(1/4) of the beam on an elastic foundation (2.50)."""
    return (k_y / (4.0 * ei_z)) ** 0.25


def eps_from_belt(k_y, ei_z):
    """Tread-base deflection coefficient eps = lambda^3 / (2 k_y) (5.13) [1/(N m)]."""
    return belt_lambda(k_y, ei_z) ** 3 / (2.0 * k_y)


# ---------------------------------------------------------------------------
# Command line: verification table (closed forms vs quadrature, every n)

def verify_table(cases_per_n=12, seed=7):
    """Max |closed form - quadrature| per n, relative to mu_s Fz (forces) and
    mu_s Fz l (moment). Returns rows (n, count, max_fx, max_fy, max_mz)."""
    rng = np.random.default_rng(seed)
    rows = []
    for n in range(N_MIN, N_MAX + 1):
        worst = [0.0, 0.0, 0.0]
        for i in range(cases_per_n):
            p = random_neofiala(rng, n)
            kappa, alpha, gamma, fz, vx = random_inputs(rng, p)
            a = neofiala_cf(p, kappa, alpha, gamma, fz, vx)
            b = neofiala_ref(p, kappa, alpha, gamma, fz, vx)
            f0 = p.mu_s * min(max(fz, p.fz_min), p.fz_max)
            worst[0] = max(worst[0], abs(a["fx"] - b["fx"]) / f0)
            worst[1] = max(worst[1], abs(a["fy"] - b["fy"]) / f0)
            worst[2] = max(worst[2], abs(a["mz"] - b["mz"]) / (f0 * p.l))
        rows.append((n, cases_per_n, *worst))
    return rows


def random_neofiala(rng, n=None, couplings=True):
    """A random parameter set inside the valid range (validate() passes)."""
    for _ in range(1000):
        fz_max = rng.uniform(4000.0, 30000.0)
        mu_s = rng.uniform(0.3, 1.5)
        l = rng.uniform(0.08, 0.3)
        ky = fz_max * rng.uniform(3.0, 40.0)
        p = NeoFiala(l=l, w=rng.uniform(0.1, 0.35), ky=ky, kx=ky * math.exp(rng.uniform(-0.7, 0.7)),
                     mu_s=mu_s, mu_d0=mu_s * rng.uniform(0.5, 1.0), a_v=rng.uniform(0.0, 0.01),
                     n=int(n if n is not None else rng.integers(N_MIN, N_MAX + 1)),
                     fz_min=fz_max * 0.05, fz_max=fz_max, alpha_max=0.6, kappa_max=1.0, gamma_max=0.2)
        if couplings:
            f = mu_s * fz_max
            p.q0 = rng.uniform(-0.4, 0.4)
            p.c_q = rng.uniform(-0.18, 0.18) / f
            p.c_qm = rng.uniform(-0.18, 0.18) / (f * l)
            p.c_xc = rng.uniform(-0.09, 0.09) / f
            p.xi = rng.uniform(-0.09, 0.09) * l / f
            p.eps = rng.uniform(0.0, 1.4) / (l * ky)
            p.g_mz = ky * l / rng.uniform(0.05, 1.4)
            p.a_x = rng.uniform(-0.09, 0.09) * mu_s * p.fz_min * l
            p.c_gamma = rng.uniform(-1.0, 1.0)
            p.h = rng.uniform(0.0, 0.05)
            p.g_my = ky * rng.uniform(0.5, 5.0)
            while 4.0 * abs(_camber_a(p)) * p.gamma_max > 0.5:
                p.g_my *= 2.0
        if not validate("neofiala", p):
            return p
    raise RuntimeError("could not draw a valid parameter set")


def random_inputs(rng, p):
    mode = rng.integers(0, 4)
    kappa = 0.0 if mode == 0 else float(rng.uniform(-1.0, 1.0) * rng.choice([0.01, 0.05, 0.2, 1.0]))
    alpha = 0.0 if mode == 1 else float(rng.uniform(-1.0, 1.0) * rng.choice([0.02, 0.1, 0.3, 0.6]))
    gamma = float(rng.uniform(-p.gamma_max, p.gamma_max)) if rng.uniform() < 0.5 else 0.0
    fz = float(rng.uniform(p.fz_min, p.fz_max))
    vx = float(rng.uniform(0.0, 40.0))
    return kappa, alpha, gamma, fz, vx


def convergence_study(seed, cases=10000, iters=(4, 5, 6, 7)):
    """Truncation error of the fixed iteration over the valid range: `cases`
    random sets and inputs (random_neofiala / random_inputs, every third
    without couplings), max over Fx, Fy (/ mu_s Fz) and Mz (/ mu_s Fz l) of
    |fixed - exact| for each step count; also the number of cases above
    1e-6 and the smallest slope 1 - n1 of the moment equation at the root.
    Returns {iters: (max_err, count_above_1e-6)}, min_slope."""
    rng = np.random.default_rng(seed)
    worst = {it: [0.0, 0] for it in iters}
    min_slope = math.inf
    for i in range(cases):
        p = random_neofiala(rng, couplings=(i % 3 != 0))
        x = random_inputs(rng, p)
        kappa, alpha, gamma, fz, vx, _ = _clamp_inputs(p, *x)
        K = kinematics(p, kappa, alpha, gamma, fz, vx)
        ex = nf_solve(K, "exact")
        min_slope = min(min_slope, ex["slope"])
        for it in iters:
            fx = nf_solve(K, "fixed", it)
            e = max(abs(fx["fx"] - ex["fx"]), abs(fx["fy"] - ex["fy"]), abs(fx["mz"] - ex["mz"]))
            worst[it][0] = max(worst[it][0], e)
            worst[it][1] += int(e > 1e-6)
    return {it: tuple(v) for it, v in worst.items()}, min_slope


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(prog="grip brush-verify", description=
                                 "Closed forms of Neo-FIALA vs the quadrature reference, every supported n; "
                                 "with --write-table: regenerate lib/brush/brush_table.h instead.")
    ap.add_argument("--cases", type=int, default=12, help="random cases per n")
    ap.add_argument("--write-table", nargs="?", const=os.path.join("lib", "brush", "brush_table.h"),
                    metavar="PATH", help="write the C inverse tables (default lib/brush/brush_table.h)")
    ap.add_argument("--study", metavar="SEEDS", help="instead: convergence study of the fixed iteration, "
                    "--cases sets per seed (comma-separated seeds; docs/brush-models.md uses 21,22,23,24 "
                    "with --cases 10000)")
    ap.add_argument("--iters", default="4,5,6,7", help="step counts of the study")
    args = ap.parse_args(argv)
    if args.cases < 1:
        ap.error(f"--cases: {args.cases}: at least 1 (a verification over no case proves nothing)")

    def int_list(opt, text, lo):
        try:
            vals = tuple(int(v) for v in text.split(","))
        except ValueError:
            vals = ()
        if not vals or min(vals) < lo:
            ap.error(f"{opt}: {text!r}: comma-separated integers >= {lo}")
        return vals
    if args.study:
        its = int_list("--iters", args.iters, 1)
        seeds = int_list("--study", args.study, 0)
        print(f"{'seed':>5} {'cases':>6} " + " ".join(f"{f'{it} steps':>18}" for it in its) + "  min slope")
        for seed in seeds:
            res, slope = convergence_study(seed, args.cases, its)
            print(f"{seed:5d} {args.cases:6d} " + " ".join(f"{res[it][0]:9.2e} ({res[it][1]:5d})" for it in its)
                  + f"  {slope:.3f}", flush=True)
        print("max |fixed - exact| of Fx, Fy / (mu_s Fz), Mz / (mu_s Fz l); in brackets: cases above 1e-6")
        return 0
    if args.write_table:
        with open(args.write_table, "w") as f:
            f.write(render_table_header())
        return 0
    print(f"{'n':>3} {'cases':>6} {'max|dFx|/muFz':>14} {'max|dFy|/muFz':>14} {'max|dMz|/muFzl':>15}")
    for n, cnt, ex, ey, em in verify_table(args.cases):
        print(f"{n:3d} {cnt:6d} {ex:14.3e} {ey:14.3e} {em:15.3e}")
    return 0


# ---------------------------------------------------------------------------
# Generated C table (lib/brush/brush_table.h)

TABLE_N_MAX = 16     # rows generated; the library compiles rows 2..GRIP_BRUSH_N_MAX


def render_table_header():
    lines = [
        "/* Generated by `grip brush-verify --write-table` (brush.py).",
        " * Do not edit: regenerate. For n = 2..16: rh_j with",
        " * c D(rh_j; n, 0) / (2 rh_j) = (n + 1) j / M, j = 0..M, c = (n + 1) / n: the",
        " * nodes of the piecewise-linear map y -> rh that makes the adhesion-boundary",
        " * root nearly linear in y (docs/brush-models.md, \"Root finding\"). */",
        "#ifndef GRIP_BRUSH_TABLE_H",
        "#define GRIP_BRUSH_TABLE_H",
        "",
        f"#define GRIP_BRUSH_TABLE_M {TABLE_M}",
        "",
    ]
    for n in range(N_MIN, TABLE_N_MAX + 1):
        vals = lmax_inverse_table(n)
        lines.append(f"#define GRIP_BRUSH_TAB_{n} {{ \\")
        for i in range(0, len(vals), 4):
            chunk = ", ".join(f"RC({v:.10f})" for v in vals[i:i + 4])
            end = ", \\" if i + 4 < len(vals) else " }"
            lines.append(f"    {chunk}{end}")
        lines.append("")
    lines.append("#endif /* GRIP_BRUSH_TABLE_H */")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------
# C-struct units and fixed-point formats (include/grip/grip_brush.h): the
# fields of each struct in order, their format (QS, QL or int) and the factor
# from SI (this module, parameter files) to the struct's unit.

C_UNITS = {
    "fiala": [("ky", "QL", 1.0), ("mu", "QS", 1.0), ("l", "QS", 1.0), ("fz_min", "QL", 1.0),
              ("fz_max", "QL", 1.0), ("alpha_max", "QS", 1.0)],
    "brush": [("kx", "QL", 1.0), ("mu_s", "QS", 1.0), ("mu_d0", "QS", 1.0), ("a_v", "QS", 1.0),
              ("n", "int", 1.0), ("fz_min", "QL", 1.0), ("fz_max", "QL", 1.0), ("kappa_max", "QS", 1.0),
              ("v_max", "QS", 1.0)],
    "sakai": [("k", "QL", 1.0), ("g_y", "QL", 1.0), ("mu_s", "QS", 1.0), ("mu_d", "QS", 1.0), ("l", "QS", 1.0),
              ("fz_min", "QL", 1.0), ("fz_max", "QL", 1.0), ("alpha_max", "QS", 1.0), ("kappa_max", "QS", 1.0)],
    "neofiala": [("l", "QS", 1.0), ("w", "QS", 1.0), ("kx", "QL", 1.0), ("ky", "QL", 1.0), ("mu_s", "QS", 1.0),
                 ("mu_d0", "QS", 1.0), ("a_v", "QS", 1.0), ("n", "int", 1.0), ("q0", "QS", 1.0),
                 ("c_q", "QS", 1000.0), ("c_qm", "QS", 1000.0), ("c_xc", "QS", 1000.0), ("xi", "QS", 1000.0),
                 ("eps", "QS", 1000.0), ("g_mz", "QL", 1.0), ("a_x", "QL", 1.0), ("c_gamma", "QS", 1.0),
                 ("h", "QS", 1.0), ("g_my", "QL", 1.0), ("fz_min", "QL", 1.0), ("fz_max", "QL", 1.0),
                 ("alpha_max", "QS", 1.0), ("kappa_max", "QS", 1.0), ("gamma_max", "QS", 1.0),
                 ("v_max", "QS", 1.0)],
}
FMT_LSB = {"QS": 1.0 / 65536.0, "QL": 1.0 / 256.0}


def to_c_units(model, p, quantize=True):
    """[(field, value in the C struct's unit, format)] in struct order."""
    out = []
    for name, fmt, scale in C_UNITS[model]:
        v = getattr(p, name) * scale
        if fmt == "int":
            v = int(v)
        elif quantize:
            v = round(v / FMT_LSB[fmt]) * FMT_LSB[fmt]
        out.append((name, v, fmt))
    return out


def quantized(model, p):
    """The parameter set as both C builds store it (values on the QS/QL grid
    of their struct unit), back in SI."""
    vals = {name: (v if fmt == "int" else v / scale)
            for (name, v, fmt), (_, _, scale) in zip(to_c_units(model, p), C_UNITS[model])}
    return MODELS[model](**vals)


# ---------------------------------------------------------------------------
# Vectorized Neo-FIALA with the C library's algorithm (fixed iteration),
# float64, for the fitting tool: the vectorized kinematics, then the same
# nf_state and _fixed_root as neofiala_cf(..., solver="fixed").

def _table_rh_vec(n, y):
    tab = _TABLES.get(n)
    if tab is None:
        tab = _TABLES[n] = lmax_inverse_table(n)
    tab = np.asarray(tab)
    t = np.clip(y, 0.0, 1.0) * TABLE_M
    j = np.minimum(t.astype(int), TABLE_M - 1)
    return tab[j] + (t - j) * (tab[j + 1] - tab[j])


def neofiala_vec(p, kappa, alpha, gamma, fz, vx, iters=ROOT_ITERS):
    """Neo-FIALA on arrays (broadcast), the C library's fixed iteration in
    float64. Returns dict fx, fy, mz (ISO-W) and rh."""
    kappa, alpha, gamma, fz, vx = np.broadcast_arrays(*(np.asarray(v, dtype=float)
                                                        for v in (kappa, alpha, gamma, fz, vx)))
    alpha = np.clip(alpha, -p.alpha_max, p.alpha_max)
    kappa = np.clip(kappa, -1.0, p.kappa_max)
    gamma = np.clip(gamma, -p.gamma_max, p.gamma_max)
    fz = np.clip(fz, p.fz_min, p.fz_max)
    vx = np.minimum(np.abs(vx), p.v_max)
    n = int(p.n)
    c = (n + 1.0) / n
    f0 = p.mu_s * fz
    ta = np.tan(alpha)
    ca = _camber_a(p)
    g = np.abs(gamma)
    ge = np.sign(gamma) * 2.0 * g / (1.0 + np.sqrt(1.0 - 4.0 * ca * g))
    teq = ta + p.c_gamma * ge
    sgn = np.where(teq < 0.0, -1.0, 1.0)
    teq = np.abs(teq)
    brake = kappa < 0.0
    gx = np.where(brake, kappa, kappa / (1.0 + np.abs(kappa)))
    kf = np.where(brake, 1.0, 1.0 / (1.0 + np.abs(kappa)))
    k = np.where(brake, 1.0 + kappa, 1.0)
    gyk = kf * teq
    h = np.hypot(gx, gyk)
    hs = np.where(h > 0.0, h, 1.0)
    cth = np.where(h > 0.0, gx / hs, 0.0)
    sth = np.where(h > 0.0, gyk / hs, 0.0)
    vs = vx * np.hypot(kappa, ta)
    rd = np.maximum(p.mu_d0 - p.a_v * vs, 0.0) / p.mu_s
    kx, ky = p.kx / f0, p.ky / f0
    K = dict(n=n, c=c, inv1=1.0 / (n + 1.0), inv2=1.0 / (n + 2.0), inv3=1.0 / (n + 3.0), sx=kx * gx, kf=kf, k=k,
             teq=teq, ky=ky, rdcc=rd * c * cth, rdcs=rd * c * sth, eky=p.eps * p.l * p.ky,
             kyg=(p.ky * p.l / p.g_mz) if p.g_mz > 0 else 0.0, gn=(f0 * p.l / p.g_mz) if p.g_mz > 0 else 0.0 * f0,
             axn=p.a_x / (f0 * p.l), cqx=p.c_q * f0, cqm=p.c_qm * f0 * p.l, cxc=p.c_xc * f0, xin=p.xi * f0 / p.l,
             q0=p.q0)
    r0, s0 = nf_state(np.zeros_like(kappa), K)
    s_unc = np.hypot(K["sx"], kf * ky * teq)
    st = _fixed_root(K, r0, s0, s_unc, iters)
    slide = r0 <= 0.0
    noslip = (~slide) & (s_unc <= 0.0)
    s1 = nf_state(np.ones_like(kappa), K)[1]
    st = {k: np.where(slide, s0[k], np.where(noslip, s1[k], st[k])) for k in ("fx", "fy", "mz", "rh")}
    fxn, fyn, mzn, rh = st["fx"], st["fy"], st["mz"], st["rh"]
    return dict(fx=fxn * f0, fy=-sgn * fyn * f0, mz=sgn * mzn * f0 * p.l, rh=np.clip(rh, 0.0, 1.0))
