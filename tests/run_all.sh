#!/bin/sh
# Every test of grip, in every configuration CI cares about. Each step's
# output is kept in build/test-logs/<step>.log and echoed; TAP lines
# ("ok" / "not ok") are counted; a step that fails without a "not ok" line
# (a build error, a crash) counts as one failure. Ends with the summary line
# "N passed, N failed", preceded by every failing line (with its step) so
# that the last lines of a CI log name what failed. Exit status 0 only if
# nothing failed.
set -u
cd "$(dirname "$0")/.."
LOGS=build/test-logs
rm -rf "$LOGS"
mkdir -p "$LOGS"
JOBS="-j2"
passed=0
failed=0
FAILURES="$LOGS/failures.txt"
: >"$FAILURES"
start=$(date +%s)

step() {
    name=$1
    shift
    echo "=== $name: $*"
    t0=$(date +%s)
    "$@" >"$LOGS/$name.log" 2>&1
    rc=$?
    grep -E '^(ok|not ok) |^# ' "$LOGS/$name.log" | grep -vE '^# (suite|ok|not ok) -' || true
    p=$(grep -cE '^ok ' "$LOGS/$name.log")
    f=$(grep -cE '^not ok ' "$LOGS/$name.log")
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "not ok - $name exited with status $rc; last lines of $LOGS/$name.log:"
        tail -20 "$LOGS/$name.log" | sed 's/^/#   /'
        f=1
        echo "$name: exited with status $rc" >>"$FAILURES"
    fi
    grep -E '^not ok ' "$LOGS/$name.log" | sed "s/^/$name: /" >>"$FAILURES"
    passed=$((passed + p))
    failed=$((failed + f))
    echo "=== $name: $p passed, $f failed ($(( $(date +%s) - t0 )) s)"
}

# Vectors once, from the current reference models.
step golden make --no-print-directory golden
for cfg in "ARITH=float" "ARITH=fixed" "ARITH=fixed DEBUG_SAT=1" \
           "ARITH=float SAN=1" "ARITH=fixed SAN=1" \
           "ARITH=float CC=clang" "ARITH=fixed CC=clang"; do
    name=$(echo "$cfg" | tr ' =' '_-')
    # shellcheck disable=SC2086
    step "unit_$name" make --no-print-directory $JOBS $cfg run-tests
done
# the lane evaluation of the Magic Formula against the scalar path bit for
# bit: both on grip's float kernels (GRIP_FLOAT_KERNELS=2), gcc and clang
for cc in gcc clang; do
    step "unit_mf_lanes_kernels2_$cc" sh -c "make --no-print-directory $JOBS CC=$cc BUILDROOT=build/k2 \
        DEFS='-DGRIP_ARITH_FIXED=0 -DGRIP_DEBUG_SATURATION=0 -DGRIP_FLOAT_KERNELS=2' GOLDEN=build/golden \
        build/k2/float-$cc/tests/test_mf_lanes && sh tests/run_suite.sh build/k2/float-$cc/tests/test_mf_lanes"
done
step firmware make --no-print-directory $JOBS firmware
# make install / uninstall into a staging prefix; external consumers through
# pkg-config and CMake, on the host and (toolchain files) on emulated Cortex-M.
step install sh tests/install/run_install_test.sh
# Golden vectors on emulated Cortex-M4F / M0+ (fixed: bit-identical to the host).
step target sh tests/target/run_target_tests.sh
# libFuzzer harnesses, both arithmetics, a bounded time each.
step fuzz env FUZZ_TIME=10 sh tests/fuzz/run_fuzz.sh
# cppcheck MISRA C:2012 and clang-tidy over lib/; deviations in docs/assurance.md.
step static sh tests/static/run_static.sh
# The real Linux CAN stack: a QEMU VM with vcan, canplayer and grip-replay -i vcan0.
step vm sh tests/vm/run_vcan_test.sh
# The bad-input corpus: grip-replay, grip-tire and the Python tools (grip), then the C programs
# of the fixed build.
step badinput sh tests/badinput/run_badinput.sh
step badinput_fixed sh tests/badinput/run_badinput.sh --only grip-replay,grip-tire --bin build/fixed-gcc/bin
# the Python modules in two processes (CI has two cores; the step runs alone)
step python env GRIP_TEST_JOBS=2 GRIP_TIRE_BIN=build/float-gcc/bin/grip-tire .venv/bin/python tests/python/run.py
# The command-line program again, on the fixed build.
step python_grip_tire_fixed env GRIP_TIRE_BIN=build/fixed-gcc/bin/grip-tire \
    .venv/bin/python tests/python/run.py 'test_grip_tire*.py'

if [ -s "$FAILURES" ]; then
    echo "failures (logs in $LOGS):"
    sed 's/^/  /' "$FAILURES"
fi
echo "total time $(( $(date +%s) - start )) s"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
