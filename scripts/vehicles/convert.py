#!/usr/bin/env python3
"""Convert the third-party vehicle meshes of share/vehicles/transforms.csv into the modelbase
convention (formats/README.md): binary little-endian PLY, triangles only, metres, z up, front
toward +x, centred on the bounding box in x and y, bottom at z = 0.

Usage: scripts/vehicles/convert.py [--mirror DIR] [--out DIR] [--only NAME] [--check]
       scripts/vehicles/convert.py --split   (rewrites share/vehicles/split.csv, see below)

Sources are read with `git show COMMIT:PATH` from the repository snapshots under
--mirror (default /work/.mirror, as the `fetch` tool leaves them: <owner>+<name>/repo). The
transform of each mesh is one row of transforms.csv:

  name, class, repo, commit, path   where the mesh comes from (path: one file; several
                                    parts are joined with '|'; a part written FILE@x;y;z is
                                    placed translated by (x, y, z) in the file's own units and
                                    axes, before scale/up/yaw: how a source's wheel mesh is put
                                    at each spindle position of a chassis); FILE@x;y;z;rx first
                                    turns the part by rx degrees about its x axis (a wheel mesh
                                    whose axle is its own z axis, as URDF's rpy="-pi/2 0 0"), and
                                    FILE@x;y;z;rx;ry then by ry degrees about its y axis (a track
                                    shoe laid on its belt, scripts/vehicles/track_belt.py); both
                                    right-handed, before the translation;
                                    FILE@x;y;z;rx;ry;s first scales the part
                                    by s (a wheel model of unit diameter, as
                                    jMonkeyEngine's vehicles are modelled)
  scale                             multiplies the file's coordinates (after COLLADA's
                                    <unit meter>) to give metres
  up                                the file's up axis: z, y (right-handed y up: (x,y,z) ->
                                    (x,-z,y)) or -y
  yaw_deg                           rotation about z (counter-clockwise seen from above) that
                                    turns the vehicle's front to +x, applied after 'up'
  max_triangles                     decimation target (vertex clustering, below)

Then the mesh is translated so its bounding box is centred at x = y = 0 with its bottom at
z = 0. Meshes with more triangles than max_triangles are decimated by vertex clustering: all
vertices in one cube of side h (grid anchored at the bounding-box minimum) become their mean;
triangles that collapse or repeat are dropped; h starts at 5 mm and grows by 10 % until the
count fits. Pure Python, no third-party module; the output is a function of the source bytes
and the row only (byte-identical on re-runs).

--split assigns instances to the modelbase and test splits from transforms.csv alone: in each
class, instances sorted by the SHA-256 of their name (hex); a class of n >= 2 instances puts the
first ceil(n/3) in `test`, the rest in `modelbase`; a class of one instance is `modelbase` only
(an instance can only be judged "unseen" against others of its class).

--check re-converts every row and compares with the committed files instead of writing.
Writes catalogue figures (dimensions; triangles in the source and in the output, which differ
when decimated or when the source repeats triangles) to stdout as CSV.
"""

import argparse
import csv
import hashlib
import json
import math
import os
import re
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def git_show(mirror, repo, commit, path):
    gitdir = os.path.join(mirror, repo.replace("/", "+"), "repo")
    return subprocess.run(["git", "--git-dir", gitdir, "show", commit + ":" + path],
                          check=True, capture_output=True).stdout


# ---------------------------------------------------------------- readers (vertices, faces)

