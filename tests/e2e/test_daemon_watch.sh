#!/usr/bin/env bash
# Scan progress through the full stack (uwbemu + uwbd): `status` carries
# position k of N and the time left while a scan runs; `watch` streams
# PROGRESS lines with k rising to N and then the VERDICT to the client that
# asked, and to no other; gpsd's ?WATCH form is the same; `uwbd ctl scan`
# prints PROGRESS lines on a stderr that is not a terminal and keeps stdout
# to the one verdict line.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-watch

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }

start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
wait_for uwbemu --ctl unix:run/emu.sock status || fail "uwbemu does not answer"

# Paced so that a scan of 21 positions lasts a few seconds: time to look.
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set scan.time_scale=0.15 -v \
    > uwbd.log 2>&1 &
pids+=($!)
wait_for ctl status || fail "uwbd does not answer on its control socket"
positions=$(json_get scan.positions < "$config")

# ---- the command's forms ------------------------------------------------------
printf 'watch\nwatch off\n?WATCH={"enable":true}\n?WATCH={"enable":false}\n?WATCH={"device":"x"}\nwatch on\n' |
    unix_peer ask run/control.sock 6 > forms.out || fail "watch forms: $(cat forms.out)"
sed -n 1p forms.out | json_check - 'class == WATCH' 'enable = true' 'verdicts = true' || fail "watch: $(cat forms.out)"
sed -n 2p forms.out | json_check - 'class == WATCH' 'enable = false' || fail "watch off: $(sed -n 2p forms.out)"
sed -n 3p forms.out | json_check - 'class == WATCH' 'enable = true' || fail "?WATCH true: $(sed -n 3p forms.out)"
sed -n 4p forms.out | json_check - 'class == WATCH' 'enable = false' || fail "?WATCH false: $(sed -n 4p forms.out)"
sed -n 5p forms.out | json_check - 'class == ERROR' 'message contains ?WATCH' 'message contains enable' ||
    fail "other ?WATCH JSON: $(sed -n 5p forms.out)"
sed -n 5p forms.out | json_check - 'message imatches too long' 2>/dev/null && fail "?WATCH refused as too long"
sed -n 6p forms.out | json_check - 'class == ERROR' 'message contains watch off' || fail "watch on: $(sed -n 6p forms.out)"
pass "watch, watch off, gpsd's ?WATCH={\"enable\":true|false} answered WATCH; other forms refused by name"

# ---- a watcher, a bystander, a status poller, during one scan ---------------
uwbd ctl --socket run/control.sock watch > watch.out 2> watch.err &
watch_pid=$!
pids+=($watch_pid)
wait_for grep -q WATCH watch.out || fail "ctl watch: no WATCH answer: $(cat watch.err)"
# The bystander asks for a scan but not for the stream: its first line after
# STATUS must be the verdict, not a PROGRESS line.
printf 'status\nscan\n' | unix_peer ask run/control.sock 2 > bystander.out &
bystander_pid=$!
pids+=($bystander_pid)
mid_scan() {
    ctl status > mid.json && json_check mid.json 'state == scanning' 'progress.position >= 2' 'progress.left_s exists'
}
wait_for mid_scan || fail "status never showed progress mid-scan: $(cat mid.json)"
json_check mid.json "progress.positions = $positions" 'progress.elapsed_s > 0' 'progress.left_s > 0' ||
    fail "mid-scan status: $(cat mid.json)"
pass "status mid-scan: $(json_get progress.position progress.positions progress.elapsed_s progress.left_s < mid.json | paste -sd ' ' | awk '{printf "position %s of %s, %s s elapsed, %s s left", $1, $2, $3, $4}')"

wait "$bystander_pid" || fail "bystander: $(cat bystander.out)"
sed -n 1p bystander.out | json_check - 'class == STATUS' || fail "bystander line 1: $(cat bystander.out)"
sed -n 2p bystander.out | json_check - 'class == VERDICT' || fail "bystander got a stream it did not ask for: $(cat bystander.out)"
wait_for grep -q '"class":"VERDICT"' watch.out || fail "the watcher got no VERDICT: $(cat watch.out)"
kill "$watch_pid"; wait "$watch_pid" 2>/dev/null || true

