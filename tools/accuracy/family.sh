#!/usr/bin/env bash
# The shared family of random tanks (../shared/data/fdtd2d-var-*): each
# moved scan replayed against its own tank's intact scan, its figure set
# against the truth. The truth of the centre's move is the shift plus half
# the height change (a squeezed spacer: data/README.md). A figure is right
# when it is within 0.25 mm and 2 sigma of the truth. Prints a line per
# pair and a closing count; the figures are in the README's family table.
# Then the same for the pairs uwbd was developed on (the paper's, the
# tank's), and the robust scatter of the errors, 1.4826 x their median
# absolute value (a normal spread's sigma, a gross error or two aside):
# of the family, and of every pair, from which the least sigma a
# displacement is given comes (src/verdict/compare.c); and the same scatter
# of the height change's error per mm moved, its sigma's static-scene
# share (compare.c's height_change_per_shift).
#
# Last, the fresh draws (FRESH_DIR/fdtd2d-fresh-*: tanks drawn by
# tools/fdtd/draw_tank.py and simulated with gprMax after every constant
# above was set, so none was tuned to them), tallied apart; then the
# control pairs with a tank's clamp plates taken out of the model
# (fdtd2d-fresh-*-noplate-*: what the plate does to the figure).
#
# Usage: tools/accuracy/family.sh [DATA_DIR [BUILD_DIR [FRESH_DIR]]]
set -euo pipefail
data=${1:-../shared/data}
build=${2:-build}
fresh=${3:-tests/fixtures}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
number() { grep -o "\"$1\": *[-0-9.]*" | head -n 1 | grep -o '[-0-9.]*$' || true; }

right=0 close=0 wrong=0 withheld=0 pairs=0
# replay_pair MOVED BASELINE: one line, and the error's size to $out/KIND.
replay_pair() {
    local moved=$1 baseline=$2 kind=$3 name truth want verdict status got sigma verdict_word
    name=$(basename "$moved" .uwbscan)
    truth=${moved%.uwbscan}.truth.json
    want=$(awk -v s="$(number displacement_mm < "$truth")" -v h="$(number height_change_mm < "$truth")" \
        'BEGIN { print s + h / 2 }')
    verdict=$("$build/uwbd" --replay "$moved" --baseline "$baseline" --out "$out" | head -n 1)
    status=$(grep -o '"status":"[a-z]*"' <<< "$verdict" | head -n 1 | cut -d'"' -f4)
    got=$(sed 's/":/": /g' <<< "$verdict" | number axial_displacement_mm)
    sigma=$(sed 's/":/": /g' <<< "$verdict" | number uncertainty_mm)
    pairs=$((pairs + 1))
    height_share "$verdict" "$truth"
    if [[ -z $got ]]; then
        withheld=$((withheld + 1))
        printf '%-28s truth %+7.2f  %s, no figure\n' "$name" "$want" "$status"
        return
    fi
    verdict_word=$(awk -v w="$want" -v g="$got" -v s="$sigma" 'BEGIN {
        e = g - w; if (e < 0) e = -e
        print (e <= 2 * s) ? ((e <= 0.25) ? "right" : "within-2sigma") : "wrong" }')
    case $verdict_word in
        right) right=$((right + 1)) ;;
        within-2sigma) close=$((close + 1)) ;;
        *) wrong=$((wrong + 1)) ;;
    esac
    awk -v w="$want" -v g="$got" 'BEGIN { e = g - w; print (e < 0) ? -e : e }' >> "$out/$kind"
    awk -v n="$name" -v w="$want" -v g="$got" -v s="$sigma" -v st="$status" -v v="$verdict_word" 'BEGIN {
        printf "%-28s truth %+7.2f  read %+7.2f ± %.2f %-6s off %+.2f (%.1f sigma)  %s\n",
               n, w, g, s, st, g - w, (g - w) / s, v }'
}
# height_share VERDICT TRUTH: where both faces' edges were read, the height
# change they give (even when withheld) off the truth, per metre moved, to
# $out/height (the static scene's share of its sigma in compare.c).
height_share() {
    local edges shift truth_h
    edges=$(grep -o '"\(lower\|upper\)_edge_mm":[-0-9.]*' <<< "$1" | cut -d: -f2 | tr '\n' ' ' || true)
    shift=$(number displacement_mm < "$2")
    truth_h=$(number height_change_mm < "$2")
    awk -v e="$edges" -v s="${shift:-0}" -v h="${truth_h:-0}" 'BEGIN {
        if (split(e, x, " ") < 4 || s == 0) exit
        err = (x[2] - x[1]) - (x[4] - x[3]) - h
        printf "%.6f\n", (err < 0 ? -err : err) / (s < 0 ? -s : s) }' >> "$out/height"
}
tally() {
    echo "$pairs pairs: $right within 0.25 mm and 2 sigma, $close within 2 sigma only," \
        "$wrong outside 2 sigma, $withheld without a figure"
    right=0 close=0 wrong=0 withheld=0 pairs=0
}
# robust_scatter FILE...: 1.4826 x the median of the sizes in the files.
robust_scatter() {
    sort -g "$@" | awk '{ e[NR] = $1 } END {
        m = (NR % 2) ? e[(NR + 1) / 2] : (e[NR / 2] + e[NR / 2 + 1]) / 2
        printf "%.2f mm (%d figures)", 1.4826 * m, NR }'
}

# replay_tanks KIND HEADING MOVED...: each moved scan against its own
# tank's intact one (NAME-d+00), HEADING printed before the first.
replay_tanks() {
    local kind=$1 heading=$2 moved
    shift 2
    for moved; do
        [[ $moved == *-d+00.uwbscan ]] && continue
        [[ -n $heading ]] && echo "$heading"
        heading=
        replay_pair "$moved" "${moved%-d*}-d+00.uwbscan" "$kind"
    done
}

shopt -s nullglob
replay_tanks family "" "$data"/fdtd2d-var-s*-d[+-]*.uwbscan
(( pairs > 0 )) || { echo "family: no fdtd2d-var-* pairs in $data" >&2; exit 66; }
tally
echo "developed on:"
for moved in "$data"/fdtd2d-tank-d[+-]*.uwbscan; do
    [[ $moved == *-d+00.0.uwbscan ]] && continue
    replay_pair "$moved" "$data/fdtd2d-tank-d+00.0.uwbscan" developed
done
replay_pair "$data/fdtd2d-paper-up20mm.uwbscan" "$data/fdtd2d-paper-intact.uwbscan" developed
tally
echo "robust scatter of the errors: family $(robust_scatter "$out/family"), every pair" \
    "$(robust_scatter "$out/family" "$out/developed")"
sort -g "$out/height" | awk '{ e[NR] = $1 } END {
    m = (NR % 2) ? e[(NR + 1) / 2] : (e[NR / 2] + e[NR / 2 + 1]) / 2
    printf "height change read off its truth per mm moved (robust scatter): %.3f (%d pairs)\n", 1.4826 * m, NR }'
replay_tanks fresh "fresh draws (not used to set any constant):" \
    "$fresh"/fdtd2d-fresh-s[0-9][0-9][0-9]-d[+-]*.uwbscan
if ((pairs > 0)); then
    tally
    echo "robust scatter of the errors: fresh draws $(robust_scatter "$out/fresh")"
fi
replay_tanks control "the same tanks with their clamp plates left out of the model:" \
    "$fresh"/fdtd2d-fresh-s*-noplate-d[+-]*.uwbscan
if ((pairs > 0)); then
    tally
fi
