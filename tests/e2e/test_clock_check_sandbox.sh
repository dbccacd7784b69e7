#!/usr/bin/env bash
# Issue 27, break 5: the clock check under the shipped unit's syscall
# filter. board/uwbd.service filtered the clock syscalls (ProtectClock=yes,
# and @system-service lacks @clock), so ntp_adjtime() failed with EPERM and
# uwbd_clock_synchronised() always said "not synchronised": retention by
# age never acted on an installed appliance. Here the check runs under the
# unit's filter: through systemd-run when systemd runs, else under a seccomp
# filter denying (EPERM, as SystemCallErrorNumber=EPERM) every @clock
# syscall the unit does not allow, worked out from the unit's lines with
# systemd-analyze. The kernel must answer, and the check agree with its
# answer outside the filter.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-clock-sandbox
unit=$REPO/board/uwbd.service
check() { $HOST_PREFIX "$HOST_BUILD/e2e/clock_check" "$@"; }

command -v systemd-analyze > /dev/null || { echo "SKIP: no systemd-analyze to read syscall groups"; exit 77; }

# The syscalls of a SystemCallFilter= item, groups expanded.
expand() {
    local item
    for item in "$@"; do
        if [[ $item == @* ]]; then
            # shellcheck disable=SC2046
            expand $(systemd-analyze syscall-filter "$item" | sed -n 's/^    \([^# ][^ ]*\).*$/\1/p')
        else
            echo "$item"
        fi
    done
}
# The unit's [Service] values of KEY, one line each.
unit_values() { sed -n "s/^$1=//p" "$unit"; }

declare -A allowed=()
while read -r line; do
    [[ -z $line ]] && continue
    if [[ $line == "~"* ]]; then
        for s in $(expand ${line#"~"}); do unset "allowed[$s]"; done
    else
        for s in $(expand $line); do allowed[$s]=1; done
    fi
done < <(unit_values SystemCallFilter)
# ProtectClock=yes is a filter of its own over @clock, whatever is allowed.
if [[ $(unit_values ProtectClock) == yes ]]; then
    for s in $(expand @clock); do unset "allowed[$s]"; done
fi
[[ $(unit_values SystemCallErrorNumber) == EPERM ]] || fail "the unit no longer answers filtered syscalls with EPERM"
deny=() denied=()
for s in $(expand @clock); do [[ -n ${allowed[$s]:-} ]] || { deny+=(--deny "$s"); denied+=("$s"); }; done

outside=$(check | sed -n 's/^synchronised: //p')
[[ $outside == [01] ]] || fail "clock_check outside any filter: '$outside'"

if [[ $(systemctl is-system-running 2>/dev/null || true) =~ ^(running|degraded)$ && $(id -u) == 0 ]]; then
    props=()
    for key in SystemCallFilter SystemCallErrorNumber SystemCallArchitectures ProtectClock; do
        while read -r value; do props+=(-p "$key=$value"); done < <(unit_values $key)
    done
    systemd-run --quiet --wait --pipe "${props[@]}" "$HOST_BUILD/e2e/clock_check" > inside.txt ||
        fail "systemd-run with the unit's filter failed"
    how="under systemd-run with the unit's ${#props[@]} filter properties"
else
    check "${deny[@]}" > inside.txt || fail "clock_check under the filter failed"
    how="under seccomp denying what the unit denies of @clock: ${denied[*]:-nothing}"
fi
grep -qx "kernel: answered" inside.txt ||
    fail "the unit's filter keeps the kernel's clock state from uwbd ($how): $(head -n 1 inside.txt)"
grep -qx "synchronised: $outside" inside.txt ||
    fail "the clock check says $(sed -n 's/^synchronised: //p' inside.txt) under the unit's filter, $outside outside it"
pass "the clock check gets the kernel's answer ($outside) $how"

# A sandbox stricter than the unit (a drop-in with ProtectClock=yes, or a
# container's filter) refuses every @clock syscall: then systemd-timesyncd's
# flag file is the witness, and without it the clock counts as not
# synchronised, with the reason given.
strict=()
for s in $(expand @clock); do strict+=(--deny "$s"); done
: > synchronized
check "${strict[@]}" --timesync-flag "$work/synchronized" > flagged.txt || fail "clock_check with the flag failed"
grep -qx "synchronised: 1" flagged.txt && grep -q "^how: systemd-timesyncd says so" flagged.txt ||
    fail "adjtimex filtered, timesyncd's flag present: $(tr '\n' ' ' < flagged.txt)"
check "${strict[@]}" --timesync-flag "$work/no-such-flag" > unflagged.txt || fail "clock_check without the flag failed"
grep -qx "synchronised: 0" unflagged.txt && grep -q "^how: adjtimex is filtered" unflagged.txt ||
    fail "adjtimex filtered, no flag: $(tr '\n' ' ' < unflagged.txt)"
pass "with every @clock syscall filtered: systemd-timesyncd's flag says synchronised, its absence not (reason given)"

echo "$passed passed"
