#!/usr/bin/env python3
"""Where each vehicle of a ladder tile is lost: detect's pieces (pieces.py) and classify's answer.

  loss.py RUN [RUN ...] [--tag TAG] [--bin build/bin] [--classify-ini share/params/classify-sim.ini]
          [--modelbase DIR] [--model-classes share/models/classes.csv] [--list]

Each RUN is a directory of bench/detect/pieces.sh (scan.pcd with label and instance, truth.json,
cands-TAG/ from detect). classify runs on every candidate of cands-TAG (the ladder's class level:
class-TAG/<id>.json, made once) and each vehicle gets one fate, the first that applies:

  found         a class answer whose position (pose_tile) lies within 1.5 m of the vehicle's
                centre (score's match radius; nearest vehicle first, one answer per vehicle)
  no_candidate  no candidate holds >= 50% of its points (pieces.py's "missed")
  merged        a candidate holds >= 50% of it and >= 50% of another vehicle
  pieces        candidates hold parts of it, none >= 80%
  refused:<why> a candidate holds >= 80% of it (whole) and classify answers none (its reason)
  off_centre    whole and answered, but the answer lies more than 1.5 m off the vehicle's centre
                (something beside it joined its candidate)

The model level (fitvox ... gmatch, objects of >= 50 points/m²) is not run: at 10-50 points/m²
a ladder vehicle's answer is classify's (density-ladder.md). Per level and cover: the fates
with counts; recall = found / vehicles with a 95% Wilson interval (bench/rates.py); candidates
and candidates on no vehicle; false alarms (class answers that took no vehicle) per ha of the
tiles' extent, by the kind of the nearest clutter object within 1.5 m ("none": no clutter object
there: vegetation, or a piece of a vehicle answered off its centre). Truth is read only here.
"""
import argparse, collections, json, math, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, ".."))
sys.path.insert(0, os.path.join(here, "..", "classify"))
sys.path.insert(0, here)
from rates import rate  # noqa: E402
from pieces import held_by  # noqa: E402  (per candidate, the vehicles' points in its crop)

src = os.path.abspath(os.path.join(here, "..", ".."))


def classify_all(run, tag, a):
    index = json.load(open(os.path.join(run, "cands-" + tag, "index.json")))
    out = os.path.join(run, "class-" + tag)
    os.makedirs(out, exist_ok=True)
    verdicts = {}
    for c in index["candidates"]:
        v = os.path.join(out, c["id"] + ".json")
        if not os.path.exists(v) or os.path.getmtime(v) < os.path.getmtime(
                os.path.join(run, "cands-" + tag, "index.json")):
            subprocess.run([os.path.join(a.bin, "classify"), "-q", "--config", a.classify_ini,
                            "-i", os.path.join(run, "cands-" + tag, c["id"] + ".pcd"),
                            "--index", os.path.join(run, "cands-" + tag, "index.json"),
                            "--modelbase", a.modelbase, "--model-classes", a.model_classes,
                            "-o", v], check=True)
        verdicts[c["id"]] = json.load(open(v))
    return index, verdicts


