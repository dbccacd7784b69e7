# Sourced by the daemon e2e scripts (tests/e2e/test_daemon_*.sh): our
# programs under $UWB_EXEC_PREFIX, a scratch directory whose background
# processes are stopped at exit, PASS/FAIL lines, waiting without timing,
# and reading JSON and the sockets with our own helpers.

BUILD=$(cd "${UWB_BUILD_DIR:?run through tests/run-tests.sh}" && pwd)
REPO=$(pwd)
# Foreground helpers: a function started in the background is a subshell
# running it, so $! would not be the program and the cleanup's kill would
# miss it; programs started in the background are written out in full
# (start_emulated_board below). The wrappers do not exec: a subshell may
# have more to do after them.
uwbd() { ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" "$@"; }
# The emulated board and the scripts' own checkers stand in for hardware and
# the tester: with UWB_HOST_BUILD_DIR (make test-arm) they run natively from
# there, and only the programs under test run under $UWB_EXEC_PREFIX.
if [[ -n ${UWB_HOST_BUILD_DIR:-} ]]; then
    HOST_BUILD=$(cd "$UWB_HOST_BUILD_DIR" && pwd)
    HOST_PREFIX=""
else
    HOST_BUILD=$BUILD
    HOST_PREFIX=${UWB_EXEC_PREFIX:-}
fi
uwbemu() { $HOST_PREFIX "$HOST_BUILD/uwbemu" "$@"; }

# start_emulated_board [UWBEMU ARGS...]: the emulated board in the background
# on run/gpio.sock, run/digitiser.sock and run/emu.sock (its log emu.log),
# stopped at exit; returns once it listens, its pid in $emu_pid.
start_emulated_board() {
    $HOST_PREFIX "$HOST_BUILD/uwbemu" --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock \
        --control unix:run/emu.sock "$@" > emu.log 2>&1 &
    emu_pid=$!
    pids+=($emu_pid)
    wait_for test -S run/emu.sock || fail "uwbemu did not come up"
}

root_flag=()
[[ $(id -u) == 0 ]] && root_flag=(--allow-root)

# e2e_workdir NAME: a fresh /tmp/NAME-XXXXXX as $work and the working
# directory, with run/ in it; the pids added to $pids are stopped and
# reaped, and $work removed, when the script exits.
e2e_workdir() {
    work=$(mktemp -d "/tmp/$1-XXXXXX")
    pids=()
    trap e2e_cleanup EXIT
    cd "$work"
    mkdir run
}
e2e_cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
    rm -rf "$work"
}

passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
fail() {
    echo "FAIL: $*" >&2
    for log in "$work"/*.log; do [[ -f "$log" ]] && { echo "--- $log" >&2; tail -n 20 "$log" >&2; }; done
    exit 1
}
# Wait until a command succeeds, E2E_WAIT_TRIES tenths of a second at most
# (default ~20 s); no timing is asserted.
wait_for() {
    for _ in $(seq "${E2E_WAIT_TRIES:-200}"); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
    return 1
}
# JSON and sockets through the project's own helpers (tests/e2e/helpers/,
# built by make into $BUILD/e2e): a fresh Debian minbase has no Python.
#   json_check FILE 'PATH OP ARG'...   assertions, see json_check.c
#   json_get KEY... < JSON             the values, strings bare
#   json_edit IN OUT 'PATH=JSON' '-PATH'...
#   unix_peer ask|console|slots ...    see unix_peer.c
json_check() { $HOST_PREFIX "$HOST_BUILD/e2e/json_check" "$@"; }
json_get() { $HOST_PREFIX "$HOST_BUILD/e2e/state_check" get "$@"; }
json_edit() { $HOST_PREFIX "$HOST_BUILD/e2e/json_edit" "$@"; }
unix_peer() { $HOST_PREFIX "$HOST_BUILD/e2e/unix_peer" "$@"; }
