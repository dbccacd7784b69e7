#!/usr/bin/env bash
# Where the radial figure stops: the shared tank's winding in the simulator
# (tools/uwbsim, 2-D physical optics, no clutter, no noise) with single-disk
# and wider bulges and dents, a change over most of the face, and a lean,
# each replayed against the intact winding. Prints a markdown table; with
# --readme FILE also puts it between FILE's "make accuracy-radial-limits"
# markers. tests/accuracy.md's "Radial deformation" chapter reads from it.
#
# Usage: tools/accuracy/radial-limits.sh BUILD_DIR [--readme FILE]
set -euo pipefail
build=${1:?usage: radial-limits.sh BUILD_DIR [--readme FILE]}
readme=
[[ ${2:-} == --readme ]] && readme=${3:?--readme needs a file}
scene=tools/uwbsim/scenes/fdtd2d-tank-winding.json
# The scene leaves the direct coupling out; the daemon checks time zero on it.
coupling=(--coupling-gain 0.05 --t0-s -1e-9)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/uwbsim" --scene "$scene" "${coupling[@]}" --seed 1 -o "$work/base.uwbscan" > /dev/null
field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2 | tr -d '"' || true; }

table=$work/table.md
{
    echo "| winding (disks 1-7 from the bottom) | true change | status | radial change ± σ | at | tilt | axial |"
    echo "|---|---|---|---|---|---|---|"
} > "$table"
row() { # label truth uwbsim-options...
    local label=$1 truth=$2
    shift 2
    "$build/uwbsim" --scene "$scene" "${coupling[@]}" --seed 1 "$@" -o "$work/cur.uwbscan" > /dev/null
    local v radial axial
    v=$("$build/uwbd" --replay "$work/cur.uwbscan" --baseline "$work/base.uwbscan" --out "$work" | head -n 1)
    radial=$(grep -o '"radial":{[^}]*}' <<< "$v" || true)
    axial=withheld
    [[ -n $(field axial_displacement_mm <<< "$v") ]] &&
        axial=$(printf '%+.2f ± %.2f mm' "$(field axial_displacement_mm <<< "$v")" "$(field uncertainty_mm <<< "$v")")
    # A tilt withheld (a change at the face's end) is said so, not printed as 0.
    local tilt=withheld
    [[ -n $(field tilt_mm <<< "$radial") ]] &&
        tilt=$(printf '%+.2f ± %.2f mm' "$(field tilt_mm <<< "$radial")" "$(field tilt_uncertainty_mm <<< "$radial")")
    printf '| %s | %s | %s | %+.2f ± %.2f mm | %.0f mm | %s | %s |\n' "$label" "$truth" \
        "$(field status <<< "$radial")" "$(field max_change_mm <<< "$radial")" \
        "$(field uncertainty_mm <<< "$radial")" "$(field at_mm <<< "$radial")" \
        "$tilt" "$axial" >> "$table"
}
row "disk 4 bulged 2 mm" "+2 mm at 300-318 mm" --radial-m 4:0.002
row "disk 4 bulged 3 mm" "+3 mm at 300-318 mm" --radial-m 4:0.003
row "disk 4 bulged 4 mm" "+4 mm at 300-318 mm" --radial-m 4:0.004
row "disk 4 bulged 6 mm" "+6 mm at 300-318 mm" --radial-m 4:0.006
row "disk 4 dented 4 mm" "-4 mm at 300-318 mm" --radial-m 4:-0.004
row "disk 1 (bottom) bulged 4 mm" "+4 mm at 230-248 mm" --radial-m 1:0.004
row "disks 3-5 bulged 2 mm" "+2 mm at 276-342 mm" --radial-m 3-5:0.002
row "disks 3-5 bulged 3 mm" "+3 mm at 276-342 mm" --radial-m 3-5:0.003
row "disks 2-6 bulged 4 mm (most of the face)" "+4 mm at 254-366 mm" --radial-m 2-6:0.004
row "face leaning, top 3 mm nearer" "tilt +3 mm" --face-tilt-m 0.003
row "face leaning, top 6 mm nearer" "tilt +6 mm" --face-tilt-m 0.006
cat "$table"
if [[ -n $readme ]]; then
    begin='<!-- make accuracy-radial-limits: begin -->'
    end='<!-- make accuracy-radial-limits: end -->'
    grep -qF "$begin" "$readme" && grep -qF "$end" "$readme" ||
        { echo "radial-limits: $readme has no block between $begin and $end" >&2; exit 65; }
    awk -v b="$begin" -v e="$end" -v t="$table" '
        $0 == b { print; while ((getline line < t) > 0) print line; skip = 1; next }
        $0 == e { skip = 0 }
        !skip' "$readme" > "$work/readme" && cat "$work/readme" > "$readme"
fi
