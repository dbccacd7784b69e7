#!/usr/bin/env bash
# The README's images (tools/readme/images) are what the command it shows
# draws: tools/readme/readme-images.sh redraws them into a temporary
# directory; each decodes (libpng, every row), names the paper scan and
# this uwbd in its text chunks like the committed one, and, natively, is
# byte for byte the committed file (the PNG writer is deterministic).
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The decoder runs natively from UWB_HOST_BUILD_DIR under make test-arm.
if [[ -n ${UWB_HOST_BUILD_DIR:-} ]]; then png_info() { "$UWB_HOST_BUILD_DIR/e2e/png_info" "$@"; }
else png_info() { ${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/e2e/png_info" "$@"; }; fi
version=$(${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" --version | awk '{print $NF}')

sh tools/readme/readme-images.sh "$UWB_BUILD_DIR" "$tmp/images" > /dev/null
for kind in migrated bscan comparison; do
    committed=tools/readme/images/paper-up20mm-$kind.png drawn=$tmp/images/paper-up20mm-$kind.png
    [[ -f $committed ]] || fail "$committed is missing: run make readme-images"
    png_info "$drawn" > "$tmp/drawn.txt" || fail "$drawn does not decode"
    png_info "$committed" > "$tmp/committed.txt" || fail "$committed does not decode"
    grep -qx 'Scan=fdtd2d-paper-up20mm' "$tmp/drawn.txt" || fail "$kind: no Scan chunk: $(cat "$tmp/drawn.txt")"
    grep -qx "Software=uwbd $version" "$tmp/drawn.txt" || fail "$kind: not uwbd $version"
    grep -q '^Description=.*thresholds watch 2.00 mm, alarm 5.00 mm' "$tmp/drawn.txt" ||
        fail "$kind: the description does not give the thresholds"
    # The provenance the README's image carries is what the command writes now.
    diff -u "$tmp/committed.txt" "$tmp/drawn.txt" >&2 ||
        fail "$committed: its size or text chunks differ from what the command draws: run make readme-images"
    if [[ -z ${UWB_EXEC_PREFIX:-} ]]; then
        cmp -s "$committed" "$drawn" || fail "$committed differs from what the command draws: run make readme-images"
    fi
done
# The check notices a stale image: one drawn with other thresholds differs.
${UWB_EXEC_PREFIX:-} "$UWB_BUILD_DIR/uwbd" --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
    --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --watch-mm 3 --out "$tmp/other" > /dev/null
png_info "$tmp/other/fdtd2d-paper-up20mm-migrated.png" > "$tmp/other.txt"
png_info tools/readme/images/paper-up20mm-migrated.png > "$tmp/committed.txt"
! diff -q "$tmp/committed.txt" "$tmp/other.txt" > /dev/null || fail "an image drawn with watch 3 mm passed as the README's"
echo "README images: the command's output, decoded, provenance as committed${UWB_EXEC_PREFIX:+ (bytes not compared under $UWB_EXEC_PREFIX)}"
