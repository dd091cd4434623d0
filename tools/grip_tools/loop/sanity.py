"""Base-model sanity, before any attribution: does the base model explain the
measured signal at all, and if not, does the misfit look like a sign, a
tyre side, a unit or a scale error rather than a physical effect?

Each measured output o with model prediction b is scored by its explained
share R2 = 1 - var(o - b) / var(o). The alternatives tried, each a whole
hypothesis about the data rather than a fitted effect:

  sign        o ~ -b            (SAE vs ISO-W axes, a load cell mounted reversed)
  tyre side   o ~ b mirrored    (the tyre was on the other side: --side)
  scale       o ~ s b, s fitted (units: 1000 kN/N, 9.81 kgf/N, 4.45 lbf/N;
                                  or a force-sensor gain)
  offset      o ~ b + c         (a zeroed load cell that was not zeroed)

A hypothesis is named when it explains at least GOOD of the signal and
leaves at most RESIDUAL_SHARE of the base model's residual variance; the base
model "does not fit" when its R2 is below POOR or such a cause is named. Only the tyre level has a side
(a TireModel); the rest apply to any model.
"""
from dataclasses import dataclass, field

import numpy as np

POOR = 0.5     # explained share below which the base model does not fit
GOOD = 0.9     # explained share a named cause must reach
RESIDUAL_SHARE = 0.25   # ... leaving at most this share of the base model's residual variance
# measured / model ratios that are a unit, not physics
UNIT_FACTORS = {1e-3: "kN (or kN m) labelled N", 1e3: "N labelled kN (or mN labelled N)",
                1.0 / 9.80665: "kgf labelled N", 1.0 / 4.4482216: "lbf labelled N",
                9.80665: "N labelled kgf", 4.4482216: "N labelled lbf"}


@dataclass
class Finding:
    output: str
    r2: float                   # explained share of the base model
    cause: str = ""             # the named hypothesis, '' if none
    r2_cause: float = float("nan")
    detail: str = ""
    rms: float = 0.0            # residual RMS of the base model
    rms_cause: float = float("nan")


@dataclass
class Sanity:
    findings: list = field(default_factory=list)

    @property
    def fits(self):
        return all(f.r2 >= POOR and not f.cause for f in self.findings)

    def summary(self):
        bad = [f for f in self.findings if f.cause or f.r2 < POOR]
        if not bad:
            return ""
        parts = []
        for f in bad:
            s = f"{f.output}: residual RMS {f.rms:.4g} (R2 {f.r2:.3f})"
            if f.cause:
                s += f"; it looks like {f.cause}: {f.detail} (residual RMS {f.rms_cause:.4g}, R2 {f.r2_cause:.4f})"
            parts.append(s)
        return "the base model does not fit the data - " + "; ".join(parts)


def explained(meas, pred):
    v = float(np.var(meas))
    if v <= 0.0:
        return 1.0
    return 1.0 - float(np.var(meas - pred)) / v


def _unit_name(s):
    for f, what in UNIT_FACTORS.items():
        for sign in (1.0, -1.0):
            if abs(s / (sign * f) - 1.0) < 0.03:
                return what + (", sign flipped" if sign < 0 else "")
    return ""


def check(model, ds, base):
    """A Sanity of the base model's prediction `base` against ds."""
    out = Sanity()
    mirrored = None
    for o in ds.outputs:
        m = np.asarray(ds.ch[o], dtype=float)
        b = np.asarray(base[o], dtype=float)
        r2 = explained(m, b)
        f = Finding(o, r2, rms=float(np.sqrt(np.mean((m - b) ** 2))))
        out.findings.append(f)
        tries = []
        tries.append((-b, "a sign error", "measured = -model: SAE vs ISO-W axes or a reversed sensor"))
        bb = float(np.dot(b - b.mean(), b - b.mean()))
        s = float(np.dot(b - b.mean(), m - m.mean())) / bb if bb > 0.0 else 0.0
        if s != 0.0 and abs(np.log(abs(s))) > np.log(1.3):
            unit = _unit_name(s)
            tries.append((s * b + (m.mean() - s * b.mean()),
                          f"a unit error: {unit}" if unit else "a scale error",
                          f"measured = {s:.4g} x model"))
        c = float(np.mean(m - b))
        if abs(c) > 0.5 * float(np.std(m)):
            tries.append((b + c, "an offset", f"measured = model {c:+.4g}"))
        if o in ("fy", "mz") and hasattr(model, "params") and "tyreside" in getattr(model, "params", {}):
            if mirrored is None:
                mirrored = _mirrored_prediction(model, ds)
            if mirrored is not None:
                tries.append((mirrored[o], "a tyre-side error",
                              "the data fit the tyre mounted on the other side (grip analyze --side)"))
        scored = [(explained(m, alt), alt, cause, detail) for alt, cause, detail in tries]
        r2_alt, alt, cause, detail = max(scored, key=lambda t: t[0])
        # named when it explains the data well and leaves at most a quarter of
        # the base model's residual variance (half its RMS): a whole-data
        # hypothesis that good is not a small physical effect
        if r2_alt >= GOOD and (1.0 - r2_alt) <= RESIDUAL_SHARE * (1.0 - r2):
            f.r2_cause, f.cause, f.detail = r2_alt, cause, detail
            f.rms_cause = float(np.sqrt(np.mean((m - alt) ** 2)))
    return out


def _mirrored_prediction(model, ds):
    """The base model with the mounting side swapped (options bit 3)."""
    try:
        other = type(model)(dict(model.params, options=int(model.params.get("options", 0)) ^ (1 << 3)),
                            model.name, getattr(model, "tir_path", None))
        return other.predict(ds.ch)
    except Exception:  # noqa: BLE001 - a model that cannot be mirrored has no side hypothesis
        return None
