#!/usr/bin/env bash
# Issue 48, finding 3: the README is a short entry (at most 400 lines) and
# every chapter it dropped lives on in a document beside what it describes,
# one link away: the README's list of documents is what their headings say
# (tools/readme/readme-docs.sh, `make readme-docs`), every relative link in
# the README and those documents reaches an existing file and heading, each
# chapter of the old 2,564-line README is a heading the README links to,
# the simulator's parameter table is printed by uwbsim, and the manual
# pages the README and the install guide list are board/man/'s.
set -euo pipefail
export LC_ALL=C
fail() { echo "FAIL: $*" >&2; exit 1; }
passed=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

lines=$(wc -l < README.md)
((lines <= 400)) || fail "README.md has $lines lines; the entry is at most 400 (move a chapter beside what it describes)"
[[ -z $(find . -maxdepth 1 -name docs) ]] || fail "a top-level docs/: the brief fixes the top level"
pass "README.md: $lines lines"

# The list of documents is written from the headings, and a stale one is noticed.
bash tools/readme/readme-docs.sh --check README.md || fail "README.md's list of documents is stale: run make readme-docs"
sed '/<!-- readme-docs: begin/,/<!-- readme-docs: end/{/tests\/accuracy\.md/d}' README.md > "$tmp/README.md"
! cmp -s README.md "$tmp/README.md" || fail "could not plant a list without tests/accuracy.md"
if bash tools/readme/readme-docs.sh --check "$tmp/README.md" 2> "$tmp/err"; then
    fail "a README whose list lacks tests/accuracy.md passed the check"
