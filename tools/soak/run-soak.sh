#!/usr/bin/env bash
# Soak: many accelerated scan cycles of uwbd against the emulated board
# (uwbemu), watching what must stay flat on an appliance that runs for
# years: the daemon's resident memory, its open file descriptors and the
# size of its state directory under retention. Prints a table of samples
# and one summary line; exits non-zero when
#   - a cycle gave an `error` verdict, or no verdict, or the daemon died;
#   - the open descriptors, once the cycle's client has gone, are not the
#     same count at every sample;
#   - the archive holds more scans, or verdicts.jsonl more lines, than
#     retention.max_scans, or the state directory once full grew by more
#     than 10 % by the end;
#   - the lowest VmRSS of the last quarter of the samples is above that of
#     the first quarter after warm-up by more than the tolerance (not checked under ASan, valgrind or qemu-user,
#     whose own memory is in the process's RSS: printed only);
#   - SIGTERM does not end the daemon with exit 0, or a sanitizer or
#     valgrind reported anything.
# Nothing is timed: the seconds per cycle are printed, never asserted.
#
# "Accelerated": no waits in the scan (scan.time_scale 0), one pulse per
# position (digitiser.stack 1) and a coarse emulated carriage (5 microsteps
# per mm on both sides), cycles back to back on `uwbd ctl scan`. The imaging,
# images, archive, baseline comparison and retention are the appliance's own.
#
# Usage: tools/soak/run-soak.sh [options]
#   --build DIR          build directory with uwbd and uwbemu ($UWB_BUILD_DIR, else build)
#   --cycles N           scan cycles after the commissioning one (default 1000)
#   --every K            sample every K cycles (default N/20, at least 1)
#   --max-scans N        retention.max_scans (default 20)
#   --warmup N           cycles before the first RSS window (default max(max-scans, N/10))
#   --rss-tolerance-kb N allowed VmRSS growth, first to last window (default 1024)
#   --daemon-wrapper CMD run uwbd under CMD, e.g. "valgrind --leak-check=full --error-exitcode=99"
#   --keep               keep the work directory (printed at the end)
# Environment: UWB_EXEC_PREFIX is put before uwbd, uwbd ctl and uwbemu (qemu-user).
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${UWB_BUILD_DIR:-build}
cycles=1000
every=""
max_scans=20
warmup=""
rss_tolerance_kb=1024
wrapper=""
keep=0

die() { echo "run-soak: $*" >&2; exit 2; }
need_number() { [[ $2 =~ ^[0-9]+$ ]] || die "$1: want a whole number, got '$2'"; }
while [[ $# -gt 0 ]]; do
    case "$1" in
        --build) build=${2:?--build needs a directory}; shift 2 ;;
        --cycles) need_number "$1" "${2:-}"; cycles=$2; shift 2 ;;
        --every) need_number "$1" "${2:-}"; every=$2; shift 2 ;;
        --max-scans) need_number "$1" "${2:-}"; max_scans=$2; shift 2 ;;
        --warmup) need_number "$1" "${2:-}"; warmup=$2; shift 2 ;;
        --rss-tolerance-kb) need_number "$1" "${2:-}"; rss_tolerance_kb=$2; shift 2 ;;
        --daemon-wrapper) wrapper=${2?--daemon-wrapper needs a command}; shift 2 ;;
        --keep) keep=1; shift ;;
        -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown argument: $1 (see --help)" ;;
    esac
done
((cycles >= 1)) || die "--cycles: at least 1"
((max_scans >= 1)) || die "--max-scans: at least 1 (0 would switch retention off)"
[[ -n $every ]] || every=$((cycles / 20 > 0 ? cycles / 20 : 1))
((every >= 1)) || die "--every: at least 1"
[[ -n $warmup ]] || warmup=$((cycles / 10 > max_scans ? cycles / 10 : max_scans))
[[ -d $build ]] || die "$build: no such build directory"
build=$(cd "$build" && pwd)
for program in uwbd uwbemu; do
    [[ -x $build/$program ]] || die "$build/$program: not built (make BUILD=... all)"
