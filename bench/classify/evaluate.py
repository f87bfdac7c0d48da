#!/usr/bin/env python3
"""classify on rendered tiles: per tile, detect's candidates -> classify -> compared with truth.json.

  evaluate.py BIN RUN_DIR [RUN_DIR ...] [--csv rows.csv] [--classify-args "..."] [--reuse]

Each RUN_DIR holds cands/ (detect's output, index.json with truth) and truth.json (rangetrace's
canopy.scene_truth). classify runs on every candidate (RUN_DIR/verdicts/<id>.json) unless
--reuse. Prints the counts with 95% Wilson intervals (docs/decisions/classify.md §6).

Truth is read only here, never by classify: a candidate belongs to the vehicle instance its
index truth names when that instance holds >= half of the candidate's object points.
"""
import json, math, os, subprocess, sys, argparse, statistics
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from pcdlabels import majority_label
from rates import rate
from concurrent.futures import ThreadPoolExecutor

GROUP = {"sedan": "car", "hatchback": "car", "suv": "car", "pickup": "car", "van": "van",
         "box-truck": "truck", "semi-tractor": "truck", "bus": "bus", "wheeled-apc": "machine",
         "tracked-apc": "tracked", "tank": "tracked", "wheel-loader": "machine"}


def fold180(d):
    d = abs(d) % 180
    return min(d, 180 - d)


def classify_run(binary, run, extra, reuse):
    index = json.load(open(os.path.join(run, "cands", "index.json")))
    os.makedirs(os.path.join(run, "verdicts"), exist_ok=True)
    jobs = []
    for c in index["candidates"]:
        out = os.path.join(run, "verdicts", c["id"] + ".json")
        if reuse and os.path.exists(out):
            continue
        cmd = [binary, "-q", "-i", os.path.join(run, "cands", c["file"]), "--index",
               os.path.join(run, "cands", "index.json"), "-o", out] + extra
        jobs.append(cmd)
    with ThreadPoolExecutor(2) as ex:
        for r in ex.map(lambda cmd: subprocess.run(cmd, capture_output=True, text=True), jobs):
            if r.returncode != 0:
                sys.exit("classify failed: " + " ".join(r.args) + "\n" + r.stderr)
    return index


def rows_of(run, index):
    truth = json.load(open(os.path.join(run, "truth.json")))
    vehicles = {v["instance"]: v for v in truth["vehicles"]}
    rows = []
    for c in index["candidates"]:
        v = json.load(open(os.path.join(run, "verdicts", c["id"] + ".json")))
        t = c.get("truth")
        inst = t["instance"] if t and t["purity"] >= 0.5 else None
        tv = vehicles.get(inst) if inst else None
        row = {"run": run, "id": c["id"], "instance": inst,
               "true_class": tv.get("class") if tv else None,
               "true_size": tv["size"] if tv else None,
               "true_heading": tv["pose"]["heading"] if tv else None,
               "coverage": t["coverage"] if t else None,
               "cover": tv.get("canopy_cover") if tv else None,
               "class": v["class"], "group": v["group"], "reason": v["reason"], "detail": v["detail"],
               "confidence": v["confidence"], "density": v["density"], "points": v["points"],
               "size": v["size"], "measured": v["measured"], "features": v["features"],
               "heading": v["pose_tile"]["heading_deg"] if v["pose_tile"] else None,
               "xy": v["pose_tile"]["translation"][:2] if v["pose_tile"] else None,
               "true_xy": [tv["pose"]["x"], tv["pose"]["y"]] if tv else None,
               "label": majority_label(os.path.join(run, "cands", c["file"])) if inst is None else 1}
        if v["measured"]:
            # heading of the measured rectangle in the tile, for pose errors of every candidate
            T = c["transform"]
            th = math.atan2(T[1][0], T[0][0]) if isinstance(T[0], list) else math.atan2(T[4], T[0])
            row["heading_any"] = math.degrees(th) + v["measured"]["heading_deg"]
            row["heading_refined"] = math.degrees(th) + v["features"]["heading_refined_deg"]
            row["heading_pca"] = math.degrees(th) + v["features"]["heading_pca_deg"]
            row["heading_hull"] = math.degrees(th) + v["features"]["heading_hull_deg"]
        rows.append(row)
    return rows, vehicles


