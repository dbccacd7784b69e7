#!/usr/bin/env bash
# Runs every unit-test binary BUILD_DIR/tests/test_* and every end-to-end
# script tests/e2e/test_*.sh, then sums the results into one closing line:
#     N passed, N failed[, N skipped]
# N counts test cases: Unity's summary ("N Tests M Failures K Ignored") of
# each binary, and one per e2e script.  A binary that crashes, times out,
# exits non-zero or prints no summary counts at least one failure.
#
# Usage: tests/run-tests.sh BUILD_DIR [RUNNER]
#   RUNNER   optional command prefix for each test binary, e.g.
#            "qemu-aarch64 -L /" for cross-built tests
#
# Environment given to every test binary and e2e script (run from the repo
# root, stdin from /dev/null):
#   UWB_BUILD_DIR    BUILD_DIR as an absolute path (uwbd, uwbsim, ... are
#                    there; the C tests also get it as a relative macro)
#   UWB_EXEC_PREFIX  RUNNER (empty for native runs): put it before any
#                    program from UWB_BUILD_DIR that a test starts, since
#                    qemu-user does not follow exec into a foreign binary
# Knobs: UWB_TEST_TIMEOUT (seconds per binary or script, default 300; 900
#        with a RUNNER: an emulator is that much slower),
#        UWB_TEST_VERBOSE=1 (print every test's full output),
#        UWB_TEST_JOBS (programs run at once, default the number of CPUs,
#        at most 4): most e2e scripts wait on a paced carriage, so two at a
#        time nearly halve the run; each report is printed whole when its
#        program ends, and the closing line counts them all.
#        UWB_TEST_ONLY (an extended regex: run only the programs whose name,
#        "test_NAME" or "e2e/test_NAME.sh", it matches),
#        UWB_TEST_E2E_LIST (a file: run only the e2e scripts it names, one
#        "test_NAME.sh  reason" a line, # comments; make test-arm's list).
# An e2e script that exits 77 counts as skipped (automake convention).
#
# Where the time goes: programs start longest first (by BUILD_DIR/
# test-times.txt, what the last run measured, else tests/test-times.txt, a
# native run's), so both cores stay busy to the end; the run closes with its
# ten slowest programs (wall and CPU seconds) and its own wall time. The
# whole report is kept in BUILD_DIR/test-logs/run.log and each failing
# program's whole output in BUILD_DIR/test-logs/NAME.log.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
    echo "usage: $0 BUILD_DIR [RUNNER]" >&2
    exit 2
fi
[[ -d "$1" ]] || { echo "run-tests: $1: no such build directory" >&2; exit 2; }
BUILD_DIR="$(cd "$1" && pwd)"
readonly BUILD_DIR
readonly RUNNER="${2:-}"
# An emulator (RUNNER) runs FFTW ~80x slower: three times the time.
default_timeout=300
[[ -z "$RUNNER" ]] || default_timeout=900
readonly TIMEOUT_SECONDS="${UWB_TEST_TIMEOUT:-$default_timeout}"
readonly VERBOSE="${UWB_TEST_VERBOSE:-0}"
readonly TAIL_LINES=40
jobs="${UWB_TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}"
[[ "$jobs" =~ ^[0-9]+$ && "$jobs" -ge 1 ]] || { echo "run-tests: UWB_TEST_JOBS=$jobs: want a whole number >= 1" >&2; exit 2; }
((jobs > 4)) && jobs=4
readonly jobs

cd "$(dirname "${BASH_SOURCE[0]}")/.."
readonly ONLY="${UWB_TEST_ONLY:-}"
readonly E2E_LIST="${UWB_TEST_E2E_LIST:-}"
[[ -z "$E2E_LIST" || -f "$E2E_LIST" ]] || { echo "run-tests: UWB_TEST_E2E_LIST=$E2E_LIST: no such file" >&2; exit 2; }
readonly TIMES_FILE="$BUILD_DIR/test-times.txt"
readonly SEED_TIMES_FILE="tests/test-times.txt"
readonly LOG_DIR="$BUILD_DIR/test-logs"
run_start="$EPOCHREALTIME"
# A fresh log directory per run: what is in it is this run's.
rm -rf "$LOG_DIR"
mkdir -p "$LOG_DIR"
# A test that runs make (test_install, test_operator_pages) starts afresh:
# make test's jobserver descriptors are not the tests' (fd 3 is reused just
# below), and a child make handed them reads a closed pipe and stops.
unset MAKEFLAGS MFLAGS
exec 3>&1 > >(tee "$LOG_DIR/run.log") 2>&1
tee_pid=$!

