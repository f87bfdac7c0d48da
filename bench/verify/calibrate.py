#!/usr/bin/env python3
"""calibrate.py FIT.csv [HELD.csv]: chooses verify's acceptance threshold and fits its confidence
(logistic in the best score and its margin over the next model) on FIT (trials.sh rows), then
reports accuracy, rejection and the reliability table on HELD (trials never tuned on).
Clutter trials are those whose model starts with "clutter". Standard library only."""
import csv, math, sys

COLS = ["trial", "model", "scene", "noise", "heading", "x", "y", "seed", "gmatch_top",
        "gmatch_margin", "verify_model", "confidence", "best_score", "best_explained",
        "best_violation", "true_score", "heading_err", "pos_err", "verify_s", "best_model",
        "second_score", "true_flipped"]

def load(path):
    rows = []
    for r in csv.reader(open(path)):
        if len(r) != len(COLS):
            continue
        d = dict(zip(COLS, r))
        d["clutter"] = d["model"].startswith("clutter")
        for k in ("best_score", "second_score", "confidence", "heading_err", "pos_err", "verify_s", "true_score"):
            d[k] = float(d[k])
        d["margin"] = d["best_score"] - d["second_score"]
        d["right_best"] = (not d["clutter"]) and d["best_model"] == d["model"]
        rows.append(d)
    return rows

def fit_logistic(xs, ys, iters=20000, lr=0.5, l2=1e-3):
    w = [0.0] * (len(xs[0]) + 1)
    n = len(xs)
    for _ in range(iters):
        g = [0.0] * len(w)
        for x, y in zip(xs, ys):
            z = w[0] + sum(wi * xi for wi, xi in zip(w[1:], x))
            p = 1 / (1 + math.exp(-max(-50, min(50, z))))
            g[0] += (p - y)
            for i, xi in enumerate(x):
                g[i + 1] += (p - y) * xi
        for i in range(len(w)):
            w[i] -= lr * (g[i] / n + (l2 * w[i] if i else 0))
    return w

def decide(rows, accept, w):
    out = []
    for d in rows:
        z = w[0] + w[1] * d["best_score"] + w[2] * d["margin"]
        p = 1 / (1 + math.exp(-max(-50, min(50, z))))
        answer = d["best_model"] if d["best_score"] >= accept else "none"
        conf = p if answer != "none" else 1 - p
        right = (answer == "none") if d["clutter"] else (answer == d["model"])
        out.append((d, answer, conf, right))
    return out

def summary(name, dec):
    veh = [x for x in dec if not x[0]["clutter"]]
    clu = [x for x in dec if x[0]["clutter"]]
    print(f"## {name}: {len(veh)} vehicle trials, {len(clu)} clutter trials")
    if veh:
        print(f"- vehicles answered right: {sum(x[3] for x in veh)}/{len(veh)} "
              f"({100 * sum(x[3] for x in veh) / len(veh):.1f}%); answered none: "
              f"{sum(x[1] == 'none' for x in veh)} ({100 * sum(x[1] == 'none' for x in veh) / len(veh):.1f}%)")
        g = sum(x[0]["gmatch_top"] == x[0]["model"] for x in veh)
        print(f"- gmatch rank-1 alone: {g}/{len(veh)} ({100 * g / len(veh):.1f}%)")
    if clu:
        print(f"- clutter answered none: {sum(x[1] == 'none' for x in clu)}/{len(clu)} "
              f"({100 * sum(x[1] == 'none' for x in clu) / len(clu):.1f}%)")
    pe = sorted(x[0]["pos_err"] for x in veh if x[1] == x[0]["model"])
    he = sorted(x[0]["heading_err"] for x in veh if x[1] == x[0]["model"])
    if pe:
        print(f"- pose error of right answers: median {pe[len(pe) // 2]:.4f} m, {he[len(he) // 2]:.3f} deg; "
              f"max {pe[-1]:.4f} m, {he[-1]:.3f} deg")
    ts = sorted(x[0]["verify_s"] for x in dec)
    print(f"- verify wall time per candidate (process, loaded machine): median {ts[len(ts) // 2]:.2f} s")
    print("\n| confidence | answers | right | share right |\n|---|---:|---:|---:|")
    for lo, hi in [(0, 0.5), (0.5, 0.7), (0.7, 0.8), (0.8, 0.9), (0.9, 0.95), (0.95, 0.99), (0.99, 1.01)]:
        b = [x for x in dec if lo <= x[2] < hi]
        if b:
            print(f"| {lo:.2f}–{min(hi, 1):.2f} | {len(b)} | {sum(x[3] for x in b)} | "
                  f"{100 * sum(x[3] for x in b) / len(b):.0f}% |")
    print()

fit = load(sys.argv[1])
held = load(sys.argv[2]) if len(sys.argv) > 2 else []
veh_scores = sorted(d["best_score"] for d in fit if not d["clutter"] and d["right_best"])
clu_scores = sorted(d["best_score"] for d in fit if d["clutter"])
print("fit set: right-model best scores (vehicles):", " ".join(f"{s:.3f}" for s in veh_scores))
print("fit set: best scores on clutter:", " ".join(f"{s:.3f}" for s in clu_scores))
# Threshold: midway between the clutter's highest score and the lowest right-vehicle score
# when they separate; otherwise the value minimising errors (clutter accepted + vehicles rejected).
cands = sorted(set([0.0] + [d["best_score"] + 1e-4 for d in fit]))
def cost(t):
    # errors made by the threshold itself: clutter or a wrong best model accepted, a right best
    # model rejected (a vehicle whose model was not among the hypotheses cannot be made right)
    return sum((d["best_score"] >= t) != d["right_best"] for d in fit)
best = min(cost(t) for t in cands)
ok = [t for t in cands if cost(t) == best]
lo_t, hi_t = ok[0], ok[-1]
# widest interval of optimal thresholds: its middle
# the middle of the widest gap of optimal thresholds
wrong = sorted(d["best_score"] for d in fit if not d["right_best"])
below = max([s for s in wrong if s < lo_t] + [0.0])
above = min([s for s in veh_scores if s >= hi_t - 1e-4] + [1.0])
accept = round((below + above) / 2, 3)
print(f"accept threshold: {accept} (training errors {best})")
xs = [[d["best_score"], d["margin"]] for d in fit]
ys = [1 if d["right_best"] else 0 for d in fit]
w = fit_logistic(xs, ys)
print("confidence logistic: conf-bias %.3f conf-score %.3f conf-margin %.3f" % tuple(w))
print()
summary("fit set", decide(fit, accept, w))
if held:
    summary("held-out set", decide(held, accept, w))