fi
grep -q 'run make readme-docs' "$tmp/err" || fail "the failing check does not say how to fix it: $(cat "$tmp/err")"
mapfile -t docs < <(find board src tests tools -name '*.md' -not -path '*/third_party/*' | sort)
((${#docs[@]} >= 10)) || fail "only ${#docs[@]} documents found"
for doc in "${docs[@]}"; do
    grep -qF "]($doc)" README.md || fail "README.md does not link $doc"
done
pass "README.md links all ${#docs[@]} documents and their chapters, as their headings say"

# The simulator's parameter table, which moved with its chapter, is what
# uwbsim prints (tools/readme/readme-sim-params.sh), and a typed one is noticed.
bash tools/readme/readme-sim-params.sh "$UWB_BUILD_DIR" --check tools/uwbsim/README.md ||
    fail "tools/uwbsim/README.md's parameter table differs from uwbsim --params-markdown: run make readme-sim-params"
sed '/<!-- readme-sim-params: begin/,/<!-- readme-sim-params: end/ s/^\(| `mode` \/ `--mode` |  |\) 3d |/\1 2d |/' \
    tools/uwbsim/README.md > "$tmp/uwbsim.md"
! cmp -s tools/uwbsim/README.md "$tmp/uwbsim.md" || fail "could not plant a wrong default"
if bash tools/readme/readme-sim-params.sh "$UWB_BUILD_DIR" --check "$tmp/uwbsim.md" 2> /dev/null; then
    fail "a parameter table saying mode 2d by default passed the check"
fi
pass "tools/uwbsim/README.md's parameter table is uwbsim's"

# Every relative link (file, and heading when it names one) resolves.
links=0
for doc in README.md "${docs[@]}"; do
    dir=$(dirname "$doc")
    while IFS= read -r target; do
        [[ $target == *://* || $target == mailto:* ]] && continue
        file=${target%%#*} anchor=
        [[ $target == *#* ]] && anchor=${target#*#}
        [[ -n $file ]] && path=$dir/$file || path=$doc
        [[ -e $path ]] || fail "$doc: link $target: no $path"
        if [[ -n $anchor ]]; then
            [[ $path == *.md ]] || fail "$doc: link $target: a heading in a file that is not Markdown"
            bash tools/readme/readme-docs.sh --anchors "$path" | grep -qxF -- "$anchor" ||
                fail "$doc: link $target: $path has no heading whose anchor is #$anchor"
        fi
        links=$((links + 1))
    done < <(sed '/^```/,/^```/d' "$doc" | grep -oE '\]\([^) ]+\)' | sed -E 's/^\]\((.*)\)$/\1/')
done
((links >= 100)) || fail "only $links links checked"
pass "$links relative links in README.md and ${#docs[@]} documents reach their file and heading"

# Each chapter of the long README (its ## and ### headings before issue 48)
# is a heading of README.md or of a document README.md links.
linked=$(grep -oE '\]\([^)#: ]+\.md(#[^) ]*)?\)' README.md | sed -E 's/^\]\(([^)#]*).*/\1/' | sort -u)
{
    cat README.md
    for doc in $linked; do cat "$doc"; done
} | sed '/^```/,/^```/d' | sed -n 's/^#\{1,3\} //p' > "$tmp/headings"
missing=0
while IFS= read -r chapter; do
    [[ -n $chapter ]] || continue
    grep -qxF -- "$chapter" "$tmp/headings" || { echo "not reachable: $chapter" >&2; missing=$((missing + 1)); }
done <<'CHAPTERS'
Reading a verdict
Command line
The appliance: `uwbd --config`
Commands: serial console and `uwbd ctl`
Into the substation: alarm contacts and the event input
Alarm contacts
Scan after an event
Prometheus textfile
MQTT
A fleet: hundreds of appliances, one historian
Modbus (RTU and TCP)
Exit status
Least privilege, and the faults tried
Time, and boards without a real-time clock
Bad input, fuzzed
Fuzzing
Long runs
The hardware layer and the emulated board
uwbemu, the emulated board
The board in the loop: `make test-board`
How a scan becomes a verdict
Reading the images
Recorded scans: the `uwbscan/1` file
Layout
Coordinates and units
Header keys
What the reader refuses
Writing
Simulator (`tools/uwbsim`)
Scene
Physics
How well it agrees
Library (for tests and the emulated board)
Parameters
Noisy copies of a scan: `build/uwbimpair`
Accuracy on the full-wave scans: `make accuracy`
Radial deformation: what is measured, how well, where it stops
Accuracy on simulated tank scans, and known limits
Performance
What the figures mean
How the fixed-point path gets there
What stands in the way of the 100 ms replay
aarch64
Building and testing
On a fresh machine
Developing
Where things are
CHAPTERS
((missing == 0)) || fail "$missing chapters of the old README are not reachable from README.md (above)"
pass "every chapter of the old README is a heading of README.md or of a document it links"

# The pages the README and the install guide list (their `man ...` lines)
# are board/man/'s, with uwbd.json(5) printed by uwbd.
{
    for page in board/man/*.[1-8] board/man/*.7.scd; do
        name=$(basename "$page" .scd)
        section=${name##*.}
        [[ $section == 7 ]] && echo "man 7 ${name%.*}" || echo "man ${name%.*}"
    done
    echo "man uwbd.json"
} | sort > "$tmp/pages"
(($(wc -l < "$tmp/pages") >= 12)) || fail "only $(wc -l < "$tmp/pages") manual pages in board/man/"
grep -qx 'man 7 uwbd' "$tmp/pages" || fail "no overview page uwbd(7) in board/man/"
for doc in README.md board/install-guide.md; do
    grep -E '^man ' "$doc" | tr ';' '\n' | sed -E 's/#.*//; s/^ +//; s/ +$//' | grep . | sort -u > "$tmp/listed" || true
    diff "$tmp/pages" "$tmp/listed" > "$tmp/diff" ||
        fail "$doc's man lines are not board/man/'s pages (< only in board/man, > only in $doc): $(tr '\n' ' ' < "$tmp/diff")"
done
pass "README.md and board/install-guide.md list all $(wc -l < "$tmp/pages") manual pages, section 7 included"
echo "$passed passed"
