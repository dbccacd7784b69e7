#!/usr/bin/env python3
"""Draw one random 2-D oil tank exactly as draw_tank.py does (same seed,
same tank) and write its intact scan's gprMax input with deformed ones:
the winding leaning (its top disk LEAN mm nearer the antennas, each disk
its share by its centre's height, on the model's 2 mm grid) or disks
FROM..TO bulged (+ toward the antennas) or dented by MM. Exploration only
(no make target, test or CI runs this; it needs gprMax 4.0.1 from PyPI).

Its intact input is draw_tank.py's, byte for byte but the title; the
scans made from it are tests/fixtures/fdtd2d-fresh-s1*-{lean,r}*.

Usage: draw_deformed.py SEED OUT_DIR KIND...
  KIND: lean+6 (top 6 mm nearer), lean-4, r2-4+6 (disks 2-4 from the
  bottom, 6 mm nearer), r3-5-4 (dented 4 mm), intact
Each writes fdtd2d-fresh-sSEED-KIND.in/.truth.json; the truth carries the
disks' offsets and the whole input. Then per scan: python -m gprMax
NAME.in -n 21, and gprmax_to_uwbscan.py NAME 21.
"""
import json
import os
import random
import sys

seed = int(sys.argv[1])
out = sys.argv[2]
kinds = sys.argv[3:]
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


def lean_as_uwbd_reads(offsets):
    """The staircase's lean as uwbd gives it: the least-squares slope of the
    disks' offsets over their centres' heights, times the face's height
    edge to edge (mm)."""
    centres = [i * (disk_h + gap) + disk_h / 2 for i in range(disks)]
    mc, mo = sum(centres) / disks, sum(offsets) / disks
    slope = sum((c - mc) * (o - mo) for c, o in zip(centres, offsets)) / sum((c - mc) ** 2 for c in centres)
    return round(slope * (disks * disk_h + (disks - 1) * gap) * 1000, 2)


def scene(kind):
    """The gprMax input and the truth of one scan: kind as in the usage."""
    offsets = [0.0] * disks  # each disk's move toward the antennas, m
    height = disks * disk_h + (disks - 1) * gap
    if kind.startswith("lean"):
        top_mm = float(kind[4:])
        for i in range(disks):
            centre = i * (disk_h + gap) + disk_h / 2
            # the top disk's centre carries the whole lean
            offsets[i] = round(top_mm / 1000 * centre / (height - disk_h / 2) / 0.002) * 0.002
    elif kind.startswith("r"):
        lo_s, rest_s = kind[1:].split("-", 1)
        # r2-4+6 / r3-5-4: FROM-TO then a signed size
        for j, ch in enumerate(rest_s):
            if ch in "+-":
                hi_s, mm = rest_s[:j], float(rest_s[j:])
                break
        for i in range(int(lo_s) - 1, int(hi_s)):
            offsets[i] = mm / 1000
    elif kind != "intact":
        sys.exit("draw_deformed: unknown kind %s" % kind)
    lines = [
        "#title: tank family %s" % kind,
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
    y = Y0 + y1
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (x_face - offsets[0], y - ring, x_face + build, y))
    bottom = y
    for i in range(disks):
        # a disk moved toward the antennas grows at its front (its back stays on the core's side)
        lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" % (x_face - offsets[i], y, x_face + build, y + disk_h))
        y += disk_h
        if i < disks - 1:
            front = x_face - min(offsets[i], offsets[i + 1])
            lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (front, y, x_face + build, y + gap))
            y += gap
    top = y
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 board" % (x_face - offsets[-1], y, x_face + build, y + ring))
    ring_top = Y0 + y1 + disks * disk_h + (disks - 1) * gap + ring
    lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" %
                 (X0 + clamp_front, ring_top + clamp_above, plate_end, ring_top + clamp_above + 0.012))
    if clamp_below:
        ring_bottom = Y0 + y1 - ring
        lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" %
                     (X0 + clamp_front + 0.02, ring_bottom - 0.072, plate_end, ring_bottom - 0.06))
    lines += ["#hertzian_dipole: z 0.0500 0.0800 0 pulse", "#rx: 0.0500 0.1200 0",
              "#src_steps: 0 0.03 0", "#rx_steps: 0 0.03 0"]
    disk_spans = [[round(Y0 + y1 - Y0 + i * (disk_h + gap), 4), round(y1 + i * (disk_h + gap) + disk_h, 4)]
                  for i in range(disks)]
    truth = {
        "y1_m": round(bottom - Y0, 4), "y2_m": round(top - Y0, 4), "z_face_m": face,
        "displacement_mm": 0.0, "height_change_mm": 0.0,
        "kind": "tank-family-fresh-deformed", "deformation": kind, "fc_hz": fc,
        "disk_offsets_mm": [round(o * 1000, 1) for o in offsets], "disk_spans_m": disk_spans,
        "tilt_mm": lean_as_uwbd_reads(offsets) if kind.startswith("lean") else 0.0,
        "scene": {"seed": seed, "oil_eps": oil, "wall_m": wall, "window_eps": window_eps, "face_m": face,
                  "barrier_m": round(face - barrier_gap, 4), "barrier_t_m": barrier_t, "disks": disks,
                  "disk_h_m": disk_h, "gap_m": gap, "build_m": build, "ring_m": ring, "core_gap_m": core_gap,
                  "core_w_m": core_w, "y1_m": y1, "clamp_above_m": clamp_above, "clamp_front_m": clamp_front,
                  "clamp_below": clamp_below, "pulse": pulse, "fc_hz": fc},
        "input": "\n".join(lines) + "\n",
    }
    return lines, truth


os.makedirs(out, exist_ok=True)
for kind in kinds:
    lines, truth = scene(kind)
    name = "fdtd2d-fresh-s%03d-%s" % (seed, kind)
    with open(os.path.join(out, name + ".in"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, name + ".truth.json"), "w") as f:
        json.dump(truth, f)
    print(name, "disks", disks, "offsets_mm", truth["disk_offsets_mm"])
