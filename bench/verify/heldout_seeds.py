#!/usr/bin/env python3
"""heldout_seeds.py MANIFEST CANDS_CSV ANSWERS_JSONL CAL_INI (docs/decisions/verify.md §18): verify's none map and collect's none map
refitted on development seeds, checked on held-out seeds, at the verify level and end to end.

CANDS_CSV: tile_candidates.py's rows (verify --seen-spacing 1 --box-margin -1) of MANIFEST's runs.
ANSWERS_JSONL: final_answers.py's final answers of the same runs (collected with CAL_INI, stated p).
Folds: seeds split in two halves (odd/even position in the sorted list), each half fitted on the
other; the table pools both held-out halves."""
import json, math, os, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))
import calibrate_tiles as ct  # noqa: E402
from rates import wilson  # noqa: E402
import importlib.util
_spec = importlib.util.spec_from_file_location("collect_calibrate", os.path.join(HERE, "..", "collect", "calibrate.py"))
cal = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cal)

OLD_CONF = (-3.548, 0.132, 6.874, 3.044)
OLD_NONE = (0.059, -0.364, 1.018, 5.177)
ACCEPT = 0.556


def sig(z):
    return 1 / (1 + math.exp(-max(-50, min(50, z))))


def logit(p):
    p = min(max(p, 1e-12), 1 - 1e-12)
    return math.log(p / (1 - p))


def none_p(w, s, m, ob):
    return 1 - sig(w[0] + w[1] * s + w[2] * m + w[3] * ob)


def conf_p(w, s, m, ob):
    return sig(w[0] + w[1] * s + w[2] * m + w[3] * ob)


def platt_bias(ps, rights):
    """collect's fit (bench/collect/calibrate.py fit_platt) for one source; bias alone unless
    >= 10 right and >= 10 wrong."""
    rows = [dict(p=p, right=r) for p, r in zip(ps, rights)]
    return cal.fit_platt(rows)


def table(scored, title):
    """collect's reliability table (bench/collect/calibrate.py), with this script's header."""
    return cal.table(scored, title, "\n| answer | stated | answers | right [Wilson 95%] | mean stated | "
                     "within ±10 (≥ 20) |\n|---|---|---:|---|---:|---|")


