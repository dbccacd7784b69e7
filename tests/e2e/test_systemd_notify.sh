#!/usr/bin/env bash
# Issue 19, item 3: systemd-native. With NOTIFY_SOCKET and WATCHDOG_USEC set
# as systemd sets them for Type=notify and WatchdogSec=, uwbd says READY=1
# and STATUS=, pings WATCHDOG=1 while healthy (during a scan too), says
# STOPPING=1 on SIGTERM; the pings stop when the scan worker or the main
# loop hangs (the test-only hook UWBD_TEST_HANG=worker|loop), so systemd
# would kill and restart it. The test plays systemd's end with
# build/e2e/notify_listen (a unix datagram socket).
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-notify

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
start_emulated_board

# A ping every 200 ms (half of WatchdogSec=0.4 s).
export WATCHDOG_USEC=400000
pings() { grep -c ' WATCHDOG=1$' "$1" || true; }

# start_daemon NAME [ENV=VALUE...]: a listener and a daemon; $listener, $daemon.
start_daemon() {
    local name=$1
    shift
    $HOST_PREFIX "$HOST_BUILD/e2e/notify_listen" "$work/run/$name.notify" "$name.notify.log" 120 &
    listener=$!
    pids+=($listener)
    wait_for test -S "run/$name.notify" || fail "$name: the notify listener did not come up"
    env NOTIFY_SOCKET="$work/run/$name.notify" "$@" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" \
        "${root_flag[@]}" -v > "$name.log" 2>&1 &
    daemon=$!
    pids+=($daemon)
    wait_for grep -q ' READY=1$' "$name.notify.log" || fail "$name: no READY=1"
    wait_for test -S run/control.sock || fail "$name: no control socket"
}

# ---- healthy: READY, STATUS, pings before, during and after a scan, STOPPING
start_daemon healthy
grep -q ' STATUS=idle; no verdict yet$' healthy.notify.log || fail "no STATUS=idle at start: $(cat healthy.notify.log)"
sleep 1
before=$(pings healthy.notify.log)
(( before >= 3 )) || fail "only $before watchdog pings in the first second"
uwbd ctl --socket run/control.sock scan > scan.json || fail "the scan failed: $(cat scan.json)"
json_check scan.json 'class == VERDICT' || fail "no verdict: $(cat scan.json)"
grep -q ' STATUS=scanning (cycle 1)$' healthy.notify.log || fail "no STATUS=scanning"
wait_for grep -q ' STATUS=idle; latest verdict ' healthy.notify.log || fail "no STATUS with the latest verdict"
sleep 0.6
after=$(pings healthy.notify.log)
(( after > before + 1 )) || fail "pings stopped during or after a healthy scan ($before, then $after)"
kill -TERM "$daemon"
wait "$daemon" || fail "SIGTERM: exit $?"
wait_for grep -q ' STOPPING=1$' healthy.notify.log || fail "no STOPPING=1"
pass "READY=1, STATUS= idle/scanning/latest verdict, WATCHDOG=1 ($after pings) through a scan, STOPPING=1"

# ---- the scan worker hangs: the main loop still answers, but stops pinging
start_daemon worker UWBD_TEST_HANG=worker UWBD_TEST_SCAN_STALL_S=1
sleep 0.6
(( $(pings worker.notify.log) >= 2 )) || fail "worker: no pings before the hang"
uwbd ctl --socket run/control.sock --timeout 1 scan > /dev/null 2>&1 || true
sleep 2   # the worker's 1 s allowance, and a tick
first=$(pings worker.notify.log)
uwbd ctl --socket run/control.sock status > status.json || fail "worker hang: the main loop does not answer"
json_check status.json 'state == scanning' || fail "worker hang: $(cat status.json)"
sleep 2
[[ $(pings worker.notify.log) == "$first" ]] || fail "worker hang: pings went on ($first, then $(pings worker.notify.log))"
grep -q 'silent for .* no more watchdog pings' worker.log || fail "worker hang: not logged: $(tail -3 worker.log)"
kill -KILL "$daemon"; wait "$daemon" 2> /dev/null || true
rm -f run/control.sock
pass "a hung scan worker: pings stop ($first, none in 2 s), the log says why, status still answers"

# ---- the main loop hangs: pings stop at once
start_daemon loop UWBD_TEST_HANG=loop
sleep 0.6
(( $(pings loop.notify.log) >= 2 )) || fail "loop: no pings before the hang"
uwbd ctl --socket run/control.sock --timeout 1 scan > /dev/null 2>&1 || true
sleep 0.5
first=$(pings loop.notify.log)
set +e
uwbd ctl --socket run/control.sock --timeout 1 status > /dev/null 2>&1
rc=$?
set -e
[[ $rc == 75 ]] || fail "loop hang: status got exit $rc, want 75 (no reply in time)"
sleep 1
[[ $(pings loop.notify.log) == "$first" ]] || fail "loop hang: pings went on ($first, then $(pings loop.notify.log))"
kill -KILL "$daemon"; wait "$daemon" 2> /dev/null || true
pass "a hung main loop: pings stop ($first, none for the next 1.5 s), status unanswered"
echo "$passed passed"
