#!/usr/bin/env bash
# board/fleet/'s site gateway in a real Mosquitto: the recipe's
# configuration, with only its addresses and paths made local and its TLS
# lines left out (no certificates here), loads, takes the ACL and the
# password file, and its bridge connects to a second Mosquitto standing in
# for the utility's central broker, under the recipe's client id and with
# its notification topic. Skipped (77) without /usr/sbin/mosquitto. The
# two-appliances test waits for uwbd's MQTT client.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
[[ -x /usr/sbin/mosquitto && -x /usr/bin/mosquitto_passwd ]] || { echo "SKIP: no mosquitto"; exit 77; }
e2e_workdir uwbd-fleet
mbc() { $HOST_PREFIX "$HOST_BUILD/e2e/modbus_client" "$@"; }   # its freeport

central_port=$(mbc freeport)
gateway_port=$(mbc freeport)
while [[ $gateway_port == "$central_port" ]]; do gateway_port=$(mbc freeport); done
me=$(id -un)

printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nuser %s\n' "$central_port" "$me" > central.conf
/usr/sbin/mosquitto -v -c central.conf > central.log 2>&1 &
pids+=($!)
wait_for grep -q "listen socket on port $central_port" central.log || fail "central broker: $(cat central.log)"

mkdir gw
cp "$REPO/board/fleet/uwbd-site.acl" site.acl
: > site.passwd
/usr/bin/mosquitto_passwd -b site.passwd SUB042-T1 secret-of-t1
sed -e "s|^listener 1883 192.0.2.1$|listener $gateway_port 127.0.0.1|" \
    -e "s|^password_file .*|password_file $work/site.passwd|" \
    -e "s|^acl_file .*|acl_file $work/site.acl|" \
    -e "s|^persistence_location .*|persistence_location $work/gw/|" \
    -e "s|^address mqtt-central.example.net:8883$|address 127.0.0.1:$central_port|" \
    -e '/^bridge_cafile /d' -e '/^bridge_certfile /d' -e '/^bridge_keyfile /d' \
    "$REPO/board/fleet/mosquitto-site-gateway.conf" > gateway.conf
echo "user $me" >> gateway.conf
# Only what was meant changed: the addresses, the paths, the three TLS lines, the user.
changed=$(diff "$REPO/board/fleet/mosquitto-site-gateway.conf" gateway.conf | grep -c '^[<>]' || true)
[[ $changed == 14 ]] || fail "the test's copy differs from the recipe in $changed lines: $(diff "$REPO/board/fleet/mosquitto-site-gateway.conf" gateway.conf)"

/usr/sbin/mosquitto -v -c gateway.conf > gateway.log 2>&1 &
pids+=($!)
wait_for grep -q "listen socket on port $gateway_port" gateway.log || fail "the gateway config does not load: $(cat gateway.log)"
grep -qi "error" gateway.log && fail "the gateway logged an error: $(cat gateway.log)"
wait_for grep -q "as SITE-gateway " central.log || fail "the bridge never reached the central broker: $(cat gateway.log)"
wait_for grep -q "uwbd-bridges/SITE/state" central.log ||
    fail "no bridge notification at the centre: $(cat central.log)"
pass "board/fleet gateway config loads in $(/usr/sbin/mosquitto -h 2>&1 | head -1 | cut -d' ' -f1-3);" \
     "its bridge reaches the central broker as SITE-gateway"
echo "$passed passed"
