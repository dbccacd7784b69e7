#!/usr/bin/env bash
# The e2e scripts' JSON and socket helpers (tests/e2e/helpers) judge every
# daemon reply: a check that cannot fail would make those tests pass on
# anything. Each operator here holds once and fails once, and a failure
# names the check and the value found.
set -euo pipefail
json_check() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/json_check" "$@"; }
json_edit() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/json_edit" "$@"; }
unix_peer() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/unix_peer" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

printf '%s\n' '{"class":"VERDICT","d":20.3,"ok":true,"n":0,"reason":"Home switch not seen",' \
    '"images":["a.png","b.png"],"baseline":{"id":"x"},"none":null}' > v.json
printf '%s\n' '{"images":["a.png","b.png"],"d":20.3,"class":"VERDICT","n":0,"ok":true,' \
    '"reason":"Home switch not seen","none":null,"baseline":{"id":"x"}}' > same.json
# CHECK, then whether it holds.
while IFS='|' read -r check want; do
    set +e; json_check v.json "$check" 2> err; rc=$?; set -e
    if [[ $want == yes && $rc != 0 ]]; then fail "'$check' should hold: $(cat err)"; fi
    if [[ $want == no && $rc != 1 ]]; then fail "'$check' should fail with exit 1, got $rc"; fi
    if [[ $want == no ]] && ! grep -qF "'$check' does not hold" err; then fail "'$check': message $(cat err)"; fi
done <<'CASES'
class == VERDICT|yes
class == VERDICTS|no
d == 20.3|no
d ~ 20.0 0.5|yes
d ~ 20.0 0.2|no
d > 20|yes
d <= 20|no
n = 0|yes
n = false|no
ok = true|yes
ok = 1|no
ok is bool|yes
ok is number|no
images len 2|yes
images len 3|no
images.1 == b.png|yes
images.2 exists|no
baseline absent|no
missing absent|yes
none is null|yes
. same same.json|yes
baseline same same.json|no
reason imatches home switch (not seen|never closed)|yes
reason matches home switch|no
reason contains switch not|yes
reason contains stuck|no
CASES
set +e; json_check v.json 'd frobs 1' 2> /dev/null; rc=$?; set -e
[[ $rc == 64 ]] || fail "an unknown operator: exit $rc, want 64"
printf '{"a":1}\n{"a":2}\n' > lines.jsonl
json_check --each-line lines.jsonl 'a > 0' || fail "--each-line on good lines"
printf '{"a":1}\n{"a":2} x\n' > torn.jsonl
set +e; json_check --each-line torn.jsonl 'a > 0' 2> /dev/null; rc=$?; set -e
[[ $rc == 2 ]] || fail "--each-line on a line with trailing bytes: exit $rc, want 2"
echo '{"a":1} {"b":2}' > two.json
set +e; json_check two.json '. exists' 2> /dev/null; rc=$?; set -e
[[ $rc == 2 ]] || fail "two values in one file: exit $rc, want 2"

json_edit v.json e.json 'baseline.id="y"' 'baseline.new=[1]' '-none'
json_check e.json 'baseline.id == y' 'baseline.new = [1]' 'none absent' 'd = 20.3' || fail "json_edit"
set +e; json_edit v.json e2.json '-nothing' 2> /dev/null; rc=$?; set -e
[[ $rc == 1 && ! -e e2.json ]] || fail "json_edit removing a missing key: exit $rc"

# unix_peer ask against its own console listener: lines go out, replies come back.
unix_peer console peer.sock go out.txt 'hello' 'world' &
peer=$!
for _ in $(seq 100); do [[ -S peer.sock ]] && break; sleep 0.1; done
touch go
set +e; printf 'r1\nr2\n' | unix_peer ask peer.sock 2 > asked.txt; rc=$?; set -e
wait "$peer" || true
[[ $rc == 0 && $(cat asked.txt) == $'hello\nworld' && $(cat out.txt) == $'r1\nr2' ]] ||
    fail "unix_peer: ask exit $rc, it got '$(cat asked.txt)', the console got '$(cat out.txt)'"

# unix_peer invert (make test-board's serial peer) answers each byte with its
# inverse: the console peer sends ~"hello" and 0xf5 (~'\n') and reads "hello".
unix_peer console uart.sock go2 inverted.txt $'\x97\x9a\x93\x93\x90\xf5' &
peer=$!
touch go2
unix_peer invert uart.sock 10 2> invert.log || fail "unix_peer invert: $(cat invert.log)"
wait "$peer" || fail "the console peer got no inverted reply"
[[ $(cat inverted.txt) == hello ]] || fail "unix_peer invert answered '$(cat inverted.txt)', want hello"
grep -q "^serial-peer: 7 bytes received and answered" invert.log || fail "unix_peer invert: $(cat invert.log)"

echo "e2e helpers ok"
