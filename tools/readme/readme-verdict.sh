#!/usr/bin/env bash
# The README's paper-pair figure and example verdict, from a run of the
# command the README shows, not typed:
#   readme-verdict.sh BUILD_DIR --write README.md   replace the two marked blocks
#   readme-verdict.sh BUILD_DIR --check README.md   exit 1 (with a diff) when they differ
# `make readme-verdict` writes; tests/e2e/test_readme_verdict.sh checks.
# The verdict is wrapped before some keys ("\n " inserted) for reading;
# joining the lines without that gives back the printed line.
set -euo pipefail
[[ $# == 3 && ($2 == --write || $2 == --check) ]] || { echo "usage: $0 BUILD_DIR --write|--check README" >&2; exit 64; }
build=$1 mode=$2 readme=$3
run() { ${UWB_EXEC_PREFIX:-} "$build/$1" "${@:2}"; }
# The checker runs natively from UWB_HOST_BUILD_DIR under make test-arm, as in the e2e scripts.
if [[ -n ${UWB_HOST_BUILD_DIR:-} ]]; then helper_build=$UWB_HOST_BUILD_DIR helper_prefix=""
else helper_build=$build helper_prefix=${UWB_EXEC_PREFIX:-}; fi
json_get() { $helper_prefix "$helper_build/e2e/state_check" get "$@"; }

readme_out=/tmp/uwbd-out   # where the README's command writes its images
work=$(mktemp -d /tmp/uwbd-readme-XXXXXX)
trap 'rm -rf "$work"' EXIT
run uwbd --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan \
    --out "$work/out" > "$work/line"
sed -i "s|$work/out/|$readme_out/|g" "$work/line"

read -r measured lower upper < <(json_get axial_displacement_mm lower_edge_mm upper_edge_mm < "$work/line" | paste -sd ' ')
read -r truth y1 y2 < <(json_get displacement_mm y1_m y2_m < tests/fixtures/fdtd2d-paper-up20mm.truth.json | paste -sd ' ')
figure=$(awk -v m="$measured" -v t="$truth" -v lo="$lower" -v up="$upper" -v y1="$y1" -v y2="$y2" '
    function abs(x) { return x < 0 ? -x : x }
    BEGIN { e1 = abs(lo - 1000 * y1); e2 = abs(up - 1000 * y2)
            printf "On the same experiment simulated full-wave (the FDTD fixtures in\n"
            printf "`tests/fixtures/`), uwbd measures **%.2f mm** (error %.2f mm), with both\n", m, abs(m - t)
            printf "edges within %.2f mm of the truth:\n", (e1 > e2 ? e1 : e2) }')
{ echo '```json'
  sed -e 's/,"\(lower_edge_mm\|height_change_mm\|height_change_withheld\|face_range_mm\|baseline\|direct_coupling_ps\|images\)"/,\n "\1"/g' \
      -e 's/,"\(\/tmp\/uwbd-out\/\)/,\n "\1/g' "$work/line"
  echo '```'; } > "$work/verdict-block"
printf '%s\n' "$figure" > "$work/figure-block"

# README with the text between "<!-- NAME: begin" and "<!-- NAME: end -->" replaced by FILE.
replace_block() {  # NAME FILE IN OUT
    awk -v name="$1" -v file="$2" '
        index($0, "<!-- " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
        index($0, "<!-- " name ": end -->") == 1 { skip = 0 }
        !skip { print }
        END { if (found != 1) { print "readme-verdict: marker <!-- " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
        "$3" > "$4"
}
replace_block readme-figure "$work/figure-block" "$readme" "$work/readme.1"
replace_block readme-verdict "$work/verdict-block" "$work/readme.1" "$work/readme.2"

if [[ $mode == --write ]]; then
    cmp -s "$work/readme.2" "$readme" || cp "$work/readme.2" "$readme"
    echo "readme-verdict: $readme: $(sed 's/^/  /' "$work/line" | head -c 160)..."
else
    if ! diff -u "$readme" "$work/readme.2" >&2; then
        echo "readme-verdict: $readme's example verdict is not what the command prints (above); run make readme-verdict" >&2
        exit 1
    fi
fi
