#!/usr/bin/env bash
# Manual pages: uwbd.json(5) printed from the key table lists every key;
# uwbd(8), uwbd-ctl(1) and uwbsim(1) (board/man/) name every option the
# programs' --help lists, and every ctl command; all are well-formed roff
# (known requests only; groff, when installed, warns about nothing) and
# render without losing text (tools/man/no-lost-text.sh: a stray \" once
# cut uwbd-ctl(1) short).
set -euo pipefail
uwbd() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" "$@"; }
uwbsim() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbsim" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

uwbd --config-keys=man > "$out/uwbd.json.5"
uwbd --config-keys > "$out/keys.md"

# well_formed PAGE SECTION: .TH first, then only the man(7) requests below;
# no line starting with ' (a control line too); fonts switched back.
well_formed() {
    local page=$1 section=$2
    head -n 1 "$page" | grep -qE "^\.TH [A-Z.\\-]+ $section " || fail "$page: does not start with .TH ... $section"
    local bad
    bad=$(grep -nE '^\.' "$page" | grep -vE '^[0-9]+:\.(TH|SH|SS|TP|PP|LP|IP|B|I|BR|RB|BI|IB|IR|RI|br|EX|EE|nf|fi|RS|RE|sp)( |$)' || true)
    [[ -z $bad ]] || fail "$page: unknown requests: $bad"
    ! grep -qn "^'" "$page" || fail "$page: a line starts with ' (a roff control line)"
    ! grep -qn '`' "$page" || fail "$page: a raw backquote: $(grep -n '`' "$page" | head -3)"
    for s in NAME SYNOPSIS DESCRIPTION 'SEE ALSO'; do
        grep -qx "\\.SH $s" "$page" || fail "$page: no $s section"
    done
    if command -v groff > /dev/null; then
        groff -man -Tutf8 -ww -z "$page" 2> "$out/groff.err" || fail "$page: groff failed"
        [[ ! -s "$out/groff.err" ]] || fail "$page: groff warns: $(head -5 "$out/groff.err")"
    fi
    if command -v man > /dev/null; then
        MANWIDTH=80 man -l "$page" > "$out/rendered" 2> /dev/null || fail "$page: man -l failed"
        grep -q NAME "$out/rendered" || fail "$page: man -l renders no NAME"
    fi
}
well_formed "$out/uwbd.json.5" 5
well_formed board/man/uwbd.8 8
well_formed board/man/uwbd-ctl.1 1
pass "uwbd.json(5), uwbd(8), uwbd-ctl(1): well-formed roff"

# Issue 48, finding 10: at the widths man fills on common terminals (80 and
# 100 columns; groff's own 78 is above) no line groff cannot adjust (a wide
# gap: a long JSON example once) or break.
if command -v groff > /dev/null; then
    for page in "$out/uwbd.json.5" board/man/uwbd.8 board/man/uwbd-ctl.1 board/man/uwbsim.1; do
        for width in 80 100; do
            groff -man -Tutf8 -ww -z -rLL=${width}n "$page" 2> "$out/groff.err" || fail "$page: groff failed"
            [[ ! -s "$out/groff.err" ]] || fail "$page at $width columns: groff warns: $(head -3 "$out/groff.err")"
        done
    done
    pass "uwbd.json(5), uwbd(8), uwbd-ctl(1), uwbsim(1): no groff warning at 80 and 100 columns"
fi

