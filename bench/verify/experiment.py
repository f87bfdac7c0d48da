#!/usr/bin/env python3
"""experiment.py OUT [VERDICT_NAME]: verify's results on the thesis experiment's trials
(OUT/<object>/<scene>/noise-<mm>/{match.json,<VERDICT_NAME>}, default verdict.json). The
trials render every object at heading 0 at the origin, so the true pose is the identity.
Prints overall / per-object / per-noise correct answers, answers none, gmatch rank-1 alone,
pose errors of the right answers, and a reliability table. Standard library only."""
import json, math, os, sys

out = sys.argv[1]
name = sys.argv[2] if len(sys.argv) > 2 else "verdict.json"
objects = ["earthmover", "obj1", "sedan", "semi", "tank"]
scenes = ["circle", "flyby", "unoccluded"]
noises = [0, 2, 4, 8, 16, 32]
rows = []
for o in objects:
    for s in scenes:
        for n in noises:
            d = f"{out}/{o}/{s}/noise-{n}"
            try:
                v = json.load(open(f"{d}/{name}"))
                m = json.load(open(f"{d}/match.json"))
            except (OSError, ValueError):
                rows.append(dict(o=o, s=s, n=n, answer="(missing)", conf=0, g=None, pe=None, he=None))
                continue
            pe = he = None
            if v["model"] == o:
                t = v["pose"]["translation"]
                pe = math.hypot(t[0], t[1])
                he = abs((v["pose"]["heading_deg"] + 180) % 360 - 180)
            rows.append(dict(o=o, s=s, n=n, answer=v["model"] or "none", conf=v["confidence"],
                             g=m["models"][0]["model"], pe=pe, he=he))

def rate(rs, key=lambda r: r["answer"] == r["o"]):
    return f"{sum(map(key, rs))}/{len(rs)} ({100 * sum(map(key, rs)) / max(1, len(rs)):.1f}%)"

print(f"overall correct: {rate(rows)}; answered none: {rate(rows, lambda r: r['answer'] == 'none')}; "
      f"gmatch rank-1 alone: {rate(rows, lambda r: r['g'] == r['o'])}")
print("\n| object | verify correct | gmatch rank-1 |\n|---|---:|---:|")
for o in objects:
    rs = [r for r in rows if r["o"] == o]
    print(f"| {o} | {rate(rs)} | {rate(rs, lambda r: r['g'] == r['o'])} |")
print("\n| noise (mm) | verify correct | gmatch rank-1 |\n|---:|---:|---:|")
for n in noises:
    rs = [r for r in rows if r["n"] == n]
    print(f"| {n} | {rate(rs)} | {rate(rs, lambda r: r['g'] == r['o'])} |")
pe = sorted(r["pe"] for r in rows if r["pe"] is not None)
he = sorted(r["he"] for r in rows if r["he"] is not None)
if pe:
    print(f"\npose error of the right answers: median {pe[len(pe) // 2]:.4f} m, {he[len(he) // 2]:.3f} deg; "
          f"max {pe[-1]:.4f} m, {he[-1]:.3f} deg; heading error > 90 deg (flip): {sum(h > 90 for h in he)}")
print("\n| confidence | answers | right | share right |\n|---|---:|---:|---:|")
for lo, hi in [(0, 0.5), (0.5, 0.7), (0.7, 0.8), (0.8, 0.9), (0.9, 0.95), (0.95, 0.99), (0.99, 1.01)]:
    b = [r for r in rows if lo <= r["conf"] < hi]
    if b:
        print(f"| {lo:.2f}–{min(hi, 1):.2f} | {len(b)} | {sum(r['answer'] == r['o'] for r in b)} | "
              f"{100 * sum(r['answer'] == r['o'] for r in b) / len(b):.0f}% |")
wrong = [r for r in rows if r["answer"] != r["o"]]
if wrong:
    print("\nwrong answers: " + "; ".join(f"{r['o']}/{r['s']}/{r['n']} -> {r['answer']} ({r['conf']:.2f})" for r in wrong))
