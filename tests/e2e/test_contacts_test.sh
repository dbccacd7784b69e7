#!/usr/bin/env bash
# Issue 31, finding 4: `contacts test [S]`, the point-to-point check with the
# RTU, on the emulated board (uwbemu --site-io). Refused while a scan runs;
# then every contact released for 1 s, and watch, alarm and fault each
# energised alone for S s with 1 s released between, every step logged;
# afterwards the contacts are back where the verdicts put them (an alarm:
# all three energised), although the client that asked was gone long before. A daemon stopped in the middle
# leaves every contact open.
# Issue 43, break 2: during a standing alarm only `contacts test force`; only
# root, the daemon's user and contacts.test_group's members may test (as
# root, a uid 65534 in the control group but not in that group is refused,
# and one in it may); one test per contacts.test_min_interval_s.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-contacts-test

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }
# The three contacts as the board sees them: "watch alarm fault", 1 = energised.
contacts() { emu status | json_get lines.watch lines.alarm lines.fault | paste -sd ' '; }
contacts_are() { [[ $(contacts) == "$1" ]]; } # for wait_for, which runs it anew each time
site=(--set site.asset_id=T3-north --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock)
# As root, the tests of who may run as uid 65534 (setpriv) in the control
# group "users"; the group that may test the contacts is "staff" (both in
# every Debian's base-passwd).
json_edit "$config" "$config" 'contacts={}' || fail "json_edit: a contacts section"
as_member=() as_admin=()
if [[ $(id -u) == 0 ]] && command -v setpriv > /dev/null; then
    as_member=(setpriv --reuid=65534 --regid=65534 --groups=100 --)
    as_admin=(setpriv --reuid=65534 --regid=65534 --groups=100,50 --)
    json_edit "$config" "$config" 'control.group="users"' 'contacts.test_group="staff"' || fail "json_edit: groups"
    chmod o+x "$work" run
fi

start_emulated_board --site-io unix:run/site.sock --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" "${site[@]}" -v > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"
wait_for contacts_are "0 0 1" || fail "at start: contacts $(contacts), want 0 0 1"

# ---- refused while a scan runs -------------------------------------------------
# One connection: `scan` starts the cycle before the next line is read, so
# the test is asked for while the scan runs, whatever the machine's speed.
# That scan becomes the baseline.
printf 'baseline set 1\nscan\ncontacts test 1\n' | unix_peer ask run/control.sock 3 > during-scan.out ||
    fail "scan, then contacts test: $(cat during-scan.out)"
sed -n 2p during-scan.out | json_check - 'class == ERROR' 'message contains scan' ||
    fail "contacts test during a scan: $(cat during-scan.out)"
sed -n 3p during-scan.out | json_check - 'class == VERDICT' 'baseline_set = true' ||
    fail "the scan's verdict: $(cut -c1-300 during-scan.out)"
pass "contacts test refused while a scan runs: $(sed -n 2p during-scan.out | json_get message)"

# An alarm, so that the contacts the verdicts call for (1 1 1, latched)
# differ from every step of the test.
emu "set displacement_m 0.008" > /dev/null
ctl scan > alarm.json 2>/dev/null || fail "alarm scan: $(cut -c1-300 alarm.json)"
json_check alarm.json 'status == alarm' || fail "alarm scan: $(cut -c1-300 alarm.json)"
wait_for contacts_are "1 1 1" || fail "after an alarm: contacts $(contacts), want 1 1 1"

# ---- during the alarm: only on purpose, and only who may ---------------------------
set +e; ctl contacts test 1 > unforced.json; rc=$?; set -e
[[ $rc == 1 ]] && json_check unforced.json 'class == ERROR' 'message contains contacts test force' ||
    fail "contacts test during an alarm, without force: exit $rc, $(cat unforced.json)"
