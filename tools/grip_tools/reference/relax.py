"""Float64 reference of the first-order relaxation-length transient of slip
(include/grip/grip_relax.h, lib/relax):

    sigma dx'/dt + |vx| x' = |vx| x,   x in {kappa, alpha}

Time step (the C library's scheme, reproduced exactly): inputs held over dt,
exact solution of the linear ODE for that,
    x' += (1 - exp(-|vx| dt / sigma)) (x - x'),
with |vx| clamped to [v_min, v_max] and kappa, alpha to +-kappa_max,
+-alpha_max. `lag_series` is the same filter over a whole time series
(vectorised over parameters where possible), used by the residual tool's
relaxation effect.
"""
from dataclasses import dataclass, fields

import numpy as np

A_MAX = 16.0   # |vx| dt / sigma beyond this is a full step (exp(-16) < 2^-16)


@dataclass
class RelaxParams:
    sigma_kappa: float = 0.3   # m
    sigma_alpha: float = 0.6   # m
    v_min: float = 0.5         # m/s
    v_max: float = 100.0       # m/s
    kappa_max: float = 1.0
    alpha_max: float = 0.5     # rad

    def as_dict(self):
        return {f.name: getattr(self, f.name) for f in fields(self)}


PARAM_ORDER = [f.name for f in fields(RelaxParams)]


def phi(dist, sigma):
    """1 - exp(-dist / sigma), = 1 beyond A_MAX (as the C code)."""
    a = dist / sigma
    return 1.0 if a >= A_MAX else -np.expm1(-a)


def step(prm, state, kappa, alpha, vx, dt):
    """One step; state = (kappa_t, alpha_t). Returns the new state."""
    k = min(max(kappa, -prm.kappa_max), prm.kappa_max)
    a = min(max(alpha, -prm.alpha_max), prm.alpha_max)
    v = min(max(abs(vx), prm.v_min), prm.v_max)
    dist = v * dt
    kt, at = state
    kt = kt + phi(dist, prm.sigma_kappa) * (k - kt)
    at = at + phi(dist, prm.sigma_alpha) * (a - at)
    return kt, at


def simulate(prm, kappa0, alpha0, kappa, alpha, vx, dt):
    """Run `step` over sequences; returns arrays (kappa_t, alpha_t) after each step."""
    n = max(np.size(x) for x in (kappa, alpha, vx, dt))
    seq = [np.broadcast_to(np.asarray(x, dtype=float), (n,)) for x in (kappa, alpha, vx, dt)]
    st = (min(max(kappa0, -prm.kappa_max), prm.kappa_max),
          min(max(alpha0, -prm.alpha_max), prm.alpha_max))
    out_k = np.zeros(n)
    out_a = np.zeros(n)
    for i in range(n):
        st = step(prm, st, float(seq[0][i]), float(seq[1][i]), float(seq[2][i]), float(seq[3][i]))
        out_k[i], out_a[i] = st
    return out_k, out_a


def lag_series(x, vx, t, sigma, v_min=0.5):
    """First-order relaxation of series x(t) with length sigma [m]: the value
    at sample i is the state after the step from t[i-1] to t[i] with input
    x[i-1] held (the state starts at x[0]). sigma <= 0 returns x unchanged."""
    x = np.asarray(x, dtype=float)
    if sigma <= 0.0:
        return x.copy()
    v = np.maximum(np.abs(np.asarray(vx, dtype=float)), v_min)
    dt = np.diff(np.asarray(t, dtype=float), prepend=t[0])
    g = -np.expm1(-v * dt / sigma)
    y = np.empty_like(x)
    s = x[0]
    for i in range(len(x)):
        s = s + g[i] * ((x[i - 1] if i > 0 else x[0]) - s)
        y[i] = s
    return y
