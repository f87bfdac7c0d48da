#!/usr/bin/env python3
"""heldout_none.py MANIFEST CANDS_CSV ANSWERS_JSONL CAL_INI [--below D] (docs/decisions/verify.md §19):
a density-aware statement of confidence for the final `none` answers, measured held out by seed on
development scene runs. Standard library only.

MANIFEST: the runs' score list (out/scenes/tiles.txt; each run's cands/index.json is read beside
its detections for the candidates' object density, as collect reads it). CANDS_CSV:
bench/verify/tile_candidates.py's rows of the same runs (verify's scores per model-level
candidate). ANSWERS_JSONL: bench/verify/final_answers.py's final answers of the same runs,
collected with CAL_INI (their stated p; the level's own p is recovered through CAL_INI's map).

Variants, each fitted on some seeds and stated on the others (pooled over the folds):
  as rendered   CAL_INI as it is (nothing fitted on these seeds)
  refit         collect's four maps refitted (bench/collect/calibrate.py fit_platt), none one source
  split         collect's maps refitted with verify's none split in two sources by the candidate's
                object density (index.json): coarse below D (default 370 points/m², the density
                rule's dense end, common/density_scale.h kDenseDensity) and dense at or above it
  split-none    the same, but only the two none maps refitted (CAL_INI's model, class and
                none-class maps kept): what share/params/calibration.ini holds
  verify-term   verify's none logistic refitted with a coarse term (score, margin, score - box,
                [density < D]) on the model-level candidates (label "a vehicle is there", as
                bench/verify/calibrate_tiles.py), then collect's maps refitted on top of it
Folds: 2-fold (seeds at odd / even positions, as bench/verify/heldout_seeds.py) and leave one
seed out. Printed: each variant's reliability table (calibrate.py's, bins of >= 20 answers judged
within ±10 points), the maps of the split fitted on all seeds (what calibration.ini holds), and
the split variant's none answers by density group."""
import importlib.util
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, os.path.join(HERE, "..", "verify"))
import calibrate_tiles as ct  # noqa: E402
from rates import wilson  # noqa: E402

_spec = importlib.util.spec_from_file_location("collect_calibrate", os.path.join(HERE, "calibrate.py"))
cal = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cal)

OLD_NONE = (0.059, -0.364, 1.018, 5.177)  # share/params/verify.ini none-* (verify.md §15)


def index_density(run_dir):
    """Object density per candidate id of a run (documents::Candidate::object_density)."""
    d = json.load(open(os.path.join(run_dir, "cands", "index.json")))
    out = {}
    for c in d["candidates"]:
        if c.get("density") is not None:
            out[c["id"]] = c["density"]
        elif c.get("object_points") is not None and c["length"] * c["width"] > 0:
            out[c["id"]] = c["object_points"] / (c["length"] * c["width"])
    return out


def none_p(w, x):
    return 1 - ct.sig(sum(a * b for a, b in zip(w, (1,) + tuple(x))))


