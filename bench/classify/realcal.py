#!/usr/bin/env python3
"""classify's vegetation cues on real tiles: vehicles vs the rest (docs/decisions/classify.md §5).

  realcal.py OUT_REAL LABELS TILE [TILE ...] [--ini classify.ini ...] [--csv rows.csv]
             [--classify BIN --work DIR]
  realcal.py OUT_REAL LABELS TILE [TILE ...] --figures

OUT_REAL/<tile>/cands/index.json and cands/<id>/class.json (a `real-tiles` run), LABELS/<tile>.truth.json
(share/real, or bench/real/labels for the AHN4 development tiles; a tile without one has no
vehicles: a forest plot). A candidate is a **vehicle**
when its centre lies within 1.5 m (score's match radius) of a labelled vehicle's centre,
**mixed** when it lies within 1 m of a labelled footprint or 1.5 m of an uncertain object
otherwise (merged rows, parts: neither set), else **other**. Prints, per cue, the quantiles
of each set and, with --ini, what each threshold of that file keeps (vehicles) and removes
(other), cue by cue and as classify applies them. With --classify, BIN runs on every candidate
with each --ini (answers in DIR/<ini name>/<tile>/<id>.json, reused when present) and the
answers are counted: class answers (detections) on vehicles by visibility, on the rest, and per
ha on a tile without labels (every answer a false alarm; area = detect's occupied 1 m cells,
index.json "density"). Labels are read only here. --figures prints only a run's outcome per tile (recall over the
clear and all labelled vehicles, precision without the detections on uncertain objects, the
group of the matched detections, false alarms per ha on the plots; Wilson and exact Poisson 95%
intervals), as the report counts them: it reads no cue, so it is the one mode for the test tiles.
Run the cue tables on development tiles only (docs/decisions/real-tiles.md: the split).
"""
import argparse, json, math, os, subprocess, sys
from concurrent.futures import ThreadPoolExecutor
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import poisson_exact, rate

CUES = ["fill", "ground_through", "below_share", "top_roughness_rel", "top_roughness_line_rel", "late_returns",
        "plateau_share"]


def quantile(v, q):
    v = sorted(v)
    if not v:
        return float("nan")
    i = q * (len(v) - 1)
    a = int(math.floor(i))
    b = min(a + 1, len(v) - 1)
    return v[a] + (v[b] - v[a]) * (i - a)


def inside(poly, x, y):
    c = False
    for i in range(len(poly)):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % len(poly)]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            c = not c
    return c


def seg_dist(p, a, b):
    ax, ay = b[0] - a[0], b[1] - a[1]
    t = max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / (ax * ax + ay * ay or 1)))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay)


def near_footprint(poly, x, y, r):
    if inside(poly, x, y):
        return True
    return min(seg_dist((x, y), poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))) <= r


def read_ini(path):
    p = {}
    for line in open(path):
        line = line.split("#")[0].strip()
        if "=" in line:
            k, v = (s.strip() for s in line.split("=", 1))
            try:
                p[k] = float(v[:-2]) / 1000 if v.endswith("mm") else float(v)
            except ValueError:  # a word: roughness = line, by-pass = true
                p[k] = v
    return p


def rows(out, labels, tile):
    truth = os.path.join(labels, tile + ".truth.json")
    veh, unc = [], []
    if os.path.exists(truth):
        t = json.load(open(truth))
        veh = t["vehicles"]
        unc = t.get("uncertain", [])
    index = json.load(open(os.path.join(out, tile, "cands", "index.json")))
    for c in index["candidates"]:
        x, y = c["centre"][0], c["centre"][1]
        d = [math.hypot(x - v["pose"]["x"], y - v["pose"]["y"]) for v in veh]
        kind = "other"
        if d and min(d) <= 1.5:
            kind = "vehicle"
            v = veh[d.index(min(d))]
        elif any(near_footprint(v["footprint"], x, y, 1.0) for v in veh) or any(
                math.hypot(x - u["pose"]["x"], y - u["pose"]["y"]) <= 1.5 for u in unc):
            kind = "mixed"
        j = json.load(open(os.path.join(out, tile, "cands", c["id"], "class.json")))
        f = j["features"]
        r = {"tile": tile, "id": c["id"], "kind": kind, "labelled": bool(veh), "reason": j["reason"] or "", "class": j["class"] or "",
             "visibility": v.get("visibility", "") if kind == "vehicle" else "",
             "instance": v["instance"] if kind == "vehicle" else "", "spacing": (j["measured"] or {}).get("spacing"),
             "density": j["density"], "points": j["points"]}
        for k in ["fill", "ground_through", "below_share", "top_roughness", "late_returns", "top_cells",
                  "plateau_share"]:
            r[k] = f.get(k)
        r["top_roughness_rel"] = (f["top_roughness"] / j["measured"]["spacing"]
                                  if f.get("top_roughness") is not None and (f.get("top_cells") or 0) >= 3 and j["measured"] else None)
        # Along lines (classify.md §19; class.json of a binary that measures it).
        r["top_roughness_line"] = f.get("top_roughness_line")
        r["top_roughness_line_rel"] = (f["top_roughness_line"] / j["measured"]["spacing"]
                                       if f.get("top_roughness_line") is not None and (f.get("top_cells_line") or 0) >= 3
                                       and j["measured"] else None)
        yield r


