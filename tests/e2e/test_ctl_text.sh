#!/usr/bin/env bash
# Issue 31, findings 2 and 7: `uwbd ctl --text` prints text for people for
# every reply (a status page of aligned "Name : value" lines, as chronyc's
# `tracking`; a history table; the help list; watch as a line each), while
# plain `uwbd ctl` keeps the JSON line for programs. `status` shows the
# integrations: the asset, the MQTT link (off here), Modbus listening and
# on what, the contacts energised, the baseline's age and the free space
# in the state directory (JSON keys added, none changed).
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-ctl-text

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
port=$($HOST_PREFIX "$HOST_BUILD/e2e/modbus_client" freeport)
start_emulated_board --site-io unix:run/site.sock
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set baseline.scans=1 \
    --set site.asset_id=T3-north --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock \
    --set modbus.enabled=true --set modbus.endpoint="\"tcp:127.0.0.1:$port\"" -v > uwbd.log 2>&1 &
pids+=($!)
wait_for ctl status || fail "uwbd does not answer: $(tail -5 uwbd.log)"
ctl baseline set > /dev/null
ctl scan > base.json 2>/dev/null || fail "baseline scan: $(cat base.json)"
base_id=$(json_get scan_id < base.json)

# ---- status: the JSON for programs gains keys, keeps its others ----------------
ctl status > status.json
json_check status.json 'class == STATUS' 'state == idle' "baseline.scan_id == $base_id" 'asset_id == T3-north' \
    'modbus.listening = true' "modbus.endpoint == tcp:127.0.0.1:$port" 'contacts.watch = false' \
    'contacts.alarm = false' 'contacts.fault = true' 'baseline.age_s >= 0' 'state_dir_free_bytes > 0' \
    'latest.status == edges' || fail "status: $(cat status.json)"
pass "status JSON: asset_id, modbus, contacts, baseline.age_s, state_dir_free_bytes beside the old keys"

# --json says so explicitly (the default): the reply line as the daemon sent it.
ctl --json verdict > verdict-json.json || fail "--json verdict: exit $?"
ctl verdict > verdict-plain.json
cmp -s verdict-json.json verdict-plain.json || fail "--json differs from the default: $(cat verdict-json.json)"
rc=0
ctl --json --text status > both.out 2> both.err || rc=$?
[[ $rc == 64 ]] && grep -q 'give one of --json, --text or --csv' both.err || fail "--json --text: exit $rc: $(cat both.err)"
pass "--json: the JSON line, as without it; with --text refused (exit 64)"

# ---- --text: a page for people ---------------------------------------------------
ctl --text status > status.txt
grep -q '{' status.txt && fail "--text status printed JSON: $(cat status.txt)"
for want in '^State           : idle$' '^Asset           : T3-north$' "^Baseline        : $base_id, set .* ago)" \
    '^Latest verdict  : EDGES, ' '^MQTT            : off$' "^Modbus          : listening on tcp:127.0.0.1:$port$" \
    '^Contacts        : fault energised$' '^State directory : .*run/state, [0-9.]* [KMGT]iB free$' \
    '^Version         : .* (protocol 1\.0), up '; do
    grep -q "$want" status.txt || fail "--text status: no line /$want/: $(cat status.txt)"
done
pass "--text status: aligned Name : value lines with the integrations"

ctl --text history 5 > history.txt
[[ $(head -1 history.txt) =~ ^time\ \(UTC\)\ +status ]] || fail "--text history: no header: $(cat history.txt)"
grep -q "^20[0-9-]*T[0-9:]*Z  EDGES  .*$base_id (baseline)$" history.txt || fail "--text history: $(cat history.txt)"
ctl --text help > help.txt
grep -q '^  baseline set force  the same' help.txt || fail "--text help: $(cat help.txt)"
[[ $(awk 'length > 79' help.txt | wc -l) == 0 ]] || fail "--text help: lines over 79 columns"
ctl --text --timeout 2 watch > watch.txt 2>/dev/null || true
[[ $(head -1 watch.txt) == 'watching: progress and verdicts' ]] || fail "--text watch: $(cat watch.txt)"
pass "--text history is a table, help a list within 79 columns, watch a line"

# ---- a mistyped command: ctl names the one meant --------------------------------
rc=0
ctl stauts > typo.out 2> typo.err || rc=$?
[[ $rc == 64 ]] && grep -qF 'did you mean `status`?' typo.err || fail "stauts: exit $rc: $(cat typo.err)"
ctl Baseline Set > upper.json || fail "Baseline Set refused: $(cat upper.json)"
json_check upper.json 'class == BASELINE' 'pending = true' || fail "Baseline Set: $(cat upper.json)"
pass "stauts: exit 64, did you mean status; 'Baseline Set' accepted"

