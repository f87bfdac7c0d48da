#!/usr/bin/env python3
"""The measurements behind meshsize's up check (docs/decisions/user-modelbase.md §8, stop 67).

  scripts/vehicles/upcheck.py meshes BIN MESH...   every mesh (.ply as the library's: binary
      little-endian float x y z; or .obj) turned into 7 orientations in a temporary directory
      and measured by BIN/meshsize: prints a markdown row per mesh with the horizontal mirror
      symmetry meshsize reports and its verdict (side, end) per orientation.
  scripts/vehicles/upcheck.py inc MODEL.inc...   a POV-Ray model (share/models/*.inc: y up, one
      object Vehicle): povray samples inside() at voxel centres (1/100 of the largest extent);
      the surface voxels (inside, a face neighbour outside) are scored as meshsize scores its
      voxels, with the up, the lateral and the length axis vertical in turn.

The orientations: a file written z up (the library's frame) turned so that its up axis is +y,
-y, +x (length along y), +x (length along z: on its end), +y with its front along -z (a glTF
asset), and the two y-up variants read with --up y."""
import math
import os
import re
import struct
import subprocess
import sys
import tempfile

TURN = {  # (x, y, z) of a z-up, x-forward vehicle -> the turned file's coordinates
    "z": lambda x, y, z: (x, y, z),
    "ypos": lambda x, y, z: (x, z, -y),
    "yneg": lambda x, y, z: (x, -z, y),
    "xside": lambda x, y, z: (z, x, y),
    "xend": lambda x, y, z: (z, y, -x),
    "yfwdz": lambda x, y, z: (-y, z, -x),
}
COLUMNS = [("z", "z"), ("ypos", "z"), ("yneg", "z"), ("xside", "z"), ("xend", "z"), ("z", "y"), ("ypos", "y"),
           ("yfwdz", "z"), ("yfwdz", "y")]
HEADER = ("| mesh | upright (z) | up +y read as z | up −y read as z | up +x, length along y | "
          "up +x, length along z | upright read with --up y | up +y read with --up y | "
          "up +y, front along −z, read as z | the same with --up y |")


def turn(src, dst, orient):
    f = TURN[orient]
    if src.endswith(".obj"):
        with open(src, errors="replace") as i, open(dst, "w") as o:
            for line in i:
                if line.startswith("v "):
                    t = line.split()
                    line = "v %.6f %.6f %.6f\n" % f(*map(float, t[1:4]))
                o.write(line)
        return
    data = open(src, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    nv = int(data[:end].decode().split("element vertex ")[1].split()[0])
    body = bytearray(data[end:])
    for i in range(nv):
        struct.pack_into("<3f", body, 12 * i, *f(*struct.unpack_from("<3f", body, 12 * i)))
    open(dst, "wb").write(data[:end] + bytes(body))


def cell(binary, path, up):
    r = subprocess.run([os.path.join(binary, "meshsize"), "--up", up, "-i", path, "-o", os.devnull],
                       capture_output=True, text=True)
    m = re.search(r"horizontal mirror symmetry ([0-9.]+)", r.stderr)
    verdict = (" side" if "lying on its side" in r.stderr else "") + (" end" if "on its end" in r.stderr else "")
    return (m.group(1) if m else "?") + verdict


def meshes(binary, paths):
    print(HEADER)
    print("|" + " --- |" * (len(COLUMNS) + 1))
    with tempfile.TemporaryDirectory() as tmp:
        for p in paths:
            ext = os.path.splitext(p)[1]
            row = []
            for orient, up in COLUMNS:
                q = os.path.join(tmp, orient + ext)
                if not os.path.exists(q):
                    turn(p, q, orient)
                row.append(cell(binary, q, up))
            for orient in TURN:
                os.remove(os.path.join(tmp, orient + ext))
            print("| %s | %s |" % (os.path.splitext(os.path.basename(p))[0], " | ".join(row)))


GRID = """#version 3.7;
#include "%s"
#declare Mn = min_extent(Vehicle);
#declare Sz = max_extent(Vehicle) - Mn;
#declare C = max(Sz.x, Sz.y, Sz.z) / 100;
#fopen F "%s" write
#for (I, 0, int(Sz.x / C) + 1) #for (J, 0, int(Sz.y / C) + 1) #for (K, 0, int(Sz.z / C) + 1)
  #if (inside(Vehicle, Mn + <I + 0.5, J + 0.5, K + 0.5> * C)) #write (F, I, " ", J, " ", K, "\\n") #end
#end #end #end
#fclose F
camera { location <0, 0, -10> look_at 0 }
"""


def symmetry(vox, axis):  # meshsize's score with `axis` vertical
    occ = set(vox)
    lo = min(v[axis] for v in vox)
    n = max(v[axis] for v in vox) - lo + 1
    best = 0
    for s in range(-math.ceil(0.1 * n), math.ceil(0.1 * n) + 1):
        hit = 0
        for v in vox:
            m = math.floor(n + 0.5 * s - (v[axis] - lo + 0.5)) + lo
            w = list(v)
            for d in (-1, 0, 1):
                w[axis] = m + d
                if tuple(w) in occ:
                    hit += 1
                    break
        best = max(best, hit / len(vox))
    return best


def inc(paths):
    print("| model | surface voxels | upright | on its side (lateral vertical) | on its end (length vertical) |")
    print("| --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for p in paths:
            pov, txt = os.path.join(tmp, "grid.pov"), os.path.join(tmp, "grid.txt")
            open(pov, "w").write(GRID % (os.path.abspath(p), txt))
            subprocess.run(["povray", "-D", "-GA", "+W8", "+H8", "-O" + os.devnull, pov], check=True,
                           capture_output=True)
            inside = {tuple(int(float(t)) for t in line.split()) for line in open(txt) if line.strip()}
            faces = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))
            surf = [v for v in inside if any((v[0] + a, v[1] + b, v[2] + c) not in inside for a, b, c in faces)]
            # POV axes: x length, y up, z lateral
            print("| %s | %d | %.3f | %.3f | %.3f |" % (os.path.basename(p), len(surf), symmetry(surf, 1),
                                                       symmetry(surf, 2), symmetry(surf, 0)))


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "meshes":
        meshes(sys.argv[2], sys.argv[3:])
    elif len(sys.argv) >= 3 and sys.argv[1] == "inc":
        inc(sys.argv[2:])
    else:
        sys.exit(__doc__)
