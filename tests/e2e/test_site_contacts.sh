#!/usr/bin/env bash
# The alarm contacts and the event input on the emulated board (uwbemu
# --site-io): a config that turns them on without the asset id or the
# site's endpoint is refused naming the key; then, through the full stack,
# the contacts' states after each verdict (ok, watch, alarm, ok again, a
# radial alarm, error), after `ack`, and after the daemon is killed; a
# scan started by the event input (debounced, rate-limited) and by the
# `event` command, each verdict saying what triggered it and carrying the
# asset id.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-site

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }
# The three contacts as the board sees them: "watch alarm fault", 1 = energised.
contacts() { emu status | json_get lines.watch lines.alarm lines.fault | paste -sd ' '; }
expect_contacts() {
    local want=$1 when=$2
    wait_for test "$(contacts)" == "$want" || fail "$when: contacts (watch alarm fault) $(contacts), want $want"
}
site=(--set site.asset_id=T3-north --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock
      --set contacts.watch.latch=false --set event.enabled=true --set event.debounce_ms=20
      --set event.min_interval_s=3600 --set prometheus.enabled=true --set prometheus.textfile=run/metrics/uwbd.prom)
# One sample's value from the Prometheus textfile: prom METRIC [LABELS], e.g. prom uwbd_status 'status="alarm"'.
prom() {
    local labels="asset_id=\"T3-north\"${2:+,$2}"
    grep -F "$1{$labels} " run/metrics/uwbd.prom | awk '{print $2}'
}

# ---- refused before anything opens ------------------------------------------
check() { uwbd --check-config "$config" "$@" > check.out 2>&1 && echo 0 || echo $?; }
[[ $(check --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock) == 78 ]] &&
    grep -q 'key `site.asset_id`: missing: required once an integration is on' check.out ||
    fail "contacts without an asset id: $(cat check.out)"
[[ $(check --set site.asset_id=T1 --set event.enabled=true) == 78 ]] && grep -q 'key `gpio.site_endpoint`: missing' check.out ||
    fail "event input without the site's endpoint: $(cat check.out)"
[[ $(check "${site[@]}") == 0 ]] || fail "the site's config refused: $(cat check.out)"
pass "--check-config: an integration without the asset id or its endpoint refused (exit 78) naming the key"

mkdir run/metrics
start_emulated_board --site-io unix:run/site.sock --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
[[ $(contacts) == "0 0 0" ]] || fail "contacts before uwbd: $(contacts)"

start_daemon() {
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" "${site[@]}" \
        --set carriage.home_timeout_s=5 -v > "$1" 2>&1 &
    daemon_pid=$!
    pids+=($daemon_pid)
    wait_for ctl status || fail "uwbd does not answer on its control socket"
}
start_daemon uwbd.log
expect_contacts "0 0 1" "after start"
pass "at start: watch and alarm open, fault energised (healthy)"

# ---- the contacts after each verdict ------------------------------------------
scan_expect() {   # DISPLACEMENT_M STATUS CONTACTS FILE
    emu "set displacement_m $1" > /dev/null
    ctl scan > "$4" 2>/dev/null || fail "scan: $(cat "$4")"
    json_check "$4" 'class == VERDICT' "status == $2" 'trigger == command' 'asset_id == T3-north' ||
        fail "scan for $2: $(cut -c1-300 "$4")"
    expect_contacts "$3" "after a $2 verdict"
}
ctl baseline set 1 > /dev/null
ctl scan > base.json 2>/dev/null || fail "baseline scan: $(cat base.json)"
json_check base.json 'baseline_set = true' 'asset_id == T3-north' 'trigger == command' || fail "baseline: $(cut -c1-300 base.json)"
expect_contacts "0 0 1" "after the baseline"
scan_expect 0.003 watch "1 0 1" watch.json
scan_expect 0.008 alarm "1 1 1" alarm.json
scan_expect 0 ok "0 1 1" ok.json
pass "after watch 1 0 1, alarm 1 1 1, ok 0 1 1 (alarm latched, watch set not to latch); verdicts carry asset_id and trigger"

# The textfile after those four verdicts (baseline edges, watch, alarm, ok).
[[ $(prom uwbd_status 'status="ok"') == 1 && $(prom uwbd_status 'status="alarm"') == 0 ]] ||
    fail "textfile status: $(cat run/metrics/uwbd.prom)"
[[ $(prom uwbd_verdicts_total 'status="watch"') == 1 && $(prom uwbd_verdicts_total 'status="alarm"') == 1 &&
   $(prom uwbd_verdicts_total 'status="edges"') == 1 ]] || fail "textfile counters: $(cat run/metrics/uwbd.prom)"
