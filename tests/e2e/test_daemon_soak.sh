#!/usr/bin/env bash
# A short soak (tools/soak/run-soak.sh; `make soak` runs the long one): back
# to back scan cycles of uwbd against the emulated board with a small
# retention, then SIGTERM. Every cycle gives a verdict and none is `error`;
# the daemon's open descriptors stay the same; the archive and
# verdicts.jsonl stay within retention; its memory stays flat; it exits 0
# on SIGTERM, and an ASan build reports no leak at that exit.
set -euo pipefail

BUILD=${UWB_BUILD_DIR:?run through tests/run-tests.sh}
REPO=$(pwd)

passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
fail() {
    echo "FAIL: $*" >&2
    echo "--- soak output:" >&2
    tail -n 40 "$out" >&2
    exit 1
}

# Sizes: natively ~0.3-0.5 s a cycle; an ASan build ~1 s; under qemu-user ~11 s.
if [[ -n ${UWB_EXEC_PREFIX:-} ]]; then
    cycles=3 max_scans=1 every=1
elif grep -qa __asan_init "$BUILD/uwbd"; then
    cycles=20 max_scans=5 every=2
else
    cycles=40 max_scans=8 every=2
fi

out=$(mktemp /tmp/uwbd-soak-e2e-XXXXXX)
trap 'rm -f "$out"' EXIT
set +e
bash "$REPO/tools/soak/run-soak.sh" --build "$BUILD" --cycles "$cycles" --max-scans "$max_scans" --every "$every" \
    > "$out" 2>&1
rc=$?
set -e
grep -E '^ *(cycle|[0-9]+) ' "$out" | sed 's/^/    /'
grep '^soak: ' "$out" | sed 's/^/    /'

summary() { grep "^soak: $1" "$out" || true; }
verdicts=$(summary "$cycles cycles")
[[ $verdicts =~ ([0-9]+)\ verdicts\ \(([^\)]*)\) ]] || fail "no verdict count in the soak's summary (exit $rc)"
[[ ${BASH_REMATCH[1]} == $((cycles + 1)) ]] || fail "${BASH_REMATCH[1]} verdicts for $((cycles + 1)) cycles"
[[ ${BASH_REMATCH[2]} != *error* ]] || fail "error verdicts: ${BASH_REMATCH[2]}"
pass "$((cycles + 1)) cycles, each with a verdict, none an error (${BASH_REMATCH[2]})"

descriptors=$(summary "open descriptors")
[[ $descriptors =~ open\ descriptors\ ([0-9]+)\ -\>\ ([0-9]+) && ${BASH_REMATCH[1]} == "${BASH_REMATCH[2]}" ]] ||
    fail "open descriptors changed: $descriptors"
! grep -q "open descriptors, " "$out" || fail "$(grep -m1 "open descriptors, " "$out")"
pass "open descriptors the same at every sample (${BASH_REMATCH[1]})"

[[ $descriptors =~ in\ ([0-9]+)\ scans.*verdicts.jsonl\ ([0-9]+)\ lines ]] || fail "no archive figures: $descriptors"
((BASH_REMATCH[1] <= max_scans && BASH_REMATCH[2] <= max_scans)) ||
    fail "retention $max_scans: ${BASH_REMATCH[1]} scans archived, ${BASH_REMATCH[2]} verdict lines"
! grep -qE "retention keeps|grew from .* with the archive full" "$out" ||
    fail "$(grep -m1 -E "retention keeps|with the archive full" "$out")"
pass "archive (${BASH_REMATCH[1]} scans) and verdicts.jsonl (${BASH_REMATCH[2]} lines) held to retention $max_scans"

memory=$(summary "VmRSS")
[[ -n $memory ]] || fail "no memory figures (exit $rc)"
! grep -q "VmRSS grew" "$out" || fail "$(grep -m1 "VmRSS grew" "$out")"
pass "memory: ${memory#soak: }"

shutdown=$(summary "SIGTERM")
[[ $shutdown == "soak: SIGTERM -> exit 0"* ]] || fail "shutdown: $shutdown"
! grep -qE "sanitizer report|clean-shutdown" "$out" || fail "$(grep -m1 -E "sanitizer report|clean-shutdown" "$out")"
pass "SIGTERM: exit 0, hardware left safe, no sanitizer or leak report"

[[ $rc == 0 ]] || fail "run-soak.sh exited $rc: $(summary FAILED)"
echo "$passed passed, 0 failed"
