#!/usr/bin/env bash
# make test-board: the aarch64 build on an emulated ARM board (qemu's virt
# machine, Debian's arm64 kernel), its drivers against real kernel drivers.
#
#   drivers boot  tests/board/test_* (Unity) in the guest: the libgpiod
#                 backend against the virt machine's PL061 GPIO chip, the
#                 serial: link (libserialport) through a PCI 16550 UART to
#                 HOST_BUILD_DIR/e2e/unix_peer invert on the host.
#   appliance     the aarch64 uwbd daemon in the guest, its digitiser on
#   boot          /dev/ttyS0 (serial:, libserialport) and the emulated-GPIO
#                 protocol on /dev/ttyS1, both joined to the emulated board
#                 (HOST_BUILD_DIR/uwbemu) on the host; uwbemu's control
#                 endpoint on /dev/ttyS2. Baseline, +12 mm shift, scan: the
#                 verdict, read back from the console, must be within 0.5 mm.
#
# Prints one line per test program, like tests/run-tests.sh, and closes
# with "N passed, N failed". Fails, never skips, when the emulator or the
# guest's parts are missing.
#
# Usage: tools/board-in-loop/test-board.sh HOST_BUILD_DIR ARM_BUILD_DIR
#   ARM_BUILD_DIR holds the aarch64 build (make CROSS_COMPILE=aarch64-linux-gnu-
#   ... all board-tests): uwbd and board-tests/test_*; HOST_BUILD_DIR the
#   native one with uwbemu and e2e/{unix_peer,json_check,state_check}.
# Knobs: UWB_BOARD_BOOT_TIMEOUT (seconds per boot, default 240),
#        UWB_BOARD_KEEP=1 (keep the work directory: console logs, initramfs),
#        UWB_TEST_VERBOSE=1 (print every guest test's full output).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
readonly HERE
readonly BOOT_TIMEOUT="${UWB_BOARD_BOOT_TIMEOUT:-240}"
readonly VERBOSE="${UWB_TEST_VERBOSE:-0}"
readonly TAIL_LINES=40
# The appliance boot's emulated scene: the winding alone with the direct
# coupling and 50 dB of noise (as in tests/e2e/test_daemon_emulated.sh),
# moved up by SHIFT_MM for the second scan.
readonly SCENE=tools/uwbsim/scenes/winding-only-3d.json
readonly SCENE_SETTINGS=(--set coupling_gain=0.05 --set noise=true --set snr_db=50 --seed 7)
readonly SHIFT_MM=12
# Each microstep is two lines of the emulated-GPIO protocol on a UART that
# qemu emulates byte by byte; at the sample config's 100 steps/mm a scan
# is 63,000 steps and takes minutes. 10 steps/mm (a coarser lead screw:
# 0.1 mm a step, still far finer than the 30 mm between positions) makes
# the same moves with a tenth of the edges. The daemon and uwbemu are
# both told.
readonly STEPS_PER_MM=10
readonly SAMPLE_CONFIG=board/emulated/uwbd.json
# The sample with 4 pulses per position and one scan per baseline: every
# frame crosses a 115200-baud UART byte by byte, and the sample's 64 pulses
# and 4 commissioning scans would take the guest tens of minutes. The
# daemon, the initramfs and check-appliance.sh all use this copy
# (DAEMON_CONFIG, written into the work directory).
readonly BOARD_STACK=4
DAEMON_CONFIG=""

total_passed=0
total_failed=0
work=""
# Host processes started in the background, stopped on any exit.
background_pids=()

cleanup() {
    local pid
    for pid in "${background_pids[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${background_pids[@]}"; do
        wait "$pid" 2>/dev/null || true
    done
    if [[ -n "$work" && "${UWB_BOARD_KEEP:-0}" != 1 ]]; then
        rm -rf "$work"
    fi
}

usage() {
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
}

elapsed_since() {
    awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f s", b - a }'
}

indent() {
    sed 's/^/    /'
}

# One failure that is not a guest test case: a missing part, a boot that
# never came up.
fail_step() {
    local name="$1" problem="$2"
    total_failed=$((total_failed + 1))
    echo "FAIL  board/$name: $problem"
}

