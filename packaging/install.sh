#!/bin/sh
# install.sh - install or uninstall one part of grip into a prefix; called
# by `make install` / `make uninstall` (docs/porting.md, "Installing").
#
#   install.sh install host FLOAT_BUILD_DIR FIXED_BUILD_DIR
#   install.sh install m4f|m0p BUILD_DIR
#   install.sh uninstall host|m4f|m0p
# Environment: PREFIX (absolute), DESTDIR (staging root, may be empty),
# GRIP_VERSION, GRIP_SOVERSION (install only), GRIP_CC (host: compiler name).
#
# Parts: host (headers, libgrip-{float,fixed}.{a,so}, grip-tire and
# grip-replay, pkg-config files, the CMake package, the toolchain files);
# m4f / m0p (headers, the cross-built static library in lib/grip/<part>/
# with its own pkg-config file, the part's CMake targets and toolchain
# file). Parts share the headers and the CMake package files.
#
# Every file, symbolic link and directory an install creates is recorded,
# relative to PREFIX, in PREFIX/share/grip/manifest-<part>.txt ("f path",
# "l path", "d path"). Uninstall removes the part's files and links except
# those another installed part's manifest also lists, then every recorded
# directory that is left empty, deepest first; directories still in use by
# another part pass to that part's manifest. Nothing else is touched.
set -eu
export LC_ALL=C

