#!/bin/sh
# run_install_test.sh - grip as its users consume it: `make install` into a
# staging directory (DESTDIR), then the external consumer in this folder
# (main.c: one brush-model point through the public API) built
#   with pkg-config  against the shared host libraries (float, fixed),
#   with CMake       against the static host libraries (float, fixed),
#   with CMake and the installed toolchain files for Cortex-M4F (float) and
#                    Cortex-M0+ (fixed), run on qemu-system-arm,
#   with pkg-config  for Cortex-M4F (arm-none-eabi-gcc),
# outputs compared between the ways; then `make uninstall` of every part
# and a check that the prefix is empty again. Also: every installed header
# compiles on its own, and the installed grip-tire runs.
# TAP output; exits non-zero on any failure.
#   sh tests/install/run_install_test.sh     (BUILDROOT: default build)
set -u
cd "$(dirname "$0")/../.." || exit 2
BR=${BUILDROOT:-build}
W=$BR/install-test
rm -rf "$W"
mkdir -p "$W"
W=$(cd "$W" && pwd)
SRC=$(pwd)
PREFIX=/opt/grip
STAGE=$W/stage
ROOT=$STAGE$PREFIX
MAKE="make --no-print-directory -j2 BUILDROOT=$BR"
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
# run LABEL LOG command...: one TAP line, the log's tail on failure
run() {
    label=$1
    log=$W/$2
    shift 2
    if "$@" >"$log" 2>&1; then
        tap ok "$label"
        return 0
    fi
    tap fail "$label"
    tail -15 "$log" | sed 's/^/#   /'
    return 1
}

for t in cmake pkg-config arm-none-eabi-gcc qemu-system-arm; do
    if ! command -v $t >/dev/null 2>&1; then
        case $t in
            arm-none-eabi-gcc) pkg="gcc-arm-none-eabi libnewlib-arm-none-eabi" ;;
            *) pkg=$t ;;
        esac
        # shellcheck disable=SC2086
        apt-get install -y $pkg >/dev/null 2>&1
    fi
    if ! command -v $t >/dev/null 2>&1; then
        tap fail "$t is missing"
        finish
    fi
done
t0=$(date +%s)

# ---- install: host, then the two Cortex-M libraries into the same prefix
run "make install PREFIX=$PREFIX DESTDIR=... (host: headers, libraries, programs, pkg-config, CMake)" \
    install-host.log $MAKE install PREFIX=$PREFIX DESTDIR="$STAGE" || finish
run "make install TARGET=m4f (Cortex-M4F float library)" install-m4f.log \
    $MAKE install TARGET=m4f PREFIX=$PREFIX DESTDIR="$STAGE" || finish
run "make install TARGET=m0p (Cortex-M0+ fixed library)" install-m0p.log \
    $MAKE install TARGET=m0p PREFIX=$PREFIX DESTDIR="$STAGE" || finish
echo "# install: $(( $(date +%s) - t0 )) s"

VERSION=$(sed -n 's/^Version: //p' "$ROOT/lib/pkgconfig/grip-float.pc")
SOVER=$(echo "$VERSION" | awk -F. '{ print ($1 == 0) ? $1 "." $2 : $1 }')
missing=""
for f in include/grip/grip_types.h include/grip/grip_convert.h include/grip/grip_version.h \
         lib/libgrip-float.a lib/libgrip-fixed.a \
         lib/libgrip-float.so "lib/libgrip-float.so.$SOVER" "lib/libgrip-float.so.$VERSION" \
         lib/libgrip-fixed.so "lib/libgrip-fixed.so.$SOVER" "lib/libgrip-fixed.so.$VERSION" \
         bin/grip-tire bin/grip-replay lib/pkgconfig/grip-float.pc lib/pkgconfig/grip-fixed.pc \
         lib/cmake/grip/gripConfig.cmake lib/cmake/grip/gripConfigVersion.cmake \
         lib/cmake/grip/grip-host-targets.cmake lib/cmake/grip/grip-m4f-targets.cmake \
         lib/cmake/grip/grip-m0p-targets.cmake lib/grip/m4f/libgrip-float.a \
         lib/grip/m0p/libgrip-fixed.a lib/grip/m4f/pkgconfig/grip-float.pc \
         lib/grip/m0p/pkgconfig/grip-fixed.pc share/grip/cmake/arm-cortex-m4f.cmake \
         share/grip/cmake/arm-cortex-m0plus.cmake; do
    [ -e "$ROOT/$f" ] || missing="$missing $f"
