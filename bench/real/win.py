#!/usr/bin/env python3
"""A window of a tile in four views (HAG top, under 2.4 m, points per 0.25 m cell, multi-return).
  LABEL_WORK=DIR /usr/bin/python3 bench/real/win.py NAME XMIN XMAX YMIN YMAX OUT.png"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
name, xa, xb, ya, yb = sys.argv[1], *map(float, sys.argv[2:6])
out = sys.argv[6]
d = np.load(os.path.join(WORK, f"{name}.npz"))
x, y, hag = d["x"], d["y"], d["hag"]
m = (x >= xa) & (x < xb) & (y >= ya) & (y < yb)
cell = 0.25
top = grid_max(x[m], y[m], hag[m], xa, ya, xb - xa, yb - ya, cell)
und = grid_max(x[m], y[m], hag[m], xa, ya, xb - xa, yb - ya, cell, mask=hag[m] < 2.4)
cnt = np.zeros_like(top)
ix = ((x[m]-xa)/cell).astype(int); iy=((y[m]-ya)/cell).astype(int)
ok=(ix<cnt.shape[1])&(iy<cnt.shape[0]); np.add.at(cnt,(iy[ok],ix[ok]),1)
mr = grid_max(x[m], y[m], (d["nr"][m] > 1).astype(float) + 1e-4*hag[m], xa, ya, xb - xa, yb - ya, 0.5, mask=hag[m] > 0.4)
fig, ax = plt.subplots(1, 4, figsize=(28, 9 * (yb-ya)/(xb-xa) * 1.0 + 1))
ext = [xa, xb, ya, yb]
ax[0].imshow(top, origin="lower", extent=ext, cmap="turbo", vmin=0, vmax=3); ax[0].set_title("top HAG 0-3")
ax[1].imshow(und, origin="lower", extent=ext, cmap="turbo", vmin=0, vmax=2.4); ax[1].set_title("under 2.4")
ax[2].imshow(cnt, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=6); ax[2].set_title("points per 0.25 cell")
ax[3].imshow(mr, origin="lower", extent=ext, cmap="RdYlGn_r", vmin=0, vmax=1); ax[3].set_title("multi")
for q in ax:
    q.set_xticks(np.arange(np.ceil(xa), xb, 2)); q.set_yticks(np.arange(np.ceil(ya), yb, 2)); q.grid(True, alpha=0.35); q.tick_params(labelsize=6)
    plt.setp(q.get_xticklabels(), rotation=90)
plt.tight_layout(); plt.savefig(out, dpi=55)
