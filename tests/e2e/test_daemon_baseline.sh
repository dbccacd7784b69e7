#!/usr/bin/env bash
# The baseline's life through the full stack (build/uwbemu + build/uwbd):
# one stacking default that makes the sample config decisive on a 12 mm
# rise, and the breaks of issue 17 that concern the baseline, each first
# reproduced here.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-baseline

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$@"; }
# get KEY... < JSON: one line per key (the project's own JSON reader).
get() { "$BUILD/e2e/state_check" get "$@"; }

start_emu() {   # extra uwbemu arguments
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbemu" --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock \
        --control unix:run/emu.sock --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --seed 5 "$@" \
        > emu.log 2>&1 &
    emu_pid=$!
    pids+=($emu_pid)
    wait_for test -S run/emu.sock || fail "uwbemu did not come up"
    wait_for emu status || fail "uwbemu does not answer"
}
stop_emu() { kill -TERM "$emu_pid"; wait "$emu_pid" 2>/dev/null || true; rm -f run/emu.sock; }
start_daemon() {   # log name, extra uwbd arguments
    local log=$1; shift
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" -v "$@" > "$log" 2>&1 &
    daemon_pid=$!
    pids+=($daemon_pid)
    wait_for ctl status || fail "uwbd does not answer ($log)"
}
stop_daemon() {
    kill -TERM "$daemon_pid"
    local rc=0
    wait "$daemon_pid" || rc=$?
    [[ $rc == 0 ]] || fail "uwbd exit $rc at SIGTERM"
}

# ---- one stacking default -----------------------------------------------------
keys_row=$(uwbd --config-keys | grep -F '| `digitiser.stack` |')
default_stack=$(sed 's/.*| `\([0-9]*\)` |.*/\1/' <<< "$keys_row")
[[ $default_stack == 64 ]] || fail "key table: digitiser.stack default '$default_stack': $keys_row"
for sample in "$REPO"/board/*/uwbd.json; do
    [[ $(get digitiser.stack < "$sample") == "$default_stack" ]] ||
        fail "$sample: digitiser.stack $(get digitiser.stack < "$sample"), the key table says $default_stack"
done
grep -qF "$keys_row" "$REPO/board/config.md" || fail "board/config.md's digitiser.stack row is not the key table's"
grep -q "64 pulses stacked per position (\`digitiser.stack\`, whose default 64" "$REPO/README.md" ||
    fail "README does not name the stacking default"

# The sample config as shipped, the emulated board at its scene's 20 dB per pulse.
start_emu
start_daemon uwbd-sample.log
ctl baseline set > /dev/null
ctl scan > sample-base.json || fail "commissioning with the sample config: $(cat sample-base.json)"
[[ $(get status baseline_set < sample-base.json | paste -sd' ') == "edges true" ]] ||
    fail "commissioning with the sample config: $(cat sample-base.json)"
emu 'set displacement_m 0.012' > /dev/null
ctl scan > sample-12.json || fail "12 mm scan: $(cat sample-12.json)"
read -r status shift sigma < <(get status axial_displacement_mm uncertainty_mm < sample-12.json | paste -sd' ')
[[ $status == alarm ]] || fail "the sample config on a 12 mm rise: $(cat sample-12.json)"
awk -v d="$shift" 'BEGIN { exit !(d > 11.5 && d < 12.5) }' || fail "12 mm rise measured $shift mm"
stop_daemon
pass "one stacking default ($default_stack: key table, samples, config.md, README); the sample config" \
     "as shipped on the emulated board: 12 mm rise -> alarm $shift ± $sigma mm"

echo "$passed passed, 0 failed"
