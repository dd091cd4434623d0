#!/bin/sh
# The bad-input corpus: every case of tests/badinput/cases.tsv, TAP lines.
# Arguments go to run_badinput.py (--bin DIR, --only PROGRAM, case ids).
cd "$(dirname "$0")/../.." || exit 1
PY=.venv/bin/python
[ -x "$PY" ] || PY=python3
exec "$PY" tests/badinput/run_badinput.py "$@"