show_tail() {
    local file="$1"
    if [[ -s "$file" ]]; then
        echo "    --- last $TAIL_LINES lines of $(basename "$file"):"
        tail -n "$TAIL_LINES" "$file" | indent
    else
        echo "    --- $(basename "$file") is empty"
    fi
}

# The console log with the tty's carriage returns removed.
clean_console() {
    tr -d '\r' <"$1"
}

# Reads the BOARD-BEGIN/BOARD-END sections of a console log and prints a
# PASS or FAIL line per test program, counting Unity's test cases.
report_guest_tests() {
    local console="$1" expected=("${@:2}")
    local clean="$console.clean"
    clean_console "$console" >"$clean"
    local name section status summary tests failures ignored passed failed problem
    for name in "${expected[@]}"; do
        section="$(awk -v n="$name" '$0 == "BOARD-BEGIN " n { on = 1; next }
                                     on && index($0, "BOARD-END " n " ") == 1 { print; exit }
                                     on { print }' "$clean")"
        status="$(sed -n "s/^BOARD-END $name status=\\([0-9]*\\)$/\\1/p" "$clean" | tail -n 1)"
        summary="$(grep -E '^[0-9]+ Tests [0-9]+ Failures [0-9]+ Ignored' <<<"$section" | tail -n 1 || true)"
        problem=""
        if ! grep -qx "BOARD-BEGIN $name" "$clean"; then
            passed=0 failed=1 problem="never started in the guest"
        elif [[ -z "$summary" ]]; then
            passed="$(grep -c ':PASS$' <<<"$section" || true)"
            failed=$(($(grep -c ':FAIL' <<<"$section" || true) + 1))
            problem="ended without a Unity summary (exit status ${status:-unknown: no end marker})"
        else
            read -r tests _ failures _ ignored _ <<<"$summary"
            passed=$((tests - failures - ignored))
            failed=$failures
            if [[ "$status" != 0 && "$failures" == 0 ]]; then
                problem="exit status ${status:-unknown} after its summary"
                failed=1
                passed=$((passed > 0 ? passed - 1 : 0))
            fi
        fi
        total_passed=$((total_passed + passed))
        total_failed=$((total_failed + failed))
        if [[ "$failed" == 0 ]]; then
            echo "PASS  board/$name  ($passed ok)"
            if [[ "$VERBOSE" == 1 ]]; then indent <<<"$section"; fi
        else
            echo "FAIL  board/$name  ($passed ok, $failed failing)${problem:+: $problem}"
            if [[ "$VERBOSE" == 1 || -n "$problem" ]]; then
                tail -n "$TAIL_LINES" <<<"$section" | indent
            else
                grep -E ':FAIL' <<<"$section" | indent || true
            fi
        fi
    done
}

# Checks a boot's console: the guest came up and its job ended. Prints a
# FAIL line and returns 1 otherwise.
check_boot() {
    local name="$1" console="$2" qemu_status="$3"
    local clean="$console.clean"
    clean_console "$console" >"$clean"
    if ! grep -q '^BOARD: booted' "$clean"; then
        fail_step "$name" "the guest never reached its init (qemu exit status $qemu_status)"
        show_tail "$clean"
        return 1
    fi
    if ! grep -q '^BOARD: job finished' "$clean"; then
        local why="qemu exit status $qemu_status"
        [[ "$qemu_status" == 124 ]] && why="timed out after $BOOT_TIMEOUT s"
        fail_step "$name" "the guest's job did not finish ($why)"
        show_tail "$clean"
        return 1
    fi
    return 0
}

