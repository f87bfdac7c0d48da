#!/usr/bin/env python3
"""The instance distance of the vehicle library (docs/decisions/vehicle-library.md, section 6):
for every test instance, the symmetric chamfer distance to every modelbase instance of its
class, and which one is nearest (the report's instance accuracy judges model answers by it).

Usage: scripts/vehicles/distance.py [--library DIR] [--check] [--samples N]
       scripts/vehicles/distance.py --self-test

Both meshes are taken in the library frame (front +x, z up, bounding box centred in x and y,
bottom at z = 0: split.csv's meshes already are), so their boxes' centres and bottoms are
aligned and nothing is scaled (size is part of what makes an instance). Each mesh gives N
surface points (default 4096), area-uniform, from Python's Mersenne Twister seeded with the
first 8 bytes of SHA-256(mesh name): reproducible. D(A, B) = 1/2 (mean over a in A of the
distance to the nearest b in B + mean over b in B of the distance to the nearest a in A), in
metres, minimised over B's yaw in {0, 180 deg} (a front/back mix-up of a third-party mesh must
not decide). Writes DIR/distances.csv: test, class, modelbase, distance_m, rank (1 = nearest),
rows by test instance then rank; --check compares with the file instead (exit 1 if it differs).
"""

import argparse
import csv
import hashlib
import math
import os
import random
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from preview import read_ply  # noqa: E402  (the library's binary PLY reader)


def sample(verts, faces, n, name):
    """n area-uniform surface points, seeded by the name."""
    rng = random.Random(int.from_bytes(hashlib.sha256(name.encode()).digest()[:8], "big"))
    cum, total = [], 0.0
    for a, b, c in faces:
        p, q, r = verts[a], verts[b], verts[c]
        u = [q[i] - p[i] for i in range(3)]
        w = [r[i] - p[i] for i in range(3)]
        cx = u[1] * w[2] - u[2] * w[1]
        cy = u[2] * w[0] - u[0] * w[2]
        cz = u[0] * w[1] - u[1] * w[0]
        total += 0.5 * math.sqrt(cx * cx + cy * cy + cz * cz)
        cum.append(total)
    if total <= 0:
        raise ValueError("%s: the mesh has no area" % name)
    pts = []
    for _ in range(n):
        t = rng.random() * total
        lo, hi = 0, len(cum) - 1
        while lo < hi:
            mid = (lo + hi) // 2
            if cum[mid] < t:
                lo = mid + 1
            else:
                hi = mid
        a, b, c = faces[lo]
        r1, r2 = rng.random(), rng.random()
        s = math.sqrt(r1)
        wa, wb, wc = 1 - s, s * (1 - r2), s * r2
        p, q, r = verts[a], verts[b], verts[c]
        pts.append(tuple(wa * p[i] + wb * q[i] + wc * r[i] for i in range(3)))
    return pts


class Grid:
    """Nearest-neighbour search over a point set by cubic cells (exact: rings grow until no
    closer point can remain)."""

    def __init__(self, pts, h):
        self.h = h
        self.cells = {}
        for p in pts:
            self.cells.setdefault(self.key(p), []).append(p)
        self.keys = list(self.cells)

    def key(self, p):
        return tuple(int(math.floor(c / self.h)) for c in p)

    def nearest(self, p):
        k = self.key(p)
        best = float("inf")
        ring = 0
        while True:
            for dx in range(-ring, ring + 1):
                for dy in range(-ring, ring + 1):
                    for dz in range(-ring, ring + 1):
                        if max(abs(dx), abs(dy), abs(dz)) != ring:
                            continue
                        for q in self.cells.get((k[0] + dx, k[1] + dy, k[2] + dz), ()):
                            d = (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2
                            if d < best:
                                best = d
            # Every point outside the rings searched is at least ring * h away.
            if best <= (ring * self.h) ** 2:
                return math.sqrt(best)
            ring += 1


def mean_nearest(a, grid_b):
    return sum(grid_b.nearest(p) for p in a) / len(a)


def chamfer(a, b, h=0.25):
    """Symmetric chamfer distance of two point sets (metres), minimised over b's yaw 0/180."""
    best = float("inf")
    grid_a = Grid(a, h)
    for flip in (False, True):
        bb = [(-x, -y, z) for x, y, z in b] if flip else b
        d = 0.5 * (mean_nearest(a, Grid(bb, h)) + mean_nearest(bb, grid_a))
        best = min(best, d)
    return best


def distances(library, n):
    split = list(csv.DictReader(open(os.path.join(library, "split.csv"), newline="")))
    cat = {r["name"]: r for r in csv.DictReader(open(os.path.join(library, "catalogue.csv"), newline=""))}
    samples = {}

    def pts(name):
        if name not in samples:
            v, f = read_ply(os.path.join(library, cat[name]["file"]))
            samples[name] = sample(v, f, n, name)
        return samples[name]

    rows = []
    for t in split:
        if t["split"] != "test":
            continue
        cand = [m["name"] for m in split if m["split"] == "modelbase" and m["class"] == t["class"]]
        ds = sorted((chamfer(pts(t["name"]), pts(m)), m) for m in cand)
        for rank, (d, m) in enumerate(ds, 1):
            rows.append([t["name"], t["class"], m, "%.4f" % d, rank])
    return rows


def self_test():
    # Known answers: a unit square against itself (same samples) is 0; against a copy 2 m
    # above it, every nearest point is straight across up to the sampling (>= 2 m, and at most
    # sqrt(4 + spacing^2)); the yaw flip finds a mesh turned by 180 deg identical.
    sq_v = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
    sq_f = [(0, 1, 2), (0, 2, 3)]
    a = sample(sq_v, sq_f, 2000, "square")
    assert chamfer(a, a) == 0.0
    up = [(x, y, z + 2.0) for x, y, z in a]
    d = chamfer(a, up, h=1.0)
    assert 2.0 <= d <= 2.001, d
    # An L shape and the same L turned by 180 deg about z (centred): distance 0 after the flip.
    l_v = [(-1.0, -0.5, 0.0), (1.0, -0.5, 0.0), (1.0, 0.5, 0.0), (-1.0, 0.5, 0.0), (1.0, -0.5, 1.0), (1.0, 0.5, 1.0)]
    l_f = [(0, 1, 2), (0, 2, 3), (1, 4, 5), (1, 5, 2)]
    l = sample(l_v, l_f, 1000, "L")
    turned = [(-x, -y, z) for x, y, z in l]
    assert chamfer(l, turned) == 0.0
    print("distance.py self-test: ok")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--library", default=os.path.join(ROOT, "share", "vehicles"))
    ap.add_argument("--samples", type=int, default=4096)
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    rows = distances(a.library, a.samples)
    text = "test,class,modelbase,distance_m,rank\n" + "".join(",".join(str(c) for c in r) + "\n" for r in rows)
    path = os.path.join(a.library, "distances.csv")
    if a.check:
        if open(path).read() != text:
            print("differs: " + path, file=sys.stderr)
            return 1
        return 0
    with open(path + ".tmp", "w") as fh:
        fh.write(text)
    os.replace(path + ".tmp", path)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
