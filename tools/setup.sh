#!/bin/sh
# One-time set-up of a fresh Debian machine for grip: system packages and the
# Python virtual environment (.venv). Idempotent and quick when done already.
# Called by `make setup`, which every README command depends on.
set -eu
cd "$(dirname "$0")/.."

PKGS="gcc make clang libcmocka-dev libsocketcan-dev pkg-config valgrind \
gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi \
qemu-system-arm qemu-system-x86 busybox-static cpio can-utils python3-venv \
cppcheck clang-tidy libclang-rt-14-dev cmake"

missing=""
for p in $PKGS; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "setup: installing Debian packages:$missing"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq
    # shellcheck disable=SC2086
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi

REQ=tools/requirements.txt
STAMP=.venv/.grip-requirements
if [ ! -x .venv/bin/python ]; then
    echo "setup: creating Python virtual environment .venv"
    python3 -m venv .venv
fi
if [ ! -f "$STAMP" ] || ! cmp -s "$REQ" "$STAMP"; then
    echo "setup: installing Python packages from $REQ"
    .venv/bin/pip install -q --disable-pip-version-check -r "$REQ"
    cp "$REQ" "$STAMP"
fi
# The tools as a package in editable mode: the `grip` command runs the code
# of this clone.
PKG_STAMP=.venv/.grip-pyproject
if [ ! -x .venv/bin/grip ] || [ ! -f "$PKG_STAMP" ] || ! cmp -s tools/pyproject.toml "$PKG_STAMP"; then
    echo "setup: installing the grip tools (editable) into .venv"
    .venv/bin/pip install -q --disable-pip-version-check --no-deps -e tools
    cp tools/pyproject.toml "$PKG_STAMP"
fi
# The Python binding (tools/grip) holds lib/ compiled into two C extensions
# by that install: compile them again when a C source or header of lib/,
# include/ or port/linux/, or their build script, changed since (only the
# changed objects are recompiled), so that `import grip` runs this clone's C.
SO=$(ls tools/grip/_grip_f32*.so 2>/dev/null | head -n 1)
if [ -z "$SO" ] || [ -n "$(find lib include port/linux tools/setup.py tools/grip/_build.py \
        -newer "$SO" \( -name '*.c' -o -name '*.h' -o -name '*.py' \) 2>/dev/null | head -n 1)" ]; then
    echo "setup: compiling lib/ into the Python binding (tools/grip)"
    .venv/bin/pip install -q --disable-pip-version-check --no-deps -e tools
fi