def main():
    manifest, cands_csv, e2e, cal_ini = sys.argv[1:5]
    lines = [l.split() for l in open(manifest) if l.strip()]
    seed_of_line = {n: int(l[1].split("tile-")[1].split("/")[0]) for n, l in enumerate(lines)}
    rows = ct.load([cands_csv])
    for d in rows:
        d["seed"] = seed_of_line[int(d["tile"].split(":")[1])]
    fin = [json.loads(l) for l in open(e2e)]
    cal_maps = cal.read_ini(cal_ini)
    seeds = sorted({d["seed"] for d in rows})
    halves = [set(seeds[0::2]), set(seeds[1::2])]
    print("seeds", seeds, "halves", [sorted(h) for h in halves])
    print(f"{len(rows)} model-level candidates; final answers {len(fin)}")

    # Verify level: all-data fit (the coefficients proposed), and the held-out tables.
    P_all = ct.fit(rows)
    print("\nverify-level fit on all seeds:", P_all)
    ct.table(rows, dict(accept=ACCEPT, box_margin=0.0, conf=OLD_CONF, none=OLD_NONE), "verify level, current coefficients (no fit on these seeds)")
    held = []
    fold_P = []
    for h in (0, 1):
        Ph = ct.fit([d for d in rows if d["seed"] in halves[h]])
        Ph = dict(Ph, accept=ACCEPT)  # acceptance kept: only the confidences are refitted
        fold_P.append(Ph)
        print(f"fold {h} (fit on seeds {sorted(halves[h])}): conf {Ph['conf']}, none {Ph['none']} (accept of the fit would be {ct.fit([d for d in rows if d['seed'] in halves[h]])['accept']})")
        held += [(d, Ph) for d in rows if d["seed"] not in halves[h]]
    dec = [ct.decide(d, Ph) for d, Ph in held]
    table([(lv, p, ok) for lv, p, ok in dec], "verify level, refitted confidences, 2-fold held out by seed (accept 0.556)")

    # End to end: the final answers.
    def final(r, conf_w, none_w, maps):
        src = r["source"]
        p = r["p"]
        if src == "none" and "s" in r:
            p = cal.apply(maps["none"][:2], none_p(none_w, r["s"], r["margin"], r["over_box"]))
        elif src == "model" and "s" in r:
            p = cal.apply(maps["model"][:2], conf_p(conf_w, r["s"], r["margin"], r["over_box"]))
        else:
            p = cal.apply(maps[src][:2], r["p_raw"]) if "p_raw" in r else p
        return (cal.LEVEL[src], p, r["right"])

    # the level's own confidence (before collect's map), recovered from the stated one
    for r in fin:
        m = cal_maps[r["source"]]
        r["p_raw"] = sig((logit(r["p"]) - m[0]) / m[1]) if (m[0], m[1]) != (0.0, 1.0) else r["p"]
    f0 = table([final(r, OLD_CONF, OLD_NONE, cal_maps) for r in fin], "end to end as rendered (current verify.ini with seen-spacing 1, current calibration.ini)")
    # check the recomputation reproduces the stated
    dev = max(abs(final(r, OLD_CONF, OLD_NONE, cal_maps)[1] - r["p"]) for r in fin)
    print(f"(recomputed vs stated: max difference {dev:.2e})")

    variants = {}
    for name, refit_verify, refit_collect in (("collect's none/model maps refitted, verify kept", False, True),
                                             ("verify's confidences refitted, collect's maps kept", True, False),
                                             ("verify's confidences and collect's maps refitted", True, True)):
        scored = []
        for h in (0, 1):
            train = [r for r in fin if r["seed"] in halves[h]]
            test = [r for r in fin if r["seed"] not in halves[h]]
            cw, nw = (fold_P[h]["conf"], fold_P[h]["none"]) if refit_verify else (OLD_CONF, OLD_NONE)
            maps = dict(cal_maps)
            if refit_collect:
                for src, f in (("none", lambda r: none_p(nw, r["s"], r["margin"], r["over_box"]) if "s" in r else r["p_raw"]),
                               ("model", lambda r: conf_p(cw, r["s"], r["margin"], r["over_box"]) if "s" in r else r["p_raw"])):
                    tr = [r for r in train if r["source"] == src]
                    maps[src] = platt_bias([f(r) for r in tr], [r["right"] for r in tr])
                print(f"  [{name}] fold {h}: collect none {maps['none'][:2]} model {maps['model'][:2]}")
            scored += [final(r, cw, nw, maps) for r in test]
        variants[name] = table(scored, f"end to end, {name}, 2-fold held out by seed")

    # collect's none map split by the candidate's density (< 370 points/m²: the density rule's
    # coarse candidates) — not in collect; what such a map would state, verify kept.
    for r in fin:
        r["grp"] = r["source"] + ("-sparse" if r["source"] == "none" and (r.get("density") or 1e9) < 370 else "")
    scored = []
    for h in (0, 1):
        tr = [r for r in fin if r["seed"] in halves[h]]
        maps = {g: cal.fit_platt([dict(p=r["p_raw"], right=r["right"]) for r in tr if r["grp"] == g])
                for g in {r["grp"] for r in fin}}
        print(f"  [none split at 370 points/m²] fold {h}:", {g: maps[g][:2] for g in sorted(maps)})
        scored += [(cal.LEVEL[r["source"]], cal.apply(maps[r["grp"]][:2], r["p_raw"]), r["right"])
                   for r in fin if r["seed"] not in halves[h]]
    table(scored, "end to end, collect's maps refitted with none split at 370 points/m², 2-fold held out by seed")
    for lo, hi in ((0, 0.8), (0.8, 0.9), (0.9, 1.01)):
        for sparse in (True, False):
            b = [r for r in fin if cal.LEVEL[r["source"]] == "none" and lo <= r["p"] < hi and r.get("density")
                 and (r["density"] < 370) == sparse]
            if b:
                k = sum(r["right"] for r in b)
                w = wilson(k, len(b))
                print(f"as rendered, none {lo:.1f}-{min(hi, 1):.1f}, {'< 370' if sparse else '>= 370'} points/m²: "
                      f"{k}/{len(b)} = {100 * k / len(b):.1f}% [{100 * w[0]:.1f}, {100 * w[1]:.1f}] "
                      f"at {100 * sum(r['p'] for r in b) / len(b):.1f}%")

    # the bin in question on dev: what the none 0.8-0.9 answers are
    print("\nnone answers stated 0.8-0.9 as rendered:")
    from collections import Counter
    b = [r for r in fin if cal.LEVEL[r["source"]] == "none" and 0.8 <= r["p"] < 0.9]
    print(Counter((r["source"], r["right"], r.get("truth"), r.get("reason")) for r in b).most_common())
    print("by cover:", Counter((r["cover"], r["right"]) for r in b))
    print("by noise:", Counter((r["noise"], r["right"]) for r in b))


if __name__ == "__main__":
    main()
