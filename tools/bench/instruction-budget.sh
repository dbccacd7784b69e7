#!/usr/bin/env bash
# The replay's budget in instructions (issue 44, the bench decision): uwbd's
# whole replay of the paper pair, counted by callgrind, must stay at or under
# BUDGET_G thousand million instructions. A count does not move with the
# machine's load, as a wall time does; make bench judges it, no timed test.
#
# Usage: tools/bench/instruction-budget.sh BUILD_DIR [--budget-g G] [--from CALLGRIND_OUT]
#   --budget-g G        the budget (default 1.15; 1.09 G when it was set)
#   --from FILE         judge a callgrind output already written (tests)
# Prints "uwbd --replay, the paper pair: N G instructions (callgrind), budget
# G: met" and exits 0, or "NOT met" on stderr and exits 1; 2 when it cannot
# count (no valgrind, a cross build, a replay that failed).
set -euo pipefail

usage() {
    echo "usage: $0 BUILD_DIR [--budget-g G] [--from CALLGRIND_OUT]" >&2
    exit 64
}
[[ $# -ge 1 ]] || usage
build=$1
shift
budget_g=1.15
from=""
while [[ $# -gt 0 ]]; do
    case $1 in
        --budget-g) [[ $# -ge 2 ]] || usage; budget_g=$2; shift 2 ;;
        --from) [[ $# -ge 2 ]] || usage; from=$2; shift 2 ;;
        *) usage ;;
    esac
done
[[ $budget_g =~ ^[0-9]+(\.[0-9]+)?$ ]] && awk -v g="$budget_g" 'BEGIN { exit !(g > 0) }' ||
    { echo "instruction-budget: --budget-g '$budget_g' is not a positive number" >&2; exit 64; }

# Paths as given, then the fixtures from the repository's root.
build=$(realpath -m -- "$build")
[[ -z $from ]] || from=$(realpath -m -- "$from")
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
work=$(mktemp -d /tmp/uwbd-instructions-XXXXXX)
trap 'rm -rf "$work"' EXIT
if [[ -z $from ]]; then
    [[ -z ${UWB_EXEC_PREFIX:-} ]] ||
        { echo "instruction-budget: valgrind cannot run under $UWB_EXEC_PREFIX; count on the native build" >&2; exit 2; }
    command -v valgrind > /dev/null ||
        { echo "instruction-budget: no valgrind (tools/deps/ensure-deps.sh --soak installs it)" >&2; exit 2; }
    [[ -x $build/uwbd ]] || { echo "instruction-budget: $build/uwbd is not built" >&2; exit 2; }
    from=$work/callgrind.out
    if ! valgrind --tool=callgrind --callgrind-out-file="$from" "$build/uwbd" \
        --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
        --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --out "$work/out" \
        > "$work/verdict.json" 2> "$work/valgrind.log"; then
        echo "instruction-budget: the replay under callgrind failed: $(tail -n 5 "$work/valgrind.log")" >&2
        exit 2
    fi
fi
[[ -f $from ]] || { echo "instruction-budget: $from: no such file" >&2; exit 2; }
# callgrind's last line: "totals: N" (older: "summary: N"), N the Ir count.
count=$(sed -n 's/^\(totals\|summary\): *\([0-9][0-9]*\).*/\2/p' "$from" | tail -n 1)
[[ -n $count ]] || { echo "instruction-budget: $from: no totals: line (not a callgrind output?)" >&2; exit 2; }
line=$(awk -v n="$count" -v g="$budget_g" 'BEGIN {
    printf "uwbd --replay, the paper pair: %.3f G instructions (callgrind), budget %s G", n / 1e9, g }')
if awk -v n="$count" -v g="$budget_g" 'BEGIN { exit !(n <= g * 1e9) }'; then
    echo "$line: met"
else
    echo "$line: NOT met" >&2
    exit 1
fi
