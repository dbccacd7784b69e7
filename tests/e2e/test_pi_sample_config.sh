#!/usr/bin/env bash
# The Raspberry Pi 4 sample config (board/raspberry-pi-4/uwbd.json, the
# package's /etc/uwbd/uwbd.json) passes --check-config as shipped, and with
# the alarm contacts, the event input and Modbus RTU switched on: it carries
# their lines and endpoint, so turning one on is one word (issue 31, 4).
# control.group is emptied: this machine need not have the group uwbd.
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }
config=board/raspberry-pi-4/uwbd.json
uwbd() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" "$@"; }

out=$(uwbd --check-config "$config" --set 'control.group=""' 2>&1) || fail "as shipped: $out"
echo "PASS: $config passes --check-config as shipped"

out=$(uwbd --check-config "$config" --set 'control.group=""' --set site.asset_id=T1 \
    --set contacts.enabled=true --set event.enabled=true --set modbus.enabled=true 2>&1) ||
    fail "with contacts, event and modbus on: $out"
echo "PASS: $config passes --check-config with contacts, event input and Modbus on"

# On, the keys are what the pin map says: RTU on the RS-485 port.
grep -q '"endpoint": "serial:/dev/uwb-rs485?baud=[0-9]*"' "$config" ||
    fail "modbus.endpoint is not the RS-485 port of pinmap.md"
echo "PASS: modbus.endpoint is the RS-485 port"
