"""grip analyze: residual analysis, attribution and model
update for a measured tire-level CSV (schema: loop/io.py), a generated
undeclared-effect data set, or the AV-21 log (axle forces from the motion).

  analyze DATA.csv --tir FILE.tir [-o OUTDIR]
  analyze --generate {thermal,relaxation,slip_velocity,load,bank,none} [-o OUTDIR]
  analyze --vehicle {relaxation,bank,aero,thermal,yaw_bias,none} [-o OUTDIR]
  analyze --av21 [CSV] [--axle front|rear] [-o OUTDIR]
  analyze --rav4 LOG --replay build/float-gcc/bin/grip-replay [-o OUTDIR]
  analyze apply UPDATE.json DATA.csv --tir FILE.tir [-o OUT.csv]
  analyze --benchmark N [--out DIR] [--seed S] [--duration T] [--rate HZ] [--jobs J]

--holdout blocks:N (default blocks:8, interleaved) or forward:F (fit on the
first 1-F of the record, judge on the last F); tyre models: the best
accepted candidates are also re-fitted and scored on the other of blocks:8 /
forward:0.3 and chosen on both splits; both scores are reported. `apply`
predicts with a fitted update (update.json of an earlier run; state effects
run over the whole new record) and writes the corrected model's output next
to the measured channels, with RMS before / after.
Tyre models are searched with the candidate grammar (loop/grammar.py);
--named-only restricts the search to the named effects. --derived lists
channels derived from vehicle motion rather than measured at the tyre
(e.g. fz,fy): only then are downforce and road bank candidates.
--benchmark runs the generality benchmark (loop/benchmark.py) and writes
DIR/benchmark.md and benchmark.json.
"""
import argparse
import sys
import time

from grip_tools.errors import EXIT_HELP
from grip_tools.loop import attribution, io, report
from grip_tools.loop.effects import TireModel


def progress(i, n, name, _t0=[None]):
    """One line per search step on a terminal (rewritten in place); silent in a log."""
    now = time.monotonic()
    if _t0[0] is None or i == 0:
        _t0[0] = now
    if sys.stderr.isatty():
        print(f"\ranalyze: step {i + 1}/{n} {name[:40]:<40s} {now - _t0[0]:6.1f} s", end="",
              file=sys.stderr, flush=True)


def progress_end():
    if sys.stderr.isatty():
        print(file=sys.stderr)


