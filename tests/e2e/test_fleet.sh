#!/usr/bin/env bash
# The fleet recipe (board/fleet/): two emulated appliances publish to a
# substation gateway broker run from board/fleet/mosquitto-gateway.conf (its
# SITE lines pointed at 127.0.0.1), whose bridge carries their topics to a
# central broker; a historian subscribed there gets both assets' verdicts,
# each on its own asset's topic with its own asset_id.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
need_mosquitto
e2e_workdir uwbd-fleet
mqtt_sub() { $HOST_PREFIX "$HOST_BUILD/e2e/mqtt_sub" "$@"; }

touch central.pw gateway.pw
mosquitto_passwd -b central.pw gateway-northfield gw-secret 2> /dev/null
mosquitto_passwd -b central.pw historian h-secret 2> /dev/null
for asset in T1 T2; do
    mosquitto_passwd -b gateway.pw "app-$asset" "secret-$asset" 2> /dev/null
    mkdir -p "run/$asset"
    printf 'secret-%s\n' "$asset" > "run/$asset/mqtt.pw"
    chmod 600 "run/$asset/mqtt.pw"
done

start_mosquitto central mosquitto_conf "$work/central.pw"
central_port=$port
central_log=$broker_log

# The shipped gateway recipe, its SITE lines set for this test.
gateway_conf() {
    sed -e "s|^listener 1883\$|listener $1 127.0.0.1|" \
        -e "s|^password_file /etc/mosquitto/uwbd.passwd\$|password_file $work/gateway.pw|" \
        -e "s|^persistence_location /var/lib/mosquitto/\$|persistence_location $work/|" \
        -e "s|^address central.example.net:8883\$|address 127.0.0.1:$central_port|" \
        -e "/^bridge_cafile /d" \
        -e "s|^remote_password CHANGE-ME\$|remote_password gw-secret|" \
        "$REPO/board/fleet/mosquitto-gateway.conf"
    echo "user $(id -un)"
}
gateway_conf 1 > probe.conf
for want in "listener 1 127.0.0.1" "password_file $work/gateway.pw" "address 127.0.0.1:$central_port" \
            "remote_password gw-secret"; do
    grep -qxF "$want" probe.conf || fail "board/fleet/mosquitto-gateway.conf changed: no line to make '$want'"
done
! grep -q '^bridge_cafile' probe.conf || fail "bridge_cafile left in"
start_mosquitto gateway gateway_conf
gateway_port=$port
E2E_WAIT_TRIES=600 wait_for grep -q "as gateway-northfield" "$central_log" || fail "the gateway's bridge did not reach the central broker"
pass "board/fleet/mosquitto-gateway.conf: the gateway starts and its bridge logs in to the central broker"

mqtt_sub "$central_port" historian h-secret 'uwbd/+/verdict' 2 120 > historian.out 2> historian.err &
sub_pid=$!
pids+=($sub_pid)
E2E_WAIT_TRIES=600 wait_for grep -q subscribed historian.err || fail "the historian did not subscribe"

cp "$REPO/board/emulated/uwbd.json" uwbd.json
for asset in T1 T2; do
    d="run/$asset"
    $HOST_PREFIX "$HOST_BUILD/uwbemu" --gpio "unix:$d/gpio.sock" --digitiser "unix:$d/digitiser.sock" \
        --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7 > "emu-$asset.log" 2>&1 &
    pids+=($!)
    wait_for test -S "$d/digitiser.sock" || fail "uwbemu $asset did not come up"
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config uwbd.json "${root_flag[@]}" --set "state_dir=$d/state" \
        --set "control.socket=$d/control.sock" --set "gpio.endpoint=unix:$d/gpio.sock" \
        --set "digitiser.endpoint=unix:$d/digitiser.sock" --set "site.asset_id=$asset" --set mqtt.enabled=true \
        --set "mqtt.endpoint=tcp:127.0.0.1:$gateway_port" --set "mqtt.username=app-$asset" \
        --set "mqtt.password_file=$d/mqtt.pw" > "uwbd-$asset.log" 2>&1 &
    pids+=($!)
    wait_for uwbd ctl --socket "$d/control.sock" status || fail "uwbd $asset does not answer"
done
uwbd ctl --socket run/T1/control.sock scan > T1.json 2>/dev/null &
scan1=$!
uwbd ctl --socket run/T2/control.sock scan > T2.json 2>/dev/null || fail "T2's scan: $(cat T2.json)"
wait "$scan1" || fail "T1's scan: $(cat T1.json)"
wait "$sub_pid" || fail "the historian did not get both verdicts: $(cut -c1-120 historian.out)"
for asset in T1 T2; do
    line=$(grep "^uwbd/$asset/verdict " historian.out) || fail "no verdict of $asset at the historian: $(cut -c1-120 historian.out)"
    printf '%s\n' "$line" | cut -d' ' -f3- > "got-$asset.json"
    json_check "got-$asset.json" "asset_id == $asset" "scan_id == $(json_get scan_id < "$asset.json")" ||
        fail "$asset's verdict at the historian: $(cut -c1-200 "got-$asset.json")"
done
pass "two appliances through the gateway's bridge: the historian got T1's and T2's verdicts, each on its own topic"
echo "$passed passed"
