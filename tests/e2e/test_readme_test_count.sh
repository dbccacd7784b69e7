#!/usr/bin/env bash
# Issue 31, finding 10: the README said `make test` ran 295 tests when it
# ran 480. Its count is now what tools/readme/readme-test-count.sh counts
# from the sources (`make readme-test-count` writes it), no typed count of
# make test's cases is left, and the counting agrees with Unity's own
# summary on some binaries. The count lives in tests/README.md (building
# and testing, moved out of the README: issue 48, finding 3).
set -euo pipefail
doc=tests/README.md
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

bash tools/readme/readme-test-count.sh --check $doc ||
    fail "$doc's test count differs from what make test runs: run make readme-test-count"
read -r cases _ < <(bash tools/readme/readme-test-count.sh)
# The check notices a typed count.
sed "s/runs \*\*$cases test cases\*\*/runs **295 test cases**/" $doc > "$tmp/README.md"
! cmp -s $doc "$tmp/README.md" || fail "could not plant a wrong count"
if bash tools/readme/readme-test-count.sh --check "$tmp/README.md" 2> "$tmp/err"; then fail "a README saying 295 passed the check"; fi
grep -q 'run make readme-test-count' "$tmp/err" || fail "the failing check does not say how to fix it: $(cat "$tmp/err")"
# No other closing line of make test typed into the README or beside the count.
typed=$(grep -nE '`[0-9]+ passed, [0-9]+ failed' README.md $doc | grep -v 'make test-deb\|20 passed' || true)
[[ -z $typed ]] || fail "a make test result typed by hand: $typed"

# One case per RUN_TEST is what Unity counts (quick binaries; cross builds too).
for name in test_verdict_text test_console_line test_atomic_file test_utc_time; do
    binary=$UWB_BUILD_DIR/tests/$name
    [[ -x $binary ]] || fail "$binary is not built"
    unity=$(${UWB_EXEC_PREFIX:-} "$binary" < /dev/null 2>&1 | sed -n 's/^\([0-9]*\) Tests [0-9]* Failures.*/\1/p' | tail -n 1)
    counted=$(grep -cE '^[[:space:]]*RUN_TEST\(' "tests/unit/$name.c")
    [[ $unity == "$counted" ]] || fail "$name: Unity ran ${unity:-no} tests, the sources count $counted RUN_TESTs"
done
echo "$doc's test count: $cases, as counted from the sources and by Unity"
