#!/bin/sh
# The README's main job: the bundled real Toyota RAV4 drive (60 s of CAN,
# comma2k19) replayed through grip: CAN frames -> decoded, checked,
# time-aligned inputs -> the onboard estimator with a Magic Formula tire
# (grip-replay -e), in the float and the fixed build; then the estimator's
# yaw-rate reference against the measured yaw rate, and the tire model on a
# real tire (Goodyear G275 MF-Tyre fit) against the float64 reference.
# Outputs in build/main-job/.
set -eu
cd "$(dirname "$0")/../.."
OUT=build/main-job
LOG=tests/data/comma2k19-rav4/rav4_bus0.log
TIRE=tests/data/mfeval-tir/PacejkaBook_Defaults.tir
mkdir -p "$OUT"
for a in float fixed; do
    make --no-print-directory -s -j2 ARITH=$a lib progs
done
echo "== RAV4 CAN log -> inputs -> estimator (grip-replay -e, fixed build summary)"
build/float-gcc/bin/grip-replay -q -e "$TIRE" -o "$OUT/rav4_estimates_float.csv" "$LOG"
build/fixed-gcc/bin/grip-replay -e "$TIRE" -o "$OUT/rav4_estimates_fixed.csv" "$LOG"
echo "== Estimates, and the Magic Formula on a real tire (the C library via grip.mf) vs the float64 reference"
.venv/bin/grip main-job --outdir "$OUT" \
    --rav4 "$OUT/rav4_estimates_float.csv" "$OUT/rav4_estimates_fixed.csv"
