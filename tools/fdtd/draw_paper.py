#!/usr/bin/env python3
"""Write gprMax inputs and truths of the paper's scene (../shared/data's
fdtd2d-paper-*: 2-D, 2 mm cells, air; six PEC disks 22 mm tall with 4 mm
air gaps, 300 mm deep, front face 450 mm from the antennas; Ricker 2 GHz;
line source and receiver 40 mm apart), intact or with disks bulged toward
the antennas or dented away. The shared pair's truth gives the scene, not
its input: the layout here is the fresh family's (antennas at x = 50 mm
stepped 30 mm from y = 80/120 mm, scan y = model y - 100 mm, 0.9 m domain,
8 ns); its intact scan is the shared one's, sample for sample (checked:
relative difference 0), and is the deformed ones' baseline.
Exploration only (no make target, test or CI runs this; it needs gprMax
4.0.1 from PyPI).

Usage: draw_paper.py OUT_DIR KIND...
  KIND: intact, r1-3+8 (disks 1-3 from the bottom 8 mm nearer), r3-5-6
  (dented 6 mm); writes fdtd2d-paperscene-KIND.in/.truth.json.
Then per scan: python -m gprMax NAME.in -n 21, and gprmax_to_uwbscan.py NAME 21.
"""
import json
import os
import sys

out = sys.argv[1]
kinds = sys.argv[2:]
DISKS, DISK_H, GAP, DEPTH, FACE, Y1, FC = 6, 0.022, 0.004, 0.300, 0.45, 0.23, 2e9
X0, Y0 = 0.05, 0.10  # antenna line x; model y of the scan's y = 0


def scene(kind):
    """The gprMax input and the truth of one scan: kind as in the usage."""
    offsets = [0.0] * DISKS  # each disk's move toward the antennas, m
    if kind.startswith("r"):
        lo_s, rest_s = kind[1:].split("-", 1)
        for j, ch in enumerate(rest_s):
            if ch in "+-":
                hi_s, mm = rest_s[:j], float(rest_s[j:])
                break
        for i in range(int(lo_s) - 1, int(hi_s)):
            offsets[i] = mm / 1000
    elif kind != "intact":
        sys.exit("draw_paper: unknown kind %s" % kind)
    x_face = X0 + FACE
    lines = [
        "#title: paper scene %s" % kind,
        "#domain: 0.90 0.90 0.002",
        "#dx_dy_dz: 0.002 0.002 0.002",
        "#time_window: 8e-9",
        "#waveform: ricker 1 %.3g pulse" % FC,
    ]
    y = Y0 + Y1
    for i in range(DISKS):
        # a disk moved toward the antennas grows at its front (its back stays)
        lines.append("#box: %.4f %.4f 0 %.4f %.4f 0.002 pec" % (x_face - offsets[i], y, x_face + DEPTH, y + DISK_H))
        y += DISK_H + GAP
    lines += ["#hertzian_dipole: z 0.0500 0.0800 0 pulse", "#rx: 0.0500 0.1200 0",
              "#src_steps: 0 0.03 0", "#rx_steps: 0 0.03 0"]
    spans = [[round(Y1 + i * (DISK_H + GAP), 4), round(Y1 + i * (DISK_H + GAP) + DISK_H, 4)] for i in range(DISKS)]
    truth = {
        "y1_m": Y1, "y2_m": round(Y1 + DISKS * DISK_H + (DISKS - 1) * GAP, 4), "z_face_m": FACE,
        "displacement_mm": 0.0, "height_change_mm": 0.0, "kind": "paper-scene-deformed", "deformation": kind,
        "fc_hz": FC, "disk_offsets_mm": [round(o * 1000, 1) for o in offsets], "disk_spans_m": spans,
        "tilt_mm": 0.0, "scene": {"pulse": "ricker", "fc_hz": FC, "header_eps_r": 1.0}, "input": "\n".join(lines) + "\n",
    }
    return lines, truth


os.makedirs(out, exist_ok=True)
for kind in kinds:
    lines, truth = scene(kind)
    name = "fdtd2d-paperscene-%s" % kind
    with open(os.path.join(out, name + ".in"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, name + ".truth.json"), "w") as f:
        json.dump(truth, f)
    print(name, "offsets_mm", truth["disk_offsets_mm"])
