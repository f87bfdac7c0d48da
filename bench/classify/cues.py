#!/usr/bin/env python3
"""Distributions of classify's cues by what a candidate is (evaluate.py --json rows).
  cues.py rows.json [rows.json ...]"""
import json, sys

names = {1: "vehicle", 2: "vegetation", 4: "clutter", 3: "ground"}
cues = ["fill", "below_share", "ground_through", "top_roughness", "plateau_share", "end_low", "end_high"]


def q(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))]


rows = []
for f in sys.argv[1:]:
    rows += json.load(open(f))
groups = {}
for r in rows:
    if not r["measured"]:
        continue
    if r["instance"] is not None:
        if (r["coverage"] or 0) < 0.8:
            continue
        k = "vehicle"
    else:
        k = names.get(r["label"], str(r["label"]))
    groups.setdefault(k, []).append(r)
for c in cues:
    print(c)
    for k, rs in sorted(groups.items()):
        v = [r["features"][c] for r in rs if r["features"][c] is not None]
        if not v:
            continue
        print(f"  {k:10s} n={len(v):4d} min {min(v):.3f} 5% {q(v, .05):.3f} 50% {q(v, .5):.3f} 95% {q(v, .95):.3f} max {max(v):.3f}")
