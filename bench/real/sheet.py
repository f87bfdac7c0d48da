#!/usr/bin/env python3
"""Contact sheet: per object a 12 m top view (with its footprint if given) and side views along and across.
  LABEL_WORK=DIR /usr/bin/python3 bench/real/sheet.py NAME OBJECTS.json OUT.png
OBJECTS.json: a list of {x, y[, heading][, footprint][, band][, tag]} (e.g. measure.py output). LABEL_DPI (default 45)
sets the picture's resolution."""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
name, objs_path, out = sys.argv[1], sys.argv[2], sys.argv[3]
d = np.load(os.path.join(WORK, f"{name}.npz"))
x, y, hag, nr = d["x"], d["y"], d["hag"], d["nr"]
objs = json.load(open(objs_path))
R = 6.0
fig, axes = plt.subplots(len(objs), 3, figsize=(15, 4.2 * len(objs)))
axes = np.atleast_2d(axes)
for row, o in zip(axes, objs):
    cx, cy = o["x"], o["y"]
    m = (np.abs(x - cx) < R) & (np.abs(y - cy) < R)
    X, Y, H, M = x[m], y[m], hag[m], nr[m] > 1
    # heading: given, else from points 0.8-2.4 m within 3 m via PCA
    if "heading" in o: a = math.radians(o["heading"])
    else:
        s = (H > 0.8) & (H < 2.4) & (np.hypot(X - cx, Y - cy) < 2.8)
        if s.sum() > 5:
            P = np.c_[X[s] - X[s].mean(), Y[s] - Y[s].mean()]
            ev, evec = np.linalg.eigh(P.T @ P); v = evec[:, 1]; a = math.atan2(v[1], v[0])
        else: a = 0.0
    c, s_ = math.cos(a), math.sin(a)
    u = (X - cx) * c + (Y - cy) * s_; v = -(X - cx) * s_ + (Y - cy) * c
    top = grid_max(X, Y, H, cx - R, cy - R, 2 * R, 2 * R, 0.2, mask=H < 3.5)
    row[0].imshow(top, origin="lower", extent=[cx - R, cx + R, cy - R, cy + R], cmap="turbo", vmin=0, vmax=3)
    row[0].plot([cx - 4 * c, cx + 4 * c], [cy - 4 * s_, cy + 4 * s_], "w--", lw=0.7)
    if "footprint" in o:
        fp = np.array(o["footprint"] + [o["footprint"][0]]); row[0].plot(fp[:, 0], fp[:, 1], "w-", lw=1.2)
    row[0].set_title(f"{o.get('tag', o.get('id'))} ({cx:.1f},{cy:.1f}) hd {math.degrees(a)%180:.0f}", fontsize=9)
    band = o.get("band", 1.1)
    for q, (A, B, lab_) in zip(row[1:], [(u, v, "along"), (v, u, "across")]):
        sel = (np.abs(B) < band) & (np.abs(A) < R) & (H < 4)
        q.scatter(A[sel & ~M], H[sel & ~M], s=3, c="k"); q.scatter(A[sel & M], H[sel & M], s=3, c="r")
        q.set_xlim(-R, R); q.set_ylim(-0.3, 3.5); q.set_aspect("equal"); q.grid(True, alpha=0.4)
        q.set_title(f"{lab_} (band ±{band} m) n={sel.sum()}", fontsize=9)
plt.tight_layout(); plt.savefig(out, dpi=int(os.environ.get("LABEL_DPI", 45)))
