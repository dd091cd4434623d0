#!/bin/sh
# run_fuzz.sh - builds the libFuzzer harnesses of tests/fuzz in both
# arithmetic builds (-DGRIP_ARITH_FIXED=0/1, lib/ sources compiled in, ASan +
# UBSan) and runs each for a bounded time on a copy of its seed corpus.
# TAP output: one line per harness and build, with executions, coverage
# (libFuzzer cov: edges, ft: features) and corpus size in the comment.
#
#   sh tests/fuzz/run_fuzz.sh            (from the repository root)
# Environment: FUZZ_TIME (seconds per harness per build, default 20),
#   BUILDROOT (default build; work files go to $BUILDROOT/fuzz),
#   FUZZ_JOBS (harness runs at once, default: number of CPUs, at most 4).
# A crash input is kept as $BUILDROOT/fuzz/artifacts/<harness>-<build>-crash-*;
# reproduce with: $BUILDROOT/fuzz/fuzz_<harness>_<0|1> <that file>
set -u
cd "$(dirname "$0")/../.." || exit 2
FUZZ_TIME=${FUZZ_TIME:-20}
B=${BUILDROOT:-build}/fuzz
mkdir -p "$B/obj0" "$B/obj1" "$B/artifacts" "$B/log" "$B/work"

# clang with the libFuzzer runtime (Debian: libclang-rt-<ver>-dev)
CC=${FUZZ_CC:-clang}
if ! command -v "$CC" >/dev/null 2>&1; then
    apt-get install -y clang >/dev/null 2>&1
fi
probe="$B/probe.c"
printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n);\nint LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { (void)d; (void)n; return 0; }\n' > "$probe"
if ! "$CC" -fsanitize=fuzzer "$probe" -o "$B/probe" >/dev/null 2>&1; then
    ver=$("$CC" --version | sed -n 's/.*clang version \([0-9]*\).*/\1/p' | head -1)
    apt-get install -y "libclang-rt-$ver-dev" >/dev/null 2>&1
    if ! "$CC" -fsanitize=fuzzer "$probe" -o "$B/probe" >/dev/null 2>&1; then
        echo "not ok 1 - clang cannot link -fsanitize=fuzzer (install libclang-rt-dev)"
        echo "1..1"
        exit 1
    fi
fi