[[ $(contacts) == "1 1 1" ]] || fail "a refused test touched the contacts: $(contacts)"
pass "contacts test during a standing alarm refused without force: $(json_get message < unforced.json)"
if ((${#as_member[@]})); then
    set +e
    "${as_member[@]}" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" ctl --socket run/control.sock contacts test force 1 \
        > member.json 2> member.err
    rc=$?
    set -e
    [[ $rc == 1 ]] && json_check member.json 'class == ERROR' 'message contains uid 65534' \
        'message contains only root' 'message contains "staff"' ||
        fail "a control-group member outside contacts.test_group: exit $rc, $(cat member.json member.err)"
    [[ $(contacts) == "1 1 1" ]] || fail "a refused member's test touched the contacts: $(contacts)"
    pass "a member of the control group, not of contacts.test_group: refused: $(json_get message < member.json)"
fi

# ---- the test: each contact alone, in turn ---------------------------------------
t0=$(date +%s%N)
"${as_admin[@]}" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" ctl --socket run/control.sock contacts test force 1 \
    > test.json || fail "contacts test force: $(cat test.json)"
json_check test.json 'class == CONTACTS_TEST' 'hold_s = 1' 'gap_s = 1' 'duration_s = 6' \
    'sequence.0 == watch' 'sequence.1 == alarm' 'sequence.2 == fault' || fail "contacts test: $(cat test.json)"
# ctl has exited: the client is gone. Every state the board shows, in order,
# until the contacts are back at 1 1 1 (at most 20 s).
seen=()
for _ in $(seq 400); do
    now=$(contacts)
    [[ ${#seen[@]} == 0 || ${seen[-1]} != "$now" ]] && seen+=("$now")
    [[ ${#seen[@]} -gt 1 && $now == "1 1 1" ]] && break
    sleep 0.05
done
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
got=$(printf '%s|' "${seen[@]}")
[[ ${seen[0]} == "1 1 1" ]] || got="1 1 1|$got" # the test may have begun before the first look
[[ $got == "1 1 1|0 0 0|1 0 0|0 0 0|0 1 0|0 0 0|0 0 1|1 1 1|" ]] ||
    fail "contacts during the test (watch alarm fault): $got"
((ms >= 5000)) || fail "the test ended after $ms ms, before its 6 s"
tester=$( ((${#as_admin[@]})) && echo 65534 || id -u)
for step in "contacts test: forced by a control client (uid $tester) while an alarm stands" \
    'watch energised for 1 s' 'alarm energised for 1 s' 'fault energised for 1 s' \
    'contacts test: done; contacts back to watch 1, alarm 1, fault 1'; do
    grep -qF "$step" uwbd.log || fail "not logged: '$step': $(grep 'contacts test' uwbd.log)"
done
got=${got%|}
pass "contacts test force 1 by uid $tester: ${got//|/ -> } in $ms ms, each step logged with the uid, back to" \
     "the alarm's contacts with the client long gone"

# ---- one per contacts.test_min_interval_s (60 s by default) ---------------------------
set +e; ctl contacts test force 5 > soon.json; rc=$?; set -e
[[ $rc == 1 ]] && json_check soon.json 'class == ERROR' 'message contains contacts.test_min_interval_s' ||
    fail "a second contacts test within the interval: exit $rc, $(cat soon.json)"
pass "a second test within the interval: refused: $(json_get message < soon.json)"
# The interval off (a reload), so that a test runs for the checks below.
json_edit "$config" "$config" 'contacts.test_min_interval_s=0' || fail "json_edit: the interval"
kill -HUP "$daemon_pid"
wait_for grep -q "configuration reloaded" uwbd.log || fail "no reload: $(tail -3 uwbd.log)"

# ---- one at a time ----------------------------------------------------------------
ctl contacts test force 5 > long.json || fail "contacts test force 5: $(cat long.json)"
set +e; ctl contacts test force 1 > second.json; rc=$?; set -e
[[ $rc == 1 ]] && json_check second.json 'class == ERROR' 'message contains already' ||
    fail "a second contacts test: exit $rc, $(cat second.json)"
pass "a second contacts test while one runs: refused (exit 1)"

# ---- the daemon stopped in the middle: every contact open ----------------------------
E2E_WAIT_TRIES=50 wait_for contacts_are "1 0 0" || fail "contacts test 5: watch never energised: $(contacts)"
kill "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
[[ $(contacts) == "0 0 0" ]] || fail "SIGTERM during the test: contacts $(contacts), want 0 0 0"
pass "SIGTERM during the test: every contact de-energised (0 0 0)"
echo "$passed passed"