def read_obj(data):
    verts, faces = [], []
    for line in data.decode("latin-1").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            verts.append((float(w[1]), float(w[2]), float(w[3])))
        elif w[0] == "f":
            idx = []
            for t in w[1:]:
                i = int(t.split("/")[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            for k in range(1, len(idx) - 1):
                faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def read_stl(data):
    verts, faces = [], []
    if len(data) >= 84 and len(data) == 84 + 50 * struct.unpack_from("<I", data, 80)[0]:
        n = struct.unpack_from("<I", data, 80)[0]
        for t in range(n):
            c = struct.unpack_from("<9f", data, 84 + 50 * t + 12)
            b = len(verts)
            verts += [c[0:3], c[3:6], c[6:9]]
            faces.append((b, b + 1, b + 2))
        return verts, faces
    for line in data.decode("latin-1").splitlines():
        w = line.split()
        if w and w[0] == "vertex":
            verts.append((float(w[1]), float(w[2]), float(w[3])))
            if len(verts) % 3 == 0:
                faces.append((len(verts) - 3, len(verts) - 2, len(verts) - 1))
    return verts, faces


def _mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _ident():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def _node_matrix(node, ns):
    m = _ident()
    for child in node:
        tag = child.tag.replace(ns, "")
        v = [float(x) for x in (child.text or "").split()]
        if tag == "matrix":
            t = [v[4 * i:4 * i + 4] for i in range(4)]
        elif tag == "translate":
            t = _ident()
            t[0][3], t[1][3], t[2][3] = v
        elif tag == "scale":
            t = _ident()
            t[0][0], t[1][1], t[2][2] = v
        elif tag == "rotate":
            x, y, z, a = v[0], v[1], v[2], math.radians(v[3])
            n = math.sqrt(x * x + y * y + z * z) or 1.0
            x, y, z = x / n, y / n, z / n
            c, s, C = math.cos(a), math.sin(a), 1 - math.cos(a)
            t = [[c + x * x * C, x * y * C - z * s, x * z * C + y * s, 0],
                 [y * x * C + z * s, c + y * y * C, y * z * C - x * s, 0],
                 [z * x * C - y * s, z * y * C + x * s, c + z * z * C, 0], [0, 0, 0, 1]]
        else:
            continue
        m = _mat_mul(m, t)
    return m


def read_dae(data):
    """COLLADA 1.4: <triangles>/<polylist>/<polygons> of every geometry instanced in the
    visual scene, with the node transforms and <unit meter>; the up axis is left to the row."""
    root = ET.fromstring(data)
    ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    unit = root.find(f"{ns}asset/{ns}unit")
    meter = float(unit.get("meter")) if unit is not None and unit.get("meter") else 1.0
    geoms = {}
    for g in root.iter(f"{ns}geometry"):
        mesh = g.find(f"{ns}mesh")
        if mesh is None:
            continue
        sources = {s.get("id"): [float(x) for x in s.find(f"{ns}float_array").text.split()]
                   for s in mesh.findall(f"{ns}source") if s.find(f"{ns}float_array") is not None}
        vmap = {}
        for vs in mesh.findall(f"{ns}vertices"):
            for inp in vs.findall(f"{ns}input"):
                if inp.get("semantic") == "POSITION":
                    vmap[vs.get("id")] = inp.get("source")[1:]
        tris = []
        for prim in list(mesh):
            tag = prim.tag.replace(ns, "")
            if tag not in ("triangles", "polylist", "polygons"):
                continue
            inputs = prim.findall(f"{ns}input")
            stride = max(int(i.get("offset")) for i in inputs) + 1
            vin = [i for i in inputs if i.get("semantic") == "VERTEX"][0]
            pos = sources[vmap[vin.get("source")[1:]]]
            off = int(vin.get("offset"))
            plist = [[int(x) for x in p.text.split()] for p in prim.findall(f"{ns}p") if p.text]
            if tag == "triangles":
                counts = None
            elif tag == "polylist":
                counts = [int(x) for x in prim.find(f"{ns}vcount").text.split()]
            for p in plist:
                ids = p[off::stride]
                cs = [3] * (len(ids) // 3) if counts is None and tag == "triangles" else (
                    counts if tag == "polylist" else [len(ids)])
                k = 0
                for c in cs:
                    poly = ids[k:k + c]
                    k += c
                    for j in range(1, c - 1):
                        tris.append(tuple(tuple(pos[3 * i:3 * i + 3]) for i in (poly[0], poly[j], poly[j + 1])))
        geoms[g.get("id")] = tris
    verts, faces = [], []

    def walk(node, m):
        m = _mat_mul(m, _node_matrix(node, ns))
        for ig in node.findall(f"{ns}instance_geometry"):
            for tri in geoms.get(ig.get("url")[1:], []):
                b = len(verts)
                for p in tri:
                    verts.append(tuple(meter * (m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3])
                                       for r in range(3)))
                faces.append((b, b + 1, b + 2))
        for ch in node.findall(f"{ns}node"):
            walk(ch, m)

    for vs in root.iter(f"{ns}visual_scene"):
        for n in vs.findall(f"{ns}node"):
            walk(n, _ident())
    return verts, faces


def read_glb(data):
    """Binary glTF 2.0 (one JSON chunk, one BIN chunk): see read_gltf_doc."""
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF"
    off, doc, blob = 12, None, b""
    while off < length:
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8:off + 8 + clen]
        if ctype == 0x4E4F534A:
            doc = json.loads(chunk)
        elif ctype == 0x004E4942:
            blob = chunk
        off += 8 + clen
    return read_gltf_doc(doc, [blob])


