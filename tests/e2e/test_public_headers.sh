#!/usr/bin/env bash
# include/uwb/ is the library's API: each header there compiles on its own
# in a program that sees only include/ (no -Isrc), so none of them leans on
# a private header (those live beside their code: src/daemon/*.h,
# src/output/render_internal.h, src/gpio/gpio_backend.h, ...).
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }
cc=${CC:-gcc}
command -v "$cc" > /dev/null || cc=cc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

headers=$(cd include && find uwb -name '*.h' | sort)
n=$(echo "$headers" | grep -c .)
(( n > 10 )) || fail "only $n headers under include/uwb"
for h in $headers; do
    printf '#include "%s"\nint main(void) { return 0; }\n' "$h" > "$work/program.c"
    "$cc" -std=c11 -Wall -Wextra -Werror -D_DEFAULT_SOURCE -fsyntax-only -Iinclude "$work/program.c" \
        2> "$work/err" || fail "include/$h does not compile on its own with -Iinclude: $(head -3 "$work/err")"
done
echo "PASS: $n public headers, each compiles on its own"
