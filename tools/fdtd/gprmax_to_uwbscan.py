#!/usr/bin/env python3
"""Merge a gprMax 4 B-scan (NAME1.h5 .. NAMEk.h5, one per antenna position,
from `python -m gprMax NAME.in -n k`) into NAME.uwbscan, with the header the
shared family's scans carry (2-D or 3-D, by the truth's kind): 30 mm steps from y = 0, the antennas 20 mm
either side of the reference point, eps_r 2.2 (the header's, not the oil's
true one; the truth's scene.header_eps_r where it has one: 1.0 in air), and t0 the pulse's own delay in gprMax (Ricker sqrt(2)/fc, the
Gaussian derivatives 1/fc), read from NAME.truth.json. Removes the .h5
files it merged. Exploration only (needs h5py and numpy, which come with
gprMax); no make target, test or CI runs this.

Usage: gprmax_to_uwbscan.py NAME POSITIONS
"""
import json
import os
import sys

import h5py
import numpy as np

name, positions = sys.argv[1], int(sys.argv[2])
truth = json.load(open(name + ".truth.json"))
fc = truth["fc_hz"]
t0 = -(2 ** 0.5) / fc if truth["scene"]["pulse"] == "ricker" else -1.0 / fc
traces, dt = [], None
for i in range(1, positions + 1):
    with h5py.File("%s%d.h5" % (name, i), "r") as f:
        dt = float(f.attrs["dt"])
        traces.append(np.asarray(f["rxs"]["rx1"]["Ez"], dtype="<f4"))
header = {"format": "uwbscan/1", "positions": positions, "samples": len(traces[0]), "sample_interval_s": dt,
          "t0_s": t0, "antenna_y_m": [round(0.03 * i, 4) for i in range(positions)], "tx_m": [-0.02, 0.0],
          "rx_m": [0.02, 0.0], "eps_r": truth["scene"].get("header_eps_r", 2.2),
          "source": "gprMax 4.0.1 %s FDTD" % ("3-D" if truth["kind"].startswith("tank3d") else "2-D"), "comment": "synthetic"}
with open(name + ".uwbscan.part", "wb") as out:
    out.write(json.dumps(header, separators=(",", ":")).encode() + b"\n")
    for trace in traces:
        out.write(trace.tobytes())
os.replace(name + ".uwbscan.part", name + ".uwbscan")
for i in range(1, positions + 1):
    os.remove("%s%d.h5" % (name, i))
print(name, len(traces[0]), dt)
