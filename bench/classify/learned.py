#!/usr/bin/env python3
"""A learned vehicle-or-not decision on classify's own features, against classify's hand-set gates
(docs/decisions/classify.md §48, stop 66): a feasibility study; nothing in classify uses it.

  /usr/bin/python3 bench/classify/learned.py [--sim NAME=DIR ...] [--real RUN TRUTH_DIR]
                                             [--rounds 100] [--lam 1.0] [--quick]

Needs numpy (Debian's python3-numpy; the pyenv python3 of the session has none, hence
/usr/bin/python3). Standard library otherwise; no scikit-learn.

Inputs (read only, development data only):
  --sim NAME=DIR   a density-ladder output tree (`make density` with SCENE_KEEP_TILE_SCANS=1):
                   DIR/d{10,25,50}/tiles.txt, each tile's truth.json and noise-0/cands/index.json
                   and cands/<id>/class.json. Default: pix=/work/dev63/pix25/run/out/density (the
                   pixel ladder of stop 63, seeds 101-110) and fam=/work/dev64/fam/out/density (the
                   car/van family ladder of stop 64, seeds 101-106). Seeds below 101 are refused.
  --real RUN TRUTH the real development tiles run by bench/classify/passes.sh (RUN/<tile>/cands/...,
                   classify.ini) and the labels' directory (<tile>.truth.json; forest plots have
                   none: every candidate there is a negative). The held-out tiles are refused.

Labels (per candidate, by its centre in index.json): `vehicle` inside a true vehicle's footprint,
`clutter:<kind>` inside a clutter box or within 1.5 m of one (bench/density/wrong.py's fell_on),
`other` (vegetation, terrain) otherwise; on real tiles a candidate inside an `uncertain` label is
dropped. Baseline = classify's decision (class.json `class` not null = answered a vehicle).

Features: class.json `features` without the three headings, `measured.size` (L, W, H),
`measured.spacing`, `density`; counts as log(1+x); standardized on the training fold; a null is
the training mean plus a missing indicator; a column null in every training row is dropped (on
simulated tiles late_returns, echo_widening and multi_returns are never measured).

Learners: L2 logistic regression (Newton; --lam on the summed loss, intercept free) and gradient-
boosted depth-2 trees (logistic loss, --rounds, rate 0.1, 32 quantile thresholds per feature, a
null its own branch): both a few hundred lines of C++ with Eigen at most.

Evaluation: grouped cross-validation, leave one seed out (all its tiles, covers, levels and both
ladders together). Two operating points per learner: `matched` (pooled out-of-fold scores: the
false alarms at the baseline's true-vehicle candidates, the true-vehicle candidates at the baseline's
false alarms: what the ranking can do, chosen after the fact) and `honest` (the threshold chosen in
the training seeds alone, by an inner leave-one-seed-out, to keep the baseline's recall on them,
then applied to the held-out seed). Recall per vehicle (a vehicle is found when a candidate inside
its footprint is answered) with 95% Wilson intervals (bench/rates.py); false alarms (answered
candidates on no vehicle) with exact Poisson 95% intervals.

Prints: the data's counts; per learner the matched and honest points; the honest point per level,
per cover and per clutter kind; the features that carry the decision (logistic coefficients,
boosted gains); single-feature vetoes and rescues on the baseline; with --real the transfer from
all simulated data to the real development tiles (per tile; also behind classify's size and density
gates), each feature's own AUC on simulated and on real candidates, and (without --quick)
leave-one-real-tile-out. --drop / --keep choose the feature columns (docs: no size, surface only).
Deterministic (no random draws): the same inputs print the same figures.
"""
import argparse, collections, json, math, os, sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import poisson_exact, rate, wilson  # noqa: E402

HELD_OUT = ("ign_lidarhd_870000_6618000", "ahn3_delft_2", "ign_stbarth_100m", "forest_lareunion")
LOGS = {"crop_points", "ground_points", "object_points", "interior_points", "top_cells", "top_cells_line",
        "interior_cells", "dents", "density", "ground_density"}
SKIP = {"heading_pca_deg", "heading_hull_deg", "heading_refined_deg"}
MODEL_CLASS = {"earthmover": "wheel-loader", "obj1": "wheeled-apc", "semi": "semi-tractor"}  # wrong.py's


# ----------------------------------------------------------------------------------------- data
def inside(poly, x, y):
    c = False
    for i in range(len(poly)):
        x1, y1 = poly[i]
        x2, y2 = poly[(i + 1) % len(poly)]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            c = not c
    return c


