#!/usr/bin/env bash
# Issue 47: the graph of what uses what (rooms of src/, files of
# src/daemon/) is drawn from the build by tools/readme/readme-arch.sh, not
# by hand; it must be what the build says, a stale one must fail with the
# fix named, and it must show no circle among daemon/ files (the output
# modules see the daemon through a port, not struct daemon).
set -euo pipefail
doc=src/README.md
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

bash tools/readme/readme-arch.sh "$UWB_BUILD_DIR" > "$tmp/graph" || fail "readme-arch.sh could not draw the graph"
grep -A1 '^  daemon  *-> ' "$tmp/graph" | tr '\n' ' ' | grep -q ' control .* loop .* state ' ||
    fail "the graph does not show the daemon using control/, loop/ and state/: $(grep '^  daemon ' "$tmp/graph")"
bash tools/readme/readme-arch.sh "$UWB_BUILD_DIR" --check $doc ||
    fail "$doc's architecture graph differs from the build's: run make readme-arch"

# A graph typed by hand (one arrow removed) is noticed, and the fix named.
sed -E '/<!-- make readme-arch: begin/,/<!-- make readme-arch: end/ s/^(  daemon  *->) config /\1 /' $doc > "$tmp/README.md"
! cmp -s $doc "$tmp/README.md" || fail "could not plant a stale graph"
if bash tools/readme/readme-arch.sh "$UWB_BUILD_DIR" --check "$tmp/README.md" 2> "$tmp/err"; then
    fail "a README missing the daemon -> config arrow passed the check"
fi
grep -q 'run make readme-arch' "$tmp/err" || fail "the failing check does not say how to fix it: $(cat "$tmp/err")"

# No circle among daemon/ files (tests/e2e/test_object_cycles.sh fails on one too).
if grep -q '^Files that reach each other' "$tmp/graph"; then
    fail "daemon/ files in a circle: $(sed -n '/^Files that reach each other/,$p' "$tmp/graph" | tr -s ' \n' ' ')"
fi
grep -q '^No circle: ' "$tmp/graph" || fail "the graph does not say whether daemon/ files reach themselves"

echo "PASS: $doc's graph is the build's ($(wc -l < "$tmp/graph") lines); no circle among daemon/ files"
