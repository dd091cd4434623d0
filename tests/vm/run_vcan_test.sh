#!/bin/sh
# tests/vm/run_vcan_test.sh - grip-replay on a real Linux CAN stack.
#
# This machine's kernel has no CAN support, so the test boots a small VM
# with QEMU: Debian's linux-image-amd64 kernel (downloaded with apt-get
# download, unpacked, never installed on the host), its can, can-raw,
# can-dev and vcan modules, and a busybox initramfs built here holding a
# static grip-replay, canplayer (can-utils) and ip (iproute2) with their
# shared libraries, and the bundled RAV4 log. Inside the VM: vcan0 is
# created, `grip-replay -i vcan0` listens while canplayer replays the log
# onto vcan0 in real time (60 s), and the results come back over a second
# serial port. On the host, tests/vm/compare_live.py checks (docs/can.md):
#   - every frame of the table's ids arrived, same ids, payloads and order,
#     nothing else passed the kernel filter, zero drops, zero decode errors;
#   - replaying grip-replay's dump of what it received gives exactly the
#     live CSV (live and file paths are the same code);
#   - the live samples agree with the file replay of the original log:
#     each live value is the value of a frame within +-J of the step, J the
#     measured timing jitter, and the differences stay within the tolerance
#     derived from J.
# Prints TAP lines; skips (1..0 # SKIP) only where QEMU cannot be had or
# cannot start. Usage: sh tests/vm/run_vcan_test.sh   (BUILDROOT=dir to build elsewhere)
set -u
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
BR=${BUILDROOT:-build}
case $BR in /*) ;; *) BR=$ROOT/$BR ;; esac
W=$BR/vm
LOG=$ROOT/tests/data/comma2k19-rav4/rav4_bus0.log
PY=$ROOT/.venv/bin/python
T0=$(date +%s)
mkdir -p "$W"

n=0
failed=0
tap() {   # tap ok|fail TEXT
    n=$((n + 1))
    if [ "$1" = ok ]; then echo "ok $n - $2"; else echo "not ok $n - $2"; failed=1; fi
}
skip_all() {
    echo "# $*"
    echo "1..0 # SKIP $*"
    exit 0
}
die() {   # a failure of the test itself (not a skip): report and stop
    tap fail "$1"
    [ -n "${2:-}" ] && [ -f "$2" ] && tail -30 "$2" | sed 's/^/#   /'
    echo "1..$n"
    exit 1
}

# ---- 1. host tools -----------------------------------------------------------
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
missing=""
for p in qemu-system-x86 busybox-static can-utils cpio iproute2 libsocketcan-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "# installing:$missing"
    # shellcheck disable=SC2086
    if ! { $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
           $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing; } \
           >"$W/apt.log" 2>&1; then
        command -v qemu-system-x86_64 >/dev/null 2>&1 || skip_all "qemu-system-x86 cannot be installed (see $W/apt.log)"
        die "installing$missing failed" "$W/apt.log"
    fi
fi
command -v qemu-system-x86_64 >/dev/null 2>&1 || skip_all "qemu-system-x86_64 unavailable"

# ---- 2. kernel and modules ----------------------------------------------------
K=$W/kernel
if ! ls "$K"/root/boot/vmlinuz-* >/dev/null 2>&1; then
    rm -rf "$K"
    mkdir -p "$K/root"
    (
        cd "$K" || exit 1
        apt-get download linux-image-amd64 >"$K/download.log" 2>&1 || exit 1
        dep=$(dpkg-deb -f linux-image-amd64_*.deb Depends | sed 's/ *(.*//; s/,.*//; s/|.*//')
        apt-get download "$dep" >>"$K/download.log" 2>&1 || exit 1
        dpkg-deb -x "$(ls linux-image-[0-9]*.deb | head -1)" root || exit 1
        rm -f ./*.deb
    ) || die "downloading the Debian kernel (apt-get download linux-image-amd64)" "$K/download.log"
fi
VMLINUZ=$(ls "$K"/root/boot/vmlinuz-* | head -1)
KVER=${VMLINUZ##*/vmlinuz-}
MODDIR=$K/root/lib/modules/$KVER/kernel
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko; do
    [ -f "$MODDIR/$m" ] || die "kernel $KVER lacks module $m"
done

# ---- 3. programs ----------------------------------------------------------------
# The host grip-replay (compare_live.py replays files with it) and a static
# one for the VM, from the same libraries (float build).
make --no-print-directory -s BUILDROOT="$BR" ARITH=float lib progs "$BR/float-gcc/libgrip_port.a" \
    >"$W/build.log" 2>&1 || die "building grip-replay" "$W/build.log"
HOSTBIN=$BR/float-gcc/bin/grip-replay
gcc -static -std=c99 -O2 -D_POSIX_C_SOURCE=200809L -DGRIP_ARITH_FIXED=0 -DGRIP_DEBUG_SATURATION=0 \
    -Iinclude -Ilib/arith -Iport/linux port/linux/grip_replay.c "$BR/float-gcc/libgrip_port.a" \
    "$BR/float-gcc/libgrip.a" -lsocketcan -lm -o "$W/grip-replay-static" >>"$W/build.log" 2>&1 \
    || die "linking a static grip-replay" "$W/build.log"

# ---- 4. initramfs -----------------------------------------------------------------
I=$W/initramfs
rm -rf "$I"
mkdir -p "$I/bin" "$I/sbin" "$I/proc" "$I/sys" "$I/dev" "$I/tmp/out" "$I/data" "$I/mod"
cp /bin/busybox "$I/bin/busybox"
cp "$W/grip-replay-static" "$I/bin/grip-replay"
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko; do
    cp "$MODDIR/$m" "$I/mod/"
