#!/usr/bin/env bash
# Installs what building and testing uwbd needs, so that `make test`,
# `make demo` and `make test-arm` work on a fresh Debian 12 machine with
# nothing run before them.  It runs on every `make test`, so the common case
# (everything present) only asks pkg-config and returns.
#
# Usage: tools/deps/ensure-deps.sh [--cross ARCH] [--board] [--fuzz] [--soak] [--dev] [--deb] [--unity-only]
#   (no option)    native toolchain + -dev packages, then Unity
#   --cross ARCH   cross toolchain, qemu-user and the ARCH multiarch -dev
#                  packages (ARCH: aarch64), then Unity
#   --board        make test-board: native and aarch64 as above, plus
#                  qemu-system-aarch64 and cpio (the guest's kernel
#                  and busybox: tools/board-in-loop/fetch-guest.sh)
#   --fuzz         make fuzz: native as above, plus clang and its libFuzzer
#                  runtime (Debian 12: clang-14, libclang-rt-14-dev, which
#                  clang only recommends)
#   --soak         make soak: native as above, plus valgrind (its leak-checked run)
#   --dev          make format / format-check / lint / coverage: native as above,
#                  plus clang-format, clang-tidy, cppcheck and gcovr (not needed
#                  by make test, so a fresh machine's make test does not fetch them)
#   --deb          make deb / make test-deb: native as above, plus dpkg-dev,
#                  debhelper, lintian, fakeroot, debootstrap and systemd
#                  (systemd-analyze verifies the unit)
#   --unity-only   only fetch Unity if it is absent
#
# Unity 2.4.3 comes from Debian's cjson source package (its tests/unity):
# third_party/unity/{unity.c,unity.h,unity_internals.h} plus
# third_party/examples/unity_config.h, which cJSON's unity_internals.h
# includes as "../examples/unity_config.h".
#
# Hooks for exercising the slow paths without uninstalling anything:
#   UWB_DEPS_FAKE_MISSING="libgpiod qemu-aarch64 unity"  treat these
#       pkg-config modules / commands / "unity" as missing
#   UWB_DEPS_DRY_RUN=1   print the root commands (apt-get, dpkg) instead
#       of running them
#   UWB_UNITY_DIR=DIR    fetch Unity into DIR instead of third_party/unity
set -euo pipefail

REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
readonly REPO_ROOT
readonly NATIVE_MODULES=(fftw3f libcjson libpng libgpiod libserialport zlib libsystemd libmosquitto libmodbus)
readonly NATIVE_PACKAGES=(gcc make libc6-dev pkg-config groff-base scdoc
    libfftw3-dev libcjson-dev libpng-dev libgpiod-dev libserialport-dev zlib1g-dev libsystemd-dev
    libmosquitto-dev mosquitto libmodbus-dev systemd)
readonly UNITY_FILES=(unity.c unity.h unity_internals.h)
readonly UNITY_EXPECTED_VERSION="2.4.3"
# Unity comes from the cJSON source package of one fixed Debian release so
# every machine gets byte-identical test framework sources.
readonly UNITY_SOURCE_PACKAGE="cjson"
readonly DEBIAN_MIRROR="${UWB_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
readonly DEBIAN_SUITE="bookworm"

UNITY_DIR="${UWB_UNITY_DIR:-$REPO_ROOT/third_party/unity}"
DRY_RUN="${UWB_DEPS_DRY_RUN:-0}"
FAKE_MISSING=" ${UWB_DEPS_FAKE_MISSING:-} "
APT_UPDATED=0

die() {
    echo "ensure-deps: $*" >&2
    exit 1
}

note() {
    echo "ensure-deps: $*" >&2
}

is_faked_missing() {
    [[ "$FAKE_MISSING" == *" $1 "* ]]
}

have_command() {
    ! is_faked_missing "$1" && command -v "$1" >/dev/null 2>&1
}