done
sonames=""
for a in float fixed; do
    sonames="$sonames $(readelf -d "$ROOT/lib/libgrip-$a.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')"
done
if [ -z "$missing" ] && [ "$sonames" = " libgrip-float.so.$SOVER libgrip-fixed.so.$SOVER" ]; then
    tap ok "installed tree complete (version $VERSION; sonames$sonames)"
else
    tap fail "installed tree complete"
    echo "#   missing:${missing:- none}; sonames:$sonames"
fi

# ---- the installed headers are self-contained: each compiles on its own
# with only the installed include directory, under strict warnings
STRICT="-std=c99 -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wdouble-promotion -Wshadow -Wundef -Wstrict-prototypes -Werror"
bad=""
count=0
for h in "$ROOT"/include/grip/*.h; do
    b=$(basename "$h")
    [ "$b" = grip_config_check.h ] && continue   # included by grip_config.h only
    for A in 0 1; do
        count=$((count + 1))
        printf '#include <grip/%s>\ntypedef int grip_header_check_t;\n' "$b" >"$W/hdr.c"
        gcc $STRICT -DGRIP_ARITH_FIXED=$A -I"$ROOT/include" -fsyntax-only "$W/hdr.c" \
            >>"$W/headers.log" 2>&1 || bad="$bad $b($A)"
    done
done
if [ -z "$bad" ]; then
    tap ok "every installed header compiles alone against the installed tree ($count compilations, both arithmetics)"
else
    tap fail "installed headers compile alone:$bad"
    tail -10 "$W/headers.log" | sed 's/^/#   /'
fi

# ---- the installed program
printf 'kappa,alpha,gamma,fz,p,vx\n0.05,0.03,0,4000,0,20\n' >"$W/tire_in.csv"
if "$ROOT/bin/grip-tire" --tir tests/data/mfeval-tir/MagicFormula61_Paramerters.tir \
        <"$W/tire_in.csv" >"$W/tire_out.csv" 2>"$W/tire.log" && [ "$(wc -l <"$W/tire_out.csv")" -eq 2 ]; then
    tap ok "installed grip-tire evaluates a Magic Formula point"
else
    tap fail "installed grip-tire evaluates a Magic Formula point"
    sed 's/^/#   /' "$W/tire.log" | tail -5
fi

# ---- host consumers: pkg-config (shared libraries) and CMake (static)
export PKG_CONFIG_SYSROOT_DIR="$STAGE"
for a in float fixed; do
    export PKG_CONFIG_LIBDIR="$ROOT/lib/pkgconfig"
    flags="$(pkg-config --cflags-only-other grip-$a) $(pkg-config --libs-only-l grip-$a)"
    case $flags in
        *"-DGRIP_ARITH_FIXED=$([ $a = fixed ] && echo 1 || echo 0)"*) ;;
        *) tap fail "pkg-config grip-$a: Cflags carry GRIP_ARITH_FIXED ($flags)" ;;
    esac
    # shellcheck disable=SC2086
    if run "pkg-config: build the consumer against grip-$a ($(echo $flags))" pc-$a.log \
            gcc $STRICT -O2 tests/install/main.c $(pkg-config --cflags grip-$a) \
            $(pkg-config --libs grip-$a) -o "$W/pc-$a"; then
        needed=$(readelf -d "$W/pc-$a" | sed -n 's/.*Shared library: \[\(libgrip-[a-z]*\.so[0-9.]*\)\]/\1/p')
        run "pkg-config: the $a consumer runs on the shared library ($needed)" pc-$a.run \
            env LD_LIBRARY_PATH="$ROOT/lib" "$W/pc-$a"
        [ "$needed" = "libgrip-$a.so.$SOVER" ] || tap fail "the $a consumer needs libgrip-$a.so.$SOVER, not '$needed'"
    fi
    unset PKG_CONFIG_LIBDIR
    if run "CMake: find_package(grip COMPONENTS $a), grip::$a, build" cmake-$a.log \
            sh -c "cmake -S tests/install -B '$W/cmake-$a' -DCMAKE_PREFIX_PATH='$ROOT' -DGRIP_ARITH=$a &&
                   cmake --build '$W/cmake-$a'"; then
        run "CMake: the $a consumer runs (static library)" cmake-$a.run "$W/cmake-$a/consumer"
    fi
    if [ -s "$W/pc-$a.run" ] && cmp -s "$W/pc-$a.run" "$W/cmake-$a.run"; then
        tap ok "$a: pkg-config and CMake consumers print the same ($(sed -n 's/^fx_mN //p' "$W/cmake-$a.run") mN)"
    else
        tap fail "$a: pkg-config and CMake consumers print the same"
        diff "$W/pc-$a.run" "$W/cmake-$a.run" 2>&1 | head -6 | sed 's/^/#   /'
    fi
done
fxf=$(sed -n 's/^fx_mN //p' "$W/cmake-float.run" 2>/dev/null)
fxq=$(sed -n 's/^fx_mN //p' "$W/cmake-fixed.run" 2>/dev/null)
if [ -n "$fxf" ] && [ -n "$fxq" ] && awk -v f="$fxf" -v q="$fxq" \
        'BEGIN { d = f - q; if (d < 0) d = -d; r = f < 0 ? -f : f; exit !(r > 0 && d <= 1e-3 * r) }'; then
    tap ok "float and fixed consumers agree within 0.1 % (Fx $fxf / $fxq mN)"
else
    tap fail "float and fixed consumers agree within 0.1 % (Fx '$fxf' / '$fxq' mN)"
fi

# ---- firmware consumers: CMake with the installed toolchain files, on QEMU
qemu_run() {   # machine elf out: semihosting output arrives on stderr
    timeout 60 qemu-system-arm -M "$1" -nographic -monitor none -serial none \
        -semihosting-config enable=on,target=native -kernel "$2" >/dev/null 2>"$3"
}
for spec in m4f:arm-cortex-m4f:float:mps2-an386:Cortex-M4F m0p:arm-cortex-m0plus:fixed:mps2-an385:Cortex-M0+; do
    IFS=: read -r t tc a machine cpu <<EOF
$spec
EOF
    if run "CMake, $tc.cmake: $cpu consumer of grip::$a builds" cmake-$t.log \
            sh -c "cmake -S tests/install -B '$W/cmake-$t' -DCMAKE_PREFIX_PATH='$ROOT' -DGRIP_ARITH=$a \
                       -DCMAKE_TOOLCHAIN_FILE='$ROOT/share/grip/cmake/$tc.cmake' \
                       -DGRIP_BM_PORT='$SRC/port/baremetal' &&
                   cmake --build '$W/cmake-$t'"; then
        if ! grep -q "grip $VERSION ($t)" "$W/cmake-$t.log"; then
            tap fail "$cpu: find_package chose the $t library"
        fi
        if qemu_run "$machine" "$W/cmake-$t/consumer.elf" "$W/cmake-$t.run"; then
            tap ok "$cpu consumer runs on qemu-system-arm -M $machine"
        else
            tap fail "$cpu consumer runs on qemu-system-arm -M $machine"
            tail -5 "$W/cmake-$t.run" | sed 's/^/#   /'
        fi
    fi
done
# fixed: bit-identical on the target and the host (the library's guarantee)
if [ -s "$W/cmake-m0p.run" ] && cmp -s "$W/cmake-m0p.run" "$W/cmake-fixed.run"; then
    tap ok "Cortex-M0+ and host fixed consumers print the same"
else
    tap fail "Cortex-M0+ and host fixed consumers print the same"
    diff "$W/cmake-m0p.run" "$W/cmake-fixed.run" 2>&1 | head -6 | sed 's/^/#   /'
fi
# float: not required bit-identical (FMA contraction, libm); within 0.01 %
fxm=$(sed -n 's/^fx_mN //p' "$W/cmake-m4f.run" 2>/dev/null)
if [ -n "$fxm" ] && [ -n "$fxf" ] && awk -v f="$fxf" -v q="$fxm" \
        'BEGIN { d = f - q; if (d < 0) d = -d; r = f < 0 ? -f : f; exit !(r > 0 && d <= 1e-4 * r) }'; then
    tap ok "Cortex-M4F and host float consumers agree within 0.01 % (Fx $fxm / $fxf mN)"
else
    tap fail "Cortex-M4F and host float consumers agree within 0.01 % (Fx '$fxm' / '$fxf' mN)"
fi
# the Cortex-M4F pkg-config file, with the toolchain file's flags
M4F_FLAGS=$(sed -n 's/^set(GRIP_CPU_FLAGS "\(.*\)")$/\1/p' "$ROOT/share/grip/cmake/arm-cortex-m4f.cmake")
export PKG_CONFIG_LIBDIR="$ROOT/lib/grip/m4f/pkgconfig"
PC_CFLAGS=$(pkg-config --cflags grip-float)
PC_LIBS=$(pkg-config --libs grip-float)
# shellcheck disable=SC2086
if run "pkg-config (lib/grip/m4f/pkgconfig): Cortex-M4F consumer builds with arm-none-eabi-gcc $M4F_FLAGS" \
        pc-m4f.log sh -c "arm-none-eabi-gcc $M4F_FLAGS $STRICT -O2 -DCONSUMER_BAREMETAL=1 $PC_CFLAGS \
                              -Iport/baremetal -c tests/install/main.c -o '$W/pc-m4f.o' &&
                          arm-none-eabi-gcc $M4F_FLAGS -std=c99 -Wall -Wextra -Werror -O2 -Iport/baremetal \
                              -nostartfiles -nostdlib -T port/baremetal/mps2.ld '$W/pc-m4f.o' \
                              port/baremetal/startup.c port/baremetal/semihost.c $PC_LIBS -lc -lgcc \
                              -o '$W/pc-m4f.elf'"; then
    if qemu_run mps2-an386 "$W/pc-m4f.elf" "$W/pc-m4f.run" && cmp -s "$W/pc-m4f.run" "$W/cmake-m4f.run"; then
        tap ok "Cortex-M4F: pkg-config and CMake consumers print the same"
    else
        tap fail "Cortex-M4F: pkg-config and CMake consumers print the same"
        diff "$W/pc-m4f.run" "$W/cmake-m4f.run" 2>&1 | head -6 | sed 's/^/#   /'
    fi
fi
unset PKG_CONFIG_LIBDIR PKG_CONFIG_SYSROOT_DIR
# a component the target does not have is refused, with the reason
if cmake -S tests/install -B "$W/cmake-m4f-fixed" -DCMAKE_PREFIX_PATH="$ROOT" -DGRIP_ARITH=fixed \
        -DCMAKE_TOOLCHAIN_FILE="$ROOT/share/grip/cmake/arm-cortex-m4f.cmake" \
        -DGRIP_BM_PORT="$SRC/port/baremetal" >"$W/cmake-m4f-fixed.log" 2>&1; then
    tap fail "CMake refuses COMPONENTS fixed for the Cortex-M4F (float only)"
elif grep -q "component 'fixed' is not available for GRIP_TARGET=m4f" "$W/cmake-m4f-fixed.log"; then
    tap ok "CMake refuses COMPONENTS fixed for the Cortex-M4F (float only), saying why"
else
    tap fail "CMake refuses COMPONENTS fixed for the Cortex-M4F, saying why"
    grep -i error -A3 "$W/cmake-m4f-fixed.log" | head -6 | sed 's/^/#   /'
fi

# ---- uninstall: host first (the headers stay for the Cortex-M parts),
# then the Cortex-M parts; afterwards nothing of grip is left
run "make uninstall (host)" uninstall-host.log $MAKE uninstall PREFIX=$PREFIX DESTDIR="$STAGE"
left=$(cd "$ROOT" 2>/dev/null && ls lib/libgrip-* bin/grip-* lib/pkgconfig/grip-*.pc \
       lib/cmake/grip/grip-host-targets.cmake 2>/dev/null)
if [ -z "$left" ] && [ -f "$ROOT/include/grip/grip_types.h" ] && [ -f "$ROOT/lib/grip/m4f/libgrip-float.a" ]; then
    tap ok "uninstall (host) removed the host files and kept what the Cortex-M parts share"
else
    tap fail "uninstall (host) removed the host files and kept what the Cortex-M parts share"
    echo "#   left: $left" | head -3
fi
run "make uninstall TARGET=m4f" uninstall-m4f.log $MAKE uninstall TARGET=m4f PREFIX=$PREFIX DESTDIR="$STAGE"
run "make uninstall TARGET=m0p" uninstall-m0p.log $MAKE uninstall TARGET=m0p PREFIX=$PREFIX DESTDIR="$STAGE"
if [ ! -e "$ROOT" ] || [ -z "$(ls -A "$ROOT")" ]; then
    tap ok "prefix empty after uninstalling every part"
else
    tap fail "prefix empty after uninstalling every part"
    (cd "$ROOT" && find . | head -10 | sed 's/^/#   /')
fi
echo "# install test: $(( $(date +%s) - t0 )) s"
finish