def run_tile(run, tag, a):
    truth = json.load(open(os.path.join(run, "truth.json")))
    index, verdicts = classify_all(run, tag, a)
    total, held = held_by(index, run)
    cands = index["candidates"]
    # score's matching, simplified: answers by falling confidence take the nearest free vehicle
    # within 1.5 m.
    answers = []
    for k, c in enumerate(cands):
        v = verdicts[c["id"]]
        if v.get("class"):
            tr = v["pose_tile"]["translation"]
            answers.append((-(v.get("confidence") or 0), c["id"], k, tr[0], tr[1]))
    answers.sort()
    found = {}
    for _, cid, k, x, y in answers:
        best, bd = None, 1.5
        for tv in truth["vehicles"]:
            i = tv["instance"]
            if i in found:
                continue
            d = math.hypot(x - tv["pose"]["x"], y - tv["pose"]["y"])
            if d <= bd:
                best, bd = i, d
        if best is not None:
            found[best] = k
    rows = []
    for tv in truth["vehicles"]:
        i = tv["instance"]
        tot = total.get(i, 0)
        share = [(h.get(i, 0) / tot if tot else 0.0, k) for k, h in enumerate(held)]
        best, bk = max(share) if share else (0.0, -1)
        others = lambda k: [o for o in held[k] if o != i and total[o] and held[k][o] / total[o] >= 0.5]
        if i in found:
            fate = "found"
        elif best < 0.5:
            fate = "no_candidate"
        elif any(s >= 0.5 and others(k) for s, k in share):
            fate = "merged"
        elif best < 0.8:
            fate = "pieces"
        else:
            v = verdicts[cands[bk]["id"]]
            fate = "off_centre" if v.get("class") else "refused:" + str(v.get("reason"))
        bc = cands[bk] if bk >= 0 and best > 0 else None
        bv = verdicts[bc["id"]] if bc else {}
        rows.append({"tile": os.path.basename(run), "instance": i, "model": tv["model"], "points": tot,
                     "cover": round(tv.get("canopy_cover", 0), 2), "fate": fate, "best": round(best, 2),
                     "cand": bc["id"] if bc else "-", "cand_size": (bc["length"], bc["width"], bc["height"])
                     if bc else (0, 0, 0), "answer": bv.get("class") or bv.get("reason") or "-",
                     "detail": bv.get("detail") or "",
                     "pieces": [(round(s, 2), cands[k]["id"]) for s, k in share if s >= 0.1]})
    none = sum(1 for h in held if not any(total[o] and n / total[o] >= 0.1 for o, n in h.items()))
    # False alarms: class answers that took no vehicle, by the kind of the nearest clutter object
    # within 1.5 m of the answer ("none": no clutter object there, e.g. vegetation).
    used = set(found.values())
    alarms = []
    for _, cid, k, x, y in answers:
        if k in used:
            continue
        kind, bd = "none", 1.5
        for cl in truth.get("clutter", []):
            cx, cy = cl["box"]["centre"][:2]
            d = math.hypot(x - cx, y - cy)
            if d <= bd:
                kind, bd = cl["kind"], d
        alarms.append(kind)
    area = truth["extent"][0] * truth["extent"][1] / 1e4
    return rows, len(cands), none, alarms, area


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--tag", default="default")
    ap.add_argument("--bin", default=os.path.join(src, "build", "bin"))
    ap.add_argument("--classify-ini", default=os.path.join(src, "share", "params", "classify-sim.ini"))
    ap.add_argument("--modelbase", required=True)
    ap.add_argument("--model-classes", default=os.path.join(src, "share", "models", "classes.csv"))
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    groups = collections.OrderedDict()
    for run in a.runs:
        level, cover = os.path.basename(run).split("-")[:2]
        r, c, n, fa, area = run_tile(run, a.tag, a)
        g = groups.setdefault((level, cover), {"rows": [], "cands": 0, "none": 0, "alarms": [], "ha": 0.0})
        g["rows"] += r
        g["cands"] += c
        g["none"] += n
        g["alarms"] += fa
        g["ha"] += area
        if a.list:
            for x in r:
                sz = "x".join(f"{s:.1f}" for s in x["cand_size"])
                print(f"{x['tile']:16s} {x['instance']:2d} {x['model']:10s} pts {x['points']:5d} cover "
                      f"{x['cover']:.2f} {x['fate']:28s} best {x['best']:.2f} {x['cand']} ({sz}) "
                      f"{x['answer']} {x['pieces']}")
    fates = sorted({x["fate"] for g in groups.values() for x in g["rows"]})
    print("| level | cover | vehicles | found (recall) | " + " | ".join(fates) +
          " | candidates (on no vehicle) | false alarms (per ha; by clutter kind) |")
    print("|---|---|---|---|" + "---|" * len(fates) + "---|---|")
    for (level, cover), g in groups.items():
        rows = g["rows"]
        cnt = collections.Counter(x["fate"] for x in rows)
        print(f"| {level} | {cover} | {len(rows)} | {rate(cnt['found'], len(rows))} | " +
              " | ".join(str(cnt[f]) for f in fates) + f" | {g['cands']} ({g['none']}) | " +
              f"{len(g['alarms'])} ({len(g['alarms']) / g['ha']:.1f}/ha; " +
              ", ".join(f"{k} {v}" for k, v in sorted(collections.Counter(g['alarms']).items())) + ") |")


if __name__ == "__main__":
    main()
