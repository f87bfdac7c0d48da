#!/usr/bin/env python3
"""Where each labelled vehicle of a real development tile is lost (docs/decisions/real-tiles.md
"Where the clear vehicles of ahn3_delft_1 are lost").

  realloss.py RUN LABELS TILE [--visibility clear|partial|occluded|all] [--list]

RUN/<tile>/ is a bench/detect/real.sh tile directory (cands/index.json, cands/<id>/class.json,
detections.json, score.json); LABELS/<tile>.truth.json the labels (share/real, or
bench/real/labels for the AHN4 development tiles). A real tile has
no per-point truth, so what a candidate holds is measured in the top view: the share of the
label's footprint (its rectangle of returns, sampled on a 0.1 m grid) inside the candidate's
object rectangle (centre, length, width, heading of index.json). Each vehicle gets one fate, the
first that applies:

  found          score matched a detection to it (1.5 m)
  no_candidate   no candidate covers >= 20% of its footprint
  pieces         candidates cover parts of it, none >= 60% (`pieces n`: how many cover >= 20%)
  merged         the candidate covering most of it (>= 60%) covers >= 40% of another label's
                 footprint (`merged:vehicle`), or is > 1.5 m longer or > 1 m wider than the
                 label (`merged:other`: a wall, a shrub, a bonnet)
  refused:<why>  that candidate is about the vehicle's size and classify answers none (its
                 reason's first word)
  off_centre     answered, but the answer was matched to no label or to another one

Development tiles only: it reads the labels against detect's and classify's outputs vehicle by
vehicle (never run it on the held-out tiles). Prints the count per fate, and with --list one
line per vehicle.
"""
import argparse, collections, json, math, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "classify"))
from rates import rate  # noqa: E402
from realcal import inside  # noqa: E402  (point in polygon, the labels' footprints)


def samples(poly, step=0.1):
    xs = [p[0] for p in poly]
    ys = [p[1] for p in poly]
    out = []
    y = min(ys) + step / 2
    while y < max(ys):
        x = min(xs) + step / 2
        while x < max(xs):
            if inside(poly, x, y):
                out.append((x, y))
            x += step
        y += step
    return out


def in_rect(c, x, y):
    h = c["heading"]
    dx, dy = x - c["centre"][0], y - c["centre"][1]
    u = dx * math.cos(h) + dy * math.sin(h)
    v = -dx * math.sin(h) + dy * math.cos(h)
    return abs(u) <= c["length"] / 2 and abs(v) <= c["width"] / 2


def cover(c, pts):
    return sum(in_rect(c, x, y) for x, y in pts) / max(1, len(pts))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("labels")
    ap.add_argument("tile")
    ap.add_argument("--visibility", default="clear")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    d = os.path.join(a.run, a.tile)
    truth = json.load(open(os.path.join(a.labels, a.tile + ".truth.json")))
    index = json.load(open(os.path.join(d, "cands", "index.json")))
    score = json.load(open(os.path.join(d, "score.json")))
    cands = index["candidates"]
    found = {m["instance"] for m in score["matches"] if m["outcome"] not in ("missed", "false_alarm")}
    veh = truth["vehicles"]
    pts = {v["instance"]: samples(v["footprint"]) for v in veh}
    fates = collections.Counter()
    lines = []
    n = 0
    for v in veh:
        if a.visibility != "all" and v.get("visibility") != a.visibility:
            continue
        n += 1
        i = v["instance"]
        L, W = v["size"][0], v["size"][1]
        cov = sorted(((cover(c, pts[i]), c) for c in cands if
                      math.hypot(c["centre"][0] - v["pose"]["x"], c["centre"][1] - v["pose"]["y"]) < 30),
                     key=lambda t: -t[0])
        best_cov, best = cov[0] if cov else (0.0, None)
        detail = ""
        if i in found:
            fate = "found"
        elif best_cov < 0.2:
            fate = "no_candidate"
        elif best_cov < 0.6:
            fate = "pieces"
            detail = f"{sum(1 for k, _ in cov if k >= 0.2)} pieces"
        else:
            others = [w["instance"] for w in veh if w["instance"] != i and
                      math.hypot(w["pose"]["x"] - v["pose"]["x"], w["pose"]["y"] - v["pose"]["y"]) < 20 and
                      cover(best, pts[w["instance"]]) >= 0.4]
            j = json.load(open(os.path.join(d, "cands", best["id"], "class.json")))
            if others:
                fate = "merged:vehicle"
                detail = "with #" + ",#".join(str(o) for o in others)
            elif best["length"] > L + 1.5 or best["width"] > W + 1.0:
                fate = "merged:other"
            elif j.get("class"):
                fate = "off_centre"
                detail = f"answered {j['class']}"
            else:
                fate = "refused:" + (j.get("reason") or "?").split()[0]
                detail = (j.get("reason") or "")[:90]
        fates[fate] += 1
        bc = (f"{best['id']} {best['length']:.1f}x{best['width']:.1f}x{best['height']:.1f} cov {best_cov:.2f}"
              if best else "-")
        lines.append(f"#{i} {v.get('visibility')} {v['model']} {L:.1f}x{W:.1f}x{v['size'][2]:.1f} "
                     f"pts {v.get('points')}: {fate} | best {bc} | {detail}")
    if a.list:
        print("\n".join(lines))
    print(f"{a.tile} ({a.visibility}, {n} vehicles): found {rate(fates['found'], n)}")
    for f, k in sorted(fates.items(), key=lambda t: -t[1]):
        if f != "found":
            print(f"  {f}: {k}")


if __name__ == "__main__":
    main()
