#!/usr/bin/env bash
# `make bench` asserts the replay budget (issue 18): uwbbench --assert-budget
# exits 1, naming the figures and the budget, when uwbd's whole replay of
# the paper pair is over its time or its memory budget, and 0 within it.
# The real budget (100 ms, 16 MiB) is make bench's to judge, on a quiet
# machine; here budgets nothing can meet, or nothing can miss, check the
# verdict itself in any build (sanitizers, qemu).
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-bench-budget

pair=("$REPO/tests/fixtures/fdtd2d-paper-up20mm.uwbscan" "$REPO/tests/fixtures/fdtd2d-paper-intact.uwbscan")
# bench NAME ARGS...: uwbbench once through the replay; $status, NAME.out, NAME.err.
bench() {
    local name=$1
    shift
    status=0
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbbench" --replay-only --quick --replay "${pair[@]}" --assert-budget "$@" \
        > "$name.out" 2> "$name.err" || status=$?
}

bench slow --budget-ms 1 --budget-mib 100000
[[ $status == 1 ]] && grep -q '^uwbbench: replay budget NOT met: .*; the budget is 1 ms and 100000 MiB$' slow.err &&
    grep -q 'whole replay <= 1 ms, CPU time .* NOT met$' slow.out ||
    fail "over the time budget: exit $status: $(cat slow.err) $(tail -5 slow.out)"
pass "over the time budget: exit 1, the figures and the budget named"

bench big --budget-ms 100000 --budget-mib 1
[[ $status == 1 ]] && grep -q '^uwbbench: replay budget NOT met: .* peak RSS [0-9.]* MiB; the budget is 100000 ms and 1 MiB$' big.err &&
    grep -q 'uwbd peak RSS <= 1 MiB .* NOT met$' big.out ||
    fail "over the memory budget: exit $status: $(cat big.err) $(tail -5 big.out)"
pass "over the memory budget: exit 1"

bench within --budget-ms 100000 --budget-mib 100000
[[ $status == 0 ]] && grep -q '^replay budget met: wall .* MiB$' within.out &&
    grep -q 'verdict: status alarm' within.out || fail "within budget: exit $status: $(cat within.err) $(tail -5 within.out)"
pass "within the budget: exit 0, the paper pair's alarm replayed"

bench bad --budget-ms fast
[[ $status == 64 ]] && grep -q "budget-ms: 'fast' is not a positive number" bad.err || fail "--budget-ms fast: exit $status: $(cat bad.err)"
pass "a budget that is not a number: exit 64"

echo "$passed passed"
