#!/usr/bin/env bash
# Checks the appliance boot of make test-board.
#
# Reads the guest's console (the BOARD-REPLY lines guest-appliance.sh
# prints) and the emulated board's status taken on the host after the guest
# powered off; prints one PASS or FAIL line per claim, in the style of
# tests/run-tests.sh, and exits with the number of failed claims. The JSON
# is read with the project's own json_check (tests/e2e/helpers), so a board
# host needs no interpreter beyond bash.
#
# Usage: check-appliance.sh HOST_BUILD_DIR CONSOLE_LOG EMU_STATUS_JSON SHIFT_MM POSITIONS STACK
#   HOST_BUILD_DIR holds e2e/json_check and e2e/state_check (make tests).
set -uo pipefail

if [[ $# != 6 ]]; then
    sed -n '2,12p' "$0" >&2
    exit 64
fi
readonly BUILD="$1" CONSOLE="$2" STATUS_JSON="$3" SHIFT_MM="$4" POSITIONS="$5" STACK="$6"
readonly TOLERANCE_MM=0.5
json_check() { "$BUILD/e2e/json_check" "$@"; }
json_get() { "$BUILD/e2e/state_check" get "$@"; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

failed=0
pass() { echo "PASS  board/appliance: $1${2:+  ($2)}"; }
fail() { echo "FAIL  board/appliance: $1: $2"; failed=$((failed + 1)); }

# The last "BOARD-REPLY NAME STATUS TEXT" line for NAME: sets reply_status
# and reply_text; 1 when there is none.
find_reply() {
    local line
    line=$(grep -a "^BOARD-REPLY $1 " "$CONSOLE" | tail -n 1)
    [[ -n $line ]] || return 1
    read -r _ _ reply_status reply_text <<<"$line"
    reply_text=${reply_text%$'\r'}
}

# A reply that must have exit status 0, written as NAME.json; the reason on
# stdout and 1 when not.
json_reply() {
    if ! find_reply "$1"; then
        echo "no '$1' reply on the console (the guest's job stopped before it)"
        return 1
    fi
    if [[ $reply_status != 0 ]]; then
        echo "exit status $reply_status: ${reply_text:0:300}"
        return 1
    fi
    printf '%s\n' "$reply_text" > "$work/$1.json"
}

# Each claim: a PASS line with a note, or a FAIL line with the reason.
claim_daemon_up() {
    local name="daemon starts on the emulated board"
    if find_reply daemon-start && [[ $reply_status == 0 ]]; then
        pass "$name" "aarch64 uwbd answered uwbd ctl on its control socket"
    elif find_reply daemon-start; then
        fail "$name" "$reply_text"
    else
        fail "$name" "no start line"
    fi
}

claim_commissioning() {
    local name="commissioning scan becomes the baseline" why
    why=$(json_reply baseline-set) || { fail "$name" "$why"; return; }
    json_check "$work/baseline-set.json" 'class == BASELINE' 'pending = true' 2>/dev/null ||
        { fail "$name" "$(cat "$work/baseline-set.json")"; return; }
    why=$(json_reply baseline-scan) || { fail "$name" "$why"; return; }
    local v="$work/baseline-scan.json"
    json_check "$v" 'class == VERDICT' 'status == edges' 'baseline_set = true' 2>/dev/null ||
        { fail "$name" "$(cat "$v")"; return; }
    local id lower upper
    { read -r id; read -r lower; read -r upper; } < <(json_get scan_id lower_edge_mm upper_edge_mm < "$v")
    pass "$name" "baseline $id: edges $(printf '%.2f..%.2f' "$lower" "$upper") mm"
}

claim_shift_requested() {
    local name="winding shifted on the emulated board" text="no reply"
    find_reply emu-control && text=$reply_text
    if [[ $text == *'"class":"OK"'* ]]; then
        pass "$name" "uwbemu control over the third UART: set displacement_m $(awk -v mm="$SHIFT_MM" 'BEGIN { print mm / 1000 }')"
    else
        fail "$name" "uwbemu's control endpoint over the UART answered: '$text'"
    fi
}

claim_shifted() {
    local name="shifted scan measures the shift within $TOLERANCE_MM mm" why
    why=$(json_reply shifted-scan) || { fail "$name" "$why"; return; }
    local v="$work/shifted-scan.json" measured uncertainty
    json_check "$v" 'class == VERDICT' 'status == alarm' 2>/dev/null || { fail "$name" "$(cat "$v")"; return; }
    { read -r measured; read -r uncertainty; } < <(json_get axial_displacement_mm uncertainty_mm < "$v")
    json_check "$v" "axial_displacement_mm ~ $SHIFT_MM $TOLERANCE_MM" 2>/dev/null ||
        { fail "$name" "$(printf 'displacement %+.2f mm for an emulated shift of %+.2f mm (tolerance %s mm)' \
              "$measured" "$SHIFT_MM" "$TOLERANCE_MM")"; return; }
    pass "$name" "$(printf 'measured %+.2f ± %.2f mm for %+.2f mm, status alarm' "$measured" "$uncertainty" "$SHIFT_MM")"
}

claim_history() {
    local name="history" why
    why=$(json_reply history) || { fail "$name" "$why"; return; }
    json_check "$work/history.json" 'class == HISTORY' 'verdicts len 2' 'verdicts.0.status == edges' \
        'verdicts.1.status == alarm' 2>/dev/null || { fail "$name" "$(cat "$work/history.json")"; return; }
    pass "$name" "verdicts.jsonl holds both scans"
}

claim_clean_exit() {
    local name="daemon stops cleanly" status=missing
    find_reply daemon-exit && status=$reply_status
    if [[ $status == 0 ]]; then pass "$name" "SIGTERM: exit 0"; else fail "$name" "uwbd exit status $status after SIGTERM"; fi
}

claim_board_state() {
    local name="emulated board saw a full, safe scan cycle" wanted=$((2 * POSITIONS * STACK)) errors
    if ! errors=$(json_check "$STATUS_JSON" 'class == STATUS' 'lines.trigger = 0' 'lines.enable = 0' \
            'steps_while_disabled = 0' "frames_sent >= $wanted" 2>&1); then
        fail "$name" "$(sed 's/^json_check: //' <<<"$errors" | paste -sd ';' -) (want trigger and enable 0, no steps while disabled, >= $wanted frames)"
        return
    fi
    local frames steps
    { read -r frames; read -r steps; } < <(json_get frames_sent steps_counted < "$STATUS_JSON")
    pass "$name" "$frames frames over the UART, $steps steps, pulser idle, motor disabled"
}

claim_daemon_up
claim_commissioning
claim_shift_requested
claim_shifted
claim_history
claim_clean_exit
claim_board_state
exit "$failed"
