#!/usr/bin/env bash
# Issue 19, item 1: a serial console people can type into. A terminal
# program (minicom, picocom, screen) sends CR, or CRLF, at Enter, 0x08 or
# 0x7f at Backspace, escape sequences for cursor keys; the console echoes,
# prompts, and ends its lines with CRLF. The control socket stays
# machine-clean: no echo, no prompt. Driven over a unix socket endpoint,
# a byte at a time (unix_peer terminal).
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-console

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
start_emulated_board

keys=(
    'status\r'                 # 1 minicom/picocom: Enter is CR
    'help\r\n'                 # 2 CRLF: one line, not a line and an empty one
    'stau\x7f\x7fatus\r'       # 3 DEL (picocom's Backspace) twice: "status"
    'hisx\btory 1\n'           # 4 BS (0x08) once, LF alone: "history 1"
    '\e[A\e[Dverdict\r'        # 5 cursor keys (up, left) do nothing: "verdict"
    '\r'                       # 6 an empty line: just a new prompt
    'bogus\x03'                # 7 Ctrl-C drops the line: a new prompt
    'status\r'                 # 8 and the next line is whole
)
$HOST_PREFIX "$HOST_BUILD/e2e/unix_peer" terminal run/console.sock run/console.go transcript.bin \
    "${keys[@]}" > terminal.log 2>&1 &
terminal_pid=$!
pids+=($terminal_pid)
wait_for test -S run/console.sock || fail "console listener did not come up"
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" --console unix:run/console.sock -v \
    > uwbd.log 2>&1 &
pids+=($!)
wait_for test -S run/control.sock || fail "uwbd did not come up"
touch run/console.go
wait "$terminal_pid" || fail "terminal peer: $(cat terminal.log)"

# The replies: JSON lines, in order.
tr -d '\r' < transcript.bin | grep '^{' > replies.jsonl || true
[[ $(wc -l < replies.jsonl) == 6 ]] || fail "want 6 replies: $(od -c transcript.bin | head -40)"
n=0
for class in STATUS HELP STATUS HISTORY ERROR STATUS; do
    n=$((n + 1))
    sed -n "${n}p" replies.jsonl | json_check - "class == $class" || fail "reply $n: want $class: $(sed -n "${n}p" replies.jsonl)"
done
sed -n 5p replies.jsonl | json_check - 'message contains no verdict yet' || fail "verdict: $(sed -n 5p replies.jsonl)"
grep -q 'not printable' transcript.bin && fail "a typed line was refused as not printable"
pass "CR, CRLF and LF end a line; BS and DEL edit; cursor keys ignored"

# Echo and prompt: what was typed comes back, Backspace rubs out, every
# line the console sends ends with CRLF, the last thing is a prompt.
grep -aq 'uwbd> status' transcript.bin || fail "no prompt and echo of 'status'"
grep -aqF "$(printf 'stau\b \b\b \batus')" transcript.bin || fail "DEL did not rub out: $(od -c transcript.bin | head)"
grep -aqF "$(printf 'hisx\b \btory 1')" transcript.bin || fail "BS did not rub out"
grep -aqF "$(printf 'bogus^C\r\nuwbd> ')" transcript.bin || fail "Ctrl-C did not drop the line"
grep -aqF "$(printf 'uwbd> \r\nuwbd> ')" transcript.bin || fail "an empty line did not prompt again"
[[ $(head -c -6 transcript.bin | grep -ac "$(printf '[^\r]$')") == 0 ]] || fail "a line not ended by CRLF: $(od -c transcript.bin | head -40)"
[[ $(tail -c 6 transcript.bin) == 'uwbd> ' ]] || fail "the console does not end on a prompt"
[[ $(grep -ao 'uwbd> ' transcript.bin | wc -l) -ge 9 ]] || fail "want a prompt at start and after each of 8 inputs"
pass "echo, rub-out, prompt, CRLF line ends on the console"

# The control socket: the same command gets exactly one JSON line, no echo.
printf 'status\r\n' | unix_peer ask run/control.sock 1 > control.out || fail "control socket status"
json_check control.out 'class == STATUS' || fail "control status: $(cat control.out)"
grep -q 'uwbd>' control.out && fail "the control socket prompts"
[[ $(tr -d '\n' < control.out | head -c 1) == '{' ]] || fail "the control socket echoes: $(cat control.out)"
pass "the control socket stays machine-clean"
echo "$passed passed"
