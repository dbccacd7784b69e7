#!/bin/busybox sh
# shellcheck shell=dash
# /init of the emulated board (packed by make-initramfs.sh): mounts the
# kernel file systems, runs the boot's job (/etc/board/job, chosen by the
# host script) and powers the machine off, so qemu exits when the job is
# done. Everything printed goes to the console, ttyAMA0, which is qemu's
# standard output on the host: the host reads the results from there.
/bin/busybox --install -s /bin
export PATH=/usr/bin:/bin
mount -t devtmpfs devtmpfs /dev
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t debugfs debugfs /sys/kernel/debug
mount -t tmpfs tmpfs /tmp
mount -t tmpfs tmpfs /run
mkdir -p /var/lib /var/log
hostname uwbd-board

echo "BOARD: booted $(uname -m) $(uname -r) in $(cut -d' ' -f1 /proc/uptime) s"
if [ -f /etc/board/job ]; then
    sh /etc/board/job
    status=$?
else
    echo "BOARD: no /etc/board/job in the initramfs"
    status=127
fi
echo "BOARD: job finished status=$status"
sync
poweroff -f
