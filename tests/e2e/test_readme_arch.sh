#!/usr/bin/env bash
# Issue 47: the graph of what uses what (rooms of src/, files of
# src/daemon/) is drawn from the build by tools/readme/readme-arch.sh, not
# by hand; it must be what the build says, a stale one must fail with the
# fix named, and the only circle left among daemon/ files is the one the
# issue names (the output modules and the daemon's loop, which share
# struct daemon): any other circle fails here.
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

# One circle at most among daemon/ files: the daemon's own (daemon.c in it).
circles=$(sed -n '/^Files that reach each other/,$p' "$tmp/graph" |
    awk '/^  [0-9]+ files:/ { if (line != "") print line; line = $0; next } /^    / { line = line " " $1; for (i = 2; i <= NF; i++) line = line " " $i } END { if (line != "") print line }')
others=$(echo "$circles" | grep -v ' daemon ' | grep . || true)
[[ -z $others ]] || fail "daemon/ files in a circle other than the daemon's loop: $others"

echo "PASS: $doc's graph is the build's ($(wc -l < "$tmp/graph") lines); $(echo "$circles" | grep -c . || true) circle among daemon/ files, the daemon's loop"
