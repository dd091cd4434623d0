"""The `grip` command: `grip <command> [args]` (also `python -m grip_tools`).

Each command is a module with a main(argv) function; this table is the only
place that names them. Modules are imported only when their command runs, so
`grip --help` does not load numpy or scipy.
"""
import importlib
import sys

from grip_tools import __version__
from grip_tools.errors import EXIT_DATA, EXIT_USAGE, DataError, UsageError

COMMANDS = {
    # tire engineer: evaluate, fit, convert, close the loop
    "tir2c": ("grip_tools.reference.tir", "emit a grip_mf_params C definition from a .tir file"),
    "fit-mf": ("grip_tools.fit.mf", "identify Magic Formula coefficients from measured sweeps"),
    "axle-stiffness": ("grip_tools.fit.axle_stiffness", "rear-axle .tir whose cornering stiffness gives the car's understeer gradient (or a ramp's)"),
    "fit-brush": ("grip_tools.fit.brush", "fit Neo-FIALA to Magic Formula curves (G275 demo) or to sweeps"),
    "mf89": ("grip_tools.reference.mf89", "1989-style lateral Magic Formula: constraint report of a coefficient set"),
    "brush-verify": ("grip_tools.reference.brush", "brush models: closed forms vs quadrature, every n (--write-table: lib/brush/brush_table.h)"),
    "analyze": ("grip_tools.loop.cli", "measured data: residual analysis, effect attribution, model update"),
    # vehicle-dynamics engineer: simulate, evaluate the estimator, inject faults
    "simulate": ("grip_tools.sim.cli", "reference vehicle simulator: truth.csv, sensors.csv, can.log"),
    "est-eval": ("grip_tools.evaluate.est_eval", "estimator accuracy on simulator manoeuvres and real logs: beta, mu, axle Fy (table + PNG)"),
    "est-axle": ("grip_tools.sim.independent.axle", "the independent judge's axle Fy by error source: the estimate, the sensors' force and moment balance, the car's roll gradient"),
    "est-sensitivity": ("grip_tools.evaluate.sensitivity", "each estimator constant's class and its effect on the independent judge (halved, doubled)"),
    "faults": ("grip_tools.evaluate.faults", "fault injection on the ESC inputs: monitor + estimator, fault table, false alarms"),
    "main-job": ("grip_tools.evaluate.main_job", "the README's main job (see tools/scripts/main_job.sh)"),
    "fleet": ("grip_tools.fleet.cli", "the estimator over a fleet of logs on Dask: run, analyze, report"),
    "sim-fleet": ("grip_tools.fleet.simfleet", "N simulator logs with truth and a manifest, for grip fleet run"),
    # CAN
    "can-table": ("grip_tools.can.dbc", "DBC + map file -> CAN signal table (C source, text form)"),
    "comma2k19": ("grip_tools.logs.comma2k19", "comma2k19 raw CAN arrays -> candump log"),
    # golden vectors, code generation, firmware measurements
    "golden-all": ("grip_tools.golden.all", "write every golden-vector file and test parameter set"),
    "golden-brush": ("grip_tools.golden.brush", "write golden vectors of the brush-model family"),
    "golden-est": ("grip_tools.golden.est", "write golden vectors of the onboard estimator (reference over input sequences)"),
    "golden-q16": ("grip_tools.golden.q16", "write golden vectors for the Q15.16 math primitives"),
    "kernels": ("grip_tools.golden.q16_kernels", "regenerate the Q15.16 kernels header (piecewise quadratic atan and sin, exp2 and log2 polynomials)"),
    "kernels-f32": ("grip_tools.golden.f32_kernels", "regenerate the float build's polynomial kernels header"),
    "stack": ("grip_tools.evaluate.stack", "worst-case stack per function from -fcallgraph-info files"),
    "bench": ("grip_tools.evaluate.bench", "benchmarks: host ns/call, callgrind and Cortex-M instruction counts"),
}


EXIT_HELP = """exit status: 0 success, 1 a check the command ran failed (e.g. a fit that
did not converge), 2 usage (bad option, a file that cannot be opened),
3 data (a file read but not usable: the message names file, line, field)"""


def data_error_types():
    """Exception classes of the readers that mean 'bad input data', so that
    every reader's error is reported the same way. Only from modules already
    loaded (an error of a module that was never imported cannot have been
    raised): reporting a .tir error must not import numpy, so it works under
    a small memory limit too."""
    types = [DataError]
    for module, name in (("grip_tools.reference.tir", "TirError"), ("grip_tools.reference.brush", "ParamError"),
                         ("grip_tools.can.dbc", "MapError")):
        m = sys.modules.get(module)
        if m is not None and hasattr(m, name):
            types.append(getattr(m, name))
    return tuple(types)


def run_command(name, argv):
    """Run one command; user errors end as one line on stderr and an exit
    code (EXIT_HELP), programming errors keep their traceback."""
    prog = f"grip {name}"
    from grip_tools.reference import tir      # .tir warnings name the command, as its errors do
    old_handler = tir.set_warning_handler(lambda w: print(f"{prog}: warning: {w}", file=sys.stderr))
    old_policy = dict(tir.POLICY)
    try:
        module = importlib.import_module(COMMANDS[name][0])
        return module.main(argv) or 0
    except UsageError as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return EXIT_USAGE
    except (FileNotFoundError, IsADirectoryError, PermissionError, NotADirectoryError) as e:
        if e.filename is not None:
            print(f"{prog}: cannot open {e.filename}: {e.strerror}", file=sys.stderr)
        else:                           # raised without the OS's fields (numpy's readers): its text names the file
            print(f"{prog}: cannot open: {e}", file=sys.stderr)
        return EXIT_USAGE
    except UnicodeDecodeError as e:
        print(f"{prog}: input is not UTF-8 text (byte offset {e.start}: {e.reason})", file=sys.stderr)
        return EXIT_DATA
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - only the readers' data errors are caught below
        if isinstance(e, data_error_types()):
            print(f"{prog}: {e}", file=sys.stderr)
            return EXIT_DATA
        raise
    finally:
        tir.set_warning_handler(old_handler)
        tir.POLICY.update(old_policy)


def usage(out):
    print("usage: grip <command> [args]   (grip <command> --help for its options)\n\ncommands:", file=out)
    for name, (_, what) in sorted(COMMANDS.items()):
        print(f"  {name:14s} {what}", file=out)
    print("\n" + EXIT_HELP, file=out)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        usage(sys.stderr)
        return 2
    if argv[0] in ("-h", "--help"):
        usage(sys.stdout)
        return 0
    if argv[0] == "--version":
        print(f"grip {__version__}")
        return 0
    name = argv[0]
    if name not in COMMANDS:
        print(f"grip: unknown command '{name}' (try grip --help)", file=sys.stderr)
        return 2
    return run_command(name, argv[1:])
