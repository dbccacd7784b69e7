#!/usr/bin/env bash
# Boots the emulated board: qemu-system-aarch64's virt machine (Cortex-A53,
# TCG, no KVM) with Debian's arm64 kernel and an initramfs from
# make-initramfs.sh. The guest's console (PL011, ttyAMA0) is this script's
# standard output; the machine powers itself off when its job is done, and
# qemu exits then.
#
# Usage: tools/board-in-loop/boot-guest.sh --kernel FILE --initrd FILE \
#            [--uart SOCKET:MODE]... [--append TEXT] [-- QEMU_OPTIONS...]
#   --uart SOCKET:MODE  one 16550 UART on the PCI bus (qemu's pci-serial)
#                       whose other end is the unix socket SOCKET; the
#                       guest sees the first as /dev/ttyS0, the next as
#                       /dev/ttyS1 (the kernel's 8250 driver has 4 ports).
#        MODE qemu      qemu creates SOCKET and listens; the host program
#                       connects to it (bytes the guest sends before the
#                       program connects are dropped)
#        MODE host      a host program listens on SOCKET and qemu connects,
#                       retrying every second until it can, and again after
#                       the program drops the connection
#   --append TEXT       added to the kernel command line
set -euo pipefail

die() {
    echo "boot-guest: $*" >&2
    exit 1
}

usage() {
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
}

main() {
    local kernel="" initrd="" append="" uarts=() extra=()
    while [[ $# -gt 0 ]]; do
        case "$1" in
            --kernel) kernel="${2:?}"; shift 2 ;;
            --initrd) initrd="${2:?}"; shift 2 ;;
            --uart) uarts+=("${2:?}"); shift 2 ;;
            --append) append="${2:?}"; shift 2 ;;
            --) shift; extra=("$@"); break ;;
            *) usage ;;
        esac
    done
    [[ -n "$kernel" && -n "$initrd" ]] || usage
    [[ -f "$kernel" ]] || die "$kernel: no such kernel image"
    [[ -f "$initrd" ]] || die "$initrd: no such initramfs"
    command -v qemu-system-aarch64 >/dev/null ||
        die "qemu-system-aarch64 is not installed (Debian package qemu-system-arm; make test-board installs it)"

    local options=(
        -M virt -cpu cortex-a53 -m 512 -smp 1
        -accel tcg
        # Only the devices asked for: no network card (its option ROM is
        # in another package), no monitor on the console.
        -nodefaults -no-user-config -display none -serial stdio
        -no-reboot
        -kernel "$kernel" -initrd "$initrd"
        # quiet + loglevel=3: kernel messages stay off the console unless
        # they are errors, so the job's output is readable; panic=-1 with
        # -no-reboot ends qemu on a kernel panic instead of hanging.
        -append "console=ttyAMA0 quiet loglevel=3 panic=-1 $append"
    )
    local index=0 spec socket mode
    for spec in "${uarts[@]}"; do
        socket="${spec%:*}" mode="${spec##*:}"
        [[ "$spec" == *:* && -n "$socket" ]] || die "--uart $spec: want SOCKET:qemu or SOCKET:host"
        case "$mode" in
            qemu) options+=(-chardev "socket,id=uart$index,path=$socket,server=on,wait=off") ;;
            host) options+=(-chardev "socket,id=uart$index,path=$socket,server=off,reconnect=1") ;;
            *) die "--uart $spec: mode must be qemu or host" ;;
        esac
        options+=(-device "pci-serial,chardev=uart$index")
        index=$((index + 1))
    done
    exec qemu-system-aarch64 "${options[@]}" "${extra[@]}" </dev/null
}

main "$@"
