#!/usr/bin/env python3
"""CPU of a finished `make -f Makefile.experiments all` by part of the experiment and by tool
(docs/decisions/cost.md §20).

  bench/make/parts.py DIR [OUT RES]     (OUT, RES: the run's directories under DIR; out results)

Walks OUT and RES for the stage runner's .time files (%e %M %U %S: wall, peak KiB, user,
system); the tool is the first word of the stage's .log when it names one ("rangetrace: …"),
else the artifact's name. The real tiles' whole-tile records (tile.time: GNU time around each
tile's make) are shown apart and left out of the total (their stages are counted already)."""
import collections, os, sys
root = sys.argv[1]
out_dir, res_dir = (sys.argv[2], sys.argv[3]) if len(sys.argv) > 3 else ("out", "results")
THESIS = {"earthmover", "obj1", "sedan", "semi", "tank", "modelbase"}
def part(rel):
    p = rel.split("/")
    if p[0] == "RES": return "results"
    if p[1] in THESIS: return "thesis"
    if p[1] == "density": return "density-sensor" if p[2].startswith("als") else "density-pixel"
    return {"ablation": "fitvox ablation", "scenes": "scenes", "openset": "openset",
            "families": "families", "real": "real"}.get(p[1], p[1])
cpu = collections.defaultdict(float); n = collections.Counter()
tool = collections.defaultdict(float)
for top, name in ((out_dir, "OUT"), (res_dir, "RES")):
    for d, _, fs in os.walk(os.path.join(root, top)):
        for f in fs:
            if not f.endswith(".time"): continue
            path = os.path.join(d, f)
            rel = name + "/" + os.path.relpath(path, os.path.join(root, top))
            try: w = open(path).read().split()
            except OSError: continue
            if len(w) < 4: continue
            c = float(w[2]) + float(w[3]); pt = part(rel)
            t = f[:-5]
            try:
                with open(path[:-5] + ".log", errors="replace") as g: first = g.readline()
                if ":" in first and " " not in first.split(":")[0]: t = first.split(":")[0]
            except OSError: pass
            if f == "tile.time": pt, t = "real (whole-tile records)", "make tile"
            cpu[pt] += c; n[pt] += 1; tool[(pt, t)] += c
tot = sum(v for k, v in cpu.items() if not k.startswith("real (whole"))
for k in sorted(cpu, key=lambda k: -cpu[k]):
    tops = sorted(((v, t) for (p, t), v in tool.items() if p == k), reverse=True)[:6]
    print(f"{k:28s} {n[k]:6d} stages {cpu[k]:9.1f} CPU-s  " + ", ".join(f"{t} {v:.0f}" for v, t in tops))
stages = sum(v for k, v in n.items() if not k.startswith("real (whole"))
print(f"{'stages total':28s} {stages:6d}        {tot:9.1f} CPU-s = {tot/60:.1f} CPU-min")
