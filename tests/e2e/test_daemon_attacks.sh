#!/usr/bin/env bash
# Attacks and accidents of issue 17 against the running daemon on the
# emulated board, with tests/e2e/helpers/ctl_attack.c for hostile clients:
#   - --check-config refuses state_dir / or a system directory, and a
#     control.group that does not exist (breaks 1 and 9);
#   - a state directory holding files that are not uwbd's: only uwbd's own
#     temporary is removed at start, the rest named in a warning (break 1);
#   - 16 clients each sending one byte every 0.9 s (never a whole line):
#     a fresh `status` is still answered (before: nobody got in for 20 s),
#     and the tricklers are dropped after CLIENT_LINE_TIMEOUT_S (5 s);
#   - 15 clients sending `help` x400 and never reading: a fresh `status` is
#     answered at once (before: 24 s) and SIGTERM is prompt (break 6);
#   - `scan\nscan\n` on one connection: two answers (a refusal for the
#     second, then the verdict), not one (break 9);
#   - steps lost on the way up: an `error` verdict "steps lost", and the
#     next scan re-homes and is ordinary (break 8);
#   - a SIGHUP reload whose rig cannot be reached is refused whole (the log
#     said both "cannot connect" and "reloaded") (break 9);
#   - a corrupt latest.json: `verdict` falls back to verdicts.jsonl (break 9);
#   - issue 27, break 7 (as root): 15 connections of one control-group
#     member re-sending `scan` after each verdict: another member's
#     `status` is still answered, that user holds at most 8 slots, and its
#     scans are rate-limited with the time of the next one named.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-attacks

ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }
attack() { $HOST_PREFIX "$HOST_BUILD/e2e/ctl_attack" "$@"; }
get() { $HOST_PREFIX "$HOST_BUILD/e2e/state_check" get "$@"; }

start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 11 --start-mm 5 --steps-per-mm 10
# Break 1 and 9 at the command line: --check-config refuses a state_dir
# that is / or a system directory, and a control.group that does not exist.
cp "$REPO/board/emulated/uwbd.json" uwbd.json
for bad in "state_dir=/:is a system directory" "state_dir=/var/lib/:is /var/lib" \
           "control.group=uwbd-no-such-group-17:no group named"; do
    set +e; uwbd --check-config uwbd.json --set "${bad%%:*}" > /dev/null 2> check.err; rc=$?; set -e
    [[ $rc == 78 ]] || fail "--check-config --set ${bad%%:*}: exit $rc, want 78"
    grep -q "${bad#*:}" check.err || fail "--check-config --set ${bad%%:*}: $(cat check.err)"
done
pass "--check-config refuses state_dir / and /var/lib/, and a control.group that does not exist (exit 78)"

# Break 1: a state directory holding files that are not uwbd's: only uwbd's
# own temporary goes at start; the others are named in a warning and kept.
mkdir -p run/state/home/alice run/state/baseline run/state/archive/2026/01/01
for f in home/alice/.bashrc.backup baseline/.current.uwbscan.zzzzzz archive/2026/01/01/.scan.json.Ab12Cd \
         .uwbd-tmp.latest.json.Ab12Cd.part; do echo "someone's" > "run/state/$f"; done
ln -s /etc run/state/archive/2026/01/02
# As root the socket goes to group nogroup, so that ctl_attack scanhold can
# act as two unprivileged control-group members (reaching run/ through this
# work directory, hence its o+x).
group_flag=()
if [[ $(id -u) == 0 ]]; then group_flag=(--set control.group='"nogroup"'); chmod o+x "$work"; fi
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config uwbd.json "${root_flag[@]}" "${group_flag[@]}" -v \
    --set carriage.steps_per_mm=10 > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"

for f in home/alice/.bashrc.backup baseline/.current.uwbscan.zzzzzz archive/2026/01/01/.scan.json.Ab12Cd; do
    [[ -f run/state/$f ]] || fail "start-up cleanup deleted run/state/$f"
done
[[ ! -e run/state/.uwbd-tmp.latest.json.Ab12Cd.part ]] || fail "uwbd's own leftover temporary was kept"
grep -q "removed 1 leftover" uwbd.log || fail "no log line for the removed temporary"
for f in baseline/.current.uwbscan.zzzzzz archive/2026/01/01/.scan.json.Ab12Cd; do
    grep -q "$f is a hidden file, not uwbd's: left alone" uwbd.log || fail "no warning naming $f"
done
grep -q "archive/2026/01/02 is a symbolic link, not uwbd's: left alone" uwbd.log || fail "no warning for the symlink"
grep -q "bashrc" uwbd.log && fail "looked outside the directories uwbd writes"
pass "start-up cleanup: only uwbd's own temporary removed; foreign hidden files and a symlink named and kept"

attack trickle run/control.sock 16 8 > trickle.out || fail "trickling clients locked out status: $(cat trickle.out)"
grep -q "trickling clients dropped: 16 of 16" trickle.out || fail "tricklers kept their slots: $(cat trickle.out)"
grep -q "no complete command line in time" uwbd.log || fail "no log line for a dropped trickler"
pass "16 trickling clients: $(head -n 1 trickle.out), all 16 dropped"

attack noread run/control.sock 15 400 > noread.out || fail "clients that never read stalled the loop: $(cat noread.out)"
pass "15 clients that never read: $(cat noread.out)"

# The 15 non-readers' slots are freed when the daemon's loop sees them close;
# on a loaded machine that can come after this connect (a refusal naming the
# full table), so wait for a slot, bounded.
for try in $(seq 50); do
    rc=0
    attack send run/control.sock 'scan\nscan\n' 2 120 > pipeline.out 2> pipeline.err || rc=$?
    grep -q "too many control clients" pipeline.out pipeline.err || break
    sleep 0.2
