#!/usr/bin/env bash
# The appliance through the full stack, daemon and emulated board as
# separate processes talking over unix sockets: commissioning a baseline,
# a +12 mm shift measured, the state directory's files, replies on the
# control socket and the serial console, SIGHUP reload, SIGTERM in the
# middle of a scan, and the start-up refusals with their exit codes.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-e2e

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }

# ---- configuration refused with the key named, exit 78 -------------------
uwbd --check-config "$config" > check.out || fail "the emulated sample does not validate"
python3 - "$config" <<'PY'
import json, sys
base = json.load(open(sys.argv[1]))
def variant(name, change):
    v = json.loads(json.dumps(base)); change(v); json.dump(v, open(name, "w"))
variant("bad-unknown.json", lambda v: v["digitiser"].__setitem__("sampels", 2048))
variant("bad-missing.json", lambda v: v["scan"].pop("positions"))
variant("bad-type.json", lambda v: v["carriage"].__setitem__("travel_mm", "650"))
variant("bad-mode.json", lambda v: v["control"].__setitem__("mode", "0666"))
open("bad-syntax.json", "w").write('{"state_dir": "x",\n "schedule": {"interval_s": 0,}}\n')
PY
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
emu_args=(--gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock --control unix:run/emu.sock
          --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7)
${UWB_EXEC_PREFIX:-} "$BUILD/uwbemu" "${emu_args[@]}" > emu.log 2>&1 &
pids+=($!)
wait_for test -S run/emu.sock || fail "uwbemu did not come up"
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
cat > console.py <<'PY'
# Listens where uwbd's console connects; when run/console.go appears, sends
# each command line and records the reply lines in console.out.
import json, os, socket, sys, time
srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
srv.bind("run/console.sock"); srv.listen(1); srv.settimeout(60)
conn, _ = srv.accept(); conn.settimeout(60)
while not os.path.exists("run/console.go"):
    time.sleep(0.05)
out = open("console.out", "w")
buf = b""
for line in sys.argv[1:]:
    conn.sendall(line.encode() + b"\n")
    while b"\n" not in buf:
        chunk = conn.recv(65536)
        if not chunk:
            sys.exit("console: uwbd closed the connection")
        buf += chunk
    reply, buf = buf.split(b"\n", 1)
    out.write(reply.decode() + "\n"); out.flush()
PY
long_line=$(printf 'x%.0s' $(seq 100))
python3 console.py help status "frobnicate --now" "$long_line" "history 2" verdict > console.log 2>&1 &
console_pid=$!
pids+=($console_pid)
wait_for test -S run/console.sock || fail "console listener did not come up"

# ---- the daemon ------------------------------------------------------------
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --console unix:run/console.sock -v \
    > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"
[[ $(stat -c %a run/control.sock) == 660 ]] || fail "control socket mode $(stat -c %a run/control.sock), want 660"
ctl status > status0.json
[[ $(json_get 'v["class"], v["state"], "baseline" in v' < status0.json) == "('STATUS', 'idle', False)" ]] ||
    fail "first status: $(cat status0.json)"
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
[[ $(json_get 'v["class"], v["pending"]' < baseline.json) == "('BASELINE', True)" ]] || fail "baseline set: $(cat baseline.json)"
ctl scan > scan1.json || fail "first scan: $(cat scan1.json)"
[[ $(json_get 'v["class"], v["status"], v["baseline_set"]' < scan1.json) == "('VERDICT', 'edges', True)" ]] ||
    fail "commissioning scan: $(cat scan1.json)"
base_id=$(json_get 'v["scan_id"]' < scan1.json)
pass "commissioning: the scan after \`baseline set\` became the baseline ($base_id)"

uwbemu --ctl unix:run/emu.sock 'set displacement_m 0.012' > /dev/null
ctl scan > scan2.json || fail "second scan: $(cat scan2.json)"
python3 - scan2.json <<'PY' || fail "shifted scan: $(cat scan2.json)"
import json, sys
v = json.load(open(sys.argv[1]))
assert v["class"] == "VERDICT" and v["status"] == "alarm", v
d = v["axial_displacement_mm"]
assert abs(d - 12.0) <= 0.5, f"displacement {d} mm for an emulated +12 mm shift"
print(f"measured {d:+.2f} +- {v['uncertainty_mm']:.2f} mm, direct coupling shift {v['direct_coupling_shift_ps']} ps")
PY
pass "winding shifted +12 mm on the emulated board: $(json_get '"%+.2f mm" % v["axial_displacement_mm"]' < scan2.json), status alarm"

