#!/usr/bin/env python3
"""Print the transforms.csv `path` of a Chrono::Vehicle tracked vehicle assembled from its meshes:
chassis, sprockets, idlers, road wheels, and the track shoes laid on a belt around them.

Usage: scripts/vehicles/track_belt.py [--mirror DIR] [--commit C] [--check-shoes]

Chrono places the track shoes at run time (the simulation wraps the chain around the wheels), so
the source has no mesh of the assembled track. This script lays it the simplest way that keeps the
source's own numbers, for the M113 of projectchrono/chrono (data/vehicle/M113, SinglePin track):

- Track assemblies at y = ±Offset (vehicle/M113_Vehicle_SinglePin.json); in each, the sprocket,
  the idler and the road wheels (suspension locations) at the locations of its
  track_assembly/*.json, the wheel centres on the assembly's line (y = ±Offset).
- The belt is the convex wrap, in the x-z plane, of circles around those centres: the sprocket's
  "Assembly Radius" (the pin circle), the idler's and road wheels' "Radius" plus half the shoe's
  "Height" (the shoe's frame is mid-pad). The real M113 has no return rollers and its upper run
  sags onto the road wheels; the wrap keeps it straight from sprocket to idler.
- "Number Shoes" shoes (63) spaced evenly along the wrap, each turned about y so its x axis
  follows the belt and its z axis (guide pins) points inward; the count against
  perimeter / "Pitch" is printed with --check-shoes.

Part syntax FILE@x;y;z;rx;ry of convert.py: turned by rx about x, then ry about y (degrees), then
translated.
"""
import argparse
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from convert import git_show  # noqa: E402  (the same mirror layout as the converter's)

REPO = "projectchrono/chrono"
BASE = "data/vehicle/"


def show(mirror, commit, path):
    text = git_show(mirror, REPO, commit, BASE + path).decode()
    text = re.sub(r"//[^\n]*", "", text)   # Chrono's JSON files carry // comments
    return json.loads(text)


def hull(points):
    pts = sorted(set(points))

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]   # counter-clockwise in (x, z)


def belt(circles, n_shoes):
    pts = []
    for cx, cz, r in circles:
        for k in range(1440):
            a = 2 * math.pi * k / 1440
            pts.append((round(cx + r * math.cos(a), 9), round(cz + r * math.sin(a), 9)))
    poly = hull(pts)
    seg = [(poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))]
    lens = [math.dist(a, b) for a, b in seg]
    perimeter = sum(lens)
    # start at the lowest point under the front wheel so the layout does not depend on the hull's
    # first vertex: the point of minimum z with maximum x
    start = max(range(len(poly)), key=lambda i: (-round(poly[i][1], 6), poly[i][0]))
    shoes, i, acc = [], start, 0.0
    step = perimeter / n_shoes
    targets = [k * step for k in range(n_shoes)]
    t = 0
    walked = 0.0
    while t < n_shoes:
        (ax, az), (bx, bz) = seg[i % len(seg)]
        L = lens[i % len(seg)]
        while t < n_shoes and targets[t] <= walked + L:
            u = (targets[t] - walked) / L if L > 0 else 0.0
            tx, tz = (bx - ax) / L, (bz - az) / L
            shoes.append((ax + u * (bx - ax), az + u * (bz - az), -math.degrees(math.atan2(tz, tx))))
            t += 1
        walked += L
        i += 1
    return shoes, perimeter


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mirror", default="/work/.mirror")
    ap.add_argument("--commit", default="7689fbc02d12c5419fa6acad8791100fd89979dd")
    ap.add_argument("--check-shoes", action="store_true")
    a = ap.parse_args()
    veh = show(a.mirror, a.commit, "M113/vehicle/M113_Vehicle_SinglePin.json")
    parts = ["data/vehicle/M113/meshes/Chassis.obj"]
    for ta_ref in veh["Track Assemblies"]:
        ta = show(a.mirror, a.commit, ta_ref["Input File"])
        y = ta_ref["Offset"]
        side = "L" if y > 0 else "R"
        spr = show(a.mirror, a.commit, ta["Sprocket"]["Input File"])
        idl = show(a.mirror, a.commit, ta["Idler"]["Input File"])
        idw = show(a.mirror, a.commit, idl["Idler Wheel Input File"])
        shoe = show(a.mirror, a.commit, ta["Track Shoes"]["Input File"])
        half = shoe["Shoe"]["Height"] / 2
        sx, _, sz = ta["Sprocket"]["Location"]
        ix, _, iz = ta["Idler"]["Location"]
        circles = [(sx, sz, spr["Profile"]["Assembly Radius"]), (ix, iz, idw["Wheel"]["Radius"] + half)]
        parts.append("%s@%g;%g;%g" % ("data/" + spr["Visualization"]["Mesh"], sx, y, sz))
        parts.append("%s@%g;%g;%g" % ("data/" + idw["Visualization"]["Mesh"], ix, y, iz))
        for s in ta["Suspension Subsystems"]:
            sus = show(a.mirror, a.commit, s["Input File"])
            rw = show(a.mirror, a.commit, sus["Road Wheel Input File"])
            x, _, z = s["Location"]
            circles.append((x, z, rw["Wheel"]["Radius"] + half))
            parts.append("%s@%g;%g;%g" % ("data/" + rw["Visualization"]["Mesh"], x, y, z))
        n = ta["Track Shoes"]["Number Shoes"]
        shoes, perimeter = belt(circles, n)
        if a.check_shoes:
            print("%s: perimeter %.3f m, %d shoes of pitch %.3f m -> %.3f m apart"
                  % (side, perimeter, n, shoe["Shoe"]["Pitch"], perimeter / n), file=sys.stderr)
        mesh = "data/vehicle/M113/meshes/TrackShoeSinglePin.obj"
        for x, z, ry in shoes:
            parts.append("%s@%.4f;%g;%.4f;0;%.2f" % (mesh, x, y, z, ry))
    print("|".join(parts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
