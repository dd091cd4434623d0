"""Attribution: rank candidate effects by the residual they explain on
held-out data.

Split: the record is cut into n_blocks contiguous time blocks; even blocks
train, odd blocks are held out (so both halves cover the whole run, and no
held-out sample has a training neighbour closer than a block edge). State
effects (thermal, relaxation) run over the whole record with the trained
parameters; only the loss is masked.

Score: held-out residual energy relative to the baseline's, with each output
normalised by the RMS of its measured signal (so an output the effect does
not touch does not dilute the one it does):
    score = sqrt(sum_o (rms_o / s_o)^2 / sum_o (rms_base_o / s_o)^2)
(1.0 = baseline, 0.5 = held-out RMS halved). An effect
with k parameters is accepted only if it improves the score by at least
min_gain * k (default 5 % per parameter); the ranking key is the
penalised score score * (1 + min_gain * k).
"""
from dataclasses import dataclass, field

import numpy as np

from grip_tools.loop import candidates, sanity
from grip_tools.loop.effects import TireModel, all_effects


def block_masks(n, n_blocks=8):
    idx = np.arange(n) * n_blocks // n
    train = idx % 2 == 0
    return train, ~train


def forward_masks(n, share=0.3):
    """Fit on the first (1 - share) of the record, judge on the last share:
    the test a model faces when it is used after it was fitted."""
    train = np.arange(n) < int(round(n * (1.0 - share)))
    return train, ~train


def holdout_masks(n, spec):
    """'blocks:N' (interleaved contiguous blocks, even ones fit) or
    'forward:F' (the last share F held out)."""
    kind, _, arg = spec.partition(":")
    if kind == "blocks":
        k = int(arg or 8)
        if k < 2:
            raise ValueError(f"holdout {spec}: at least 2 blocks")
        return block_masks(n, k)
    if kind == "forward":
        f = float(arg or 0.3)
        if not 0.05 <= f <= 0.8:
            raise ValueError(f"holdout {spec}: the held-out share must be in [0.05, 0.8]")
        return forward_masks(n, f)
    raise ValueError(f"holdout '{spec}': blocks:N or forward:F")


def rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else 0.0


@dataclass
class Candidate:
    name: str
    params: dict
    k: int
    score: float
    penalised: float
    accepted: bool
    ho_rms: dict
    ho_max: dict
    note: str = ""
    onboard: str = ""


@dataclass
class Result:
    base_ho_rms: dict
    base_ho_max: dict
    ranked: list
    chosen: object
    structure: dict
    dependence: dict
    train: np.ndarray = field(repr=False, default=None)
    test: np.ndarray = field(repr=False, default=None)
    base_pred: dict = field(repr=False, default=None)
    chosen_pred: dict = field(repr=False, default=None)
    skipped: list = field(default_factory=list)
    sanity: object = None              # sanity.Sanity of the base model
    holdout: str = "blocks:8"          # the split the ranking used
    cross: dict = field(default_factory=dict)   # hold-out spec -> the chosen effect's score there


