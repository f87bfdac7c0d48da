#!/usr/bin/env python3
"""tile_candidates.py MANIFEST OUTDIR [--verify BIN | --reuse] [-- VERIFY-ARGS...]: verify's answers on the
model-level candidates of scene tiles, with what each candidate truly is (docs/decisions/verify.md
§14, §15). Standard library only.

MANIFEST is score's tile list (`detections.json truth.json noise cover` per line, as make writes
it: out/.../tiles.txt). For every candidate of a tile whose model chain ran (cands/<id>/match.json
and verdict.json exist), verify is run again on the same match, samples, segments, modelbase and
transform (read from the existing verdict) with `--config share/params/verify.ini` and the extra
VERIFY-ARGS, writing OUTDIR/<n>/<id>.json (n = the tile's line); an existing output is reused. Then
one CSV row per candidate goes to stdout:

  tile,cover,candidate,truth,truth_model,best_model,best_score,best_explained,best_violation,
  second_score,box_score,box_explained,box_violation,answer,confidence,verdict_class

truth = "vehicle" when the candidate's centre (index.json) lies in a true vehicle's footprint
(else within 1.5 m of its centre), the clutter kind when in a clutter object's box (else its
centre within 1.5 m), else "none"; truth_model = the vehicle's model.

--reuse reads each candidate's own cands/<id>/verdict.json instead of running verify again (no
VERIFY-ARGS, OUTDIR unused): its hypotheses' and box's scores are what a re-run with only other
decision options (--box-margin, --accept, the confidences) would give, so the score columns are the
same (checked on 24 candidates, verify.md §18); answer and confidence are then the run's own. The
run must have been verified with the parameters wanted (e.g. make's P= with seen-spacing = 1)."""
import csv, json, math, os, subprocess, sys


def inside(px, py, cx, cy, length, width, heading_deg):
    h = math.radians(heading_deg)
    dx, dy = px - cx, py - cy
    u = math.cos(h) * dx + math.sin(h) * dy
    w = -math.sin(h) * dx + math.cos(h) * dy
    return abs(u) <= length / 2 and abs(w) <= width / 2


def in_polygon(px, py, ring):
    n, c = len(ring), False
    for i in range(n):
        (x1, y1), (x2, y2) = ring[i], ring[(i + 1) % n]
        if (y1 > py) != (y2 > py) and px < (x2 - x1) * (py - y1) / (y2 - y1) + x1:
            c = not c
    return c


def truth_of(truth, x, y):
    for v in truth["vehicles"]:
        if in_polygon(x, y, v["footprint"]):
            return "vehicle", v["model"]
    for c in truth.get("clutter", []):
        b = c["box"]
        if inside(x, y, b["centre"][0], b["centre"][1], b["size"][0], b["size"][1], b["heading"]):
            return c["kind"], ""
    best = (1.5, "none", "")
    for v in truth["vehicles"]:
        d = math.hypot(x - v["pose"]["x"], y - v["pose"]["y"])
        if d < best[0]:
            best = (d, "vehicle", v["model"])
    for c in truth.get("clutter", []):
        d = math.hypot(x - c["box"]["centre"][0], y - c["box"]["centre"][1])
        if d < best[0]:
            best = (d, c["kind"], "")
    return best[1], best[2]


def transform_arg(v):
    m = v["transform"]["matrix"]
    return ",".join(repr(float(x)) for x in m)


def main():
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[:args.index("--")]
    verify = "build/bin/verify"
    reuse = "--reuse" in args
    if reuse:
        args.remove("--reuse")
        if extra:
            sys.exit("tile_candidates.py: --reuse takes no VERIFY-ARGS (the run's verdicts are read as they are)")
    if "--verify" in args:
        i = args.index("--verify")
        verify = args[i + 1]
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    manifest, outdir = args
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["tile", "cover", "candidate", "truth", "truth_model", "best_model", "best_score",
                "best_explained", "best_violation", "second_score", "box_score", "box_explained",
                "box_violation", "answer", "confidence", "verdict_class"])
    for n, line in enumerate(l.split() for l in open(manifest) if l.strip()):
        det, truth_path, _noise, cover = line
        run = os.path.dirname(det)
        truth = json.load(open(truth_path))
        index = json.load(open(os.path.join(run, "cands", "index.json")))
        if not reuse:
            os.makedirs(os.path.join(outdir, str(n)), exist_ok=True)
        for c in index["candidates"]:
            cd = os.path.join(run, "cands", c["id"])
            old = os.path.join(cd, "verdict.json")
            if not os.path.isfile(os.path.join(cd, "match.json")) or not os.path.isfile(old) \
                    or os.path.getsize(old) == 0:
                continue
            out = old if reuse else os.path.join(outdir, str(n), c["id"] + ".json")
            if not os.path.isfile(out):
                ov = json.load(open(old))
                cmd = [verify, "--config", "share/params/verify.ini", "-i", os.path.join(cd, "match.json"),
                       "--points", os.path.join(cd, "samples.pcd"), "--segments",
                       os.path.join(cd, "segments.json"), "--modelbase", ov["provenance"]["inputs"][3],
                       "--transform", transform_arg(ov), "-o", out, "-q"] + extra
                subprocess.run(cmd, check=True)
            v = json.load(open(out))
            hs = sorted(v["hypotheses"], key=lambda h: -h["score"])
            best = hs[0] if hs else None
            second = max((h["score"] for h in hs if best and h["model"] != best["model"]), default=0)
            kind, tmodel = truth_of(truth, c["centre"][0], c["centre"][1])
            box = v.get("box") or {}
            w.writerow([n, cover, c["id"], kind, tmodel, best["model"] if best else "",
                        f"{best['score']:.4f}" if best else 0, f"{best['explained']:.4f}" if best else 0,
                        f"{best['free_space_violation']:.4f}" if best else 1, f"{second:.4f}",
                        f"{box.get('score', 0):.4f}", f"{box.get('explained', 0):.4f}",
                        f"{box.get('free_space_violation', 1):.4f}", v["model"] or "none",
                        f"{v['confidence']:.4f}", v.get("class") or ""])


if __name__ == "__main__":
    main()
