#!/usr/bin/env bash
# The README's "make bench" block, from a run of the bench, not typed:
#   readme-bench.sh BUILD_DIR README.md
# replaces the text between "<!-- make readme-bench: begin" and
# "<!-- make readme-bench: end -->" with what `make bench` prints.
# `make readme-bench` runs it. Times are the machine's at that moment
# (the block says its load); the instruction count is not. make bench fails
# when the paper pair's replay is over budget; here a run over budget is written down as it is.
set -euo pipefail
[[ $# == 2 ]] || { echo "usage: $0 BUILD_DIR README" >&2; exit 64; }
build=$1 readme=$2
work=$(mktemp -d /tmp/uwbd-readme-bench-XXXXXX)
trap 'rm -rf "$work"' EXIT
{
    echo '```'
    echo '$ make bench'
    "$build/uwbbench"
    "$build/uwbbench" --replay-only --assert-budget --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
        tests/fixtures/fdtd2d-paper-intact.uwbscan ||
        echo "(make bench fails here: the replay is over its memory budget)"
    bash tools/bench/instruction-budget.sh "$build" 2>&1 ||
        echo "(make bench fails here: the replay is over its instruction budget)"
    echo "(load average when run: $(cut -d' ' -f1-3 /proc/loadavg))"
    echo '```'
} > "$work/block"
awk -v file="$work/block" '
    index($0, "<!-- make readme-bench: begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- make readme-bench: end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-bench: marker <!-- make readme-bench: begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$readme" > "$work/readme"
cmp -s "$work/readme" "$readme" || cp "$work/readme" "$readme"
echo "readme-bench: $readme: the bench block rewritten"