def analyse(model, ds, effects=None, n_blocks=8, min_gain=0.05, holdout=None, also=(), progress=None):
    """Rank the effects on held-out data. holdout: 'blocks:N' (default
    blocks:n_blocks) or 'forward:F'; also: further hold-out specs on which
    the chosen effect is re-fitted and scored, for the report (cross).
    progress(i, n, name): called before each candidate."""
    effects = effects or all_effects()
    holdout = holdout or f"blocks:{n_blocks}"
    train, test = holdout_masks(len(ds), holdout)
    base = model.predict(ds.ch)
    base_check = sanity.check(model, ds, base)
    base_res = {o: ds.ch[o] - base[o] for o in ds.outputs}
    base_ho_rms = {o: rms(base_res[o][test]) for o in ds.outputs}
    base_ho_max = {o: float(np.max(np.abs(base_res[o][test]))) for o in ds.outputs}
    scale = {o: max(rms(ds.ch[o][train]), 1e-9) for o in ds.outputs}
    den = sum((base_ho_rms[o] / scale[o]) ** 2 for o in ds.outputs)
    cands = candidates.derived(ds, base)
    dep = {o: candidates.dependence(base_res[o], cands) for o in ds.outputs}
    structure = {o: candidates.autocorr(base_res[o]) for o in ds.outputs}
    ranked, skipped, preds = [], [], {}
    by_name = {}
    for i, e in enumerate(effects):
        if progress is not None:
            progress(i, len(effects), e.name)
        kind = getattr(model, "kind", "tire" if isinstance(model, TireModel) else "vehicle")
        if e.level == "tire" and kind != "tire":
            continue                   # a tyre term; its vehicle-level form (if any) is listed
        if e.level == "vehicle" and kind != "vehicle":
            continue
        if e.level == "vehicle" and e.name not in getattr(model, "supports", ()):
            skipped.append((e.name, "not a term of this vehicle model"))
            continue
        ok, why = e.applicable(ds)
        if not ok:
            skipped.append((e.name, why))
            continue
        x = e.fit(model, ds, train, scale)
        pr = e.predict(model, ds, x)
        ho = {o: rms((ds.ch[o] - pr[o])[test]) for o in ds.outputs}
        hm = {o: float(np.max(np.abs((ds.ch[o] - pr[o])[test]))) for o in ds.outputs}
        score = float(np.sqrt(sum((ho[o] / scale[o]) ** 2 for o in ds.outputs) / max(den, 1e-30)))
        k = e.n_params(ds)
        names = list(e.pnames) or [f"{e.name}_{o}" for o in ds.outputs]
        c = Candidate(e.name, dict(zip(names, map(float, x))), k, score, score * (1 + min_gain * k),
                      (1.0 - score) >= min_gain * k, ho, hm, onboard=e.onboard)
        ranked.append(c)
        preds[e.name] = pr
        by_name[e.name] = e
    ranked.sort(key=lambda c: c.penalised)
    chosen = next((c for c in ranked if c.accepted), None)
    if chosen is not None and by_name[chosen.name].level != "any":
        # a physical effect that explains an output better than a whole-data
        # hypothesis (sign, side, unit, offset) is the finding, not that error
        # (a sensor effect - bias, scale, delay - is that error in other words)
        pr = preds[chosen.name]
        for f in base_check.findings:
            if f.cause and rms(ds.ch[f.output] - pr[f.output]) <= f.rms_cause:
                f.cause, f.detail = "", f"{chosen.name} explains it better than any sign/side/unit/offset error"
    cross = {holdout: chosen.score if chosen else 1.0}
    for spec in also:
        if spec == holdout:
            continue
        tr2, te2 = holdout_masks(len(ds), spec)
        if chosen is None:
            cross[spec] = 1.0
            continue
        e = by_name[chosen.name]
        pr = e.predict(model, ds, e.fit(model, ds, tr2, scale))
        num = sum((rms((ds.ch[o] - pr[o])[te2]) / scale[o]) ** 2 for o in ds.outputs)
        den2 = sum((rms(base_res[o][te2]) / scale[o]) ** 2 for o in ds.outputs)
        cross[spec] = float(np.sqrt(num / max(den2, 1e-30)))
    return Result(base_ho_rms, base_ho_max, ranked, chosen, structure, dep, train, test, base,
                  preds.get(chosen.name) if chosen else None, skipped, base_check, holdout, cross)


def verdict(res):
    """One paragraph: first whether the base model fits at all (and the likely
    cause when it does not), then what was found, or that nothing explains
    the structure."""
    pre = res.sanity.summary() if res.sanity is not None else ""
    txt = _attribution_verdict(res)
    return f"{pre}. Attribution on top of it: {txt}" if pre else txt


def _attribution_verdict(res):
    struct = {o: a for o, a in res.structure.items() if a > 0.3}
    if res.chosen is not None:
        c = res.chosen
        gain = 1.0 - c.score
        txt = (f"effect: {c.name} ({', '.join(f'{k}={v:.4g}' for k, v in c.params.items())}); "
               f"held-out error {100 * gain:.1f} % lower (score {c.score:.3f}, {c.k} parameter(s), "
               f"hold-out {res.holdout})")
        other = {k: v for k, v in res.cross.items() if k != res.holdout}
        if other:
            txt += "; " + ", ".join(f"{100 * (1.0 - v):.1f} % lower on hold-out {k}" for k, v in other.items())
        ties = [d.name for d in res.ranked if d is not c and d.accepted and d.penalised - c.penalised < 0.01]
        if ties:
            txt += f"; not distinguishable from {', '.join(ties)} on this data (penalised scores within 0.01)"
        if c.score > 0.7 and struct:
            txt += ("; most of the structured residual remains unexplained (it correlates with "
                    + "; ".join(f"{o}: " + ", ".join(f"{n} r={r:+.2f}" for n, r, _ in res.dependence[o][:3])
                                for o in struct) + ")")
        return txt
    if struct:
        names = {o: ", ".join(f"{n} (r={r:+.2f})" for n, r, _ in res.dependence[o][:4]) for o in struct}
        return ("no candidate effect explains the structured residual (lag-1 autocorrelation "
                + ", ".join(f"{o} {a:.2f}" for o, a in struct.items())
                + "); it correlates most with: " + "; ".join(f"{o}: {v}" for o, v in names.items()))
    return "no effect found: the residual is unstructured (noise-like) and no candidate reduces the held-out error enough"
