#!/bin/sh
# shellcheck shell=dash
# Job of the drivers boot: runs every test program /usr/bin/test_* (Unity
# binaries from tests/board/) in turn, each between two marker lines the
# host script parses:
#   BOARD-BEGIN NAME
#   ... Unity output ...
#   BOARD-END NAME status=N
# A test that hangs is killed after UWB_BOARD_TEST_TIMEOUT seconds.
limit=${UWB_BOARD_TEST_TIMEOUT:-120}
for program in /usr/bin/test_*; do
    [ -x "$program" ] || continue
    name=${program##*/}
    echo "BOARD-BEGIN $name"
    timeout -s KILL "$limit" "$program" </dev/null 2>&1
    echo "BOARD-END $name status=$?"
done
