#!/usr/bin/env bash
# The README's excerpt of `make demo` (its radial step), from a run of the
# demo, not typed:
#   readme-demo.sh --write README.md DEMO_OUTPUT   replace the marked block
#   readme-demo.sh --check README.md DEMO_OUTPUT   exit 1 (with a diff) when it differs
# DEMO_OUTPUT is what tools/demo/run-demo.sh printed. `make readme-demo`
# runs the demo and writes; tests/e2e/test_demo.sh runs it and checks.
# What changes from run to run is written as the demo's default place:
# archive paths as build/demo/run/state/archive/DATE/SCAN_ID, a verdict's
# time as TIME and its scan id as SCAN_ID. The step's
# VERDICT line (one long JSON line) is left out: the text verdict says it.
set -euo pipefail
[[ $# == 3 && ($1 == --write || $1 == --check) ]] || { echo "usage: $0 --write|--check README DEMO_OUTPUT" >&2; exit 64; }
mode=$1 readme=$2 demo=$3
work=$(mktemp -d /tmp/uwbd-readme-demo-XXXXXX)
trap 'rm -rf "$work"' EXIT

{ echo '```'
  sed -n "/^\\\$ uwbemu --ctl unix:run\\/emu.sock 'set displacement_m 0' /,/^   the comparison picture/p" "$demo" |
      grep -v '^{"class":"VERDICT"' |
      sed -E -e 's#[^ ]*/run/state/archive/[0-9]{4}/[0-9]{2}/[0-9]{2}/[A-Za-z0-9_-]*uwb-[0-9T.]*Z#build/demo/run/state/archive/DATE/SCAN_ID#g' \
          -e 's#[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z#TIME#g' \
          -e 's#[A-Za-z0-9_.-]*uwb-[0-9]{8}T[0-9]{6}\.[0-9]{3}Z#SCAN_ID#g'
  echo '```'; } > "$work/block"
(($(wc -l < "$work/block") > 4)) || { echo "readme-demo: $demo has no radial step (the lines from 'set displacement_m 0' to the comparison picture)" >&2; exit 1; }

awk -v name=readme-demo -v file="$work/block" '
    index($0, "<!-- " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- " name ": end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-demo: marker <!-- " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$readme" > "$work/readme"

if [[ $mode == --write ]]; then
    cmp -s "$work/readme" "$readme" || cp "$work/readme" "$readme"
    echo "readme-demo: $readme: the radial step's excerpt written"
elif ! diff -u "$readme" "$work/readme" >&2; then
    echo "readme-demo: $readme's demo excerpt is not what the demo printed (above); run make readme-demo" >&2
    exit 1
fi
