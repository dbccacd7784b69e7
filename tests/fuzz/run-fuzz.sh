#!/usr/bin/env bash
# Runs every libFuzzer target BUILD_DIR/fuzz/fuzz_<name> (built by
# `make fuzz`) for SECONDS each, on a fresh copy of its seed corpus
# tests/fuzz/corpus/<name>/ plus tests/fuzz/regressions/<name>/ (the
# committed corpus never grows in place). A crash, a hang (-timeout=5), an
# input using more than 512 MB, a leak or any sanitizer report fails the
# target; the input that did it is kept in BUILD_DIR/artifacts/. Prints one
# line per target and a closing "N passed, N failed" line (.ci/run reads it).
#
# Usage: tests/fuzz/run-fuzz.sh BUILD_DIR SECONDS
# Knobs: UWB_FUZZ_TARGETS="scan frame" runs only those;
#        UWB_FUZZ_VERBOSE=1 prints each run's full log.
set -euo pipefail

if [[ $# -ne 2 || ! "$2" =~ ^[0-9]+$ || "$2" -lt 1 ]]; then
    echo "usage: $0 BUILD_DIR SECONDS (a whole number >= 1)" >&2
    exit 2
fi
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
readonly BUILD_DIR="$1" SECONDS_EACH="$2"
readonly ARTIFACTS="$BUILD_DIR/artifacts"
readonly RUNS="$BUILD_DIR/runs"
mkdir -p "$ARTIFACTS" "$RUNS"

# halt_on_error: the first UBSan report ends the run as a crash would.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# quarantine_size_mb=64: ASan's default 256 MB quarantine of freed memory
# counts toward -rss_limit_mb; fuzz_analysis frees tens of MB per input and
# reached 532 MB with 26 MB live (a clean-clone CI run). With 64 MB its RSS
# levels off near 200 MB, and a use after free is still caught.
export ASAN_OPTIONS="detect_leaks=1:quarantine_size_mb=64${ASAN_OPTIONS:+:$ASAN_OPTIONS}"

targets=()
if [[ -n "${UWB_FUZZ_TARGETS:-}" ]]; then
    read -r -a targets <<<"$UWB_FUZZ_TARGETS"
else
    for source in tests/fuzz/fuzz_*.c; do
        name="${source#tests/fuzz/fuzz_}"
        targets+=("${name%.c}")
    done
fi

# What went wrong, from a libFuzzer log.
classify() {
    local log="$1"
    if grep -q 'ERROR: libFuzzer: timeout' "$log"; then echo "hang (over 5 s on one input)"
    elif grep -q 'ERROR: libFuzzer: out-of-memory' "$log"; then echo "out of memory (over 512 MB)"
    elif grep -q 'ERROR: LeakSanitizer' "$log"; then echo "leak"
    elif grep -q 'ERROR: AddressSanitizer' "$log"; then
        echo "AddressSanitizer: $(grep -m1 -o 'ERROR: AddressSanitizer: [a-z-]*' "$log" | cut -d' ' -f3)"
    elif grep -q 'runtime error:' "$log"; then
        echo "UBSan: $(grep -m1 'runtime error:' "$log" | sed 's/.*runtime error: //' | cut -c1-100)"
    elif grep -q 'fuzz contract broken:' "$log"; then
        echo "contract: $(grep -m1 'fuzz contract broken:' "$log" | sed 's/.*broken: //' | cut -c1-100)"
    elif grep -q 'ERROR: libFuzzer: deadly signal' "$log"; then echo "crash (deadly signal)"
    else echo "failed (see log)"
    fi
}

# One target's run: its report line on stdout, "ok" or "failed" in
# $RUNS/NAME.result.
fuzz_one() {
    local name="$1" binary log work status runs coverage artifact
    binary="$BUILD_DIR/fuzz/fuzz_$name"
    log="$RUNS/$name.log"
    if [[ ! -x "$binary" ]]; then
        printf '%-12s %12s  FAILED: %s not built\n' "$name" "-" "$binary"
        echo failed >"$RUNS/$name.result"
        return 0
    fi
    work="$RUNS/$name-corpus"
    rm -rf "$work"
    mkdir -p "$work"
    cp -R "tests/fuzz/corpus/$name/." "$work/"
    if [[ -d "tests/fuzz/regressions/$name" ]]; then
        cp -R "tests/fuzz/regressions/$name/." "$work/"
    fi
    status=0
    "$binary" -max_total_time="$SECONDS_EACH" -timeout=5 -rss_limit_mb=512 -detect_leaks=1 \
        -print_final_stats=1 -artifact_prefix="$ARTIFACTS/$name-" "$work" >"$log" 2>&1 || status=$?
    runs="$(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)"
    [[ -n "$runs" ]] || runs="$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#' || true)"
    [[ -n "$runs" ]] || runs="?"
    # A run that exits 0 but printed a sanitizer report still fails.
    if [[ "$status" == 0 ]] && ! grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$log"; then
        coverage="$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)"
        printf '%-12s %12s runs  ok (%s s, %s, %d seeds)\n' "$name" "$runs" "$SECONDS_EACH" "${coverage:-cov: ?}" \
            "$(find "tests/fuzz/corpus/$name" -type f | wc -l)"
        echo ok >"$RUNS/$name.result"
    else
        artifact="$(grep -o "Test unit written to [^ ]*" "$log" | tail -n 1 | sed 's/Test unit written to //' || true)"
        printf '%-12s %12s runs  FAILED: %s%s (log: %s)\n' "$name" "$runs" "$(classify "$log")" \
            "${artifact:+, input: $artifact}" "$log"
        echo failed >"$RUNS/$name.result"
        tail -n 40 "$log" | sed 's/^/    /'
    fi
    if [[ "${UWB_FUZZ_VERBOSE:-0}" == 1 ]]; then
        sed 's/^/    /' "$log"
    fi
}

# Targets run UWB_FUZZ_JOBS at a time (default the number of CPUs): each
# libFuzzer run is one thread, so two at once halve the stage.
jobs="${UWB_FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}"
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "run-fuzz: UWB_FUZZ_JOBS=$jobs: want a whole number >= 1" >&2; exit 2; }
running=0
for name in "${targets[@]}"; do
    rm -f "$RUNS/$name.result"
    if ((running >= jobs)); then
        wait -n || true
        running=$((running - 1))
    fi
    fuzz_one "$name" >"$RUNS/$name.report" 2>&1 &
    running=$((running + 1))
done
wait || true
passed=0
failed=0
for name in "${targets[@]}"; do
    cat "$RUNS/$name.report"
    if [[ "$(cat "$RUNS/$name.result" 2>/dev/null)" == ok ]]; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
    fi
done
echo "fuzz: ${#targets[@]} targets, $SECONDS_EACH s each; artifacts in $ARTIFACTS"
echo "$passed passed, $failed failed"
[[ "$failed" == 0 ]]
