#!/bin/sh
# run_target_tests.sh - golden-vector tests of the tyre models on the target
# instruction sets, under qemu-system-arm with semihosting:
#   Cortex-M4F float build  (-mcpu=cortex-m4 hard float) on -M mps2-an386
#   Cortex-M0+ fixed build  (-mcpu=cortex-m0plus, ARMv6-M) on -M mps2-an385
#                           (a Cortex-M3: it executes the ARMv6-M subset)
# The same program (tests/target/target_main.c) and vector subset
# (gen_vectors.py: Magic Formula, Q15.16, MF 1989, MF thermal, the brush
# family, the relaxation transient, estimator sequences) also run on
# the host; compare.py checks every output
# against the golden reference with the host tests' tolerances, and the
# fixed results of the M0+ and the host must be identical bit for bit.
# TAP output; exits non-zero on any failure.
#   sh tests/target/run_target_tests.sh     (BUILDROOT: default build)
set -u
cd "$(dirname "$0")/../.." || exit 2
BR=${BUILDROOT:-build}
B=$BR/target
PY=python3
[ -x .venv/bin/python ] && PY=.venv/bin/python
mkdir -p "$B"
n=0
fail=0
tap() {   # ok|fail text
    n=$((n + 1))
    if [ "$1" = ok ]; then echo "ok $n - $2"; else echo "not ok $n - $2"; fail=1; fi
}
finish() {
    echo "1..$n"
    exit $fail
}

if ! command -v qemu-system-arm >/dev/null 2>&1; then
    apt-get install -y qemu-system-arm >/dev/null 2>&1
fi
if ! command -v arm-none-eabi-gcc >/dev/null 2>&1; then
    apt-get install -y gcc-arm-none-eabi libnewlib-arm-none-eabi >/dev/null 2>&1
fi
for t in qemu-system-arm arm-none-eabi-gcc; do
    if ! command -v $t >/dev/null 2>&1; then
        tap fail "$t is missing"
        finish
    fi
done

# golden vectors (the Python reference) if this build root has none yet
need_golden=0
for f in mf_params.c q16.txt mf89.txt mf_thermal.txt brush_neofiala.txt relax.txt est_bicycle_100hz.txt est_faults_100hz.txt; do
    [ -f "$BR/golden/$f" ] || need_golden=1
done
if [ $need_golden = 1 ]; then
    make --no-print-directory BUILDROOT="$BR" golden >"$B/golden.log" 2>&1 || { sed 's/^/# /' "$B/golden.log" | tail -20; }
fi
if $PY tests/target/gen_vectors.py "$BR/golden" "$B/tv_vectors.h" >"$B/gen.log" 2>&1; then
    tap ok "vector subset generated"
    cat "$B/gen.log"
else
    sed 's/^/# /' "$B/gen.log"
    tap fail "vector subset generated"
    finish
fi

# libraries: both cross builds and both host builds
for v in "TARGET=m4f" "TARGET=m0p" "ARITH=float" "ARITH=fixed"; do
    if ! make --no-print-directory BUILDROOT="$BR" $v lib >"$B/lib.log" 2>&1; then
        sed 's/^/# /' "$B/lib.log" | tail -20
        tap fail "make $v lib"
        finish
    fi
done

CF="-std=c99 -Wall -Wextra -Werror -O2 -g -Iinclude -Ilib/arith -Iport/baremetal -Itests/support -I$B -DGRIP_DEBUG_SATURATION=0"
BM="-nostartfiles -nostdlib -T port/baremetal/mps2.ld port/baremetal/startup.c port/baremetal/semihost.c"
SRC="tests/target/target_main.c $BR/golden/mf_params.c"
build() {   # label command...
    label=$1
    shift
    if "$@" >"$B/build.log" 2>&1; then
        tap ok "build $label"
    else
        sed 's/^/# /' "$B/build.log" | head -20
        tap fail "build $label"
    fi
}
build "Cortex-M4F float image" arm-none-eabi-gcc $CF -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard \
    -DGRIP_ARITH_FIXED=0 $BM $SRC "$BR/m4f-float/libgrip.a" -lm -lc -lgcc -o "$B/tv-m4f.elf"
