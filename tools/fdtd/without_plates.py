#!/usr/bin/env python3
"""Write a gprMax input with a tank's clamp plates left out (and with
`bare`, its barrier and core leg too): the control scenes that tell what a
plate does to a pair's figure (README, "Fresh draws"). Exploration only.

Usage: without_plates.py IN.in np|bare OUT.in
"""
import sys
from collections import Counter

if len(sys.argv) != 4 or sys.argv[2] not in ("np", "bare"):
    sys.exit("usage: without_plates.py IN.in np|bare OUT.in")
source, mode, target = sys.argv[1:4]
lines = open(source).read().splitlines()
# The winding's boxes share one x0 (its face), more boxes than any other.
winding_x = Counter(l.split()[1] for l in lines if l.startswith("#box")).most_common(1)[0][0]
kept = []
for line in lines:
    if line.startswith("#box"):
        f = line.split()
        x0, y0, y1, material = f[1], f[2], f[5], f[7]
        full_height = y0 == "0.0000" and y1 == "0.9000"
        wall = x0 == "0.0600"
        plate = material == "pec" and not full_height and x0 != winding_x and not wall
        core = material == "pec" and full_height and not wall
        barrier = material == "board" and full_height
        if plate or (mode == "bare" and (core or barrier)):
            continue
    kept.append(line)
open(target, "w").write("\n".join(kept) + "\n")