def fell_on(truth, x, y):
    """(label, instance): bench/density/wrong.py's fell_on, a vehicle's footprint first."""
    best = None
    for v in truth.get("vehicles", []):
        if v.get("footprint") and inside(v["footprint"], x, y):
            d = math.hypot(x - v["pose"]["x"], y - v["pose"]["y"])
            if best is None or d < best[0]:
                best = (d, v["instance"])
    if best:
        return "vehicle", best[1]
    for c in truth.get("clutter", []):
        b = c["box"]
        h = math.radians(b["heading"])
        dx, dy = x - b["centre"][0], y - b["centre"][1]
        u = dx * math.cos(h) + dy * math.sin(h)
        w = -dx * math.sin(h) + dy * math.cos(h)
        if abs(u) <= b["size"][0] / 2 and abs(w) <= b["size"][1] / 2:
            return "clutter:" + c["kind"], None
    near = sorted((math.hypot(x - c["box"]["centre"][0], y - c["box"]["centre"][1]), c["kind"])
                  for c in truth.get("clutter", []))
    if near and near[0][0] <= 1.5:
        return "clutter:" + near[0][1], None
    return "other", None


def row(cls, cand, **kw):
    m = cls.get("measured") or {}
    size = m.get("size") or [None, None, None]
    f = {k: v for k, v in (cls.get("features") or {}).items() if k not in SKIP}
    f["L"], f["W"], f["H"] = size
    f["spacing"] = m.get("spacing")
    f["density"] = cls.get("density")
    r = dict(cand=cand, feats=f, answered=cls.get("class") is not None, reason=cls.get("reason"),
             answer=cls.get("class"))
    r.update(kw)
    return r


def load_sim(name, root):
    rows, vehicles = [], []
    for level in ("d10", "d25", "d50"):
        tt = os.path.join(root, level, "tiles.txt")
        if not os.path.exists(tt):
            continue
        for line in open(tt):
            det, truthp, _, cover = line.split()
            tile_dir = os.path.dirname(truthp)
            seed = int(tile_dir.split("tile-")[1])
            if seed < 101:
                sys.exit(f"refused: seed {seed} is not a development seed ({tile_dir})")
            truth = json.load(open(truthp))
            key = (name, level, cover, seed)
            vclass = {}
            for v in truth["vehicles"]:
                vclass[v["instance"]] = MODEL_CLASS.get(v["model"], v["model"].split("-")[0])
                vehicles.append(dict(key=key + (v["instance"],), level=level, cover=cover, seed=seed, src=name,
                                     vis="sim", vclass=vclass[v["instance"]]))
            cdir = os.path.join(tile_dir, "noise-0", "cands")
            for c in json.load(open(os.path.join(cdir, "index.json")))["candidates"]:
                p = os.path.join(cdir, c["id"], "class.json")
                if not os.path.exists(p):
                    continue
                lab, inst = fell_on(truth, c["centre"][0], c["centre"][1])
                rows.append(row(json.load(open(p)), c["id"], src=name, level=level, cover=cover, seed=seed,
                                group=f"seed{seed}", label=lab, vkey=key + (inst,) if inst else None,
                                vclass=vclass.get(inst)))
    return rows, vehicles


def load_real(run, truth_dir):
    rows, vehicles = [], []
    for tile in sorted(os.listdir(run)):
        if tile in HELD_OUT:
            sys.exit(f"refused: {tile} is a held-out tile")
        cdir = os.path.join(run, tile, "cands")
        if not os.path.exists(os.path.join(cdir, "index.json")):
            continue
        tp = os.path.join(truth_dir, tile + ".truth.json")
        truth = json.load(open(tp)) if os.path.exists(tp) else {"vehicles": []}
        key = ("real", tile)
        for v in truth["vehicles"]:
            vehicles.append(dict(key=key + (v["instance"],), level=tile, cover="real", seed=tile, src="real",
                                 vis=v.get("visibility")))
        unc = [u["footprint"] for u in truth.get("uncertain", [])]
        for c in json.load(open(os.path.join(cdir, "index.json")))["candidates"]:
            p = os.path.join(cdir, c["id"], "class.json")
            if not os.path.exists(p):
                continue
            x, y = c["centre"][0], c["centre"][1]
            lab, inst = fell_on(truth, x, y)
            if lab != "vehicle" and any(inside(u, x, y) for u in unc):
                continue
            rows.append(row(json.load(open(p)), c["id"], src="real", level=tile, cover="real", seed=tile,
                            group=tile, label=lab, vkey=key + (inst,) if inst else None))
    return rows, vehicles