# ---- the state directory ---------------------------------------------------
python3 - run/state "$base_id" scan1.json scan2.json <<'PY' || fail "state directory"
import glob, json, os, sys
state, base_id = sys.argv[1], sys.argv[2]
verdicts = [json.load(open(p)) for p in sys.argv[3:]]
lines = open(os.path.join(state, "verdicts.jsonl")).read().splitlines()
assert [json.loads(l) for l in lines] == verdicts, "verdicts.jsonl is not the two verdicts, in order"
assert json.load(open(os.path.join(state, "latest.json"))) == verdicts[-1], "latest.json is not the last verdict"
for v in verdicts:
    day = [os.path.abspath(p) for p in glob.glob(os.path.join(state, "archive", "[0-9]" * 4, "[0-9]" * 2, "[0-9]" * 2))]
    assert len(day) == 1, day
    stem = os.path.join(day[0], v["scan_id"])
    assert json.load(open(stem + ".json")) == v
    head = open(stem + ".uwbscan", "rb").readline()
    assert json.loads(head)["scan_id"] == v["scan_id"] and json.loads(head)["format"] == "uwbscan/1"
    assert len(v["images"]) == 3
    for png in v["images"]:
        assert png.startswith(day[0]) and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n", png
cur = json.load(open(os.path.join(state, "baseline", "current.json")))
assert cur["scan_id"] == base_id and "direct_coupling_ps" in cur, cur
head = json.loads(open(os.path.join(state, "baseline", "current.uwbscan"), "rb").readline())
assert head["scan_id"] == base_id
hidden = [p for p in glob.glob(os.path.join(state, "**", ".*"), recursive=True)]
assert not hidden, f"temporary files left: {hidden}"
PY
pass "archive, verdicts.jsonl, latest.json and baseline files present and valid"

# ---- control socket replies --------------------------------------------------
ctl history 5 > history.json
[[ $(json_get 'v["class"], v["count"], [h["status"] for h in v["verdicts"]]' < history.json) == \
   "('HISTORY', 2, ['edges', 'alarm'])" ]] || fail "history: $(cat history.json)"
ctl verdict > verdict.json
cmp -s <(json_get 'v' < verdict.json) <(json_get 'v' < scan2.json) || fail "verdict is not the latest scan's"
ctl help | grep -q '"class":"HELP"' || fail "help"
set +e; ctl frobnicate > /dev/null 2> ctl-bad.err; rc=$?; set -e
[[ $rc == 64 ]] || fail "ctl with an unknown command: exit $rc, want 64"
# The daemon itself refuses what a client other than uwbd ctl might send.
python3 - <<'PY' > raw.json || fail "raw control socket"
import socket
s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM); s.connect("run/control.sock")
s.sendall(b"scan ../../etc/passwd\n" + b"y" * 500 + b"\nstatus\n")
buf = b""
while buf.count(b"\n") < 3:
    buf += s.recv(65536)
print(buf.decode(), end="")
PY
[[ $(sed -n 1p raw.json | json_get 'v["class"]') == ERROR ]] || fail "a path argument was not refused: $(sed -n 1p raw.json)"
[[ $(sed -n 2p raw.json | json_get 'v["class"]') == ERROR ]] || fail "an over-long line was not refused"
[[ $(sed -n 3p raw.json | json_get 'v["class"]') == STATUS ]] || fail "the connection did not recover after bad lines"
pass "uwbd ctl: status, baseline set, scan, history, verdict, help; bad lines refused with ERROR"

# At most 16 control clients; when all are taken, one quiet for 2 s or more
# makes room, so silent connections cannot lock the operators out.
python3 - <<'PY' || fail "control client slots"
import json, socket, time
def connect():
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM); s.connect("run/control.sock"); s.settimeout(20)
    return s
def ask(s, line):
    s.sendall(line.encode() + b"\n")
    buf = b""
    while not buf.endswith(b"\n"):
        chunk = s.recv(65536)
        assert chunk, f"closed while waiting for the reply to {line!r}"
        buf += chunk
    return json.loads(buf)
