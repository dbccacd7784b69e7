#!/usr/bin/env bash
# No cycles between files of different jobs in libuwb.a: for every object of
# src/, the global symbols it uses are resolved to the object defining them
# (nm), and the resulting "uses" graph must have no loop (tsort). A loop
# means neither file can be understood, tested or replaced without the other
# (issue 18: the store's open repaired the verdict log, which writes through
# the store).
#
# Files that are one job split for size are one node; each group says why.
# Then files (issue 47): a call or a private #include between two files of
# src/ is an arrow, and no file may reach itself through them, so any file
# is read knowing only the ones it uses. The daemon's own files are no
# group: the output modules see the daemon through a port
# (src/daemon/output_module.h), not by calling back into it.
set -euo pipefail
fail() { echo "FAIL: $*" >&2; exit 1; }

obj="$UWB_BUILD_DIR/obj/src"
[[ -d $obj ]] || fail "$obj: no objects (build first)"

groups=$(cat <<'EOF'
# An interface and the backends in its table: the front end picks a backend,
# the backends use the front end's helpers.
gpio src/gpio/gpio.o src/gpio/gpio_emulated.o src/hw/gpio_libgpiod.o
link src/link/link.o src/link/link_socket.o
# One job split for size, one header between them (for the files' check
# below, which counts includes too): the control socket and its account
# of a refused connect; the carriage and its step timing (pacer: when,
# ramp: how fast), both declared in carriage.h; the configuration and its
# site part, checked against the whole.
control-socket src/control/control_socket.o src/control/control_denied.o
carriage src/rig/carriage.o src/rig/pacer.o src/rig/ramp.o
config src/config/config.h src/config/site_config.o
EOF
)

# The nm that reads these objects (a cross build's are not the host's).
first=$(cd "$UWB_BUILD_DIR/obj" && find src -name '*.o' | sort | head -n 1)
nm_tool=
for candidate in nm aarch64-linux-gnu-nm; do
    if command -v "$candidate" > /dev/null && "$candidate" "$UWB_BUILD_DIR/obj/$first" > /dev/null 2>&1; then
        nm_tool=$candidate
        break
    fi
done
[[ -n $nm_tool ]] || fail "no nm reads $first"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# node OBJECT: the group an object belongs to, or the object itself.
echo "$groups" | awk '!/^#/ && NF > 1 { for (i = 2; i <= NF; i++) print $i, $1 }' | sort > "$work/node"

repo=$(pwd)
cd "$UWB_BUILD_DIR/obj"
# Objects of sources that still exist (a renamed file leaves its old object behind).
objects=$(find src -name '*.o' | sort | while read -r o; do if [[ -f $repo/${o%.o}.c ]]; then echo "$o"; fi; done)
[[ $(echo "$objects" | wc -l) -gt 20 ]] || fail "only $(echo "$objects" | wc -l) objects under $obj"
for o in $objects; do
    "$nm_tool" --defined-only -g "$o" | awk -v o="$o" 'NF == 3 { print $3, o }'
done | sort > "$work/defined"
for o in $objects; do
    "$nm_tool" -u "$o" | awk -v o="$o" '{ print $2, o }'
done | sort > "$work/used"

# "user provider" per symbol, then each object replaced by its node.
join "$work/used" "$work/defined" | awk '{ print $2, $3, $1 }' | sort > "$work/edges"
awk 'NR == FNR { node[$1] = $2; next }
     { u = ($1 in node) ? node[$1] : $1; p = ($2 in node) ? node[$2] : $2;
       if (u != p) print u, p, $3 }' "$work/node" "$work/edges" > "$work/node-edges"
[[ -s $work/node-edges ]] || fail "no references between objects found (nm output changed?)"

if ! awk '{ print $1, $2 }' "$work/node-edges" | sort -u | tsort > /dev/null 2> "$work/loops"; then
    echo "objects of libuwb.a that use each other (a cycle), with a symbol each way:" >&2
    loop=$(grep -v 'input contains a loop' "$work/loops" | sed 's/^tsort: //' | sort -u)
    for a in $loop; do
        for b in $loop; do
            awk -v a="$a" -v b="$b" '$1 == a && $2 == b { print "    " a " uses " b ": " $3; exit }' \
                "$work/node-edges" >&2
        done
    done
    fail "cycles between objects of different jobs"
fi

# Files: the calls above and the private includes (#include "FOLDER/x.h",
# or "x.h" beside the includer), each file's .c and .h one node ("src/daemon/peers"),
# a group's files its group. No circle, and the check must see one planted.

