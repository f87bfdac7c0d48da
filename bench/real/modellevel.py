#!/usr/bin/env python3
"""The model level on real tiles, two TILE_MODEL_DENSITY values paired (bench/real/modellevel.sh's runs).

  modellevel.py RUN_DIR TRUTH_DIR A B TILE [TILE ...]

RUN_DIR/<A|B>/<tile>/ (a `make tile` run each). Per tile and value: candidates, those the plan sends to
the model chain (cands.mk TILE_LEVEL_<id> := model), the chain's outcome there (failed: an empty
verdict.json, a stage's own error; none; a model named), the model-level detections and how score
matched them (right group: the model's class from share/models/classes.csv, its group as
bench/classify/realcal.py's GROUP), the candidates whose answer differs between A and B, and the
whole tile's CPU (tile.time: wall s, peak KiB, user s, sys s). Development tiles only.
"""
import csv, json, os, re, sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "classify"))
from realcal import GROUP  # noqa: E402

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
MODEL_CLASS = {r["model"]: r["class"] for r in csv.DictReader(
    (line for line in open(os.path.join(SRC, "share", "models", "classes.csv")) if not line.startswith("#")))}


def group_of(det):
    if det.get("group"):
        return det["group"]
    if det.get("class"):
        return GROUP.get(det["class"], "")
    return GROUP.get(MODEL_CLASS.get(det.get("model") or "", ""), "")


def run(d):
    r = {"levels": {}, "chain": {}, "dets": {}, "score": {}}
    for line in open(os.path.join(d, "cands.mk")):
        m = re.match(r"TILE_LEVEL_(\S+) := (\S+)", line)
        if m:
            r["levels"][m.group(1)] = m.group(2)
    for c, lev in r["levels"].items():
        if lev != "model":
            continue
        p = os.path.join(d, "cands", c, "verdict.json")
        s = open(p).read() if os.path.exists(p) else ""
        r["chain"][c] = (json.loads(s).get("model") or "none") if s.strip() else "failed"
    det = json.load(open(os.path.join(d, "detections.json")))
    r["ncand"] = det["candidates"]
    for x in det["detections"]:
        r["dets"][x["candidate"]] = x
    for x in det["rejected"]:
        if x.get("model_chain") == "set_aside":
            r.setdefault("set_aside", []).append(x["candidate"])
    sp = os.path.join(d, "score.json")
    if os.path.exists(sp):
        for m in json.load(open(sp))["matches"]:
            if m.get("candidate"):
                r["score"][m["candidate"]] = m
    t = open(os.path.join(d, "tile.time")).read().split("\n")
    t = [line for line in t if line and not line.startswith("Command")][-1].split()
    r["time"] = (float(t[0]), float(t[2]) + float(t[3]))
    return r


def fate(r, c):
    x = r["dets"].get(c)
    if not x:
        return "no detection"
    m = r["score"].get(c)
    name = x.get("model") or x.get("class")
    g = group_of(x)
    if m is None:
        o = "(plot: false alarm)"
    elif m["outcome"] == "false_alarm":
        o = "false alarm"
    else:
        o = f"matches a {m['true_model']}, group {'right' if g == m['true_model'] else 'wrong'}"
    return f"{x['level']} {name} ({g}, {x['confidence']:.2f}): {o}"


def main():
    out, truth, a, b = sys.argv[1:5]
    tiles = sys.argv[5:]
    print(f"| tile | candidates | to the chain at {a} / {b} | chain at {b}: failed / none / model | "
          f"model-level detections {a} / {b} | CPU s {a} / {b} | wall s {a} / {b} |")
    print("|---|---|---|---|---|---|---|")
    tot = [0, 0, 0, 0, 0, 0, 0, 0, 0, 0.0, 0.0, 0.0, 0.0]
    diffs = []
    for t in tiles:
        ra, rb = run(os.path.join(out, a, t)), run(os.path.join(out, b, t))
        na = sum(v == "model" for v in ra["levels"].values())
        nb = sum(v == "model" for v in rb["levels"].values())
        ch = list(rb["chain"].values())
        fl, no = ch.count("failed"), ch.count("none")
        md = len(ch) - fl - no
        la = sum(x["level"] == "model" for x in ra["dets"].values())
        lb = sum(x["level"] == "model" for x in rb["dets"].values())
        print(f"| {t} | {ra['ncand']} | {na} / {nb} | {fl} / {no} / {md} | {la} / {lb} | "
              f"{ra['time'][1]:.1f} / {rb['time'][1]:.1f} | {ra['time'][0]:.1f} / {rb['time'][0]:.1f} |")
        for i, v in enumerate([ra["ncand"], na, nb, fl, no, md, la, lb, 0, ra["time"][1], rb["time"][1],
                               ra["time"][0], rb["time"][0]]):
            tot[i] += v
        for c in sorted(set(ra["levels"]) | set(rb["levels"])):
            fa, fb = fate(ra, c), fate(rb, c)
            named = rb["chain"].get(c, "")
            if fa != fb or named not in ("", "none", "failed"):
                diffs.append(f"{t} {c}: chain at {b}: {named or '-'}; at {a}: {fa}; at {b}: {fb}")
        for c in rb.get("set_aside", []):
            diffs.append(f"{t} {c}: model answer set aside at {b} (collect)")
    print(f"| **all** | {tot[0]} | {tot[1]} / {tot[2]} | {tot[3]} / {tot[4]} / {tot[5]} | {tot[6]} / {tot[7]} | "
          f"{tot[9]:.1f} / {tot[10]:.1f} | {tot[11]:.1f} / {tot[12]:.1f} |")
    print("\nCandidates whose answer differs, or that the chain names:")
    for line in diffs:
        print("  " + line)


main()
