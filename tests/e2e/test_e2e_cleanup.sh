#!/usr/bin/env bash
# The e2e scripts' cleanup stops what a script started in the background
# with the helpers (start_emulated_board): no emulator outlives its test
# and keeps a core busy for the rest of the run. (Started as 'uwbemu ... &'
# through the wrapper function, $! was the shell running it, and three
# scripts left their emulators running.)
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
    start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json"
    [[ -n $emu_pid ]] || exit 3
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
pass "an emulator started by start_emulated_board is stopped at the script's exit"

echo "$passed passed"
