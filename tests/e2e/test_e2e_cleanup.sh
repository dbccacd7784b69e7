#!/usr/bin/env bash
# The e2e scripts' cleanup stops what a script started in the background,
# also when it was started through the uwbemu wrapper function (there $! is
# the shell that runs the function): no emulator outlives its test and
# keeps a core busy for the rest of the run.
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-e2e-cleanup

# processes_in DIR: the pids whose working directory is DIR (or was, deleted).
processes_in() {
    local proc cwd
    for proc in /proc/[0-9]*; do
        cwd=$(readlink "$proc/cwd" 2>/dev/null) || continue
        [[ $cwd == "$1" || $cwd == "$1 (deleted)" ]] && echo "${proc#/proc/}"
    done
    return 0
}

(cd "$REPO" && UWB_BUILD_DIR=$BUILD bash -c '
    source tests/e2e/daemon_e2e.sh
    e2e_workdir uwbd-e2e-cleanup-inner
    echo "$work" > "$1/inner-work"
    uwbemu --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock \
        --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" > emu.log 2>&1 &
    pids+=($!)
    wait_for test -S run/digitiser.sock || exit 3
' _ "$work") || fail "the inner script: exit $?"
inner=$(cat inner-work)
[[ ! -d $inner ]] || fail "the inner script's directory $inner is still there"
left=""
for _ in $(seq 20); do
    left=$(processes_in "$inner")
    [[ -z $left ]] && break
    sleep 0.1
done
if [[ -n $left ]]; then
    for pid in $left; do kill "$pid" 2>/dev/null || true; done
    fail "uwbemu outlived its test: pid(s) $left still in $inner"
fi
pass "an emulator started through the uwbemu function is stopped at the script's exit"

echo "$passed passed"
