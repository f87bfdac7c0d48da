#!/usr/bin/env python3
"""The labels picture: the tile from above (HAG of the highest point; highest point below 2.4 m) with every label.
  LABEL_WORK=DIR /usr/bin/python3 bench/real/labelpic.py NAME TRUTH.json OUT.png"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
name, truth, out = sys.argv[1:4]
d = np.load(os.path.join(WORK, f"{name}.npz")); x, y, hag = d["x"], d["y"], d["hag"]
T = json.load(open(truth)); x0, y0 = T["origin"]; w, h = T["extent"]
fig, ax = plt.subplots(1, 2, figsize=(22, 11))
for q, g, t in [(ax[0], grid_max(x, y, hag, x0, y0, w, h, 0.25), "highest point HAG 0-3 m"),
                (ax[1], grid_max(x, y, hag, x0, y0, w, h, 0.25, mask=hag < 2.4), "highest point below 2.4 m")]:
    q.imshow(g, origin="lower", extent=[x0, x0 + w, y0, y0 + h], cmap="viridis", vmin=0, vmax=3); q.set_title(t)
    for v in T["vehicles"]:
        fp = np.array(v["footprint"] + [v["footprint"][0]])
        q.plot(fp[:, 0], fp[:, 1], "w-", lw=1.2)
        q.text(v["pose"]["x"], v["pose"]["y"], f"{v['instance']}{'' if v['visibility']=='clear' else v['visibility'][0]}", color="w", fontsize=9, ha="center", va="center")
    for u in T["uncertain"]:
        fp = np.array(u["footprint"] + [u["footprint"][0]])
        q.plot(fp[:, 0], fp[:, 1], "m--", lw=1.2); q.text(u["pose"]["x"], u["pose"]["y"], u["id"], color="m", fontsize=9)
plt.suptitle(f"{T['scene']}: {len(T['vehicles'])} vehicles (p partial, o occluded, no letter clear), {len(T['uncertain'])} uncertain")
plt.tight_layout(); plt.savefig(out, dpi=60)
try:  # a 64-colour palette: a third of the size, for pictures kept in the repository
    from PIL import Image
    Image.open(out).convert("RGB").quantize(64).save(out, optimize=True)
except ImportError:
    pass
