#!/usr/bin/env bash
# The appliance through the full stack, daemon and emulated board as
# separate processes talking over unix sockets: commissioning a baseline,
# a +12 mm shift measured, the state directory's files, replies on the
# control socket and the serial console, SIGHUP reload, SIGTERM in the
# middle of a scan, and the start-up refusals with their exit codes.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
# uwbd ctl --text writes "±" where the locale is UTF-8, "+/-" elsewhere
# (issue 48): the checks below read the UTF-8 form, the console's the ASCII.
export LC_ALL=C.UTF-8
e2e_workdir uwbd-e2e

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }

# ---- configuration refused with the key named, exit 78 -------------------
uwbd --check-config "$config" > check.out || fail "the emulated sample does not validate"
json_edit "$config" bad-unknown.json 'digitiser.sampels=2048'
json_edit "$config" bad-missing.json '-scan.positions'
json_edit "$config" bad-type.json 'carriage.travel_mm="650"'
json_edit "$config" bad-mode.json 'control.mode="0666"'
printf '{"state_dir": "x",\n "schedule": {"interval_s": 0,}}\n' > bad-syntax.json
for case in unknown:digitiser.sampels missing:scan.positions type:carriage.travel_mm mode:control.mode \
            syntax:line; do
    name=${case%%:*} key=${case#*:}
    set +e; uwbd --check-config "bad-$name.json" > /dev/null 2> "bad-$name.err"; rc=$?; set -e
    [[ $rc == 78 ]] || fail "--check-config bad-$name.json: exit $rc, want 78"
    grep -q "bad-$name.json: " "bad-$name.err" || fail "bad-$name: message does not name the file: $(cat "bad-$name.err")"
    if [[ $name != syntax ]]; then
        grep -qF "key \`$key\`" "bad-$name.err" || fail "bad-$name: message does not name $key: $(cat "bad-$name.err")"
    fi
done
set +e; uwbd --config "bad-missing.json" "${root_flag[@]}" 2> start-bad.err; rc=$?; set -e
[[ $rc == 78 ]] || fail "daemon on an incomplete config: exit $rc, want 78"
pass "malformed and incomplete configs refused with the key named, exit 78"

# ---- root only when allowed ----------------------------------------------
if [[ $(id -u) == 0 ]]; then
    set +e; uwbd --config "$config" 2> root.err; rc=$?; set -e
    [[ $rc == 77 ]] || fail "as root without --allow-root: exit $rc, want 77"
    grep -q "refusing to run as root" root.err || fail "no clear message for root: $(cat root.err)"
    pass "refuses to run as root without allow_root (77)"
fi

# ---- missing hardware: distinct exit codes, clear messages ----------------
set +e
uwbd --config "$config" "${root_flag[@]}" --set gpio.backend=libgpiod --set gpio.endpoint='""' \
     --set gpio.chip=gpiochip9 --set gpio.lines='{"trigger":17,"step":27,"dir":22,"enable":23,"home":24}' \
     --state-dir run/state-hw 2> gpio.err
rc_gpio=$?
set -e
[[ $rc_gpio == 69 ]] || fail "missing GPIO chip: exit $rc_gpio, want 69 ($(cat gpio.err))"
grep -q "gpiochip9" gpio.err || fail "missing GPIO chip: message does not name it: $(cat gpio.err)"
pass "missing GPIO chip (libgpiod backend) -> exit 69: $(grep -o "gpio chip 'gpiochip9'[^(]*" gpio.err | head -1)"

# The emulated board: the tank scene (window, core leg, barrier, far wall,
# jitter, drift), with 40 dB per pulse on top of the config's 64 pulses per
# position; tests/e2e/test_daemon_baseline.sh runs the sample config at 20 dB.
start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
wait_for uwbemu --ctl unix:run/emu.sock status || fail "uwbemu does not answer"

set +e
uwbd --config "$config" "${root_flag[@]}" --set digitiser.endpoint='"serial:/dev/ttyUWBmissing?baud=921600"' \
     --state-dir run/state-hw 2> serial.err
rc_serial=$?
set -e
[[ $rc_serial == 74 ]] || fail "missing serial port: exit $rc_serial, want 74 ($(cat serial.err))"
grep -q "/dev/ttyUWBmissing" serial.err || fail "missing serial port: message does not name it: $(cat serial.err)"
pass "missing digitiser serial port -> exit 74"

# ---- the console: a peer the daemon connects to ---------------------------
long_line=$(printf 'x%.0s' $(seq 100))
$HOST_PREFIX "$HOST_BUILD/e2e/unix_peer" session run/console.sock run/console.go console.out \
    help status "frobnicate --now" "$long_line" "history 2" verdict > console.log 2>&1 &
console_pid=$!
pids+=($console_pid)
wait_for test -S run/console.sock || fail "console listener did not come up"

# ---- the daemon ------------------------------------------------------------
# As root the socket goes to group nogroup, so that unix_peer slots can act
# as an unprivileged control-group member (uid 65534) below; that one user
# fills all 15 ordinary slots, so its per-user share is raised to 15 here
# (test_daemon_attacks.sh tests the default share of 8).
group_flag=()
if [[ $(id -u) == 0 ]]; then
    group_flag=(--set control.group='"nogroup"' --set control.max_clients_per_user=15)
fi
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" "${group_flag[@]}" --console unix:run/console.sock -v \
    --set site.phase='"B"' --set site.label='"Hillside GT2, north window"' --set csv.enabled=true > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"
[[ $(stat -c %a run/control.sock) == 660 ]] || fail "control socket mode $(stat -c %a run/control.sock), want 660"
ctl status > status0.json
json_check status0.json 'class == STATUS' 'state == idle' 'baseline absent' 'site.phase == B' \
    'site.label == Hillside GT2, north window' || fail "first status: $(cat status0.json)"
pass "daemon up: control socket mode 0660, STATUS idle, no baseline"

# A second daemon stops before it touches the state or the hardware.
set +e
uwbd --config "$config" "${root_flag[@]}" 2> second.err; rc_state=$?
uwbd --config "$config" "${root_flag[@]}" --state-dir run/state-second 2> second-socket.err; rc_socket=$?
set -e
[[ $rc_state == 73 ]] && grep -q "another uwbd is using this state directory" second.err ||
    fail "second daemon on the same state: exit $rc_state: $(cat second.err)"
[[ $rc_socket == 73 ]] && grep -q "another uwbd is listening there" second-socket.err ||
    fail "second daemon on the same socket: exit $rc_socket: $(cat second-socket.err)"
ctl status > /dev/null || fail "the first daemon was disturbed by the second"
pass "a second uwbd on the same state directory or socket exits 73 and leaves the first alone"

ctl baseline set > baseline.json
json_check baseline.json 'class == BASELINE' 'pending = true' || fail "baseline set: $(cat baseline.json)"
ctl scan > scan1.json || fail "first scan: $(cat scan1.json)"
json_check scan1.json 'class == VERDICT' 'status == edges' 'baseline_set = true' ||
    fail "commissioning scan: $(cat scan1.json)"
base_id=$(json_get scan_id < scan1.json)
pass "commissioning: the scan after \`baseline set\` became the baseline ($base_id)"

uwbemu --ctl unix:run/emu.sock 'set displacement_m 0.012' > /dev/null
ctl scan > scan2.json || fail "second scan: $(cat scan2.json)"
json_check scan2.json 'class == VERDICT' 'status == alarm' 'axial_displacement_mm ~ 12.0 0.5' ||
    fail "shifted scan (the emulated winding moved +12 mm): $(cat scan2.json)"
read -r shift_mm uncertainty_mm coupling_ps < <(json_get axial_displacement_mm uncertainty_mm direct_coupling_shift_ps < scan2.json | paste -sd ' ')
echo "measured $(printf '%+.2f +- %.2f' "$shift_mm" "$uncertainty_mm") mm, direct coupling shift $coupling_ps ps"
pass "winding shifted +12 mm on the emulated board: $(printf '%+.2f' "$shift_mm") mm, status alarm"

# ---- the state directory ---------------------------------------------------
state=run/state
[[ $(wc -l < $state/verdicts.jsonl) == 2 ]] || fail "verdicts.jsonl is not two lines"
for n in 1 2; do
    sed -n "${n}p" $state/verdicts.jsonl | json_check - ". same scan$n.json" ||
        fail "verdicts.jsonl line $n is not the verdict of scan $n"
done
json_check $state/latest.json '. same scan2.json' || fail "latest.json is not the last verdict"
days=($state/archive/[0-9][0-9][0-9][0-9]/[0-9][0-9]/[0-9][0-9])
[[ ${#days[@]} == 1 && -d ${days[0]} ]] || fail "want one archive day directory, found: ${days[*]}"
day=$(cd "${days[0]}" && pwd)
for n in 1 2; do
    id=$(json_get scan_id < scan$n.json)
    json_check "$day/$id.json" ". same scan$n.json" || fail "archived verdict $id"
    head -n 1 "$day/$id.uwbscan" | json_check - "scan_id == $id" 'format == uwbscan/1' ||
        fail "archived scan $id: header $(head -n 1 "$day/$id.uwbscan" | head -c 300)"
    json_check scan$n.json 'images len 3' || fail "scan $n: not three images"
    for i in 0 1 2; do
        png=$(json_get "images.$i" < scan$n.json)
        [[ $png == "$day"/* && $(head -c 8 "$png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] ||
            fail "scan $n: image $png is not a PNG in $day"
    done
done
json_check $state/baseline/current.json "scan_id == $base_id" 'direct_coupling_ps exists' ||
    fail "baseline/current.json: $(cat $state/baseline/current.json)"
head -n 1 $state/baseline/current.uwbscan | json_check - "scan_id == $base_id" || fail "baseline/current.uwbscan"
[[ -z $(find $state -name '.*') ]] || fail "temporary files left: $(find $state -name '.*')"
pass "archive, verdicts.jsonl, latest.json and baseline files present and valid"
# csv.enabled: the CSV output module's file (written from the whole record at each verdict) is
# byte for byte what `ctl --csv history` prints from the HISTORY reply: every cell filled alike.
ctl --csv history > history.csv || fail "ctl --csv history"
cmp history.csv $state/verdicts.csv || fail "ctl --csv history is not verdicts.csv: $(diff history.csv $state/verdicts.csv)"
[[ $(wc -l < $state/verdicts.csv) == 3 ]] || fail "verdicts.csv: not a header and two rows"
pass "csv.enabled: verdicts.csv is what ctl --csv history prints, a header and a row per verdict"

# ---- control socket replies --------------------------------------------------
ctl history 5 > history.json
json_check history.json 'class == HISTORY' 'count = 2' 'verdicts len 2' 'verdicts.0.status == edges' \
    'verdicts.1.status == alarm' || fail "history: $(cat history.json)"
# The same history as CSV: CRLF rows, as many fields on each (commas inside
# quotes are not separators), and the displacement cells the JSON's digits
# (no column before it holds a comma, so a plain split finds it).
ctl --csv history 5 > history.csv || fail "uwbd ctl --csv history: $(cat history.csv)"
[[ $(wc -l < history.csv) == 3 && $(grep -c $'\r$' history.csv) == 3 ]] ||
    fail "history --csv: not a header and two CRLF rows: $(cat -A history.csv)"
csv_cells=$(awk '{ sub(/\r$/, ""); line = line $0; n = 1; q = 0
                   for (i = 1; i <= length(line); i++) { c = substr(line, i, 1)
                       if (c == "\"") q = !q; else if (c == "," && !q) n++ }
                   if (q) { line = line "\n"; next }
                   if (NR == 1) { want = n; split(line, h, ",")
                       for (k in h) if (h[k] == "axial_displacement_mm") col = k }
                   else if (n != want) { print "row " NR - 1 ": " n " fields, the header " want; exit 1 }
                   else { split(line, f, ","); printf "%s;", f[col] }
                   line = "" }' history.csv) || fail "history --csv: $csv_cells"
json_cells=$(json_get verdicts.0.axial_displacement_mm verdicts.1.axial_displacement_mm < history.json |
    sed 's/^(missing)$//' | tr '\n' ';')
[[ $csv_cells == "$json_cells" && $csv_cells == ";$shift_mm;" ]] ||
    fail "history --csv displacement cells '$csv_cells', the JSON's '$json_cells' (shift $shift_mm)"
# The trend: the same two verdicts as a series, and trend.png rewritten
# after each (its Description chunk is plain text in the file).
ctl trend 5 > trend.json || fail "trend: $(cat trend.json)"
json_check trend.json 'class == TREND' 'count = 2' 'verdicts.0.status == edges' 'verdicts.0.baseline_set = true' \
    'verdicts.1.status == alarm' "verdicts.1.axial_displacement_mm = $shift_mm" "verdicts.1.uncertainty_mm = $uncertainty_mm" \
    'thresholds.alarm_mm exists' "image == $(cd $state && pwd)/trend.png" 'rate.figures = 1' 'rate.mm_per_year absent' \
    'rate.withheld == 1 figure since the last baseline change; a rate needs at least 4 figures over 7 days' ||
    fail "trend: $(cat trend.json)"
ctl --text trend 5 > trend.txt || fail "uwbd ctl --text trend"
grep -q "ALARM  *$(printf '%+.2f' "$shift_mm") ± $(printf '%.2f' "$uncertainty_mm") mm" trend.txt &&
    grep -q 'EDGES  *no figure' trend.txt && grep -q "^image: /.*/trend.png$" trend.txt &&
    grep -q '^rate: not known yet (1 figure since the last baseline change; ' trend.txt ||
    fail "uwbd ctl --text trend: $(cat trend.txt)"
[[ $(head -c 8 $state/trend.png | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "trend.png is not a PNG"
grep -aq '2 verdicts: 1 with a figure, 0 inconclusive, 0 error, 1 edges only.*; rate not known yet: 1 figure since' \
    $state/trend.png ||
    fail "trend.png does not describe the two verdicts"
grep -aq 'phase B, Hillside GT2, north window' $state/trend.png || fail "trend.png does not name the site"
pass "trend: JSON and --text from verdicts.jsonl; trend.png rewritten after the scan"
ctl verdict > verdict.json
json_check verdict.json '. same scan2.json' || fail "verdict is not the latest scan's"
ctl --text verdict > verdict.txt || fail "uwbd ctl --text verdict"
shift_text=$(printf '%+.2f' "$(json_get axial_displacement_mm < scan2.json)")
scan2_id=$(json_get scan_id < scan2.json)
[[ $(sed -n 1p verdict.txt) == "verdict of $(json_get created < scan2.json), scan $scan2_id" &&
   $(sed -n 2p verdict.txt) == "status ALARM: displacement $shift_text ± "*" mm (edges "*" mm, baseline "*" mm)" &&
   $(grep -c '^image: /' verdict.txt) == 3 && $(grep -c '^height change ' verdict.txt) == 1 &&
   $(grep -c '^radial change .*: OK$' verdict.txt) == 1 && $(wc -l < verdict.txt) == 7 ]] ||
    fail "uwbd ctl --text verdict: $(cat verdict.txt)"
ctl help | grep -q '"class":"HELP"' || fail "help"
set +e; ctl frobnicate > /dev/null 2> ctl-bad.err; rc=$?; set -e
[[ $rc == 64 ]] || fail "ctl with an unknown command: exit $rc, want 64"
# The daemon itself refuses what a client other than uwbd ctl might send.
{ printf 'scan ../../etc/passwd\n'; printf 'y%.0s' $(seq 500); printf '\nstatus\n'; } |
    unix_peer ask run/control.sock 3 > raw.json || fail "raw control socket"
sed -n 1p raw.json | json_check - 'class == ERROR' || fail "a path argument was not refused: $(sed -n 1p raw.json)"
sed -n 2p raw.json | json_check - 'class == ERROR' || fail "an over-long line was not refused"
sed -n 3p raw.json | json_check - 'class == STATUS' || fail "the connection did not recover after bad lines"
pass "uwbd ctl: status, baseline set, scan, history (JSON and --csv), verdict (JSON and --text), help; bad lines refused with ERROR"

# At most 16 control clients; when all are taken, one quiet for 2 s or more
# makes room, so silent connections cannot lock the operators out. Clients
# other than root and the uwbd user get at most 15: as root, unix_peer also
# floods 15 slots as uid 65534 in the socket's group nogroup (reaching run/
# through this work directory, hence its o+x) and checks root still gets in.
if [[ $(id -u) == 0 ]]; then chmod o+x "$work"; fi
unix_peer slots run/control.sock 16 > slots.out || fail "control client slots: $(cat slots.out)"
cat slots.out
grep -q "dropping one idle" uwbd.log || fail "no log line for the dropped idle client"
if [[ $(id -u) == 0 ]]; then
    grep -q "kept for root" slots.out || fail "no unprivileged client refused for the slot kept for root"
    pass "17th control client refused while all 16 are fresh; after 2 s idle the oldest makes room; 15 unprivileged clients sending status every 0.5 s cannot take the last slot, root is answered"
else
    pass "17th control client refused while all 16 are fresh; after 2 s idle the oldest makes room (slot kept for root: skipped, not root)"
fi

# ---- the console ---------------------------------------------------------------
touch run/console.go
wait "$console_pid" || fail "console peer: $(cat console.log)"
# The console is for people: each reply as `uwbd ctl --text` prints it.
grep -q '^{' console.out && fail "the console printed JSON: $(cat console.out)"
grep -q '^Commands (case does not matter):$' console.out || fail "console help: $(cat console.out)"
grep -q '^Baseline        : .' console.out || fail "console status: no baseline: $(cat console.out)"
grep -q '^error: unknown command' console.out || fail "console frobnicate: $(cat console.out)"
grep -q '^error: command line too long' console.out || fail "console long line: $(cat console.out)"
[[ $(grep -c '^20[0-9-]*T[0-9:]*Z  ' console.out) == 2 ]] || fail "console history 2: want 2 rows: $(cat console.out)"
# The console writes ASCII (its terminal is not known to be UTF-8), as
# uwbd ctl does under LC_ALL=C.
LC_ALL=C ctl --text verdict > verdict.txt
grep -qxF "$(sed -n 2p verdict.txt)" console.out && grep -q '+/- .* mm 1 sigma' verdict.txt ||
    fail "console verdict differs from uwbd ctl --text verdict in ASCII: $(cat verdict.txt) $(cat console.out)"
LC_ALL=C grep -qP '[\x80-\xff]' console.out && fail "the console wrote a byte that is not ASCII: $(cat console.out)"
pass "serial console (unix endpoint): the same replies, as text for people"

# ---- SIGHUP reload, then SIGTERM in the middle of a scan --------------------------
json_edit "$config" "$config" 'scan.time_scale=0.2'
kill -HUP "$daemon_pid"
wait_for grep -q "configuration reloaded" uwbd.log || fail "SIGHUP did not reload the configuration"
lines_before=$(wc -l < run/state/verdicts.jsonl)
triggers_before=$(uwbemu --ctl unix:run/emu.sock status | json_get triggers)
(ctl scan > scan-stopped.json 2>&1 && echo 0 > scan-stopped.rc || echo $? > scan-stopped.rc) &
ctl_pid=$!
emu_fired_since() { uwbemu --ctl unix:run/emu.sock status | json_check - "triggers > $1"; }
wait_for emu_fired_since "$triggers_before" || fail "the slowed scan never started firing"
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 0 ]] || fail "SIGTERM mid-scan: exit $rc, want 0"
wait "$ctl_pid" || true
[[ $(cat scan-stopped.rc) == 1 ]] || fail "the interrupted scan's client: exit $(cat scan-stopped.rc), want 1 (ERROR)"
grep -q "stopped" scan-stopped.json || fail "the interrupted scan's reply: $(cat scan-stopped.json)"
uwbemu --ctl unix:run/emu.sock status > emu-after.json
json_check emu-after.json 'lines.trigger = 0' 'lines.enable = 0' ||
    fail "hardware not safe after SIGTERM: $(cat emu-after.json)"
[[ $(wc -l < run/state/verdicts.jsonl) == "$lines_before" ]] || fail "the stopped scan left a verdict"
[[ -z $(find run/state -name '.*') ]] || fail "half-written files left: $(find run/state -name '.*')"
[[ ! -e run/control.sock ]] || fail "control socket left behind"
grep -q "stopped; hardware left safe" uwbd.log || fail "no shutdown log line"
pass "SIGHUP reloaded (scan slowed); SIGTERM mid-scan: exit 0, pulser idle, motor disabled, nothing written"

# ---- it starts again on the same state and scans -----------------------------------
# With a schedule now, the first scheduled scan counts from the latest
# verdict's "created" time (written seconds ago), not from the start.
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set scan.time_scale=0 --interval 3600 \
    > uwbd2.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not come back"
next_s=$(sed -n 's/.*next scheduled scan in \([0-9]*\) s (the schedule carries on from the latest verdict).*/\1/p' uwbd2.log)
[[ -n $next_s && $next_s -lt 3600 && $next_s -gt 3000 ]] || fail "restart: schedule not carried on from the latest verdict: $(cat uwbd2.log)"
ctl status > status2.json
json_check status2.json "baseline.scan_id == $base_id" 'latest.status == alarm' || fail "after restart: $(cat status2.json)"
ctl scan > scan3.json || fail "scan after restart: $(cat scan3.json)"
json_check scan3.json 'status == alarm' || fail "scan after restart: $(cat scan3.json)"
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 0 ]] || fail "SIGTERM when idle: exit $rc"
pass "restart on the same state: baseline and latest verdict kept, schedule carried on (next in $next_s s), next scan fine, idle SIGTERM exit 0"

echo "$passed passed, 0 failed"
