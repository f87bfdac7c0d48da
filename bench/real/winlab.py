#!/usr/bin/env python3
"""A window of a tile from above, highest point below CUT (2.4 m) in CELL (0.2 m) cells, a 1 m grid (labels: metres
mod 100) and, when given, the objects of a measure.py output (footprint and tag) inside the window: to place search
boxes by hand and check the measured rectangles.
  LABEL_WORK=DIR [CELL=0.2] [CUT=2.4] /usr/bin/python3 bench/real/winlab.py NAME XMIN XMAX YMIN YMAX OUT.png [MEAS.json]"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
name, xa, xb, ya, yb, out = sys.argv[1], *map(float, sys.argv[2:6]), sys.argv[6]
d = np.load(os.path.join(WORK, f"{name}.npz")); x, y, hag = d["x"], d["y"], d["hag"]
m = (x >= xa) & (x < xb) & (y >= ya) & (y < yb); cell = float(os.environ.get("CELL", 0.2))
g = grid_max(x[m], y[m], hag[m], xa, ya, xb - xa, yb - ya, cell, mask=hag[m] < float(os.environ.get("CUT", 2.4)))
s = 18 / max(xb - xa, yb - ya)
fig, ax = plt.subplots(1, 1, figsize=((xb - xa) * s + 0.5, (yb - ya) * s + 0.3))
ax.imshow(g, origin="lower", extent=[xa, xb, ya, yb], cmap="turbo", vmin=0, vmax=2.4, interpolation="nearest")
tx = np.arange(np.ceil(xa), xb, 1); ty = np.arange(np.ceil(ya), yb, 1)
ax.set_xticks(tx); ax.set_yticks(ty); ax.grid(True, alpha=0.4, color="w", lw=0.5)
ax.set_xticklabels([f"{v % 100:.0f}" for v in tx], fontsize=7); ax.set_yticklabels([f"{v % 100:.0f}" for v in ty], fontsize=7)
if len(sys.argv) > 7:
    for o in [o for o in json.load(open(sys.argv[7])) if xa < o["x"] < xb and ya < o["y"] < yb]:
        if "footprint" in o:
            fp = np.array(o["footprint"] + [o["footprint"][0]]); ax.plot(fp[:, 0], fp[:, 1], "w-", lw=1)
        ax.text(o["x"], o["y"], o["tag"], color="w", fontsize=8)
ax.set_xlim(xa, xb); ax.set_ylim(ya, yb)
plt.tight_layout(); plt.savefig(out, dpi=60)
