#!/usr/bin/env python3
"""A window of a tile, highest point below 2.6 m, 0.2 m cells, 1 m grid (to place labels by hand).
  LABEL_WORK=DIR /usr/bin/python3 bench/real/win2.py NAME XMIN XMAX YMIN YMAX OUT.png"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
name, xa, xb, ya, yb = sys.argv[1], *map(float, sys.argv[2:6]); out = sys.argv[6]
d = np.load(os.path.join(WORK, f"{name}.npz"))
x, y, hag = d["x"], d["y"], d["hag"]
m = (x >= xa) & (x < xb) & (y >= ya) & (y < yb)
cell = 0.2
top = grid_max(x[m], y[m], hag[m], xa, ya, xb - xa, yb - ya, cell, mask=hag[m] < 2.6)
fig, ax = plt.subplots(1, 1, figsize=(14, 14 * (yb-ya)/(xb-xa)))
ax.imshow(top, origin="lower", extent=[xa, xb, ya, yb], cmap="turbo", vmin=0, vmax=2.6, interpolation="nearest")
ax.set_xticks(np.arange(np.ceil(xa), xb, 1)); ax.set_yticks(np.arange(np.ceil(ya), yb, 1)); ax.grid(True, alpha=0.3, color="w")
ax.tick_params(labelsize=7); plt.setp(ax.get_xticklabels(), rotation=90)
ax.set_xticklabels([f"{v%100:.0f}" for v in np.arange(np.ceil(xa), xb, 1)]); ax.set_yticklabels([f"{v%100:.0f}" for v in np.arange(np.ceil(ya), yb, 1)])
plt.tight_layout(); plt.savefig(out, dpi=60)