# ------------------------------------------------------------------------------------- features
def columns(rows, drop=()):
    return sorted({k for r in rows for k in r["feats"]} - set(drop))


def raw_matrix(rows, names):
    X = np.full((len(rows), len(names)), np.nan)
    for i, r in enumerate(rows):
        for j, k in enumerate(names):
            v = r["feats"].get(k)
            if v is not None:
                X[i, j] = math.log1p(max(0.0, v)) if k in LOGS else float(v)
    return X


class Prep:
    """Standardize on the training rows; null -> mean plus an indicator; all-null columns dropped."""

    def __init__(self, X, names):
        ok = ~np.all(np.isnan(X), axis=0)
        self.keep = np.where(ok)[0]
        self.mu = np.nanmean(X[:, self.keep], axis=0)
        sd = np.nanstd(X[:, self.keep], axis=0)
        self.sd = np.where(sd > 0, sd, 1.0)
        self.miss = [j for j in self.keep if np.isnan(X[:, j]).any()]
        self.names = [names[j] for j in self.keep] + ["missing:" + names[j] for j in self.miss]

    def __call__(self, X):
        Z = (X[:, self.keep] - self.mu) / self.sd
        Z = np.clip(np.nan_to_num(Z, nan=0.0), -5, 5)
        M = np.isnan(X[:, self.miss]).astype(float)
        return np.hstack([Z, M])


class Logistic:
    def __init__(self, lam=1.0):
        self.lam = lam

    def fit(self, X, y, names):
        self.prep = Prep(X, names)
        Z = self.prep(X)
        A = np.hstack([np.ones((len(Z), 1)), Z])
        w = np.zeros(A.shape[1])
        R = self.lam * np.eye(A.shape[1])
        R[0, 0] = 0
        for _ in range(50):
            p = 1 / (1 + np.exp(-A @ w))
            g = A.T @ (p - y) + R @ w
            H = (A * (p * (1 - p))[:, None]).T @ A + R + 1e-9 * np.eye(len(w))
            step = np.linalg.solve(H, g)
            w -= step
            if np.max(np.abs(step)) < 1e-8:
                break
        self.w = w
        return self

    def score(self, X):
        Z = self.prep(X)
        return self.w[0] + Z @ self.w[1:]


class Boost:
    """Gradient-boosted depth-2 trees, logistic loss; a null goes to its own branch (bin 0)."""

    def __init__(self, rounds=100, rate=0.1, bins=32, lam=1.0):
        self.rounds, self.rate, self.nb, self.lam = rounds, rate, bins, lam

    def binner(self, X):
        B = np.zeros(X.shape, dtype=np.int64)
        for j in range(X.shape[1]):
            x = X[:, j]
            ok = ~np.isnan(x)
            B[ok, j] = 1 + np.searchsorted(self.edges[j], x[ok], side="right")
        return B

    def best_split(self, B, g, h, idx):
        best = (0.0, None, None)
        G, H = g[idx].sum(), h[idx].sum()
        base = G * G / (H + self.lam)
        for j in range(B.shape[1]):
            nb = len(self.edges[j]) + 2
            gs = np.bincount(B[idx, j], weights=g[idx], minlength=nb)
            hs = np.bincount(B[idx, j], weights=h[idx], minlength=nb)
            # the null bin (0) on either side; thresholds between ordered bins 1..nb-1
            for null_left in (True, False):
                gl = np.cumsum(gs[1:])[:-1] + (gs[0] if null_left else 0)
                hl = np.cumsum(hs[1:])[:-1] + (hs[0] if null_left else 0)
                gr, hr = G - gl, H - hl
                gain = gl * gl / (hl + self.lam) + gr * gr / (hr + self.lam) - base
                valid = (hl > 1e-3) & (hr > 1e-3)
                if not valid.any():
                    continue
                gain = np.where(valid, gain, -1)
                k = int(np.argmax(gain))
                if gain[k] > best[0]:
                    best = (float(gain[k]), j, (k + 1, null_left))  # left: bins 1..k+1 (+ null)
        return best

    @staticmethod
    def goes_left(B, j, split):
        k, null_left = split
        b = B[:, j]
        return np.where(b == 0, null_left, b <= k)

    def fit(self, X, y, names):
        self.names = list(names)
        self.edges = []
        for j in range(X.shape[1]):
            x = X[~np.isnan(X[:, j]), j]
            e = np.unique(np.quantile(x, np.linspace(0, 1, self.nb + 1)[1:-1])) if len(x) else np.array([])
            self.edges.append(e)
        B = self.binner(X)
        p0 = min(max(y.mean(), 1e-3), 1 - 1e-3)
        self.f0 = math.log(p0 / (1 - p0))
        F = np.full(len(y), self.f0)
        self.trees = []
        self.gain = collections.Counter()
        for _ in range(self.rounds):
            p = 1 / (1 + np.exp(-F))
            g, h = p - y, p * (1 - p)
            allidx = np.arange(len(y))
            gain, j, split = self.best_split(B, g, h, allidx)
            if j is None:
                break
            self.gain[names[j]] += gain
            left = self.goes_left(B, j, split)
            tree = [j, split, []]
            for side in (left, ~left):
                idx = allidx[side]
                gain2, j2, split2 = self.best_split(B, g, h, idx)
                if j2 is None:
                    v = -g[idx].sum() / (h[idx].sum() + self.lam)
                    tree[2].append((None, None, v, v))
                    continue
                self.gain[names[j2]] += gain2
                l2 = self.goes_left(B[idx], j2, split2)
                vl = -g[idx][l2].sum() / (h[idx][l2].sum() + self.lam)
                vr = -g[idx][~l2].sum() / (h[idx][~l2].sum() + self.lam)
                tree[2].append((j2, split2, vl, vr))
            self.trees.append(tree)
            F += self.rate * self.tree_out(tree, B)
        return self

    def tree_out(self, tree, B):
        j, split, kids = tree
        left = self.goes_left(B, j, split)
        out = np.zeros(len(B))
        for side, (j2, s2, vl, vr) in zip((left, ~left), kids):
            if j2 is None:
                out[side] = vl
            else:
                l2 = self.goes_left(B, j2, s2)
                out[side & l2] = vl
                out[side & ~l2] = vr
        return out

    def score(self, X):
        B = self.binner(X)
        F = np.full(len(X), self.f0)
        for t in self.trees:
            F += self.rate * self.tree_out(t, B)
        return F