def main(argv):
    below = 370.0
    if "--below" in argv:
        i = argv.index("--below")
        below = float(argv[i + 1])
        del argv[i:i + 2]
    if len(argv) != 4:
        sys.exit(__doc__)
    manifest, cands_csv, answers, cal_ini = argv
    lines = [l.split() for l in open(manifest) if l.strip()]
    dens = [index_density(os.path.dirname(l[0])) for l in lines]
    seed_of = [int(l[1].split("tile-")[1].split("/")[0]) for l in lines]
    cal_maps = cal.read_ini(cal_ini)
    if any(cal_maps[k][:2] != cal_maps["none"][:2] for k in ("none-dense", "none-coarse")):
        # final_answers.py's rows know one none source: the level's own p is recovered through it.
        sys.exit(f"heldout_none.py: {cal_ini} splits verify's none by density; the answers must have been "
                 "collected with one none map (a file of before the split, or --coarse-none-below 0): give that file")

    fin = [json.loads(l) for l in open(answers)]
    for r in fin:
        m = cal_maps[r["source"]]
        r["p_raw"] = ct.sig((cal.logit(r["p"]) - m[0]) / m[1]) if (m[0], m[1]) != (0.0, 1.0) else r["p"]
        r["idx_density"] = dens[r["tile"]].get(r["candidate"])
        r["coarse"] = r["idx_density"] is not None and r["idx_density"] < below
        r["grp"] = r["source"] + ("-coarse" if r["source"] == "none" and r["coarse"] else "")
    rows = ct.load([cands_csv])
    for d in rows:
        t = int(d["tile"].split(":")[1])
        d["seed"] = seed_of[t]
        dd = dens[t].get(d["candidate"])
        d["coarse"] = dd is not None and dd < below
    seeds = sorted(set(seed_of))
    n_none = [r for r in fin if r["source"] == "none"]
    print(f"seeds {seeds}; {len(fin)} final answers ({len(n_none)} verify nones, "
          f"{sum(r['coarse'] for r in n_none)} of them coarse: object density < {below:g} points/m²); "
          f"{len(rows)} model-level candidates ({sum(d['coarse'] for d in rows)} coarse)")
    # The rejection's "density" (classify's rectangle when it answered) and the index's disagree on
    # which side of the line some candidates are: say how many.
    other = sum(1 for r in n_none if r.get("density") is not None and (r["density"] < below) != r["coarse"])
    print(f"verify nones on the other side of {below:g} by the rejection's density (classify's): {other}")

    def fit_maps(train, key):
        return {g: cal.fit_platt([dict(p=r["p_raw"], right=r["right"]) for r in train if r[key] == g])
                for g in {r[key] for r in fin}}

    def verify_term_p(w, r):
        return none_p(w, (r["s"], r["margin"], r["over_box"], 1.0 if r["coarse"] else 0.0))

    def variant(name, train_seeds, test):
        train = [r for r in fin if r["seed"] in train_seeds]
        if name == "refit":
            maps = fit_maps(train, "source")
            return [(cal.LEVEL[r["source"]], cal.apply(maps[r["source"]][:2], r["p_raw"]), r["right"], r) for r in test]
        if name in ("split", "split-none"):
            maps = fit_maps(train, "grp")
            if name == "split-none":  # CAL_INI's model, class and none-class maps kept
                maps.update({k: cal_maps[k] for k in ("model", "class", "none-class")})
            return [(cal.LEVEL[r["source"]], cal.apply(maps[r["grp"]][:2], r["p_raw"]), r["right"], r) for r in test]
        # verify-term: verify's none refitted with the coarse term on the training seeds'
        # candidates, collect's maps refitted on the training seeds' answers through it.
        cand = [d for d in rows if d["seed"] in train_seeds]
        xs = [(d["best_score"], d["margin"], d["over_box"], 1.0 if d["coarse"] else 0.0) for d in cand]
        w = ct.fit_logistic(xs, [1 if d["vehicle"] else 0 for d in cand], iters=4000)
        for r in fin:
            r["p_vt"] = verify_term_p(w, r) if r["source"] == "none" else r["p_raw"]
        maps = {s: cal.fit_platt([dict(p=r["p_vt"], right=r["right"]) for r in train if r["source"] == s])
                for s in cal.SOURCES}
        return [(cal.LEVEL[r["source"]], cal.apply(maps[r["source"]][:2], r["p_vt"]), r["right"], r) for r in test]

    def by_group(scored, title):
        """verify's nones by density group: right at mean stated, Brier score and log loss (a
        statement calibrated within each group stays so whatever the groups' mix)."""
        print(f"\n{title}: verify's nones by the candidate's object density")
        nones = [(p, ok, r) for _lv, p, ok, r in scored if r["source"] == "none"]
        for label, sel in ((f"< {below:g}", [x for x in nones if x[2]["coarse"]]),
                           (f">= {below:g}", [x for x in nones if not x[2]["coarse"]]), ("all", nones)):
            n, k = len(sel), sum(ok for _, ok, _ in sel)
            w = wilson(k, n)
            brier = sum((p - ok) ** 2 for p, ok, _ in sel) / n
            ll = -sum(math.log(min(max(p if ok else 1 - p, 1e-9), 1)) for p, ok, _ in sel) / n
            print(f"  {label}: {k}/{n} = {100 * k / n:.1f}% [{100 * w[0]:.1f}, {100 * w[1]:.1f}] right at mean stated "
                  f"{100 * sum(p for p, _, _ in sel) / n:.1f}%; Brier {brier:.4f}, log loss {ll:.4f}")

    def report(scored, title):
        by_group(scored, title)
        return cal.table([x[:3] for x in scored], title)

    as_rendered = [(cal.LEVEL[r["source"]], r["p"], r["right"], r) for r in fin]
    summary = {}
    summary["as rendered"] = report(as_rendered, f"as rendered ({cal_ini}; nothing fitted on these seeds)")
    folds = {"2-fold by seed": [set(seeds[0::2]), set(seeds[1::2])],
             "leave one seed out": [set(seeds) - {s} for s in seeds]}
    for fname, trains in folds.items():
        for name in ("refit", "split", "split-none", "verify-term"):
            scored = []
            for tr in trains:
                scored += variant(name, tr, [r for r in fin if r["seed"] not in tr])
            summary[f"{name}, {fname}"] = report(scored, f"{name}, held out {fname}")

    maps = fit_maps(fin, "grp")
    print(f"\nsplit maps fitted on all seeds (calibration.ini; none-coarse = object density < {below:g}):")
    for g in sorted(maps):
        print(f"  {g}: bias {maps[g][0]:g}, slope {maps[g][1]:g}: {maps[g][2]}")
    for tr in folds["2-fold by seed"]:
        m = fit_maps([r for r in fin if r["seed"] in tr], "grp")
        print(f"  fold fitted on {sorted(tr)}:", {g: m[g][:2] for g in sorted(m)})

    # The split's held-out none answers by group (2-fold).
    print("\nnone answers by density group, split held out 2-fold by seed:")
    for coarse in (True, False):
        for tr in folds["2-fold by seed"]:
            m = fit_maps([r for r in fin if r["seed"] in tr], "grp")
            for r in fin:
                if r["seed"] not in tr:
                    r["p_split"] = cal.apply(m[r["grp"]][:2], r["p_raw"])
        for lo, hi in ((0, 0.5), (0.5, 0.8), (0.8, 0.9), (0.9, 1.01)):
            b = [r for r in n_none if r["coarse"] == coarse and lo <= r["p_split"] < hi]
            if not b:
                continue
            k = sum(r["right"] for r in b)
            w = wilson(k, len(b))
            print(f"  {'coarse' if coarse else 'dense '} none {lo:.1f}-{min(hi, 1):.1f}: {k}/{len(b)} = "
                  f"{100 * k / len(b):.1f}% [{100 * w[0]:.1f}, {100 * w[1]:.1f}] at "
                  f"{100 * sum(r['p_split'] for r in b) / len(b):.1f}%")
    print("\nbins of >= 20 answers outside ±10 points:")
    for k, v in summary.items():
        print(f"  {k}: {v}")


if __name__ == "__main__":
    main(sys.argv[1:])
