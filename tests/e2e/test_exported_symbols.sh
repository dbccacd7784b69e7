#!/usr/bin/env bash
# Every global symbol libuwb.a defines carries the project's prefix (uwb_,
# uwbd_ for the daemon, uwbscan_ for the scan-file format, UWB_ for
# constants), so a program linking the library never meets a bare name
# such as scan_now or face_search. File-local functions are static.
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }

lib="$UWB_BUILD_DIR/libuwb.a"
[[ -f $lib ]] || fail "$lib: not built"
# The nm that reads the archive (a cross build's is not the host's).
nm_tool=
for candidate in nm aarch64-linux-gnu-nm; do
    if command -v "$candidate" > /dev/null && "$candidate" "$lib" > /dev/null 2>&1; then
        nm_tool=$candidate
        break
    fi
done
[[ -n $nm_tool ]] || fail "no nm reads $lib"

symbols=$("$nm_tool" --defined-only -g "$lib" | awk 'NF == 3 { print $3 }' | sort -u)
count=$(echo "$symbols" | grep -c .)
(( count > 100 )) || fail "only $count global symbols in $lib (nm output changed?)"
# ASan adds a global __odr_asan.NAME beside each global NAME it instruments:
# the instrumentation's, checked through NAME.
bare=$(echo "$symbols" | grep -vE '^(uwb_|uwbd_|uwbscan_|UWB_|__odr_asan\.(uwb_|uwbd_|uwbscan_|UWB_))' || true)
if [[ -n $bare ]]; then
    echo "global symbols of libuwb.a without the uwb prefix (rename them, or make them static):" >&2
    for s in $bare; do
        member=$("$nm_tool" -A --defined-only -g "$lib" | awk -v s="$s" '$NF == s && !found++ { split($1, part, ":"); print part[2] }')
        echo "    $s (in $member)" >&2
    done
    fail "$(echo "$bare" | wc -l) unprefixed global symbols"
fi
echo "PASS: $count global symbols in libuwb.a, all prefixed"
