#!/usr/bin/env python3
"""Which surface or shape cue refuses each candidate of a ladder tile, and by how much
(docs/decisions/classify.md §25).

  cuemargin.py RUN [RUN ...] [--tag TAG] [--params KEY=VALUE ...] [--all]

Each RUN is a directory of bench/detect/pieces.sh (scan.pcd with label and instance, truth.json,
cands-TAG/ with classify's verdicts in cands-TAG/<id>/class.json, as bench/detect/classlevel.sh
writes them). Per candidate it prints what it is (the vehicle it holds >= 80% of: `vehicle`; a
vehicle's part, 10-80%: `piece`; no vehicle >= 10%: the nearest clutter kind within 1.5 m of its
centre, else `veg`), classify's answer, and each vegetation cue as value / threshold (> 1
refuses): fill (threshold / value), below_share, ground_through, late_returns, roughness (the
plane roughness against max(roughness-floor, max-roughness x spacing); the floor is 0.1 m in
verdicts from before the option, classify.md §28). The thresholds are read from the verdict's
provenance (its parameters). Without --all only vehicles and candidates answered
vegetation_like or not_vehicle_shape, and every class answer on no vehicle, are printed.
Truth is read only here.
"""
import argparse, json, math, os, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "detect"))
from pieces import held_by  # noqa: E402


def length(text):
    """A length as classify's provenance gives it: 100mm, 10cm, 0.1m, 0.1 (m)."""
    for unit, scale in (("mm", 1e-3), ("cm", 1e-2), ("m", 1.0)):
        if text.endswith(unit):
            return float(text[: -len(unit)]) * scale
    return float(text)


def cues(v):
    f, p = v.get("features") or {}, v["provenance"]["parameters"]
    out = {}
    if f.get("fill") is not None:
        out["fill"] = float(p["min-fill"]) / max(f["fill"], 1e-6)
    out["below"] = f.get("below_share", 0) / float(p["max-below-share"])
    out["gthru"] = f.get("ground_through", 0) / float(p["max-ground-through"])
    if f.get("late_returns") is not None:
        out["late"] = f["late_returns"] / float(p["max-late-returns"])
    sp = (v.get("measured") or {}).get("spacing") or f.get("crop_spacing") or 0.2
    floor = length(p.get("roughness-floor", "0.1"))
    out["rough"] = f.get("top_roughness", 0) / max(floor, float(p["max-roughness"]) * sp)
    return out, f


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--tag", default="on")
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--extra", default="plateau_share,multi_returns,interior_points",
                    help="comma-separated features printed as they are")
    a = ap.parse_args()
    extra = [e for e in a.extra.split(",") if e]
    print("tile cand what cover size answer | fill below gthru late rough | " + " ".join(extra) + " | detail")
    for run in a.runs:
        c = os.path.join(run, "cands-" + a.tag)
        index = json.load(open(os.path.join(c, "index.json")))
        truth = json.load(open(os.path.join(run, "truth.json")))
        veh = {t["instance"]: t for t in truth["vehicles"]}
        total, held = held_by(index, run)
        for k, cand in enumerate(index["candidates"]):
            vp = os.path.join(c, cand["id"], "class.json")
            if not os.path.exists(vp):
                continue
            v = json.load(open(vp))
            share = {i: n / total[i] for i, n in held[k].items() if total.get(i)}
            best = max(share.items(), key=lambda kv: kv[1]) if share else (None, 0.0)
            cover = "-"
            if best[1] >= 0.8:
                what = "vehicle:%s/%d" % (veh[best[0]]["model"], best[0])
                cover = "%.2f" % veh[best[0]].get("canopy_cover", 0)
            elif best[1] >= 0.1:
                what = "piece:%s/%d(%.2f)" % (veh[best[0]]["model"], best[0], best[1])
            else:
                what, bd = "veg", 1.5
                x, y = cand["centre"][:2]
                for cl in truth.get("clutter", []):
                    d = math.hypot(x - cl["box"]["centre"][0], y - cl["box"]["centre"][1])
                    if d <= bd:
                        what, bd = "clutter:" + cl["kind"], d
            ans = v.get("class") or v.get("reason") or "-"
            if not a.all and not what.startswith("vehicle") and ans not in (
                    "vegetation_like", "not_vehicle_shape") and not v.get("class"):
                continue
            cs, f = cues(v)
            row = " ".join("%5.2f" % cs[n] if n in cs else "    -" for n in ("fill", "below", "gthru", "late", "rough"))
            ex = " ".join("%.3g" % f[e] if isinstance(f.get(e), (int, float)) else "-" for e in extra)
            print("%s %s %s %s %.1fx%.1fx%.1f %s | %s | %s | %s" % (
                os.path.basename(run), cand["id"], what, cover, cand["length"], cand["width"], cand["height"],
                ans, row, ex, v.get("detail", "")))


if __name__ == "__main__":
    main()
