#!/usr/bin/env python3
"""Write the scene-truth file (canopy.scene_truth v1, the conventions of docs/decisions/real-tiles.md) from
measure.py output and the hand decisions {"_source": ...[, "_labelled_by": ..., "_method": ...],
"<tag>": {visibility, model, note}}; canopy_cover is measured (cells more than 0.5 m above H and above 2.3 m), and an
unset visibility is clear below 0.15, partial below 0.7, else occluded. Coordinates are said to be RD New unless the
decisions give "_coordinates" (the sentence to write instead).
  LABEL_WORK=DIR /usr/bin/python3 bench/real/finalize.py NAME MEAS.json DECISIONS.json SCENE OUT.truth.json"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
name, meas, decisions, scene, out = sys.argv[1:6]
d = np.load(os.path.join(WORK, f"{name}.npz"))
x, y, hag = d["x"], d["y"], d["hag"]
M = json.load(open(meas)); D = json.load(open(decisions))
def cover(o):
    fp = np.array(o["footprint"]); xa, ya = fp.min(0); xb, yb = fp.max(0)
    m = (x >= xa) & (x < xb) & (y >= ya) & (y < yb)
    g = grid_max(x[m], y[m], hag[m], xa, ya, xb - xa, yb - ya, 0.25)
    cx = xa + (np.arange(g.shape[1]) + .5) * .25; cy = ya + (np.arange(g.shape[0]) + .5) * .25
    X, Y = np.meshgrid(cx, cy)
    from matplotlib.path import Path
    inside = Path(fp).contains_points(np.c_[X.ravel(), Y.ravel()]).reshape(X.shape)
    thr = max(o["H"] + 0.5, 2.3)
    v = g[inside]; v = v[~np.isnan(v)]
    return float((v > thr).mean()) if len(v) else 0.0
def ccw(fp):
    a = 0
    for i in range(4): a += fp[i][0] * fp[(i + 1) % 4][1] - fp[(i + 1) % 4][0] * fp[i][1]
    return fp if a > 0 else fp[::-1]
veh, unc = [], []
for o in M:
    dd = D.get(o["tag"], {})
    fp = [[round(p[0], 2), round(p[1], 2)] for p in ccw(o["footprint"])]
    if o.get("kind") == "unc":
        unc.append(dict(id=o["tag"], pose=dict(x=round(o["x"], 2), y=round(o["y"], 2), z=round(o["ground"], 2), heading=o["heading"]),
                        size=[o["L"], o["W"], o["H"]], footprint=fp, points=o["points"], note=dd.get("note", "")))
        continue
    cv = round(cover(o), 2)
    vis = dd.get("visibility", "clear")
    if vis == "clear" and cv >= 0.15: vis = "partial" if cv < 0.7 else "occluded"
    model = dd.get("model") or ("van" if (o["H"] >= 1.95 or o["L"] > 5.3) else "car")
    veh.append(dict(instance=int(o["tag"]), model=model,
                    pose=dict(x=round(o["x"], 2), y=round(o["y"], 2), z=round(o["ground"], 2), heading=o["heading"], pitch=0, roll=0),
                    size=[o["L"], o["W"], o["H"]], footprint=fp, canopy_cover=0.0 if vis == "clear" else cv,
                    visibility=vis, points=o["points"], note=dd.get("note", "")))
xmin, ymin, xmax, ymax = float(x.min()), float(y.min()), float(x.max()), float(y.max())
T = {"format": "canopy.scene_truth", "version": 1,
     "provenance": {"labelled_by": D.get("_labelled_by", "hand, canopy session 2026-12-05 (stop 47)"),
                    "method": D.get("_method", "docs/decisions/real-tiles.md (\"A development tile from another survey (stop 47)\")"),
                    "source": D.get("_source", ""),
                    "decoding": "canopy pcd2ply (LAZ -> PLY), read with numpy"},
     "scene": scene, "extent": [round(xmax - xmin, 3), round(ymax - ymin, 3)], "origin": [round(xmin, 3), round(ymin, 3)],
     "coordinates": D.get("_coordinates", "pose x y and footprints in the file's coordinates (RD New, EPSG:28992, metres, as in the LAS); z = ground height under the centre; heading in degrees counter-clockwise from +x along the long axis, in [0, 180): front and back are not known"),
     "vehicles": veh, "uncertain": unc}
json.dump(T, open(out, "w"), indent=1)
from collections import Counter
print(scene, len(veh), Counter(v["visibility"] for v in veh), Counter(v["model"] for v in veh), "unc", len(unc))
for v in veh: print(v["instance"], v["model"], v["visibility"], v["canopy_cover"], v["points"], v["size"], v["note"][:50])
