#!/usr/bin/env python3
"""Issue 26: verify's answers with the true sensor directions (columns) vs derived ones, from
bench/sensordir/run.sh's OUT_DIR. Rates carry their counts and Wilson 95 % intervals."""
import glob
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import rates  # noqa: E402  (bench/rates.py)

SOURCES = ["columns", "trajectory", "scan-angle", "vertical"]


def wilson(k, n):
    if n == 0:
        return "n/a"
    lo, hi = rates.wilson(k, n)
    return "%d/%d = %.2f [%.2f, %.2f]" % (k, n, k / n, lo, hi)


def main():
    out = sys.argv[1]
    rows = []
    for d in sorted(glob.glob(os.path.join(out, "*-*"))):
        if not os.path.isfile(os.path.join(d, "truth.json")):
            continue
        look = os.path.basename(d).split("-")[0]
        truth = json.load(open(os.path.join(d, "truth.json")))
        models = {v["instance"]: v["model"] for v in truth["vehicles"]}
        index = json.load(open(os.path.join(d, "cands", "index.json")))
        for c in index["candidates"]:
            cd = os.path.join(d, "cands", c["id"])
            if not all(os.path.isfile(os.path.join(cd, "v-%s.json" % s)) for s in SOURCES):
                continue
            t = c.get("truth")
            expected = models[t["instance"]] if t else "none"
            r = {"look": look, "tile": os.path.basename(d), "id": c["id"], "expected": expected}
            for s in SOURCES:
                v = json.load(open(os.path.join(cd, "v-%s.json" % s)))
                hyp = {h["model"]: h for h in v["hypotheses"]}
                r[s] = {"answer": v["model"] or "none", "confidence": v["confidence"],
                        "violation_true": hyp[expected]["free_space_violation"] if expected in hyp else None,
                        "violation_wrong": [h["free_space_violation"] for h in v["hypotheses"]
                                            if h["model"] != expected]}
            rows.append(r)
    print("| look | source | candidates | right answer | same answer as columns | abs. confidence change: mean, max "
          "| mean violation, true model | mean violation, wrong models |")
    print("|---|---|---|---|---|---|---|---|")
    for look in ["across", "foreaft", "forest", "all"]:
        sel = [r for r in rows if look == "all" or r["look"] == look]
        if not sel:
            continue
        for s in SOURCES:
            n = len(sel)
            right = sum(r[s]["answer"] == r["expected"] for r in sel)
            same = sum(r[s]["answer"] == r["columns"]["answer"] for r in sel)
            dc = [abs(r[s]["confidence"] - r["columns"]["confidence"]) for r in sel]
            vt = [r[s]["violation_true"] for r in sel if r[s]["violation_true"] is not None]
            vw = [x for r in sel for x in r[s]["violation_wrong"]]
            mean = lambda xs: "%.3f (%d)" % (sum(xs) / len(xs), len(xs)) if xs else "n/a"
            spread = "%.3f, %.3f" % (sum(dc) / len(dc), max(dc))
            print("| %s | %s | %d | %s | %s | %s | %s | %s |" % (look, s, n, wilson(right, n), wilson(same, n),
                                                               spread, mean(vt), mean(vw)))
    print()
    print("per candidate: tile id expected | " + " | ".join(SOURCES))
    for r in rows:
        print("%s %s %s | %s" % (r["tile"], r["id"], r["expected"], " | ".join(
            "%s %.3f" % (r[s]["answer"], r[s]["confidence"]) for s in SOURCES)))


if __name__ == "__main__":
    main()