SAN="-g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
INC="-Iinclude -Ilib/arith -Iport/linux -Itests/fuzz -D_POSIX_C_SOURCE=200809L"
LIBSRC=$(ls lib/*/*.c)

# harness:extra host sources
HARNESSES="mf:port/linux/tir_reader.c mf89: mf_thermal: brush: can: candump:port/linux/candump.c tir:port/linux/tir_reader.c est:port/linux/tir_reader.c chain:port/linux/tir_reader.c"
[ -f include/grip/grip_brush.h ] || HARNESSES=$(echo "$HARNESSES" | sed 's/brush: //')
[ -f include/grip/grip_est.h ] || HARNESSES=$(echo "$HARNESSES" | sed 's/ est:[^ ]*//; s/ chain:[^ ]*//')

n=0
fail=0
tap() {   # status text
    n=$((n + 1))
    if [ "$1" = ok ]; then echo "ok $n - $2"; else echo "not ok $n - $2"; fail=1; fi
}

# 1. lib/ objects per build, instrumented for coverage (no libFuzzer main);
# the two builds at once (each compiles one file at a time)
build_objs() {   # A; writes $B/log/build-$A.status: ok, or fail, and est-broken when lib/est/ fails
    A=$1
    st=ok
    : >"$B/log/build-$A.notes"
    for s in $LIBSRC $(echo "$HARNESSES" | tr ' ' '\n' | sed -n 's/^[^:]*://p' | sort -u); do
        o="$B/obj$A/$(echo "$s" | tr '/' '_' | sed 's/\.c$/.o/')"
        if [ ! -f "$o" ] || [ "$s" -nt "$o" ] || [ -n "$(find include lib port/linux -name '*.h' -newer "$o" 2>/dev/null | head -1)" ]; then
            if ! $CC $SAN -fsanitize=fuzzer-no-link -DGRIP_ARITH_FIXED=$A -DGRIP_DEBUG_SATURATION=0 $INC -c "$s" -o "$o" \
                2>"$B/log/build-$A.err"; then
                rm -f "$o"
                case "$s" in
                lib/est/*)   # an unfinished estimator must not stop the other harnesses
                    echo "# $s does not build: fuzz_est skipped" >>"$B/log/build-$A.notes"
                    touch "$B/log/build-$A.est-broken" ;;
                *)
                    st=fail
                    sed 's/^/# /' "$B/log/build-$A.err" | head -20 >>"$B/log/build-$A.notes" ;;
                esac
            fi
        fi
    done
    echo $st >"$B/log/build-$A.status"
}
rm -f "$B"/log/build-*.est-broken
for A in 0 1; do build_objs $A & done
wait
for A in 0 1; do
    cat "$B/log/build-$A.notes"
    if [ -f "$B/log/build-$A.est-broken" ]; then
        HARNESSES=$(echo "$HARNESSES" | sed 's/ est:[^ ]*//; s/ chain:[^ ]*//')
        LIBSRC=$(echo "$LIBSRC" | grep -v '^lib/est/')
    fi
    if [ "$(cat "$B/log/build-$A.status" 2>/dev/null)" = ok ]; then
        tap ok "build lib/ for fuzzing (GRIP_ARITH_FIXED=$A)"
    else
        tap fail "build lib/ for fuzzing (GRIP_ARITH_FIXED=$A)"
    fi
done

# 2. harnesses, the two builds at once
link_harnesses() {   # A
    A=$1
    for h in $HARNESSES; do
        name=${h%%:*}
        extra=$(echo "${h#*:}" | tr '/' '_' | sed 's/\.c$/.o/')
        objs=""
        for s in $LIBSRC; do objs="$objs $B/obj$A/$(echo "$s" | tr '/' '_' | sed 's/\.c$/.o/')"; done
        [ -n "$extra" ] && objs="$objs $B/obj$A/$extra"
        if ! $CC $SAN -fsanitize=fuzzer -DGRIP_ARITH_FIXED=$A -DGRIP_DEBUG_SATURATION=0 $INC \
            "tests/fuzz/fuzz_$name.c" $objs -lm -o "$B/fuzz_${name}_$A" 2>"$B/log/$name-$A.build"; then
            rm -f "$B/fuzz_${name}_$A"
        fi
    done
}
for A in 0 1; do link_harnesses $A & done
wait
for h in $HARNESSES; do
    for A in 0 1; do
        [ -x "$B/fuzz_${h%%:*}_$A" ] || sed 's/^/# /' "$B/log/${h%%:*}-$A.build" | head -20
    done
done

# 3. runs, FUZZ_JOBS at a time
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -gt 4 ] && jobs=4
run_one() {   # name build
    w="$B/work/$1-$2"
    rm -rf "$w"
    mkdir -p "$w"
    [ -d "tests/fuzz/corpus/$1" ] && cp "tests/fuzz/corpus/$1"/* "$w"/ 2>/dev/null
    maxlen=4096
    [ "$1" = est ] && maxlen=16384   # up to 200 estimator steps of 71 bytes
    [ "$1" = chain ] && maxlen=16448  # calibration (1 + 27 bytes), then as est
    "$B/fuzz_$1_$2" -max_total_time="$FUZZ_TIME" -timeout=10 -rss_limit_mb=2048 -max_len=$maxlen \
        -print_final_stats=1 -artifact_prefix="$B/artifacts/$1-$2-" "$w" >"$B/log/$1-$2.run" 2>&1
    echo $? >"$B/log/$1-$2.rc"
}
running=0
for h in $HARNESSES; do
    name=${h%%:*}
    for A in 0 1; do
        [ -x "$B/fuzz_${name}_$A" ] || continue
        rm -f "$B/log/$name-$A.rc"
        run_one "$name" "$A" &
        running=$((running + 1))
        if [ "$running" -ge "$jobs" ]; then
            wait
            running=0
        fi
    done
done
wait

for h in $HARNESSES; do
    name=${h%%:*}
    for A in 0 1; do
        label="fuzz_$name $( [ $A = 1 ] && echo fixed || echo float )"
        if [ ! -x "$B/fuzz_${name}_$A" ]; then
            tap fail "$label: harness does not build"
            continue
        fi
        log="$B/log/$name-$A.run"
        rc=$(cat "$B/log/$name-$A.rc" 2>/dev/null || echo 99)
        execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
        last=$(grep -E '^#[0-9]+' "$log" | tail -1)
        cov=$(echo "$last" | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
        ft=$(echo "$last" | sed -n 's/.*ft: \([0-9]*\).*/\1/p')
        corp=$(echo "$last" | sed -n 's/.*corp: \([0-9]*\).*/\1/p')
        info="${FUZZ_TIME} s, ${execs:-?} executions, cov: ${cov:-?} ft: ${ft:-?}, corpus ${corp:-?}"
        if [ "$rc" = 0 ] && ! grep -q -E 'ERROR: (AddressSanitizer|libFuzzer|UndefinedBehaviorSanitizer)|runtime error|PROPERTY VIOLATED' "$log"; then
            tap ok "$label: $info"
        else
            tap fail "$label: rc $rc, $info"
            grep -E 'PROPERTY VIOLATED|ERROR:|runtime error|SUMMARY|Test unit written' "$log" | head -8 | sed 's/^/# /'
        fi
    done
done
echo "1..$n"
exit $fail
