#!/usr/bin/env bash
# make demo: the main job on data the project ships or makes. Replays the
# full-wave FDTD pair (intact, +20 mm), then, with the simulator, a 3-D tank
# scene with clutter and noise: a baseline and the winding moved up 12 mm.
set -euo pipefail
BUILD=${UWB_BUILD_DIR:-${1:-build}}
OUT=${UWB_DEMO_OUT:-$BUILD/demo}
mkdir -p "$OUT"

show() {   # label, verdict line
    python3 - "$1" "$2" <<'PY'
import json, sys
label, v = sys.argv[1], json.loads(sys.argv[2])
print(f"== {label}")
if "axial_displacement_mm" in v:
    print(f"   status {v['status'].upper()}: displacement {v['axial_displacement_mm']:+.2f} ± {v['uncertainty_mm']:.2f} mm "
          f"(edges {v['lower_edge_mm']:.1f}..{v['upper_edge_mm']:.1f} mm, baseline "
          f"{v['baseline']['lower_edge_mm']:.1f}..{v['baseline']['upper_edge_mm']:.1f} mm)")
else:
    print(f"   status {v['status'].upper()}: {v.get('reason', '')}")
for p in v.get("images", []):
    print(f"   image: {p}")
PY
}

echo "uwbd demo: verdict lines are printed as JSON, then summarised."
line=$("$BUILD/uwbd" --replay tests/fixtures/fdtd2d-paper-up20mm.uwbscan \
       --baseline tests/fixtures/fdtd2d-paper-intact.uwbscan --out "$OUT/fdtd")
echo "$line"
show "full-wave FDTD scan of the paper's experiment, winding moved up 20 mm" "$line"

if [[ -x "$BUILD/uwbsim" ]]; then
    "$BUILD/uwbsim" --seed 1 -o "$OUT/sim-baseline.uwbscan" --truth "$OUT/sim-baseline.truth.json"
    "$BUILD/uwbsim" --seed 2 --displacement-m 0.012 -o "$OUT/sim-up12mm.uwbscan" --truth "$OUT/sim-up12mm.truth.json"
    line=$("$BUILD/uwbd" --replay "$OUT/sim-up12mm.uwbscan" --baseline "$OUT/sim-baseline.uwbscan" --out "$OUT/sim")
    echo "$line"
    show "simulated 3-D tank (oil, clutter, noise), winding moved up 12 mm" "$line"
fi
