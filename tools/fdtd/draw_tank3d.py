#!/usr/bin/env python3
"""Draw one random 3-D oil tank of the shared fdtd3d-var-* kind and write
its gprMax inputs and truths (exploration only: no make target, test or CI
runs this; it needs gprMax 4.0.1 from PyPI, which the project does not
install).

The ranges are the ones ../shared/data/README.md gives for the 3-D tanks,
and the layout the one their truth files' `input` shows (5 mm cells; the
winding's axis at the antennas' x + face + radius, the domain 100 mm past
its back and 100 mm either side of it across; the steel wall at x = 60-70
mm with the window from y = 40 to 760 mm; a 5 mm pressboard barrier
cylinder; a 35 mm core leg; 15 mm plates 100 mm in from the domain's sides,
the upper one's back at the winding's back, the lower one 20 mm behind the
upper one's front and 60 mm below the lower end ring; horizontal dipoles
stepped 30 mm from y = 80/120 mm; scan y = model y - 100 mm). Three scans
per tank, as there: intact, shifted by the first draw, and shifted by the
second with the spacer above the middle disk squeezed by one cell.

A 3-D scan takes 20-40 min of both cores here (run one gprMax at a time:
two at once spin-wait each other ~20x slower). Seeds 201 and 203 (8 and 7
disks) are the ones scanned: tests/fixtures/fdtd3d-fresh-*.

Usage: draw_tank3d.py SEED OUT_DIR [WHICH...]
  WHICH: 0, 1, 2 (intact, first shift, second shift squeezed); all three
  when none is given. Writes fdtd3d-fresh-sSEED-dSHIFT.in/.truth.json.
Then per scan: python -m gprMax NAME.in -n 21, and gprmax_to_uwbscan.py NAME 21.
"""
import json
import os
import random
import sys

seed = int(sys.argv[1])
out = sys.argv[2]
which = [int(w) for w in sys.argv[3:]] or [0, 1, 2]
rng = random.Random(seed)
DX = 0.005


def cells(lo, hi):
    """A uniform draw in [lo, hi] on the model's 5 mm grid."""
    return round(round(rng.uniform(lo, hi) / DX) * DX, 4)


oil = round(rng.uniform(2.14, 2.26), 3)
window_eps = round(rng.uniform(2.4, 3.2), 2)
window_w = cells(0.25, 0.36)
face = cells(0.39, 0.48)
radius = cells(0.12, 0.18)
barrier_gap = cells(0.025, 0.07)
disks = rng.randint(5, 8)
disk_h = cells(0.015, 0.025)
gap = cells(0.005, 0.01)
ring = cells(0.02, 0.04)
y1 = cells(0.20, 0.26)
clamp_above = cells(0.045, 0.2)
clamp_front = round(face + cells(-0.12, 0.0), 4)
clamp_below = rng.random() < 0.5
pulse = rng.choice(["ricker", "gaussiandotnorm"])
fc = round(rng.uniform(1.5e9, 2.2e9), -7)
first = rng.choice([-1, 1]) * 5 * rng.randint(1, 6)
second = rng.choice([-1, 1]) * 5 * rng.randint(1, 6)

X0, Y0 = 0.05, 0.10  # antenna line x; model y of the scan's y = 0
axis_x = X0 + face + radius
zc = round(radius + 0.10, 4)
dom_x, dom_z = round(axis_x + radius + 0.10, 4), round(2 * zc, 4)


