#!/bin/sh
# Run cmocka test binaries with TAP output; print their output and keep the
# exit status non-zero if any failed. Usage: run_suite.sh BIN...
status=0
for bin in "$@"; do
    echo "# suite: $bin"
    CMOCKA_MESSAGE_OUTPUT=TAP "$bin" || status=1
done
exit $status
