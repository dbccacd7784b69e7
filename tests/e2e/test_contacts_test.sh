#!/usr/bin/env bash
# Issue 31, finding 4: `contacts test [S]`, the point-to-point check with the
# RTU, on the emulated board (uwbemu --site-io). Refused while a scan runs;
# then every contact released for 1 s, and watch, alarm and fault each
# energised alone for S s with 1 s released between, every step logged;
# afterwards the contacts are back where the verdicts put them (an alarm:
# all three energised), although the client that asked was gone long before. A daemon stopped in the middle
# leaves every contact open.
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

# ---- the test: each contact alone, in turn ---------------------------------------
t0=$(date +%s%N)
ctl contacts test 1 > test.json || fail "contacts test: $(cat test.json)"
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
for step in 'watch energised for 1 s' 'alarm energised for 1 s' 'fault energised for 1 s' \
    'contacts test: done; contacts back to watch 1, alarm 1, fault 1'; do
    grep -qF "$step" uwbd.log || fail "not logged: '$step': $(grep 'contacts test' uwbd.log)"
done
got=${got%|}
pass "contacts test 1: ${got//|/ -> } in $ms ms, each step logged, back to the alarm's contacts with the client long gone"

# ---- one at a time ----------------------------------------------------------------
ctl contacts test 5 > long.json || fail "contacts test 5: $(cat long.json)"
set +e; ctl contacts test 1 > second.json; rc=$?; set -e
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