def summarise(all_rows, all_vehicles, label=""):
    nveh = sum(len(v) for v in all_vehicles.values())
    by_inst = {}
    for r in all_rows:
        if r["instance"] is not None:
            by_inst.setdefault((r["run"], r["instance"]), []).append(r)
    covered = len(by_inst)
    found = grp = cls = 0
    herr, herr_pca, herr_hull, herr_ref, lerr, werr, herr_all, perr = [], [], [], [], [], [], [], []
    missed_reasons = {}
    confusion = {}
    for key, rs in by_inst.items():
        # the candidate with the most of the vehicle (largest coverage) stands for it
        rs.sort(key=lambda r: -(r["coverage"] or 0))
        best = next((r for r in rs if r["class"]), None)
        tg = GROUP.get(rs[0]["true_class"])
        if best:
            found += 1
            grp += best["group"] == tg
            cls += best["class"] == rs[0]["true_class"]
            confusion[(tg, best["group"])] = confusion.get((tg, best["group"]), 0) + 1
            herr.append(fold180(best["heading"] - best["true_heading"]))
            perr.append(math.dist(best["xy"], best["true_xy"]))
            lerr.append(best["size"][0] - best["true_size"][0])
            werr.append(best["size"][1] - best["true_size"][1])
        else:
            r0 = rs[0]
            missed_reasons[r0["reason"]] = missed_reasons.get(r0["reason"], 0) + 1
            confusion[(tg, None)] = confusion.get((tg, None), 0) + 1
        r0 = rs[0]
        if "heading_any" in r0 and (r0["coverage"] or 0) >= 0.8:
            herr_all.append(fold180(r0["heading_any"] - r0["true_heading"]))
            herr_pca.append(fold180(r0["heading_pca"] - r0["true_heading"]))
            herr_hull.append(fold180(r0["heading_hull"] - r0["true_heading"]))
            herr_ref.append(fold180(r0["heading_refined"] - r0["true_heading"]))
    false = [r for r in all_rows if r["instance"] is None and r["class"]]
    names = {2: "vegetation", 4: "clutter", 3: "ground", 1: "vehicle"}
    kinds = {}
    for r in all_rows:
        if r["instance"] is None:
            k = names.get(r["label"], str(r["label"]))
            tot, fa = kinds.get(k, (0, 0))
            kinds[k] = (tot + 1, fa + (1 if r["class"] else 0))
    nonveh = [r for r in all_rows if r["instance"] is None]
    dup = sum(max(0, sum(1 for r in rs if r["class"]) - 1) for rs in by_inst.values())
    print(f"== {label}: {len(all_vehicles)} tiles, {nveh} vehicles, {len(all_rows)} candidates")
    print(f"  vehicles with a candidate: {rate(covered, nveh)}")
    print(f"  found as vehicles (of covered): {rate(found, covered)}; of all: {rate(found, nveh)}")
    print(f"  group right (of found): {rate(grp, found)}; class right: {rate(cls, found)}")
    if herr:
        print(f"  heading error (found, mod 180): median {statistics.median(herr):.1f} deg, "
              f"p90 {sorted(herr)[int(0.9 * (len(herr) - 1))]:.1f}; within 5 deg {rate(sum(h <= 5 for h in herr), len(herr))}")
        print(f"  length error median {statistics.median(lerr):+.2f} m, width {statistics.median(werr):+.2f} m; "
              f"position error median {statistics.median(perr):.2f} m, p90 {sorted(perr)[int(0.9 * (len(perr) - 1))]:.2f} m")
    if herr_all:
        p90 = lambda v: sorted(v)[int(0.9 * (len(v) - 1))]
        print(f"  heading of every candidate with coverage >= 0.8 (n={len(herr_all)}), median / p90: "
              f"min-area rectangle {statistics.median(herr_hull):.2f} / {p90(herr_hull):.1f}, "
              f"two-line refinement {statistics.median(herr_ref):.2f} / {p90(herr_ref):.1f}, "
              f"principal axis {statistics.median(herr_pca):.2f} / {p90(herr_pca):.1f} deg")
    print(f"  not-vehicle candidates answered vehicle: {rate(len(false), len(nonveh))}; duplicate vehicle answers {dup}")
    print("    by majority label: " + "; ".join(f"{k} {rate(fa, tot)}" for k, (tot, fa) in sorted(kinds.items())))
    print(f"  missed (covered, answered none) by reason: {missed_reasons}")
    print(f"  confusion (true group -> answer): {sorted(confusion.items(), key=str)}")
    for r in false:
        print(f"    false: {r['run']}/{r['id']} ({names.get(r['label'], r['label'])}) {r['class']} conf {r['confidence']:.2f} size {[round(x,2) for x in r['size']]}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bin")
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--csv")
    ap.add_argument("--json")
    ap.add_argument("--classify-args", default="")
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--label", default="")
    a = ap.parse_args()
    all_rows, all_veh = [], {}
    for run in a.runs:
        index = classify_run(a.bin, run, a.classify_args.split(), a.reuse)
        rows, veh = rows_of(run, index)
        all_rows += rows
        all_veh[run] = veh
    summarise(all_rows, all_veh, a.label)
    if a.json:
        json.dump(all_rows, open(a.json, "w"))


if __name__ == "__main__":
    main()
