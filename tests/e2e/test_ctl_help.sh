#!/usr/bin/env bash
# Issue 31, finding 9: every command the daemon takes is in every list a
# person reads. The daemon's HELP reply is its command table (the unit test
# test_daemon_command checks it is exactly what the parser accepts); each of
# its commands is in `uwbd ctl --help` with its meaning, in the console's
# help list (the --text rendering the console prints) and in uwbd-ctl(1) as
# rendered by man; `uwbd ctl --help` lists nothing else; `uwbd --help`
# tells of `uwbd ctl`.
set -euo pipefail
source "$(dirname "$0")/daemon_e2e.sh"
e2e_workdir uwbd-ctl-help

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }
start_emulated_board
${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" --config "$config" "${root_flag[@]}" -v > uwbd.log 2>&1 &
pids+=($!)
wait_for ctl status || fail "uwbd does not answer: $(tail -5 uwbd.log)"

ctl help > help.json
keys=()
for i in $(seq 0 40); do keys+=("commands.$i.command"); done
json_get "${keys[@]}" < help.json | grep -vx '(missing)' > table.txt
(( $(wc -l < table.txt) >= 12 )) || fail "only $(wc -l < table.txt) commands in the HELP reply: $(cat help.json)"

uwbd ctl --help > ctl-usage.txt
# The usage's command list: "  COMMAND  meaning" lines after "Commands".
sed -n '/^Commands/,/^$/p' ctl-usage.txt | sed -n 's/^  \([a-z][a-z ]*[a-z]\( \[[A-Z]\]\)\?\)  .*/\1/p' > ctl-listed.txt
ctl --text help > console-help.txt
# Rendered by groff (groff-base: make deps installs it) the one way on every
# machine: man(1) is absent from a minbase Debian, and its line length
# differs from groff's, so a phrase checked below could wrap on one path only.
groff -man -Tutf8 -rHY=0 -rLL=100n -P-cbou "$REPO/board/man/uwbd-ctl.1" 2> /dev/null > man.txt
# uwbd-ctl(1)'s commands: the tag of each tagged paragraph under COMMANDS,
# as man prints it (fonts and quotes dropped).
sed -n '/^\.SH COMMANDS/,/^\.SH /{/^\.TP/{n;p}}' "$REPO/board/man/uwbd-ctl.1" |
    sed -E 's/^\.[BI]+ //; s/\\f[RPBI]//g; s/"//g; s/  +/ /g; s/ $//' > man-commands.txt
[[ -s man-commands.txt ]] || fail "uwbd-ctl(1) has no tagged commands under COMMANDS"

missing=()
while IFS= read -r command; do
    grep -qxF "$command" ctl-listed.txt || missing+=("uwbd ctl --help: $command")
    grep -qE "^  $(sed 's/[][]/\\&/g' <<< "$command")( |$)" console-help.txt || missing+=("console help: $command")
    grep -qxF "$command" man-commands.txt || missing+=("uwbd-ctl(1): $command")
done < table.txt
(( ${#missing[@]} == 0 )) || fail "commands the daemon takes but a list lacks: $(printf '%s; ' "${missing[@]}")"
while IFS= read -r command; do
    grep -qxF "$command" table.txt || fail "uwbd ctl --help lists '$command', which the daemon's table has not"
done < ctl-listed.txt
pass "all $(wc -l < table.txt) commands of the daemon's table in uwbd ctl --help, the console's help and uwbd-ctl(1)"

uwbd --help > uwbd-usage.txt
grep -q '^usage: uwbd ctl ' uwbd-usage.txt || fail "uwbd --help does not tell of uwbd ctl"
# The phrase is looked for in the text with its line breaks joined, so a
# narrower rendering still finds it.
grep -qE '^ +[a-z]' man.txt && tr -s ' \n' '  ' < man.txt | grep -q 'Its verdict says' && grep -q '^EXAMPLES' man.txt ||
    fail "uwbd-ctl(1) does not render to its end"
pass "uwbd --help tells of uwbd ctl; uwbd-ctl(1) renders to its end"
echo "$passed passed"
