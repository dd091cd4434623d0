#!/bin/sh
# The README's main job. Until the estimator and the CAN replay exist
# (issues 5 and 6) it runs the most complete job grip has: evaluate the
# Magic Formula of a real tire (Goodyear G275, fitted to Calspan flat-belt
# measurements) with the C library in both arithmetics (grip-tire), compare
# against the float64 reference and plot the curves (build/main-job/).
set -eu
cd "$(dirname "$0")/../.."
for a in float fixed; do
    make --no-print-directory -s -j2 ARITH=$a lib progs
done
PYTHONPATH=tools .venv/bin/python -m grip_tools main-job --outdir build/main-job
