#!/usr/bin/env bash
# Issue 19, item 8: short errors. A mistyped option is one line naming it
# (and the option meant) plus "see --help", not the usage; value errors show
# the values; a missing emulated board says to start uwbemu and how; a
# failed start by hand leaves no state directory behind.
set -uo pipefail
source tests/e2e/daemon_e2e.sh
e2e_workdir uwbd-cli-errors
rmdir run   # this test wants to see run/ created, or not

# one_line_error NAME WANT_RC PATTERN COMMAND...: exit WANT_RC, stdout empty,
# stderr exactly one line matching PATTERN (grep -E) that says "see ... --help".
one_line_error() {
    local name=$1 want=$2 pattern=$3
    shift 3
    "$@" > "$name.out" 2> "$name.err"
    local rc=$?
    [[ $rc == "$want" ]] || fail "$name: exit $rc, want $want: $(cat "$name.err")"
    [[ ! -s "$name.out" ]] || fail "$name: stdout not empty: $(head -c 300 "$name.out")"
    [[ $(wc -l < "$name.err") == 1 ]] || fail "$name: want one line of error, got $(wc -l < "$name.err"): $(head -n 5 "$name.err")"
    grep -qE -- "$pattern" "$name.err" || fail "$name: '$(cat "$name.err")' does not match '$pattern'"
}

one_line_error replay-typo 64 "unknown option '--basline' \(did you mean --baseline\?\); see uwbd --help" \
    uwbd --replay x.uwbscan --basline y.uwbscan
one_line_error daemon-typo 64 "unknown option '--state-dri' \(did you mean --state-dir\?\); see uwbd --help" \
    uwbd --config x.json --state-dri /tmp/x
one_line_error ctl-typo 64 "^uwbd ctl: unknown option '--sockt' \(did you mean --socket\?\); see uwbd ctl --help" \
    uwbd ctl --sockt x status
one_line_error no-value 64 "option '--config' needs a value; see uwbd --help" uwbd --config
one_line_error extra-value 64 "option '--help' takes no value; see uwbd --help" uwbd --replay x --help=yes
one_line_error short-unknown 64 "unknown option '-q'; see uwbd --help" uwbd --replay x -q
pass "a wrong option: one line naming it (and the option meant), then 'see --help'"
# --csv is for history only, and one rendering at a time: refused before connecting.
one_line_error ctl-csv-status 64 '^uwbd ctl: --csv is for `history \[N\]` only, not `status`$' \
    uwbd ctl --socket nowhere.sock --csv status
one_line_error ctl-csv-text 64 '^uwbd ctl: give one of --json, --text or --csv$' uwbd ctl --socket nowhere.sock --text --csv history
pass "uwbd ctl --csv with a command other than history, or with --text: one line, exit 64"

# Issue 48, finding 8: a ctl command typed without `ctl` is named with it;
# -t, which no help shows, is an unknown option, not --timeout's; --help
# starts with the daemon and ctl, the replay last.
one_line_error bare-command 64 "^uwbd: unexpected argument 'status' \(did you mean .uwbd ctl status.\?\)$" uwbd status
one_line_error bare-command-words 64 "^uwbd: unexpected argument 'history' \(did you mean .uwbd ctl history 3.\?\)$" \
    uwbd history 3
one_line_error bare-typo 64 "^uwbd: unexpected argument 'stauts' \(did you mean .uwbd ctl status.\?\)$" uwbd stauts
one_line_error bare-scan-file 64 "^uwbd: unexpected argument 'x.uwbscan' \(did you mean .uwbd --replay x.uwbscan.\?\)$" \
    uwbd x.uwbscan