done
[[ $rc == 0 ]] || fail "scan\\nscan\\n on one connection: not two answers: $(cat pipeline.out pipeline.err)"
[[ $(sed -n 1p pipeline.out | get class) == ERROR ]] || fail "second scan not refused first: $(cat pipeline.out)"
sed -n 1p pipeline.out | get message | grep -q "already pending on this connection" ||
    fail "refusal does not say why: $(cat pipeline.out)"
[[ $(sed -n 2p pipeline.out | get class) == VERDICT ]] || fail "no verdict for the first scan: $(cat pipeline.out)"
pass "scan\\nscan\\n on one connection: a refusal for the second, then the first one's verdict"

# Issue 27, break 7: one control-group member's 15 connections re-sending
# `scan` after each verdict held every ordinary slot (scan waiters are never
# evicted): 21 scan cycles in 25 s, and other members were turned away.
if [[ $(id -u) == 0 ]]; then
    attack scanhold run/control.sock 15 8 > scanhold.out 2> scanhold.err ||
        fail "a member's scan re-senders locked another member out: $(cat scanhold.out scanhold.err)"
    held=$(sed -n 's/^attacker: \([0-9]*\) of 15 connections held, \([0-9]*\) verdicts.*/\1 \2/p' scanhold.out)
    [[ -n $held ]] || fail "no attacker summary: $(cat scanhold.out scanhold.err)"
    (( ${held% *} <= 8 )) || fail "one user held ${held% *} control slots: $(cat scanhold.out)"
    (( ${held#* } <= 2 )) || fail "one user's scans were not rate-limited: $(cat scanhold.out)"
    grep -q "first refusal: .*the next is allowed in" scanhold.out || fail "scan refusal names no time: $(cat scanhold.out)"
    pass "15 scan re-senders of one member: $(tr '\n' ' ' < scanhold.out | cut -c1-300)"
else
    pass "scan re-senders of one member locking out another: skipped, not root"
fi

# Issue 17, break 8: steps lost on the way up (the emulated belt slips on
# every 50th upward step: 12 mm over the 600 mm travel) put every trace
# elsewhere than recorded; the home switch after the last position must
# agree with the counted steps, else the scan is an `error` verdict.
emu fault lose-steps every 50 > /dev/null || fail "uwbemu refused the lose-steps fault"
set +e; ctl scan > lost.json; set -e
[[ $(get class status < lost.json | tr '\n' ' ') == "VERDICT error " ]] || fail "lost steps: not an error verdict: $(cat lost.json)"
get reason < lost.json | grep -Eq "steps lost: [0-9.]+ mm" || fail "lost steps: reason: $(get reason < lost.json)"
[[ $(emu status | get steps_lost) != 0 ]] || fail "the emulated board lost no steps"
emu fault lose-steps off > /dev/null
ctl scan > after-lost.json || fail "scan after the lost steps: $(cat after-lost.json)"
[[ $(get status < after-lost.json) != error ]] || fail "the next scan did not recover: $(cat after-lost.json)"
pass "lost steps: error verdict ($(get reason < lost.json)); the next scan re-homes: $(get status < after-lost.json)"

# Issue 17, break 9: a reload whose rig cannot be reached is refused whole:
# the log never says both "cannot connect" and "reloaded", and the running
# rig still scans.
sed 's|unix:run/digitiser.sock|unix:run/nowhere.sock|' uwbd.json > uwbd.json.new && mv uwbd.json.new uwbd.json
log_before=$(wc -l < uwbd.log)
kill -HUP "$daemon_pid"
wait_for grep -q "reload refused" uwbd.log || fail "a reload with an unreachable rig was not refused"
tail -n +"$((log_before + 1))" uwbd.log > reload.log
grep -q "configuration reloaded" reload.log && fail "the log says both: $(cat reload.log)"
ctl scan > after-reload.json || fail "scan after the refused reload: $(cat after-reload.json)"
[[ $(get status < after-reload.json) != error ]] || fail "the running rig did not survive: $(cat after-reload.json)"
pass "reload with an unreachable rig: $(grep -o 'reload refused.*' reload.log | cut -c1-90)...; scans go on"

attack noread run/control.sock 15 400 > /dev/null || true
t0=$(date +%s%N)
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
[[ $rc == 0 ]] || fail "SIGTERM with clients that never read: exit $rc"
(( ms < 3000 )) || fail "SIGTERM with clients that never read took $ms ms"
pass "SIGTERM with 15 clients that never read: exit 0 in $ms ms"

# Issue 17, break 9: after a corrupt latest.json, `verdict` falls back to
# the newest line of verdicts.jsonl instead of "no scan has been recorded".
cp "$REPO/board/emulated/uwbd.json" uwbd.json
printf '{"class":"VERDICT","status":' > run/state/latest.json
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config uwbd.json "${root_flag[@]}" -v --set carriage.steps_per_mm=10 \
    > uwbd-restart.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd did not come back"
ctl verdict > fallback.json || fail "verdict after a corrupt latest.json: $(cat fallback.json)"
[[ $(get class scan_id < fallback.json | tr '\n' ' ') == "VERDICT $(tail -n 1 run/state/verdicts.jsonl | get scan_id) " ]] ||
    fail "verdict is not the newest history line: $(cat fallback.json)"
grep -q "taken from verdicts.jsonl" uwbd-restart.log || fail "no warning about the corrupt latest.json"
kill -TERM "$daemon_pid"
wait "$daemon_pid" || fail "SIGTERM after the restart: exit $?"
pass "corrupt latest.json: verdict falls back to verdicts.jsonl ($(get scan_id < fallback.json))"

echo "$passed passed, 0 failed"