# ----------------------------------------------------------------------------------- evaluation
def fa(k):
    lo, hi = poisson_exact(k)
    return f"{k} [{lo:.1f}, {hi:.1f}]"


def outcome(rows, vehicles, ans):
    """(found vehicles, their count, false alarms, duplicates) of answers `ans` (bool per row)."""
    keys = {v["key"] for v in vehicles}
    found = {r["vkey"] for r, a in zip(rows, ans) if a and r["label"] == "vehicle"} & keys
    fas = sum(1 for r, a in zip(rows, ans) if a and r["label"] != "vehicle")
    hits = sum(1 for r, a in zip(rows, ans) if a and r["label"] == "vehicle")
    return len(found), len(keys), fas, hits - len(found)


def folds(rows):
    return sorted({r["group"] for r in rows}, key=str)


def fit_model(kind, X, y, names, a):
    return (Logistic(a.lam) if kind == "logistic" else Boost(a.rounds)).fit(X, y, names)


def oof(kind, rows, X, y, names, a, groups=None):
    s = np.zeros(len(rows))
    g = np.array([r["group"] for r in rows])
    for k in groups or folds(rows):
        te = g == k
        s[te] = fit_model(kind, X[~te], y[~te], names, a).score(X[te])
    return s


def thr_for_hits(s, y, hits):
    """The threshold at which the `hits` highest-scored positives are answered."""
    pos = np.sort(s[y == 1])[::-1]
    return pos[hits - 1] if hits > 0 else np.inf


def thr_for_fas(s, y, fas):
    neg = np.sort(s[y == 0])[::-1]
    return (neg[fas] + 1e-12) if fas < len(neg) else -np.inf


def honest(kind, rows, X, y, names, base, a, point="recall"):
    """Per outer seed, a threshold chosen on the other seeds' inner out-of-fold scores (to keep the
    baseline's true-vehicle candidates there, or its false alarms), applied to the outer seed."""
    ans = np.zeros(len(rows), dtype=bool)
    s_all = np.zeros(len(rows))
    g = np.array([r["group"] for r in rows])
    for k in folds(rows):
        te = g == k
        tr = ~te
        tr_rows = [r for r, t in zip(rows, tr) if t]
        s_in = oof(kind, tr_rows, X[tr], y[tr], names, a)
        if point == "recall":
            t = thr_for_hits(s_in, y[tr], int((base[tr] & (y[tr] == 1)).sum()))
        else:
            t = thr_for_fas(s_in, y[tr], int((base[tr] & (y[tr] == 0)).sum()))
        s = fit_model(kind, X[tr], y[tr], names, a).score(X[te])
        s_all[te] = s
        ans[te] = s >= t
    return ans, s_all


