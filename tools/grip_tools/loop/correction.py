"""Non-parametric correction: what is fitted when no candidate of the grammar
explains a structured residual. It is not an effect and names nothing.

Per measured output o, the residual y_o - b_o (b: the base model) is fitted
on the training rows by a two-dimensional lookup map over the two channels
z1, z2 (measured or derived, loop/candidates.py) most correlated with the
base residual:

    c_o = A_o(z1, z2) + M_o(z1, z2) b_o / s_o

A and M are bilinear interpolations between NODES x NODES nodes placed at
the training quantiles of z1 and z2 (s_o: the RMS of the measured output):
an additive map and one multiplying the model's output, the form an ECU
stores as calibration maps. Outside the training range z1, z2 and b_o / s_o
are held at its edge (no extrapolation). The node values are a penalised
least-squares fit: second differences between neighbouring nodes and the
values themselves are penalised, the weight chosen from PENALTIES by a
4-fold cross-validation over contiguous blocks of the training rows; the
correction is zero when no weight beats zero there. The held-out score is
computed as the candidates' is; it is reported with the share of the
held-out residual variance it explains, and used (update.json, `grip
analyze apply`) only when it lowers the held-out error by MIN_GAIN.
"""
from dataclasses import dataclass, field

import numpy as np

from grip_tools.loop import candidates

NODES = 6
PENALTIES = (1e-3, 1e-2, 1e-1, 1.0, 10.0)
FOLDS = 4
MIN_GAIN = 0.03


def _weights(x, knots):
    """(n, len(knots)) bilinear hat weights of x on the knots (held at the ends)."""
    x = np.clip(x, knots[0], knots[-1])
    k = len(knots)
    i = np.clip(np.searchsorted(knots, x, side="right") - 1, 0, k - 2)
    span = np.maximum(knots[i + 1] - knots[i], 1e-300)
    f = np.clip((x - knots[i]) / span, 0.0, 1.0)
    W = np.zeros((len(x), k))
    W[np.arange(len(x)), i] = 1.0 - f
    W[np.arange(len(x)), i + 1] += f
    return W


def _knots(x):
    q = np.quantile(x, np.linspace(0.005, 0.995, NODES))
    # strictly increasing (a channel with few distinct values repeats quantiles)
    for j in range(1, len(q)):
        if q[j] <= q[j - 1]:
            q[j] = q[j - 1] + 1e-9 * max(1.0, abs(q[j - 1]))
    return q


def _penalty(k):
    """second differences along both axes of a k x k node grid (row-major)."""
    rows = []
    for a in range(k):
        for b in range(1, k - 1):
            r = np.zeros(k * k)
            r[a * k + b - 1], r[a * k + b], r[a * k + b + 1] = 1, -2, 1
            rows.append(r)
            r = np.zeros(k * k)
            r[(b - 1) * k + a], r[b * k + a], r[(b + 1) * k + a] = 1, -2, 1
            rows.append(r)
    D = np.array(rows)
    return D.T @ D + 1e-3 * np.eye(k * k)


