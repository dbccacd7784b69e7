#!/usr/bin/env bash
# Issue 31, finding 10: one progress bar over a whole commissioning.
# `baseline set 3` makes the next cycle acquire three scans; its PROGRESS
# lines say which pass they belong to (pass k of passes) and how far the
# whole is (fraction), rising over all three passes and reaching 1 only at
# the last position of the last one; the time left counts the passes still
# to come (it said "about 0 s left" at the end of each). On a terminal,
# `uwbd ctl scan` draws one bar over the three passes.
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-commissioning-progress

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
start_emulated_board
# Paced (each pass about a second), so that the time left is an estimate of something.
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set scan.time_scale=0.05 -v \
    > uwbd.log 2>&1 &
pids+=($!)
wait_for ctl status || fail "uwbd does not answer: $(tail -5 uwbd.log)"
positions=$(json_get scan.positions < "$config")

# check_passes FILE: the PROGRESS lines of one 3-pass cycle, in order.
check_passes() {
    local file=$1 lines=0 last_fraction=0 last_pass=1 pass passes position n fraction left
    local -a last_left_of_pass=()
    while IFS= read -r line; do
        read -r pass passes position n fraction left < <(printf '%s\n' "$line" |
            json_get pass passes position positions fraction left_s | paste -sd ' ')
        [[ $passes == 3 && $n == "$positions" ]] || fail "$file: want passes 3 of $positions positions: $line"
        (( pass >= last_pass && pass <= 3 )) || fail "$file: pass $pass after pass $last_pass: $line"
        awk -v f="$fraction" -v l="$last_fraction" 'BEGIN { exit !(f >= l && f <= 1) }' ||
            fail "$file: fraction $fraction after $last_fraction: $line"
        if awk -v f="$fraction" 'BEGIN { exit !(f == 1) }'; then
            (( pass == 3 && position == positions )) || fail "$file: full before the end: $line"
        fi
        (( position == positions )) && last_left_of_pass[$pass]=$left
        last_fraction=$fraction last_pass=$pass lines=$((lines + 1))
    done < <(grep '"class":"PROGRESS"' "$file")
    (( lines >= 3 * positions )) || fail "$file: only $lines PROGRESS lines for 3 passes of $positions"
    awk -v f="$last_fraction" 'BEGIN { exit !(f == 1) }' || fail "$file: the last fraction is $last_fraction, not 1"
    for p in 1 2; do
        awk -v l="${last_left_of_pass[$p]:-0}" 'BEGIN { exit !(l > 0) }' ||
            fail "$file: at the end of pass $p of 3, left_s is ${last_left_of_pass[$p]:-missing}, not above 0"
    done
    echo "$lines"
}

# One commissioning, watched twice: `watch progress` takes the PROGRESS lines
# and `uwbd ctl scan` draws its bar, on a terminal when script(1) gives one.
ctl baseline set 3 > set.json
json_check set.json 'class == BASELINE' || fail "baseline set 3: $(cat set.json)"
uwbd ctl --socket run/control.sock watch progress > progress.txt 2> watch.err &
watch_pid=$!
pids+=($watch_pid)
wait_for grep -q WATCH progress.txt || fail "watch progress: no WATCH answer: $(cat watch.err)"
scan_cmd="${UWB_EXEC_PREFIX:-} $BUILD/uwbd ctl --socket run/control.sock --json scan"
if command -v script > /dev/null; then
    script -qec "$scan_cmd" /dev/null > tty.out || fail "ctl scan on a terminal: $(cat -v tty.out)"
    tail -n 1 tty.out | tr -d '\r' > scan.json
else
    $scan_cmd > scan.json 2> /dev/null || fail "ctl scan: $(cat scan.json)"
fi
json_check scan.json 'class == VERDICT' 'baseline_set = true' 'baseline_scans = 3' || fail "commissioning: $(cat scan.json)"
kill "$watch_pid"
wait "$watch_pid" 2> /dev/null || true
lines=$(check_passes progress.txt)
pass "3-pass commissioning: $lines PROGRESS lines, pass 1..3, fraction rising to 1 only at the end, time left at each pass's end"

if [[ -f tty.out ]]; then
    tr '\r' '\n' < tty.out | grep -oE '^\[[#-]{30}\]' | tr -cd '#\n' | awk '{ print length }' > fills.txt
    (( $(wc -l < fills.txt) >= 3 * positions )) || fail "the bar was not drawn at every position: $(cat -v tty.out)"
    sort -n -c fills.txt 2> /dev/null || fail "the bar went back: $(tr '\n' ' ' < fills.txt)"
    [[ $(grep -c '^30$' fills.txt) == 1 && $(tail -n 1 fills.txt) == 30 ]] ||
        fail "the bar was full before the end: $(tr '\n' ' ' < fills.txt)"
    tr '\r' '\n' < tty.out | grep -q "pass 3 of 3, $positions/$positions positions" ||
        fail "the bar does not say which pass: $(cat -v tty.out)"
    pass "ctl scan on a terminal: one bar over 3 passes ($(wc -l < fills.txt) draws), full only at the end"
fi
echo "$passed passed"
