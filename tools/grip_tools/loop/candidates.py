"""Derived candidate channels for the residual-dependence analysis."""
import numpy as np


def lowpass(x, t, tau):
    """First-order lag of x with time constant tau [s] (exact for held inputs)."""
    x = np.asarray(x, dtype=float)
    dt = np.diff(t, prepend=t[0])
    g = (-np.expm1(-dt / tau)).tolist()
    xs = x.tolist()
    y = [0.0] * len(xs)
    s = xs[0]
    prev = xs[0]
    for i in range(len(xs)):
        s += g[i] * (prev - s)
        y[i] = s
        prev = xs[i]
    return np.array(y)


def slip_speed(ch):
    vx = np.abs(ch["vx"])
    return vx * np.hypot(ch.get("kappa", 0.0 * vx), np.tan(ch["alpha"]))


def derived(ds, model_out=None):
    """dict of candidate channels (name -> array). model_out: the model's
    outputs (for friction power)."""
    ch, t = ds.ch, ds.t
    out = {}
    for n in ("alpha", "kappa", "fz", "gamma", "p", "vx", "t_road", "delta", "r"):
        if n in ch and np.std(ch[n]) > 0:
            out[n] = ch[n]
    out["|alpha|"] = np.abs(ch["alpha"]) if "alpha" in ch else None
    if "alpha" in ch and "vx" in ch:
        vs = slip_speed(ch)
        out["slip_speed"] = vs
        f = None
        if model_out is not None:
            f = np.hypot(model_out.get("fx", 0.0 * vs), model_out.get("fy", 0.0 * vs))
        else:
            f = np.hypot(ch.get("fx", 0.0 * vs), ch.get("fy", 0.0 * vs))
        out["friction_power"] = f * vs
        out["friction_energy_10s"] = lowpass(f * vs, t, 10.0) * 10.0
        out["friction_energy_60s"] = lowpass(f * vs, t, 60.0) * 60.0
        out["slip_rate"] = np.gradient(ch["alpha"], t)
        out["speed^2"] = ch["vx"] ** 2
    out["time"] = t - t[0]
    if "alpha" in ch:
        for lag in (0.05, 0.2):
            out[f"alpha_lag{lag}s"] = np.interp(t - lag, t, ch["alpha"])
    return {k: v for k, v in out.items() if v is not None and np.all(np.isfinite(v)) and np.std(v) > 0}


def dependence(res, cands, mask=None):
    """|Pearson r| and |Spearman-like rank r| of the residual with each
    candidate, sorted strongest first: list of (name, r, rank_r)."""
    m = np.ones(len(res), bool) if mask is None else mask
    rows = []
    for k, v in cands.items():
        a, b = res[m], v[m]
        if np.std(a) == 0 or np.std(b) == 0:
            continue
        r = float(np.corrcoef(a, b)[0, 1])
        ra = np.argsort(np.argsort(a))
        rb = np.argsort(np.argsort(b))
        rr = float(np.corrcoef(ra, rb)[0, 1])
        rows.append((k, r, rr))
    rows.sort(key=lambda x: -max(abs(x[1]), abs(x[2])))
    return rows


def autocorr(res, lag=1):
    r = res - res.mean()
    d = float(np.dot(r, r))
    return float(np.dot(r[:-lag], r[lag:]) / d) if d > 0 else 0.0