want_m=$(awk -v mm="$(json_get axial_displacement_mm < ok.json)" 'BEGIN {printf "%.9g", mm / 1000}')
[[ $(prom uwbd_axial_displacement_meters) == "$want_m" ]] ||
    fail "textfile displacement $(prom uwbd_axial_displacement_meters), verdict $want_m m"
[[ $(prom uwbd_scan_duration_seconds | awk '$1 > 0 {print "yes"}') == yes ]] ||
    fail "no scan duration in the textfile: $(cat run/metrics/uwbd.prom)"
[[ $(prom uwbd_contact_energised 'contact="alarm"') == 1 ]] || fail "textfile contacts: $(cat run/metrics/uwbd.prom)"
[[ $(stat -c %a run/metrics/uwbd.prom) == 644 ]] || fail "textfile mode $(stat -c %a run/metrics/uwbd.prom)"
ls -a run/metrics | grep -q uwbd-tmp && fail "a temporary left in the textfile directory"
pass "prometheus textfile: status, counters by status, displacement in metres ($want_m), scan duration, contacts; mode 644"

ctl ack > ack.json || fail "ack: $(cat ack.json)"
json_check ack.json 'class == ACK' 'contacts.alarm = false' 'contacts.watch = false' 'contacts.fault = true' ||
    fail "ack: $(cat ack.json)"
expect_contacts "0 0 1" "after ack"
[[ $(prom uwbd_contact_energised 'contact="alarm"') == 0 ]] || fail "the textfile after ack: $(cat run/metrics/uwbd.prom)"
printf 'ack\n' | unix_peer ask run/control.sock 1 > ack2.out
json_check ack2.out 'class == ACK' || fail "a second ack: $(cat ack2.out)"
pass "ack: the latched alarm contact released (0 0 1)"

# A radial alarm drives the alarm contact as an axial one does: disks 4-6
# bulged 8 mm toward the antennas, the winding not moved. The verdict's
# status is the radial one; the axial figure, withheld or given, is no alarm.
emu "set radial 4 6 8" > /dev/null
ctl scan > radial.json 2>/dev/null || fail "radial scan: $(cat radial.json)"
json_check radial.json 'status == alarm' 'radial.status == alarm' 'radial.max_change_mm exists' 'reason contains radial' ||
    fail "a bulge of disks 4-6 by 8 mm: $(cut -c1-400 radial.json)"
axial=$(json_get axial_displacement_mm < radial.json)
[[ $axial == "(missing)" ]] || awk -v a="$axial" 'BEGIN { exit !(a < 5 && a > -5) }' ||
    fail "the axial figure is an alarm by itself ($axial mm): the contact would prove nothing"
expect_contacts "1 1 1" "after a radial alarm"
[[ $(prom uwbd_contact_energised 'contact="alarm"') == 1 && $(prom uwbd_radial_status 'status="alarm"') == 1 ]] ||
    fail "textfile after the radial alarm: $(cat run/metrics/uwbd.prom)"
want_m=$(awk -v mm="$(json_get radial.max_change_mm < radial.json)" 'BEGIN {printf "%.9g", mm / 1000}')
[[ $(prom uwbd_radial_max_change_meters) == "$want_m" ]] ||
    fail "textfile radial change $(prom uwbd_radial_max_change_meters), verdict $want_m m"
emu "set radial 4 6 0" > /dev/null
scan_expect 0 ok "0 1 1" radial-undone.json
pass "a radial alarm (radial $(json_get radial.max_change_mm < radial.json) mm, axial $axial mm) energises" \
     "the alarm contact (1 1 1); the textfile says radial alarm, $want_m m; undone, ok latched"

