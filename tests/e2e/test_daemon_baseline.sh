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
get() { json_get "$@"; }

start_emu() {   # extra uwbemu arguments
    start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --seed 5 "$@"
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
grep -q "64 pulses stacked per position (\`digitiser.stack\`, whose default 64" "$REPO/tests/accuracy.md" ||
    fail "tests/accuracy.md does not name the stacking default"

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
pass "one stacking default ($default_stack: key table, samples, config.md, tests/accuracy.md); the sample config" \
     "as shipped on the emulated board: 12 mm rise -> alarm $shift ± $sigma mm"

# ---- decisive when the data allows: acquire again within the budget -----------------
# A baseline of 4 pulses per position, then scans of one pulse at 20 dB: the
# 4 mm rise's sigma is over the 1 mm limit and its 95 % interval reaches
# across both status limits (a 12 mm rise's lies wholly past the alarm
# limit, so it is given at any sigma: issue 44), and acquiring again brings
# the current scan's share down (with 4 pulses the displacement's sigma,
# about 0.8 mm, is already under the limit; with a one-pulse baseline the
# baseline's own share is over it and no re-acquisition of the current scan
# can help).
emu 'set displacement_m 0' > /dev/null
few_stack=1
few=(--state-dir run/state3 --set digitiser.stack=$few_stack --set baseline.scans=1)
start_daemon uwbd-few0.log --state-dir run/state3 --set digitiser.stack=4 --set baseline.scans=1 \
    --set analysis.reacquire_budget_s=0
ctl baseline set > /dev/null
ctl scan > few-base.json
[[ $(get baseline_set < few-base.json) == true ]] || fail "commissioning with 4 pulses: $(cat few-base.json)"
stop_daemon
start_daemon uwbd-few.log "${few[@]}" --set analysis.reacquire_budget_s=0
emu 'set displacement_m 0.004' > /dev/null
ctl scan > few-nobudget.json
[[ $(get status acquisitions < few-nobudget.json | paste -sd' ') == "inconclusive 1" ]] ||
    fail "$few_stack pulse(s), no budget: $(cat few-nobudget.json)"
stop_daemon
start_daemon uwbd-few2.log "${few[@]}"
ctl scan > few-budget.json
read -r status acq pulses shift sigma < <(get status acquisitions pulses_per_position axial_displacement_mm \
                                             uncertainty_mm < few-budget.json | paste -sd' ')
[[ ($status == watch || $status == alarm) && $acq -ge 2 && $pulses == $((few_stack * acq)) ]] ||
    fail "$few_stack pulse(s) with the default budget: $(cat few-budget.json)"
awk -v s="$sigma" 'BEGIN { exit !(s <= 1.0) }' || fail "uncertainty $sigma mm after acquiring again"
stop_daemon
pass "uncertainty over the limit: without a budget inconclusive ($(get reason < few-nobudget.json));" \
     "with it $acq acquisitions, $pulses pulses per position: $status $shift ± $sigma mm"

# ---- a baseline from several scans ---------------------------------------------------
emu 'set displacement_m 0' > /dev/null
# `baseline set 3` on the serial console (a unix endpoint the daemon connects to).
rm -f run/console.go
$HOST_PREFIX "$HOST_BUILD/e2e/unix_peer" session run/console.sock run/console.go console.out \
    "baseline set 3" scan > console.log 2>&1 &
console_pid=$!
pids+=($console_pid)
wait_for test -S run/console.sock || fail "console listener did not come up"
start_daemon uwbd-n.log --state-dir run/state4 --set digitiser.stack=4 --set baseline.scans=2 \
    --console unix:run/console.sock
touch run/console.go
wait "$console_pid" || fail "console peer: $(cat console.log)"
[[ $(sed -n 1p console.out) == "the next good scan becomes the baseline" ]] ||
    fail "console baseline set 3: $(cat console.out)"
grep -q '^status EDGES: .*became the baseline: yes$' console.out || fail "console scan: $(cat console.out)"
ctl verdict > n-base.json
read -r set scans acq pulses rep < <(get baseline_set baseline_scans acquisitions pulses_per_position \
                                         baseline_repeatability_mm < n-base.json | paste -sd' ')
[[ $set == true && $scans == 3 && $acq == 3 && $pulses == 12 && $rep != "(missing)" ]] ||
    fail "baseline set 3: $(cat n-base.json)"
[[ $(get scans repeatability_mm < run/state4/baseline/current.json | paste -sd' ') == "3 $rep" ]] ||
    fail "current.json: $(cat run/state4/baseline/current.json)"
[[ $(ctl status | get baseline.scans baseline.repeatability_mm | paste -sd' ') == "3 $rep" ]] ||
    fail "status does not show the baseline's scans and repeatability"
ctl scan > n-next.json
read -r status sigma < <(get status uncertainty_mm < n-next.json | paste -sd' ')
awk -v s="$sigma" -v r="$rep" 'BEGIN { exit !(s >= r / sqrt(3) - 0.005) }' ||
    fail "the verdict's uncertainty $sigma mm leaves out the baseline's repeatability $rep mm / sqrt(3)"
# `baseline set` without N takes baseline.scans (2 here).
ctl baseline set > /dev/null
ctl scan > n-default.json
[[ $(get baseline_set baseline_scans < n-default.json | paste -sd' ') == "true 2" ]] ||
    fail "baseline set without N: $(cat n-default.json)"
stop_daemon
pass "baseline set 3 (console): 3 scans averaged (12 pulses per position), repeatability $rep mm recorded in" \
     "current.json and status; next verdict ± $sigma mm includes it; without N, baseline.scans"

# ---- the baseline watched, recoverable by the operator -------------------------
# Quicker settings from here on: 40 dB per pulse, 4 pulses, one scan per baseline.
stop_emu
start_emu --set snr_db=40
fast=(--state-dir run/state2 --set digitiser.stack=4 --set baseline.scans=1)
state=run/state2
start_daemon uwbd-watch.log "${fast[@]}"
ctl baseline set > /dev/null
ctl scan > w-base.json
[[ $(get baseline_set < w-base.json) == true ]] || fail "commissioning: $(cat w-base.json)"
base_id=$(get scan_id < w-base.json)
[[ -n $(get crc32 < $state/baseline/current.json) && $(get crc32 < $state/baseline/current.json) != "(missing)" ]] ||
    fail "current.json records no checksum: $(cat $state/baseline/current.json)"

# A baseline deleted while running: the next scan is an error with a fault, not a silent `edges`.
emu 'set displacement_m 0.012' > /dev/null
rm $state/baseline/current.uwbscan
ctl scan > w-deleted.json || true
[[ $(get status fault < w-deleted.json | paste -sd' ') == "error baseline" ]] ||
    fail "a deleted baseline: $(cat w-deleted.json)"
[[ $(get reason < w-deleted.json) == "fault: baseline missing: "*"$base_id"* ]] || fail "reason: $(cat w-deleted.json)"
grep -q "warning: .*fault: baseline missing" uwbd-watch.log || fail "no warning-level log line for the fault"
ctl status > w-status.json
[[ $(get fault baseline.check < w-status.json | paste -sd'|') == "baseline missing: "*"|failed" ]] ||
    fail "status does not say the baseline failed its check: $(cat w-status.json)"
pass "baseline deleted while running: error verdict, fault 'baseline missing', warning logged, status says so"

# `baseline set` recovers: the next good scan replaces it; the fault clears.
ctl baseline set > /dev/null
emu 'set displacement_m 0' > /dev/null
ctl scan > w-recommission.json
[[ $(get status baseline_set < w-recommission.json | paste -sd' ') == "edges true" ]] ||
    fail "recommissioning after a deleted baseline: $(cat w-recommission.json)"
[[ $(get baseline_note < w-recommission.json) == "replaced a baseline that failed its check"* ]] ||
    fail "note: $(cat w-recommission.json)"
ctl status > w-status2.json
[[ $(get fault < w-status2.json) == "(missing)" ]] || fail "fault not cleared: $(cat w-status2.json)"
base_id=$(get scan_id < w-recommission.json)

# A damaged (truncated) baseline: fault; `baseline set` moves it aside and replaces it.
size=$(stat -c %s $state/baseline/current.uwbscan)
truncate -s $((size / 2)) $state/baseline/current.uwbscan
ctl scan > w-damaged.json || true
[[ $(get status fault < w-damaged.json | paste -sd' ') == "error baseline" &&
   $(get reason < w-damaged.json) == "fault: baseline damaged: "* ]] || fail "a damaged baseline: $(cat w-damaged.json)"
# ...and a daemon started on it says so from the start.
stop_daemon
start_daemon uwbd-watch1b.log "${fast[@]}"
[[ $(ctl status | get fault) == "baseline damaged: "* ]] || fail "after a restart: $(ctl status)"
grep -q "warning: device fault: baseline damaged" uwbd-watch1b.log || fail "no warning at start for the damaged baseline"
ctl baseline set > /dev/null
ctl scan > w-replaced.json
[[ $(get status baseline_set < w-replaced.json | paste -sd' ') == "edges true" ]] ||
    fail "a damaged baseline was not replaced: $(cat w-replaced.json)"
damaged=( $state/baseline/history/damaged-*.uwbscan )
[[ -f ${damaged[0]} && $(stat -c %s "${damaged[0]}") == $((size / 2)) ]] ||
    fail "the damaged baseline was not kept in history: $(ls $state/baseline/history)"
ctl scan > w-after.json
[[ $(get status < w-after.json) == ok ]] || fail "scan after replacing the damaged baseline: $(cat w-after.json)"
pass "damaged baseline: fault; \`baseline set\` replaced it (the damaged one kept as $(basename "${damaged[0]}")), next scan ok"

# A pending `baseline set` survives a restart.
ctl baseline set > /dev/null
stop_daemon
start_daemon uwbd-watch2.log "${fast[@]}"
[[ $(ctl status | get baseline_pending) == true ]] || fail "the pending baseline set was forgotten at restart"
ctl scan > w-restart.json
[[ $(get baseline_set < w-restart.json) == true ]] || fail "pending after restart not applied: $(cat w-restart.json)"
[[ ! -e $state/baseline/pending.json && $(ctl status | get baseline_pending) == false ]] ||
    fail "the request is still pending after it was applied"
base_id=$(get scan_id < w-restart.json)
pass "a pending \`baseline set\` survives a restart and is applied to the next good scan"

# ...and is never applied to an alarm: refused with the reason, the old baseline kept.
emu 'set displacement_m 0.012' > /dev/null
ctl baseline set > /dev/null
ctl scan > w-alarm.json
[[ $(get status baseline_set < w-alarm.json | paste -sd' ') == "alarm false" &&
   $(get baseline_note < w-alarm.json) == "refused: this scan is an alarm"* ]] ||
    fail "baseline set on an alarm: $(cat w-alarm.json)"
[[ $(ctl status | get baseline_pending baseline.scan_id | paste -sd' ') == "false $base_id" ]] ||
    fail "after the refusal: $(ctl status)"
ctl scan > w-alarm2.json
[[ $(get status baseline_set < w-alarm2.json | paste -sd' ') == "alarm (missing)" ]] ||
    fail "the refused request came back: $(cat w-alarm2.json)"
pass "a pending \`baseline set\` meets an alarm: refused with the reason, the baseline kept, the alarm stays"

# After a repair that moved the winding, the operator says so: `baseline set force`.
ctl baseline set force > /dev/null
ctl scan > w-force.json
[[ $(get status baseline_set < w-force.json | paste -sd' ') == "alarm true" &&
   $(get baseline_note < w-force.json) == "forced (\`baseline set force\`)"* ]] ||
    fail "baseline set force on an alarm: $(cat w-force.json)"
grep -q "warning: scan .*: baseline set force: taking it as the baseline" uwbd-watch2.log || fail "force not logged"
ctl scan > w-after-force.json
[[ $(get status < w-after-force.json) == ok ]] || fail "after baseline set force: $(cat w-after-force.json)"
pass "\`baseline set force\` (after a repair): the alarm scan becomes the baseline, said in the verdict and log"

# A current.json whose direct coupling is wrong is checked against the baseline scan itself.
stop_daemon
sed -i 's/"direct_coupling_ps":[-0-9.e]*/"direct_coupling_ps":1234.5/' $state/baseline/current.json
grep -q '"direct_coupling_ps":1234.5' $state/baseline/current.json || fail "could not edit current.json"
start_daemon uwbd-watch3.log "${fast[@]}"
ctl scan > w-dc.json
[[ $(get status < w-dc.json) == ok ]] || fail "a wrong direct_coupling_ps in current.json: $(cat w-dc.json)"
grep -q "warning: baseline: current.json gives the direct coupling at 1234.5 ps" uwbd-watch3.log ||
    fail "no warning about the wrong direct coupling"
! grep -q '"direct_coupling_ps":1234.5' $state/baseline/current.json || fail "current.json not corrected"
pass "current.json with a wrong direct_coupling_ps: the baseline scan's own is used (warning), scan ok"

# The state directory deleted under the daemon: it stops (73) with a clear message; a new one may start.
rm -rf "$state"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 73 ]] || fail "daemon after its state directory was deleted: exit $rc, want 73"
grep -q "lock file .* was deleted or replaced" uwbd-watch3.log || fail "no clear message: $(tail -3 uwbd-watch3.log)"
start_daemon uwbd-watch4.log "${fast[@]}"
stop_daemon
pass "state directory deleted while running: the daemon stops (73) naming the lock; the next one starts cleanly"

echo "$passed passed, 0 failed"
