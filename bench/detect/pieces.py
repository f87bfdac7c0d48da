#!/usr/bin/env python3
"""Vehicles in pieces and vehicles merged: detect's candidates against a rendered tile's truth.

  pieces.py RUN [RUN ...] [--tag TAG] [--list]

Each RUN directory holds scan.pcd (rangetrace's tile, with label and instance fields),
truth.json and cands-TAG/index.json (detect's output). For every candidate, the vehicle points
inside its crop box (footprint + the index's margin, from -margin to height + margin in the
candidate's frame: what candtruth counts) are counted per vehicle. Per vehicle:

  whole   a candidate holds >= 80% of its points and no other vehicle's >= 50% (one candidate,
          no neighbour merged in)
  merged  a candidate holds >= 50% of it and >= 50% of another vehicle
  pieces  candidates holding >= 10% of it that hold less than 80% of it (parts)
  missed  no candidate holds >= 50% of it
  long    whole, but the candidate is more than 1 m longer than the vehicle (something merged in)

Prints one line per vehicle with --list, then per model and in all: whole / vehicles with a 95%
Wilson interval, merged, in pieces, missed, long; and the candidates on no vehicle (holding
< 10% of every vehicle).
Truth is read only here (evaluation; detect never reads it).
"""
import argparse, json, math, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "classify"))
from pcdlabels import read_pcd  # noqa: E402


def wilson(k, n, z=1.96):
    if n == 0:
        return (0.0, 100.0)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (100 * max(0.0, c - h), 100 * min(1.0, c + h))


def held_by(index, run):
    """Per candidate: {instance: vehicle points inside its crop box} (candtruth's count)."""
    cols = read_pcd(os.path.join(run, "scan.pcd"), ["x", "y", "z", "label", "instance"])
    margin = index["margin"]
    veh = {}
    for x, y, z, lab, inst in zip(cols["x"], cols["y"], cols["z"], cols["label"], cols["instance"]):
        if inst > 0 and lab == 1:
            veh.setdefault(int(inst), []).append((x, y, z))
    total = {v: len(p) for v, p in veh.items()}
    held = []
    for c in index["candidates"]:
        t = c["transform"]
        hx, hy, top = 0.5 * c["length"] + margin, 0.5 * c["width"] + margin, c["height"] + margin
        counts = {}
        for v, pts in veh.items():
            n = 0
            for x, y, z in pts:
                dx, dy, dz = x - t[0][3], y - t[1][3], z - t[2][3]
                lx = t[0][0] * dx + t[1][0] * dy + t[2][0] * dz
                ly = t[0][1] * dx + t[1][1] * dy + t[2][1] * dz
                lz = t[0][2] * dx + t[1][2] * dy + t[2][2] * dz
                if abs(lx) <= hx and abs(ly) <= hy and -margin <= lz <= top:
                    n += 1
            if n:
                counts[v] = n
        held.append(counts)
    return total, held


def run_tile(run, tag):
    truth = json.load(open(os.path.join(run, "truth.json")))
    index = json.load(open(os.path.join(run, "cands-" + tag, "index.json")))
    total, held = held_by(index, run)
    rows = []
    for v in truth["vehicles"]:
        i = v["instance"]
        tot = total.get(i, 0)
        share = [(h.get(i, 0) / tot if tot else 0.0, k) for k, h in enumerate(held)]
        best, bk = max(share) if share else (0.0, -1)
        others = lambda k: [o for o in held[k] if o != i and total[o] and held[k][o] / total[o] >= 0.5]
        whole = best >= 0.8 and not others(bk)
        merged = any(s >= 0.5 and others(k) for s, k in share)
        pieces = [(round(s, 2), index["candidates"][k]["length"]) for s, k in share if 0.1 <= s < 0.8]
        long_by = (index["candidates"][bk]["length"] - v["size"][0]) if bk >= 0 and best > 0 else 0.0
        rows.append({"tile": os.path.basename(run), "instance": i, "model": v["model"], "points": tot,
                     "long": whole and long_by > 1.0,
                     "cover": round(v.get("canopy_cover", 0), 2), "best": round(best, 2),
                     "best_len": index["candidates"][bk]["length"] if bk >= 0 and best > 0 else 0,
                     "whole": whole, "merged": merged, "pieces": pieces, "missed": best < 0.5})
    none = sum(1 for h in held if not any(total[o] and n / total[o] >= 0.1 for o, n in h.items()))
    return rows, len(index["candidates"]), none, index["density"]["rule"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--tag", default="default")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    rows, cands, none = [], 0, 0
    for run in a.runs:
        r, c, n, rule = run_tile(run, a.tag)
        rows += r
        cands += c
        none += n
        if a.list:
            print(f"# {run}: {c} candidates, {n} on no vehicle, voxel {rule['voxel']:.3f}, "
                  f"split_rows {rule.get('split_rows')}")
            for x in r:
                print(f"  {x['instance']:2d} {x['model']:10s} pts {x['points']:6d} cover {x['cover']:.2f} "
                      f"best {x['best']:.2f} ({x['best_len']:.1f} m) whole {int(x['whole'])} "
                      f"merged {int(x['merged'])} pieces {x['pieces']}")
    models = sorted({x["model"] for x in rows})
    print("| vehicles | whole | merged | in pieces | missed | whole but > 1 m too long |")
    print("|---|---|---|---|---|---|")
    for m in models + ["all"]:
        sel = [x for x in rows if m == "all" or x["model"] == m]
        k = sum(x["whole"] for x in sel)
        lo, hi = wilson(k, len(sel))
        print(f"| {m} ({len(sel)}) | {k}/{len(sel)} = {100 * k / len(sel):.1f}% [{lo:.1f}, {hi:.1f}] | "
              f"{sum(x['merged'] for x in sel)} | {sum(1 for x in sel if x['pieces'] and not x['whole'])} | "
              f"{sum(x['missed'] for x in sel)} | {sum(x['long'] for x in sel)} |")
    print(f"candidates {cands}, on no vehicle {none}")


if __name__ == "__main__":
    main()