def read_gltf(data, sibling):
    """glTF 2.0 JSON with its buffers in files beside it (sibling(uri) gives their bytes)."""
    doc = json.loads(data)
    return read_gltf_doc(doc, [sibling(b["uri"]) for b in doc["buffers"]])


def read_gltf_doc(doc, buffers):
    """Every mesh primitive (mode 4, triangles) of the default scene, node transforms (matrix
    or TRS) applied; float positions, any index type."""

    def accessor(i):
        a = doc["accessors"][i]
        bv = doc["bufferViews"][a["bufferView"]]
        blob = buffers[bv.get("buffer", 0)]
        fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
        ncomp = {"SCALAR": 1, "VEC3": 3}[a["type"]]
        size = struct.calcsize(fmt)
        stride = bv.get("byteStride", size * ncomp)
        base = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
        return [struct.unpack_from("<%d%s" % (ncomp, fmt), blob, base + k * stride) for k in range(a["count"])]

    def trs(n):
        if "matrix" in n:
            c = n["matrix"]
            return [[c[0], c[4], c[8], c[12]], [c[1], c[5], c[9], c[13]], [c[2], c[6], c[10], c[14]], [0, 0, 0, 1]]
        t = n.get("translation", [0, 0, 0])
        x, y, z, w = n.get("rotation", [0, 0, 0, 1])
        s = n.get("scale", [1, 1, 1])
        r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
             [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
             [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]

    verts, faces = [], []

    def walk(ni, m):
        n = doc["nodes"][ni]
        m = _mat_mul(m, trs(n))
        if "mesh" in n:
            for prim in doc["meshes"][n["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                pos = accessor(prim["attributes"]["POSITION"])
                idx = [i[0] for i in accessor(prim["indices"])] if "indices" in prim else list(range(len(pos)))
                b = len(verts)
                for p in pos:
                    verts.append(tuple(m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3] for r in range(3)))
                for k in range(0, len(idx) - 2, 3):
                    faces.append((b + idx[k], b + idx[k + 1], b + idx[k + 2]))
        for c in n.get("children", []):
            walk(c, m)

    for ni in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        walk(ni, _ident())
    return verts, faces


# jMonkeyEngine BinaryExporter (.j3o): class table (field aliases and type codes), location
# table (object id -> offset), then per object: class alias, data length, fields (alias, value).
INT, INT_1D, FLOAT, FLOAT_1D, BYTE, BYTE_1D, SHORT, SHORT_1D = 10, 11, 20, 21, 0, 1, 50, 51
DOUBLE, LONG, BOOLEAN, BOOLEAN_1D, STRING, STRING_1D = 30, 40, 60, 61, 70, 71
SAVABLE, SAVABLE_1D, SAVABLE_AL = 90, 91, 100
SAVABLE_MAP, STRING_SAVABLE_MAP, INT_SAVABLE_MAP = 105, 106, 107
FLOATBUFFER_AL, BYTEBUFFER_AL = 110, 111
FLOATBUFFER, INTBUFFER, BYTEBUFFER, SHORTBUFFER = 120, 121, 122, 123
NULL, DEFAULT = -1, -2


def read_j3o(data):
    p = 0

    def i32():
        nonlocal p
        v = struct.unpack_from(">i", data, p)[0]
        p += 4
        return v
    if data[:4] != b"JME3":
        raise ValueError("not a j3o file (no JME3 signature)")
    p = 4
    version = i32()
    nclasses = i32()
    alias_size = int(math.log(nclasses, 256)) + 1 if nclasses > 0 else 1
    classes = {}
    for _ in range(nclasses):
        alias = data[p:p + alias_size]
        p += alias_size
        if version >= 1:
            nh = data[p]
            p += 1 + 4 * nh
        name = data[p + 4:p + 4 + i32()].decode()
        p += len(name)
        fields = {}
        for _ in range(i32()):
            fa, ft = data[p], data[p + 1]
            p += 2
            n = i32()
            fields[fa] = (ft, data[p:p + n].decode())
            p += n
        classes[alias] = (name, fields)
    locs = {}
    for _ in range(i32()):
        k = i32()
        locs[k] = i32()
    i32()
    root = i32()
    body = data[p:]
    cache = {}

    def obj(oid):
        if oid in cache:
            return cache[oid]
        loc = locs[oid]
        cname, fields = classes[body[loc:loc + alias_size]]
        length = struct.unpack_from(">i", body, loc + alias_size)[0]
        q = loc + alias_size + 4
        end = q + length
        out = {"@class": cname}

        def rint():
            nonlocal q
            n = body[q]
            if n in (0xFF, 0xFE):
                q += 1
                return NULL if n == 0xFF else DEFAULT
            v = int.from_bytes(body[q + 1:q + 1 + n], "big", signed=False) if n else 0
            q += 1 + n
            if n == 4 and v >= 1 << 31:
                v -= 1 << 32
            return v

        def raw(fmt):
            nonlocal q
            v = struct.unpack_from(">" + fmt, body, q)[0]
            q += struct.calcsize(fmt)
            return v

        def rstr():
            nonlocal q
            n = rint()
            if n == NULL:
                return None
            s = body[q:q + n].decode("utf-8", "replace")
            q += n
            return s

        def rarr(f):
            n = rint()
            return None if n == NULL else [f() for _ in range(n)]

        def rsav():
            k = rint()
            return None if k == NULL else ("@ref", k)

        def rbuf(fmt):
            nonlocal q
            n = rint()
            if n == NULL:
                return None
            sz = struct.calcsize(fmt)
            v = list(struct.unpack_from("<%d%s" % (n, fmt), body, q))  # buffers: little-endian
            q += n * sz
            return v
        while q < end:
            ft, fname = fields[body[q]]
            q += 1
            if ft == INT or ft == LONG:
                v = rint()
            elif ft == INT_1D:
                v = rarr(rint)
            elif ft == FLOAT:
                v = raw("f")
            elif ft == FLOAT_1D:
                v = rarr(lambda: raw("f"))
            elif ft == DOUBLE:
                v = raw("d")
            elif ft == BYTE:
                v = raw("b")
            elif ft == BYTE_1D:
                v = rarr(lambda: raw("b"))
            elif ft == SHORT:
                v = raw("h")
            elif ft == SHORT_1D:
                v = rarr(lambda: raw("h"))
            elif ft == BOOLEAN:
                v = raw("?")
            elif ft == BOOLEAN_1D:
                v = rarr(lambda: raw("?"))
            elif ft == STRING:
                v = rstr()
            elif ft == STRING_1D:
                v = rarr(rstr)
            elif ft == SAVABLE:
                v = rsav()
            elif ft in (SAVABLE_1D, SAVABLE_AL):
                v = rarr(rsav)
            elif ft in (SAVABLE_MAP, STRING_SAVABLE_MAP, INT_SAVABLE_MAP):
                # size, then the keys' array and the values' array
                v = None if rint() == NULL else (
                    rarr({SAVABLE_MAP: rsav, STRING_SAVABLE_MAP: rstr, INT_SAVABLE_MAP: rint}[ft]), rarr(rsav))
            elif ft == FLOATBUFFER:
                v = rbuf("f")
            elif ft == INTBUFFER:
                v = rbuf("i")
            elif ft == SHORTBUFFER:
                v = rbuf("h")
            elif ft == BYTEBUFFER:
                v = rbuf("b")
            elif ft == FLOATBUFFER_AL:
                v = rarr(lambda: rbuf("f"))
            elif ft == BYTEBUFFER_AL:
                v = rarr(lambda: rbuf("b"))
            else:
                raise ValueError("j3o: field %s of %s has type %d, not read" % (fname, cname, ft))
            out[fname] = v
        cache[oid] = out
        return out
    return obj, root


def read_j3o_mesh(data):
    """Triangles of every Geometry under the root Node, local transforms (scale, rotation,
    translation) applied down the tree; positions from the 'Position' buffer, indices from
    'Index' (or consecutive)."""
    obj, root = read_j3o(data)

    def get(ref):
        return obj(ref[1]) if ref else None

    def vec(ref, default):
        o = get(ref)
        return default if o is None else [o.get("x", 0.0), o.get("y", 0.0), o.get("z", 0.0)]

    def local(o):
        t = get(o.get("transform"))
        if t is None:
            return [1.0, 1.0, 1.0], (0.0, 0.0, 0.0, 1.0), [0.0, 0.0, 0.0]
        r = get(t.get("rot"))
        q = (0.0, 0.0, 0.0, 1.0) if r is None else (r.get("x", 0.0), r.get("y", 0.0), r.get("z", 0.0), r.get("w", 1.0))
        return vec(t.get("scale"), [1.0, 1.0, 1.0]), q, vec(t.get("translation"), [0.0, 0.0, 0.0])

    def mat(s, q, t):
        x, y, z, w = q
        r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
             [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
             [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]

    def mul(a, b):
        return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]

    verts, faces = [], []

    def walk(o, m):
        m = mul(m, mat(*local(o)))
        if o["@class"].endswith("Geometry"):
            mesh = get(o.get("mesh"))
            if mesh.get("mode", "Triangles") != "Triangles":
                raise ValueError("j3o: mesh mode %s, not read" % mesh.get("mode"))
            keys, vals = mesh["buffers"]
            bufs = {}
            for v in vals:
                vb = get(v)
                data_ = next(vb[k] for k in vb if k.startswith("data"))
                bufs[vb["buffer_type"]] = (vb.get("components", 1), data_)
            c, pos = bufs["Position"]
            if c != 3:
                raise ValueError("j3o: positions of %d components" % c)
            idx = bufs["Index"][1] if "Index" in bufs else list(range(len(pos) // 3))
            idx = [i & 0xFFFF if i < 0 and len(pos) // 3 <= 0x10000 else i for i in idx]
            b = len(verts)
            for k in range(0, len(pos), 3):
                px, py, pz = pos[k:k + 3]
                verts.append(tuple(m[r][0] * px + m[r][1] * py + m[r][2] * pz + m[r][3] for r in range(3)))
            for k in range(0, len(idx) - 2, 3):
                faces.append((b + idx[k], b + idx[k + 1], b + idx[k + 2]))
        for ch in o.get("children") or []:
            walk(get(ch), m)
    walk(obj(root), [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)])
    return verts, faces


READERS = {"obj": read_obj, "stl": read_stl, "dae": read_dae, "glb": read_glb, "gltf": read_gltf,
           "j3o": read_j3o_mesh}


# ---------------------------------------------------------------- transform, decimate, write

def transform(verts, scale, up, yaw_deg):
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    out = []
    for x, y, z in verts:
        x, y, z = x * scale, y * scale, z * scale
        if up == "y":
            x, y, z = x, -z, y
        elif up == "-y":
            x, y, z = x, z, -y
        out.append((c * x - s * y, s * x + c * y, z))
    lo = [min(v[i] for v in out) for i in range(3)]
    hi = [max(v[i] for v in out) for i in range(3)]
    cx, cy = (lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2
    return [(x - cx, y - cy, z - lo[2]) for x, y, z in out]


def weld(verts, faces, h):
    """Vertex clustering with cell size h (h = 0: merge identical coordinates only)."""
    lo = [min(v[i] for v in verts) for i in range(3)]
    cell, sums, remap = {}, [], []
    for v in verts:
        key = v if h == 0 else tuple(int(math.floor((v[i] - lo[i]) / h)) for i in range(3))
        k = cell.get(key)
        if k is None:
            k = cell[key] = len(sums)
            sums.append([0.0, 0.0, 0.0, 0])
        s = sums[k]
        s[0] += v[0]
        s[1] += v[1]
        s[2] += v[2]
        s[3] += 1
        remap.append(k)
    seen, out_faces = set(), []
    for a, b, c in faces:
        a, b, c = remap[a], remap[b], remap[c]
        if a == b or b == c or a == c:
            continue
        key = tuple(sorted((a, b, c)))
        if key in seen:
            continue
        seen.add(key)
        out_faces.append((a, b, c))
    used = sorted({i for f in out_faces for i in f})
    index = {old: new for new, old in enumerate(used)}
    out_verts = [(sums[i][0] / sums[i][3], sums[i][1] / sums[i][3], sums[i][2] / sums[i][3]) for i in used]
    return out_verts, [(index[a], index[b], index[c]) for a, b, c in out_faces]


def decimate(verts, faces, max_triangles):
    verts, faces = weld(verts, faces, 0)
    h = 0.005
    cur_v, cur_f = verts, faces
    while len(cur_f) > max_triangles:
        cur_v, cur_f = weld(verts, faces, h)
        h *= 1.1
    return cur_v, cur_f


def ply_bytes(verts, faces, comments):
    head = ["ply", "format binary_little_endian 1.0"] + ["comment " + c for c in comments] + [
        "element vertex %d" % len(verts), "property float x", "property float y", "property float z",
        "element face %d" % len(faces), "property list uchar int vertex_indices", "end_header"]
    out = bytearray(("\n".join(head) + "\n").encode("ascii"))
    for v in verts:
        out += struct.pack("<3f", *v)
    for f in faces:
        out += struct.pack("<B3i", 3, *f)
    return bytes(out)


def read_part(row, mirror, path, ext):
    data = git_show(mirror, row["repo"], row["commit"], path)
    if ext == "gltf":
        folder = os.path.dirname(path)
        return read_gltf(data, lambda uri: git_show(mirror, row["repo"], row["commit"],
                                                     (folder + "/" if folder else "") + uri))
    return READERS[ext](data)


def convert(row, mirror):
    verts, faces, cache = [], [], {}
    for part in row["path"].split("|"):
        path, _, at = part.partition("@")
        offset = [float(t) for t in at.split(";")] if at else [0.0, 0.0, 0.0]
        if len(offset) not in (3, 4, 5, 6):
            raise ValueError("%s: part %r: the offset after @ must be x;y;z, x;y;z;rx, x;y;z;rx;ry or "
                             "x;y;z;rx;ry;s" % (row["name"], part))
        ext = path.rsplit(".", 1)[1].lower()
        if path in cache:
            v, f = cache[path]
        else:
            v, f = cache[path] = read_part(row, mirror, path, ext)
        if len(offset) == 6:
            v = [(x * offset[5], y * offset[5], z * offset[5]) for x, y, z in v]
        if len(offset) >= 4:
            c, s = math.cos(math.radians(offset[3])), math.sin(math.radians(offset[3]))
            v = [(x, c * y - s * z, s * y + c * z) for x, y, z in v]
        if len(offset) >= 5:
            c, s = math.cos(math.radians(offset[4])), math.sin(math.radians(offset[4]))
            v = [(c * x + s * z, y, -s * x + c * z) for x, y, z in v]
        b = len(verts)
        verts += [(x + offset[0], y + offset[1], z + offset[2]) for x, y, z in v]
        faces += [(a + b, c + b, d + b) for a, c, d in f]
    n_source = len(faces)
    verts = transform(verts, float(row["scale"]), row["up"], float(row["yaw_deg"]))
    verts, faces = decimate(verts, faces, int(row["max_triangles"]))
    # Vertex clustering moves the extreme vertices inward by up to a cell: when that left the box
    # off the frame by more than 1 mm (coarse cells, the Chrono meshes), translate it back (a
    # finer decimation, the OpenMATERIAL truck's 5 mm, is left as it was).
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    shift = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2])
    if max(abs(c) for c in shift) > 0.001:
        verts = [(x - shift[0], y - shift[1], z - shift[2]) for x, y, z in verts]
    # Round to float32 first, so the bounding box written below is the file's own.
    verts = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in verts]
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    comments = ["canopy vehicle library: %s (%s)" % (row["name"], row["class"]),
                "source: github.com/%s %s %s" % (row["repo"], row["commit"], row["path"]),
                "transform: scale %s, up %s, yaw %s deg, bbox centred in x y, bottom z = 0" % (
                    row["scale"], row["up"], row["yaw_deg"])]
    return ply_bytes(verts, faces, comments), lo, hi, n_source, len(faces)


def split_rows(rows):
    by_class = {}
    for r in rows:
        by_class.setdefault(r["class"], []).append(r["name"])
    out = {}
    for cls, names in by_class.items():
        names.sort(key=lambda n: hashlib.sha256(n.encode()).hexdigest())
        n_test = (len(names) + 2) // 3 if len(names) >= 2 else 0
        for i, n in enumerate(names):
            out[n] = "test" if i < n_test else "modelbase"
    return [(r["name"], r["class"], out[r["name"]]) for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mirror", default="/work/.mirror")
    ap.add_argument("--out", default=os.path.join(ROOT, "share", "vehicles"))
    ap.add_argument("--table", default=os.path.join(ROOT, "share", "vehicles", "transforms.csv"))
    ap.add_argument("--only", default="")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--split", action="store_true")
    a = ap.parse_args()
    with open(a.table, newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if not a.only or r["name"] == a.only]
    if a.split:
        path = os.path.join(a.out, "split.csv")
        with open(path + ".tmp", "w", newline="") as fh:
            sw = csv.writer(fh, lineterminator="\n")
            sw.writerow(["name", "class", "split"])
            sw.writerows(split_rows(rows))
        os.replace(path + ".tmp", path)
        return 0
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["name", "class", "length_m", "width_m", "height_m", "source_triangles", "triangles"])
    bad = 0
    for r in rows:
        data, lo, hi, n_source, ntri = convert(r, a.mirror)
        path = os.path.join(a.out, r["class"], r["name"] + ".ply")
        if a.check:
            with open(path, "rb") as fh:
                if fh.read() != data:
                    print("differs: " + path, file=sys.stderr)
                    bad += 1
        else:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            tmp = path + ".tmp"
            with open(tmp, "wb") as fh:
                fh.write(data)
            os.replace(tmp, path)
        w.writerow([r["name"], r["class"], "%.3f" % (hi[0] - lo[0]), "%.3f" % (hi[1] - lo[1]),
                    "%.3f" % (hi[2] - lo[2]), n_source, ntri])
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
