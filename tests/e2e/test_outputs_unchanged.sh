#!/usr/bin/env bash
# The outputs pinned byte for byte (issue 29: refactoring the verdict's
# path must not change what leaves the appliance). Two runs:
#   - uwbd --replay on four fixture pairs: the JSON line and its PNGs;
#   - the emulated daemon (tank scene, fixed seed), a baseline scan and a
#     4 mm scan, with MQTT (a loopback mosquitto), Modbus TCP and the
#     Prometheus textfile on: the archived verdict files, verdicts.jsonl,
#     latest.json, the MQTT verdict and health payloads, the Modbus
#     register block, the textfile and the ctl replies (verdict, --text,
#     history, trend).
# What legitimately differs between runs is masked before hashing: UTC
# stamps, scan ids (they carry the time), the scratch directory, Unix
# times and the scan's duration. The daemon's PNGs carry the scan's time
# in their captions, so they are not hashed; the replay PNGs pin the same
# renderer.
#
# The digests are per architecture (floating point may round differently
# on aarch64): tests/fixtures/outputs-unchanged.MACHINE.sha256, MACHINE
# read from uwbd's ELF header. Without a digest file for the machine the
# test is skipped. When an output change is intended, record new digests:
#     UWB_RECORD_OUTPUTS=1 UWB_BUILD_DIR=$PWD/build bash tests/e2e/test_outputs_unchanged.sh
# and commit the digest file with the change, saying why in the message.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
# uwbd ctl --text writes "±" or "+/-" by the locale's codeset (issue 48):
# pinned, so the digests do not depend on the caller's locale.
export LC_ALL=C.UTF-8
need_mosquitto
case $(od -An -j18 -N2 -tu2 "$BUILD/uwbd" | tr -d ' ') in
    62) machine=x86_64 ;;
    183) machine=aarch64 ;;
    *) machine=unknown ;;
esac
digests="$REPO/tests/fixtures/outputs-unchanged.$machine.sha256"
record=${UWB_RECORD_OUTPUTS:-0}
if [[ $record != 1 && ! -f $digests ]]; then
    echo "SKIP: no $digests (record it with UWB_RECORD_OUTPUTS=1)"
    exit 77
fi
e2e_workdir uwbd-outputs
mkdir out

