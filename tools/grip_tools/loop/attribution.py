"""Attribution: rank candidate effects by the residual they explain on
held-out data.

Split (holdout_masks): 'blocks:N' cuts the record into N contiguous time
blocks, even blocks train, odd blocks are held out; 'forward:F' fits on the
first 1 - F of the record and judges on the last F. State effects run over
the whole record with the trained parameters; only the loss is masked.

Score: held-out residual energy relative to the baseline's, with each output
normalised by the RMS of its measured signal (so an output the effect does
not touch does not dilute the one it does):
    score = sqrt(S / S_0),  S = sum_o RSS_o / s_o^2 on the held-out rows
(1.0 = baseline, 0.5 = held-out RMS halved).

Tyre models (grammar search, docs/measured-data-loop.md "Method"): the
candidates are the grammar's (target x driver) pairs (loop/grammar.py),
screened linearly and the best REFINE refined with the full model, plus the
named forms of effects.tyre_specials(). Criterion: a BIC on the held-out
residual,
    IC = N_eff ln(S / S_0) + k ln N_eff,
N_eff = sum_o n_test (1 - rho_o) / (1 + rho_o), rho_o the lag-1
autocorrelation of the best candidate's held-out residual (the number of
independent held-out samples an AR(1) residual carries). Accepted: IC < 0
and score <= 1 - MIN_GAIN. Not distinguishable from the best (lowest IC)
accepted candidate: within TIE_IC of its IC. Chosen: among those, the one
with the fewest parameters (then a constant change before a modulation,
then the lowest IC); a named form whose family the chosen pair belongs to replaces
it when it achieves at least 1 - SPECIAL_TOL of the chosen pair's error
reduction 1 - score (it is the form that runs onboard).
Second split (_confirm): the best CONFIRM accepted candidates are re-fitted
on the other of forward:0.3 / blocks:8 and scored there (IC2, its own
N_eff); the choice above is made again among those with IC2 < 0 on the sum
IC + IC2 (on none: the first split's choice). One split of a short record
holds out a few blocks of the test plan; a driver that wins there by a
fraction of a per cent (a state of slip for one of friction power, a
quadratic in camber for one in load) has to win on the other split's
held-out rows as well.
When nothing is accepted and the residual is structured, a non-parametric
correction (loop/correction.py) is fitted and reported as such.

Vehicle models: every applicable effect of effects.all_effects() is fitted;
an effect with k parameters is accepted only if it improves the score by at
least min_gain * k (default 5 % per parameter); the ranking key is the
penalised score score * (1 + min_gain * k).
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np

from grip_tools.loop import blas, candidates, correction, grammar, sanity
from grip_tools.loop.effects import TireModel, all_effects, tyre_specials

MIN_GAIN = 0.03      # a named tyre effect lowers the normalised held-out error by at least 3 %
TIE_IC = 6.0         # candidates closer than this in IC are not distinguishable on the data
SPECIAL_TOL = 0.02   # a named form with 98 % of the chosen pair's error reduction replaces it
STRUCTURE = 0.3      # lag-1 autocorrelation above which a residual counts as structured
CONFIRM = 6          # accepted candidates re-fitted and scored on the second split
PARALLEL_ROWS = 20000  # records at least this long are refined in parallel (analyse(jobs=...))


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
    family: tuple = ()          # grammar (target, driver), or the named form's first family
    families: tuple = ()        # a named form: every grammar pair it competes with
    description: str = ""
    kind: str = "named"         # "grammar" (a generated pair) or "named" (a named form)
    ic: float = float("nan")    # held-out BIC relative to the base model (tyre models)
    screen_score: float = float("nan")   # the linear screening's held-out score (grammar pairs)
    score2: float = float("nan")   # re-fitted and scored on the second split (_confirm)
    ic2: float = float("nan")      # its IC there


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
    ties: list = field(default_factory=list)    # accepted candidates not distinguishable from the chosen
    effect: object = field(repr=False, default=None)   # the chosen effect (Effect or GrammarEffect)
    correction: object = None          # correction.Correction when nothing physical was identified
    search: dict = field(default_factory=dict)  # search statistics (pairs, refined, CPU seconds)
    scale: dict = field(default_factory=dict)   # per-output normalisation (RMS of the measured signal)


def analyse(model, ds, effects=None, n_blocks=8, min_gain=0.05, holdout=None, also=(), progress=None,
            n_refine=grammar.REFINE, use_grammar=True, jobs=1):
    """Rank the candidate effects on held-out data. holdout: 'blocks:N'
    (default blocks:n_blocks) or 'forward:F'; also: further hold-out specs
    on which the chosen effect is re-fitted and scored, for the report
    (cross). progress(i, n, name): called before each stage / candidate.
    A tyre model (TireModel) is searched with the grammar (effects: the
    named forms beside it, default effects.tyre_specials()); any other model
    with `effects` (default effects.all_effects()). use_grammar=False: a tyre
    model with the named effects only (every tyre and sensor effect of
    effects.all_effects(), none gated), selected by the same criterion.
    jobs > 1: the grammar's refinement runs in that many processes on
    records of PARALLEL_ROWS rows or more."""
    with blas.single_thread():          # processes, not BLAS threads (loop/blas.py)
        return _analyse(model, ds, effects, n_blocks, min_gain, holdout, also, progress, n_refine,
                        use_grammar, jobs)


def _analyse(model, ds, effects, n_blocks, min_gain, holdout, also, progress, n_refine, use_grammar, jobs):
    t_start, w_start = time.process_time(), time.perf_counter()
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
    kind = getattr(model, "kind", "tire" if isinstance(model, TireModel) else "vehicle")

    def evaluate(name, x, pr, k, onboard, e, family=(), description="", pnames=None):
        ho = {o: rms((ds.ch[o] - pr[o])[test]) for o in ds.outputs}
        hm = {o: float(np.max(np.abs((ds.ch[o] - pr[o])[test]))) for o in ds.outputs}
        score = float(np.sqrt(sum((ho[o] / scale[o]) ** 2 for o in ds.outputs) / max(den, 1e-30)))
        names = list(pnames or getattr(e, "pnames", ()) or [f"{name}_{o}" for o in ds.outputs])
        return Candidate(name, dict(zip(names, map(float, x))), k, score, score * (1 + min_gain * k),
                         (1.0 - score) >= min_gain * k, ho, hm, onboard=onboard,
                         family=tuple(family), description=description)

    ranked, skipped, preds, by_name = [], [], {}, {}
    search = {}
    if kind == "tire":
        ranked, skipped, preds, by_name, search = _tyre_search(model, ds, base, train, test, scale, effects,
                                                                progress, n_refine, evaluate, use_grammar, jobs)
        chosen, ties, n_eff = _select(ranked, ds, preds, test, scale, den)
        search["n_eff"] = n_eff
        if CONFIRM and chosen is not None:
            if progress is not None:
                progress(0, 1, "second split")
            chosen, ties, second = _confirm(model, ds, base, ranked, by_name, holdout, scale, base_res)
            search["second"] = second
    else:
        effects = effects or all_effects()
        for i, e in enumerate(effects):
            if progress is not None:
                progress(i, len(effects), e.name)
            if e.level == "tire":
                continue                   # a tyre term; its vehicle-level form (if any) is listed
            if e.level == "vehicle" and e.name not in getattr(model, "supports", ()):
                skipped.append((e.name, "not a term of this vehicle model"))
                continue
            ok, why = e.applicable(ds)
            if not ok:
                skipped.append((e.name, why))
                continue
            x = e.fit(model, ds, train, scale)
            pr = e.predict(model, ds, x)
            c = evaluate(e.name, x, pr, e.n_params(ds), e.onboard, e)
            ranked.append(c)
            preds[e.name] = pr
            by_name[e.name] = e
        ranked.sort(key=lambda c: c.penalised)
        chosen = next((c for c in ranked if c.accepted), None)
        ties = [d.name for d in ranked if chosen is not None and d is not chosen and d.accepted
                and d.penalised - chosen.penalised < 0.01]
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
        if chosen is not None and search.get("second", {}).get("split") == spec \
                and chosen.name in search["second"]["score"]:
            cross[spec] = search["second"]["score"][chosen.name]     # re-fitted there already
            continue
        tr2, te2 = holdout_masks(len(ds), spec)
        if chosen is None:
            cross[spec] = 1.0
            continue
        e = by_name[chosen.name]
        if isinstance(e, grammar.GrammarEffect):
            e = grammar.GrammarEffect(e.spec)          # its own u_ref: the chosen one keeps the first split's
        pr = e.predict(model, ds, e.fit(model, ds, tr2, scale))
        num = sum((rms((ds.ch[o] - pr[o])[te2]) / scale[o]) ** 2 for o in ds.outputs)
        den2 = sum((rms(base_res[o][te2]) / scale[o]) ** 2 for o in ds.outputs)
        cross[spec] = float(np.sqrt(num / max(den2, 1e-30)))
    corr = None
    if chosen is None and kind == "tire" and max(structure.values()) > STRUCTURE:
        if progress is not None:
            progress(0, 1, "non-parametric correction")
        corr = correction.fit(ds, base, cands, dep, train, test, scale)
    search["cpu_s"] = time.process_time() - t_start        # this process (not the refinement workers)
    search["wall_s"] = time.perf_counter() - w_start
    return Result(base_ho_rms, base_ho_max, ranked, chosen, structure, dep, train, test, base,
                  preds.get(chosen.name) if chosen else None, skipped, base_check, holdout, cross,
                  ties=ties, effect=by_name.get(chosen.name) if chosen else None, correction=corr,
                  search=search, scale=scale)


_POOL_ARGS = None


def _refine_job(i):
    ctx, top, train, scale = _POOL_ARGS
    return grammar.refine(ctx, top[i], train, scale)


def _refine_all(ctx, top, train, scale, jobs, prog):
    """grammar.refine of every screened pair in top; in `jobs` forked
    processes when the record is long."""
    global _POOL_ARGS
    if jobs > 1 and ctx.n >= PARALLEL_ROWS and len(top) > 1:
        import multiprocessing as mp
        prog(f"fit {len(top)} pairs in {jobs} processes")
        _POOL_ARGS = (ctx, top, train, scale)
        try:
            with mp.get_context("fork").Pool(jobs) as pool:
                return pool.map(_refine_job, range(len(top)))
        finally:
            _POOL_ARGS = None
    out = []
    for sc in top:
        prog(f"fit {sc.spec.name}")
        out.append(grammar.refine(ctx, sc, train, scale))
    return out


def _tyre_search(model, ds, base, train, test, scale, effects, progress, n_refine, evaluate, use_grammar=True,
                 jobs=1):
    """The grammar's candidates (screened, the best refined) and the named
    tyre forms. Returns ranked (unsorted), skipped, preds, by_name, info."""
    t0 = time.perf_counter()
    ctx = grammar.Context(model, ds, base, train)
    skipped = []
    if use_grammar:
        specs = grammar.pairs(ctx, skipped)
        specials = list(effects) if effects is not None else tyre_specials()
    else:
        specs, n_refine = [], 0
        specials = list(effects) if effects is not None else [e for e in all_effects() if e.level != "vehicle"]
    n_targets = len({s.target.name for s in specs})
    n_steps = n_targets + n_refine + len(specials)
    step = [0]

    def prog(name):
        if progress is not None:
            progress(min(step[0], n_steps - 1), n_steps, name)
        step[0] += 1
    screened, rr_te = grammar.screen(ctx, specs, train, test, scale, progress=lambda t: prog(f"screen {t}"))
    n_te = int(test.sum()) * len(ds.outputs)
    lnN = math.log(max(n_te, 2))
    screened.sort(key=lambda sc: n_te * math.log(max(sc.s_test, 1e-300) / max(rr_te, 1e-300)) + sc.k * lnN)
    t1 = time.perf_counter()
    ranked, preds, by_name = [], {}, {}
    top, n_t, n_d = [], {}, {}
    for sc in screened:                  # the best pairs, at most REFINE_PER per target and per driver
        if len(top) >= n_refine:
            break
        t, d = sc.spec.family
        if n_t.get(t, 0) >= grammar.REFINE_PER or n_d.get(d, 0) >= grammar.REFINE_PER:
            continue
        top.append(sc)
        n_t[t], n_d[d] = n_t.get(t, 0) + 1, n_d.get(d, 0) + 1
    # every refined target's constant change is refined too: a modulation
    # must beat the constant change of the same target
    fams = {sc.spec.family for sc in top}
    for sc in screened:
        t, d = sc.spec.family
        if d == "const" and t in n_t and (t, d) not in fams:
            top.append(sc)
    for sc, x in zip(top, _refine_all(ctx, top, train, scale, jobs, prog)):
        pr = sc.spec.predict(ctx, x)
        e = grammar.GrammarEffect(sc.spec, ctx.u_ref)
        c = evaluate(sc.spec.name, x, pr, sc.k, e.onboard, e, sc.spec.family, sc.spec.description(),
                     sc.spec.pnames(ctx))
        c.kind = "grammar"
        c.screen_score = float(math.sqrt(max(sc.s_test, 0.0) / max(rr_te, 1e-300)))
        ranked.append(c)
        preds[c.name] = pr
        by_name[c.name] = e
    t2 = time.perf_counter()
    top_fam = {sc.spec.family for sc in top}
    for e in specials:
        if e.level == "vehicle":
            continue
        ok, why = e.applicable(ds)
        if not ok:
            skipped.append((e.name, why))
            continue
        if use_grammar and e.families and not (set(e.families) & top_fam):
            skipped.append((e.name, "none of its grammar pairs among the best screened ("
                            + ", ".join(f"{a}~{b}" for a, b in e.families) + ")"))
            continue
        prog(e.name)
        e.hint(screened)
        x = e.fit(model, ds, train, scale)
        pr = e.predict(model, ds, x)
        c = evaluate(e.name, x, pr, e.n_params(ds), e.onboard, e, e.families[0] if e.families else ())
        c.kind = "named"
        c.families = tuple(e.families)
        ranked.append(c)
        preds[e.name] = pr
        by_name[e.name] = e
    info = {"pairs": len(specs), "screened": len(screened), "refined": len(top),
            "wall_screen_s": t1 - t0, "wall_refine_s": t2 - t1, "wall_named_s": time.perf_counter() - t2,
            "screen_top": [(sc.spec.name, float(math.sqrt(max(sc.s_test, 0.0) / max(rr_te, 1e-300))), sc.k)
                           for sc in screened[:max(n_refine, 12)]]}
    return ranked, skipped, preds, by_name, info


def _n_eff(ds, pr, test):
    """independent held-out samples of an AR(1) residual (module doc)"""
    n_te = int(test.sum())
    n_eff = 0.0
    for o in ds.outputs:
        r = (ds.ch[o] - pr[o])[test]
        rho = min(max(candidates.autocorr(r) if len(r) > 2 else 0.0, 0.0), 0.99)
        n_eff += n_te * (1.0 - rho) / (1.0 + rho)
    return max(n_eff, 2.0)


def _ic(score, k, n_eff):
    return n_eff * 2.0 * math.log(max(score, 1e-12)) + k * math.log(n_eff)


def _select(ranked, ds, preds, test, scale, den):
    """IC per candidate, acceptance, the chosen one and its ties (module doc)."""
    if not ranked:
        return None, [], 0.0
    best = min(ranked, key=lambda c: c.score)
    n_eff = _n_eff(ds, preds[best.name], test)
    for c in ranked:
        c.ic = _ic(c.score, c.k, n_eff)
        c.penalised = c.ic
        c.accepted = c.ic < 0.0 and c.score <= 1.0 - MIN_GAIN
    ranked.sort(key=lambda c: c.ic)
    acc = [c for c in ranked if c.accepted]
    if not acc:
        return None, [], n_eff
    chosen, ties = _choose(acc, lambda c: c.ic)
    return chosen, ties, n_eff


def _choose(acc, ic):
    """the chosen one among accepted candidates (sorted by ic(c)) and its ties"""
    band = [c for c in acc if ic(c) <= ic(acc[0]) + TIE_IC]
    chosen = min(band, key=lambda c: (c.k, c.family[1:] != ("const",), ic(c)))
    if chosen.kind == "grammar":
        named = [c for c in acc if c.kind == "named" and chosen.family in c.families
                 and 1.0 - c.score >= (1.0 - chosen.score) * (1.0 - SPECIAL_TOL)]
        if named:
            chosen = min(named, key=lambda c: c.score)
    ties = [c.name for c in band if c is not chosen]
    return chosen, ties


def _second_split(holdout):
    return "blocks:8" if holdout.startswith("forward") else "forward:0.3"


def _confirm(model, ds, base, ranked, by_name, holdout, scale, base_res):
    """The best CONFIRM accepted candidates re-fitted and scored on the
    other split (_second_split); the choice is made again on the sum of
    both splits' ICs (module doc). Returns chosen, ties, statistics."""
    split = _second_split(holdout)
    tr2, te2 = holdout_masks(len(ds), split)
    acc = [c for c in ranked if c.accepted][:CONFIRM]
    den2 = sum((rms(base_res[o][te2]) / scale[o]) ** 2 for o in ds.outputs)
    fits = {}
    specs = [by_name[c.name].spec for c in acc if isinstance(by_name[c.name], grammar.GrammarEffect)]
    if specs:
        for sp, pr in zip(specs, grammar.refit(model, ds, base, specs, tr2, scale)):
            fits[sp.name] = pr
    for c in acc:
        if c.name not in fits:
            e = by_name[c.name]
            fits[c.name] = e.predict(model, ds, e.fit(model, ds, tr2, scale))
    sc2 = {}
    for c in acc:
        pr = fits[c.name]
        num = sum((rms((ds.ch[o] - pr[o])[te2]) / scale[o]) ** 2 for o in ds.outputs)
        sc2[c.name] = float(np.sqrt(num / max(den2, 1e-30)))
    best = min(acc, key=lambda c: sc2[c.name])
    n2 = _n_eff(ds, fits[best.name], te2)
    for c in acc:
        c.score2 = sc2[c.name]
        c.ic2 = _ic(sc2[c.name], c.k, n2)
    info = {"split": split, "n_eff": n2, "score": sc2}
    both = sorted((c for c in acc if c.ic2 < 0.0), key=lambda c: c.ic + c.ic2)
    if not both:                                   # nothing holds on the second split: the first's choice
        return (*_choose(acc, lambda c: c.ic), info)
    return (*_choose(both, lambda c: c.ic + c.ic2), info)


