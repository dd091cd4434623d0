"""grip analyze: residual analysis, attribution and model
update for a measured tire-level CSV (schema: loop/io.py), a generated
undeclared-effect data set, or the AV-21 log (axle forces from the motion).

  analyze DATA.csv --tir FILE.tir [-o OUTDIR]
  analyze --generate {thermal,relaxation,slip_velocity,load,bank,none} [-o OUTDIR]
  analyze --vehicle {relaxation,bank,aero,thermal,yaw_bias,none} [-o OUTDIR]
  analyze --av21 [CSV] [--axle front|rear] [-o OUTDIR]
  analyze --rav4 LOG --replay build/float-gcc/bin/grip-replay [-o OUTDIR]
"""
import argparse
import sys

from grip_tools.loop import attribution, io, report
from grip_tools.loop.effects import TireModel


def main(argv=None):
    ap = argparse.ArgumentParser(prog="grip analyze", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("data", nargs="?")
    ap.add_argument("--tir")
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
    ap.add_argument("-o", "--outdir", default="build/analyze")
    a = ap.parse_args(argv)
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
    res = attribution.analyse(model, ds)
    path, upd = report.write(res, ds, model, a.outdir)
    print(attribution.verdict(res))
    print(f"report: {path}", file=sys.stderr)
    return 0