done
read -r -a prefix <<<"${UWB_EXEC_PREFIX:-}"
read -r -a wrap <<<"$wrapper"

# Whose memory the RSS figure also counts: then it is printed, not judged.
rss_judged=1 rss_note=""
if grep -qa __asan_init "$build/uwbd"; then
    rss_judged=0 rss_note="ASan build: its quarantine and shadow memory are in the RSS"
elif [[ -n $wrapper ]]; then
    rss_judged=0 rss_note="under ${wrap[0]}: its own memory is in the RSS"
elif [[ ${#prefix[@]} -gt 0 ]]; then
    rss_judged=0 rss_note="under ${prefix[0]}: its translation cache is in the RSS"
fi

work=$(mktemp -d /tmp/uwbd-soak-XXXXXX)
emu_pid="" daemon_pid=""
cleanup() {
    [[ -n $daemon_pid ]] && kill "$daemon_pid" 2>/dev/null && wait "$daemon_pid" 2>/dev/null
    [[ -n $emu_pid ]] && kill "$emu_pid" 2>/dev/null && wait "$emu_pid" 2>/dev/null
    if ((keep)); then echo "run-soak: work directory kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
cd "$work"
mkdir run

failures=()
failed() { failures+=("$*"); echo "run-soak: FAIL: $*" >&2; }
# The end of the daemon's log, for a failure that stops the run.
stop_run() {
    echo "run-soak: FAIL: $*" >&2
    echo "--- last lines of the daemon's log ($work/uwbd.log):" >&2
    tail -n 30 uwbd.log >&2 || true
    exit 1
}
wait_for() {
    for _ in $(seq 300); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
    return 1
}
ctl() { "${prefix[@]}" "$build/uwbd" ctl --socket run/control.sock "$@"; }
daemon_alive() { kill -0 "$daemon_pid" 2>/dev/null; }

# ---- the emulated board and the daemon ------------------------------------
steps_per_mm=5
"${prefix[@]}" "$build/uwbemu" --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock \
    --control unix:run/emu.sock --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7 \
    --steps-per-mm "$steps_per_mm" > emu.log 2>&1 &
emu_pid=$!
wait_for "${prefix[@]}" "$build/uwbemu" --ctl unix:run/emu.sock status || stop_run "uwbemu did not come up: $(cat emu.log)"

root_flag=()
[[ $(id -u) == 0 ]] && root_flag=(--allow-root)
settings=(--set digitiser.stack=1 --set "carriage.steps_per_mm=$steps_per_mm" --set scan.time_scale=0
          --set schedule.interval_s=0 --set "retention.max_scans=$max_scans" --set retention.max_age_days=0)
"${prefix[@]}" "${wrap[@]}" "$build/uwbd" --config "$REPO/board/emulated/uwbd.json" "${root_flag[@]}" \
    "${settings[@]}" > uwbd.log 2>&1 &
daemon_pid=$!
wait_for ctl status || stop_run "uwbd does not answer on its control socket"

# ---- sampling ------------------------------------------------------------------
fd_count() { local fds=(/proc/"$daemon_pid"/fd/*); echo "${#fds[@]}"; }
rss_kb() { awk '/^VmRSS:/ { print $2 }' /proc/"$daemon_pid"/status; }
# A finished `uwbd ctl` closes its end at once, the daemon its end when it
# sees that: wait (up to ~3 s) for the count to come back to the reference.
# A leaked descriptor never does.
settled_fds() {
    local want=$1 n
    for _ in $(seq 60); do
        n=$(fd_count)
        [[ $n == "$want" ]] && break
        sleep 0.05
    done
    echo "$n"
}
archive_scans() { find run/state/archive -name '*.json' | wc -l; }
log_lines() { if [[ -f run/state/verdicts.jsonl ]]; then wc -l < run/state/verdicts.jsonl; else echo 0; fi; }
du_kb() { du -sk "$1" | cut -f1; }

samples=()   # "cycle rss fds archive_kb scans lines state_kb"
sample() {
    local cycle=$1 fds
    fds=$(settled_fds "$fd_reference")
    samples+=("$cycle $(rss_kb) $fds $(du_kb run/state/archive) $(archive_scans) $(log_lines) $(du_kb run/state)")
}

declare -A statuses=()
verdicts=0
one_cycle() {
    local reply rc=0
    reply=$(ctl scan 2>&1) || rc=$?
    daemon_alive || stop_run "the daemon died during cycle $1"
    [[ $reply =~ \"class\":\"VERDICT\",\"status\":\"([a-z]+)\" ]] ||
        stop_run "cycle $1: no verdict (uwbd ctl exit $rc): $reply"
    local status=${BASH_REMATCH[1]}
    statuses[$status]=$((${statuses[$status]:-0} + 1))
    verdicts=$((verdicts + 1))
    if [[ $status == error ]]; then
        failed "cycle $1: error verdict: $(sed -n 's/.*"reason":"\([^"]*\)".*/\1/p' <<<"$reply")"
    fi
}

# Commissioning: the first cycle becomes the baseline; every later one is compared with it.
ctl baseline set > /dev/null || stop_run "baseline set refused"
one_cycle 0
[[ -n ${statuses[edges]:-} ]] || stop_run "the commissioning scan did not find the winding"
fd_reference=$(fd_count)
for _ in $(seq 10); do
    n=$(fd_count)
    ((n < fd_reference)) && fd_reference=$n
    sleep 0.02
done
sample 0
started=$EPOCHREALTIME
for ((c = 1; c <= cycles; c++)); do
    one_cycle "$c"
    if ((c % every == 0 || c == cycles)); then sample "$c"; fi
done
elapsed=$(awk -v a="$started" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')

# ---- shutdown ------------------------------------------------------------------
kill -TERM "$daemon_pid"
set +e; wait "$daemon_pid"; exit_code=$?; set -e
daemon_pid=""
((exit_code == 0)) || failed "SIGTERM: the daemon exited $exit_code, want 0"
if grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:' uwbd.log; then
    failed "sanitizer report in the daemon's log: $(grep -m1 -E 'ERROR: |runtime error:' uwbd.log)"
fi
valgrind_note=""
if grep -q '^==[0-9]*== ERROR SUMMARY' uwbd.log; then
    valgrind_note="; valgrind: $(grep -m1 -o 'ERROR SUMMARY: [0-9]* errors' uwbd.log | tail -n1), \
$(grep -m1 -o 'definitely lost: [0-9,]* bytes' uwbd.log || echo 'no leaks possible')"
fi
grep -q "stopped; hardware left safe" uwbd.log || failed "no clean-shutdown line in the daemon's log"

# ---- table and judgement ---------------------------------------------------------
printf '%8s %9s %5s %11s %6s %7s %9s\n' cycle rss_kB fds archive_kB scans lines state_kB
for s in "${samples[@]}"; do
    read -r c rss fds akb scans lines skb <<<"$s"
    printf '%8d %9d %5d %11d %6d %7d %9d\n' "$c" "$rss" "$fds" "$akb" "$scans" "$lines" "$skb"
done

for s in "${samples[@]}"; do
    read -r c rss fds akb scans lines skb <<<"$s"
    [[ $fds == "$fd_reference" ]] || failed "cycle $c: $fds open descriptors, $fd_reference after commissioning"
    ((scans <= max_scans)) || failed "cycle $c: $scans scans archived, retention keeps $max_scans"
    ((lines <= max_scans)) || failed "cycle $c: verdicts.jsonl has $lines lines, retention keeps $max_scans"
done

# The windows: the first quarter of the samples after warm-up, and the last quarter.
judged=()
for s in "${samples[@]}"; do
    read -r c _ <<<"$s"
    ((c >= warmup)) && judged+=("$s")
done
window=$(((${#judged[@]} + 3) / 4))
# The lowest RSS (column 2) of the samples given. An idle daemon's RSS
# jumps up by up to ~2 MB now and then with what malloc keeps cached from
# the last scan's thread; a leak lifts every sample, the lowest too.
rss_floor() { printf '%s\n' "$@" | awk 'NR == 1 || $2 < m { m = $2 } END { print m + 0 }'; }
rss_first=0 rss_last=0 state_first=0 state_last=0 slope="n/a"
if ((window >= 1 && ${#judged[@]} >= 2)); then
    rss_first=$(rss_floor "${judged[@]:0:window}")
    rss_last=$(rss_floor "${judged[@]: -window}")
    # Least-squares growth per cycle over the judged samples: a figure, not a verdict.
    slope=$(printf '%s\n' "${judged[@]}" | awk '{ n++; sx += $1; sy += $2 * 1024; sxx += $1 * $1; sxy += $1 * $2 * 1024 }
        END { d = n * sxx - sx * sx; if (d > 0) printf "%+.1f B/cycle", (n * sxy - sx * sy) / d; else print "n/a" }')
    if ((rss_judged && rss_last > rss_first + rss_tolerance_kb)); then
        failed "VmRSS grew from ${rss_first} kB to ${rss_last} kB after warm-up (tolerance ${rss_tolerance_kb} kB)"
    fi
else
    rss_note="${rss_note:+$rss_note; }too few samples after warm-up ($warmup cycles) to compare windows"
    rss_judged=0
fi
# Once retention has filled the archive, the state directory must not grow.
full=()
for s in "${samples[@]}"; do
    read -r c _ <<<"$s"
    ((c > max_scans)) && full+=("$s")
done
if ((${#full[@]} >= 2)); then
    read -r _ _ _ _ _ _ state_first <<<"${full[0]}"
    read -r _ _ _ _ _ _ state_last <<<"${full[-1]}"
    if ((state_last * 10 > state_first * 11)); then
        failed "state directory grew from ${state_first} kB to ${state_last} kB with the archive full"
    fi
else
    failed "too few samples after the archive filled (cycle > $max_scans) to judge its size: run more cycles"
fi

read -r _ rss0 fds0 _ _ _ _ <<<"${samples[0]}"
read -r _ rss_end fds_end akb_end scans_end lines_end _ <<<"${samples[-1]}"
status_list=""
for s in $(printf '%s\n' "${!statuses[@]}" | sort); do status_list+="${status_list:+, }${statuses[$s]} $s"; done
per_cycle=$(awk -v t="$elapsed" -v n="$cycles" 'BEGIN { printf "%.3f", t / n }')
echo "soak: $cycles cycles + commissioning, $verdicts verdicts ($status_list) in $elapsed s ($per_cycle s/cycle)"
echo "soak: VmRSS $rss0 kB after commissioning, $rss_end kB at the end; lowest in the first window $rss_first kB, in the last $rss_last kB" \
     "(windows of $window samples after $warmup cycles; slope $slope; $( ((rss_judged)) && echo "tolerance $rss_tolerance_kb kB" || echo "not judged: $rss_note"))"
echo "soak: open descriptors $fds0 -> $fds_end; archive $akb_end kB in $scans_end scans (retention $max_scans)," \
     "verdicts.jsonl $lines_end lines; state directory $state_first -> $state_last kB while full"
echo "soak: SIGTERM -> exit $exit_code$valgrind_note"
if ((${#failures[@]})); then
    echo "soak: FAILED (${#failures[@]}): ${failures[0]}${failures[1]:+; ...}"
    echo "--- last lines of the daemon's log:"
    tail -n 20 uwbd.log
    exit 1
fi
echo "soak: passed"