# Prints the modules (from the arguments) that pkg-config cannot find.
missing_modules() {
    local module
    if [[ -z "${FAKE_MISSING// /}" ]] && have_command pkg-config &&
        pkg-config --exists "$@" 2>/dev/null; then
        return 0    # one pkg-config call: the every-run fast path
    fi
    for module in "$@"; do
        if is_faked_missing "$module" || ! have_command pkg-config ||
            ! pkg-config --exists "$module" 2>/dev/null; then
            echo "$module"
        fi
    done
}

# Stops with what to run by hand when installing is impossible: not root
# and no sudo.
require_root() {
    local by_hand="$1"
    [[ "$DRY_RUN" == 1 || "$(id -u)" == 0 ]] && return 0
    command -v sudo >/dev/null 2>&1 && return 0
    die "installing packages needs root, and sudo is not installed; as root run:
    $by_hand"
}

# Runs a command as root: directly or through sudo.
as_root() {
    if [[ "$DRY_RUN" == 1 ]]; then
        echo "ensure-deps: would run as root: $*" >&2
    elif [[ "$(id -u)" == 0 ]]; then
        "$@"
    else
        sudo "$@"
    fi
}

apt_update_once() {
    if [[ "$APT_UPDATED" == 0 ]]; then
        as_root apt-get -q update
        APT_UPDATED=1
    fi
}

apt_install() {
    apt_update_once
    # Lock::Timeout: several engineers may share this machine and checkout.
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
        --no-install-recommends -o DPkg::Lock::Timeout=600 "$@"
}

# Prints what the native build lacks, one item a line.
missing_native() {
    local command_name
    # groff: tests/e2e/test_man_pages.sh renders the manual pages; scdoc
    # writes the section 7 ones (board/man/*.7.scd) for make man and install.
    for command_name in gcc make pkg-config groff scdoc; do
        have_command "$command_name" || echo "$command_name"
    done
    # systemd-analyze: tests/e2e/test_clock_check_sandbox.sh reads the
    # syscall groups the unit allows with it (a minbase Debian lacks it).
    have_command systemd-analyze || echo systemd-analyze
    # The MQTT tests start a real broker (Debian installs it in /usr/sbin).
    { ! is_faked_missing mosquitto && [[ -x /usr/sbin/mosquitto ]]; } || echo mosquitto
    missing_modules "${NATIVE_MODULES[@]}"
}

