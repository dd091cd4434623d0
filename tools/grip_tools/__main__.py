"""Command-line entry: python -m grip_tools <command> [args]."""
import importlib
import sys

COMMANDS = {
    "kernels": ("grip_tools.kernels", "regenerate the Q15.16 polynomial kernels header"),
    "golden-q16": ("grip_tools.golden_q16", "write golden vectors for the Q15.16 math primitives"),
    "stack": ("grip_tools.stack", "worst-case stack per function from -fcallgraph-info files"),
    "bench": ("grip_tools.bench", "benchmarks: host ns/call, callgrind and Cortex-M instruction counts"),
    "main-job": ("grip_tools.main_job", "the README's main job (see tools/scripts/main_job.sh)"),
    "mf89": ("grip_tools.mf89", "1989-style lateral Magic Formula: constraint report of a coefficient set"),
    "golden-all": ("grip_tools.golden_all", "write every golden-vector file and test parameter set"),
    "brush-verify": ("grip_tools.brush", "brush models: closed forms vs quadrature, every n (--write-table: lib/brush/brush_table.h)"),
    "golden-brush": ("grip_tools.golden_brush", "write golden vectors of the brush-model family"),
    "fit-brush": ("grip_tools.fit_brush", "fit Neo-FIALA to Magic Formula curves (G275 demo) or to sweeps"),
    "simulate": ("grip_tools.vehsim.cli", "reference vehicle simulator: truth.csv, sensors.csv, can.log"),
    "can-table": ("grip_tools.dbc", "DBC + map file -> CAN signal table (C source, text form)"),
    "comma2k19": ("grip_tools.comma2k19", "comma2k19 raw CAN arrays -> candump log"),
    "tir2c": ("grip_tools.tir", "emit a grip_mf_params C definition from a .tir file"),
    "fit-mf": ("grip_tools.fit_mf", "identify Magic Formula coefficients from measured sweeps"),
    "analyze": ("grip_tools.residual.cli", "measured data: residual analysis, effect attribution, model update"),
    "golden-est": ("grip_tools.golden_est", "write golden vectors of the onboard estimator (est_ref over input sequences)"),
    "est-eval": ("grip_tools.est_eval", "estimator accuracy on simulator manoeuvres: beta, mu, axle Fy (table + PNG)"),
    "faults": ("grip_tools.faults", "fault injection on the ESC inputs: monitor + estimator, fault table, false alarms"),
}


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print("usage: python -m grip_tools <command> [args]\n\ncommands:")
        for name, (_, what) in sorted(COMMANDS.items()):
            print(f"  {name:14s} {what}")
        return 0 if len(sys.argv) >= 2 else 2
    name = sys.argv[1]
    if name not in COMMANDS:
        print(f"grip_tools: unknown command '{name}' (try --help)", file=sys.stderr)
        return 2
    module = importlib.import_module(COMMANDS[name][0])
    return module.main(sys.argv[2:]) or 0


if __name__ == "__main__":
    sys.exit(main())