def table(title, rows, vehicles, answers, by):
    print(f"\n{title}")
    cols = list(answers)
    print("| " + by + " | " + " | ".join(f"{c}: found | {c}: false alarms" for c in cols) + " |")
    print("|---" * (1 + 2 * len(cols)) + "|")
    cats = sorted({r[by] for r in rows} | {v[by] for v in vehicles}, key=str)
    for c in cats + ["all"]:
        sel = [c == "all" or r[by] == c for r in rows]
        rr = [r for r, s in zip(rows, sel) if s]
        vv = [v for v in vehicles if c == "all" or v[by] == c]
        cells = []
        for name in cols:
            ans = [x for x, s in zip(answers[name], sel) if s]
            f, n, k, _ = outcome(rr, vv, ans)
            cells += [rate(f, n), fa(k)]
        print(f"| {c} | " + " | ".join(cells) + " |")


def clutter_table(rows, answers):
    print("\nFalse alarms by what they fell on (candidates answered):")
    kinds = sorted({r["label"] for r in rows if r["label"] != "vehicle"})
    print("| fell on | candidates | " + " | ".join(answers) + " |")
    print("|---" * (2 + len(answers)) + "|")
    for k in kinds:
        sel = [r["label"] == k for r in rows]
        print(f"| {k} | {sum(sel)} | " + " | ".join(
            str(sum(1 for a, s in zip(ans, sel) if a and s)) for ans in answers.values()) + " |")


# ----------------------------------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sim", action="append", default=None)
    ap.add_argument("--real", nargs=2, default=None)
    ap.add_argument("--rounds", type=int, default=100)
    ap.add_argument("--lam", type=float, default=1.0)
    ap.add_argument("--quick", action="store_true", help="no nested (honest) thresholds")
    ap.add_argument("--drop", default="", help="comma-separated feature columns left out (e.g. L,W,H)")
    ap.add_argument("--keep", default="", help="comma-separated feature columns, the only ones used")
    a = ap.parse_args()
    sims = a.sim or ["pix=/work/dev63/pix25/run/out/density", "fam=/work/dev64/fam/out/density"]
    rows, vehicles = [], []
    for s in sims:
        name, root = s.split("=", 1)
        r, v = load_sim(name, root)
        rows += r
        vehicles += v
    a.dropped = [c for c in a.drop.split(",") if c]
    if a.keep:
        a.dropped += sorted(set(columns(rows)) - set(a.keep.split(",")))
    names = columns(rows, a.dropped)
    X = raw_matrix(rows, names)
    y = np.array([r["label"] == "vehicle" for r in rows], dtype=float)
    base = np.array([r["answered"] for r in rows])
    print("== Data (simulated development ladders)")
    for src in sorted({r["src"] for r in rows}):
        rr = [r for r in rows if r["src"] == src]
        print(f"{src}: {len({(r['level'], r['cover'], r['seed']) for r in rr})} tiles, {len(rr)} candidates "
              f"({sum(r['label'] == 'vehicle' for r in rr)} on a vehicle, "
              f"{sum(r['label'].startswith('clutter') for r in rr)} on clutter, "
              f"{sum(r['label'] == 'other' for r in rr)} on neither), "
              f"{sum(v['src'] == src for v in vehicles)} vehicles; seeds "
              f"{min(r['seed'] for r in rr)}-{max(r['seed'] for r in rr)}")
    print(f"features: {len(names)} columns ({', '.join(names)})"
          + (f"; left out: {', '.join(a.dropped)}" if a.dropped else ""))

    answers = {"classify": list(base)}
    scores = {}
    for kind in ("logistic", "boosted"):
        s = oof(kind, rows, X, y, names, a)
        scores[kind] = s
        hits_b = int((base & (y == 1)).sum())
        fas_b = int((base & (y == 0)).sum())
        t1 = thr_for_hits(s, y, hits_b)
        t2 = thr_for_fas(s, y, fas_b)
        a1, a2 = s >= t1, s >= t2
        f0, n0, k0, d0 = outcome(rows, vehicles, base)
        f1, n1, k1, d1 = outcome(rows, vehicles, a1)
        f2, n2, k2, d2 = outcome(rows, vehicles, a2)
        print(f"\n== {kind}, leave one seed out, pooled out-of-fold scores (matched after the fact)")
        print(f"| decision | vehicle candidates answered | vehicles found | false alarms |")
        print("|---|---|---|---|")
        print(f"| classify | {hits_b}/{int(y.sum())} | {rate(f0, n0)} | {fa(k0)} |")
        print(f"| {kind} at classify's vehicle candidates | {int((a1 & (y == 1)).sum())} | {rate(f1, n1)} | {fa(k1)} |")
        print(f"| {kind} at classify's false alarms | {int((a2 & (y == 1)).sum())} | {rate(f2, n2)} | {fa(k2)} |")
        # rank quality: AUC of the out-of-fold scores
        pos, neg = s[y == 1], s[y == 0]
        auc = (np.sum(pos[:, None] > neg[None, :]) + 0.5 * np.sum(pos[:, None] == neg[None, :])) / (len(pos) * len(neg))
        print(f"out-of-fold AUC {auc:.3f}")
        if not a.quick:
            for point in ("recall", "false alarms"):
                ans, _ = honest(kind, rows, X, y, names, base, a, "recall" if point == "recall" else "fas")
                answers[f"{kind} ({point})"] = list(ans)
                f, n, k, d = outcome(rows, vehicles, ans)
                print(f"honest, threshold keeping classify's {point} on the training seeds: "
                      f"found {rate(f, n)}, false alarms {fa(k)} (classify {rate(f0, n0)}, {fa(k0)})")
    if len(answers) > 1:
        for by in ("level", "cover", "src", "seed"):
            table(f"== Per {by} (honest thresholds; found = vehicles with an answered candidate on them)",
                  rows, vehicles, answers, by)
        clutter_table(rows, answers)
        # disagreements
        for name, ans in answers.items():
            if name == "classify":
                continue
            gained = sum(1 for r, x, b in zip(rows, ans, base) if x and not b and r["label"] == "vehicle")
            lost = sum(1 for r, x, b in zip(rows, ans, base) if b and not x and r["label"] == "vehicle")
            trio = list(zip(rows, ans, base))
            newfa = collections.Counter(r["label"] for r, x, b in trio if x and not b and r["label"] != "vehicle")
            gone = collections.Counter(r["label"] for r, x, b in trio if b and not x and r["label"] != "vehicle")
            rescued = collections.Counter(r["reason"] for r, x, b in trio if x and not b and r["label"] == "vehicle")
            print(f"{name} vs classify: vehicle candidates gained {gained} (refused by classify as {dict(rescued)}), "
                  f"lost {lost}; false alarms new {dict(newfa)}, removed {dict(gone)}")

    lomo(rows, X, y, names, base, scores, a)

    print("\n== What carries the decision (fitted on all simulated rows)")
    lg = Logistic(a.lam).fit(X, y, names)
    co = sorted(zip(lg.prep.names, lg.w[1:]), key=lambda t: -abs(t[1]))
    print("logistic, standardized coefficients (largest 15): " +
          ", ".join(f"{n} {w:+.2f}" for n, w in co[:15]))
    bo = Boost(a.rounds).fit(X, y, names)
    tot = sum(bo.gain.values())
    print("boosted, share of split gain (largest 12): " +
          ", ".join(f"{n} {100 * g / tot:.0f}%" for n, g in bo.gain.most_common(12)))
    single_rules(rows, X, y, names, base)

    if a.real:
        transfer(a, rows, X, y, names, base, scores, vehicles)