done
copy_with_libs() {   # a dynamic program and every library ldd names, at the same paths
    mkdir -p "$I$(dirname "$2")"
    cp "$1" "$I$2"
    ldd "$1" | awk '{for (i = 1; i <= NF; i++) if ($i ~ /^\//) print $i}' | while read -r lib; do
        mkdir -p "$I$(dirname "$lib")"
        cp -L "$lib" "$I$lib"
    done
}
copy_with_libs "$(command -v canplayer)" /bin/canplayer
copy_with_libs "$(command -v ip)" /sbin/ip
cp "$LOG" "$I/data/rav4.log"
cat >"$I/init" <<'EOF'
#!/bin/busybox sh
/bin/busybox --install -s /bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
say() { echo "GRIPVM: $*"; }
for m in can can-raw can-dev vcan; do
    insmod /mod/$m.ko || say "insmod $m failed"
done
say "modules: $(cut -d' ' -f1 /proc/modules | tr '\n' ' ')"
ip link add dev vcan0 type vcan && ip link set up vcan0 && say "vcan0 up"
grip-replay -i vcan0 -o /tmp/out/live.csv --dump /tmp/out/live.log --idle-exit 3 2>/tmp/out/replay.err &
pid=$!
i=0
while ! grep -q listening /tmp/out/replay.err 2>/dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
say "$(head -1 /tmp/out/replay.err)"
t0=$(date +%s)
canplayer -I /data/rav4.log
say "canplayer exit $? after $(( $(date +%s) - t0 )) s"
wait $pid
echo $? >/tmp/out/replay.rc
say "grip-replay exit $(cat /tmp/out/replay.rc)"
cd /tmp/out && tar cf - . | gzip -1 | base64 >/dev/ttyS1
echo "==END==" >/dev/ttyS1
sleep 1
say "done"
poweroff -f
EOF
chmod +x "$I/init"
(cd "$I" && find . | cpio -o -H newc 2>/dev/null | gzip -1) >"$W/initramfs.cpio.gz" \
    || die "building the initramfs"

# ---- 5. boot ----------------------------------------------------------------------
# Software emulation (TCG) by default: it works everywhere, and KVM inside
# this workplace's own VM is unreliable (nested KVM hung or aborted on MSR
# writes when tried). GRIP_VM_ACCEL=kvm uses KVM where it is known to work.
ACCEL="-accel ${GRIP_VM_ACCEL:-tcg}"
rm -f "$W/console.log" "$W/data.b64"
TB=$(date +%s)
# shellcheck disable=SC2086
# The timeout only stops a hung VM; it is not a speed check (software
# emulation on a loaded machine may take several times the usual 80 s).
timeout 600 qemu-system-x86_64 $ACCEL -m 768 -smp 2 -display none -monitor none -no-reboot \
    -kernel "$VMLINUZ" -initrd "$W/initramfs.cpio.gz" \
    -append "console=ttyS0 panic=-1 quiet loglevel=3" \
    -serial "file:$W/console.log" -serial "file:$W/data.b64" >"$W/qemu.log" 2>&1
qrc=$?
VMTIME=$(( $(date +%s) - TB ))
if [ ! -s "$W/console.log" ]; then
    grep -qiE "could not|failed|not supported" "$W/qemu.log" 2>/dev/null &&
        skip_all "QEMU could not start a VM here: $(head -1 "$W/qemu.log")"
    die "the VM printed nothing (qemu exit $qrc)" "$W/qemu.log"
fi
grep '^GRIPVM' "$W/console.log" | sed 's/^/# /'
grep -q 'GRIPVM: modules: .*vcan' "$W/console.log" && grep -q 'GRIPVM: vcan0 up' "$W/console.log" \
    && tap ok "VM ($(echo "$ACCEL" | awk '{print $2}'), kernel $KVER) loaded can, can-raw, can-dev, vcan and brought vcan0 up" \
    || die "VM did not bring up vcan0" "$W/console.log"

# ---- 6. results ---------------------------------------------------------------------
OUT=$W/out
rm -rf "$OUT"
mkdir -p "$OUT"
sed -n '/==END==/q;p' "$W/data.b64" | tr -d '\r' | base64 -d 2>/dev/null | tar xzf - -C "$OUT" 2>/dev/null
[ -s "$OUT/live.csv" ] && [ -s "$OUT/live.log" ] || die "no results came back from the VM" "$W/console.log"
sed 's/^/# VM: /' "$OUT/replay.err"
[ "$(cat "$OUT/replay.rc" 2>/dev/null)" = 0 ] && tap ok "grip-replay -i vcan0 exited 0" \
    || tap fail "grip-replay -i vcan0 exited $(cat "$OUT/replay.rc" 2>/dev/null)"
"$PY" tests/vm/compare_live.py --bin "$HOSTBIN" --log "$LOG" --out "$OUT" >"$W/compare.txt" 2>&1
crc=$?
grep '^#' "$W/compare.txt"
while IFS= read -r line; do
    case $line in
        "RESULT ok "*) tap ok "${line#RESULT ok }" ;;
        "RESULT fail "*) tap fail "${line#RESULT fail }" ;;
    esac
done <"$W/compare.txt"
[ $crc -eq 0 ] || grep -q '^RESULT fail' "$W/compare.txt" || { tail -20 "$W/compare.txt" | sed 's/^/#   /'; tap fail "compare_live.py crashed"; }
TOTAL=$(( $(date +%s) - T0 ))
# reported, not asserted: timing thresholds do not belong in tests
echo "# VM run ${VMTIME} s (60 s of it is the real-time replay), whole test ${TOTAL} s"
echo "1..$n"
exit $failed
