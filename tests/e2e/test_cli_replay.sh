#!/usr/bin/env bash
# uwbd --replay on the FDTD fixtures, as an engineer would run it: one JSON
# line on stdout, the PNGs in --out, clear errors and distinct exit codes.
set -euo pipefail
uwbd() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" "$@"; }
# JSON through our own helpers (tests/e2e/helpers): a fresh Debian has no Python.
json_check() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/json_check" "$@"; }
json_get() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/state_check" get "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

uwbd --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
     --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --out "$out/img" > "$out/stdout"
[[ $(wc -l < "$out/stdout") -eq 1 ]] || fail "stdout is not exactly one line"
json_check "$out/stdout" 'class == VERDICT' 'status == alarm' 'axial_displacement_mm ~ 20.0 0.5' \
    'uncertainty_mm is number' 'lower_edge_mm is number' 'upper_edge_mm is number' 'center_mm is number' \
    'height_mm is number' 'height_change_withheld exists' 'baseline.lower_edge_mm exists' \
    'baseline.upper_edge_mm exists' 'baseline.center_mm exists' 'images len 3' || fail "verdict JSON: $(cat "$out/stdout")"
for i in 0 1 2; do
    png=$(json_get "images.$i" < "$out/stdout")
    [[ $(head -c 8 "$png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "not a PNG: $png"
done
ls -A "$out/img" | grep -q '^\.' && fail "temporary files left in the output directory"
# --out holds the verdict too, as --help says: the printed line, named like the images.
cmp -s "$out/stdout" "$out/img/fdtd2d-paper-up20mm.json" || fail "--out: no STEM.json equal to the printed verdict"
[[ $(ls "$out/img" | wc -l) == 4 ]] || fail "--out: want 3 PNGs and the verdict: $(ls "$out/img")"

# Issue 48, finding 8: --text prints the verdict for people, as uwbd ctl does.
uwbd --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
     --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --text > "$out/text"
grep -q '{' "$out/text" && fail "--replay --text printed JSON: $(cat "$out/text")"
grep -Eq '^status ALARM.*\+(19\.[5-9]|20\.[0-4])[0-9]* ' "$out/text" || fail "--replay --text: $(cat "$out/text")"

# Without a baseline: edges only.
uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan | grep -q '"status":"edges"' || fail "edges-only status"

# Bad inputs: message names the file, distinct exit codes, nothing on stdout.
set +e
uwbd --replay "$out/missing.uwbscan" > "$out/o1" 2> "$out/e1"; rc_missing=$?
head -c 300 tests/fixtures/fdtd2d-paper-intact.uwbscan > "$out/short.uwbscan"
uwbd --replay "$out/short.uwbscan" > "$out/o2" 2> "$out/e2"; rc_bad=$?
uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --alarm-mm banana > /dev/null 2> "$out/e3"; rc_usage=$?
set -e
[[ $rc_missing -eq 66 ]] || fail "missing file exit $rc_missing, want 66"
[[ $rc_bad -eq 65 ]] || fail "malformed file exit $rc_bad, want 65"
[[ $rc_usage -eq 64 ]] || fail "bad option exit $rc_usage, want 64"
# --target-z is NEAR:FAR, both finite, 0 <= NEAR < FAR: anything else is a
# usage error naming the text (parsed with strtod, not sscanf).
for bad in "5" "5:" ":6" "5:6x" "5x:6" "6:5" "-1:2" "0:inf" "nan:1" "5::6" ""; do
    set +e
    uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --target-z "$bad" > "$out/otz" 2> "$out/etz"
    rc=$?
    set -e
    [[ $rc -eq 64 ]] || fail "--target-z '$bad': exit $rc, want 64"
    grep -qF -- "--target-z: '$bad' is not NEAR:FAR" "$out/etz" || fail "--target-z '$bad': message $(cat "$out/etz")"
    [[ ! -s "$out/otz" ]] || fail "--target-z '$bad': stdout written"
done
# --winding-span is LOW:HIGH, both finite, LOW < HIGH (heights may be negative).
for bad in "0.2" "0.4:0.2" "0.2:0.2" "x:0.3" "0.2:inf" ""; do
    set +e
    uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --winding-span "$bad" > "$out/ows" 2> "$out/ews"
    rc=$?
    set -e
    [[ $rc -eq 64 ]] || fail "--winding-span '$bad': exit $rc, want 64"
    grep -qF -- "--winding-span: '$bad' is not LOW:HIGH" "$out/ews" || fail "--winding-span '$bad': $(cat "$out/ews")"
done
uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --winding-span -0.05:0.5 > "$out/ows" ||
    fail "--winding-span -0.05:0.5 refused"
# Issue 43, break 7: the same limits as analysis.winding_span_mm (+-100,000 mm),
# by the same validator, named in the message.
for bad in "1e300:1e301" "-101:0.5" "0.2:100.001"; do
    set +e
    uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --winding-span "$bad" > "$out/ows" 2> "$out/ews"
    rc=$?
    set -e
    [[ $rc -eq 64 ]] || fail "--winding-span '$bad': exit $rc, want 64 (past analysis.winding_span_mm's range)"
    grep -qF -- "--winding-span: '$bad':" "$out/ews" && grep -qF "is out of range [-100000, 100000] mm" "$out/ews" ||
        fail "--winding-span '$bad': $(cat "$out/ews")"
    [[ ! -s "$out/ows" ]] || fail "--winding-span '$bad': stdout written"
done
uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --winding-span -100:100 > "$out/ows" ||
    fail "--winding-span -100:100 (the key's limits) refused"
grep -q "missing.uwbscan" "$out/e1" || fail "error does not name the missing file"
grep -q "short.uwbscan" "$out/e2" || fail "error does not name the malformed file"
[[ ! -s "$out/o1" && ! -s "$out/o2" ]] || fail "stdout written on error"

# Issue 17, break 9: an inconclusive verdict with no migrated image still
# writes what it can (the B-scan) and exits 0, not 73.
set +e
uwbd --replay tests/fixtures/fdtd2d-paper-intact.uwbscan --target-z 5:6 --out "$out/inc" > "$out/o4" 2> "$out/e4"
rc_inconclusive=$?
set -e
[[ $rc_inconclusive -eq 0 ]] || fail "inconclusive --out: exit $rc_inconclusive, want 0 ($(cat "$out/e4"))"
grep -q '"status":"inconclusive"' "$out/o4" || fail "inconclusive --out: no inconclusive verdict"
[[ -s "$out/inc/fdtd2d-paper-intact-bscan.png" ]] || fail "inconclusive --out: no B-scan written"

# Issue 17, breaks 5 and 9: a crafted header (positions spread over 600 m,
# a 1 nm step, a duplicated position) is refused when read, exit 65, with
# the reason; nothing is analysed. The payload is the fixture's own.
crafted() {  # NAME SED-EXPRESSION
    { head -n 1 tests/fixtures/fdtd2d-paper-intact.uwbscan | sed -e "$2"
      tail -n +2 tests/fixtures/fdtd2d-paper-intact.uwbscan; } > "$out/$1.uwbscan"
}
crafted spread600m 's/,0\.57,0\.6\]/,0.57,600.0]/'
crafted step1nm 's/\[0\.0,0\.03,/[0.0,0.000000001,/; s/,0\.03,0\.06,.*,0\.6\]/]/'
crafted duplicated 's/\[0\.0,0\.03,0\.06,/[0.0,0.03,0.03,/'
for name in spread600m:"over the rig's largest travel of 5 m" step1nm:"under the smallest step of 1 mm" \
            duplicated:"antenna_y_m\[2\] = 0.03 m repeats antenna_y_m\[1\]"; do
    file=${name%%:*} want=${name#*:}
    set +e; uwbd --replay "$out/$file.uwbscan" > "$out/o-$file" 2> "$out/e-$file"; rc=$?; set -e
    [[ $rc -eq 65 ]] || fail "$file: exit $rc, want 65"
    grep -q "$file.uwbscan: .*$want" "$out/e-$file" || fail "$file: message: $(cat "$out/e-$file")"
    [[ ! -s "$out/o-$file" ]] || fail "$file: a verdict was printed"
done

# Issue 27, break 10: data the format takes but the analysis cannot (a
# sample of 3e38, beyond single precision's squares; one sample per trace,
# no spectrum) is bad input, exit 65 with the reason, not an internal
# error (70).
fixture=tests/fixtures/fdtd2d-paper-intact.uwbscan
header_bytes=$(head -n 1 "$fixture" | wc -c)
{ head -n 1 "$fixture" | sed -e 's/"samples":1697,/"samples":1,/'
  head -c $((header_bytes + 21 * 4)) "$fixture" | tail -c $((21 * 4)); } > "$out/one-sample.uwbscan"
cp "$fixture" "$out/huge-sample.uwbscan"
# 3e38 as little-endian binary32 over sample 100 of position 0
printf '\xe6\xb1\x61\x7f' | dd of="$out/huge-sample.uwbscan" bs=1 seek=$((header_bytes + 400)) \
    conv=notrunc status=none
for name in one-sample:"positions x 1 samples" huge-sample:"sample 100 of position 0 is 3e+38"; do
    file=${name%%:*} want=${name#*:}
    for role in replay baseline; do
        if [[ $role == replay ]]; then args=(--replay "$out/$file.uwbscan")
        else args=(--replay "$fixture" --baseline "$out/$file.uwbscan"); fi
        set +e; uwbd "${args[@]}" > "$out/o-$file" 2> "$out/e-$file"; rc=$?; set -e
        [[ $rc -eq 65 ]] || fail "$file as --$role: exit $rc, want 65 ($(cat "$out/e-$file"))"
        grep -q "$file.uwbscan: .*$want" "$out/e-$file" || fail "$file as --$role: message: $(cat "$out/e-$file")"
        [[ ! -s "$out/o-$file" ]] || fail "$file as --$role: a verdict was printed"
    done
done

# Issue 27, break 11: a replay's memory grew with the file (a 268 MB scan
# took 1.37 GB and 23 s). A scan past 64 MiB of samples is refused at its
# header, at once, exit 65, the limit named; one at the limit replays
# within the README's bound (400 MiB peak). The payloads are sparse zeros.
# sized_scan NAME POSITIONS SAMPLES: the fixture's header with that shape.
sized_scan() {
    local ys
    ys=$(awk -v k="$2" 'BEGIN { for (i = 0; i < k; i++) printf "%s%.6f", (i ? "," : ""), i * 0.6 / (k - 1) }')
    head -n 1 "$fixture" | sed -e "s/\"positions\":21,/\"positions\":$2,/; s/\"samples\":1697,/\"samples\":$3,/" \
        -e "s/\"antenna_y_m\":\[[^]]*\]/\"antenna_y_m\":[$ys]/" > "$out/$1.uwbscan"
    truncate -s $(($(wc -c < "$out/$1.uwbscan") + $2 * $3 * 4)) "$out/$1.uwbscan"
}
sized_scan past-limit 512 32769
started=$(date +%s%N)
set +e; uwbd --replay "$out/past-limit.uwbscan" > "$out/o-past" 2> "$out/e-past"; rc=$?; set -e
elapsed_ms=$((($(date +%s%N) - started) / 1000000))
[[ $rc -eq 65 ]] || fail "a scan past the limit: exit $rc, want 65 ($(cat "$out/e-past"))"
grep -q "past-limit.uwbscan: .*over the limit of 16777216 (64 MiB of float32)" "$out/e-past" ||
    fail "a scan past the limit: message: $(cat "$out/e-past")"
(( elapsed_ms < 2000 )) || fail "a scan past the limit took $elapsed_ms ms to refuse"
# At the limit, the fixture's echoes (trace k*21/128, repeated along time)
# so that the analysis runs every step: sparse zeros stop it early.
sized_scan at-limit 128 131072
truncate -s "$(head -n 1 "$out/at-limit.uwbscan" | wc -c)" "$out/at-limit.uwbscan"
for t in $(seq 0 20); do
    dd if="$fixture" of="$out/trace" iflag=skip_bytes,count_bytes skip=$((header_bytes + t * 1697 * 4)) \
        count=$((1697 * 4)) status=none
    for r in $(seq 78); do cat "$out/trace"; done > "$out/trace-$t"
    truncate -s $((131072 * 4)) "$out/trace-$t"
done
for k in $(seq 0 127); do cat "$out/trace-$((k * 21 / 128))"; done >> "$out/at-limit.uwbscan"
rm -f "$out"/trace*
set +e
# The meter is the tester's: native from UWB_HOST_BUILD_DIR under make test-arm.
peak_rss=${UWB_HOST_BUILD_DIR:-$UWB_BUILD_DIR}/e2e/peak_rss
# 120 s natively; under an emulator FFTW is ~80x slower, and a loaded machine
# took past 120 s there (make test-arm beside other work): 480 s.
at_limit_s=120
[[ -z ${UWB_EXEC_PREFIX:-} ]] || at_limit_s=480
"$peak_rss" "$out/rss" "$at_limit_s" ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" --replay "$out/at-limit.uwbscan" \
    > "$out/o-at" 2> "$out/e-at"
rc=$?
set -e
[[ $rc -eq 0 ]] || fail "a scan at the limit: exit $rc ($(cat "$out/e-at"))"
# Sanitizers and an emulator (UWB_EXEC_PREFIX) measure their own memory, not uwbd's.
if [[ -z ${UWB_EXEC_PREFIX:-} ]] && ! grep -qa __asan_init "$UWB_BUILD_DIR/uwbd"; then
    echo "a scan at the limit (128 x 131072 samples): peak RSS $(cat "$out/rss") KiB"
    (( $(cat "$out/rss") <= 400 * 1024 )) || fail "a scan at the limit peaked at $(cat "$out/rss") KiB, over 400 MiB"
fi
grep -q '"status":"edges"' "$out/o-at" || fail "a scan at the limit, the winding not found: $(cut -c1-200 "$out/o-at")"

# --help documents every option the parser accepts.
help=$(uwbd --help)
for opt in --replay --baseline --out --migration --target-z --winding-span --time-zero-offset-ps --watch-mm \
           --alarm-mm --max-uncertainty-mm --edge-fraction --direct-coupling-window-ns \
           --direct-coupling-tolerance-ps --help --version; do
    grep -q -- "$opt" <<< "$help" || fail "--help does not mention $opt"
done
echo "cli replay ok"