# The drivers boot: tests/board programs with the serial peer on ttyS0.
run_drivers_boot() {
    local work="$1" arm_build="$2" host_build="$3"
    local programs=("$arm_build"/board-tests/test_*)
    if [[ ! -x "${programs[0]}" ]]; then
        fail_step drivers "no test programs in $arm_build/board-tests (make ... board-tests)"
        return
    fi
    local names=() program initrd_args=()
    for program in "${programs[@]}"; do
        names+=("$(basename "$program")")
        initrd_args+=(--program "$program")
    done
    local initrd="$work/drivers.cpio.gz"
    if ! bash "$HERE/make-initramfs.sh" --out "$initrd" --busybox "$BUSYBOX" \
        --init "$HERE/guest-init.sh" --file "$HERE/guest-tests.sh=/etc/board/job" "${initrd_args[@]}" \
        2>"$work/initramfs.log"; then
        fail_step drivers "packing the initramfs failed"
        show_tail "$work/initramfs.log"
        return
    fi

    local start="$EPOCHREALTIME" console="$work/drivers-console.log"
    local digitiser_socket="$work/drivers-ttyS0.sock" spare_socket="$work/drivers-ttyS1.sock"
    timeout -k 5 "$BOOT_TIMEOUT" bash "$HERE/boot-guest.sh" --kernel "$KERNEL" --initrd "$initrd" \
        --uart "$digitiser_socket:qemu" --uart "$spare_socket:qemu" >"$console" 2>&1 &
    local qemu_pid=$!
    background_pids+=("$qemu_pid")
    "$host_build/e2e/unix_peer" invert "$digitiser_socket" 30 2>"$work/serial-peer.log" &
    local peer_pid=$!
    background_pids+=("$peer_pid")
    local qemu_status=0
    wait "$qemu_pid" || qemu_status=$?
    # qemu closed the socket: the peer sees the end and exits by itself.
    wait "$peer_pid" || true
    echo "      drivers boot: $(elapsed_since "$start"), $(cat "$work/serial-peer.log" 2>/dev/null)"
    if check_boot drivers "$console" "$qemu_status"; then
        report_guest_tests "$console" "${names[@]}"
    else
        # The tests it would have run count as failed too, so a broken boot
        # never looks like fewer tests.
        total_failed=$((total_failed + ${#names[@]}))
    fi
}

# Waits up to 20 s for a unix socket to appear.
wait_for_socket() {
    local socket="$1" tries
    for ((tries = 0; tries < 200; tries++)); do
        [[ -S "$socket" ]] && return 0
        sleep 0.1
    done
    return 1
}

# The appliance boot: uwbd in the guest, uwbemu on the host.
run_appliance_boot() {
    local work="$1" host_build="$2" arm_build="$3"
    local name=appliance
    if [[ ! -x "$arm_build/uwbd" ]]; then
        fail_step "$name" "no aarch64 daemon $arm_build/uwbd"
        return
    fi
    if [[ ! -x "$host_build/uwbemu" ]]; then
        fail_step "$name" "no emulated board $host_build/uwbemu"
        return
    fi
    local env_file="$work/appliance.env"
    cat >"$env_file" <<ENV
DIGITISER_TTY=/dev/ttyS0
GPIO_TTY=/dev/ttyS1
CONTROL_TTY=/dev/ttyS2
SHIFT_M=$(awk -v mm="$SHIFT_MM" 'BEGIN { print mm / 1000 }')
STEPS_PER_MM=$STEPS_PER_MM
ENV
    DAEMON_CONFIG="$work/uwbd-board.json"
    if ! "$host_build/e2e/json_edit" "$SAMPLE_CONFIG" "$DAEMON_CONFIG" "digitiser.stack=$BOARD_STACK" \
        'baseline={"scans":1}' 2>"$work/config.log"; then
        fail_step "$name" "cannot write the board's config: $(cat "$work/config.log")"
        return
    fi
    local initrd="$work/appliance.cpio.gz"
    if ! bash "$HERE/make-initramfs.sh" --out "$initrd" --busybox "$BUSYBOX" \
        --init "$HERE/guest-init.sh" --file "$HERE/guest-appliance.sh=/etc/board/job" \
        --file "$env_file=/etc/board/appliance.env" --file "$DAEMON_CONFIG=/etc/uwbd/uwbd.json" \
        --program "$arm_build/uwbd" 2>"$work/initramfs.log"; then
        fail_step "$name" "packing the initramfs failed"
        show_tail "$work/initramfs.log"
        return
    fi

    local start="$EPOCHREALTIME"
    local gpio_socket="$work/gpio.sock" digitiser_socket="$work/digitiser.sock" control_socket="$work/emu.sock"
    "$host_build/uwbemu" --gpio "unix:$gpio_socket" --digitiser "unix:$digitiser_socket" \
        --control "unix:$control_socket" --scene "$SCENE" "${SCENE_SETTINGS[@]}" \
        --steps-per-mm "$STEPS_PER_MM" >"$work/uwbemu.log" 2>&1 &
    local emu_pid=$!
    background_pids+=("$emu_pid")
    local socket
    for socket in "$gpio_socket" "$digitiser_socket" "$control_socket"; do
        if ! wait_for_socket "$socket"; then
            fail_step "$name" "uwbemu did not listen on $socket"
            show_tail "$work/uwbemu.log"
            kill "$emu_pid" 2>/dev/null || true
            wait "$emu_pid" 2>/dev/null || true
            return
        fi
    done

    # The emulated board listens; qemu connects to it (and would reconnect).
    local console="$work/appliance-console.log" qemu_status=0
    timeout -k 5 "$BOOT_TIMEOUT" bash "$HERE/boot-guest.sh" --kernel "$KERNEL" --initrd "$initrd" \
        --uart "$digitiser_socket:host" --uart "$gpio_socket:host" --uart "$control_socket:host" \
        >"$console" 2>&1 || qemu_status=$?
    "$host_build/uwbemu" --ctl "unix:$control_socket" status >"$work/uwbemu-status.json" 2>>"$work/uwbemu.log" || true
    "$host_build/uwbemu" --ctl "unix:$control_socket" quit >/dev/null 2>&1 || kill "$emu_pid" 2>/dev/null || true
    wait "$emu_pid" 2>/dev/null || true
    echo "      appliance boot: $(elapsed_since "$start")"

    if ! check_boot "$name" "$console" "$qemu_status"; then
        return
    fi
    local positions stack checks status=0
    { read -r positions; read -r stack; } < <("$host_build/e2e/state_check" get scan.positions digitiser.stack \
        < "$DAEMON_CONFIG")
    checks="$(bash "$HERE/check-appliance.sh" "$host_build" "$console.clean" "$work/uwbemu-status.json" \
        "$SHIFT_MM" "$positions" "$stack")" || status=$?
    echo "$checks"
    total_passed=$((total_passed + $(grep -c '^PASS' <<<"$checks" || true)))
    total_failed=$((total_failed + $(grep -c '^FAIL' <<<"$checks" || true)))
    if [[ "$status" != 0 ]] && ! grep -q '^FAIL' <<<"$checks"; then
        fail_step "$name" "check-appliance.sh ended with status $status"
    fi
    if [[ "$status" != 0 || "$VERBOSE" == 1 ]]; then
        echo "    --- guest console (daemon log lines start with BOARD-LOG):"
        tail -n 60 "$console.clean" | indent
        echo "    --- uwbemu log:"
        tail -n 20 "$work/uwbemu.log" | indent
    fi
}

main() {
    [[ $# == 2 ]] || usage
    local host_build="$1" arm_build="$2"
    [[ -d "$arm_build" ]] || { echo "test-board: $arm_build: no such build directory" >&2; exit 2; }
    [[ -d "$host_build" ]] || { echo "test-board: $host_build: no such build directory" >&2; exit 2; }
    cd "$HERE/../.."

    trap cleanup EXIT
    # Short: unix socket paths must fit in 108 bytes.
    work="$(mktemp -d /tmp/uwbd-board.XXXXXX)"
    if [[ "${UWB_BOARD_KEEP:-0}" == 1 ]]; then
        echo "test-board: keeping $work"
    fi

    local start="$EPOCHREALTIME"
    if ! command -v qemu-system-aarch64 >/dev/null; then
        fail_step qemu "qemu-system-aarch64 is not installed and could not be installed (Debian package qemu-system-arm)"
    elif [[ ! -x "$host_build/e2e/unix_peer" || ! -x "$host_build/e2e/json_check" || ! -x "$host_build/e2e/json_edit" ]]; then
        fail_step host "no $host_build/e2e/unix_peer, json_check or json_edit (host helpers; make tests builds them)"
    elif ! parts="$(bash "$HERE/fetch-guest.sh" 2>"$work/fetch.log")"; then
        fail_step guest-parts "could not fetch the arm64 kernel and busybox"
        show_tail "$work/fetch.log"
    else
        eval "$parts"   # KERNEL=… BUSYBOX=…
        run_drivers_boot "$work" "$arm_build" "$host_build"
        run_appliance_boot "$work" "$host_build" "$arm_build"
    fi
    echo "test-board: $(elapsed_since "$start") in all"
    echo "$total_passed passed, $total_failed failed"
    [[ "$total_failed" == 0 ]]
}

main "$@"