# ---- replay: four pairs and one scan alone ------------------------------------
fixtures=$REPO/tests/fixtures
replay() {   # NAME CURRENT [BASELINE]
    local name=$1 current=$2 args=()
    [[ -n ${3:-} ]] && args=(--baseline "$fixtures/$3.uwbscan")
    mkdir "replay-$name"
    uwbd --replay "$fixtures/$current.uwbscan" "${args[@]}" --out "replay-$name" > "out/replay-$name.json" ||
        fail "replay $name: exit $?"
    for png in "replay-$name"/*.png; do cp "$png" "out/replay-$name-$(basename "$png")"; done
}
replay paper-alarm fdtd2d-paper-up20mm fdtd2d-paper-intact
replay tank-watch fdtd2d-tank-d+04.0 fdtd2d-tank-d+00.0
replay tank-down fdtd2d-tank-d-08.0 fdtd2d-tank-d+00.0
replay var3d-inconclusive fdtd3d-var-s012-d-20 fdtd3d-var-s012-d+00
replay paper-edges fdtd2d-paper-intact
pass "replay: 5 verdicts and their PNGs written"

# ---- the daemon with MQTT, Modbus TCP and the Prometheus textfile --------------
config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }
mbc() { $HOST_PREFIX "$HOST_BUILD/e2e/modbus_client" "$@"; }
mqtt_sub() { $HOST_PREFIX "$HOST_BUILD/e2e/mqtt_sub" "$@"; }

touch broker.pw
mosquitto_passwd -b broker.pw uwbd 'daemon-secret' 2> /dev/null
mosquitto_passwd -b broker.pw tester 'tester-secret' 2> /dev/null
printf 'daemon-secret\n' > run/mqtt.pw
chmod 600 run/mqtt.pw
start_mosquitto broker mosquitto_conf "$work/broker.pw"
modbus_port=$(mbc freeport)

start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
wait_for emu status || fail "uwbemu does not answer"
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --set site.asset_id=T7 \
    --set mqtt.enabled=true --set "mqtt.endpoint=tcp:127.0.0.1:$port" --set mqtt.username=uwbd \
    --set mqtt.password_file=run/mqtt.pw --set modbus.enabled=true \
    --set "modbus.endpoint=tcp:127.0.0.1:$modbus_port" --set prometheus.enabled=true \
    --set prometheus.textfile=run/uwbd.prom -v > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer on its control socket"
mqtt_sub "$port" tester tester-secret uwbd/T7/verdict 2 120 > mqtt-verdicts.out 2> mqtt-verdicts.err &
sub_pid=$!
pids+=($sub_pid)
E2E_WAIT_TRIES=600 wait_for grep -q subscribed mqtt-verdicts.err || fail "the MQTT subscriber did not subscribe"

ctl baseline set 1 > /dev/null
ctl scan > out/daemon-scan-1.json 2> /dev/null || fail "baseline scan: $(cat out/daemon-scan-1.json)"
emu 'set displacement_m 0.004' > /dev/null
ctl scan > out/daemon-scan-2.json 2> /dev/null || fail "4 mm scan: $(cat out/daemon-scan-2.json)"
json_check out/daemon-scan-2.json 'status == watch' 'axial_displacement_mm exists' ||
    fail "the 4 mm scan: $(cat out/daemon-scan-2.json)"
wait "$sub_pid" || fail "the two verdicts did not reach the broker: $(cat mqtt-verdicts.out)"
cp mqtt-verdicts.out out/mqtt-verdicts.txt
health_now() {
    mqtt_sub "$port" tester tester-secret uwbd/T7/health 1 5 > out/mqtt-health.txt &&
        cut -d' ' -f3- out/mqtt-health.txt | json_check - 'verdicts_since_start = 2' 2>/dev/null
}
wait_for health_now || fail "no health report after the second verdict: $(cat out/mqtt-health.txt)"
mbc tcp 127.0.0.1 "$modbus_port" dump > out/modbus.txt 2> modbus.err || fail "Modbus dump: $(cat modbus.err)"
# The register's scan time is the verdict's (masked below): check it here.
created=$(json_get created < out/daemon-scan-2.json)
grep -q "scan_time=$(date -u -d "$created" +%s) " out/modbus.txt || fail "Modbus scan_time is not $created: $(cat out/modbus.txt)"
ctl verdict > out/ctl-verdict.json
ctl --text verdict > out/ctl-verdict.txt
ctl history > out/ctl-history.json
ctl trend > out/ctl-trend.json
cp run/uwbd.prom out/prometheus.prom
cp run/state/verdicts.jsonl out/verdicts.jsonl
cp run/state/latest.json out/latest.json
n=0
for f in run/state/archive/*/*/*/*.json; do
    n=$((n + 1))
    cp "$f" "out/archived-$n.json"
done
[[ $n == 2 ]] || fail "$n archived verdicts, want 2"
kill "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
pass "daemon: 2 verdicts archived, published on MQTT, in the Modbus registers and the textfile"

# ---- mask what varies between runs, hash, compare ------------------------------
for f in out/*; do
    sed -E -e "s#$work#WORK#g" \
        -e 's#[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}(\.[0-9]+)?Z#TIME#g' \
        -e 's#uwb-[0-9]{8}T[0-9]{6}\.[0-9]{3}Z#uwb-ID#g' \
        -e 's#archive/[0-9]{4}/[0-9]{2}/[0-9]{2}#archive/DAY#g' \
        -e 's#scan_time=[0-9]+#scan_time=T#' \
        -e 's#"mqtt_queued":[0-9]+#"mqtt_queued":N#' \
        -e 's#^(uwbd_last_verdict_timestamp_seconds|uwbd_scan_duration_seconds)(\{[^}]*\}) .*#\1\2 T#' \
        "$f" > "$f.masked" 2>/dev/null || cp "$f" "$f.masked"
done
# PNGs are hashed as they are (sed above leaves binary files alone only by luck).
for f in out/*.png; do cp "$f" "$f.masked"; done
(cd out && sha256sum -- *.masked | sed 's/\.masked$//') > digests.now
if [[ $record == 1 ]]; then
    cp digests.now "$digests"
    pass "recorded $(wc -l < digests.now) digests into $digests"
else
    if ! diff "$digests" digests.now > digests.diff; then
        for name in $(awk '/^[<>]/ {print $3}' digests.diff | sort -u); do
            echo "--- out/$name (masked):" >&2
            head -c 600 "out/$name.masked" | cut -c1-300 >&2 || true
            echo >&2
        done
        fail "outputs changed against $digests: $(cat digests.diff)"
    fi
    pass "$(wc -l < digests.now) outputs byte-identical to $(basename "$digests")"
fi
echo "$passed passed"
