#!/usr/bin/env bash
# Fetches the two Debian arm64 packages the emulated board boots from and
# keeps their extracted files in a cache, so later runs need no network:
#   linux-image-6.1.0-*-arm64  (the kernel named by linux-image-arm64)
#   busybox-static             (the guest's shell and tools)
# Packages are only downloaded and unpacked with dpkg-deb -x, never
# installed. Prints two lines for the caller to eval:
#   KERNEL=/…/vmlinuz  BUSYBOX=/…/busybox
#
# Usage: tools/board-in-loop/fetch-guest.sh
# Cache: $UWB_BOARD_CACHE, else $XDG_CACHE_HOME/uwbd/board, else
#        ~/.cache/uwbd/board (the repository's third_party/board-cache
#        when there is no home directory).
set -euo pipefail

readonly GUEST_ARCH=arm64
readonly KERNEL_META_PACKAGE="linux-image-$GUEST_ARCH"
readonly BUSYBOX_PACKAGE="busybox-static"

die() {
    echo "fetch-guest: $*" >&2
    exit 1
}

note() {
    echo "fetch-guest: $*" >&2
}

cache_dir() {
    if [[ -n "${UWB_BOARD_CACHE:-}" ]]; then
        echo "$UWB_BOARD_CACHE"
    elif [[ -n "${XDG_CACHE_HOME:-}" ]]; then
        echo "$XDG_CACHE_HOME/uwbd/board"
    elif [[ -n "${HOME:-}" && -d "$HOME" && -w "$HOME" ]]; then
        echo "$HOME/.cache/uwbd/board"
    else
        echo "$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/third_party/board-cache"
    fi
}

# apt-get download as root otherwise drops privileges to _apt, which may not
# write the cache directory; it only warns, but the warning hides real errors.
apt_download() {
    local dest="$1"
    shift
    local options=(-q)
    [[ "$(id -u)" == 0 ]] && options+=(-o APT::Sandbox::User=root)
    (cd "$dest" && apt-get "${options[@]}" download "$@")
}

# The versioned kernel package the meta package points at, e.g.
# linux-image-6.1.0-56-arm64.
kernel_package_name() {
    apt-cache depends "$KERNEL_META_PACKAGE:$GUEST_ARCH" 2>/dev/null |
        sed -n 's/^ *Depends: \(linux-image-[0-9][^:]*-'"$GUEST_ARCH"'\)\(:'"$GUEST_ARCH"'\)\{0,1\}$/\1/p' |
        head -n 1
}

# Downloads PACKAGE:arm64 into SCRATCH and unpacks it into SCRATCH/tree.
# PACKAGE is a function's name when the package's name itself comes from
# the apt lists (the kernel's): a failed download may only mean stale
# lists, whose packages the mirror has dropped, so the lists are updated
# once, the name asked again and the download tried again.
fetch_and_extract() {
    local name_of="$1" scratch="$2" package
    mkdir -p "$scratch/deb" "$scratch/tree"
    package="$("$name_of")"
    if [[ -z "$package" ]] || ! apt_download "$scratch/deb" "$package:$GUEST_ARCH" >"$scratch/apt.log" 2>&1; then
        note "${package:-the kernel package}:$GUEST_ARCH not found; updating the package lists once"
        apt-get -q update >"$scratch/update.log" 2>&1 ||
            { cat "$scratch/update.log" >&2; die "apt-get update failed"; }
        package="$("$name_of")"
        [[ -n "$package" ]] ||
            die "apt-cache does not know $KERNEL_META_PACKAGE:$GUEST_ARCH (is $GUEST_ARCH a dpkg architecture here? make deps-arm adds it)"
        apt_download "$scratch/deb" "$package:$GUEST_ARCH" >"$scratch/apt.log" 2>&1 ||
            { cat "$scratch/apt.log" >&2; die "apt-get download $package:$GUEST_ARCH failed (is $GUEST_ARCH a dpkg architecture here? make deps-arm adds it)"; }
    fi
    note "unpacking $package:$GUEST_ARCH"
    local debs=("$scratch/deb/"*.deb)
    [[ -f "${debs[0]}" ]] || die "apt-get download $package:$GUEST_ARCH left no .deb"
    dpkg-deb -x "${debs[0]}" "$scratch/tree" || die "dpkg-deb -x $(basename "${debs[0]}") failed"
    basename "${debs[0]}" >"$scratch/deb-name"
}

busybox_package_name() {
    echo "$BUSYBOX_PACKAGE"
}

ensure_kernel() {
    local cache="$1"
    [[ -s "$cache/kernel/vmlinuz" ]] && return 0
    note "fetching Debian's $GUEST_ARCH kernel (about 60 MB, once) into $cache"
    local scratch
    scratch="$(mktemp -d "$cache/.kernel.XXXXXX")"
    fetch_and_extract kernel_package_name "$scratch"
    local images=("$scratch/tree/boot/vmlinuz-"*)
    [[ -f "${images[0]}" ]] || die "$(cat "$scratch/deb-name"): has no boot/vmlinuz-*"
    mkdir -p "$scratch/kernel"
    mv "${images[0]}" "$scratch/kernel/vmlinuz"
    cp "$scratch/tree/boot/config-"* "$scratch/kernel/config" 2>/dev/null || true
    cat "$scratch/deb-name" >"$scratch/kernel/SOURCE"
    # The kernel directory appears in one rename: a cache is never half filled.
    rm -rf "$cache/kernel"
    mv "$scratch/kernel" "$cache/kernel"
    rm -rf "$scratch"
}

ensure_busybox() {
    local cache="$1"
    [[ -x "$cache/busybox/busybox" ]] && return 0
    note "fetching $BUSYBOX_PACKAGE:$GUEST_ARCH into $cache"
    local scratch
    scratch="$(mktemp -d "$cache/.busybox.XXXXXX")"
    fetch_and_extract busybox_package_name "$scratch"
    [[ -x "$scratch/tree/bin/busybox" ]] || die "$(cat "$scratch/deb-name"): has no bin/busybox"
    mkdir -p "$scratch/busybox"
    mv "$scratch/tree/bin/busybox" "$scratch/busybox/busybox"
    cat "$scratch/deb-name" >"$scratch/busybox/SOURCE"
    rm -rf "$cache/busybox"
    mv "$scratch/busybox" "$cache/busybox"
    rm -rf "$scratch"
}

main() {
    [[ $# == 0 ]] || die "takes no arguments (cache: UWB_BOARD_CACHE)"
    local cache
    cache="$(cache_dir)"
    mkdir -p "$cache" || die "cannot create the cache directory $cache"
    # Two builds at once must not fetch into the same cache together.
    exec 9>"$cache/.lock"
    flock 9
    # Scratch folders of a failed fetch go too (only the lock holder has any).
    # shellcheck disable=SC2064  # expand now: cache is local
    trap "rm -rf '$cache'/.kernel.* '$cache'/.busybox.*" EXIT
    ensure_kernel "$cache"
    ensure_busybox "$cache"
    exec 9>&-
    echo "KERNEL=$cache/kernel/vmlinuz"
    echo "BUSYBOX=$cache/busybox/busybox"
}

main "$@"