# Issue 48, finding 10: what the pages say agrees with the code and with
# each other. uwbd-ctl(1) points to every section 7 page; uwbd(8)'s NAME
# covers both figures; its health bit 4 names the registers up to the last
# one the map has; uwbd.json(5)'s mqtt.topic_prefix names every topic.
see_also=$(sed -n '/^\.SH SEE ALSO/,$p' board/man/uwbd-ctl.1)
for src in board/man/*.7.scd; do
    name=$(basename "$src" .7.scd)
    grep -qF ".BR ${name//-/\\-} (7)" <<< "$see_also" || fail "uwbd-ctl(1)'s SEE ALSO lacks $name(7)"
done
sed -n '/^\.SH NAME/{n;p}' board/man/uwbd.8 | grep -q 'axial and radial displacement' ||
    fail "uwbd(8)'s NAME: $(sed -n '/^\.SH NAME/{n;p}' board/man/uwbd.8)"
last_register=$(grep -oE 'UWBD_MODBUS_REG_[A-Z_]+ = [0-9]+' src/integrations/modbus_registers.h | grep -oE '[0-9]+$' | sort -n | tail -n 1)
bit4=$(groff -man -Tascii -rLL=200n board/man/uwbd.8 2> /dev/null | grep -E '4 a verdict present' || true)
[[ $bit4 == *"15-$last_register)"* ]] || fail "uwbd(8)'s health bit 4 does not end at register $last_register: $bit4"
topic_paragraph=$(grep -A3 -xF '\fBmqtt.topic_prefix\fR' "$out/uwbd.json.5")
for topic in $(grep -oE '"%s/%s/[a-z]+"' src/integrations/mqtt_publisher.c | grep -oE '[a-z]+"$' | tr -d '"' | sort -u); do
    grep -qF "ASSET_ID/$topic" <<< "$topic_paragraph" || fail "uwbd.json(5)'s mqtt.topic_prefix lacks the topic $topic: $topic_paragraph"
done
pass "uwbd-ctl(1) sees all section 7 pages; uwbd(8): axial and radial, bit 4 to register $last_register; every MQTT topic in uwbd.json(5)"

# Every page rendered as man(1) shows it: all the source's words, in order.
pages=("$out/uwbd.json.5" board/man/*.[1-8])
(( ${#pages[@]} >= 3 )) || fail "only ${#pages[@]} manual pages found"
tools/man/no-lost-text.sh "${pages[@]}" > "$out/lost" 2>&1 || fail "text lost in rendering: $(grep -v ', none lost$' "$out/lost")"
pass "${#pages[@]} manual pages render every word of their source: $(tr '\n' ';' < "$out/lost")"

[[ -f board/man/uwbsim.1 ]] || fail "no board/man/uwbsim.1: the installed uwbsim has no manual page"
well_formed board/man/uwbsim.1 1
pass "uwbsim(1): well-formed roff"

# Every key of the table, as its own tagged paragraph, and nothing more.
mapfile -t keys < <(tail -n +3 "$out/keys.md" | cut -d'`' -f2)
(( ${#keys[@]} > 40 )) || fail "only ${#keys[@]} keys in uwbd --config-keys"
for key in "${keys[@]}"; do
    grep -qxF "\\fB$key\\fR" "$out/uwbd.json.5" || fail "uwbd.json(5) lacks the key $key"
done
[[ $(grep -c '^\.TP$' "$out/uwbd.json.5") == $((${#keys[@]} + 1)) ]] ||
    fail "uwbd.json(5): $(grep -c '^\.TP$' "$out/uwbd.json.5") tagged paragraphs for ${#keys[@]} keys (+1 file)"
grep -A3 -xF '\fBdigitiser.endpoint\fR' "$out/uwbd.json.5" | grep -q 'required' || fail "a required key not said required"
grep -A3 -xF '\fBschedule.interval_s\fR' "$out/uwbd.json.5" | grep -q 'default \\fB86400\\fR' ||
    fail "schedule.interval_s: no default 86400"
pass "uwbd.json(5) lists all ${#keys[@]} keys with type, range and default"

# Every long option in the usage texts, in the page that documents it.
options_in() { grep -oE -- '--[a-z][a-z-]+' | sort -u; }
# uwbd --help: the daemon, ctl (checked below against uwbd-ctl(1)), the replay.
for opt in $(uwbd --help | sed '/^usage: uwbd ctl/,/^usage: uwbd --replay/{/^usage: uwbd --replay/!d}' | options_in); do
    escaped=${opt//-/\\-}
    grep -qF -- "$escaped" board/man/uwbd.8 || fail "uwbd(8) does not document $opt"
done
for opt in $(uwbd ctl --help | options_in); do
    grep -qF -- "${opt//-/\\-}" board/man/uwbd-ctl.1 || fail "uwbd-ctl(1) does not document $opt"
done
commands=$(uwbd ctl --help | sed -n '/^Commands/,/^$/s/^  \([a-z][a-z ]*[a-z]\)\( \[[A-Z]\]\)\?  .*/\1/p')
(( $(wc -l <<< "$commands") >= 12 )) || fail "no list of commands in uwbd ctl --help: $commands"
while read -r cmd; do
    grep -qE "^\.B(I)? \"?$cmd" board/man/uwbd-ctl.1 || fail "uwbd-ctl(1) does not document the command '$cmd'"
done <<< "$commands"
pass "uwbd(8) and uwbd-ctl(1) document every option and command of --help"

# uwbsim(1): its options and every scene parameter of uwbsim --help.
sim_options=$(uwbsim --help | options_in)
(( $(wc -l <<< "$sim_options") > 50 )) || fail "only $(wc -l <<< "$sim_options") options in uwbsim --help"
for opt in $sim_options; do
    grep -qF -- "${opt//-/\\-}" board/man/uwbsim.1 || fail "uwbsim(1) does not document $opt"
done
# ... and nothing it does not take (the examples also run uwbd).
for opt in $(sed -n '/^\.SH OPTIONS/,/^\.SH EXIT STATUS/s/\\-/-/gp' board/man/uwbsim.1 | options_in); do
    grep -qxF -- "$opt" <<< "$sim_options" || fail "uwbsim(1) documents $opt, which uwbsim --help does not list"
done
pass "uwbsim(1) documents all $(wc -l <<< "$sim_options") options and scene parameters of uwbsim --help"
echo "$passed passed"
