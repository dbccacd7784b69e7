#!/usr/bin/env bash
# Packs the emulated board's root file system: busybox, an /init, aarch64
# programs and every shared library they load (found through their ELF
# DT_NEEDED entries in the aarch64 multiarch directories, as on the
# Debian 12 board), as a gzip-compressed newc cpio archive.
#
# Usage: tools/board-in-loop/make-initramfs.sh --out FILE.cpio.gz \
#            --busybox FILE --init FILE [--program FILE]... [--file SRC=DEST]...
#   --program FILE   an aarch64 executable, installed as /usr/bin/NAME
#   --file SRC=DEST  any other file, installed at DEST (absolute path)
# Shared libraries go to /usr/lib/aarch64-linux-gnu with /lib -> usr/lib,
# the merged-/usr layout Debian 12 has, so the loader's own default search
# path finds them.
set -euo pipefail

readonly TRIPLET=aarch64-linux-gnu
readonly LIBRARY_DIRS=("/usr/lib/$TRIPLET" "/lib/$TRIPLET")
readonly READELF="$TRIPLET-readelf"

die() {
    echo "make-initramfs: $*" >&2
    exit 1
}

usage() {
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
}

# The DT_NEEDED sonames of an ELF file, one a line.
needed_libraries() {
    "$READELF" -d "$1" 2>/dev/null | sed -n 's/.*(NEEDED).*\[\(.*\)\]$/\1/p'
}

program_interpreter() {
    "$READELF" -l "$1" 2>/dev/null | sed -n 's/.*Requesting program interpreter: \(.*\)\]$/\1/p'
}

find_library() {
    local soname="$1" dir
    for dir in "${LIBRARY_DIRS[@]}"; do
        if [[ -e "$dir/$soname" ]]; then
            echo "$dir/$soname"
            return 0
        fi
    done
    return 1
}

# Copies the libraries an ELF file needs, and theirs, into ROOT.
install_libraries() {
    local root="$1" elf="$2"
    local queue=("$elf") seen=" " current soname path
    local interpreter
    interpreter="$(program_interpreter "$elf")"
    if [[ -n "$interpreter" ]]; then
        [[ -e "$interpreter" ]] ||
            die "$(basename "$elf") asks for the loader $interpreter, which is not on this machine (libc6:arm64)"
        [[ -e "$root$interpreter" ]] || cp -L "$interpreter" "$root/usr/lib/$(basename "$interpreter")"
    fi
    while [[ ${#queue[@]} -gt 0 ]]; do
        current="${queue[0]}"
        queue=("${queue[@]:1}")
        while read -r soname; do
            [[ -z "$soname" || "$seen" == *" $soname "* ]] && continue
            seen+="$soname "
            path="$(find_library "$soname")" ||
                die "$(basename "$current") needs $soname, not found in ${LIBRARY_DIRS[*]} (is its :arm64 package installed?)"
            cp -L "$path" "$root/usr/lib/$TRIPLET/$soname"
            queue+=("$path")
        done < <(needed_libraries "$current")
    done
}

main() {
    local out="" busybox="" init="" programs=() files=()
    while [[ $# -gt 0 ]]; do
        case "$1" in
            --out) out="${2:?}"; shift 2 ;;
            --busybox) busybox="${2:?}"; shift 2 ;;
            --init) init="${2:?}"; shift 2 ;;
            --program) programs+=("${2:?}"); shift 2 ;;
            --file) files+=("${2:?}"); shift 2 ;;
            *) usage ;;
        esac
    done
    [[ -n "$out" && -n "$busybox" && -n "$init" ]] || usage
    command -v cpio >/dev/null || die "cpio is not installed (apt-get install cpio)"
    command -v "$READELF" >/dev/null || die "$READELF is not installed (binutils-$TRIPLET)"
    [[ -x "$busybox" ]] || die "$busybox: not an executable busybox"
    [[ -f "$init" ]] || die "$init: no such init script"

    local root
    root="$(mktemp -d)"
    # shellcheck disable=SC2064  # expand now: root is local
    trap "rm -rf '$root'" EXIT
    mkdir -p "$root"/{bin,dev,proc,sys,tmp,run,etc,var,usr/bin,"usr/lib/$TRIPLET"}
    ln -s usr/lib "$root/lib"
    cp "$busybox" "$root/bin/busybox"
    cp "$init" "$root/init"
    chmod 0755 "$root/init" "$root/bin/busybox"

    local program
    for program in "${programs[@]}"; do
        [[ -x "$program" ]] || die "$program: no such executable"
        cp "$program" "$root/usr/bin/$(basename "$program")"
        install_libraries "$root" "$program"
    done
    local spec source dest
    for spec in "${files[@]}"; do
        source="${spec%%=*}" dest="${spec#*=}"
        [[ "$spec" == *=/* && -f "$source" ]] || die "--file $spec: want an existing SRC=/ABSOLUTE/DEST"
        mkdir -p "$root$(dirname "$dest")"
        cp "$source" "$root$dest"
    done

    mkdir -p "$(dirname "$out")"
    local partial="$out.partial"
    (cd "$root" && find . | LC_ALL=C sort | cpio -o -H newc --quiet -R 0:0 | gzip -1) >"$partial"
    mv "$partial" "$out"
}

main "$@"