# Issue 43, break 1: the latch nobody acknowledged and the error after it
# survive a restart: alarm held, fault open (the latest verdict is an error).
emu fault home-stuck on > /dev/null
ctl scan > error.json 2>/dev/null || true
json_check error.json 'status == error' || fail "home-stuck: $(cut -c1-300 error.json)"
expect_contacts "0 1 0" "after an error verdict, the alarm latched"
emu fault home-stuck off > /dev/null
kill "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
start_daemon uwbd.log # anew: the checks below read what this start logs
expect_contacts "0 1 0" "after a restart with the alarm latched and an error recorded"
[[ -f run/state/contacts-latch.json ]] || fail "no latch kept in the state directory: $(ls run/state)"
ctl status > restarted.json
json_check restarted.json 'contacts.alarm = true' 'contacts.fault = false' || fail "status after the restart: $(cat restarted.json)"
pass "restart (SIGTERM) after an alarm, ok and an error, no ack: alarm held, fault open (0 1 0), status says so"
ctl ack > /dev/null
expect_contacts "0 0 0" "after ack, the latest verdict an error"
pass "ack after the restart releases the latch; the fault stays open while the latest verdict is an error"
emu "set displacement_m 0.008" > /dev/null
ctl scan > alarm2.json 2>/dev/null
json_check alarm2.json 'status == alarm' || fail "alarm after the fault: $(cut -c1-300 alarm2.json)"
expect_contacts "1 1 1" "after the fault cleared and an alarm"
pass "an error verdict opens the fault contact; the next scan closes it again"

# ---- the event input and the event command ------------------------------------
last_id=$(json_get scan_id < alarm2.json)
new_verdict() { ctl verdict > latest.json && ! json_check latest.json "scan_id == $last_id" 2>/dev/null; }
emu input event 1 > /dev/null || fail "uwbemu: input event 1"
wait_for new_verdict || fail "no scan after the event input: $(grep -i event uwbd.log | tail -3)"
json_check latest.json 'trigger == event' 'asset_id == T3-north' || fail "event verdict: $(cut -c1-300 latest.json)"
grep -q 'event input: active for 20 ms' uwbd.log || fail "the event is not logged"
last_id=$(json_get scan_id < latest.json)
# A reclose: open, then closed again. The daemon reads the input every 10 ms;
# each round leaves it open long enough to be seen, a few rounds at most.
reclose() {
    emu input event 0 > /dev/null && sleep 0.1 && emu input event 1 > /dev/null && sleep 0.1 &&
        grep -q 'within event.min_interval_s' uwbd.log
}
E2E_WAIT_TRIES=20 wait_for reclose || fail "a second event inside the interval was not dropped"
emu input event 0 > /dev/null
ctl status > idle.json
json_check idle.json 'state == idle' || fail "a scan runs after a dropped event: $(cat idle.json)"
new_verdict && fail "a dropped event made a verdict"
pass "event input: a scan with \"trigger\": \"event\"; a second within event.min_interval_s dropped and logged"

ctl event > event.json || fail "event: $(cat event.json)"
json_check event.json 'class == EVENT' 'scan == started' || fail "event: $(cat event.json)"
wait_for new_verdict || fail "no scan after the event command"
json_check latest.json 'trigger == event' || fail "event command verdict: $(cut -c1-300 latest.json)"
[[ $(prom uwbd_event_scans_total) == 2 ]] || fail "event scans in the textfile: $(prom uwbd_event_scans_total)"
pass "the event command: EVENT reply, a scan whose verdict says \"trigger\": \"event\""

# ---- the daemon killed, then started again -------------------------------------
expect_contacts "1 1 1" "before the kill"
kill -9 "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
expect_contacts "0 0 0" "after kill -9"
pass "kill -9: every contact de-energised, the fault contact open (fail-safe)"
# This start reads the site's endpoint from the file, so a reload can change it.
json_edit "$config" "$config" 'gpio.site_endpoint="unix:run/site.sock"' || fail "json_edit: the site endpoint"
site=("${site[@]/#gpio.site_endpoint=*/site.asset_id=T3-north}")
start_daemon uwbd2.log
expect_contacts "1 1 1" "after a restart with an alarm recorded"
pass "restart: the recorded alarm comes back (1 1 1)"

# A reload whose site lines cannot be opened: the contacts are off, and
# `ack` says so instead of acknowledging contacts it cannot drive.
json_edit "$config" "$config" 'gpio.site_endpoint="unix:run/no-such-board.sock"' || fail "json_edit: a bad endpoint"
kill -HUP "$daemon_pid"
wait_for grep -q "reload: the site's lines" uwbd2.log || fail "the reload did not report the site's lines: $(tail -3 uwbd2.log)"
expect_contacts "0 0 0" "after a reload that lost the site's lines"
set +e; ctl ack > ack-off.json 2>&1; rc=$?; set -e
[[ $rc == 1 ]] && grep -q "alarm contacts" ack-off.json ||
    fail "ack with the site's lines off: exit $rc, $(cat ack-off.json)"
pass "a reload that cannot open the site's lines: contacts off (0 0 0), ack refused (exit 1)"
kill "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
expect_contacts "0 0 0" "after SIGTERM"
pass "SIGTERM: a stopped daemon opens every contact"

echo "$passed passed"