action=${1:?action}
part=${2:?part}
shift 2
case $part in host|m4f|m0p) ;; *) echo "install.sh: unknown part '$part'" >&2; exit 2 ;; esac
: "${PREFIX:?PREFIX must be set}"
case $PREFIX in
    /*) ;;
    *) echo "install.sh: PREFIX must be an absolute path, not '$PREFIX'" >&2; exit 2 ;;
esac
PREFIX=${PREFIX%/}
DESTDIR=${DESTDIR-}
case "$DESTDIR$PREFIX" in
    *[[:space:]]*) echo "install.sh: PREFIX and DESTDIR must not contain white space" >&2; exit 2 ;;
esac
root=$DESTDIR$PREFIX
mdir=share/grip
manifest=$mdir/manifest-$part.txt
src_dir=$(cd "$(dirname "$0")/.." && pwd)

# A relative path from a manifest: no absolute paths, no "..".
check_rel() {
    case "/$1/" in
        */../*|//*) echo "install.sh: bad manifest entry '$1'" >&2; exit 2 ;;
    esac
}

# ---------------------------------------------------------------- uninstall
if [ "$action" = uninstall ]; then
    if [ ! -f "$root/$manifest" ]; then
        echo "uninstall: no '$part' installation of grip in $root"
        exit 0
    fi
    others=$(ls "$root/$mdir"/manifest-*.txt 2>/dev/null | grep -v "/manifest-$part.txt\$" || true)
    kept=0
    removed=0
    while read -r kind rel; do
        check_rel "$rel"
        case $kind in
            f|l)
                if [ -n "$others" ] && grep -qxF "$kind $rel" $others; then
                    kept=$((kept + 1))
                else
                    rm -f "$root/$rel"
                    removed=$((removed + 1))
                fi ;;
        esac
    done <"$root/$manifest"
    mine=$(sed -n 's/^d //p' "$root/$manifest")
    theirs=""
    [ -n "$others" ] && theirs=$(sed -n 's/^d //p' $others)
    rm -f "$root/$manifest"
    # deepest first (a parent sorts before its children); only if empty
    printf '%s\n%s\n' "$mine" "$theirs" | grep -v '^$' | sort -ru | while read -r rel; do
        check_rel "$rel"
        if [ "$rel" = . ]; then rmdir "$root" 2>/dev/null || true
        else rmdir "$root/$rel" 2>/dev/null || true; fi
    done
    # directories this part created that another part still uses pass to it
    if [ -n "$others" ]; then
        heir=$(printf '%s\n' "$others" | head -1)
        printf '%s\n' "$mine" | grep -v '^$' | while read -r rel; do
            if [ -d "$root/$rel" ] && ! grep -qxF "d $rel" "$heir"; then
                echo "d $rel" >>"$heir"
            fi
        done
    fi
    note=""
    [ $kept -gt 0 ] && note=", kept $kept shared with another installed part"
    echo "uninstall: $part: removed $removed files from $root$note"
    exit 0
fi
[ "$action" = install ] || { echo "install.sh: unknown action '$action'" >&2; exit 2; }

# ------------------------------------------------------------------ install
: "${GRIP_VERSION:?}"
: "${GRIP_SOVERSION:?}"
VERSION_MAJOR=${GRIP_VERSION%%.*}
VERSION_MINOR=${GRIP_VERSION#*.}
VERSION_MINOR=${VERSION_MINOR%%.*}
new=$(mktemp)
trap 'rm -f "$new" "$new.gen"' EXIT

# mkdir -p that records each directory it creates (PREFIX itself included)
mkdirs() {
    rel=$1
    todo=""
    while [ ! -d "$root/$rel" ]; do
        todo="$rel $todo"
        [ "$rel" = . ] && break
        case $rel in */*) rel=${rel%/*} ;; *) rel=. ;; esac
    done
    for d in $todo; do
        mkdir "$root/$d" 2>/dev/null || mkdir -p "$root/$d"
        echo "d $d" >>"$new"
    done
}
# put SRC REL MODE: copy a file
put() {
    mkdirs "$(dirname "$2")"
    rm -f "$root/$2"
    cp "$1" "$root/$2"
    chmod "$3" "$root/$2"
    echo "f $2" >>"$new"
}
# link TARGET REL: a relative symbolic link
link() {
    mkdirs "$(dirname "$2")"
    rm -f "$root/$2"
    ln -s "$1" "$root/$2"
    echo "l $2" >>"$new"
}
# sed replacement text: escape \ & and the delimiter |
esc() { printf '%s' "$1" | sed 's/[\\&|]/\\&/g'; }
# gen TEMPLATE REL VAR=VALUE...: a file from a template with @VAR@ replaced
gen() {
    tpl=$1
    rel=$2
    shift 2
    script="s|@VERSION@|$(esc "$GRIP_VERSION")|g;s|@SOVERSION@|$(esc "$GRIP_SOVERSION")|g"
    script="$script;s|@VERSION_MAJOR@|$VERSION_MAJOR|g;s|@VERSION_MINOR@|$VERSION_MINOR|g"
    script="$script;s|@PREFIX@|$(esc "$PREFIX")|g"
    for kv in "$@"; do
        script="$script;s|@${kv%%=*}@|$(esc "${kv#*=}")|g"
    done
    sed "$script" "$src_dir/packaging/$tpl" >"$new.gen"
    if grep -q '@[A-Z_]*@' "$new.gen"; then
        echo "install.sh: unreplaced placeholder in $tpl: $(grep -o '@[A-Z_]*@' "$new.gen" | head -1)" >&2
        exit 2
    fi
    put "$new.gen" "$rel" 644
}

# shared by every part
for h in "$src_dir"/include/grip/*.h; do
    put "$h" "include/grip/$(basename "$h")" 644
done
put "$src_dir/packaging/gripConfig.cmake" lib/cmake/grip/gripConfig.cmake 644
gen gripConfigVersion.cmake.in lib/cmake/grip/gripConfigVersion.cmake

case $part in
host)
    fb=${1:?float build dir}
    xb=${2:?fixed build dir}
    for a in float fixed; do
        b=$fb
        [ $a = fixed ] && b=$xb
        so=libgrip-$a.so
        put "$b/libgrip.a" "lib/libgrip-$a.a" 644
        put "$b/$so.$GRIP_VERSION" "lib/$so.$GRIP_VERSION" 755
        link "$so.$GRIP_VERSION" "lib/$so.$GRIP_SOVERSION"
        link "$so.$GRIP_SOVERSION" "lib/$so"
    done
    gen grip.pc.in lib/pkgconfig/grip-float.pc ARITH=float FIXED=0 LIBM=" -lm" \
        LIBDIR='${exec_prefix}/lib' TARGET=host DESC="single-precision float build"
    gen grip.pc.in lib/pkgconfig/grip-fixed.pc ARITH=fixed FIXED=1 LIBM="" \
        LIBDIR='${exec_prefix}/lib' TARGET=host DESC="integer-only fixed-point build"
    for p in "$fb"/bin/grip-*; do
        put "$p" "bin/$(basename "$p")" 755
    done
    host=$(${GRIP_CC:-cc} -dumpmachine 2>/dev/null || uname -m)
    ptr=$(${GRIP_CC:-cc} -dM -E - </dev/null | sed -n 's/^#define __SIZEOF_POINTER__ //p')
    gen grip-host-targets.cmake.in lib/cmake/grip/grip-host-targets.cmake CC="${GRIP_CC:-cc}" \
        HOST="$host" SIZEOF_VOID_P="$ptr"
    put "$src_dir/packaging/arm-cortex-m4f.cmake" share/grip/cmake/arm-cortex-m4f.cmake 644
    put "$src_dir/packaging/arm-cortex-m0plus.cmake" share/grip/cmake/arm-cortex-m0plus.cmake 644
    ;;
m4f|m0p)
    b=${1:?build dir}
    if [ $part = m4f ]; then
        a=float; fixed=0; libm=" -lm"; tc=arm-cortex-m4f; cpu="Cortex-M4F"
        flags="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard"
    else
        a=fixed; fixed=1; libm=""; tc=arm-cortex-m0plus; cpu="Cortex-M0+"
        flags="-mcpu=cortex-m0plus -mthumb -mfloat-abi=soft"
    fi
    put "$b/libgrip.a" "lib/grip/$part/libgrip-$a.a" 644
    gen grip.pc.in "lib/grip/$part/pkgconfig/grip-$a.pc" ARITH=$a FIXED=$fixed LIBM="$libm" \
        LIBDIR="\${exec_prefix}/lib/grip/$part" TARGET="$cpu, $flags" \
        DESC="$([ $a = float ] && echo "single-precision float build" || echo "integer-only fixed-point build")"
    gen grip-cross-targets.cmake.in "lib/cmake/grip/grip-$part-targets.cmake" TARGET=$part \
        ARITH=$a FIXED=$fixed CPU="$cpu" CPUFLAGS="$flags" TOOLCHAIN=$tc \
        LINKLIBS="$([ $a = float ] && echo m || true)"
    put "$src_dir/packaging/$tc.cmake" "share/grip/cmake/$tc.cmake" 644
    ;;
esac

# the manifest: this install's entries, plus those of an earlier install of
# the same part that are still there (an upgrade's left-overs stay listed)
mkdirs "$mdir"
if [ -f "$root/$manifest" ]; then
    while read -r kind rel; do
        check_rel "$rel"
        case $kind in
            d) [ -d "$root/$rel" ] && echo "d $rel" >>"$new" ;;
            *) { [ -e "$root/$rel" ] || [ -L "$root/$rel" ]; } && echo "$kind $rel" >>"$new" ;;
        esac
    done <"$root/$manifest"
fi
sort -u "$new" >"$root/$manifest"
chmod 644 "$root/$manifest"
echo "install: $part: $(grep -c '^[fl] ' "$root/$manifest") files in $root (manifest $PREFIX/$manifest)"
