#!/usr/bin/env bash
# Modbus through the full stack (uwbemu + uwbd + a libmodbus master,
# tests/e2e/helpers/modbus_client.c): RTU over a unix socket the daemon
# connects to (libserialport cannot open ptys), then Modbus TCP on a free
# 127.0.0.1 port after a reload; the registers after each verdict equal
# that verdict's JSON in 0.01 mm, a bulge's radial change included; the
# `event` coil starts a scan; `ack` is refused while not wired; registers
# are read-only; another RTU unit is not answered; four idle TCP masters do not lock a fifth out; disabling closes
# the port; enabling without an endpoint is refused at --check-config naming
# the key.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-modbus

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
json_edit "$config" "$config" 'baseline={"scans":1}'
ctl() { uwbd ctl --socket run/control.sock "$@"; }
emu() { uwbemu --ctl unix:run/emu.sock "$@"; }
mbc() { $HOST_PREFIX "$HOST_BUILD/e2e/modbus_client" "$@"; }
# The TCP sockets uwbd holds: its socket inodes found in /proc/net/tcp*.
tcp_sockets() {
    local inode count=0 tables=(/proc/net/tcp)
    [[ -r /proc/net/tcp6 ]] && tables+=(/proc/net/tcp6)
    for inode in $(ls -l /proc/"$daemon_pid"/fd 2>/dev/null | sed -n 's/.*socket:\[\([0-9]*\)\].*/\1/p'); do
        if awk -v i="$inode" 'NR > 1 && $10 == i { found = 1 } END { exit !found }' "${tables[@]}"; then
            count=$((count + 1))
        fi
    done
    echo "$count"
}

# ---- --check-config names the key --------------------------------------------
json_edit "$config" no-endpoint.json 'modbus={"enabled":true}'
rc=0
uwbd --check-config no-endpoint.json > check.out 2>&1 || rc=$?
[[ $rc == 78 ]] && grep -q 'modbus.endpoint' check.out || fail "enabled without endpoint: exit $rc: $(cat check.out)"
json_edit "$config" bad-endpoint.json 'modbus={"enabled":true,"endpoint":"udp:1.2.3.4:502"}'
rc=0
uwbd --check-config bad-endpoint.json > check2.out 2>&1 || rc=$?
[[ $rc == 78 ]] && grep -q 'modbus.endpoint' check2.out && grep -q "unknown scheme 'udp'" check2.out ||
    fail "a bad endpoint: exit $rc: $(cat check2.out)"
json_edit "$config" bad-unit.json 'modbus={"enabled":true,"endpoint":"tcp:127.0.0.1:1502","unit_id":248}'
rc=0
uwbd --check-config bad-unit.json > check3.out 2>&1 || rc=$?
[[ $rc == 78 ]] && grep -q 'modbus.unit_id' check3.out || fail "unit 248: exit $rc: $(cat check3.out)"
pass "--check-config refuses modbus.enabled without modbus.endpoint, a bad endpoint and unit 248, naming the key"
# Issue 43, break 5: an RTU line's parity and stop bits (8E1 is the Modbus
# serial line standard's default) were refused as "baud must be a positive number".
for framing in parity=even parity=odd parity=none "parity=none&stopbits=2" "stopbits=2&parity=even"; do
    json_edit "$config" framed.json "modbus={\"enabled\":true,\"endpoint\":\"serial:/dev/ttyUSB0?baud=19200&$framing\",\"unit_id\":7}"
    rc=0
    uwbd --check-config framed.json > check4.out 2>&1 || rc=$?
    [[ $rc == 0 ]] || fail "RTU at 19200 baud with $framing: exit $rc: $(cat check4.out)"
done
json_edit "$config" mark.json 'modbus={"enabled":true,"endpoint":"serial:/dev/ttyUSB0?baud=19200&parity=mark"}'
rc=0
uwbd --check-config mark.json > check5.out 2>&1 || rc=$?
[[ $rc == 78 ]] && grep -q 'modbus.endpoint' check5.out && grep -q 'parity must be none, even or odd' check5.out ||
    fail "parity=mark: exit $rc: $(cat check5.out)"
