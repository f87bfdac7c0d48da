#!/usr/bin/env python3
"""calibrate_tiles.py CSV... : verify's acceptance and confidence fitted on tile candidates
(docs/decisions/verify.md §15). Standard library only; reuses calibrate.py's logistic fit.

Each CSV is tile_candidates.py's output (verify run with --box-margin -1, so every row carries the
box's score and no decision). A row's model answer is right when its best model is the truth's
model (never, in the open set); a none is right when no vehicle stands at the candidate (score's
definition). The decision is verify's: answer the best model when score >= accept and score -
box >= box margin. Printed: the acceptance scan, the logistic weights (model answers: P(best
model right | score, margin, score - box); none: P(a vehicle is there | same)), and the
reliability tables (answers by stated confidence in tenths, share right, Wilson 95%) for the old
parameters (share/params/verify.ini before issue 29: accept 0.544, no box) and the new ones,
in-sample and 2-fold by tile (fit on one half of the tiles, evaluated on the other)."""
import csv, math, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import wilson  # noqa: E402


def fit_logistic(xs, ys, iters=4000, lr=0.5, l2=1e-3):
    """Logistic regression by gradient descent with light L2 (calibrate.py's fit; that script
    runs on import, so the function is repeated here)."""
    w = [0.0] * (len(xs[0]) + 1)
    n = len(xs)
    for _ in range(iters):
        g = [0.0] * len(w)
        for x, y in zip(xs, ys):
            p = 1 / (1 + math.exp(-max(-50, min(50, w[0] + sum(a * b for a, b in zip(w[1:], x))))))
            g[0] += p - y
            for i, xi in enumerate(x):
                g[i + 1] += (p - y) * xi
        for i in range(len(w)):
            w[i] -= lr * (g[i] / n + (l2 * w[i] if i else 0))
    return w

OLD = dict(accept=0.544, box_margin=None, conf=(-5.365, 6.317, 5.573, 0.0), none=(-5.365, 6.317, 5.573, 0.0))


def load(paths):
    rows = []
    for src, path in enumerate(paths):
        for r in csv.DictReader(open(path)):
            d = {k: r[k] for k in ("tile", "cover", "candidate", "truth", "truth_model", "best_model")}
            d["tile"] = f"{src}:{r['tile']}"
            for k in ("best_score", "second_score", "box_score"):
                d[k] = float(r[k])
            d["margin"] = d["best_score"] - d["second_score"]
            d["over_box"] = d["best_score"] - d["box_score"]
            d["vehicle"] = d["truth"] == "vehicle"
            d["right"] = d["vehicle"] and d["best_model"] == d["truth_model"]
            rows.append(d)
    return rows


def sig(z):
    return 1 / (1 + math.exp(-max(-50, min(50, z))))


def decide(d, P):
    accepted = d["best_score"] >= P["accept"] and (P["box_margin"] is None or d["over_box"] >= P["box_margin"])
    x = (1, d["best_score"], d["margin"], d["over_box"] if P["box_margin"] is not None else 0)
    if accepted:
        return "model", sig(sum(a * b for a, b in zip(P["conf"], x))), d["right"]
    return "none", 1 - sig(sum(a * b for a, b in zip(P["none"], x))), not d["vehicle"]


def table(rows, P, title):
    print(f"\n{title}\n\n| answer | confidence | answers | right | share right [95%] | mean stated |\n|---|---|---:|---:|---|---:|")
    dec = [decide(d, P) for d in rows]
    for level in ("model", "none"):
        for b in range(10):
            lo, hi = b / 10, (b + 1) / 10
            sel = [x for x in dec if x[0] == level and (lo <= x[1] < hi or (b == 9 and x[1] == 1))]
            if not sel:
                continue
            k = sum(x[2] for x in sel)
            w = wilson(k, len(sel))
            print(f"| {level} | {lo:.1f}–{hi:.1f} | {len(sel)} | {k} | {100 * k / len(sel):.1f}% "
                  f"[{100 * w[0]:.1f}, {100 * w[1]:.1f}] | {sum(x[1] for x in sel) / len(sel):.3f} |")
    acc = [x for x in dec if x[0] == "model"]
    fa = sum(1 for d, x in zip(rows, dec) if x[0] == "model" and not d["vehicle"])
    print(f"\nmodel answers {len(acc)}, right {sum(x[2] for x in acc)}, on clutter/terrain {fa}; "
          f"none {len(dec) - len(acc)}, right {sum(x[2] for x in dec if x[0] == 'none')}")


