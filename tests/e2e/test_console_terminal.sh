#!/usr/bin/env bash
# Issue 19, item 1: a serial console people can type into. A terminal
# program (minicom, picocom, screen) sends CR, or CRLF, at Enter, 0x08 or
# 0x7f at Backspace, escape sequences for cursor keys; the console echoes,
# prompts, and ends its lines with CRLF. The control socket stays
# machine-clean: no echo, no prompt. Driven over a unix socket endpoint,
# a byte at a time (unix_peer terminal).
# Issue 31, finding 2: the console is for people: text replies (a status
# page, a help list), case-insensitive commands, did-you-mean; a line that
# comes while the prompt shows (a watched scan's progress and verdict)
# clears the prompt's line, and the prompt and what was typed are drawn
# again after it; progress is redrawn in place. What a terminal would show
# is checked with unix_peer screen.
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
    'stauts\r'                 # 9 a near miss: did you mean `status`?
    'Baseline Set\r'           # 10 case does not matter
    'watch\r'                  # 11 progress and verdicts to the console
    'scan\r'                   # 12 progress lines come while...
    'sta'                      # 13 ...the person types (no Enter yet)
    '@until:became the baseline' # 14 the scan's verdict came
    'tus\r'                    # 15 the line typed across it is whole
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

# The replies: text for people, not JSON.
unix_peer screen transcript.bin > screen.txt || fail "cannot render the transcript"
grep -q '^{' screen.txt && fail "the console printed JSON: $(grep '^{' screen.txt | head -3)"
[[ $(grep -c '^State           : idle$' screen.txt) -ge 3 ]] || fail "want 3 status pages: $(cat screen.txt)"
grep -q '^Commands (case does not matter):$' screen.txt || fail "help: no list: $(cat screen.txt)"
grep -q '^  status  *daemon state' screen.txt || fail "help: no status line: $(cat screen.txt)"
grep -q '^time (UTC)  *status  *displacement' screen.txt || fail "history: no table: $(cat screen.txt)"
grep -q '^error: no verdict yet' screen.txt || fail "verdict: no error line: $(cat screen.txt)"
grep -qF 'error: unknown command `stauts` (did you mean `status`? try help)' screen.txt ||
    fail "stauts: no suggestion: $(cat screen.txt)"
grep -q '^the next good scan becomes the baseline$' screen.txt || fail "'Baseline Set' refused: $(cat screen.txt)"
grep -q 'not printable' transcript.bin && fail "a typed line was refused as not printable"
pass "CR, CRLF and LF end a line; BS and DEL edit; cursor keys ignored; text replies, any case, did-you-mean"

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

# Asynchronous lines: never after a prompt on screen, the prompt and the
# typed "sta" drawn again below them, one progress line redrawn in place.
grep -E 'uwbd> .*(scan: position|status EDGES|became the baseline)' screen.txt &&
    fail "an asynchronous line after the prompt: $(cat screen.txt)"
grep -q 'uwbd> .*uwbd> ' screen.txt && fail "two prompts on a line: $(cat screen.txt)"
[[ $(grep -c 'scan: position' screen.txt) == 1 ]] || fail "want one progress line, redrawn: $(grep 'scan: position' screen.txt)"
grep -q '^scan: position 21 of 21' screen.txt || fail "the progress line does not end at 21 of 21: $(cat screen.txt)"
verdict_row=$(grep -n '^status [A-Z]*: .*became the baseline' screen.txt | cut -d: -f1)
typed_row=$(grep -n '^uwbd> status$' screen.txt | tail -1 | cut -d: -f1)
[[ -n $verdict_row && -n $typed_row && $typed_row -gt $verdict_row ]] ||
    fail "the typed 'sta' was not drawn again below the verdict: $(cat screen.txt)"
[[ $(tail -1 screen.txt) == 'uwbd> ' ]] || fail "the screen does not end on a prompt: $(tail -3 screen.txt)"
pass "asynchronous lines clear the prompt, then the prompt and the typed text come back; progress in place"

# The control socket: the same command gets exactly one JSON line, no echo.
printf 'status\r\n' | unix_peer ask run/control.sock 1 > control.out || fail "control socket status"
json_check control.out 'class == STATUS' || fail "control status: $(cat control.out)"
grep -q 'uwbd>' control.out && fail "the control socket prompts"
[[ $(tr -d '\n' < control.out | head -c 1) == '{' ]] || fail "the control socket echoes: $(cat control.out)"
pass "the control socket stays machine-clean"
echo "$passed passed"
