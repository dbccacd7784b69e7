#!/usr/bin/env bash
# How many test cases `make test` runs (tests/run-tests.sh counts one per
# Unity RUN_TEST of each unit-test binary, one per e2e script), counted from
# the sources, for the README instead of a typed figure:
#   readme-test-count.sh                    print "CASES UNIT BINARIES E2E"
#   readme-test-count.sh --write README.md  replace the marked block
#   readme-test-count.sh --check README.md  exit 1 (with a diff) when it differs
# `make readme-test-count` writes; tests/e2e/test_readme_test_count.sh checks,
# and checks the count against Unity's own for some binaries.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
[[ $# == 0 || ($# == 2 && ($1 == --write || $1 == --check)) ]] ||
    { echo "usage: $0 [--write|--check README]" >&2; exit 64; }
shopt -s nullglob
unit_sources=(tests/unit/test_*.c)
e2e_scripts=(tests/e2e/test_*.sh)
unit=$(cat "${unit_sources[@]}" | grep -cE '^[[:space:]]*RUN_TEST\(' || true)
binaries=${#unit_sources[@]} e2e=${#e2e_scripts[@]}
cases=$((unit + e2e))
if [[ $# == 0 ]]; then
    echo "$cases $unit $binaries $e2e"
    exit 0
fi
mode=$1 readme=$2
work=$(mktemp -d /tmp/uwbd-readme-count-XXXXXX)
trap 'rm -rf "$work"' EXIT
cat > "$work/block" <<TEXT
\`make test\` runs **$cases test cases**: $unit in $binaries unit-test binaries (one
per Unity \`RUN_TEST\`) and $e2e end-to-end scripts (one each), and closes with
\`N passed, N failed\` (and \`N skipped\` when a check cannot run here).
TEXT
awk -v name=readme-test-count -v file="$work/block" '
    index($0, "<!-- " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- " name ": end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-test-count: marker <!-- " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$readme" > "$work/readme"
if [[ $mode == --write ]]; then
    cmp -s "$work/readme" "$readme" || cp "$work/readme" "$readme"
    echo "readme-test-count: $readme: $cases test cases"
elif ! diff -u "$readme" "$work/readme" >&2; then
    echo "readme-test-count: $readme's test count is not what make test runs ($cases; above); run make readme-test-count" >&2
    exit 1
fi