def lomo(rows, X, y, names, base, scores, a):
    """Leave one vehicle class out: every seed's candidates scored by fits that saw neither that seed
    nor any candidate on a vehicle of that class (the seeds share the vehicle meshes, so leaving a
    seed out does not hold out a shape); the threshold keeps classify's pooled false alarms."""
    print("\n== Leave one vehicle class out (and the seed): recall of the unseen class at classify's false alarms")
    g = np.array([r["group"] for r in rows])
    vc = np.array([r.get("vclass") or "" for r in rows])
    fas_b = int((base & (y == 0)).sum())
    classes = sorted({c for c in vc if c})
    print("| class | vehicle candidates | classify | " + " | ".join(f"{k}, seen | {k}, unseen" for k in scores) + " |")
    print("|---" * (3 + 2 * len(scores)) + "|")
    out = {}
    for kind in scores:
        for m in classes:
            s = np.zeros(len(rows))
            for k in folds(rows):
                te = g == k
                tr = ~te & ~((y == 1) & (vc == m))
                s[te] = fit_model(kind, X[tr], y[tr], names, a).score(X[te])
            t = thr_for_fas(s, y, fas_b)
            t0 = thr_for_fas(scores[kind], y, fas_b)
            sel = (y == 1) & (vc == m)
            out[(kind, m)] = (int((scores[kind][sel] >= t0).sum()), int((s[sel] >= t).sum()))
    for m in classes:
        sel = (y == 1) & (vc == m)
        n = int(sel.sum())
        cells = [rate(int((base & sel).sum()), n)]
        for kind in scores:
            cells += [rate(out[(kind, m)][0], n), rate(out[(kind, m)][1], n)]
        print(f"| {m} | {n} | " + " | ".join(cells) + " |")


