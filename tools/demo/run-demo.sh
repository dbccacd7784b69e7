#!/usr/bin/env bash
# make demo: the appliance on the emulated board. Starts the emulated board
# (build/uwbemu: pulser, carriage and digitiser, simulating a 3-D tank scene
# with clutter and noise) and the daemon (uwbd --config
# board/emulated/uwbd.json) as separate processes, commissions a baseline,
# moves the emulated winding up 12 mm, scans again, then puts it back and
# bulges disks 2..4 6 mm toward the antennas (a radial change), scans again,
# prints the verdicts and where the images are, and stops everything.
# On a terminal uwbd ctl prints text and scan progress is a bar; piped into
# a file its replies are JSON lines, as scripts read them, and progress is
# left out (only errors).
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD=$(cd "${UWB_BUILD_DIR:-${1:-$REPO/build}}" && pwd)
OUT=${UWB_DEMO_OUT:-$BUILD/demo}
CONFIG="$REPO/board/emulated/uwbd.json"
# Pulses averaged per position: the sample config's `digitiser.stack` (64,
# the one default); at the scene's 20 dB per pulse they make the figure good
# to a few tenths of a millimetre (README, Accuracy). UWB_DEMO_STACK=N
# overrides it.
stack_override=()
[[ -n ${UWB_DEMO_STACK:-} ]] && stack_override=(--set digitiser.stack="$UWB_DEMO_STACK")

# The config's relative paths (run/...) land in the demo directory.
rm -rf "$OUT/run"
mkdir -p "$OUT/run"
cd "$OUT"

emu_pid= daemon_pid= broker_pid= sub_pid=
stop_all() {
    if [[ -n $daemon_pid ]]; then kill -TERM "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; fi
    if [[ -n $emu_pid ]]; then kill -TERM "$emu_pid" 2>/dev/null || true; wait "$emu_pid" 2>/dev/null || true; fi
    if [[ -n $sub_pid ]]; then kill -TERM "$sub_pid" 2>/dev/null || true; wait "$sub_pid" 2>/dev/null || true; fi
    if [[ -n $broker_pid ]]; then kill -TERM "$broker_pid" 2>/dev/null || true; wait "$broker_pid" 2>/dev/null || true; fi
    daemon_pid= emu_pid= sub_pid= broker_pid=
}
trap stop_all EXIT
die() {
    echo "demo: $*" >&2
    for log in uwbd.log emu.log; do [[ -s $log ]] && { echo "--- $OUT/$log" >&2; tail -n 15 "$log" >&2; }; done
    exit 1
}
wait_for() {
    for _ in $(seq 100); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
    return 1
}
ctl() { "$BUILD/uwbd" ctl --socket run/control.sock "$@"; }
# `uwbd ctl scan`: on a terminal its progress bar, the verdict left to
# show (its text, once); otherwise its VERDICT line, and its PROGRESS lines
# (one per position) stay out of the output and only errors show.
scan() {
    local rc=0
    if [[ -t 1 ]]; then
        ctl --text scan > run/scan.txt || { rc=$?; cat run/scan.txt; }
        return "$rc"
    fi
    ctl scan 2> run/scan.err || rc=$?
    grep -v '^{"class":"PROGRESS"' run/scan.err >&2 || true
    return "$rc"
}
show() {   # label: the latest verdict as text, from uwbd ctl --text
    echo "== $1"
    echo "\$ uwbd ctl --text verdict"
    ctl --text verdict | sed "s/^/   /" || die "uwbd ctl --text verdict"
}
# The alarm contacts as the emulated board's relays see them (1 = energised).
contacts() {
    local status
    status=$("$BUILD/uwbemu" --ctl unix:run/emu.sock status) || die "uwbemu status"
    line() { printf '%s\n' "$status" | sed -n "s/.*\"lines\":{[^}]*\"$1\":\([01]\).*/\1/p"; }
    echo "   alarm contacts (uwbemu status, 1 = energised): watch $(line watch), alarm $(line alarm), fault $(line fault)  ${1:-}"
}
# The site's integrations, on (all are off in the shipped sample): the contacts
# on their own emulated lines.
site=(--set site.asset_id=demo-T1 --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock)

# With Debian's mosquitto installed (make deps does), a broker on 127.0.0.1 for
# the demo alone, and a subscriber that prints what uwbd publishes.
mqtt_port=
if [[ -x /usr/sbin/mosquitto && -x $BUILD/e2e/mqtt_sub ]]; then
    mqtt_port=$((20000 + RANDOM % 40000))
    printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nuser %s\n' "$mqtt_port" "$(id -un)" \
        > run/broker.conf
    /usr/sbin/mosquitto -v -c run/broker.conf > broker.log 2>&1 &
    broker_pid=$!
    if wait_for grep -q "listen socket on port $mqtt_port" broker.log; then
        site+=(--set mqtt.enabled=true --set "mqtt.endpoint=tcp:127.0.0.1:$mqtt_port")
        # Up to 100 messages in 300 s; the demo stops it once `offline` has come.
        "$BUILD/e2e/mqtt_sub" "$mqtt_port" demo demo 'uwbd/demo-T1/#' 100 300 > mqtt.out 2> mqtt.err &
        sub_pid=$!
        wait_for grep -q subscribed mqtt.err || mqtt_port=
    else
        mqtt_port=
    fi
    [[ -n $mqtt_port ]] || echo "   (mosquitto did not start: MQTT not shown; see $OUT/broker.log)"