one_line_error bare-other 64 "^uwbd: unexpected argument 'bananas'$" uwbd bananas
one_line_error ctl-short-t 64 "^uwbd ctl: unknown option '-t'; see uwbd ctl --help$" uwbd ctl -t 5 status
uwbd --help > usage.txt
mapfile -t usages < <(grep -n '^usage: uwbd' usage.txt | cut -d: -f1)
[[ ${#usages[@]} == 3 ]] || fail "uwbd --help: want three usages: $(grep '^usage' usage.txt)"
[[ $(sed -n "${usages[0]}p" usage.txt) == 'usage: uwbd --config FILE [options]'* &&
    $(sed -n "${usages[1]}p" usage.txt) == 'usage: uwbd ctl '* && $(sed -n "${usages[2]}p" usage.txt) == 'usage: uwbd --replay '* ]] ||
    fail "uwbd --help: want the daemon, then ctl, then --replay: $(grep '^usage' usage.txt)"
pass "uwbd status, stauts, x.uwbscan: the command meant; ctl -t unknown; uwbd --help: daemon, ctl, then --replay"

# Issue 27, break 3: --timeout covers connecting. A daemon that stopped
# accepting (its backlog full) made `uwbd ctl --timeout 1 status` wait in
# connect() until killed; now exit 75 within the timeout, saying so.
$HOST_PREFIX "$HOST_BUILD/e2e/ctl_attack" backlog backlog.sock 20 > backlog.out 2>&1 &
backlog_pid=$!
pids+=($backlog_pid)
wait_for grep -q "backlog full" backlog.out || fail "no full backlog: $(cat backlog.out)"
t0=$(date +%s%N)
timeout 10 ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" ctl --socket backlog.sock --timeout 1 status > backlog-ctl.out 2> backlog-ctl.err
rc=$?
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
[[ $rc == 75 ]] || fail "ctl against a full backlog: exit $rc after $ms ms, want 75: $(cat backlog-ctl.err)"
(( ms < 2500 )) || fail "ctl --timeout 1 against a full backlog took $ms ms"
grep -q "did not accept the connection within 1 s" backlog-ctl.err || fail "ctl's message: $(cat backlog-ctl.err)"
kill "$backlog_pid" 2> /dev/null
pass "uwbd ctl --timeout 1 against a full backlog ($(cat backlog.out)): exit 75 in $ms ms: $(cat backlog-ctl.err)"

one_line_error watch-above-alarm 64 "alarm-mm 5 \(the default\) is below --watch-mm 6" \
    uwbd --replay "$REPO/tests/fixtures/fdtd2d-paper-intact.uwbscan" --watch-mm 6
one_line_error both-given 64 "alarm-mm 3 is below --watch-mm 4:" \
    uwbd --replay "$REPO/tests/fixtures/fdtd2d-paper-intact.uwbscan" --alarm-mm 3 --watch-mm 4
one_line_error negative 64 "--watch-mm: '-1' is not a positive number of millimetres" \
    uwbd --replay "$REPO/tests/fixtures/fdtd2d-paper-intact.uwbscan" --watch-mm -1
pass "threshold errors show both values and which is the default"

# The emulated sample config, run by hand with no uwbemu: exit 69, the
# message says to start uwbemu with the config's own endpoints, and the
# run/state it would have used is not left behind.
uwbd --config "$REPO/board/emulated/uwbd.json" "${root_flag[@]}" > emu.out 2> emu.err
rc=$?
[[ $rc == 69 ]] || fail "no emulated board: exit $rc, want 69: $(cat emu.err)"
grep -q "cannot connect to socket run/gpio.sock" emu.err || fail "no emulated board: $(cat emu.err)"
grep -qF "start it first, in $work: uwbemu --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock" emu.err ||
    fail "no hint to start uwbemu: $(cat emu.err)"
[[ ! -e run ]] || fail "a failed start left $(find run | tr '\n' ' ')"
# A state directory that existed is kept, with whatever is in it.
mkdir -p run/state && touch run/state/keep
uwbd --config "$REPO/board/emulated/uwbd.json" "${root_flag[@]}" 2> emu2.err
[[ -f run/state/keep ]] || fail "a failed start removed an existing state directory's file"
pass "no emulated board: exit 69, 'start it first ... uwbemu --gpio ...', no run/state left"
echo "$passed passed"
