#!/usr/bin/env python3
"""Blobs of the under-canopy grid (0.25 m cells, HAG 0.9-2.4 m, 1.5-40 m^2): a list so that no candidate is missed.
  LABEL_WORK=DIR /usr/bin/python3 bench/real/cands.py NAME   ->  DIR/NAME.blobs.json"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
name = sys.argv[1]
d = np.load(os.path.join(WORK, f"{name}.npz"))
x, y, hag = d["x"], d["y"], d["hag"]
x0, y0 = x.min(), y.min(); w, h = x.max() - x0, y.max() - y0
cell = 0.25
und = grid_max(x, y, hag, x0, y0, w, h, cell, mask=hag < 2.4)
m = (und > 0.9)
lab, n = ndimage.label(m, structure=np.ones((3, 3)))
out = []
for k, sl in enumerate(ndimage.find_objects(lab), 1):
    area = (lab[sl] == k).sum() * cell * cell
    if area < 1.5 or area > 40: continue
    iy, ix = np.nonzero(lab == k)
    cx, cy = x0 + (ix.mean() + .5) * cell, y0 + (iy.mean() + .5) * cell
    out.append(dict(id=len(out) + 1, x=round(cx, 2), y=round(cy, 2), area=round(area, 2)))
json.dump(out, open(os.path.join(WORK, f"{name}.blobs.json"), "w"), indent=0)
print(len(out), "blobs")