def verdict(res):
    """One paragraph: first whether the base model fits at all (and the likely
    cause when it does not), then what was found, or that nothing explains
    the structure."""
    pre = res.sanity.summary() if res.sanity is not None else ""
    txt = _attribution_verdict(res)
    return f"{pre}. Attribution on top of it: {txt}" if pre else txt


def _attribution_verdict(res):
    struct = {o: a for o, a in res.structure.items() if a > STRUCTURE}
    if res.chosen is not None:
        c = res.chosen
        gain = 1.0 - c.score
        txt = (f"effect: {c.name} ({', '.join(f'{k}={v:.4g}' for k, v in c.params.items())}); "
               f"held-out error {100 * gain:.1f} % lower (score {c.score:.3f}, {c.k} parameter(s), "
               f"hold-out {res.holdout})")
        other = {k: v for k, v in res.cross.items() if k != res.holdout}
        if other:
            txt += "; " + ", ".join(f"{100 * (1.0 - v):.1f} % lower on hold-out {k}" for k, v in other.items())
        if c.description:
            txt += f" [{c.description}]"
        if res.ties:
            how = ((f"IC within {TIE_IC:g}" + (" summed over both splits" if res.search.get("second") else ""))
                   if res.search else "penalised scores within 0.01")
            txt += f"; not distinguishable from {', '.join(res.ties)} on this data ({how})"
        if c.score > 0.7 and struct:
            txt += ("; most of the structured residual remains unexplained (it correlates with "
                    + "; ".join(f"{o}: " + ", ".join(f"{n} r={r:+.2f}" for n, r, _ in res.dependence[o][:3])
                                for o in struct) + ")")
        return txt
    if struct:
        names = {o: ", ".join(f"{n} (r={r:+.2f})" for n, r, _ in res.dependence[o][:4]) for o in struct}
        txt = ("no candidate effect explains the structured residual (lag-1 autocorrelation "
               + ", ".join(f"{o} {a:.2f}" for o, a in struct.items())
               + "); it correlates most with: " + "; ".join(f"{o}: {v}" for o, v in names.items()))
        k = res.correction
        if k is not None:
            txt += ("; no physical effect identified: " + k.summary())
        return txt
    return "no effect found: the residual is unstructured (noise-like) and no candidate reduces the held-out error enough"
