#!/usr/bin/env python3
"""Height above ground and an overview picture of a tile.
  LABEL_WORK=DIR /usr/bin/python3 bench/real/prep.py NAME
reads DIR/raw/NAME.ply (pcd2ply of the LAZ), writes DIR/NAME.npz (x y z hag intensity returns classes source
ids gps time rgb) and DIR/pics/NAME_overview.png (HAG top, under 2.4 m, multi-return share, RGB)."""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
name = sys.argv[1]
a = read_ply(os.path.join(WORK, f"raw/{name}.ply"))
if "red" not in a.dtype.names:  # point formats without colour (LAS 1.4 format 6): black
    from numpy.lib import recfunctions as rfn
    a = rfn.append_fields(a, ["red", "green", "blue"], [np.zeros(len(a), "<u2")] * 3, usemask=False)
x, y, z = a["x"], a["y"], a["z"]
dtm = pmf_ground(x, y, z)
hag = z - dtm(x, y)
np.savez(os.path.join(WORK, f"{name}.npz"), x=x, y=y, z=z, hag=hag, i=a["intensity"], rn=a["return_number"],
         nr=a["number_of_returns"], cls=a["classification"], psid=a["point_source_id"], t=a["gps_time"],
         r=a["red"], g=a["green"], b=a["blue"])
x0, y0 = x.min(), y.min(); w, h = x.max() - x0, y.max() - y0
cell = 0.25
top = grid_max(x, y, hag, x0, y0, w, h, cell)
under = grid_max(x, y, hag, x0, y0, w, h, cell, mask=hag < 2.4)
multi = grid_max(x, y, (a["number_of_returns"] > 1).astype(float) + 0.0001 * hag, x0, y0, w, h, 0.5, mask=hag > 0.4)
rgb = np.zeros(top.shape + (3,))
ix = ((x - x0) / cell).astype(int); iy = ((y - y0) / cell).astype(int)
ok = (ix < top.shape[1]) & (iy < top.shape[0])
o = np.argsort(hag[ok])
for k, c in enumerate("rgb"):
    rgb[iy[ok][o], ix[ok][o], k] = a[{"r":"red","g":"green","b":"blue"}[c]][ok][o] / 255.0
fig, ax = plt.subplots(2, 2, figsize=(20, 20))
ext = [x0, x0 + w, y0, y0 + h]
ax[0,0].imshow(top, origin="lower", extent=ext, cmap="viridis", vmin=0, vmax=3); ax[0,0].set_title("HAG top 0-3 m")
ax[0,1].imshow(under, origin="lower", extent=ext, cmap="viridis", vmin=0, vmax=2.4); ax[0,1].set_title("under 2.4 m")
ax[1,0].imshow(multi, origin="lower", extent=ext, cmap="RdYlGn_r", vmin=0, vmax=1); ax[1,0].set_title("multi-return top >0.4")
ax[1,1].imshow(np.clip(rgb * 1.0, 0, 1), origin="lower", extent=ext); ax[1,1].set_title("RGB of highest point")
for q in ax.flat: q.grid(True, alpha=0.3)
plt.tight_layout(); plt.savefig(os.path.join(WORK, f"pics/{name}_overview.png"), dpi=50)
print(name, len(x), "bbox", w, h, "rgb max", a["red"].max(), "classes", np.unique(a["classification"], return_counts=True))
