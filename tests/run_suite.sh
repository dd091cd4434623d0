#!/bin/sh
# Run cmocka test binaries with TAP output; print their output and keep the
# exit status non-zero if any failed. Usage: run_suite.sh BIN...
# The binaries run SUITE_JOBS at a time (default: the CPUs, at most 4); each
# one's output (stdout and stderr) is kept and printed whole, in the order
# given, so the log reads as a sequential run would.
jobs=${SUITE_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -gt 4 ] && jobs=4
[ "$jobs" -lt 1 ] && jobs=1
tmp=$(mktemp -d "${TMPDIR:-/tmp}/grip-suite.XXXXXX") || exit 2
trap 'rm -rf "$tmp"' EXIT INT TERM
i=0
for bin in "$@"; do
    i=$((i + 1))
    printf '%s %s\n' "$i" "$bin"
done | xargs -P "$jobs" -L 1 sh -c \
    'CMOCKA_MESSAGE_OUTPUT=TAP "$2" >"$0/$1.out" 2>&1; echo $? >"$0/$1.rc"' "$tmp"
status=0
i=0
for bin in "$@"; do
    i=$((i + 1))
    echo "# suite: $bin"
    cat "$tmp/$i.out" 2>/dev/null
    rc=$(cat "$tmp/$i.rc" 2>/dev/null || echo 99)
    if [ "$rc" -ne 0 ]; then
        status=1
        # a crash leaves no "not ok" line: say which binary and how it ended
        grep -q '^not ok ' "$tmp/$i.out" 2>/dev/null || echo "# $bin exited with status $rc"
    fi
done
exit $status