build "Cortex-M0+ fixed image" arm-none-eabi-gcc $CF -mcpu=cortex-m0plus -mthumb -mfloat-abi=soft \
    -DGRIP_ARITH_FIXED=1 $BM $SRC "$BR/m0p-fixed/libgrip.a" -lm -lc -lgcc -o "$B/tv-m0p.elf"
build "host float program" gcc $CF -DGRIP_ARITH_FIXED=0 $SRC tests/target/host_bm.c "$BR/float-gcc/libgrip.a" -lm \
    -o "$B/tv-host-float"
build "host fixed program" gcc $CF -DGRIP_ARITH_FIXED=1 $SRC tests/target/host_bm.c "$BR/fixed-gcc/libgrip.a" -lm \
    -o "$B/tv-host-fixed"
[ $fail = 0 ] || finish

# semihosting SYS_WRITE0 output arrives on qemu's stderr
qemu_run() {   # machine elf out
    timeout 600 qemu-system-arm -M "$1" -nographic -monitor none -serial none \
        -semihosting-config enable=on,target=native -kernel "$2" >/dev/null 2>"$3"
}
check() {   # label output arith
    if $PY tests/target/compare.py "$BR/golden" "$2" "$3" >"$B/cmp.log" 2>&1; then
        tap ok "$1: every vector within the host tolerances"
    else
        tap fail "$1: vectors beyond the host tolerances"
    fi
    cat "$B/cmp.log"
}

t0=$(date +%s)
if qemu_run mps2-an386 "$B/tv-m4f.elf" "$B/m4f.out"; then
    tap ok "Cortex-M4F (mps2-an386) float: program ran to completion ($(($(date +%s) - t0)) s, $(wc -l <"$B/m4f.out") lines)"
else
    tap fail "Cortex-M4F (mps2-an386) float: program failed (exit $?)"
    tail -3 "$B/m4f.out" | sed 's/^/# /'
fi
check "Cortex-M4F float" "$B/m4f.out" float

t0=$(date +%s)
if qemu_run mps2-an385 "$B/tv-m0p.elf" "$B/m0p.out"; then
    tap ok "Cortex-M0+ code (mps2-an385) fixed: program ran to completion ($(($(date +%s) - t0)) s, $(wc -l <"$B/m0p.out") lines)"
else
    tap fail "Cortex-M0+ code (mps2-an385) fixed: program failed (exit $?)"
    tail -3 "$B/m0p.out" | sed 's/^/# /'
fi
check "Cortex-M0+ fixed" "$B/m0p.out" fixed

"$B/tv-host-fixed" >"$B/host-fixed.out" 2>&1
"$B/tv-host-float" >"$B/host-float.out" 2>&1
check "host fixed (same subset)" "$B/host-fixed.out" fixed
check "host float (same subset)" "$B/host-float.out" float

# fixed build: bit identity of every result word (and status) target vs host
if cmp -s "$B/m0p.out" "$B/host-fixed.out"; then
    tap ok "fixed build bit-identical on Cortex-M0+ and host ($(grep -c '^[MQFHSRLT]' "$B/m0p.out") result lines, every word)"
else
    tap fail "fixed build differs between Cortex-M0+ and host"
    diff "$B/m0p.out" "$B/host-fixed.out" | head -10 | sed 's/^/# /'
fi
# float build: not required to be identical (FMA contraction, libm); say how close
for k in "MFHS:MF, MF89 and MF thermal" "R:brush-family" "L:relaxation" "T:estimator"; do
    same=$(paste -d'|' "$B/m4f.out" "$B/host-float.out" | awk -F'|' -v re="^[${k%%:*}]" \
        '$1 ~ re { t++; if ($1 == $2) s++ } END { printf "%d of %d", s, t }')
    echo "# float build: $same ${k#*:} result lines bit-identical on Cortex-M4F and host (not required)"
done
finish