fi

root_flag=()
if [[ $(id -u) == 0 ]]; then
    root_flag=(--allow-root)   # uwbd refuses root otherwise; on the appliance it runs as user uwbd
fi

echo "uwbd demo: the emulated board and the daemon as two processes, talking over unix sockets in $OUT/run"
"$BUILD/uwbemu" --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock --control unix:run/emu.sock --site-io unix:run/site.sock \
    --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --seed 1 > emu.log 2>&1 &
emu_pid=$!
wait_for "$BUILD/uwbemu" --ctl unix:run/emu.sock status || die "the emulated board did not start"
"$BUILD/uwbd" --config "$CONFIG" "${root_flag[@]}" "${stack_override[@]}" "${site[@]}" > uwbd.log 2>&1 &
daemon_pid=$!
wait_for ctl status || die "uwbd did not start"
echo "   started: uwbemu (pid $emu_pid), uwbd --config board/emulated/uwbd.json (pid $daemon_pid)"
contacts "(fault energised: healthy)"

echo "\$ uwbd ctl baseline set"
ctl baseline set
echo "\$ uwbd ctl scan"
scan || die "the commissioning scan failed"
show "commissioning scan of the intact winding (it becomes the baseline)"
contacts

echo "\$ uwbemu --ctl unix:run/emu.sock 'set displacement_m 0.012'     # the winding moves up 12 mm"
"$BUILD/uwbemu" --ctl unix:run/emu.sock 'set displacement_m 0.012' > /dev/null || die "cannot move the emulated winding"
echo "\$ uwbd ctl scan"
scan || die "the second scan failed"
show "scan after the emulated winding moved up 12 mm"
contacts "(watch and alarm latch until ack)"
echo "\$ uwbd ctl ack"
ctl ack || die "ack"
contacts "(the alarm holds while the latest verdict is an alarm)"

echo "\$ uwbemu --ctl unix:run/emu.sock 'set displacement_m 0'     # the winding back in place"
"$BUILD/uwbemu" --ctl unix:run/emu.sock 'set displacement_m 0' > /dev/null || die "cannot move the emulated winding back"
echo "\$ uwbemu --ctl unix:run/emu.sock 'set radial 2 4 6'     # disks 2..4 bulge 6 mm toward the antennas"
"$BUILD/uwbemu" --ctl unix:run/emu.sock 'set radial 2 4 6' > /dev/null || die "cannot bulge the emulated winding"
echo "\$ uwbd ctl scan"
scan || die "the radial scan failed"
show "scan after disks 2..4 of the emulated winding bulged 6 mm toward the antennas (a radial change)"
comparison=$(ctl --json verdict | tr ',' '\n' | sed -n 's/.*"\([^"]*-comparison\.png\)".*/\1/p')
[[ -n $comparison ]] || die "the radial scan's verdict names no comparison picture"
echo "   the comparison picture (baseline and this scan): $comparison"
contacts

kill -TERM "$daemon_pid" 2>/dev/null; wait "$daemon_pid" 2>/dev/null || true
daemon_pid=
contacts "(uwbd stopped: every contact open, the fault contact too)"
if [[ -n $mqtt_port ]]; then
    # uwbd's last message is `offline` on its status topic; then the listing is whole.
    wait_for grep -q '^uwbd/demo-T1/status [01] offline$' mqtt.out || echo "   (no \`offline\` from uwbd within 10 s)"
    kill -TERM "$sub_pid" 2>/dev/null || true
    wait "$sub_pid" 2>/dev/null || true
    sub_pid=
    echo "== MQTT: what a subscriber to uwbd/demo-T1/# on the demo's broker (127.0.0.1:$mqtt_port) received"
    echo "   (TOPIC RETAINED PAYLOAD; payloads cut at 180 characters a line)"
    cut -c1-180 mqtt.out | sed 's/^/   /'
fi
stop_all
stop_all
echo "== stopped uwbemu and uwbd; the state directory is $OUT/run/state:"
echo "   verdicts: $OUT/run/state/verdicts.jsonl ($(wc -l < run/state/verdicts.jsonl) lines), latest: $OUT/run/state/latest.json"
echo "   baseline: $OUT/run/state/baseline/current.uwbscan"
echo "   logs: $OUT/uwbd.log, $OUT/emu.log"
