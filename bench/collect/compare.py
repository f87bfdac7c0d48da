#!/usr/bin/env python3
"""compare.py BEFORE_RES AFTER_RES: score's CSVs of two collects of the same verdicts; every
table but the reliability and the PR curve must be identical (matches.csv apart from its
confidence column); prints the reliability tables side by side (markdown)."""
import csv, sys, os
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import wilson
a, b = sys.argv[1], sys.argv[2]
for f in ("summary.csv", "models.csv", "cover_bins.csv", "clutter.csv"):
    if os.path.exists(f"{a}/{f}"):
        print(f, "identical" if open(f"{a}/{f}").read() == open(f"{b}/{f}").read() else "DIFFERS")
def rows(p, drop=()):
    r = list(csv.DictReader(open(p)))
    return [{k: v for k, v in x.items() if k not in drop} for x in r]
ma, mb = rows(f"{a}/matches.csv", ("confidence",)), rows(f"{b}/matches.csv", ("confidence",))
print("matches.csv apart from confidence:", "identical" if ma == mb else "DIFFERS", len(ma), "rows")
pa, pb = rows(f"{a}/pr.csv", ("threshold",)), rows(f"{b}/pr.csv", ("threshold",))
print("pr.csv apart from its thresholds:", "identical" if pa == pb else "DIFFERS", len(pa), "points")
ra, rb = rows(f"{a}/reliability.csv"), rows(f"{b}/reliability.csv")
def cell(x):
    n, k = int(x["answers"]), int(x["right"])
    if n == 0:
        return "–", ""
    lo, hi = wilson(k, n); m = float(x["mean_confidence"])
    ok = "–" if n < 20 else ("yes" if abs(k / n - m) <= 0.10 else "**no**")
    return f"{k}/{n} = {100*k/n:.1f}% [{100*lo:.1f}, {100*hi:.1f}] at {100*m:.1f}%", ok
print("\n| level | stated | before: right at mean stated | ±10 | after: right at mean stated | ±10 |\n|---|---|---|---|---|---|")
fails = [0, 0]
for x, y in zip(ra, rb):
    if int(x["answers"]) == 0 and int(y["answers"]) == 0:
        continue
    c1, o1 = cell(x); c2, o2 = cell(y)
    fails[0] += o1 == "**no**"; fails[1] += o2 == "**no**"
    print(f"| {x['level']} | {float(x['confidence_lo']):.1f}–{float(x['confidence_hi']):.1f} | {c1} | {o1} | {c2} | {o2} |")
print(f"bins of >= 20 answers outside ±10 points: before {fails[0]}, after {fails[1]}")
