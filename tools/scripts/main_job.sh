#!/bin/sh
# The README's main job. Until the estimator and the CAN replay exist
# (issues 5 and 6) it runs the most complete job grip has: evaluate the
# Magic Formula of a real tire (Goodyear G275, fitted to Calspan flat-belt
# measurements) with the C library in both arithmetics, compare against the
# float64 reference and plot the curves (build/main-job/).
set -eu
cd "$(dirname "$0")/../.."
OUT=build/main-job
mkdir -p "$OUT"
make --no-print-directory -s golden >/dev/null
for a in float fixed; do
    make --no-print-directory -s -j2 ARITH=$a all
done
if [ -x build/float-gcc/bin/grip-tire ] && [ -f tools/grip_tools/main_job.py ]; then
    PYTHONPATH=tools .venv/bin/python -m grip_tools main-job --outdir "$OUT"
else
    echo "main job: grip-tire not built yet; showing the measured accuracy of the numeric core"
    GRIP_GOLDEN_DIR=build/golden build/fixed-gcc/tests/test_q16 | grep '^#'
fi