def veg_reason(r, p):
    """classify's vegetation() with the thresholds of p (classify.cpp: fill first, then the worst
    of below_share, ground_through, late_returns, then roughness)."""
    if r["fill"] is not None and r["fill"] < p["min-fill"]:
        return "fill"
    worst, wv = None, 1.0
    for k, t in (("below_share", "max-below-share"), ("ground_through", "max-ground-through"),
                 ("late_returns", "max-late-returns")):
        if r[k] is not None and r[k] > p[t] and r[k] / p[t] > wv:
            worst, wv = k, r[k] / p[t]
    if worst:
        return worst
    line = p.get("roughness", "plane") == "line"
    key, rel = ("top_roughness_line", "top_roughness_line_rel") if line else ("top_roughness", "top_roughness_rel")
    if r[rel] is not None and r[key] > max(p.get("roughness-floor", 0.1), p["max-roughness"] * r["spacing"]):
        return key
    if p.get("min-plateau", 0) > 0 and r["plateau_share"] < p["min-plateau"]:
        return "no roof (plateau_share)"
    return ""


def run_classify(binary, out, tile, ini, work):
    index = os.path.join(out, tile, "cands", "index.json")
    dest = os.path.join(work, os.path.splitext(os.path.basename(ini))[0], tile)
    os.makedirs(dest, exist_ok=True)
    jobs = []
    for c in json.load(open(index))["candidates"]:
        o = os.path.join(dest, c["id"] + ".json")
        if not os.path.exists(o):
            jobs.append([binary, "-q", "--config", ini, "-i", os.path.join(out, tile, "cands", c["file"]),
                         "--index", index, "-o", o])
    with ThreadPoolExecutor(2) as ex:
        for r in ex.map(lambda cmd: subprocess.run(cmd, capture_output=True, text=True), jobs):
            if r.returncode != 0:
                sys.exit("classify failed: " + " ".join(r.args) + "\n" + r.stderr)
    return dest


def count_answers(a, rs, ini):
    by_tile = {}
    for r in rs:
        by_tile.setdefault(r["tile"], []).append(r)
    print(f"\nclassify --config {ini}: class answers (detections)")
    for tile, trs in by_tile.items():
        dest = run_classify(a.classify, a.out, tile, ini, a.work)
        why = {}
        for r in trs:
            j = json.load(open(os.path.join(dest, r["id"] + ".json")))
            r["new_class"] = j["class"] or ""
            key = (r["kind"], r["visibility"])
            why.setdefault(key, {})
            w = j["reason"] or "class"
            why[key][w] = why[key].get(w, 0) + 1
        for key, w in sorted(why.items()):
            n = sum(w.values())
            print(f"  {tile} {key[0]} {key[1]}: class {rate(w.get('class', 0), n)}; " +
                  ", ".join(f"{k} {v}" for k, v in sorted(w.items()) if k != "class"))
        if not os.path.exists(os.path.join(a.labels, tile + ".truth.json")):
            x = json.load(open(os.path.join(a.out, tile, "cands", "index.json")))
            area = x["density"]["cell"] ** 2 * x["density"]["occupied_cells"] / 1e4
            k = sum(1 for r in trs if r["new_class"])
            lo, hi = poisson_exact(k)
            print(f"  {tile}: {k} false alarms on {area:.2f} ha = {k / area:.2f}/ha [{lo / area:.2f}, {hi / area:.2f}]")


GROUP = {"sedan": "car", "hatchback": "car", "suv": "car", "pickup": "car", "van": "van",
         "box-truck": "truck", "semi-tractor": "truck", "bus": "bus", "wheeled-apc": "machine",
         "tracked-apc": "tracked", "tank": "tracked", "wheel-loader": "machine"}



def tile_outcome(d, truth):
    """One urban tile's figures from its run directory d (score.json) and labels: [k, n] pairs of
    clear recall, all recall, precision (detections on uncertain objects left out) and class right."""
    t = json.load(open(truth))
    clear = {v["instance"]: v.get("visibility") == "clear" for v in t["vehicles"]}
    unc = [(u["pose"]["x"], u["pose"]["y"]) for u in t.get("uncertain", [])]
    sc = json.load(open(os.path.join(d, "score.json")))
    radius = sc["params"]["match_radius_m"]
    matched, tp, dets, fp_unc, cls = set(), 0, 0, 0, [0, 0]
    for m in sc["matches"]:
        if m["outcome"] == "missed":
            continue
        dets += 1
        if m["outcome"] == "false_alarm":
            fp_unc += any(math.hypot(m["x"] - x, m["y"] - y) <= radius for x, y in unc)
            continue
        tp += 1
        matched.add(m["instance"])
        g = GROUP.get(m.get("class") or "", "")
        if g:
            cls[1] += 1
            cls[0] += g == m["true_model"]
    nc = sum(clear.values())
    kc = sum(1 for i in matched if clear[i])
    return {"clear": [kc, nc], "all": [len(matched), len(clear)], "prec": [tp, dets - fp_unc], "cls": cls}

