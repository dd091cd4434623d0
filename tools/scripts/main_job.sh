#!/bin/sh
# The README's main job: the bundled real Toyota RAV4 drive (60 s of CAN,
# comma2k19) replayed through grip: frames -> decoded, checked, time-aligned
# estimator inputs (grip-replay), then the tire model a VSC/AFS estimator
# runs on them, evaluated on a real tire (Goodyear G275 MF-Tyre fit) with
# the C library in float and fixed point against the float64 reference.
# Outputs in build/main-job/. The estimator step joins the replay when it
# lands (issue 5).
set -eu
cd "$(dirname "$0")/../.."
OUT=build/main-job
mkdir -p "$OUT"
for a in float fixed; do
    make --no-print-directory -s -j2 ARITH=$a lib progs
done
echo "== RAV4 CAN log -> estimator input samples (grip-replay, float and fixed builds)"
for a in float fixed; do
    build/$a-gcc/bin/grip-replay -o "$OUT/rav4_inputs_$a.csv" -q tests/data/comma2k19-rav4/rav4_bus0.log
done
build/float-gcc/bin/grip-replay -o "$OUT/rav4_inputs_float.csv" tests/data/comma2k19-rav4/rav4_bus0.log
echo "== Magic Formula on a real tire (grip-tire, float and fixed) vs the float64 reference"
PYTHONPATH=tools .venv/bin/python -m grip_tools main-job --outdir "$OUT"