last=-1 seen=0 verdict_after=0
while IFS= read -r line; do
    class=$(printf '%s\n' "$line" | json_get class)
    case $class in
    PROGRESS)
        k=$(printf '%s\n' "$line" | json_get position)
        n=$(printf '%s\n' "$line" | json_get positions)
        [[ $n == "$positions" ]] || fail "PROGRESS with positions $n, want $positions: $line"
        (( k > last )) || fail "PROGRESS position $k after $last: $(cat watch.out)"
        last=$k seen=$((seen + 1)) ;;
    VERDICT) (( last == positions )) && verdict_after=1 ;;
    WATCH) ;;
    *) fail "unexpected line in the stream: $line" ;;
    esac
done < watch.out
(( last == positions )) || fail "PROGRESS stopped at $last of $positions: $(cat watch.out)"
(( verdict_after )) || fail "no VERDICT after the last PROGRESS: $(cat watch.out)"
bystander_id=$(sed -n 2p bystander.out | json_get scan_id)
grep '"class":"VERDICT"' watch.out | json_check - "scan_id == $bystander_id" || fail "the watcher's VERDICT is not the scan's"
pass "ctl watch: $seen PROGRESS lines, position rising to $positions of $positions, then the VERDICT; the bystander got none"

# ---- ctl scan: plain PROGRESS lines on a stderr that is not a terminal ------
ctl scan > scan.json 2> scan.err || fail "ctl scan: $(cat scan.err)"
[[ $(wc -l < scan.json) == 1 ]] || fail "ctl scan stdout is not one line: $(cat scan.json)"
json_check scan.json 'class == VERDICT' || fail "ctl scan stdout: $(cat scan.json)"
json_check --each-line scan.err 'class == PROGRESS' || fail "ctl scan stderr: $(cat scan.err)"
tail -n 1 scan.err | json_check - "position = $positions" || fail "ctl scan: last PROGRESS $(tail -n 1 scan.err)"
pass "ctl scan: stdout one VERDICT line, stderr $(wc -l < scan.err) PROGRESS lines ending at $positions of $positions"

# ---- ctl scan on a terminal: a bar redrawn in place (script(1) gives it a pty) --
if command -v script > /dev/null; then
    script -qec "${UWB_EXEC_PREFIX:-} $BUILD/uwbd ctl --socket run/control.sock --json scan" /dev/null > tty.out ||
        fail "ctl scan on a terminal: $(cat tty.out)"
    grep -q "\[#\{30\}\] $positions/$positions positions" tty.out || fail "no full progress bar: $(cat -v tty.out)"
    [[ $(tr '\r' '\n' < tty.out | grep -c 'positions  ') -ge $positions ]] ||
        fail "the bar was not redrawn at every position: $(cat -v tty.out)"
    grep -q '"class":"PROGRESS"' tty.out && fail "PROGRESS lines on a terminal: $(cat -v tty.out)"
    tail -n 1 tty.out | tr -d '\r' | json_check - 'class == VERDICT' || fail "ctl scan on a terminal: last line $(tail -n 1 tty.out)"
    pass "ctl scan on a terminal: a progress bar redrawn with \\r, then the VERDICT line"
fi

# ---- ctl --timeout S watch: the stream ends at the timeout, exit 0 -----------
# It printed the last line again from freed memory when --timeout ended it.
ctl --timeout 1 watch > ended.out 2> ended.err || fail "ctl --timeout 1 watch: exit $?: $(cat ended.err)"
[[ $(wc -l < ended.out) == 1 ]] || fail "ctl --timeout 1 watch: more than the WATCH answer: $(cat -v ended.out)"
json_check ended.out 'class == WATCH' || fail "ctl --timeout 1 watch: $(cat -v ended.out)"
pass "ctl --timeout 1 watch on an idle daemon: the WATCH answer alone, exit 0"

echo "$passed passed"