def figures(out, labels, tiles):
    """The outcome of a run, as the report's "Real tiles" section counts it (tools/report/
    real_section.cpp): from score.json and the labels (urban) or detections.json (plots).
    Reads no cue: safe on the test tiles."""
    tot = {"clear": [0, 0], "all": [0, 0], "prec": [0, 0], "cls": [0, 0], "fa": 0, "ha": 0.0}
    print("| tile | clear recall | all recall | precision | class right | forest false alarms |")
    print("|---|---|---|---|---|---|")
    for tile in tiles:
        truth = os.path.join(labels, tile + ".truth.json")
        d = os.path.join(out, tile)
        if not os.path.exists(os.path.join(d, "detections.json")):
            print(f"| {tile} | not finished | | | | |")
            continue
        if not os.path.exists(truth):
            x = json.load(open(os.path.join(d, "cands", "index.json")))
            area = x["density"]["cell"] ** 2 * x["density"]["occupied_cells"] / 1e4
            k = len(json.load(open(os.path.join(d, "detections.json")))["detections"])
            lo, hi = poisson_exact(k)
            tot["fa"] += k
            tot["ha"] += area
            print(f"| {tile} | | | | | {k} on {area:.2f} ha = {k / area:.2f}/ha [{lo / area:.2f}, {hi / area:.2f}] |")
            continue
        row = tile_outcome(d, truth)
        cls = row["cls"]
        for k, v in row.items():
            tot[k][0] += v[0]
            tot[k][1] += v[1]
        print(f"| {tile} | {rate(*row['clear'])} | {rate(*row['all'])} | {rate(*row['prec'])} | {rate(*cls)} | |")
    fa = ""
    if tot["ha"] > 0:
        lo, hi = poisson_exact(tot["fa"])
        fa = f"{tot['fa']} on {tot['ha']:.2f} ha = {tot['fa'] / tot['ha']:.2f}/ha [{lo / tot['ha']:.2f}, {hi / tot['ha']:.2f}]"
    print(f"| **all** | {rate(*tot['clear'])} | {rate(*tot['all'])} | {rate(*tot['prec'])} | {rate(*tot['cls'])} | {fa} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("labels")
    ap.add_argument("tiles", nargs="+")
    ap.add_argument("--ini", action="append", default=[])
    ap.add_argument("--csv")
    ap.add_argument("--classify")
    ap.add_argument("--work")
    ap.add_argument("--figures", action="store_true",
                    help="only the run's outcome (score.json, detections.json): no cue is read")
    a = ap.parse_args()
    if a.figures:
        figures(a.out, a.labels, a.tiles)
        return
    if bool(a.classify) != bool(a.work):
        ap.error("--classify and --work go together")
    rs = [r for t in a.tiles for r in rows(a.out, a.labels, t)]
    if a.csv:
        keys = list(rs[0].keys())
        with open(a.csv, "w") as o:
            o.write(",".join(keys) + "\n")
            for r in rs:
                o.write(",".join("" if r[k] is None else str(r[k]) for k in keys) + "\n")
    sets = {"vehicle (clear)": [r for r in rs if r["kind"] == "vehicle" and r["visibility"] == "clear"],
            "vehicle (clear+partial)": [r for r in rs if r["kind"] == "vehicle" and r["visibility"] != "occluded"],
            "vehicle (all)": [r for r in rs if r["kind"] == "vehicle"],
            "mixed": [r for r in rs if r["kind"] == "mixed"],
            "other, urban": [r for r in rs if r["kind"] == "other" and r["labelled"]],
            "other, forest": [r for r in rs if r["kind"] == "other" and not r["labelled"]]}
    # The cues are read only where classify reaches them: past too_sparse.
    live = {k: [r for r in v if r["reason"] != "too_sparse"] for k, v in sets.items()}
    print("candidates: " + ", ".join(f"{k} {len(v)} ({len(live[k])} past too_sparse)" for k, v in sets.items()))
    qs = [0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.95, 0.99]
    print("\n| cue | set | n | " + " | ".join(f"{int(q * 100)}%" for q in qs) + " |")
    print("|---|---|---|" + "---|" * len(qs))
    for cue in CUES:
        for k, v in live.items():
            vals = [r[cue] for r in v if r[cue] is not None]
            print(f"| {cue} | {k} | {len(vals)} | " + " | ".join(f"{quantile(vals, q):.3f}" for q in qs) + " |")
    for ini in a.ini:
        p = read_ini(ini)
        print(f"\n{ini}: the cues alone per set (the first failing cue in classify's order; no size gate)")
        for k, v in live.items():
            why = {}
            for r in v:
                w = veg_reason(r, p)
                why[w] = why.get(w, 0) + 1
            kept = why.get("", 0)
            print(f"  {k}: passes {rate(kept, len(v))}; removed by " +
                  ", ".join(f"{w} {n}" for w, n in sorted(why.items()) if w))
        if a.classify:
            count_answers(a, rs, ini)


if __name__ == "__main__":
    main()