def fit(rows, box_margin=0.0):
    # Acceptance: fewest errors (accepted wrong + rejected right) over the scores, the middle of
    # the best gap; the box rule applied first.
    cand = sorted({round(d["best_score"], 4) for d in rows})
    best = None
    for i in range(len(cand) + 1):
        t = (cand[i - 1] + cand[i]) / 2 if 0 < i < len(cand) else (cand[0] - 1e-3 if i == 0 else cand[-1] + 1e-3)
        err = sum(1 for d in rows if (d["best_score"] >= t and d["over_box"] >= box_margin) != d["right"])
        if best is None or err < best[0]:
            best = (err, t)
    xs = [(d["best_score"], d["margin"], d["over_box"]) for d in rows]
    conf = fit_logistic(xs, [1 if d["right"] else 0 for d in rows], iters=4000)
    none = fit_logistic(xs, [1 if d["vehicle"] else 0 for d in rows], iters=4000)
    return dict(accept=round(best[1], 3), box_margin=box_margin, conf=tuple(round(w, 3) for w in conf),
                none=tuple(round(w, 3) for w in none), errors=best[0])


def main():
    rows = load(sys.argv[1:])
    kinds = {}
    for d in rows:
        kinds[d["truth"]] = kinds.get(d["truth"], 0) + 1
    print(f"{len(rows)} candidates: " + ", ".join(f"{k} {n}" for k, n in sorted(kinds.items())))
    P = fit(rows)
    print(f"\nfit on all: accept {P['accept']} (errors {P['errors']}), box margin {P['box_margin']}, "
          f"conf (bias, score, margin, box) {P['conf']}, none {P['none']}")
    table(rows, OLD, "old parameters (accept 0.544, no box), in-sample")
    table(rows, dict(OLD, box_margin=0.0), "old parameters with the box (margin 0), in-sample")
    table(rows, P, "new parameters, in-sample")
    tiles = sorted({d["tile"] for d in rows})
    halves = [set(tiles[0::2]), set(tiles[1::2])]
    held = []
    for h in (0, 1):
        Ph = fit([d for d in rows if d["tile"] in halves[h]])
        print(f"\nfold {h}: fit on {len(halves[h])} tiles: accept {Ph['accept']}, conf {Ph['conf']}, none {Ph['none']}")
        held += [(d, Ph) for d in rows if d["tile"] not in halves[h]]
    # Held-out table: each row decided with the parameters fitted on the other half.
    print("\n2-fold held out (each tile answered with the parameters fitted on the other half)")
    print("\n| answer | confidence | answers | right | share right [95%] | mean stated |\n|---|---|---:|---:|---|---:|")
    dec = [decide(d, Ph) for d, Ph in held]
    for level in ("model", "none"):
        for b in range(10):
            lo, hi = b / 10, (b + 1) / 10
            sel = [x for x in dec if x[0] == level and (lo <= x[1] < hi or (b == 9 and x[1] == 1))]
            if sel:
                k = sum(x[2] for x in sel)
                w = wilson(k, len(sel))
                print(f"| {level} | {lo:.1f}–{hi:.1f} | {len(sel)} | {k} | {100 * k / len(sel):.1f}% "
                      f"[{100 * w[0]:.1f}, {100 * w[1]:.1f}] | {sum(x[1] for x in sel) / len(sel):.3f} |")


if __name__ == "__main__":
    main()
