#!/usr/bin/env bash
# make test-deb: the .deb that `make deb` built, installed with apt in a
# fresh Debian 12 (bookworm) minbase chroot made by debootstrap, and checked
# there: installed, the system user and group made, /etc/uwbd/uwbd.json a
# conffile that `uwbd --check-config` accepts, the unit (waiting for the
# clock, its systemd-time-wait-sync drop-in; every program it runs there,
# systemd-analyze verify clean), udev rules, manual pages (one for each
# program, every word rendered) and documents in place; purged cleanly. Ends with
# "N passed, N failed". Needs root (debootstrap, chroot) and the network
# (the Debian mirror). Everything is made under CHROOT_DIR, in the build
# directory, and removed at the end.
#
# Usage: tools/deb/test-deb.sh DEB_DIR VERSION CHROOT_DIR
set -uo pipefail

if [[ $# != 3 ]]; then
    echo "usage: $0 DEB_DIR VERSION CHROOT_DIR" >&2
    exit 64
fi
deb_dir=$1 version=$2 root=$3
passed=0 failed=0
finish() {
    echo "$passed passed, $failed failed"
    [[ $failed == 0 ]]
    exit
}
check() {   # WHAT COMMAND...: one result
    local what=$1
    shift
    if "$@"; then
        echo "PASS: $what"
        passed=$((passed + 1))
    else
        echo "FAIL: $what"
        failed=$((failed + 1))
    fi
}
give_up() {
    echo "FAIL: $*"
    failed=$((failed + 1))
    finish
}

[[ $(id -u) == 0 ]] || give_up "make test-deb needs root (debootstrap and chroot)"
arch=$(dpkg --print-architecture)
deb="$deb_dir/uwbd_${version}_$arch.deb"
[[ -f $deb ]] || give_up "no $deb (make deb builds it)"

mirror=$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/debian.sources 2> /dev/null | head -n 1)
mirror=${mirror:-http://deb.debian.org/debian}
cleanup() {
    umount -l "$root/proc" 2> /dev/null
    rm -rf --one-file-system "$root"
}
trap cleanup EXIT
cleanup
mkdir -p "$root"
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"; }

SECONDS=0
debootstrap --variant=minbase bookworm "$root" "$mirror" > "$root.debootstrap.log" 2>&1 ||
    { tail -5 "$root.debootstrap.log"; rm -f "$root.debootstrap.log"; give_up "debootstrap bookworm from $mirror"; }
rm -f "$root.debootstrap.log"
echo "test-deb: Debian 12 minbase in ${SECONDS} s"
mount -t proc proc "$root/proc"
cp /etc/resolv.conf "$root/etc/" 2> /dev/null
cp "$deb" "$root/tmp/"
in_root apt-get update -qq > /dev/null 2>&1 || give_up "apt-get update in the chroot"
in_root apt-get install -y -qq --no-install-recommends "/tmp/$(basename "$deb")" > "$root/install.log" 2>&1
rc=$?
check "apt-get install ./$(basename "$deb") in a fresh Debian 12 (exit $rc)" test "$rc" = 0
[[ $rc == 0 ]] || { tail -20 "$root/install.log"; finish; }

check "dpkg says uwbd $version is installed" \
    test "$(in_root dpkg-query -W -f='${Status} ${Version}' uwbd)" = "install ok installed $version"
passwd=$(in_root getent passwd uwbd)
check "system user uwbd, home /var/lib/uwbd, no login shell: $passwd" \
    bash -c '[[ $1 =~ ^uwbd:x:([0-9]+):[0-9]+:[^:]*:/var/lib/uwbd:(/usr/sbin/nologin|/bin/false)$ ]] && (( BASH_REMATCH[1] < 1000 ))' _ "$passwd"
check "system groups uwbd and gpio" bash -c "chroot '$root' getent group uwbd > /dev/null && chroot '$root' getent group gpio > /dev/null"
check "/etc/uwbd/uwbd.json is a conffile" \
    bash -c "chroot '$root' dpkg-query -W -f='\${Conffiles}' uwbd | grep -q '^ /etc/uwbd/uwbd.json [0-9a-f]\{32\}$'"
in_root uwbd --check-config /etc/uwbd/uwbd.json > "$root/check.out" 2>&1
rc=$?
check "uwbd --check-config /etc/uwbd/uwbd.json: exit $rc, $(head -c 200 "$root/check.out")" \
    bash -c "[[ $rc == 0 ]] && grep -q 'configuration valid' '$root/check.out'"
check "the unit: /lib/systemd/system/uwbd.service, Type=notify, ExecStart=/usr/bin/uwbd" \
    bash -c "grep -qx 'Type=notify' '$root/lib/systemd/system/uwbd.service' &&
             grep -qx 'ExecStart=/usr/bin/uwbd --config /etc/uwbd/uwbd.json' '$root/lib/systemd/system/uwbd.service'"
check "the unit waits for the clock: Wants=systemd-time-wait-sync, After= it and time-sync.target" \
    bash -c "grep -qx 'Wants=systemd-time-wait-sync.service' '$root/lib/systemd/system/uwbd.service' &&
             grep -qx 'After=.*time-sync.target.*' '$root/lib/systemd/system/uwbd.service' &&
             grep -qx 'After=.*systemd-time-wait-sync.service.*' '$root/lib/systemd/system/uwbd.service'"
# Every program the unit runs (ExecStartPre=, ExecStart=, ExecReload=) is in
# the package or what it depends on: minbase has no procps, so no /bin/kill.
unit=$root/lib/systemd/system/uwbd.service
programs=$(sed -nE 's/^Exec[A-Za-z]+=[-@:+!]*([^ ]+).*$/\1/p' "$unit" | sort -u)
missing=$(for p in $programs; do in_root test -x "$p" || echo "$p"; done)
check "the unit's programs are installed: $(echo $programs)${missing:+; missing: $(echo $missing)}" \
    test -n "$programs" -a -z "$missing"
# The host's systemd-analyze reads the chroot's files (--root); minbase has
# no systemd, so its own targets are not found there: that alone is allowed.
if command -v systemd-analyze > /dev/null; then
    verify=$(systemd-analyze verify --man=no --root="$root" "$unit" 2>&1 | grep -v ': Unit [^ ]*\.target not found\.$')
    check "systemd-analyze verify uwbd.service in the chroot: ${verify:-no error}" test -z "$verify"
else
    check "systemd-analyze on this machine to verify the unit (package systemd)" false
fi
check "the drop-in bounding systemd-time-wait-sync (TimeoutStartSec=5min)" \
    grep -qx 'TimeoutStartSec=5min' "$root/lib/systemd/system/systemd-time-wait-sync.service.d/uwbd.conf"
check "the package recommends an NTP client (systemd-timesyncd | time-daemon)" \
    bash -c "chroot '$root' dpkg-query -W -f='\${Recommends}' uwbd | grep -qE '^systemd-timesyncd \| time-daemon(, |$)'"
check "the dlopened libraries: Depends libsystemd0, Recommends libmosquitto1 and libmodbus5" \
    bash -c "chroot '$root' dpkg-query -W -f='\${Depends}\\n\${Recommends}\\n' uwbd |
             awk 'NR == 1 && /(^|, )libsystemd0(,|$)/ { d = 1 } NR == 2 && /libmosquitto1 / && /libmodbus5 / { r = 1 } END { exit !(d && r) }'"
check "udev rules in /lib/udev/rules.d" test -f "$root/lib/udev/rules.d/99-uwbd-gpio.rules" -a \
    -f "$root/lib/udev/rules.d/99-uwbd-digitiser.rules"
check "manual pages uwbd(8), uwbd.json(5), uwbd-ctl(1), uwbsim(1)" test -f "$root/usr/share/man/man8/uwbd.8.gz" -a \
    -f "$root/usr/share/man/man5/uwbd.json.5.gz" -a -f "$root/usr/share/man/man1/uwbd-ctl.1.gz" -a \
    -f "$root/usr/share/man/man1/uwbsim.1.gz"
operator_pages=(uwbd uwbd-verdict uwbd-images uwbd-contacts uwbd-mqtt uwbd-modbus uwbd-prometheus uwbd-recovery)
missing_pages=$(for n in "${operator_pages[@]}"; do [[ -f $root/usr/share/man/man7/$n.7.gz ]] || echo "$n(7)"; done)
check "the operator's manual pages in section 7${missing_pages:+; not: $(echo $missing_pages)}" test -z "$missing_pages"
readme_refs=$(grep -rlI README "$root/usr/share/doc/uwbd" || true; for p in "$root"/usr/share/man/man*/uwbd*.gz; do
    zgrep -l README "$p" || true; done)
check "nothing installed names the README, which is not installed${readme_refs:+: $(echo $readme_refs)}" test -z "$readme_refs"
without_page=$(for p in $(in_root dpkg -L uwbd | grep -E '^/usr/s?bin/.'); do
    n=$(basename "$p")
    [[ -f $root/usr/share/man/man1/$n.1.gz || -f $root/usr/share/man/man8/$n.8.gz ]] || echo "$p"
done)
check "every program of the package has a manual page${without_page:+; not: $(echo $without_page)}" test -z "$without_page"
# Rendered on the host (minbase has no groff): every word of each page shown.
mapfile -t pages < <(in_root dpkg -L uwbd | grep -E '^/usr/share/man/man[1-8]/.+\.gz$' | sed "s|^|$root|")
lost=$(bash "$(dirname "$0")/../man/no-lost-text.sh" "${pages[@]}" 2>&1)
rc=$?
lost=$(grep -v ', none lost$' <<< "$lost")
check "the ${#pages[@]} installed manual pages render every word of their source${lost:+: $lost}" \
    test "$rc" = 0 -a "${#pages[@]}" -ge 4
check "uwbd.json(5) lists the keys (gpio.backend)" bash -c "zcat '$root/usr/share/man/man5/uwbd.json.5.gz' | grep -q 'gpio.backend'"
check "the install guide and the documents it links" test -f "$root/usr/share/doc/uwbd/install-guide.md" -a \
    -f "$root/usr/share/doc/uwbd/raspberry-pi-4/pinmap.md" -a -f "$root/usr/share/doc/uwbd/digitiser-protocol.md"

in_root apt-get purge -y -qq uwbd > "$root/purge.log" 2>&1
rc=$?
check "apt-get purge uwbd: exit $rc, /etc/uwbd and /usr/bin/uwbd gone" \
    bash -c "[[ $rc == 0 && ! -e '$root/etc/uwbd/uwbd.json' && ! -e '$root/usr/bin/uwbd' ]]"
echo "test-deb: ${SECONDS} s in all"
finish
