#!/usr/bin/env python3
"""Write gprMax inputs and truths of the shared tank (../shared/data's
fdtd2d-tank-*) with disks bulged toward the antennas or dented away, as
its fdtd2d-tank-radial-* scans are: the intact scan's input, taken from
its truth file, with the disks FROM..TO and the spacers between them
moved MM nearer (+) or farther (-), the whole winding shifted by SHIFT mm
(+ up) when given. Exploration only (no make target, test or CI runs this;
it needs gprMax 4.0.1 from PyPI).

Usage: draw_tank_radial.py DATA_DIR OUT_DIR KIND...
  KIND: r2-4+4 (disks 2-4 from the bottom, 4 mm nearer), r3-5-6 (dented
  6 mm), r4-5+6-d+10 (and the winding 10 mm up); writes
  fdtd2d-tankfresh-radial-KIND.in/.truth.json, the truth in the shared
  radial truths' form. Then per scan: python -m gprMax NAME.in -n 21, and
  gprmax_to_uwbscan.py NAME 21.
"""
import json
import os
import re
import sys

data, out, kinds = sys.argv[1], sys.argv[2], sys.argv[3:]
Y0 = 0.10  # model y of the scan's y = 0
with open(os.path.join(data, "fdtd2d-tank-d+00.0.truth.json")) as f:
    intact = json.load(f)
lines = intact["input"].splitlines()
BOX = re.compile(r"#box: ([0-9.]+) ([0-9.]+) 0 ([0-9.]+) ([0-9.]+) 0.002 (pec|board)$")
# The winding: the run of pec/board boxes sharing the disks' back (x1),
# end ring to end ring; its disks are the pec ones.
winding = [i for i, line in enumerate(lines) if BOX.match(line) and float(BOX.match(line).group(3)) == 0.55]
disks = [i for i in winding if BOX.match(lines[i]).group(5) == "pec"]
# The pulse, which gprmax_to_uwbscan.py times the scan's t0 by.
PULSE = next(line.split()[1] for line in lines if line.startswith("#waveform:"))


def scene(kind):
    m = re.fullmatch(r"r(\d+)-(\d+)([+-]\d+)(?:-d([+-]\d+))?", kind)
    lo, hi, mm, shift_mm = int(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4) or 0)
    first, last = disks[lo - 1], disks[hi - 1]
    result = list(lines)
    result[0] = "#title: winding tankdev %s" % kind
    for i in winding:
        g = BOX.match(lines[i])
        x0, y0, x1, y1, material = float(g.group(1)), float(g.group(2)), float(g.group(3)), float(g.group(4)), g.group(5)
        if first <= i <= last:
            x0 -= mm / 1000
        y0 += shift_mm / 1000
        y1 += shift_mm / 1000
        result[i] = "#box: %.4f %.4f 0 %.4f %.4f 0.002 %s" % (x0, y0, x1, y1, material)
    spans = [(float(BOX.match(lines[i]).group(2)) + shift_mm / 1000 - Y0,
              float(BOX.match(lines[i]).group(4)) + shift_mm / 1000 - Y0) for i in disks]
    truth = {
        "y1_m": round(spans[0][0], 4), "y2_m": round(spans[-1][1], 4), "z_face_m": intact["z_face_m"],
        "displacement_mm": shift_mm,
        "radial": [{"disks": [lo, hi], "y_from_m": round(spans[lo - 1][0], 4),
                    "y_to_m": round(spans[hi - 1][1], 4), "change_mm": float(mm)}],
        "disk_front_mm": [float(mm) if lo <= k + 1 <= hi else 0.0 for k in range(len(disks))],
        "kind": "tankdev-fresh", "fc_hz": intact["fc_hz"],
        "scene": {"pulse": PULSE, "fc_hz": intact["fc_hz"]}, "input": "\n".join(result) + "\n",
    }
    return result, truth


os.makedirs(out, exist_ok=True)
for kind in kinds:
    result, truth = scene(kind)
    name = "fdtd2d-tankfresh-radial-" + kind
    with open(os.path.join(out, name + ".in"), "w") as f:
        f.write("\n".join(result) + "\n")
    with open(os.path.join(out, name + ".truth.json"), "w") as f:
        json.dump(truth, f)
    print(name, truth["radial"], "disk fronts", truth["disk_front_mm"])
