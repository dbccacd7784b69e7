#!/usr/bin/env bash
# tools/uwbsim/README.md's parameter table, printed by the simulator from the
# table that drives its --help and JSON loader, not typed:
#   readme-sim-params.sh BUILD_DIR --write tools/uwbsim/README.md  replace the marked block
#   readme-sim-params.sh BUILD_DIR --check tools/uwbsim/README.md  exit 1 (with a diff) when it differs
# `make readme-sim-params` writes; tests/e2e/test_readme_docs.sh checks.
set -euo pipefail
[[ $# == 3 && ($2 == --write || $2 == --check) ]] ||
    { echo "usage: $0 BUILD_DIR --write|--check DOCUMENT" >&2; exit 64; }
build=$1 mode=$2 doc=$3
work=$(mktemp -d /tmp/uwbd-readme-sim-params-XXXXXX)
trap 'rm -rf "$work"' EXIT
${UWB_EXEC_PREFIX:-} "$build/uwbsim" --params-markdown > "$work/block" ||
    { echo "readme-sim-params: $build/uwbsim --params-markdown failed" >&2; exit 70; }
awk -v name=readme-sim-params -v file="$work/block" '
    index($0, "<!-- " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- " name ": end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-sim-params: marker <!-- " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$doc" > "$work/doc"
if [[ $mode == --write ]]; then
    if ! cmp -s "$work/doc" "$doc"; then
        cp "$work/doc" "$doc.tmp.$$" && mv "$doc.tmp.$$" "$doc"
    fi
    echo "readme-sim-params: $doc: $(($(wc -l < "$work/block") - 2)) parameters"
elif ! diff -u "$doc" "$work/doc" >&2; then
    echo "readme-sim-params: $doc's parameter table is not what uwbsim --params-markdown prints (above); run make readme-sim-params" >&2
    exit 1
fi