@dataclass
class Correction:
    drivers: list
    knots: list                     # two increasing node positions
    coef: dict                      # output -> node values: the additive map, then the multiplicative one
    scale: dict
    brange: dict = field(default_factory=dict)      # output -> training range of b_o / s_o
    score: float = 1.0              # held-out score (1.0 = base model)
    ho_rms: dict = field(default_factory=dict)
    base_ho_rms: dict = field(default_factory=dict)
    explained: dict = field(default_factory=dict)   # output -> share of held-out residual variance
    useful: bool = False            # lowers the held-out error by at least MIN_GAIN
    pred: dict = field(repr=False, default=None)

    def features(self, ds, base, o, chans=None):
        ch = chans if chans is not None else candidates.derived(ds, base)
        Ws = []
        for name, kn in zip(self.drivers, self.knots):
            kn = np.asarray(kn, dtype=float)
            x = np.asarray(ch[name], dtype=float) if name in ch else np.full(len(ds), kn[len(kn) // 2])
            Ws.append(_weights(x, kn))
        W = (Ws[0][:, :, None] * Ws[1][:, None, :]).reshape(len(ds), -1)
        b = np.asarray(base[o]) / self.scale[o]
        if o in self.brange:
            b = np.clip(b, *self.brange[o])
        return np.hstack([W, W * b[:, None]])

    def predict(self, ds, base):
        chans = candidates.derived(ds, base)
        return {o: np.asarray(base[o]) + (self.features(ds, base, o, chans) @ np.asarray(self.coef[o]))
                * self.scale[o] if o in self.coef else np.asarray(base[o]) for o in base}

    def summary(self):
        ex = ", ".join(f"{o} {self.base_ho_rms[o]:.4g} -> {self.ho_rms[o]:.4g} "
                       f"({100 * self.explained[o]:.0f} % of its held-out residual variance)" for o in self.coef)
        what = (f"a non-parametric correction, {NODES} x {NODES} lookup maps over {self.drivers[0]} and "
                f"{self.drivers[1]} (loop/correction.py), gives held-out score {self.score:.3f}: {ex}")
        return what if self.useful else what + "; it does not lower the held-out error enough to be used"

    def as_dict(self):
        return {"kind": "non-parametric", "drivers": list(self.drivers),
                "knots": [list(map(float, k)) for k in self.knots],
                "coef": {o: [float(v) for v in c] for o, c in self.coef.items()},
                "scale": {o: float(v) for o, v in self.scale.items()},
                "base_range": {o: [float(v[0]), float(v[1])] for o, v in self.brange.items()},
                "score": float(self.score), "explained": {o: float(v) for o, v in self.explained.items()},
                "note": "no physical effect identified; c_o = A(z1,z2) + M(z1,z2) b_o/s_o, A and M bilinear "
                        "between the knots (row-major, z1 outer), inputs held at the edges; "
                        "docs/measured-data-loop.md"}

    @classmethod
    def from_dict(cls, d):
        return cls(list(d["drivers"]), [list(k) for k in d["knots"]], {o: list(c) for o, c in d["coef"].items()},
                   dict(d["scale"]), {o: tuple(v) for o, v in d.get("base_range", {}).items()},
                   float(d.get("score", 1.0)), useful=True)


def relative_dependence(ds, base, chans, train):
    """dependence of the residual relative to the model's output, r_o / b_o,
    where |b_o| is at least a third of its 99th percentile (the drivers of a
    change that scales the force)"""
    out = {}
    for o in ds.outputs:
        b = np.asarray(base[o])
        big = train & (np.abs(b) > np.quantile(np.abs(b[train]), 0.99) / 3.0)
        if big.sum() < 20:
            continue
        rel = np.zeros(len(b))
        rel[big] = (ds.ch[o] - b)[big] / b[big]
        out[o] = candidates.dependence(rel, chans, big)
    return out


def choose_drivers(dep, chans):
    """The two channels most correlated with the base residual (strongest
    |Pearson| or |rank| correlation over the outputs, of the residual or of
    the residual relative to the model's output), the second not a near
    copy of the first (|r| < 0.9 between them)."""
    best = {}
    for d in dep:
        for rows in d.values():
            for name, r, rr in rows:
                best[name] = max(best.get(name, 0.0), abs(r), abs(rr))
    order = [n for n in sorted(best, key=lambda n: -best[n]) if n in chans]
    if len(order) < 2:
        return None
    first = order[0]
    for n in order[1:]:
        if abs(np.corrcoef(chans[first], chans[n])[0, 1]) < 0.9:
            return [first, n]
    return [first, order[1]]


def fit(ds, base, chans, dep, train, test, scale):
    names = choose_drivers([dep, relative_dependence(ds, base, chans, train)], chans)
    if names is None:
        return None
    c = Correction(names, [list(_knots(chans[n][train])) for n in names], {}, dict(scale))
    for o in ds.outputs:
        b = (np.asarray(base[o]) / scale[o])[train]
        c.brange[o] = (float(np.quantile(b, 0.005)), float(np.quantile(b, 0.995)))
    idx = np.flatnonzero(train)
    fold = np.arange(len(idx)) * FOLDS // max(len(idx), 1)
    R = _penalty(NODES)
    Z = np.zeros_like(R)
    R2 = np.block([[R, Z], [Z, R]])
    num = den = 0.0
    for o in ds.outputs:
        F = c.features(ds, base, o, chans)[idx]
        y = ((ds.ch[o] - base[o]) / scale[o])[idx]
        best = (float(np.dot(y, y)), None)            # zero correction
        for pen in PENALTIES:
            err = 0.0
            for k in range(FOLDS):
                tr, va = fold != k, fold == k
                A = F[tr].T @ F[tr]
                lam = pen * np.trace(A) / A.shape[0]
                beta = np.linalg.solve(A + lam * R2, F[tr].T @ y[tr])
                e = y[va] - F[va] @ beta
                err += float(np.dot(e, e))
            if err < best[0]:
                best = (err, pen)
        if best[1] is None:
            c.coef[o] = [0.0] * F.shape[1]
            continue
        A = F.T @ F
        lam = best[1] * np.trace(A) / A.shape[0]
        c.coef[o] = list(np.linalg.solve(A + lam * R2, F.T @ y))
    c.pred = c.predict(ds, base)
    for o in ds.outputs:
        r0 = (ds.ch[o] - base[o])[test]
        r1 = (ds.ch[o] - c.pred[o])[test]
        c.base_ho_rms[o] = float(np.sqrt(np.mean(r0 ** 2)))
        c.ho_rms[o] = float(np.sqrt(np.mean(r1 ** 2)))
        c.explained[o] = 1.0 - float(np.mean(r1 ** 2)) / max(float(np.mean(r0 ** 2)), 1e-300)
        num += (c.ho_rms[o] / scale[o]) ** 2
        den += (c.base_ho_rms[o] / scale[o]) ** 2
    c.score = float(np.sqrt(num / max(den, 1e-300)))
    c.useful = c.score <= 1.0 - MIN_GAIN
    return c