def single_rules(rows, X, y, names, base):
    """One feature, one threshold, on top of classify: a veto of its answers (drop answered
    candidates beyond t) and a rescue of its refusals (answer refused candidates beyond t), each
    threshold chosen on the other seeds (leave one seed out) to maximise (false alarms removed -
    vehicle candidates lost) or (vehicle candidates gained - false alarms added)."""
    print("\n== One feature as a new rule on top of classify (threshold chosen leaving the seed out)")
    g = np.array([r["group"] for r in rows])

    def best(xs, good, bad, mask):
        # rule: hit when x >= t (dir +1) or x <= t (dir -1); value = good hits - bad hits
        out = (0, None, None)
        ok = mask & ~np.isnan(xs)
        vals = np.unique(xs[ok])
        for d in (1, -1):
            for t in vals:
                hit = ok & ((xs >= t) if d == 1 else (xs <= t))
                v = int((hit & good).sum()) - int((hit & bad).sum())
                if v > out[0]:
                    out = (v, t, d)
        return out

    res = []
    for mode in ("veto", "rescue"):
        mask = base if mode == "veto" else ~base
        good = (y == 0) if mode == "veto" else (y == 1)
        bad = ~good
        for j, n in enumerate(names):
            xs = X[:, j]
            tot_good = tot_bad = 0
            for k in folds(rows):
                te = g == k
                v, t, d = best(xs, good & ~te, bad & ~te, mask & ~te)
                if t is None:
                    continue
                hit = te & mask & ~np.isnan(xs) & ((xs >= t) if d == 1 else (xs <= t))
                tot_good += int((hit & good).sum())
                tot_bad += int((hit & bad).sum())
            res.append((tot_good - tot_bad, mode, n, tot_good, tot_bad))
    res.sort(key=lambda t: -t[0])
    for mode in ("veto", "rescue"):
        top = [r for r in res if r[1] == mode][:5]
        what = ("false alarms removed / vehicle candidates lost" if mode == "veto"
                else "vehicle candidates gained / false alarms added")
        print(f"{mode} ({what}, out of fold): " + ", ".join(f"{n} {gd}/{bd}" for _, _, n, gd, bd in top))


