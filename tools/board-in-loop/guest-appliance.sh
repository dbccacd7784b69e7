#!/bin/sh
# shellcheck shell=dash
# Job of the appliance boot: the aarch64 uwbd daemon on the emulated board,
# wired to the emulated board (uwbemu) on the host through three PCI UARTs:
#   $DIGITISER_TTY  digitiser frames  (serial:, the production driver)
#   $GPIO_TTY       emulated-GPIO protocol (the five lines)
#   $CONTROL_TTY    uwbemu's control endpoint (to move the winding)
# It commissions a baseline, asks the board to shift the winding by
# $SHIFT_M metres, scans again, and prints every reply on the console as
#   BOARD-REPLY NAME STATUS JSON
# for the host script to check. Settings come from /etc/board/appliance.env,
# among them the carriage's microsteps per mm, which the host gives uwbemu
# too.
# shellcheck source=/dev/null
. /etc/board/appliance.env

ctl() {
    uwbd ctl --socket run/control.sock "$@"
}

uptime_s() {
    cut -d' ' -f1 /proc/uptime
}

# Prints "BOARD-REPLY NAME EXIT_STATUS REPLY" for one uwbd ctl command,
# and how long it took (guest clock) on a line of its own.
reply() {
    name=$1
    shift
    began=$(uptime_s)
    # stdout is the one reply line; stderr carries uwbd ctl scan's PROGRESS
    # lines and, on failure, the reason.
    out=$(ctl "$@" 2>run/ctl.err)
    status=$?
    [ $status -ne 0 ] && [ -z "$out" ] && out=$(tail -n 1 run/ctl.err)
    echo "BOARD-REPLY $name $status $out"
    echo "BOARD: $name: $(grep -c '"PROGRESS"' run/ctl.err) progress lines on stderr"
    echo "BOARD: $name took $(awk -v a="$began" -v b="$(uptime_s)" 'BEGIN { printf "%.1f", b - a }') s"
    return $status
}

show_daemon_log() {
    sed 's/^/BOARD-LOG /' /var/log/uwbd.log
}

# One command to uwbemu's control endpoint over its UART; prints the reply.
board_control() {
    stty -F "$CONTROL_TTY" 115200 raw -echo -echoe -echok -echoctl -echoke || return 1
    exec 3<>"$CONTROL_TTY"
    printf '%s\n' "$1" >&3
    line=""
    # busybox's read has -t, dash's has not.
    # shellcheck disable=SC3045
    read -r -t 30 line <&3
    exec 3<&-
    echo "BOARD-REPLY emu-control 0 $line"
    case "$line" in *'"class":"OK"'*) return 0 ;; esac
    return 1
}

# Stamps each line of the daemon's log with the guest's uptime: the log
# itself has no clock, and the stamps show where a scan spends its time.
stamp_lines() {
    while IFS= read -r text; do
        echo "$(uptime_s) $text"
    done
}

mkdir -p /var/lib/uwbd/run
cd /var/lib/uwbd || exit 1
mkfifo /run/uwbd-log
stamp_lines </run/uwbd-log >/var/log/uwbd.log &
# The sample configuration for the emulated board, with the digitiser and
# the GPIO protocol moved from unix sockets to the UARTs.
uwbd --config /etc/uwbd/uwbd.json --allow-root \
     --set "digitiser.endpoint=\"serial:$DIGITISER_TTY?baud=115200\"" \
     --set "gpio.endpoint=\"serial:$GPIO_TTY?baud=115200\"" \
     --set "carriage.steps_per_mm=$STEPS_PER_MM" \
     -v >/run/uwbd-log 2>&1 &
daemon=$!

tries=0
until ctl status >/dev/null 2>&1; do
    tries=$((tries + 1))
    if [ $tries -gt 600 ] || ! kill -0 $daemon 2>/dev/null; then
        echo "BOARD-REPLY daemon-start 1 the daemon did not answer on its control socket"
        show_daemon_log
        exit 1
    fi
    sleep 0.1
done
echo "BOARD-REPLY daemon-start 0 up after $tries polls"

failed=0
reply status status || failed=1
reply baseline-set baseline set || failed=1
reply baseline-scan scan || failed=1
board_control "set displacement_m $SHIFT_M" || failed=1
reply shifted-scan scan || failed=1
reply history history 5 || failed=1

kill -TERM $daemon
wait $daemon
echo "BOARD-REPLY daemon-exit $? after SIGTERM"
wait
show_daemon_log
find /var/lib/uwbd/run/state -type f | sort | sed 's/^/BOARD-STATE /'
exit $failed
