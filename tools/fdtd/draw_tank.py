#!/usr/bin/env python3
"""Draw one random 2-D oil tank of the shared family's kind and write its
gprMax inputs and truths (exploration only: no make target, test or CI
runs this; it needs gprMax 4.0.1 from PyPI, which the project does not
install).

The ranges are the ones ../shared/data/README.md gives for the
fdtd2d-var-* family, and the layout (2 mm cells, 0.9 m domain, antennas
at x = 0.05 m stepped 30 mm from y = 0.08/0.12 m, scan y = model y - 0.10
m, the second plate 60 mm below the lower end ring and 20 mm behind the
upper one's front) the one its truth files' `input` shows, so a draw here
is another member of that family. Three scans per tank, as there: intact,
shifted by the first draw, and shifted by the second with the spacer below
the middle disk squeezed by 2 mm. Each truth file carries the scene and
the whole gprMax input.

Usage: draw_tank.py SEED OUT_DIR   (writes fdtd2d-fresh-sSEED-dSHIFT.in/.truth.json)
Then per scan: python -m gprMax NAME.in -n 21, and gprmax_to_uwbscan.py NAME 21.
"""
import json
import os
import random
import sys

seed = int(sys.argv[1])
out = sys.argv[2]
rng = random.Random(seed)


def cells(lo, hi, step=0.002):
    """A uniform draw in [lo, hi] on the model's 2 mm grid."""
    return round(round(rng.uniform(lo, hi) / step) * step, 4)


oil = round(rng.uniform(2.14, 2.26), 3)
wall = cells(0.008, 0.016)
window_eps = round(rng.uniform(2.4, 3.2), 2)
face = cells(0.39, 0.49)
barrier_gap = cells(0.025, 0.08)
barrier_t = cells(0.004, 0.008)
disks = rng.randint(5, 8)
disk_h = cells(0.014, 0.024)
gap = cells(0.004, 0.008)
build = cells(0.05, 0.10)
ring = cells(0.024, 0.044)
core_gap = cells(0.02, 0.07)
core_w = cells(0.10, 0.13)
y1 = cells(0.20, 0.26)
clamp_above = cells(0.045, 0.2)
clamp_front = round(face + cells(-0.16, 0.01), 4)
clamp_below = rng.random() < 0.5
pulse = rng.choice(["ricker", "gaussiandotnorm"])
fc = round(rng.uniform(1.8e9, 2.6e9), -7)
first = rng.choice([-1, 1]) * 2 * rng.randint(1, 15)
second = rng.choice([-1, 1]) * 2 * rng.randint(1, 15)

X0, Y0 = 0.05, 0.10  # antenna line x; model y of the scan's y = 0
x_face = X0 + face
x_core = x_face + build + core_gap
plate_end = round(x_core + cells(0.05, core_w), 4)


def scene(shift_mm, squeeze):
    lines = [
        "#title: tank family d=%d" % shift_mm,
        "#domain: 0.90 0.90 0.002",
        "#dx_dy_dz: 0.002 0.002 0.002",
        "#time_window: 11e-9",
        "#waveform: %s 1 %.3g pulse" % (pulse, fc),
        "#material: %s 1e-9 1 0 oil" % oil,
        "#material: 4.4 1e-6 1 0 board",
        "#material: %s 0 1 0 window" % window_eps,
        "#box: 0.0600 0.0000 0 0.9000 0.9000 0.002 oil",
        "#box: 0.0600 0.0000 0 %.4f 0.9000 0.002 pec" % (0.06 + wall),
        "#box: 0.0600 0.0200 0 %.4f 0.8000 0.002 window" % (0.06 + wall),
        "#box: %.4f 0.0000 0 %.4f 0.9000 0.002 board" % (x_face - barrier_gap, x_face - barrier_gap + barrier_t),
        "#box: %.4f 0.0000 0 %.4f 0.9000 0.002 pec" % (x_core, x_core + core_w),
    ]
    y = Y0 + y1 + shift_mm / 1000.0
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (x_face, y - ring, x_face + build, y))
    bottom = y
    for i in range(disks):
        lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" % (x_face, y, x_face + build, y + disk_h))
        y += disk_h
        if i < disks - 1:
            spacer = gap - (0.002 if squeeze and i == disks // 2 - 1 else 0.0)
            lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (x_face, y, x_face + build, y + spacer))
            y += spacer
    top = y
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (x_face, y, x_face + build, y + ring))
    # The clamp plates stay where the intact winding put them.
    ring_top = Y0 + y1 + disks * disk_h + (disks - 1) * gap + ring
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" %
                 (X0 + clamp_front, ring_top + clamp_above, plate_end, ring_top + clamp_above + 0.012))
    if clamp_below:
        ring_bottom = Y0 + y1 - ring
        lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" %
                     (X0 + clamp_front + 0.02, ring_bottom - 0.072, plate_end, ring_bottom - 0.06))
    lines += ["#hertzian_dipole: z 0.0500 0.0800 0 pulse", "#rx: 0.0500 0.1200 0",
              "#src_steps: 0 0.03 0", "#rx_steps: 0 0.03 0"]
    truth = {
        "y1_m": round(bottom - Y0, 4), "y2_m": round(top - Y0, 4), "z_face_m": face,
        "displacement_mm": shift_mm, "height_change_mm": -2.0 if squeeze else 0.0,
        "kind": "tank-family-fresh", "fc_hz": fc,
        "scene": {"seed": seed, "oil_eps": oil, "wall_m": wall, "window_eps": window_eps, "face_m": face,
                  "barrier_m": round(face - barrier_gap, 4), "barrier_t_m": barrier_t, "disks": disks,
                  "disk_h_m": disk_h, "gap_m": gap, "build_m": build, "ring_m": ring, "core_gap_m": core_gap,
                  "core_w_m": core_w, "y1_m": y1, "clamp_above_m": clamp_above, "clamp_front_m": clamp_front,
                  "clamp_below": clamp_below, "pulse": pulse, "fc_hz": fc, "shifts_mm": [0, first, second]},
        "input": "\n".join(lines) + "\n",
    }
    return lines, truth


os.makedirs(out, exist_ok=True)
for shift, squeeze in ((0, False), (first, False), (second, True)):
    lines, truth = scene(shift, squeeze)
    name = "fdtd2d-fresh-s%03d-d%+03d" % (seed, shift)
    with open(os.path.join(out, name + ".in"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, name + ".truth.json"), "w") as f:
        json.dump(truth, f)
    print(name)
