#!/usr/bin/env bash
# The README's architecture graph, drawn from the build instead of by hand
# (issue 47): which rooms (folders) of src/ each room uses, and which files
# of src/daemon/ each daemon file uses, with the files that reach each
# other in a circle. A use is a call (a global symbol one object takes from
# another, nm) or an #include "FOLDER/x.h" of another's private header.
#   readme-arch.sh BUILD                    print the block
#   readme-arch.sh BUILD --write README.md  replace the marked block
#   readme-arch.sh BUILD --check README.md  exit 1 (with a diff) when it differs
# `make readme-arch` writes; tests/e2e/test_readme_arch.sh checks.
# tests/e2e/test_object_cycles.sh is what holds the rooms' arrows down.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
[[ $# == 1 || ($# == 3 && ($2 == --write || $2 == --check)) ]] ||
    { echo "usage: $0 BUILD [--write|--check README]" >&2; exit 64; }
build=$1
obj=$build/obj
[[ -d $obj/src ]] || { echo "readme-arch: $obj/src: no objects (build first)" >&2; exit 1; }

nm_tool=
first=$(cd "$obj" && find src -name '*.o' | sort | head -n 1)
for candidate in nm aarch64-linux-gnu-nm; do
    if command -v "$candidate" > /dev/null && "$candidate" "$obj/$first" > /dev/null 2>&1; then
        nm_tool=$candidate
        break
    fi
done
[[ -n $nm_tool ]] || { echo "readme-arch: no nm reads $obj/$first" >&2; exit 1; }

work=$(mktemp -d /tmp/uwbd-readme-arch-XXXXXX)
trap 'rm -rf "$work"' EXIT
repo=$(pwd)

# "USER PROVIDER" per use, as source paths without extension (src/daemon/peers).
# Objects of sources that still exist (a renamed file leaves its object behind).
objects=$(cd "$obj" && find src -name '*.o' | sort | while read -r o; do
    if [[ -f $repo/${o%.o}.c ]]; then echo "$o"; fi
done)
for o in $objects; do
    "$nm_tool" --defined-only -g "$obj/$o" | awk -v o="${o%.o}" 'NF == 3 { print $3, o }'
done | sort > "$work/defined"
for o in $objects; do
    "$nm_tool" -u "$obj/$o" | awk -v o="${o%.o}" '{ print $2, o }'
done | sort > "$work/used"
join "$work/used" "$work/defined" | awk '$2 != $3 { print $2, $3 }' > "$work/uses"
grep -rHE '^#include "[a-z_]+(/[a-z_0-9]+)?\.h"' src --include='*.c' --include='*.h' |
    sed -E 's|^([^:]*)\.[ch]:#include "([^"]*)\.h".*$|\1 \2|' |
    awk '{ user = $1; h = $2; if (h !~ /\//) { d = user; sub(/\/[^\/]*$/, "", d); h = d "/" h } else h = "src/" h
           if (h !~ /^src\/uwb\// && user != h) print user, h }' >> "$work/uses"

# wrap INDENT: lines cut at 96 columns between words, continued at INDENT.
wrap() {
    awk -v indent="$1" '{
        rest = $0
        while (length(rest) > 96) {
            cut = 96
            while (cut > indent + 1 && substr(rest, cut + 1, 1) != " ") cut--
            print substr(rest, 1, cut)
            rest = sprintf("%*s", indent, "") substr(rest, cut + 2)
        }
        print rest
    }'
}

# ROOM -> ROOMS, a room's line after those of the rooms using it (tsort).
# A hardware backend (src/hw/) is a row of its interface's table and counts
# as that interface's room, as in tests/e2e/test_object_cycles.sh.
awk 'function room(path, part) {
         if (path == "src/hw/gpio_libgpiod") return "gpio"
         if (path == "src/hw/link_serial") return "link"
         split(path, part, "/")
         return part[2]
     }
     { a = room($1); b = room($2); if (a != b) print a, b }' "$work/uses" |
    sed 's/^main\.c /main /' | sort -u > "$work/rooms"
order=$(tsort "$work/rooms")
{
    echo "Rooms of src/, each with the rooms it uses (a call or a private header);"
    echo "every arrow points down the list (tests/e2e/test_object_cycles.sh):"
    for room in $order; do
        printf '  %-13s -> %s\n' "$room" "$(awk -v r="$room" '$1 == r { printf "%s%s", sep, $2; sep = " " }' "$work/rooms")"
    done | sed 's/ -> $/ ->/' | wrap 19
    echo
    echo "Files of src/daemon/, each with the daemon/ files it uses:"
    awk '$1 ~ /^src\/daemon\// && $2 ~ /^src\/daemon\// { sub(/^src\/daemon\//, "", $1); sub(/^src\/daemon\//, "", $2)
         if ($1 != $2) print $1, $2 }' "$work/uses" | sort -u > "$work/files"
    awk '{ print $1; print $2 }' "$work/files" | sort -u > "$work/file-names"
    while read -r f; do
        printf '  %-17s -> %s\n' "$f" "$(awk -v f="$f" '$1 == f { printf "%s%s", sep, $2; sep = " " }' "$work/files")"
    done < "$work/file-names" | sed 's/ -> $/ ->/' | wrap 23
    # Files that reach each other: the transitive closure (Warshall), then
    # each group of mutually reachable files.
    circles=$(awk 'NR == FNR { id[$1] = ++n; name[n] = $1; next }
        { r[id[$1], id[$2]] = 1 }
        END {
            for (k = 1; k <= n; k++) for (i = 1; i <= n; i++) if (r[i, k]) for (j = 1; j <= n; j++) if (r[k, j]) r[i, j] = 1
            for (i = 1; i <= n; i++) {
                if (done[i]) continue
                line = name[i]; m = 1
                for (j = i + 1; j <= n; j++) if (r[i, j] && r[j, i]) { line = line " " name[j]; done[j] = 1; m++ }
                if (m > 1) print m " files: " line
            }
        }' "$work/file-names" "$work/files")
    if [[ -z $circles ]]; then
        echo "No circle: no daemon/ file reaches itself through the others."
    else
        echo "Files that reach each other through these uses (a circle):"
        echo "$circles" | sed 's/^/  /' | wrap 4
    fi
} > "$work/graph"

if [[ $# == 1 ]]; then
    cat "$work/graph"
    exit 0
fi
mode=$2 readme=$3
{ echo '```'; cat "$work/graph"; echo '```'; } > "$work/block"
awk -v name=readme-arch -v file="$work/block" '
    index($0, "<!-- make " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- make " name ": end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-arch: marker <!-- make " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$readme" > "$work/readme"
if [[ $mode == --write ]]; then
    cmp -s "$work/readme" "$readme" || cp "$work/readme" "$readme"
    echo "readme-arch: $readme: $(wc -l < "$work/graph") lines of graph"
elif ! diff -u "$readme" "$work/readme" >&2; then
    echo "readme-arch: $readme's architecture graph is not what the build says (above); run make readme-arch" >&2
    exit 1
fi
