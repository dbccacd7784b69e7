# Sourced by the daemon e2e scripts (tests/e2e/test_daemon_*.sh): our
# programs under $UWB_EXEC_PREFIX, a scratch directory whose background
# processes are stopped at exit, PASS/FAIL lines, waiting without timing,
# reading JSON and the sockets with our own helpers, and a loopback MQTT
# broker.

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
#   unix_peer ask|console|session|slots ... see unix_peer.c
json_check() { $HOST_PREFIX "$HOST_BUILD/e2e/json_check" "$@"; }
json_get() { $HOST_PREFIX "$HOST_BUILD/e2e/state_check" get "$@"; }
json_edit() { $HOST_PREFIX "$HOST_BUILD/e2e/json_edit" "$@"; }
unix_peer() { $HOST_PREFIX "$HOST_BUILD/e2e/unix_peer" "$@"; }

# ---- a loopback MQTT broker (Debian's mosquitto) ------------------------------
MOSQUITTO=/usr/sbin/mosquitto
# need_mosquitto: skips the script (exit 77) without the broker or mosquitto_passwd.
need_mosquitto() {
    if [[ ! -x $MOSQUITTO ]] || ! command -v mosquitto_passwd > /dev/null; then
        echo "SKIP: no mosquitto broker (make deps installs it)"
        exit 77
    fi
}
# mosquitto_conf PORT PASSWORD_FILE: a broker on 127.0.0.1:PORT for the users
# in PASSWORD_FILE, keeping nothing on disk.
mosquitto_conf() {
    # As root, mosquitto would become user mosquitto, who cannot read $work.
    printf 'listener %s 127.0.0.1\nallow_anonymous false\npassword_file %s\npersistence false\nuser %s\n' \
        "$1" "$2" "$(id -un)"
}
# start_mosquitto NAME CONF_MAKER [ARGS...]: a broker run from the config
# `CONF_MAKER PORT ARGS...` prints (into NAME.conf; its listeners must all
# be on 127.0.0.1), on MOSQUITTO_PORT if set, else on a random port, another
# one when that is taken (5 tries). Each try waits until the broker says it
# listens, MOSQUITTO_WAIT_S (default 10) seconds at most, or until it exits.
# Sets $port, $broker_pid (stopped at exit) and $broker_log (NAME-N.log, N
# counting every try of the script's, so a restart keeps the earlier logs).
start_mosquitto() {
    local name=$1 make_conf=$2 fixed=${MOSQUITTO_PORT:-} try deadline
    shift 2
    for try in 1 2 3 4 5; do
        port=${fixed:-$((20000 + RANDOM % 40000))}
        "$make_conf" "$port" "$@" > "$name.conf"
        grep -q '^listener ' "$name.conf" && ! grep '^listener ' "$name.conf" | grep -qv ' 127\.0\.0\.1$' ||
            fail "$name.conf: every listener must be on 127.0.0.1: $(grep '^listener' "$name.conf")"
        mosquitto_tries=$((${mosquitto_tries:-0} + 1))
        broker_log=$name-$mosquitto_tries.log
        "$MOSQUITTO" -v -c "$name.conf" > "$broker_log" 2>&1 &
        broker_pid=$!
        pids+=($broker_pid)
        deadline=$((SECONDS + ${MOSQUITTO_WAIT_S:-10}))
        while kill -0 "$broker_pid" 2> /dev/null && ((SECONDS <= deadline)); do
            grep -q "listen socket on port $port" "$broker_log" && return 0
            sleep 0.1
        done
        kill "$broker_pid" 2> /dev/null || true
        wait "$broker_pid" 2> /dev/null || true
        [[ -z $fixed ]] || sleep 0.5 # the same port: let its last holder go
    done
    fail "mosquitto ($name) would not start: $(cat "$name"-*.log)"
}
