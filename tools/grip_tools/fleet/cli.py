"""grip fleet: the estimator over a fleet of logs (docs/fleet.md).

    grip fleet run SOURCE... --out DIR      per-log summaries (Parquet), resumable
    grip fleet analyze DIR                  pooled residuals, effects ranked across logs
    grip fleet report DIR [--baseline DIR0] Markdown + PNG, regressions against DIR0
"""
import importlib
import sys

SUB = {"run": "grip_tools.fleet.run", "analyze": "grip_tools.fleet.analyze", "report": "grip_tools.fleet.report"}


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__, file=sys.stdout if argv else sys.stderr)
        return 0 if argv else 2
    if argv[0] not in SUB:
        print(f"grip fleet: unknown sub-command '{argv[0]}' (run, analyze, report)", file=sys.stderr)
        return 2
    return importlib.import_module(SUB[argv[0]]).main(argv[1:]) or 0
