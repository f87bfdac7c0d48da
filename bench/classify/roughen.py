#!/usr/bin/env python3
"""Development meshes for docs/decisions/classify.md §43: a library mesh (binary PLY, metres, z up,
bbox centred in x y, bottom z = 0; share/vehicles/) with equipment boxes added on its top. Writes
only OUT.ply (development data: keep it out of the repository).

  bench/classify/roughen.py IN.ply OUT.ply KIND SEED
KIND: ladder (an aerial ladder on a turntable), rack (a roof rack with cargo), boxes (equipment
boxes over about 40% of the top), mixed (ladder + boxes). Each box stands on the mesh's top under
its footprint (the highest surface there, from a 0.1 m height map of the triangles)."""
import math
import random
import struct
import sys


def read_ply(p):
    b = open(p, 'rb').read()
    h_end = b.index(b'end_header\n') + len(b'end_header\n')
    hdr = b[:h_end].decode().splitlines()
    nv = int([l for l in hdr if l.startswith('element vertex')][0].split()[2])
    nf = int([l for l in hdr if l.startswith('element face')][0].split()[2])
    off = h_end
    verts = [struct.unpack_from('<3f', b, off + 12 * i) for i in range(nv)]
    off += 12 * nv
    faces = []
    for _ in range(nf):
        n = b[off]
        faces.append(struct.unpack_from('<%di' % n, b, off + 1))
        off += 1 + 4 * n
    return verts, faces


def write_ply(p, verts, faces, comment):
    with open(p, 'wb') as f:
        f.write(('ply\nformat binary_little_endian 1.0\ncomment %s\nelement vertex %d\nproperty float x\n'
                 'property float y\nproperty float z\nelement face %d\nproperty list uchar int vertex_indices\n'
                 'end_header\n' % (comment, len(verts), len(faces))).encode())
        for v in verts:
            f.write(struct.pack('<3f', *v))
        for t in faces:
            f.write(struct.pack('<B%di' % len(t), len(t), *t))


def height_map(verts, faces, cell=0.1):
    hm = {}
    for t in faces:
        for k in range(1, len(t) - 1):
            a, b, c = verts[t[0]], verts[t[k]], verts[t[k + 1]]
            ext = max(abs(a[0] - b[0]), abs(a[0] - c[0]), abs(a[1] - b[1]), abs(a[1] - c[1]), abs(b[0] - c[0]),
                      abs(b[1] - c[1]))
            n = max(1, int(ext / (cell / 2)) + 1)
            for i in range(n + 1):
                for j in range(n + 1 - i):
                    s, r = i / n, j / n
                    x = a[0] + s * (b[0] - a[0]) + r * (c[0] - a[0])
                    y = a[1] + s * (b[1] - a[1]) + r * (c[1] - a[1])
                    z = a[2] + s * (b[2] - a[2]) + r * (c[2] - a[2])
                    key = (math.floor(x / cell), math.floor(y / cell))
                    if z > hm.get(key, -1e9):
                        hm[key] = z
    return hm


def top_under(hm, x0, x1, y0, y1, cell=0.1):
    z = 0.0
    for i in range(math.floor(x0 / cell), math.floor(x1 / cell) + 1):
        for j in range(math.floor(y0 / cell), math.floor(y1 / cell) + 1):
            z = max(z, hm.get((i, j), 0.0))
    return z