def apply_main(argv):
    from grip_tools.reference import tir
    ap = argparse.ArgumentParser(prog="grip analyze apply", description="predict with a fitted update on new data")
    ap.add_argument("update", help="update.json written by grip analyze")
    ap.add_argument("data", help="tire-level CSV (the schema of grip analyze)")
    ap.add_argument("--tir", required=True, help="the base model's .tir (as in the run that wrote the update)")
    tir.add_reader_options(ap)
    ap.add_argument("--side", choices=("fitted", "left", "right"), default="fitted")
    ap.add_argument("-o", "--output", help="CSV: the data plus <output>_model and <output>_updated columns")
    a = ap.parse_args(argv)
    tir.apply_reader_options(a)
    import json
    import numpy as np
    from grip_tools.errors import DataError
    from grip_tools.loop.effects import all_effects
    with open(a.update) as f:
        try:
            upd = json.load(f)
        except json.JSONDecodeError as e:
            raise DataError(a.update, e.lineno, None, f"not JSON: {e.msg}") from None
    ds = io.read_csv(a.data)
    params = tir.load_params(a.tir, a.side)
    model = TireModel(params, f"{a.tir} ({tir.side_description(params)})", a.tir)
    base = model.predict(ds.ch)
    name = upd.get("effect")
    if name is None and upd.get("correction"):
        from grip_tools.loop import correction
        pred = correction.Correction.from_dict(upd["correction"]).predict(ds, base)
        name = "non-parametric correction"
    elif name is None:
        pred = base
    elif upd.get("grammar"):
        from grip_tools.loop import grammar
        g = upd["grammar"]
        try:
            sp = grammar.spec((g["target"], g["driver"]))
        except KeyError:
            raise DataError(a.update, None, "grammar", f"unknown grammar pair {g.get('target')}~{g.get('driver')}") \
                from None
        ctx = grammar.Context(model, ds, base, u_ref=dict(g.get("u_ref") or {}) or None)
        for part in (sp.target, sp.driver):
            ok, why = part.applicable(ctx)
            if not ok:
                raise DataError(a.data, None, None, f"effect {name} does not apply to these data: {why}")
        if g.get("u_ref"):
            ctx.u_ref.update(g["u_ref"])
        x = np.array(list(upd.get("params", {}).values()), dtype=float)
        if len(x) != sp.k(ctx):
            raise DataError(a.update, None, "params", f"{name}: {len(x)} parameters, the pair has {sp.k(ctx)}")
        pred = sp.predict(ctx, x)
    else:
        # the tyre-level form of the effect (vehicle-level ones share some names)
        effects = {e.name: e for e in reversed(all_effects()) if e.level in ("tire", "any")}
        if name not in effects:
            raise DataError(a.update, None, "effect", f"unknown effect '{name}' (known: {', '.join(effects)})")
        e = effects[name]
        ok, why = e.applicable(ds)
        if not ok:
            raise DataError(a.data, None, None, f"effect {name} does not apply to these data: {why}")
        pred = e.predict(model, ds, np.array(list(upd.get("params", {}).values()), dtype=float))
    for o in ds.outputs:
        r0 = float(np.sqrt(np.mean((ds.ch[o] - base[o]) ** 2)))
        r1 = float(np.sqrt(np.mean((ds.ch[o] - pred[o]) ** 2)))
        print(f"{o}: RMS error {r0:.4g} -> {r1:.4g} ({name or 'no effect'})")
    if a.output:
        out = io.Dataset(ds.t, dict(ds.ch), dict(ds.units), list(ds.outputs))
        for o in ds.outputs:
            out.ch[f"{o}_model"], out.ch[f"{o}_updated"] = base[o], pred[o]
            out.units[f"{o}_model"] = out.units[f"{o}_updated"] = io.UNITS[o]
        io.write_csv(a.output, out)
        print(f"wrote {a.output}", file=sys.stderr)
    return 0