awk '{ print $1, $2, $1 " uses " $3 }' "$work/edges" | sed -E 's/\.o / /; s/\.o / /' > "$work/file-uses"
(cd "$repo" && grep -rHE '^#include "[a-z_]+(/[a-z_0-9]+)?\.h"' src --include='*.c' --include='*.h') |
    sed -E 's|^([^:]*)\.[ch]:#include "([^"]*)\.h".*$|\1 \2 \1 includes \2.h|' |
    awk '{ user = $1; h = $2; if (h !~ /\//) { d = user; sub(/\/[^\/]*$/, "", d); h = d "/" h } else h = "src/" h
           if (h !~ /^src\/uwb\// && user != h) { $2 = h; print } }' >> "$work/file-uses"
awk 'NR == FNR { sub(/\.[oh]$/, "", $1); node[$1] = $2; next }
     { u = ($1 in node) ? node[$1] : $1; p = ($2 in node) ? node[$2] : $2; if (u != p) { $1 = u; $2 = p; print } }' \
    "$work/node" "$work/file-uses" | sort -k1,2 -u > "$work/file-arrows"
[[ $(grep -c '^src/daemon/.* src/daemon/' "$work/file-arrows") -gt 20 ]] || fail "arrows between files of src/daemon/ not found"
# file_circle ARROWS: 0 and the circle's files with an arrow each way on stderr when there is one.
file_circle() {
    awk '{ print $1, $2 }' "$1" | tsort > /dev/null 2> "$work/file-loops" && return 1
    loop=$(grep -v 'input contains a loop' "$work/file-loops" | sed 's/^tsort: //' | sort -u)
    for a in $loop; do
        for b in $loop; do
            awk -v a="$a" -v b="$b" '$1 == a && $2 == b { sub(/^[^ ]+ [^ ]+ /, ""); print "    " $0; exit }' "$1" >&2
        done
    done
    return 0
}
# Planted: the table (outputs) calling a module back from the module's side.
planted=$(awk '$1 == "src/daemon/outputs" && $2 == "src/daemon/output_csv" { print $2, $1, "planted"; exit }' "$work/file-arrows")
[[ -n $planted ]] || fail "no arrow from src/daemon/outputs to src/daemon/output_csv to plant a circle against"
{ cat "$work/file-arrows"; echo "$planted"; } > "$work/file-arrows-planted"
file_circle "$work/file-arrows-planted" 2> /dev/null || fail "a planted circle (output_csv -> outputs -> output_csv) was not seen"
if file_circle "$work/file-arrows"; then
    fail "files of src/ that reach each other (a circle), with an arrow each way (above)"
fi

# Folders too: arrows between the folders of src/ point one way only, so a
# lower folder is understood without the ones above it (issue 29: the
# integrations used the daemon's log while the daemon drove them). An arrow
# is a symbol one folder's object uses from another's, an
# #include "FOLDER/x.h" of another folder's private header, or an
# #include "uwb/x.h" of a public header that belongs to another folder: a
# public header belongs to the folders defining the functions it declares
# (one declaring none, such as uwb/version.h, to no folder).
#
# A hardware backend lives in src/hw/ (hardware headers only there) but is a
# row of its interface's table: it counts as that interface's folder.
rooms=$(cat <<'EOF'
gpio src/hw/gpio_libgpiod
link src/hw/link_serial
EOF
)
echo "$rooms" | awk 'NF == 2 { print $2, $1 }' > "$work/room"
# "USER PROVIDER how" with USER and PROVIDER paths -> their folders.
to_folders() {
    awk 'NR == FNR { room[$1] = $2; next }
         function folder(path, part) {
             sub(/\.[a-z]+$/, "", path)
             if (path in room) return room[path]
             split(path, part, "/")
             return part[2]
         }
         { $1 = folder($1); $2 = folder($2); if ($1 != $2) print }' "$work/room" -
}
awk '{ print $1, $2, $1 " uses " $3 }' "$work/edges" | to_folders > "$work/folder-edges"
(cd "$repo" && grep -rHE '^#include "[a-z_]+/[a-z_0-9]+\.h"' src --include='*.c' --include='*.h') |
    sed -E 's|^([^:]*):#include "([a-z_]+)/([^"]*)".*$|\1 src/\2/x \1 includes \2/\3|' |
    awk '$2 != "src/uwb/x"' | to_folders >> "$work/folder-edges"
# "uwb/x.h OBJECT" for each object defining a function the header declares.
for h in $(cd "$repo" && find include/uwb -name '*.h' | sort); do
    { grep -oE '^[a-z][^;]*\b(uwb|uwbd|uwbscan)_[a-z0-9_]+\(' "$repo/$h" || true; } |
        sed -E 's/^.*[^a-z0-9_]([a-z0-9_]+)\($/\1/' | awk -v h="${h#include/}" '{ print $1, h }'
done | sort > "$work/declared"
join "$work/declared" "$work/defined" | awk '{ print $2, $3 }' | sort -u > "$work/header-objects"
[[ $(wc -l < "$work/header-objects") -gt 20 ]] || fail "public headers' functions not found among the objects"
(cd "$repo" && grep -rHE '^#include "uwb/[a-z_0-9]+\.h"' src include --include='*.c' --include='*.h') |
    sed -E 's|^([^:]*):#include "(uwb/[^"]*)".*$|\1 \2|' |
    awk 'NR == FNR { objects[$1] = objects[$1] " " $2; next }
         { user = $1; if (user ~ /^include\//) { sub(/^include\//, "", user); users = objects[user] } else users = user
           n = split(users, u, " "); m = split(objects[$2], p, " ")
           for (i = 1; i <= n; i++) for (j = 1; j <= m; j++) print u[i], p[j], $1 " includes " $2 }' \
        "$work/header-objects" - | to_folders >> "$work/folder-edges"
# No arrow is excused: the last one pointing up (config -> rig through
# uwb/rig.h while the rig read its limits from the key table) went when the
# rig's limits moved into the rig (src/rig/rig_keys.h, issue 29).
sort -k1,2 -u "$work/folder-edges" > "$work/folder-arrows"
[[ -s $work/folder-arrows ]] || fail "no arrows between the folders of src/ found"
if ! awk '{ print $1, $2 }' "$work/folder-arrows" | tsort > /dev/null 2> "$work/folder-loops"; then
    echo "folders of src/ that lean on each other (a cycle), with an arrow each way:" >&2
    loop=$(grep -v 'input contains a loop' "$work/folder-loops" | sed 's/^tsort: //' | sort -u)
    for a in $loop; do
        for b in $loop; do
            awk -v a="$a" -v b="$b" '$1 == a && $2 == b { sub(/^[^ ]+ [^ ]+ /, ""); print "    " a " -> " b ": " $0; exit }' \
                "$work/folder-arrows" >&2
        done
    done
    fail "cycles between the folders of src/"
fi

# The rooms, top to bottom (issue 47): an arrow goes from a room to one on a
# lower line, never up nor sideways, so each room is read knowing only the
# ones below it. A new folder is placed here on purpose, not left to tsort.
# The daemon sits on its control protocol (control), its event loop (loop)
# and its persistence (state), which know nothing of it.
layers=$(cat <<'EOF'
main
cli
daemon
control loop
state
integrations
config
evaluate output
imaging text rig
verdict gpio digitiser
scanfile link
util
EOF
)
echo "$layers" | awk '{ for (i = 1; i <= NF; i++) print $i, NR }' | sort > "$work/layer"
for folder in $(awk '{ print $1; print $2 }' "$work/folder-arrows" | sort -u); do
    grep -q "^$folder " "$work/layer" || fail "src/$folder: a room not placed in this test's layers (top to bottom)"
done
up=$(awk 'NR == FNR { line[$1] = $2; next }
          line[$1] >= line[$2] { sub(/^[^ ]+ [^ ]+ /, ""); print "    " $0 }' "$work/layer" "$work/folder-edges" | sort -u)
[[ -z $up ]] || { echo "$up" >&2; fail "arrows that point up or sideways between the rooms of src/"; }
# ctl is a client of the control protocol: it reaches it, and the config
# loader for the socket's path, without the daemon (src/daemon/).
ctl_to_daemon=$(awk '$1 == "cli" && $2 == "daemon" && $3 ~ /^src\/cli\/(ctl_cli|option_error)\./ { sub(/^[^ ]+ [^ ]+ /, ""); print "    " $0 }' \
    "$work/folder-edges" | sort -u)
[[ -z $ctl_to_daemon ]] || { echo "$ctl_to_daemon" >&2; fail "uwbd ctl leans on the daemon"; }

echo "PASS: $(echo "$objects" | wc -l) objects, $(awk '{ print $1, $2 }' "$work/node-edges" | sort -u | wc -l) uses between them, no cycle;" \
    "$(awk '{ print $1, $2 }' "$work/file-arrows" | sort -u | wc -l) arrows between files of src/ (calls, private includes), no circle;" \
    "$(wc -l < "$work/folder-arrows") arrows between $(awk '{ print $1; print $2 }' "$work/folder-arrows" | sort -u | wc -l) folders, all one way and down"