pass "--check-config takes an RTU line's parity (none, even, odd) and stop bits (1, 2); parity=mark refused naming the key"

# verdict_matches DUMP_LINE VERDICT_JSON: every figure of the verdict in the registers.
status_code() {
    case $1 in edges) echo 1 ;; ok) echo 2 ;; watch) echo 3 ;; alarm) echo 4 ;; inconclusive) echo 5 ;;
        error) echo 6 ;; *) echo 0 ;; esac
}
field() { tr ' ' '\n' <<<"$1" | sed -n "s/^$2=//p"; }
hundredths() {   # mm from the JSON ("(missing)" -> none) as the register reads it
    [[ $1 == "(missing)" ]] && { echo none; return; }
    awk -v v="$1" 'BEGIN { x = v * 100; printf "%d\n", (x < 0 ? x - 0.5 : x + 0.5) }'
}
verdict_matches() {
    local dump=$1 verdict=$2 key reg want got
    want=$(status_code "$(json_get status < "$verdict")")
    [[ $(field "$dump" status) == "$want" ]] || { echo "status: $(field "$dump" status), verdict $want"; return 1; }
    for pair in axial_displacement_mm:displacement uncertainty_mm:sigma height_change_mm:height_change \
        lower_edge_mm:lower_edge upper_edge_mm:upper_edge; do
        key=${pair%%:*} reg=${pair##*:}
        want=$(hundredths "$(json_get "$key" < "$verdict")")
        got=$(field "$dump" "$reg")
        [[ $got == "$want" ]] || { echo "$reg: $got, verdict $key gives $want"; return 1; }
    done
    want=$(status_code "$(json_get radial.status < "$verdict")")
    [[ $(field "$dump" radial_status) == "$want" ]] ||
        { echo "radial_status: $(field "$dump" radial_status), verdict $want"; return 1; }
    for pair in radial.max_change_mm:radial_change radial.uncertainty_mm:radial_sigma radial.at_mm:radial_at \
        radial.tilt_mm:radial_tilt radial.tilt_uncertainty_mm:radial_tilt_sigma; do
        key=${pair%%:*} reg=${pair##*:}
        want=$(hundredths "$(json_get "$key" < "$verdict")")
        got=$(field "$dump" "$reg")
        [[ $got == "$want" ]] || { echo "$reg: $got, verdict $key gives $want"; return 1; }
    done
    want=$(date -u -d "$(json_get created < "$verdict")" +%s)
    [[ $(field "$dump" scan_time) == "$want" ]] || { echo "scan_time: $(field "$dump" scan_time), created $want"; return 1; }
    [[ $(field "$dump" version) == 3 ]] || { echo "map version $(field "$dump" version)"; return 1; }
}

start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7
wait_for emu status || fail "uwbemu does not answer"

# ---- RTU over the socket endpoint -------------------------------------------
json_edit "$config" "$config" 'modbus={"enabled":true,"endpoint":"unix:run/modbus.sock","unit_id":7}'
mbc rtu-listen run/modbus.sock 7 dump coil=1:1 wait-count=1 dump coils coil=0:1 write-register \
    unit=9 probe unit=7 probe probe > rtu.out 2> rtu.err &
rtu_pid=$!
pids+=($rtu_pid)
wait_for test -S run/modbus.sock || fail "modbus_client does not listen: $(cat rtu.err)"
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" -v > uwbd.log 2>&1 &
daemon_pid=$!
pids+=($daemon_pid)
wait_for ctl status || fail "uwbd does not answer: $(tail -5 uwbd.log)"
wait "$rtu_pid" || fail "RTU master: $(cat rtu.err) $(cat rtu.out)"
ctl verdict > rtu-verdict.json
before=$(sed -n 1p rtu.out)
[[ $(field "$before" status) == 0 && $(field "$before" scan_count) == 0 && $(field "$before" displacement) == none &&
   $(field "$before" lower_edge) == none && $(field "$before" radial_status) == 0 &&
   $(field "$before" radial_change) == none && $(field "$before" radial_at) == none ]] ||
    fail "RTU before any verdict: $before"
after=$(sed -n 3p rtu.out)
[[ $(sed -n 2p rtu.out) == "coil 1=1: ok" ]] || fail "event coil: $(cat rtu.out)"
[[ $(field "$after" scan_count) == 1 ]] || fail "RTU after the event scan: $after"
[[ $(field "$after" contacts) == 0 ]] || fail "contacts register without contacts configured: $after"
why=$(verdict_matches "$after" rtu-verdict.json) || fail "RTU registers vs the verdict: $why: $after / $(cat rtu-verdict.json)"
grep -q 'modbus: event coil: scan requested' uwbd.log || fail "the event coil did not reach the daemon"
[[ $(sed -n 4p rtu.out) == "coils=00" ]] || fail "coils read back: $(sed -n 4p rtu.out)"
[[ $(sed -n 5p rtu.out) == "coil 0=1: Slave device or server failure" ]] ||
    fail "ack coil without contacts to acknowledge: $(sed -n 5p rtu.out)"
json_check rtu-verdict.json "trigger == event" || fail "the event coil's verdict does not say event: $(cut -c1-300 rtu-verdict.json)"
[[ $(sed -n 6p rtu.out) == "write-register: Illegal function" ]] || fail "register write: $(sed -n 6p rtu.out)"
[[ $(sed -n 7p rtu.out) == "probe: Connection timed out" ]] || fail "unit 9 answered: $(sed -n 7p rtu.out)"
# On a bus, unit 9's answer follows its request, and libmodbus's RTU server
# skips that one frame; with no unit 9 the next request is the frame skipped,
# as a master's retry covers.
[[ $(sed -n 9p rtu.out) == "probe: ok" ]] || fail "unit 7 after unit 9: $(sed -n 8,9p rtu.out)"
pass "RTU unit 7 over unix:: registers = the verdict ($after); event coil scanned (trigger event); ack refused" \
     "(no contacts configured); registers read-only; unit 9 not answered"

# ---- Modbus TCP on 127.0.0.1 after a reload -----------------------------------
port=$(mbc freeport)
json_edit "$config" "$config" "modbus.endpoint=\"tcp:127.0.0.1:$port\""
kill -HUP "$daemon_pid"
wait_for mbc tcp 127.0.0.1 "$port" probe > /dev/null 2>&1 || fail "no Modbus TCP on $port after the reload: $(tail -5 uwbd.log)"
ctl baseline set > /dev/null
ctl scan > base.json || fail "baseline scan: $(cat base.json)"
emu 'set displacement_m 0.004' > /dev/null
ctl scan > moved.json || fail "4 mm scan: $(cat moved.json)"
json_check moved.json 'axial_displacement_mm exists' 'uncertainty_mm exists' 'height_change_mm exists' ||
    fail "no compared verdict: $(cat moved.json)"
mbc tcp 127.0.0.1 "$port" dump coil=1:1 wait-count=4 dump coil=0:1 write-register > tcp.out 2> tcp.err ||
    fail "TCP master: $(cat tcp.err)"
first=$(sed -n 1p tcp.out)
[[ $(field "$first" scan_count) == 3 ]] || fail "TCP scan counter after 3 verdicts: $first"
(( ($(field "$first" health) & 8) != 0 )) || fail "TCP health without the baseline bit: $first"
why=$(verdict_matches "$first" moved.json) || fail "TCP registers vs the verdict: $why: $first / $(cat moved.json)"
ctl verdict > event.json
last=$(sed -n 3p tcp.out)
why=$(verdict_matches "$last" event.json) || fail "TCP after the event scan: $why: $last / $(cat event.json)"
[[ $(sed -n 4p tcp.out) == "coil 0=1: Slave device or server failure" && $(sed -n 5p tcp.out) == "write-register: Illegal function" ]] ||
    fail "TCP refusals: $(cat tcp.out)"
[[ $(tcp_sockets) -ge 1 ]] || fail "no TCP socket held while Modbus TCP is on (the check below would prove nothing)"
pass "Modbus TCP on 127.0.0.1:$port after SIGHUP: a 4 mm verdict in the registers ($first); event coil scanned"

# A bulge of disks 4-6 (uwbemu's radial change) and no axial move: the
# radial change's registers (15-20) hold the verdict's radial object.
emu 'set displacement_m 0' > /dev/null
emu 'set radial 4 6 8' > /dev/null
ctl scan > bulged.json || fail "bulge scan: $(cat bulged.json)"
json_check bulged.json 'radial.max_change_mm exists' 'radial.at_mm exists' || fail "no radial change measured: $(cat bulged.json)"
mbc tcp 127.0.0.1 "$port" dump > bulge.out 2> bulge.err || fail "TCP master: $(cat bulge.err)"
bulge=$(sed -n 1p bulge.out)
[[ $(field "$bulge" radial_change) != none && $(field "$bulge" radial_status) != 0 ]] ||
    fail "no radial change in the registers: $bulge"
why=$(verdict_matches "$bulge" bulged.json) || fail "TCP registers vs the bulge's verdict: $why: $bulge / $(cat bulged.json)"
# Disks 4-6 are the scene's top three: the change reaches the face's end,
# where no lean can be read: the tilt withheld, its register "none", not 0.
json_check bulged.json 'radial.tilt_mm absent' 'radial.tilt_uncertainty_mm absent' 'radial.tilt_withheld exists' ||
    fail "a bulge at the face's end gives a tilt: $(cat bulged.json)"
[[ $(field "$bulge" radial_tilt) == none ]] || fail "tilt withheld, yet register 20 reads $(field "$bulge" radial_tilt)"
[[ $(field "$bulge" radial_tilt_sigma) == none ]] ||
    fail "tilt withheld, yet register 21 reads $(field "$bulge" radial_tilt_sigma)"
emu 'set radial 4 6 0' > /dev/null
pass "a bulge of disks 4-6 by 8 mm: radial registers = the verdict's radial object, the tilt withheld ($bulge)"

# ---- issue 27, break 1: four idle masters do not lock Modbus out ----------------
# Four connections that say nothing (bash's /dev/tcp) hold every slot; past
# 2 s idle, a fifth master evicts the longest-idle and is answered (it was
# refused for good: "a TCP master refused: 4 already connected").
exec 3<> "/dev/tcp/127.0.0.1/$port" 4<> "/dev/tcp/127.0.0.1/$port" 5<> "/dev/tcp/127.0.0.1/$port" \
    6<> "/dev/tcp/127.0.0.1/$port"
sleep 2.5
mbc tcp 127.0.0.1 "$port" probe > fifth.out 2>&1 || fail "a fifth master behind four idle ones: $(cat fifth.out)"
grep -q "dropping one idle" uwbd.log || fail "no log line for the evicted idle master"
exec 3>&- 4>&- 5>&- 6>&-
pass "four idle Modbus TCP masters held: a fifth is answered ($(grep -o 'dropping one idle.*' uwbd.log | head -n 1))"

# ---- disabled: nothing listens --------------------------------------------------
json_edit "$config" "$config" 'modbus.enabled=false'
kill -HUP "$daemon_pid"
closed() { ! mbc tcp 127.0.0.1 "$port" probe > /dev/null 2>&1; }
wait_for closed || fail "port $port still answers with modbus.enabled false"
# ...and the daemon holds no TCP socket at all.
[[ $(tcp_sockets) == 0 ]] || fail "uwbd holds $(tcp_sockets) TCP socket(s) with modbus.enabled false"
kill -TERM "$daemon_pid"
wait "$daemon_pid" || fail "uwbd exit $? at SIGTERM"
pass "modbus.enabled false on reload: port $port closed, no TCP socket held (one or more while on)"
echo "$passed passed"
