#!/usr/bin/env bash
# The operator's chapters as section 7 manual pages (board/man/*.7.scd,
# rendered by scdoc through the Makefile): each one renders with groff
# warning about nothing, and every word of its scdoc source is on the
# rendered page, in order (no text lost: a roff page once lost half of
# itself to a stray \"); each paragraph's first words are found together.
# The MQTT topics, Prometheus metrics and Modbus registers the code
# publishes, writes and serves are all in the pages.
set -euo pipefail
export LC_ALL=C
fail() { echo "FAIL: $*" >&2; exit 1; }
passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
command -v scdoc > /dev/null || fail "scdoc is not installed (make deps installs it: package scdoc)"
command -v groff > /dev/null || fail "groff is not installed (make deps installs it: package groff-base)"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

make --no-print-directory -s man BUILD="$UWB_BUILD_DIR" TEST_RUNNER="${UWB_EXEC_PREFIX:-}" > "$out/make.log" 2>&1 ||
    { cat "$out/make.log" >&2; fail "make man"; }
sources=(board/man/*.7.scd)
for name in uwbd uwbd-mqtt uwbd-modbus uwbd-contacts uwbd-prometheus uwbd-images uwbd-recovery; do
    [[ -f board/man/$name.7.scd ]] || fail "no board/man/$name.7.scd"
done

# The words a reader should see in an scdoc source: not its first line (the
# page's name, made the header and footer), nor code fences; an ordered
# list item (". ") is numbered as scdoc numbers it.
words_of_scd() {
    sed 1d "$1" | awk '
        /^```/ { next }
        /^\. / { n++; sub(/^\. /, n ". "); print; next }
        /^[^ \t]/ { n = 0 }
        { print }' | sed -E 's/^#+ //; s/\\(.)/\1/g' | tr -cs 'A-Za-z0-9' '\n' | sed '/^$/d'
}
# What groff prints, as man(1) would (no hyphenation), less the header and
# footer lines.
words_rendered() {
    groff -man -Tutf8 -rHY=0 -P-cbou "$1" 2> /dev/null | sed '/^[[:space:]]*$/d' | sed '1d;$d' |
        tr -cs 'A-Za-z0-9' '\n' | sed '/^$/d'
}

for src in "${sources[@]}"; do
    name=$(basename "$src" .scd)
    page=$UWB_BUILD_DIR/man/$name
    [[ -f $page ]] || fail "make man did not make $page from $src"
    head -n 1 "$src" | grep -qxF "${name%.7}(7)" || fail "$src: its first line is not ${name%.7}(7)"
    for s in NAME DESCRIPTION 'SEE ALSO'; do
        grep -qx "# $s" "$src" || fail "$src: no $s section"
    done
    LC_ALL=C grep -q '[^[:print:][:space:]]' "$page" && fail "$page: not ASCII roff (preconv)"
    groff -man -Tutf8 -ww -z "$page" 2> "$out/groff.err" || fail "$page: groff failed"
    [[ ! -s $out/groff.err ]] || fail "$page: groff warns: $(head -3 "$out/groff.err")"
    if command -v man > /dev/null; then
        MANWIDTH=80 man --warnings -l "$page" > "$out/man" 2> "$out/man.err" || fail "$page: man -l failed"
        [[ ! -s $out/man.err ]] || fail "$page: man -l warns: $(head -3 "$out/man.err")"
    fi
    words_of_scd "$src" > "$out/src"
    words_rendered "$page" > "$out/rendered"
    (( $(wc -l < "$out/src") > 100 )) || fail "$src: only $(wc -l < "$out/src") words"
    diff "$out/src" "$out/rendered" > "$out/diff" ||
        fail "$name: the rendered page is not its source's text (diff source rendered: $(head -8 "$out/diff" | tr '\n' ' '))"
    # Each paragraph's first words, together on the rendered page.
    tr -s '[:space:]' ' ' < <(words_rendered "$page") > "$out/flat"
    paragraphs=0
    while IFS= read -r first; do
        opening=$(tr -cs 'A-Za-z0-9' '\n' <<< "$first" | sed '/^$/d' | head -n 4 | tr '\n' ' ')
        [[ -n $opening ]] || continue
        paragraphs=$((paragraphs + 1))
        grep -qF " $opening" <<< " $(cat "$out/flat")" || fail "$name: the paragraph starting '$first' is not rendered"
    done < <(awk 'NR > 1 && prev == "" && $0 != "" && $0 !~ /^(#|```)/ { print } { prev = $0 }' "$src" |
        sed -E 's/\\(.)/\1/g')
    pass "$name: $(wc -l < "$out/src") words and $paragraphs paragraphs rendered, none lost; groff quiet"
done

# Issue 48, finding 3: uwbd(7), the overview, renders its sections; it
# reads out every status a verdict can have (as uwbd-verdict(7) lists them)
# and names every other manual page in "which page covers what".
groff -man -Tutf8 -rHY=0 -P-cbou -rLL=200n "$UWB_BUILD_DIR/man/uwbd.7" 2> /dev/null > "$out/uwbd7" ||
    fail "uwbd(7): groff failed"
for s in NAME DESCRIPTION 'READING A VERDICT' 'WHICH PAGE COVERS WHAT' 'SEE ALSO'; do
    grep -qx "$s" "$out/uwbd7" || fail "uwbd(7) renders no $s section"
done
sed -n '/^READING A VERDICT$/,/^WHICH PAGE COVERS WHAT$/p' "$out/uwbd7" > "$out/reading"
statuses=$(sed -n '/^\*status\*$/{n;p;q}' board/man/uwbd-verdict.7.scd | grep -oE '\*[a-z]+\* \(' | tr -d '*( ')
(($(wc -w <<< "$statuses") >= 6)) || fail "only $(wc -w <<< "$statuses") statuses in uwbd-verdict(7): $statuses"
for status in $statuses; do
    grep -qE "^ +$status$" "$out/reading" || fail "uwbd(7) does not explain the status $status"
done
sed -n '/^WHICH PAGE COVERS WHAT$/,/^SEE ALSO$/p' "$out/uwbd7" > "$out/covers"
named=0
for page in board/man/*.[1-8] board/man/*.7.scd uwbd.json.5; do
    name=$(basename "$page" .scd)
    [[ $name == uwbd.7 ]] && continue
    grep -qF "${name%.*}(${name##*.})" "$out/covers" || fail "uwbd(7)'s WHICH PAGE COVERS WHAT lacks ${name%.*}(${name##*.})"
    named=$((named + 1))
done
pass "uwbd(7): its sections, the $(wc -w <<< "$statuses") statuses, and the $named other pages"

# The check the package test runs on every installed page passes here too.
# Issue 48, finding 10: no stray backquote (scdoc has no code spans: a
# backquote is printed as it is, as uwbd-modbus(7)'s once were).
for page in "$UWB_BUILD_DIR"/man/*.7; do
    stray=$(groff -man -Tutf8 -rLL=200n "$page" 2> /dev/null | grep '`' || true)
    [[ -z $stray ]] || fail "$(basename "$page"): a stray backquote: $stray"
done
tools/man/no-lost-text.sh "$UWB_BUILD_DIR"/man/*.7 > "$out/lost" 2>&1 ||
    fail "tools/man/no-lost-text.sh: $(grep -v ', none lost$' "$out/lost")"
pass "tools/man/no-lost-text.sh: $(tr '\n' ';' < "$out/lost")"

# What the code publishes, writes and serves, the pages list (the README
# points to them): every MQTT topic, Prometheus metric and Modbus register.
page_text() { words_rendered "$UWB_BUILD_DIR/man/$1.7" | tr '\n' ' '; }
topics=$(grep -oE '"%s/%s/[a-z]+"' src/integrations/mqtt_publisher.c | grep -oE '[a-z]+"$' | tr -d '"' | sort -u)
(( $(wc -l <<< "$topics") >= 5 )) || fail "only $(wc -l <<< "$topics") MQTT topics found in src/integrations/mqtt_publisher.c"
for topic in $topics; do
    grep -qF "PREFIX ASSET ID $topic " <<< "$(page_text uwbd-mqtt)" || fail "uwbd-mqtt(7) lacks the topic $topic"
done
# The daemon's metrics are in the textfile's code, the figures' gauges in the field table.
metric_sources="src/integrations/prometheus_textfile.c src/verdict/verdict_fields.c"
metrics=$(grep -ohE '"uwbd_[a-z_]+' $metric_sources | tr -d '"' | sort -u)
(( $(wc -l <<< "$metrics") >= 12 )) || fail "only $(wc -l <<< "$metrics") metrics found in $metric_sources"
for metric in $metrics; do
    grep -qF "$metric" "$UWB_BUILD_DIR/man/uwbd-prometheus.7" || fail "uwbd-prometheus(7) lacks $metric"
done
registers=$(grep -oE 'UWBD_MODBUS_REG_[A-Z_]+ = [0-9]+' src/integrations/modbus_registers.h | grep -oE '[0-9]+$' | sort -un)
(( $(wc -l <<< "$registers") >= 16 )) || fail "only $(wc -l <<< "$registers") registers found in src/integrations/modbus_registers.h"
sed 's/\\\[u2013\]/–/g' "$UWB_BUILD_DIR/man/uwbd-modbus.7" > "$out/modbus.7"
for register in $registers; do
    grep -qE "^\\\\fB$register(–[0-9]+)?\\\\fR: " "$out/modbus.7" || fail "uwbd-modbus(7) lacks register $register"
done
# Issue 48, finding 10: health bit 4 names the registers up to the map's last.
last_register=$(tail -n 1 <<< "$registers")
grep -qF "bit 4 registers 1–12 and 15–$last_register hold a verdict" "$out/modbus.7" ||
    fail "uwbd-modbus(7)'s health bit 4 does not end at register $last_register: $(grep -F 'bit 4' "$out/modbus.7")"
pass "the $(wc -w <<< "$topics") MQTT topics, $(wc -w <<< "$metrics") metrics and $(wc -w <<< "$registers") Modbus registers of the code are in the pages"

# uwbd-recovery(7) explains every exit status uwbd ctl --help gives.
codes=$(${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" ctl --help | sed -n '/^Exit status:/,$p' | grep -oE '(^|[;:] )[0-9]+' |
    grep -oE '[0-9]+')
(( $(wc -w <<< "$codes") >= 6 )) || fail "only $(wc -w <<< "$codes") exit statuses in uwbd ctl --help"
for code in $codes; do
    sed -n '/^\.SH EXIT STATUS OF UWBD CTL/,/^\.SH /p' "$UWB_BUILD_DIR/man/uwbd-recovery.7" |
        grep -qxF "\\fB$code\\fR" || fail "uwbd-recovery(7) does not explain uwbd ctl's exit status $code"
done
pass "uwbd-recovery(7) explains uwbd ctl's exit statuses $(echo $codes)"
echo "$passed passed"
