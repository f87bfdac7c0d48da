#!/usr/bin/env python3
"""Side (x-z, seen from -y) and top (x-y) silhouettes of a PLY written by convert.py, as one
PNG (front +x to the right), to check the yaw of a transforms.csv row by eye.

Usage: scripts/vehicles/preview.py MESH.ply OUT.png [pixels per metre, default 40]"""
import struct
import sys
import zlib


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len("end_header\n")
    head = data[:end].decode("ascii").split("\n")
    nv = int([l for l in head if l.startswith("element vertex")][0].split()[2])
    nf = int([l for l in head if l.startswith("element face")][0].split()[2])
    v = [struct.unpack_from("<3f", data, end + 12 * i) for i in range(nv)]
    off = end + 12 * nv
    f = [struct.unpack_from("<3i", data, off + 13 * i + 1) for i in range(nf)]
    return v, f


def png(path, img, w, h):
    raw = b"".join(b"\x00" + bytes(img[r * w:(r + 1) * w]) for r in range(h))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def main():
    v, f = read_ply(sys.argv[1])
    s = float(sys.argv[3]) if len(sys.argv) > 3 else 40.0
    lo = [min(p[i] for p in v) for i in range(3)]
    hi = [max(p[i] for p in v) for i in range(3)]
    w = int((hi[0] - lo[0]) * s) + 3
    hs, ht = int((hi[2] - lo[2]) * s) + 3, int((hi[1] - lo[1]) * s) + 3
    h = hs + 4 + ht
    img = bytearray([255]) * (w * h)
    for a, b, c in f:
        P = [v[a], v[b], v[c]]
        n = int(max(abs(P[i][k] - P[j][k]) for i in range(3) for j in range(3) for k in range(3)) * s) + 1
        for i in range(n + 1):
            for j in range(n + 1 - i):
                u, t = i / n, j / n
                x = P[0][0] + u * (P[1][0] - P[0][0]) + t * (P[2][0] - P[0][0])
                y = P[0][1] + u * (P[1][1] - P[0][1]) + t * (P[2][1] - P[0][1])
                z = P[0][2] + u * (P[1][2] - P[0][2]) + t * (P[2][2] - P[0][2])
                col = int((x - lo[0]) * s) + 1
                img[(hs - 1 - int((z - lo[2]) * s)) * w + col] = 60
                img[(hs + 4 + ht - 1 - int((y - lo[1]) * s)) * w + col] = 120
    png(sys.argv[2], img, w, h)


if __name__ == "__main__":
    main()
