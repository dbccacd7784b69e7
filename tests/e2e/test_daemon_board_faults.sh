#!/usr/bin/env bash
# Hardware faults injected through the emulated board into a running daemon:
# corrupt CRCs, truncated, dropped and missing frames, the link dropping,
# the home switch never seen or stuck. For each: the lost scan becomes an
# `error` verdict with a reason, the log says what happened, the pulser is
# idle and the motor disabled afterwards, the daemon keeps answering, and
# the next scan after the fault is cleared is an ordinary verdict.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-board-faults

ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }

# Short frame time-outs and few retries so a silent digitiser costs seconds,
# not minutes; the carriage starts near home, so a home search that gives up
# after 3 s has time enough when the switch works. Under qemu-user the
# emulated board computes a trace far slower, so the limits are wider. A
# coarse 10 microsteps per mm keeps the step traffic on the emulated GPIO
# link small.
frame_timeout_ms=300 home_timeout_s=3
[[ -n ${UWB_EXEC_PREFIX:-} ]] && { frame_timeout_ms=4000; home_timeout_s=10; }
start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 11 --start-mm 5 --steps-per-mm 10
wait_for emu status || fail "uwbemu does not answer"

${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$REPO/board/emulated/uwbd.json" "${root_flag[@]}" -v \
    --set digitiser.frame_timeout_ms=$frame_timeout_ms --set digitiser.frame_retries=2 \
    --set carriage.home_timeout_s=$home_timeout_s --set carriage.steps_per_mm=10 \
    > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"

ctl baseline set > /dev/null
ctl scan > commission.json || fail "commissioning scan: $(cat commission.json)"
json_check commission.json 'status == edges' 'baseline_set = true' || fail "commissioning scan: $(cat commission.json)"

# The verdict of a scan that must succeed: the winding has not moved.
expect_good_scan() {
    local what=$1 out=$2
    ctl scan > "$out" || fail "$what: scan refused: $(cat "$out")"
    json_check "$out" 'class == VERDICT' 'status == ok' 'axial_displacement_mm ~ 0 0.5' ||
        fail "$what: want an ok verdict within 0.5 mm: $(cat "$out")"
}

# The hardware is safe: trigger low, motor driver disabled.
expect_safe() {
    emu status > emu-status.json
    json_check emu-status.json 'lines.trigger = 0' 'lines.enable = 0' ||
        fail "$1: hardware not left safe: $(cat emu-status.json)"
}

# fault NAME, the words the reason must contain, the log's (extended regular
# expressions, case ignored).
check_fault() {
    local name=$1 reason_re=$2 log_re=$3
    local log_lines_before
    log_lines_before=$(wc -l < uwbd.log)
    emu fault "$name" on > /dev/null || fail "uwbemu refused fault $name"
    set +e; ctl scan > "fault-$name.json"; set -e
    json_check "fault-$name.json" 'class == VERDICT' 'status == error' "reason imatches $reason_re" ||
        fail "fault $name: $(cat "fault-$name.json")"
    tail -n +"$((log_lines_before + 1))" uwbd.log | grep -Eiq "$log_re" ||
        fail "fault $name: no log line matching '$log_re'"
    expect_safe "fault $name"
    kill -0 "$daemon_pid" 2>/dev/null || fail "fault $name: the daemon died"
    ctl status > /dev/null || fail "fault $name: the daemon stopped answering"
    tail -n 1 run/state/verdicts.jsonl | json_check - "status == error" ||
        fail "fault $name: the error verdict is not in verdicts.jsonl"
    emu fault "$name" off > /dev/null
    expect_good_scan "after fault $name cleared" "after-$name.json"
    pass "fault $name: error verdict ($(json_get reason < "fault-$name.json")), hardware safe, next scan ok"
}

# Under qemu-user each scan costs minutes of emulated FFTs: one digitiser
# fault and one home fault stand for the rest there (same code, other CPU).
faults=(crc truncate drop silent disconnect home-never home-stuck)
[[ -n ${UWB_EXEC_PREFIX:-} ]] && faults=(crc home-stuck)
for name in "${faults[@]}"; do
    case $name in
    crc)        check_fault crc        'crc|corrupt'                'crc|corrupt' ;;
    truncate)   check_fault truncate   'truncat|crc|no frame within' 'truncat|crc|no frame within' ;;
    drop)       check_fault drop       'no frame within|sequence|skipped' 'no frame within|sequence|skipped' ;;
    silent)     check_fault silent     'no frame within'            'no frame within' ;;
    disconnect) check_fault disconnect 'closed|disconnect|reset'    'closed|disconnect|reset' ;;
    home-never) check_fault home-never 'home switch (not seen|never closed)' 'home switch (not seen|never closed)' ;;
    home-stuck) check_fault home-stuck 'home switch stays closed'   'home switch stays closed' ;;
    esac
done

# A single bad frame is retried: the scan goes through and the retry counted.
emu fault crc next 1 > /dev/null
expect_good_scan "one corrupt frame" one-crc.json
emu status | json_check - "faults.crc == off" || fail "the one-shot CRC fault was never hit"
pass "one corrupt frame is retried: the scan is an ordinary verdict"

kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 0 ]] || fail "SIGTERM after the faults: exit $rc, want 0"
json_check --each-line run/state/verdicts.jsonl '. is object' || fail "verdicts.jsonl does not parse line by line"
pass "after the faults: clean exit 0, verdicts.jsonl parses line by line"

echo "$passed passed, 0 failed"
