#!/usr/bin/env python3
"""final_answers.py MANIFEST:MATCHES... --json OUT [--verdict-name verdict.json]: every final answer of scene runs with what it is
(docs/decisions/verify.md §18). Standard library only.

Rows as bench/collect/calibrate.py's (score's judgement), plus for the rejections: the verify
verdict's features (best score, margin over the next model, score - box) when the model chain
answered none, classify's reason, the truth at the candidate (tile_candidates.truth_of), the
candidate's density, cover, noise and seed. Written as JSON lines for the fits."""
import json, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tile_candidates import truth_of  # noqa: E402
import importlib.util  # noqa: E402
_spec = importlib.util.spec_from_file_location(
    "collect_calibrate", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "collect", "calibrate.py"))
cal = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cal)


VERDICT = "verdict.json"  # --verdict-name: the name collect read (collect --verdict-name)


def load(run, radius=1.5):
    manifest, matches = run.split(":")
    tiles = [line.split() for line in open(manifest) if line.strip()]
    right, missed = cal.read_matches(matches)
    rows = []
    for t, (det, truth_path, noise, cover) in enumerate(tiles):
        d = json.load(open(det))
        truth = json.load(open(truth_path))
        seed = int(truth_path.split("tile-")[1].split("/")[0])
        run_dir = os.path.dirname(det)
        base = dict(render=truth_path, seed=seed, cover=cover, noise=int(noise), tile=t)
        for x in d["detections"]:
            if x.get("confidence") is None:
                continue
            r = dict(base, candidate=x["candidate"], source=x["level"], p=x["confidence"],
                     right=right[(t, x["candidate"])])
            if x["level"] == "model":
                r.update(features(run_dir, x["candidate"]))
            rows.append(r)
        for x in d["rejected"]:
            if x.get("confidence") is None:
                continue
            source = cal.rejected_source(x)
            px, py = x["position"]["x"], x["position"]["y"]
            near = [math.hypot(vx - px, vy - py) for vx, vy in missed.get(t, [])]
            kind, tmodel = truth_of(truth, px, py)
            r = dict(base, candidate=x["candidate"], source=source, p=x["confidence"],
                     right=not any(dd <= radius for dd in near), reason=x["reason"],
                     density=x.get("density"), truth=kind, truth_model=tmodel,
                     missed_dist=min(near) if near else None)
            if source == "none":
                r.update(features(run_dir, x["candidate"]))
            rows.append(r)
    return rows


def features(run_dir, cid):
    p = os.path.join(run_dir, "cands", cid, VERDICT)
    if not os.path.isfile(p) or os.path.getsize(p) == 0:
        return {}
    v = json.load(open(p))
    hs = sorted(v["hypotheses"], key=lambda h: -h["score"])
    if not hs:
        return {"verify_p": v["confidence"]}
    best = hs[0]
    second = max((h["score"] for h in hs if h["model"] != best["model"]), default=0)
    box = (v.get("box") or {}).get("score", 0)
    return dict(verify_p=v["confidence"], best_model=best["model"], s=best["score"],
                margin=best["score"] - second, over_box=best["score"] - box,
                seen=v["provenance"]["parameters"].get("seen-spacing", "0"))


if __name__ == "__main__":
    args = sys.argv[1:]
    out = None
    if "--verdict-name" in args:
        i = args.index("--verdict-name")
        VERDICT = args[i + 1]
        del args[i:i + 2]
    if "--json" in args:
        i = args.index("--json")
        out = args[i + 1]
        del args[i:i + 2]
    rows = [r for a in args for r in load(a)]
    with open(out, "w") as f:
        for r in rows:
            f.write(json.dumps(r) + "\n")
    print(len(rows), "rows")