def box(verts, faces, x0, x1, y0, y1, z0, z1):
    base = len(verts)
    for z in (z0, z1):
        verts += [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
    q = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    for a, b, c, d in q:
        faces.append((base + a, base + b, base + c))
        faces.append((base + a, base + c, base + d))


def main():
    src, dst, kind, seed = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    rnd = random.Random(seed)
    verts, faces = read_ply(src)
    verts = [tuple(v) for v in verts]
    hm = height_map(verts, faces)
    xs = [v[0] for v in verts]
    ys = [v[1] for v in verts]
    H = max(v[2] for v in verts)
    # The top plateau: cells within 0.35 m of the top; its extent along x (the long axis) and y.
    plat = [k for k, z in hm.items() if z >= H - 0.35]
    px0 = min(k[0] for k in plat) * 0.1 + 0.1
    px1 = (max(k[0] for k in plat) + 1) * 0.1 - 0.1
    py0 = min(k[1] for k in plat) * 0.1 + 0.1
    py1 = (max(k[1] for k in plat) + 1) * 0.1 - 0.1
    if px1 - px0 < 1.5:  # a short plateau (a cab): use the middle 70% of the length
        L = max(xs) - min(xs)
        px0, px1 = min(xs) + 0.15 * L, max(xs) - 0.15 * L
    W = py1 - py0
    add_v, add_f = [], []

    def stand(x0, x1, y0, y1, h, lift=0.0):
        z = top_under(hm, x0, x1, y0, y1) + lift
        box(add_v, add_f, x0, x1, y0, y1, z, z + h)
        return z

    kinds = [kind] if kind != 'mixed' else ['ladder', 'boxes']
    for k in kinds:
        if k == 'ladder':
            # an aerial ladder on a turntable: two rails along, rungs every 0.3 m, 0.3-0.6 m above the top
            lift = rnd.uniform(0.3, 0.6)
            lx0, lx1 = px0 + 0.3, px1 - rnd.uniform(0.0, 0.8)
            half = min(0.45, W / 2 - 0.1)
            z = top_under(hm, lx0, lx1, -half, half) + lift
            for y in (-half, half - 0.12):
                box(add_v, add_f, lx0, lx1, y, y + 0.12, z, z + 0.25)
            x = lx0 + 0.1
            while x < lx1 - 0.1:
                box(add_v, add_f, x, x + 0.05, -half, half, z + 0.05, z + 0.1)
                x += 0.3
            # turntable and its post
            tx = lx1 - 1.0 if rnd.random() < 0.5 else lx0 + 0.2
            stand(tx, tx + 1.0, -0.6, 0.6, lift + 0.05)
        elif k == 'rack':
            # a roof rack: perimeter rails on posts 0.15 m high, cross bars every 0.5 m
            hgt = rnd.uniform(0.12, 0.2)
            zt = top_under(hm, px0, px1, py0, py1)
            for y in (py0, py1 - 0.05):
                box(add_v, add_f, px0, px1, y, y + 0.05, zt + hgt, zt + hgt + 0.05)
            x = px0
            while x < px1:
                box(add_v, add_f, x, x + 0.05, py0, py1, zt + hgt, zt + hgt + 0.05)
                box(add_v, add_f, x, x + 0.05, py0, py0 + 0.05, zt, zt + hgt)
                box(add_v, add_f, x, x + 0.05, py1 - 0.05, py1, zt, zt + hgt)
                x += 0.5
            # cargo on the rack
            for _ in range(rnd.randint(2, 4)):
                l, w = rnd.uniform(0.4, 1.2), rnd.uniform(0.3, min(0.9, W))
                x0 = rnd.uniform(px0, max(px0, px1 - l))
                y0 = rnd.uniform(py0, max(py0, py1 - w))
                box(add_v, add_f, x0, x0 + l, y0, y0 + w, zt + hgt + 0.05, zt + hgt + 0.05 + rnd.uniform(0.15, 0.5))
        elif k == 'boxes':
            # equipment boxes of 0.2-0.7 m over about 40% of the top
            area = (px1 - px0) * W
            placed = 0.0
            while placed < 0.4 * area:
                l, w = rnd.uniform(0.3, 1.5), rnd.uniform(0.3, min(1.2, W))
                x0 = rnd.uniform(px0, max(px0, px1 - l))
                y0 = rnd.uniform(py0, max(py0, py1 - w))
                stand(x0, x0 + l, y0, y0 + w, rnd.uniform(0.2, 0.7))
                placed += l * w
    base = len(verts)
    verts += add_v
    faces += [tuple(i + base for i in t) for t in add_f]
    write_ply(dst, verts, faces, 'dev mesh for classify.md 43: %s + %s seed %d' % (src.split('/')[-1], kind, seed))
    print('%s: plateau x %.2f..%.2f y %.2f..%.2f H %.2f, %d boxes' % (dst, px0, px1, py0, py1, H, len(add_f) // 12))


main()
