#!/usr/bin/env bash
# make install DESTDIR=... as a packager runs it: the binary, the unit, the
# udev rules, the manual pages and the documents land where they should;
# every relative link in the installed documents resolves inside the
# installed tree; no document points outside it; the emulated board's
# sample config comes with uwbemu or not at all.
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }
passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT

# The build the other tests use (BUILD, TEST_RUNNER for a cross build):
# nothing is rebuilt, only the manual pages are made if missing.
make --no-print-directory -s install DESTDIR="$root" PREFIX=/usr BUILD="$UWB_BUILD_DIR" \
    TEST_RUNNER="${UWB_EXEC_PREFIX:-}" > "$root.log" 2>&1 || { cat "$root.log" >&2; rm -f "$root.log"; fail "make install"; }
rm -f "$root.log"

for f in usr/bin/uwbd usr/lib/systemd/system/uwbd.service usr/lib/udev/rules.d/99-uwbd-gpio.rules \
         usr/lib/udev/rules.d/99-uwbd-digitiser.rules usr/share/uwbd/raspberry-pi-4/uwbd.json \
         usr/share/man/man8/uwbd.8 usr/share/man/man5/uwbd.json.5 usr/share/man/man1/uwbd-ctl.1 \
         usr/share/doc/uwbd/install-guide.md usr/share/doc/uwbd/config.md usr/share/doc/uwbd/state-dir.md \
         usr/share/man/man7/uwbd-mqtt.7 usr/share/man/man7/uwbd-modbus.7 usr/share/man/man7/uwbd-contacts.7 \
         usr/share/man/man7/uwbd-prometheus.7 usr/share/man/man7/uwbd-images.7 usr/share/man/man7/uwbd-verdict.7 \
         usr/share/man/man7/uwbd-recovery.7; do
    [[ -f $root/$f ]] || fail "not installed: /$f"
done
grep -qx 'ExecStart=/usr/bin/uwbd --config /etc/uwbd/uwbd.json' "$root/usr/lib/systemd/system/uwbd.service" ||
    fail "the unit does not run /usr/bin/uwbd"
grep -q '@[a-z]*dir@' "$root/usr/lib/systemd/system/uwbd.service" && fail "the unit has an unfilled @...@"
for line in Type=notify NotifyAccess=main 'WatchdogSec=[1-9][0-9]*' 'Documentation=man:uwbd(8) .*'; do
    grep -qx "$line" "$root/usr/lib/systemd/system/uwbd.service" || fail "the unit lacks $line"
done
cmp -s "$root/usr/share/man/man5/uwbd.json.5" <(${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" --config-keys=man) ||
    fail "the installed uwbd.json(5) is not what uwbd --config-keys=man prints"
pass "binary, unit, udev rules, sample config, manual pages and documents installed"

# Every program installed has its manual page (lintian: binary-without-manpage).
for prog in "$root"/usr/bin/*; do
    name=$(basename "$prog")
    [[ -f $root/usr/share/man/man1/$name.1 || -f $root/usr/share/man/man8/$name.8 ]] ||
        fail "/usr/bin/$name is installed without a manual page"
done
pass "every program in /usr/bin has a manual page: $(ls "$root/usr/bin" | tr '\n' ' ')"

# Every Markdown link [text](target) that is not a URL or an anchor resolves
# to a file under the installed tree, relative to the document.
docs=$(find "$root" -name '*.md' | sort)
[[ -n $docs ]] || fail "no documents installed"
links=0
for doc in $docs; do
    dir=$(dirname "$doc")
    while IFS= read -r target; do
        target=${target%%#*}
        [[ -z $target || $target =~ ^[a-z]+: ]] && continue
        links=$((links + 1))
        [[ $target != /* ]] || fail "${doc#"$root"}: absolute link $target"
        resolved=$(realpath -m "$dir/$target")
        [[ $resolved == "$root"/* ]] || fail "${doc#"$root"}: link $target leaves the installed tree"
        [[ -e $resolved ]] || fail "${doc#"$root"}: link $target does not resolve (no ${resolved#"$root"})"
    done < <(grep -oE '\]\([^) ]+\)' "$doc" | sed -E 's/^\]\((.*)\)$/\1/')
done
(( links >= 5 )) || fail "only $links links checked"
pass "$links relative links in $(wc -w <<< "$docs") installed documents resolve in the installed tree"

# No document points at the developers' machine or outside the source tree.
if grep -nE '/work/|\.\./shared|/home/[a-z]' $docs; then
    fail "an installed document names a path outside the repository"
fi
# The README is not installed: nothing installed sends the reader to it
# (the manual pages in section 7 hold what the operator needs from it).
readme_refs=$(grep -rnI 'README' "$root" | sed "s|^$root||" || true)
[[ -z $readme_refs ]] || fail "installed files refer to the README, which is not installed: $(head -5 <<< "$readme_refs")"
# Every section 7 page an installed file names (NAME(7), as roff or
# Markdown, or "man 7 NAME") is installed.
named=$(grep -rhoIE 'uwbd(\\?-[a-z]+)+(\\fR| )?\(7\)|man 7 uwbd-[a-z-]+' "$root" |
    sed -E 's/^man 7 //; s/\\fR//; s/\\-/-/g; s/ ?\(7\)$//' | sort -u)
(( $(wc -w <<< "$named") >= 6 )) || fail "only $(wc -w <<< "$named") section 7 pages named in the installed files: $named"
for ref in $named; do
    [[ -f $root/usr/share/man/man7/$ref.7 ]] || fail "an installed file names $ref(7), which is not installed"
done
if [[ -e $root/usr/share/uwbd/emulated/uwbd.json && ! -e $root/usr/bin/uwbemu ]]; then
    fail "the emulated sample config is installed without uwbemu"
fi
pass "no paths outside the repository, no README, every named section 7 page installed; no emulated sample without uwbemu"

# The clock: the unit pulls in systemd-time-wait-sync (off by default) and
# starts after it and time-sync.target; the drop-in installed with it bounds
# that wait, which is otherwise infinite, so a site without NTP is watched.
unit=$root/usr/lib/systemd/system/uwbd.service
dropin=$root/usr/lib/systemd/system/systemd-time-wait-sync.service.d/uwbd.conf
grep -qx 'Wants=systemd-time-wait-sync.service' "$unit" || fail "the unit does not pull in systemd-time-wait-sync"
after=$(sed -n 's/^After=//p' "$unit" | tr ' ' '\n')
grep -qx 'time-sync.target' <<< "$after" && grep -qx 'systemd-time-wait-sync.service' <<< "$after" ||
    fail "the unit is not ordered after time-sync.target and systemd-time-wait-sync: After=$after"
[[ -f $dropin ]] || fail "not installed: the drop-in ${dropin#"$root"}"
# The key in its [Service] section, its value a finite time span.
timeout=$(awk '/^\[/ { section = $0 } section == "[Service]" && sub(/^TimeoutStartSec=/, "") { print }' "$dropin")
[[ -n $timeout && $timeout != infinity ]] || fail "the drop-in sets no finite TimeoutStartSec in [Service]: '$timeout'"
if command -v systemd-analyze > /dev/null; then
    us=$(systemd-analyze timespan "$timeout" | sed -n 's/^ *μs: *//p')
    [[ $us =~ ^[0-9]+$ ]] && (( us >= 60000000 && us <= 3600000000 )) ||
        fail "TimeoutStartSec=$timeout is not between 1 min and 1 h (systemd-analyze: '$us' us)"
fi
pass "the unit waits for the clock: Wants=systemd-time-wait-sync, bounded to $timeout by its drop-in"
echo "$passed passed"