def _check_options(ap, a):
    """Values the loop cannot run with, refused with exit 2 and the option
    named before anything is read or generated."""
    import math
    from grip_tools.loop import attribution, datasets
    if a.benchmark is not None and a.benchmark < 1:
        ap.error("--benchmark: at least one set")
    if a.generate is not None and a.generate not in datasets.KINDS:
        ap.error(f"--generate {a.generate}: one of {', '.join(datasets.KINDS)}")
    if not (math.isfinite(a.duration) and 0.0 < a.duration <= 3600.0):
        ap.error(f"--duration {a.duration!r}: a record length in (0, 3600] s")
    if not (math.isfinite(a.rate) and 1.0 <= a.rate <= 10000.0):
        ap.error(f"--rate {a.rate!r}: a sample rate in [1, 10000] Hz")
    if a.jobs < 1:
        ap.error(f"--jobs {a.jobs}: at least 1")
    try:
        attribution.holdout_masks(16, a.holdout)
    except ValueError as e:
        ap.error(f"--holdout: {e}")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] == "apply":
        return apply_main(argv[1:])
    from grip_tools.reference import tir
    ap = argparse.ArgumentParser(prog="grip analyze", description=__doc__, epilog=EXIT_HELP,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("data", nargs="?")
    ap.add_argument("--tir")
    tir.add_reader_options(ap)
    ap.add_argument("--generate")
    ap.add_argument("--vehicle", help="vehicle-level undeclared-effect set from sim (datasets.VEH_KINDS)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--av21", action="store_true")
    ap.add_argument("--axle", default="front", choices=("front", "rear"))
    ap.add_argument("--rav4")
    ap.add_argument("--replay", default="build/float-gcc/bin/grip-replay")
    ap.add_argument("--side", choices=("fitted", "left", "right"), default="fitted",
                    help="where the tyre of --tir is mounted: as fitted (default, never mirrored, as MFeval "
                         "and MF-Tyre evaluate a .tir), or left / right (a file fitted for the other side "
                         "is mirrored); the report states it")
    ap.add_argument("--holdout", default="blocks:8", help="blocks:N or forward:F (see above)")
    ap.add_argument("--derived", default="", help="comma-separated channels derived from vehicle motion "
                    "(fz: a load model, fy: m ay, alpha: kinematics), not measured at the tyre")
    ap.add_argument("--named-only", action="store_true", help="the named effects only, no grammar search")
    ap.add_argument("--benchmark", type=int, metavar="N", help="run the generality benchmark on N generated sets")
    ap.add_argument("--duration", type=float, default=150.0, help="benchmark: record length [s]")
    ap.add_argument("--rate", type=float, default=40.0, help="benchmark: sample rate [Hz]")
    ap.add_argument("--jobs", type=int, default=2, help="processes (the benchmark's sets; the refinement of long records)")
    ap.add_argument("-o", "--outdir", "--out", default="build/analyze")
    a = ap.parse_args(argv)
    _check_options(ap, a)
    if a.benchmark is not None:
        from grip_tools.loop import benchmark
        cmd = ("grip analyze --benchmark " + f"{a.benchmark} --seed {a.seed} --duration {a.duration:g} "
               f"--rate {a.rate:g} --jobs {a.jobs} --out {a.outdir}")
        path, s = benchmark.main(a.benchmark, a.outdir, a.seed, a.duration, a.rate, a.jobs, cmd)
        print(f"benchmark: {s['effect_sets']} effect sets: named correctly {s['named']} "
              f"({100 * s['named_rate']:.0f} %), held-out error halved {s['halved']} ({100 * s['halved_rate']:.0f} %), "
              f"both {s['named_and_halved']}; null sets {s['null_sets']}: passing {s['null_ok']}")
        print(f"report: {path}", file=sys.stderr)
        return 0
    tir.apply_reader_options(a)
    if a.generate:
        from grip_tools.loop import datasets
        ds, _ = datasets.make(a.generate, a.seed)
        ds.meta["source"] = f"datasets.make('{a.generate}', seed={a.seed})"
        model = TireModel(datasets.base_params(), "MagicFormula61_Paramerters.tir", datasets.TIR)
    elif a.vehicle:
        from grip_tools.loop import datasets
        from grip_tools.loop import vehicle
        if a.vehicle not in datasets.VEH_KINDS:
            ap.error(f"--vehicle: one of {', '.join(datasets.VEH_KINDS)}")
        ds, _ = datasets.vehicle_sets(a.seed, kinds=(a.vehicle,))[a.vehicle]
        model = vehicle.VehicleModel(datasets.vehicle_base())
    elif a.av21:
        from grip_tools.loop import av21
        ds, model = av21.load(a.data, a.axle)
    elif a.rav4:
        from grip_tools.loop import vehicle
        ds, model = vehicle.load(a.rav4, a.replay)
    else:
        if not a.data or not a.tir:
            ap.error("DATA.csv and --tir are required")
        from grip_tools.reference import tir
        ds = io.read_csv(a.data)
        params = tir.load_params(a.tir, a.side)
        model = TireModel(params, f"{a.tir} ({tir.side_description(params)})", a.tir)
    if a.derived:
        der = [c.strip() for c in a.derived.split(",") if c.strip()]
        bad = [c for c in der if c not in ds.ch]
        if bad:
            ap.error(f"--derived: no channel {', '.join(bad)} in the data")
        ds.meta["derived"] = tuple(sorted(set(ds.meta.get("derived", ())) | set(der)))
    try:
        attribution.holdout_masks(10, a.holdout)
    except ValueError as e:
        ap.error(str(e))
    also = [h for h in ("blocks:8", "forward:0.3") if h != a.holdout]
    res = attribution.analyse(model, ds, holdout=a.holdout, also=also,
                              progress=progress, use_grammar=not a.named_only, jobs=max(a.jobs, 1))
    progress_end()
    path, upd = report.write(res, ds, model, a.outdir)
    print(attribution.verdict(res))
    print(f"report: {path}", file=sys.stderr)
    return 0
