#!/usr/bin/env bash
# Issue 27, break 2: a FIFO in the state directory. Before, a FIFO at
# latest.json or baseline/pending.json held the start in open() for ever,
# and one at verdicts.jsonl hung the first scan beyond SIGTERM. Now each is
# refused at once, named in the log as "is a FIFO, not a regular file":
# verdicts.jsonl stops the start (exit 73), the others are logged and the
# daemon runs on; either way SIGTERM ends it within a second.
set -euo pipefail

source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-state-fifo

ctl() { uwbd ctl --socket run/control.sock "$@"; }

start_emulated_board --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 11 --start-mm 5 --steps-per-mm 10
cp "$REPO/board/emulated/uwbd.json" uwbd.json

# Up to 5 s for pid to exit; its exit status in $exit_rc, or 1 if it did not.
exited_within() {
    local pid=$1 tenths=$2
    for _ in $(seq "$tenths"); do
        if ! kill -0 "$pid" 2>/dev/null; then
            set +e; wait "$pid"; exit_rc=$?; set -e
            return 0
        fi
        sleep 0.1
    done
    return 1
}

for rel in verdicts.jsonl latest.json baseline/pending.json; do
    rm -rf run/state
    mkdir -p run/state/baseline
    mkfifo "run/state/$rel"
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config uwbd.json "${root_flag[@]}" \
        --set carriage.steps_per_mm=10 > uwbd.log 2>&1 &
    daemon_pid=$!
    pids+=($daemon_pid)
    if [[ $rel == verdicts.jsonl ]]; then
        exited_within "$daemon_pid" 50 || fail "FIFO at $rel: the start did not end within 5 s"
        [[ $exit_rc == 73 ]] || fail "FIFO at $rel: exit $exit_rc, want 73"
    else
        wait_for ctl status || fail "FIFO at $rel: uwbd does not answer on its control socket"
        kill -TERM "$daemon_pid"
        exited_within "$daemon_pid" 10 || fail "FIFO at $rel: SIGTERM did not stop uwbd within 1 s"
    fi
    grep -q "$rel: cannot open: is a FIFO, not a regular file" uwbd.log ||
        fail "FIFO at $rel: not named in the log"
    [[ -p run/state/$rel ]] || fail "FIFO at $rel: removed, not left alone"
    pass "FIFO at $rel: refused at once and named$([[ $rel == verdicts.jsonl ]] && echo ", start refused (exit 73)" || echo ", SIGTERM within 1 s")"
done

echo "$passed passed"
