#!/bin/sh
# The README's example images: the three PNGs `uwbd --replay` writes for the
# paper pair (the command the README shows), copied to tools/readme/images.
# Usage: readme-images.sh BUILD_DIR [OUT_DIR]   (make readme-images; OUT_DIR
# defaults to tools/readme/images, tests/e2e/test_readme_images.sh draws
# them into a temporary one and compares)
set -eu
build=${1:?usage: readme-images.sh BUILD_DIR [OUT_DIR]}
out=${2:-tools/readme/images}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
${UWB_EXEC_PREFIX:-} "$build/uwbd" --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
    --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --out "$tmp" >/dev/null
mkdir -p "$out"
for kind in migrated bscan comparison; do
    cp "$tmp/fdtd2d-paper-up20mm-$kind.png" "$out/paper-up20mm-$kind.png"
done
echo "readme-images: wrote $out/paper-up20mm-{migrated,bscan,comparison}.png"
