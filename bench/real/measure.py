#!/usr/bin/env python3
"""Measure hand-placed vehicles: per seed {tag, x, y, heading[, hl, hw, cut, lo, tol, kind]} the points with HAG in
[lo 0.3, cut 2.4] inside the oriented search box (half length hl 3.0, half width hw 1.25) give the minimum-area
rectangle (heading held within +-tol 10 deg of the seed), H = 98th percentile of HAG, the ground z under the
centre, the points, the multi-return share. kind "unc" marks an uncertain object. "hole": true (dropouts: a car whose
roof and body returned almost nothing) fits the rectangle to the hole in the ground returns instead: the 0.2 m cells of
the search box with no point below HAG 0.25, opened with a 3 x 3 window (drops the single empty cells of the ground's
sampling), largest connected piece, plus the object's returns; H and points are still those of the returns.
  LABEL_WORK=DIR /usr/bin/python3 bench/real/measure.py NAME SEEDS.json OUT.json"""
import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from labtools import *  # noqa: F401,F403
import json
def measure(d, dtm_z, e):
    x, y, hag, z = d["x"], d["y"], d["hag"], d["z"]
    cx, cy, hd = e["x"], e["y"], e["heading"]
    hl, hw, cut, lo = e.get("hl", 3.0), e.get("hw", 1.25), e.get("cut", 2.4), e.get("lo", 0.3)
    a = math.radians(hd); c, s = math.cos(a), math.sin(a)
    u = (x - cx) * c + (y - cy) * s; v = -(x - cx) * s + (y - cy) * c
    m = (np.abs(u) <= hl) & (np.abs(v) <= hw) & (hag >= lo) & (hag <= cut)
    X, Y, H = x[m], y[m], hag[m]
    if e.get("hole"):
        g = (np.abs(u) <= hl) & (np.abs(v) <= hw) & (hag < 0.25)
        cell = 0.2; nu, nv = int(2 * hl / cell) + 1, int(2 * hw / cell) + 1
        occ = np.zeros((nv, nu), bool)
        occ[((v[g] + hw) / cell).astype(int), ((u[g] + hl) / cell).astype(int)] = True
        hole = ndimage.binary_opening(~occ, structure=np.ones((3, 3)))
        lab, n = ndimage.label(hole)
        if n:
            k = 1 + int(np.argmax(ndimage.sum(hole, lab, range(1, n + 1))))
            iv, iu = np.nonzero(lab == k)
            hu = -hl + (iu + 0.5) * cell; hv = -hw + (iv + 0.5) * cell
            X = np.r_[X, cx + hu * c - hv * s]; Y = np.r_[Y, cy + hu * s + hv * c]
    # rectangle: heading held within tol of the given one (scan 0.5 deg)
    tol = e.get("tol", 10)
    best = None
    for dh in np.arange(-tol, tol + 0.01, 0.5):
        b = math.radians(hd + dh); cb, sb = math.cos(b), math.sin(b)
        uu = X * cb + Y * sb; vv = -X * sb + Y * cb
        area = (uu.max() - uu.min()) * (vv.max() - vv.min())
        if best is None or area < best[0]: best = (area, b, uu.min(), uu.max(), vv.min(), vv.max())
    _, b, u0, u1, v0, v1 = best
    cb, sb = math.cos(b), math.sin(b)
    uc, vc = (u0 + u1) / 2, (v0 + v1) / 2
    rx, ry = uc * cb - vc * sb, uc * sb + vc * cb
    L, W = u1 - u0, v1 - v0
    Hh = float(np.percentile(H, 98))
    corners = []
    for du, dv in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
        pu, pv = uc + du * L / 2, vc + dv * W / 2
        corners.append([round(pu * cb - pv * sb, 3), round(pu * sb + pv * cb, 3)])
    gz = float(dtm_z(np.array([rx]), np.array([ry]))[0])
    return dict(x=round(rx, 3), y=round(ry, 3), heading=round(math.degrees(b) % 180, 1), L=round(L, 2), W=round(W, 2),
                H=round(Hh, 2), ground=round(gz, 3), points=int(m.sum()), footprint=corners,
                multi=round(float((d["nr"][m] > 1).mean()), 2))
if __name__ == "__main__":
    name, lab_in, out = sys.argv[1:4]
    d = np.load(os.path.join(WORK, f"{name}.npz"))
    # ground z under the centre: z - hag of the nearest points (HAG is z minus the DTM)
    def dtm_z(qx, qy):
        k = np.argsort(np.hypot(d["x"] - qx[0], d["y"] - qy[0]))[:20]
        return np.array([np.median(d["z"][k] - d["hag"][k])])
    L = json.load(open(lab_in)); res = []
    for e in L:
        r = measure(d, dtm_z, e); r.update({k: v for k, v in e.items() if k not in ("x", "y", "heading")}); r["seed"] = [e["x"], e["y"], e["heading"]]
        res.append(r)
        print(f"{e['tag']:>4} {e.get('kind','veh'):4} {r['x']:.2f} {r['y']:.2f} hd {r['heading']:5.1f} L {r['L']:.2f} W {r['W']:.2f} H {r['H']:.2f} pts {r['points']} multi {r['multi']}")
    json.dump(res, open(out, "w"), indent=1)