# ---- issue 48, findings 1, 2 and 8: text on a terminal, options anywhere --------
# script(1) (bsdutils, in every Debian) gives ctl a pty for its stdout.
on_terminal() { script -qec "${UWB_EXEC_PREFIX:-} $BUILD/uwbd ctl --socket run/control.sock $*" /dev/null | tr -d '\r'; }
on_terminal status > tty-status.txt
grep -q '^State           : idle$' tty-status.txt && ! grep -q '{' tty-status.txt ||
    fail "status on a terminal is not the text page: $(cat tty-status.txt)"
on_terminal verdict > tty-verdict.txt
grep -q '{' tty-verdict.txt && fail "verdict on a terminal printed JSON: $(cat tty-verdict.txt)"
on_terminal --json status | json_check - 'class == STATUS' || fail "--json on a terminal: not the JSON line"
on_terminal ack > tty-ack.txt
grep -q '^acknowledged: the watch and alarm latches are released$' tty-ack.txt &&
    grep -q "^watch and alarm released: the latest verdict is EDGES (20.*, scan $base_id)$" tty-ack.txt ||
    fail "ack on a terminal does not say what was done and what holds: $(cat tty-ack.txt)"
pass "on a terminal: text (status, verdict, ack in words); --json there the JSON line; a pipe the JSON line"

ctl status --text > late-text.txt || fail "status --text: exit $?"
grep -q '^State           : idle$' late-text.txt ||
    fail "status --text: $(cat late-text.txt)"
ctl history --csv > late.csv || fail "history --csv: exit $?"
[[ $(head -c 4 late.csv) != '{"cl' && $(wc -l < late.csv) -ge 2 ]] || fail "history --csv: $(cat late.csv)"
ctl history 1 --json | json_check - 'class == HISTORY' || fail "history 1 --json"
rc=0
ctl -- history --csv > dashdash.out 2> dashdash.err || rc=$?
[[ $rc == 64 ]] || fail "after --, --csv is a command word: exit $rc: $(cat dashdash.err)"
rc=0
ctl -t status > short.out 2> short.err || rc=$?
[[ $rc == 64 ]] && grep -qF "unknown option '-t'" short.err || fail "-t: exit $rc: $(cat short.err)"
pass "options after the command (status --text, history --csv, history 1 --json); after -- none; -t unknown"
# ---- issue 48, findings 4, 5 and 6: dated text, whole tables, ASCII where not UTF-8 ----
# One form of scan id, asset first; the rig's log line names the scan by it.
[[ $base_id =~ ^T3-north-uwb-[0-9]{8}T[0-9]{6}\.[0-9]{3}Z$ ]] || fail "scan id not in the one form: $base_id"
grep -qF "rig: scan $base_id: " uwbd.log || fail "the rig's log line does not name the scan with its asset: $(grep 'rig: scan' uwbd.log)"
ctl scan > second.json || fail "second scan: $(cat second.json)"
second_id=$(json_get scan_id < second.json)
second_at=$(json_get created < second.json)
LC_ALL=C on_terminal verdict > tty-c-verdict.txt
[[ $(head -1 tty-c-verdict.txt) == "verdict of $second_at, scan $second_id" ]] ||
    fail "the text verdict is not dated and named: $(cat tty-c-verdict.txt)"
for cmd in verdict history trend status; do
    LC_ALL=C on_terminal "$cmd" > "tty-c-$cmd.txt"
    LC_ALL=C grep -qP '[\x80-\xff]' "tty-c-$cmd.txt" && fail "LC_ALL=C: $cmd wrote a byte that is not ASCII: $(cat "tty-c-$cmd.txt")"
    LC_ALL=C.UTF-8 on_terminal "$cmd" > "tty-utf8-$cmd.txt"
done
grep -q '^status OK: displacement [-+][0-9.]* +/- [0-9.]* mm 1 sigma, ' tty-c-verdict.txt ||
    fail "LC_ALL=C verdict: $(cat tty-c-verdict.txt)"
grep -q '^status OK: displacement [-+][0-9.]* ± [0-9.]* mm 1σ, ' tty-utf8-verdict.txt ||
    fail "LC_ALL=C.UTF-8 verdict: $(cat tty-utf8-verdict.txt)"
grep -q "^Latest verdict  : OK [-+][0-9.]* +/- [0-9.]* mm, $second_at, scan $second_id$" tty-c-status.txt ||
    fail "status does not name the latest verdict's scan: $(cat tty-c-status.txt)"
head -1 tty-c-history.txt | grep -q '  height change  radial +/- 1 sigma  ' ||
    fail "history's header: $(head -1 tty-c-history.txt)"
grep -q '± .*1σ' tty-utf8-trend.txt && grep -q 'displacement +/- 1 sigma' tty-c-trend.txt ||
    fail "trend: $(cat tty-c-trend.txt tty-utf8-trend.txt)"
pass "text verdict dated and named ($second_id); ASCII under LC_ALL=C, ± σ under C.UTF-8 (pty)"
echo "$passed passed"