idle = [connect() for _ in range(16)]
time.sleep(0.3)
extra = connect()
reply = json.loads(extra.recv(65536))
assert reply["class"] == "ERROR" and "too many control clients" in reply["message"], reply
time.sleep(2.5)
late = connect()
assert ask(late, "status")["class"] == "STATUS"
assert idle[0].recv(16) == b"", "the longest-idle client was not the one dropped"
assert ask(idle[1], "status")["class"] == "STATUS", "another idle client lost its connection"
PY
grep -q "dropping one idle" uwbd.log || fail "no log line for the dropped idle client"
pass "17th control client refused while all 16 are fresh; after 2 s idle the oldest makes room"

# ---- the console ---------------------------------------------------------------
touch run/console.go
wait "$console_pid" || fail "console peer: $(cat console.log)"
python3 - console.out verdict.json <<'PY' || fail "console replies: $(cat console.out)"
import json, sys
replies = [json.loads(l) for l in open(sys.argv[1])]
classes = [r["class"] for r in replies]
assert classes == ["HELP", "STATUS", "ERROR", "ERROR", "HISTORY", "VERDICT"], classes
assert "unknown command" in replies[2]["message"] and "too long" in replies[3]["message"], replies[2:4]
assert replies[1]["baseline"]["scan_id"] and replies[4]["count"] == 2
assert replies[5] == json.load(open(sys.argv[2])), "console verdict differs from uwbd ctl verdict"
PY
pass "serial console (unix endpoint): the same replies, one JSON line each"

# ---- SIGHUP reload, then SIGTERM in the middle of a scan --------------------------
python3 - "$config" <<'PY'
import json, sys
c = json.load(open(sys.argv[1])); c["scan"]["time_scale"] = 0.2
json.dump(c, open(sys.argv[1], "w"))
PY
kill -HUP "$daemon_pid"
wait_for grep -q "configuration reloaded" uwbd.log || fail "SIGHUP did not reload the configuration"
lines_before=$(wc -l < run/state/verdicts.jsonl)
triggers_before=$(uwbemu --ctl unix:run/emu.sock status | json_get 'v["triggers"]')
(ctl scan > scan-stopped.json 2>&1 && echo 0 > scan-stopped.rc || echo $? > scan-stopped.rc) &
ctl_pid=$!
wait_for python3 -c "
import json, subprocess, sys
s = json.loads(subprocess.run(sys.argv[1:], capture_output=True, text=True).stdout)
sys.exit(0 if s['triggers'] > $triggers_before else 1)" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbemu" --ctl unix:run/emu.sock status ||
    fail "the slowed scan never started firing"
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 0 ]] || fail "SIGTERM mid-scan: exit $rc, want 0"
wait "$ctl_pid" || true
[[ $(cat scan-stopped.rc) == 1 ]] || fail "the interrupted scan's client: exit $(cat scan-stopped.rc), want 1 (ERROR)"
grep -q "stopped" scan-stopped.json || fail "the interrupted scan's reply: $(cat scan-stopped.json)"
uwbemu --ctl unix:run/emu.sock status > emu-after.json
[[ $(json_get 'v["lines"]["trigger"], v["lines"]["enable"]' < emu-after.json) == "(0, 0)" ]] ||
    fail "hardware not safe after SIGTERM: $(cat emu-after.json)"
[[ $(wc -l < run/state/verdicts.jsonl) == "$lines_before" ]] || fail "the stopped scan left a verdict"
[[ -z $(find run/state -name '.*') ]] || fail "half-written files left: $(find run/state -name '.*')"
[[ ! -e run/control.sock ]] || fail "control socket left behind"
grep -q "stopped; hardware left safe" uwbd.log || fail "no shutdown log line"
pass "SIGHUP reloaded (scan slowed); SIGTERM mid-scan: exit 0, pulser idle, motor disabled, nothing written"

# ---- it starts again on the same state and scans -----------------------------------
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set scan.time_scale=0 > uwbd2.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not come back"
ctl status > status2.json
[[ $(json_get 'v["baseline"]["scan_id"], v["latest"]["status"]' < status2.json) == "('$base_id', 'alarm')" ]] ||
    fail "after restart: $(cat status2.json)"
ctl scan > scan3.json || fail "scan after restart: $(cat scan3.json)"
[[ $(json_get 'v["status"]' < scan3.json) == alarm ]] || fail "scan after restart: $(cat scan3.json)"
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; rc=$?; set -e
[[ $rc == 0 ]] || fail "SIGTERM when idle: exit $rc"
pass "restart on the same state: baseline and latest verdict kept, next scan fine, idle SIGTERM exit 0"

echo "$passed passed, 0 failed"