ensure_native() {
    local missing
    mapfile -t missing < <(missing_native)
    [[ ${#missing[@]} == 0 ]] && return 0

    note "missing: ${missing[*]}; installing ${NATIVE_PACKAGES[*]}"
    require_root "apt-get update && apt-get install -y ${NATIVE_PACKAGES[*]}"
    apt_install "${NATIVE_PACKAGES[@]}"
    [[ "$DRY_RUN" == 1 ]] && return 0
    FAKE_MISSING=" "
    mapfile -t missing < <(missing_native)
    [[ ${#missing[@]} == 0 ]] || die "still missing after install: ${missing[*]}"
}

# Prints what the cross build and its qemu test run lack, one item a line.
missing_cross() {
    local triplet="$1" qemu="$2" loader="$3" command_name
    for command_name in make pkg-config "$triplet-gcc" "$qemu"; do
        have_command "$command_name" || echo "$command_name"
    done
    # qemu-user runs the test binaries against the multiarch libc6 of the
    # target, whose dynamic loader lives at $loader.
    if is_faked_missing "$loader" || [[ ! -e "$loader" ]]; then
        echo "$loader"
    fi
    PKG_CONFIG_LIBDIR="/usr/lib/$triplet/pkgconfig:/usr/share/pkgconfig" \
        missing_modules "${NATIVE_MODULES[@]}"
}

ensure_cross() {
    local arch="$1" debian_arch triplet
    case "$arch" in
        aarch64|arm64) arch=aarch64 debian_arch=arm64 triplet=aarch64-linux-gnu ;;
        *) die "--cross $arch: unsupported architecture (supported: aarch64)" ;;
    esac
    local qemu="qemu-$arch"
    local loader="/lib/ld-linux-$arch.so.1"
    # The cross gcc only recommends its libc headers; ask for them by name.
    local cross_packages=("gcc-$triplet" "libc6-dev-$debian_arch-cross" qemu-user make pkg-config
        "libc6:$debian_arch")
    local package
    for package in libfftw3-dev libcjson-dev libpng-dev libgpiod-dev libserialport-dev zlib1g-dev libsystemd-dev \
        libmosquitto-dev libmodbus-dev; do
        cross_packages+=("$package:$debian_arch")
    done

    local missing
    mapfile -t missing < <(missing_cross "$triplet" "$qemu" "$loader")
    [[ ${#missing[@]} == 0 ]] && return 0

    note "missing for $arch: ${missing[*]}; installing ${cross_packages[*]}"
    require_root "dpkg --add-architecture $debian_arch && apt-get update && apt-get install -y ${cross_packages[*]}"
    if ! dpkg --print-foreign-architectures | grep -qx "$debian_arch" &&
        [[ "$(dpkg --print-architecture)" != "$debian_arch" ]]; then
        as_root dpkg --add-architecture "$debian_arch"
        APT_UPDATED=0
    fi
    apt_install "${cross_packages[@]}"
    [[ "$DRY_RUN" == 1 ]] && return 0
    FAKE_MISSING=" "
    mapfile -t missing < <(missing_cross "$triplet" "$qemu" "$loader")
    [[ ${#missing[@]} == 0 ]] || die "still missing after install: ${missing[*]}"
}

# What make test-board and make soak run beside the build, as command:package pairs.
readonly BOARD_COMMANDS=(qemu-system-aarch64:qemu-system-arm cpio:cpio)
readonly SOAK_COMMANDS=(valgrind:valgrind)
# make format, lint, coverage: the developer's tools.
readonly DEV_COMMANDS=(clang-format:clang-format clang-tidy:clang-tidy cppcheck:cppcheck gcovr:gcovr)
# make deb / make test-deb: building, checking and trying the Debian package.
# make test-deb verifies the unit with systemd-analyze and renders the pages with groff.
readonly DEB_COMMANDS=(dpkg-buildpackage:dpkg-dev dh:debhelper lintian:lintian fakeroot:fakeroot
    debootstrap:debootstrap systemd-analyze:systemd groff:groff-base)

# Prints the packages (from command:package pairs) whose commands are missing, one a line.
missing_command_packages() {
    local pair
    for pair in "$@"; do
        have_command "${pair%%:*}" || echo "${pair#*:}"
    done
}

# ensure_commands PURPOSE COMMAND:PACKAGE...: installs the packages whose
# commands are missing.
ensure_commands() {
    local purpose="$1" missing
    shift
    mapfile -t missing < <(missing_command_packages "$@")
    [[ ${#missing[@]} == 0 ]] && return 0

    note "missing for $purpose: ${missing[*]}; installing them"
    require_root "apt-get update && apt-get install -y ${missing[*]}"
    apt_install "${missing[@]}"
    [[ "$DRY_RUN" == 1 ]] && return 0
    FAKE_MISSING=" "
    mapfile -t missing < <(missing_command_packages "$@")
    [[ ${#missing[@]} == 0 ]] || die "still missing after install: ${missing[*]}"
}

readonly FUZZ_PACKAGES=(clang libclang-rt-dev)

# Whether clang links a libFuzzer target with the sanitizers make fuzz uses.
fuzzer_works() {
    have_command clang || return 1
    is_faked_missing libfuzzer && return 1
    local probe
    probe="$(mktemp -d)"
    printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n);\n%s\n' \
        'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { return d && n > 99; }' \
        >"$probe/probe.c"
    local status=0
    clang -fsanitize=fuzzer,address,undefined -o "$probe/probe" "$probe/probe.c" >/dev/null 2>&1 || status=1
    rm -rf "$probe"
    return "$status"
}

ensure_fuzz() {
    fuzzer_works && return 0
    note "clang cannot build a libFuzzer target; installing ${FUZZ_PACKAGES[*]}"
    require_root "apt-get update && apt-get install -y ${FUZZ_PACKAGES[*]}"
    apt_install "${FUZZ_PACKAGES[@]}"
    [[ "$DRY_RUN" == 1 ]] && return 0
    FAKE_MISSING=" "
    fuzzer_works || die "clang still cannot build a libFuzzer target (clang -fsanitize=fuzzer,address,undefined)"
}

# cJSON's copy of Unity has unity_internals.h include
# "../examples/unity_config.h" (which turns on UNITY_INCLUDE_DOUBLE), so
# that file sits beside the unity folder, as in cJSON's tests/unity/.
unity_config_path() {
    echo "$(dirname "$UNITY_DIR")/examples/unity_config.h"
}

unity_is_complete() {
    local file
    is_faked_missing unity && return 1
    for file in "${UNITY_FILES[@]}"; do
        [[ -f "$UNITY_DIR/$file" ]] || return 1
    done
    [[ -f "$(unity_config_path)" ]]
}

# Puts a finished folder in place of DEST with one rename.
replace_dir() {
    local finished="$1" dest="$2"
    rm -rf "$dest"
    mv "$finished" "$dest"
}

# Fetches the Debian source package into a scratch directory with a private
# apt state (its own sources.list and lists), so the machine's apt setup is
# neither needed nor touched, then moves the finished folders into place
# (examples/ first: unity/ is what marks the fetch done), so an interrupted
# fetch leaves no half-filled third_party/unity.
fetch_unity() {
    local parent
    parent="$(dirname "$UNITY_DIR")"
    mkdir -p "$parent"
    local scratch
    scratch="$(mktemp -d "$parent/.unity-fetch.XXXXXX")"
    # shellcheck disable=SC2064  # expand now: scratch is local
    trap "rm -rf '$scratch'" EXIT

    local apt_dir="$scratch/apt"
    mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" \
        "$scratch/download" "$scratch/extract" "$scratch/unity" "$scratch/examples"
    local signed_by=""
    if [[ -r /usr/share/keyrings/debian-archive-keyring.gpg ]]; then
        signed_by="[signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] "
    fi
    echo "deb-src ${signed_by}$DEBIAN_MIRROR $DEBIAN_SUITE main" >"$apt_dir/sources.list"
    local apt_options=(
        -q -o "Dir::Etc::SourceList=$apt_dir/sources.list"
        -o Dir::Etc::SourceParts=/dev/null
        -o "Dir::State::Lists=$apt_dir/lists"
        -o "Dir::Cache=$apt_dir/cache"
    )
    if [[ "$(id -u)" == 0 ]]; then
        # The private folders are root's; apt's _apt download user cannot
        # write them and would only warn about it.
        apt_options+=(-o APT::Sandbox::User=root)
    fi

    note "fetching Unity from Debian $DEBIAN_SUITE source package $UNITY_SOURCE_PACKAGE"
    apt-get "${apt_options[@]}" update >"$scratch/apt.log" 2>&1 ||
        { cat "$scratch/apt.log" >&2; die "apt-get update for $DEBIAN_MIRROR $DEBIAN_SUITE deb-src failed"; }
    (cd "$scratch/download" &&
        apt-get "${apt_options[@]}" source --download-only "$UNITY_SOURCE_PACKAGE") \
        >"$scratch/apt.log" 2>&1 ||
        { cat "$scratch/apt.log" >&2; die "apt-get source --download-only $UNITY_SOURCE_PACKAGE failed"; }

    local tarballs=("$scratch/download/${UNITY_SOURCE_PACKAGE}_"*.orig.tar.gz)
    [[ -f "${tarballs[0]}" ]] || die "no ${UNITY_SOURCE_PACKAGE}_*.orig.tar.gz in the downloaded source package"
    local tarball="${tarballs[0]}" tarball_name
    tarball_name="$(basename "$tarball")"
    tar xzf "$tarball" -C "$scratch/extract" --wildcards '*/tests/unity/src/*' \
        '*/tests/unity/examples/unity_config.h' '*/tests/unity/release/version.info' ||
        die "$tarball_name: lacks tests/unity/{src,examples/unity_config.h,release/version.info}"
    local unity_root
    unity_root="$(find "$scratch/extract" -path '*/tests/unity/src/unity.c' | head -n 1)"
    [[ -n "$unity_root" ]] || die "$tarball_name: lacks tests/unity/src/unity.c"
    unity_root="$(dirname "$(dirname "$unity_root")")"

    local version
    version="$(tr -d '[:space:]' <"$unity_root/release/version.info")"
    [[ "$version" == "$UNITY_EXPECTED_VERSION" ]] ||
        die "$tarball_name: bundles Unity $version, expected $UNITY_EXPECTED_VERSION"

    local file
    for file in "${UNITY_FILES[@]}"; do
        [[ -f "$unity_root/src/$file" ]] || die "$tarball_name: lacks tests/unity/src/$file"
        cp "$unity_root/src/$file" "$scratch/unity/$file"
    done
    cp "$unity_root/examples/unity_config.h" "$scratch/examples/unity_config.h"
    # Unity 2.4.3's unity.h carries no version macro; keep the release note.
    cp "$unity_root/release/version.info" "$scratch/unity/version.info"
    echo "Unity $version from $tarball_name (Debian $DEBIAN_SUITE source package" \
        "$UNITY_SOURCE_PACKAGE: tests/unity/src and tests/unity/examples/unity_config.h)" \
        >"$scratch/unity/SOURCE"

    replace_dir "$scratch/examples" "$(dirname "$(unity_config_path)")"
    replace_dir "$scratch/unity" "$UNITY_DIR"
    rm -rf "$scratch"
    trap - EXIT

    note "fetched Unity $version from $tarball_name into $UNITY_DIR:"
    (cd "$parent" && sha256sum "${UNITY_FILES[@]/#/$(basename "$UNITY_DIR")/}" examples/unity_config.h) |
        sed 's/^/    /' >&2
}

ensure_unity() {
    unity_is_complete && return 0
    local lock_dir
    lock_dir="$(dirname "$UNITY_DIR")"
    mkdir -p "$lock_dir"
    # Parallel makes (or engineers) must not fetch into the same folder at once.
    exec 9>"$lock_dir/.unity-fetch.lock"
    flock 9
    unity_is_complete || fetch_unity
    exec 9>&-
}

main() {
    local mode=native cross_arch=""
    while [[ $# -gt 0 ]]; do
        case "$1" in
            --cross)
                [[ $# -ge 2 ]] || die "--cross needs an architecture (aarch64)"
                mode=cross cross_arch="$2"
                shift 2
                ;;
            --board) mode=board; shift ;;
            --fuzz) mode=fuzz; shift ;;
            --soak) mode=soak; shift ;;
            --dev) mode=dev; shift ;;
            --deb) mode=deb; shift ;;
            --unity-only) mode=unity; shift ;;
            -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; return 0 ;;
            *) die "unknown argument: $1 (see --help)" ;;
        esac
    done
    case "$mode" in
        native) ensure_native ;;
        cross) ensure_cross "$cross_arch" ;;
        board) ensure_native; ensure_cross aarch64; ensure_commands "the emulated board" "${BOARD_COMMANDS[@]}" ;;
        fuzz) ensure_native; ensure_fuzz ;;
        soak) ensure_native; ensure_commands "make soak" "${SOAK_COMMANDS[@]}" ;;
        dev) ensure_native; ensure_commands "make format, lint, coverage" "${DEV_COMMANDS[@]}" ;;
        deb) ensure_native; ensure_commands "make deb" "${DEB_COMMANDS[@]}" ;;
        unity) ;;
    esac
    ensure_unity
}

main "$@"
