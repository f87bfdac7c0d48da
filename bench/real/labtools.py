"""Hand-labelling toolkit for real airborne tiles (docs/decisions/real-tiles.md, "How the labels were made" and
"A development tile from another survey (stop 47)"): a PLY reader for pcd2ply's output, the progressive
morphological ground filter (Zhang et al. 2003) that gives height above ground, top-view grids and the
minimum-area rectangle. Needs numpy, scipy, matplotlib (Debian: python3-numpy python3-scipy python3-matplotlib;
run with /usr/bin/python3). The other scripts of this folder import it; their files live in $LABEL_WORK
(default: the current directory): raw/<name>.ply (`build/bin/pcd2ply -i tile.laz -o raw/<name>.ply`),
<name>.npz (prep.py), pics/, labels/. Labelling tools only: never part of a measured chain.
"""
import os, sys, re, json, math
import numpy as np
import matplotlib; matplotlib.use("Agg")
import matplotlib.pyplot as plt
from scipy import ndimage
from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

TY = {"double": "<f8", "float": "<f4", "uchar": "u1", "char": "i1", "ushort": "<u2", "short": "<i2",
      "uint": "<u4", "int": "<i4"}

def read_ply(path):
    f = open(path, "rb"); hdr = b""
    while not hdr.endswith(b"end_header\n"):
        hdr += f.readline()
    n = 0; props = []; cur = None
    for line in hdr.decode().splitlines():
        t = line.split()
        if t[:2] == ["element", "vertex"]: n = int(t[2]); cur = "v"
        elif t and t[0] == "element": cur = "o"
        elif t and t[0] == "property" and cur == "v" and t[1] != "list": props.append((t[2], TY[t[1]]))
    return np.frombuffer(f.read(n * np.dtype(props).itemsize), dtype=np.dtype(props), count=n)

def pmf_ground(x, y, z, cell=0.5, windows=(1, 2, 4, 8, 12, 16, 24, 32), slope=0.3, d0=0.25, dmax=2.5):
    x0, y0 = x.min(), y.min()
    ix = ((x - x0) / cell).astype(int); iy = ((y - y0) / cell).astype(int)
    nx, ny = ix.max() + 1, iy.max() + 1
    zmin = np.full((ny, nx), np.inf)
    np.minimum.at(zmin, (iy, ix), z)
    has = np.isfinite(zmin)
    # fill empty cells by nearest for morphology
    idx = ndimage.distance_transform_edt(~has, return_distances=False, return_indices=True)
    zf = zmin[idx[0], idx[1]]
    ground = has.copy(); surf = zf.copy(); prev_w = 0
    for w in windows:
        k = max(1, int(round(w / cell)))
        op = ndimage.grey_opening(surf, size=(k, k))
        dh = min(dmax, d0 + slope * (w - prev_w) if prev_w else d0)
        ground &= ~((zf - op) > dh)
        surf = op; prev_w = w
    gy, gx = np.nonzero(ground)
    gz = zmin[gy, gx]
    pts = np.c_[x0 + (gx + 0.5) * cell, y0 + (gy + 0.5) * cell]
    lin = LinearNDInterpolator(pts, gz); near = NearestNDInterpolator(pts, gz)
    def dtm(qx, qy):
        v = lin(qx, qy); bad = np.isnan(v)
        if bad.any(): v[bad] = near(qx[bad], qy[bad])
        return v
    return dtm

def grid_max(x, y, v, x0, y0, w, h, cell, mask=None):
    nx, ny = int(math.ceil(w / cell)), int(math.ceil(h / cell))
    ix = ((x - x0) / cell).astype(int); iy = ((y - y0) / cell).astype(int)
    ok = (ix >= 0) & (ix < nx) & (iy >= 0) & (iy < ny)
    if mask is not None: ok &= mask
    g = np.full((ny, nx), np.nan)
    order = np.argsort(v[ok])
    g[iy[ok][order], ix[ok][order]] = v[ok][order]   # last write = max
    return g

def min_rect(px, py):
    from scipy.spatial import ConvexHull
    P = np.c_[px, py]
    if len(P) < 3: return None
    h = P[ConvexHull(P).vertices]
    best = None
    for i in range(len(h)):
        e = h[(i + 1) % len(h)] - h[i]; a = math.atan2(e[1], e[0])
        c, s = math.cos(a), math.sin(a)
        u = h @ np.array([c, s]); v = h @ np.array([-s, c])
        area = (u.max() - u.min()) * (v.max() - v.min())
        if best is None or area < best[0]: best = (area, a, u.min(), u.max(), v.min(), v.max())
    _, a, u0, u1, v0, v1 = best
    L, W = u1 - u0, v1 - v0
    if W > L: a += math.pi / 2; L, W = W, L; u0, u1, v0, v1 = v0, v1, -u1, -u0
    c, s = math.cos(a), math.sin(a)
    uc, vc = (u0 + u1) / 2, (v0 + v1) / 2
    cx, cy = uc * c - vc * s, uc * s + vc * c
    hd = math.degrees(a) % 180
    return cx, cy, hd, L, W
WORK = os.environ.get("LABEL_WORK", ".")