def scene(shift_mm, squeeze):
    """The gprMax input and truth of one scan: the winding shifted by
    shift_mm (+ up), the spacer above the middle disk one cell thinner
    when squeeze."""
    shift = shift_mm / 1000
    lines = [
        "#title: tank3d fresh d=%d" % shift_mm,
        "#domain: %.4f 0.85 %.4f" % (dom_x, dom_z),
        "#dx_dy_dz: 0.005 0.005 0.005",
        "#time_window: 9e-9",
        "#waveform: %s 1 %.3g pulse" % (pulse, fc),
        "#material: %s 1e-9 1 0 oil" % oil,
        "#material: 4.4 1e-6 1 0 board",
        "#material: %s 0 1 0 window" % window_eps,
        "#box: 0.0600 0 0 %.4f 0.85 %.4f oil" % (dom_x, dom_z),
        "#box: 0.0600 0 0 0.0700 0.85 %.4f pec" % dom_z,
        "#box: 0.0600 0.0400 %.4f 0.0700 0.7600 %.4f window" % (zc - window_w / 2, zc + window_w / 2),
        "#cylinder: %.4f 0 %.4f %.4f 0.85 %.4f %.4f board" % (axis_x, zc, axis_x, zc, radius + barrier_gap),
        "#cylinder: %.4f 0 %.4f %.4f 0.85 %.4f %.4f oil" % (axis_x, zc, axis_x, zc, radius + barrier_gap - DX),
        "#cylinder: %.4f 0 %.4f %.4f 0.85 %.4f 0.0350 pec" % (axis_x, zc, axis_x, zc),
    ]

    def slab(lo, hi, material):
        lines.append("#cylinder: %.4f %.4f %.4f %.4f %.4f %.4f %.4f %s" %
                     (axis_x, lo, zc, axis_x, hi, zc, radius, material))

    y = Y0 + y1 + shift
    slab(y - ring, y, "board")
    bottom = y
    for i in range(disks):
        slab(y, y + disk_h, "pec")
        y += disk_h
        if i < disks - 1:
            g = gap - DX if squeeze and i == disks // 2 else gap
            slab(y, y + g, "board")
            y += g
    top = y
    slab(y, y + ring, "board")
    ring_top = Y0 + y1 + disks * disk_h + (disks - 1) * gap + ring  # the plates do not move
    lines.append("#box: %.4f %.4f 0.1000 %.4f %.4f %.4f pec" %
                 (X0 + clamp_front, ring_top + clamp_above, axis_x + radius, ring_top + clamp_above + 0.015,
                  dom_z - 0.10))
    if clamp_below:
        ring_bottom = Y0 + y1 - ring
        lines.append("#box: %.4f %.4f 0.1000 %.4f %.4f %.4f pec" %
                     (X0 + clamp_front + 0.02, ring_bottom - 0.075, axis_x + radius, ring_bottom - 0.06,
                      dom_z - 0.10))
    lines += ["#hertzian_dipole: z 0.0500 0.0800 %.4f pulse" % zc, "#rx: 0.0500 0.1200 %.4f" % zc,
              "#src_steps: 0 0.03 0", "#rx_steps: 0 0.03 0"]
    truth = {
        "y1_m": round(bottom - Y0, 4), "y2_m": round(top - Y0, 4), "z_face_m": face,
        "displacement_mm": shift_mm, "height_change_mm": -5.0 if squeeze else 0.0,
        "kind": "tank3d-family-fresh", "fc_hz": fc,
        "scene": {"seed": seed, "dx_m": DX, "oil_eps": oil, "window_eps": window_eps, "window_w_m": window_w,
                  "face_m": face, "radius_m": radius, "barrier_gap_m": barrier_gap, "disks": disks,
                  "disk_h_m": disk_h, "gap_m": gap, "ring_m": ring, "y1_m": y1, "clamp_above_m": clamp_above,
                  "clamp_front_m": clamp_front, "clamp_below": clamp_below, "pulse": pulse, "fc_hz": fc,
                  "shifts_mm": [0, first, second]},
        "input": "\n".join(lines) + "\n",
    }
    return lines, truth


os.makedirs(out, exist_ok=True)
for w in which:
    shift_mm, squeeze = [(0, False), (first, False), (second, True)][w]
    lines, truth = scene(shift_mm, squeeze)
    name = "fdtd3d-fresh-s%03d-d%+03d" % (seed, shift_mm)
    with open(os.path.join(out, name + ".in"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, name + ".truth.json"), "w") as f:
        json.dump(truth, f)
    print(name, "disks", disks, "face", face, "radius", radius, "fc", fc, "pulse", pulse,
          "plate front", round(clamp_front - face, 3), "below", clamp_below)