export UWB_BUILD_DIR="$BUILD_DIR"
export UWB_EXEC_PREFIX="$RUNNER"
# Stack traces for UBSan reports; ASan already prints them.
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
read -r -a runner_words <<<"$RUNNER"

total_passed=0
total_failed=0
total_skipped=0
programs_run=0
results="$(mktemp -d)"
trap 'rm -rf "$results"' EXIT
# Stopped from outside: stop the programs' process groups too, not only
# their subshells, so no test's daemons outlive the run.
stop_running() {
    local file
    for file in "$results"/*.pgid; do
        [[ -f "${file%.pgid}.counts" ]] || kill -TERM -- "-$(cat "$file")" 2>/dev/null || true
    done
    exit 130
}
trap stop_running INT TERM
# Each program runs in a subshell with its own output log; it leaves its
# report (for the terminal) and its counts ("passed failed skipped") in
# $results/N.report and $results/N.counts for the parent to add up.
log=""
counts=""

indent() {
    sed 's/^/    /'
}

show_output_tail() {
    if [[ -s "$log" ]]; then
        echo "    --- last $TAIL_LINES lines of output:"
        tail -n "$TAIL_LINES" "$log" | indent
    else
        echo "    --- no output"
    fi
}

# Runs a program under timeout, its output into $log. timeout puts it in a
# process group of its own: its id is left in $pgid_file, so a runner that
# is stopped can stop the programs still running (and their daemons).
run_bounded() {
    timeout -k 10 "$TIMEOUT_SECONDS" "$@" </dev/null >"$log" 2>&1 &
    echo "$!" >"$pgid_file"
    wait "$!"
}

# A failing program's whole output stays in the log directory.
keep_output() {
    local kept="$LOG_DIR/${1//\//_}.log"
    cp "$log" "$kept" 2>/dev/null && echo "    --- whole output: $kept"
}

count_lines() {
    grep -c -E "$1" "$log" || true
}

# Describes how a program ended from its exit status.
describe_exit() {
    local status="$1"
    if [[ "$status" == 124 ]]; then
        echo "timed out after ${TIMEOUT_SECONDS} s"
    elif [[ "$status" == 137 ]]; then
        echo "killed by SIGKILL (ignored the timeout's SIGTERM, or out of memory)"
    elif ((status > 128)); then
        echo "killed by signal $((status - 128)) ($(kill -l "$((status - 128))" 2>/dev/null || echo '?'))"
    else
        echo "exited with status $status"
    fi
}

elapsed_since() {
    local start="$1" now="$EPOCHREALTIME"
    awk -v a="$start" -v b="$now" 'BEGIN { printf "%.2f s", b - a }'
    # Raw seconds for the closing table and the next run's order.
    [[ -z "$times" ]] || awk -v a="$start" -v b="$now" 'BEGIN { printf "%.2f", b - a }' >"$times"
}

run_unit_binary() {
    local binary="$1" name
    name="$(basename "$binary")"
    local start="$EPOCHREALTIME" status=0
    # The braces take bash's own "Segmentation fault" report; describe_exit
    # says the same in the FAIL line.
    { run_bounded "${runner_words[@]}" "$binary"; } 2>/dev/null || status=$?
    local took
    took="$(elapsed_since "$start")"

    local summary tests=0 failures=0 ignored=0 passed failed problem=""
    summary="$(grep -E '^[0-9]+ Tests [0-9]+ Failures [0-9]+ Ignored' "$log" | tail -n 1 || true)"
    if [[ -n "$summary" ]]; then
        read -r tests _ failures _ ignored _ <<<"$summary"
        passed=$((tests - failures - ignored))
        failed=$failures
        if [[ "$status" != 0 && "$failures" == 0 ]]; then
            # e.g. LeakSanitizer reports at exit: the run as a whole failed.
            problem="$(describe_exit "$status") after its summary"
            failed=1
            passed=$((passed > 0 ? passed - 1 : 0))
        fi
    else
        # No summary: count the tests that finished before the end, plus
        # one failure for the test that was running.
        passed="$(count_lines ':PASS$')"
        failed=$(($(count_lines ':FAIL') + 1))
        ignored="$(count_lines ':IGNORE')"
        problem="$(describe_exit "$status") without a Unity summary"
    fi

    echo "$passed $failed $ignored" >"$counts"

    local ignored_note=""
    [[ "$ignored" != 0 ]] && ignored_note=", $ignored ignored"
    if [[ "$failed" == 0 ]]; then
        echo "PASS  $name  ($passed ok$ignored_note, $took)"
        if [[ "$VERBOSE" == 1 ]]; then
            indent <"$log"
        elif [[ "$ignored" != 0 ]]; then
            grep -E ':IGNORE' "$log" | indent || true   # a skip says why
        fi
        return 0
    fi
    echo "FAIL  $name  ($passed ok, $failed failing$ignored_note, $took)${problem:+: $problem}"
    keep_output "$name"
    if [[ "$VERBOSE" == 1 ]]; then
        indent <"$log"
        return 0
    fi
    grep -E ':FAIL' "$log" | indent || true
    if [[ -n "$problem" ]]; then
        show_output_tail
    fi
}

run_e2e_script() {
    local script="$1" name
    name="e2e/$(basename "$script")"
    local start="$EPOCHREALTIME" status=0
    { run_bounded bash "$script"; } 2>/dev/null || status=$?
    local took
    took="$(elapsed_since "$start")"

    if [[ "$status" == 0 ]]; then
        echo "1 0 0" >"$counts"
        echo "PASS  $name  ($took)"
        if [[ "$VERBOSE" == 1 ]]; then indent <"$log"; fi
    elif [[ "$status" == 77 ]]; then
        echo "0 0 1" >"$counts"
        echo "SKIP  $name  ($took)"
        tail -n 3 "$log" | indent   # the script's reason
    else
        echo "0 1 0" >"$counts"
        echo "FAIL  $name  ($took): $(describe_exit "$status")"
        keep_output "$name"
        if [[ "$VERBOSE" == 1 ]]; then
            indent <"$log"
        else
            show_output_tail
        fi
    fi
}

# Prints a finished program's report and adds its counts (one that left
# none, e.g. killed from outside, counts as a failure).
collect() {
    local index="$1" passed=0 failed=1 skipped=0
    cat "$results/$index.report"
    if [[ -s "$results/$index.counts" ]]; then
        read -r passed failed skipped <"$results/$index.counts"
    else
        echo "FAIL  ${names[$index]}  (no result)"
    fi
    total_passed=$((total_passed + passed))
    total_failed=$((total_failed + failed))
    total_skipped=$((total_skipped + skipped))
    programs_run=$((programs_run + 1))
}

# The e2e scripts first: they are the long ones, so the pool ends evenly.
kinds=()
paths=()
names=()
selected() {
    [[ -z "$ONLY" || "$1" =~ $ONLY ]]
}
listed_e2e() {
    [[ -z "$E2E_LIST" ]] || grep -qE "^$1([[:space:]]|\$)" "$E2E_LIST"
}
shopt -s nullglob
for script in tests/e2e/test_*.sh; do
    selected "e2e/$(basename "$script")" || continue
    listed_e2e "$(basename "$script")" || continue
    kinds+=(e2e)
    paths+=("$script")
    names+=("e2e/$(basename "$script")")
done
for binary in "$BUILD_DIR"/tests/test_*; do
    [[ -f "$binary" && -x "$binary" ]] || continue
    name="$(basename "$binary")"
    # A binary whose source was renamed or removed would test stale code.
    if [[ ! -f "tests/unit/$name.c" ]]; then
        echo "note  $name: no tests/unit/$name.c any more; not run" >&2
        continue
    fi
    selected "$name" || continue
    kinds+=(unit)
    paths+=("$binary")
    names+=("$name")
done

if [[ -n "$E2E_LIST" ]]; then
    while read -r listed reason; do
        [[ -z "$listed" || "$listed" == \#* ]] && continue
        [[ -f "tests/e2e/$listed" ]] || { echo "run-tests: $E2E_LIST names $listed, which is not in tests/e2e" >&2; exit 2; }
        [[ -n "$reason" ]] || { echo "run-tests: $E2E_LIST: $listed without its reason" >&2; exit 2; }
    done <"$E2E_LIST"
    all_e2e=(tests/e2e/test_*.sh)
    echo "note  e2e: the $(grep -c '^test_' "$E2E_LIST") scripts $E2E_LIST names, of ${#all_e2e[@]}" >&2
fi

# Longest first: each program's seconds from the last run here, else from
# the seed file; one never timed counts as long (an e2e script) or short.
declare -A expected=()
for file in "$SEED_TIMES_FILE" "$TIMES_FILE"; do
    [[ -f "$file" ]] || continue
    while read -r seconds name; do
        [[ "$seconds" =~ ^[0-9]+(\.[0-9]+)?$ && -n "$name" ]] && expected[$name]=$seconds
    done <"$file"
done
order=()
while read -r _ index; do
    order+=("$index")
done < <(for index in "${!paths[@]}"; do
    guess=1
    [[ "${kinds[$index]}" == e2e ]] && guess=60
    echo "${expected[${names[$index]}]:-$guess} $index"
done | sort -k1,1gr -k2,2n)

declare -A running=()   # pid -> index
# Waits for one running program to end and collects it.
reap_one() {
    local done_pid
    wait -n -p done_pid "${!running[@]}" || true
    collect "${running[$done_pid]}"
    unset "running[$done_pid]"
}
for index in "${order[@]}"; do
    while ((${#running[@]} >= jobs)); do
        reap_one
    done
    (
        log="$results/$index.log"
        counts="$results/$index.counts"
        times="$results/$index.time"
        pgid_file="$results/$index.pgid"
        trap - INT TERM
        if [[ "${kinds[$index]}" == e2e ]]; then
            run_e2e_script "${paths[$index]}"
        else
            run_unit_binary "${paths[$index]}"
        fi
        rm -f "$log"
        # The CPU seconds of the program and everything it waited for.
        # (times itself, not in a pipeline: a pipeline's fork has no children)
        times >"$results/$index.times"
        awk 'NR == 2 { for (i = 1; i <= 2; i++) { sub(/s$/, "", $i); split($i, ms, "m"); cpu += ms[1] * 60 + ms[2] } printf "%.2f\n", cpu }' "$results/$index.times" >"$results/$index.cpu"
    ) >"$results/$index.report" 2>&1 &
    running[$!]=$index
done
while ((${#running[@]} > 0)); do
    reap_one
done

if [[ "$programs_run" == 0 ]]; then
    echo "run-tests: no test binaries in $BUILD_DIR/tests and no tests/e2e/test_*.sh" >&2
    total_failed=$((total_failed + 1))
fi
# The ten slowest, and the times kept (atomically) for the next run's order.
table="$results/times.table"
for index in "${!paths[@]}"; do
    [[ -s "$results/$index.time" ]] || continue
    printf '%s %s %s\n' "$(cat "$results/$index.time")" "$(cat "$results/$index.cpu" 2>/dev/null || echo '?')" "${names[$index]}"
done | sort -k1,1gr >"$table"
if [[ -s "$table" ]]; then
    echo "slowest (wall s, cpu s):"
    head -n 10 "$table" | awk '{ printf "    %8.2f %8s  %s\n", $1, $2, $3 }'
    {
        # the earlier times of programs this run left out, then this run's
        [[ -f "$TIMES_FILE" ]] && awk 'NR == FNR { ran[$3] = 1; next } !($2 in ran)' "$table" "$TIMES_FILE"
        awk '{ print $1, $3 }' "$table"
    } >"$TIMES_FILE.tmp" && mv "$TIMES_FILE.tmp" "$TIMES_FILE"
fi
awk -v a="$run_start" -v b="$EPOCHREALTIME" -v n="$programs_run" -v j="$jobs" -v f="$table" 'BEGIN {
    while ((getline line < f) > 0) { split(line, x, " "); sum += x[1] }
    printf "wall time %.1f s: %d programs, %.1f s of test time, %d at a time\n", b - a, n, sum, j }'

closing="$total_passed passed, $total_failed failed"
[[ "$total_skipped" != 0 ]] && closing+=", $total_skipped skipped"
echo "$closing"
# Let tee write the last lines before make goes on.
exec >&3 2>&1
wait "$tee_pid" 2>/dev/null || true
[[ "$total_failed" == 0 ]]
