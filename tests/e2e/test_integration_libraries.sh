#!/usr/bin/env bash
# uwbd loads libmosquitto, libmodbus and libsystemd only when it needs them
# (src/integrations/*_loader.c): none of them is linked into uwbd, so a
# replay starts without them; with MQTT or Modbus enabled and the library
# missing (UWB_MOSQUITTO_LIB / UWB_MODBUS_LIB naming a file that is not
# there) the daemon refuses to start, naming the key, the library and the
# package; under systemd (NOTIFY_SOCKET) without libsystemd it says so and
# runs on. The working paths are test_mqtt.sh, test_daemon_modbus.sh and
# test_systemd_notify.sh.
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-libraries

# ---- not linked: what the dynamic loader maps at every start ----------------
needed=$(readelf -d "$BUILD/uwbd" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
grep -q '^libc\.so' <<<"$needed" || fail "readelf found no NEEDED libc in uwbd: $needed"
for lib in libmosquitto libmodbus libsystemd; do
    if grep -q "^$lib\\." <<<"$needed"; then fail "uwbd is linked with $lib: $(echo $needed)"; fi
done
pass "uwbd is not linked with libmosquitto, libmodbus or libsystemd ($(echo $needed))"

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
start_emulated_board
missing=$work/missing

# refused NAME ENV=LIB ARGS...: uwbd must stop by itself with an error; its
# status in $status, its log NAME.log.
refused() {
    local name=$1 assignment=$2
    shift 2
    status=0
    env "$assignment" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" "$@" \
        > "$name.log" 2>&1 || status=$?
    [[ $status != 0 ]] || fail "$name: uwbd started without its library: $(tail -3 "$name.log")"
}

# ---- MQTT enabled, libmosquitto missing --------------------------------------
refused mqtt "UWB_MOSQUITTO_LIB=$missing/libmosquitto.so.1" --set site.asset_id=T7 \
    --set mqtt.enabled=true --set mqtt.endpoint=tcp:127.0.0.1:9
grep -q "mqtt.enabled needs $missing/libmosquitto.so.1, which cannot be loaded (.*No such file.*); install the libmosquitto1 package" mqtt.log ||
    fail "mqtt without libmosquitto: exit $status: $(cat mqtt.log)"
pass "mqtt.enabled without libmosquitto: exit $status, naming the key, the library and the package"

# ---- Modbus enabled, libmodbus missing ----------------------------------------
refused modbus "UWB_MODBUS_LIB=$missing/libmodbus.so.5" --set modbus.enabled=true \
    --set modbus.endpoint=unix:run/modbus.sock
grep -q "modbus.enabled needs $missing/libmodbus.so.5, which cannot be loaded (.*No such file.*); install the libmodbus5 package" modbus.log ||
    fail "modbus without libmodbus: exit $status: $(cat modbus.log)"
pass "modbus.enabled without libmodbus: exit $status, naming the key, the library and the package"

# ---- under systemd without libsystemd: said, and the daemon runs on ---------
env NOTIFY_SOCKET="$work/run/notify" "UWB_SYSTEMD_LIB=$missing/libsystemd.so.0" ${UWB_EXEC_PREFIX:-} \
    "$BUILD/uwbd" --config "$config" "${root_flag[@]}" > systemd.log 2>&1 &
daemon=$!
pids+=($daemon)
wait_for uwbd ctl --socket run/control.sock status || fail "uwbd without libsystemd does not answer"
grep -q "NOTIFY_SOCKET) needs $missing/libsystemd.so.0, which cannot be loaded (.*); install the libsystemd0 package" systemd.log ||
    fail "no error naming libsystemd: $(cat systemd.log)"
kill -TERM "$daemon"
wait "$daemon" || fail "SIGTERM: exit $?"
pass "NOTIFY_SOCKET without libsystemd: the error names the library; the daemon runs and stops cleanly"

echo "$passed passed"
