#!/usr/bin/env python3
"""Issue 26: what a LAS file would carry for a simulated candidate (docs/decisions/verify.md,
"Sensor directions from what LAS has").

rangetrace's tile images are orthographic: every point of image k was seen along the image's
direction s_k (truth.json "images": toward_sensor, flight heading). A real airborne file has no
s, only GPS time, scan angle and flight line, so this script gives each sample of a candidate
(fitvox samples, local frame, with the true sensor_x/y/z) the LAS columns of a notional scanner
that saw it along the same ray:
  - image k is flown as its own flight line (point_source_id k + 1) at `altitude` above the
    tile's ground, heading psi_k, f = (cos psi, sin psi, 0), right r = (sin psi, -cos psi, 0);
  - the sensor that saw point p sat on p's ray at that altitude: S = p + s (H - p_z) / s_z;
  - gps_time = T0 + 1000 k + (S . f) / 50 m/s (time runs along the flight line);
  - scan_angle = atan2(-s . r, s . z) in degrees, LAS's sense (positive to the right of the
    flight), rounded to LAS 1.4's 0.006 deg steps.
The trajectory file holds, for each image, the straight line S(t) = f v (t - T0 - 1000 k) +
r c_k + H z with c_k = the cross-track position of the sensor above the tile centre's ray
((centre + s H / s_z) . r): exact for points on the tile centre's ray, off by the point's
cross-track distance from it over the range (<= ~2 deg on a 16 m tile at 300 m) elsewhere,
because a real sensor is a point and the simulator's is at infinity.

usage: synth_las.py SAMPLES.pcd(ascii) INDEX.json CANDIDATE_ID TRUTH.json OUT.pcd [TRAJ.txt]
"""
import json
import math
import sys

T0 = 300000.0
SPEED = 50.0
ALTITUDE = 300.0


def read_ascii_pcd(path):
    fields, types, sizes, rows = [], [], [], []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        w = lines[i].split()
        i += 1
        if not w or w[0].startswith("#"):
            continue
        if w[0] == "FIELDS":
            fields = w[1:]
        elif w[0] == "TYPE":
            types = w[1:]
        elif w[0] == "SIZE":
            sizes = w[1:]
        elif w[0] == "DATA":
            if w[1] != "ascii":
                sys.exit(path + ": need DATA ascii (fitvox --pcd-encoding ascii)")
            break
    for line in lines[i:]:
        if line.strip():
            rows.append([float(v) for v in line.split()])
    return fields, types, sizes, rows


def write_ascii_pcd(path, fields, types, sizes, rows):
    with open(path, "w") as f:
        f.write("# synth_las.py: LAS columns for a simulated candidate (issue 26)\n")
        f.write("VERSION 0.7\nFIELDS " + " ".join(fields) + "\nSIZE " + " ".join(sizes) + "\nTYPE " +
                " ".join(types) + "\nCOUNT " + " ".join("1" for _ in fields) + "\nWIDTH %d\nHEIGHT 1\n"
                "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA ascii\n" % (len(rows), len(rows)))
        for r in rows:
            f.write(" ".join(repr(v) if isinstance(v, float) else str(v) for v in r) + "\n")


def main():
    samples, index_path, cand_id, truth_path, out = sys.argv[1:6]
    traj = sys.argv[6] if len(sys.argv) > 6 else None
    fields, types, sizes, rows = read_ascii_pcd(samples)
    index = json.load(open(index_path))
    truth = json.load(open(truth_path))
    cand = next(c for c in index["candidates"] if c["id"] == cand_id)
    T = cand["transform"]
    R = [row[:3] for row in T[:3]]
    t = [row[3] for row in T[:3]]
    ex, ey = truth["extent"] if isinstance(truth["extent"], list) else (truth["extent"]["x"], truth["extent"]["y"])
    centre = (ex / 2, ey / 2, 0.0)
    images = truth["images"]

    def dot(a, b):
        return sum(x * y for x, y in zip(a, b))

    def rot(v):
        return [dot(R[i], v) for i in range(3)]

    geo = []
    for im in images:
        psi = math.radians(im["heading"])
        f = (math.cos(psi), math.sin(psi), 0.0)
        r = (math.sin(psi), -math.cos(psi), 0.0)
        s = im["toward_sensor"]
        c = dot([centre[i] + s[i] * ALTITUDE / s[2] for i in range(3)], r)
        geo.append((f, r, s, c))

    ix = [fields.index(n) for n in ("x", "y", "z")]
    isx = [fields.index(n) for n in ("sensor_x", "sensor_y", "sensor_z")]
    keep = [k for k in range(len(fields)) if k not in isx]
    out_rows = []
    for row in rows:
        p = [a + b for a, b in zip(rot([row[k] for k in ix]), t)]
        s = rot([row[k] for k in isx])
        n = math.sqrt(dot(s, s))
        s = [v / n for v in s]
        k = max(range(len(geo)), key=lambda j: dot(s, geo[j][2]))
        f, r, _, _ = geo[k]
        lam = (ALTITUDE - p[2]) / s[2]
        S = [p[i] + s[i] * lam for i in range(3)]
        gps = T0 + 1000.0 * k + dot(S, f) / SPEED
        angle = math.degrees(math.atan2(-dot(s, r), s[2]))
        angle = round(angle / 0.006) * 0.006
        out_rows.append([row[j] for j in keep] + [gps, angle, k + 1])
    write_ascii_pcd(out, [fields[j] for j in keep] + ["gps_time", "scan_angle", "point_source_id"],
                    [types[j] for j in keep] + ["F", "F", "U"], [sizes[j] for j in keep] + ["8", "4", "2"],
                    out_rows)
    if traj:
        with open(traj, "w") as fo:
            fo.write("# canopy trajectory 1\n# synth_las.py: one straight line per image of %s\n" % truth_path)
            fo.write("time x y z roll pitch heading\n")
            for k, (f, r, s, c) in enumerate(geo):
                heading = math.degrees(math.atan2(f[1], f[0]))
                for a in range(-500, 501, 20):
                    time = T0 + 1000.0 * k + a / SPEED
                    pos = [f[i] * a + r[i] * c + (ALTITUDE if i == 2 else 0) for i in range(3)]
                    # + 0.0: no negative zero (the reader refuses "-0.0")
                    fo.write("%r %r %r %r 0 0 %r\n" % (time + 0.0, pos[0] + 0.0, pos[1] + 0.0, pos[2] + 0.0,
                                                        heading + 0.0))


if __name__ == "__main__":
    main()