def transfer(a, rows, X, y, names, base, scores, vehicles_sim):
    run, truth = a.real
    rr, vv = load_real(run, truth)
    Xr = raw_matrix(rr, names)
    extra = sorted({k for r in rr for k in r["feats"]} - set(names) - set(a.dropped))
    yr = np.array([r["label"] == "vehicle" for r in rr], dtype=float)
    br = np.array([r["answered"] for r in rr])
    print("\n== Transfer: trained on every simulated candidate, tested on the real development tiles "
          "(classify.ini's decision there)")
    print(f"real: {len({r['seed'] for r in rr})} tiles, {len(rr)} candidates ({int(yr.sum())} on a labelled "
          f"vehicle), {len(vv)} labelled vehicles ({sum(v['vis'] == 'clear' for v in vv)} clear)"
          + (f"; columns not in the simulated data, unused: {', '.join(extra)}" if extra else ""))
    vclear = [v for v in vv if v["vis"] == "clear"]
    answers = {"classify.ini": list(br)}
    for kind in ("logistic", "boosted"):
        # the threshold: on the simulated out-of-fold scores, keeping classify's simulated recall
        s_sim = scores[kind]
        t = thr_for_hits(s_sim, y, int((base & (y == 1)).sum()))
        m = fit_model(kind, X, y, names, a)
        s = m.score(Xr)
        answers[f"{kind} (sim threshold)"] = list(s >= t)
        tr = thr_for_hits(s, yr, int((br & (yr == 1)).sum()))
        answers[f"{kind} (matched after the fact)"] = list(s >= tr)
        # the learned decision only past classify's size and density gates (too_small, too_sparse,
        # too_large stay refused): it replaces the shape and surface gates alone
        gate = np.array([r["reason"] not in ("too_small", "too_sparse", "too_large") for r in rr])
        answers[f"{kind} (sim threshold, past the size/density gates)"] = list((s >= t) & gate)
        # beside classify: the learned decision as a veto on its answers, or a rescue of its refusals
        answers[f"classify.ini and {kind} (a veto)"] = list((s >= t) & br)
        answers[f"classify.ini or {kind} (a rescue)"] = list((s >= t) | br)
        pos, neg = s[yr == 1], s[yr == 0]
        auc = (np.sum(pos[:, None] > neg[None, :]) + 0.5 * np.sum(pos[:, None] == neg[None, :])) / (len(pos) * len(neg))
        pos, neg = s_sim[y == 1], s_sim[y == 0]
        print(f"{kind}: AUC on the real candidates {auc:.3f}")
    print("\n| decision | clear found | all found | false alarms, urban | false alarms, forest |")
    print("|---|---|---|---|---|")
    forest = [r["seed"].startswith("forest") for r in rr]
    for name, ans in answers.items():
        fc, nc, _, _ = outcome(rr, vclear, ans)
        f, n, k, _ = outcome(rr, vv, ans)
        kf = sum(1 for r, x, fo in zip(rr, ans, forest) if x and fo and r["label"] != "vehicle")
        print(f"| {name} | {rate(fc, nc)} | {rate(f, n)} | {fa(k - kf)} | {fa(kf)} |")
    vv2 = [dict(v, level=v["level"]) for v in vv]
    table("Per real tile", rr, vv2, {k: v for k, v in answers.items() if "after" not in k and "classify.ini " not in k},
          "level")

    # why: each feature's own ranking of vehicle against not, on simulated and on real candidates
    print("\nOne feature alone: AUC of vehicle against not (oriented as on the simulated candidates; "
          "measured share = candidates with a value)")
    print("| feature | simulated AUC | real AUC | simulated measured | real measured |")
    print("|---|---|---|---|---|")

    def auc1(x, yy):
        ok = ~np.isnan(x)
        p, n = x[ok & (yy == 1)], x[ok & (yy == 0)]
        if len(p) == 0 or len(n) == 0:
            return float("nan")
        return (np.sum(p[:, None] > n[None, :]) + 0.5 * np.sum(p[:, None] == n[None, :])) / (len(p) * len(n))
    lines = []
    for j, n in enumerate(names):
        a_s, a_r = auc1(X[:, j], y), auc1(Xr[:, j], yr)
        if math.isnan(a_s):
            continue
        flip = a_s < 0.5
        a_s, a_r = (1 - a_s, 1 - a_r) if flip else (a_s, a_r)
        lines.append((a_s, f"| {n}{' (low = vehicle)' if flip else ''} | {a_s:.2f} | {a_r:.2f} | "
                           f"{np.mean(~np.isnan(X[:, j])):.2f} | {np.mean(~np.isnan(Xr[:, j])):.2f} |"))
    for _, ln in sorted(lines, key=lambda t: -t[0]):
        print(ln)
    if a.quick:
        return

    # leave one real tile out: real only, and simulated + real
    print("\n== Leave one real tile out (trained on the other real tiles; and on them plus all simulated)")
    names_r = sorted(set(names) | set(extra))
    Xr2 = raw_matrix(rr, names_r)
    Xs2 = raw_matrix(rows, names_r)
    g = np.array([r["group"] for r in rr])
    out = {"classify.ini": list(br)}
    for kind in ("logistic", "boosted"):
        for mix in ("real", "sim+real"):
            ans = np.zeros(len(rr), dtype=bool)
            for k in folds(rr):
                te = g == k
                tr_rows = [r for r, t in zip(rr, ~te) if t]
                Xt, yt, bt = Xr2[~te], yr[~te], br[~te]
                if mix == "sim+real":
                    Xt = np.vstack([Xt, Xs2])
                    yt = np.concatenate([yt, y])
                    bt = np.concatenate([bt, base])
                    tr_rows = tr_rows + rows
                # threshold: inner leave-one-group-out on the training rows, keeping classify's hits
                s_in = oof(kind, tr_rows, Xt, yt, names_r, a)
                t = thr_for_hits(s_in, yt, int((bt & (yt == 1)).sum()))
                ans[te] = fit_model(kind, Xt, yt, names_r, a).score(Xr2[te]) >= t
            out[f"{kind} ({mix})"] = list(ans)
    print("\n| decision | clear found | all found | false alarms, urban | false alarms, forest |")
    print("|---|---|---|---|---|")
    for name, ans in out.items():
        fc, nc, _, _ = outcome(rr, vclear, ans)
        f, n, k, _ = outcome(rr, vv, ans)
        kf = sum(1 for r, x, fo in zip(rr, ans, forest) if x and fo and r["label"] != "vehicle")
        print(f"| {name} | {rate(fc, nc)} | {rate(f, n)} | {fa(k - kf)} | {fa(kf)} |")


if __name__ == "__main__":
    main()
