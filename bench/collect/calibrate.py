#!/usr/bin/env python3
"""calibrate.py: the calibration of the confidence a final answer states (collect --calibration,
share/params/calibration.ini; docs/decisions/verify.md §16). Standard library only.

  calibrate.py RUN... [--fit] [--write INI] [--calibration INI] [--radius 1.5] [--coarse-none-below 370]

Each RUN is MANIFEST:MATCHES, a scene experiment's score inputs and outputs: the score's tile
list (out/scenes/tiles.txt: detections truth noise cover per line, read from the working
directory) and the matches.csv score wrote from it (results/scenes/matches.csv; its "tile" is the
line of the manifest). The detections.json files must have been written WITHOUT a calibration
(collect's own levels' confidences), as the fit maps those.

Every final answer is one row: its source (model: verify's model answer; class: classify's
class answer; verify's none where both levels rejected or classify did not answer: none-dense on
a candidate of at least --coarse-none-below object points per m² (its cands/index.json beside the
detections, as collect reads it; default 370, collect's: verify.md §19) or of unknown density,
none-coarse below it (with --coarse-none-below 0 both are none, as collect's ablation states
them); none-class: classify's none where the model chain did not run or failed), the confidence
it stated, and
whether it was right, as score's reliability table judges it (tools/score/intervals.cpp): a
detection is right when its outcome is "right"; a rejection is right unless a true vehicle that
no detection found (a "missed" row of matches.csv) lies within RADIUS of the candidate's centre.

The map per source (none: fitted on all of verify's nones, the map of collect --coarse-none-below
0): p' = logistic(bias + slope logit(p)) (Platt scaling; targets smoothed as
Platt's (N+ + 1)/(N+ + 2) and 1/(N- + 2), which keeps a source with no wrong answer finite).
Both bias and slope are fitted when the source has at least MIN_EACH right and MIN_EACH wrong
answers; else the bias alone (slope 1: the level's ranking and spread kept, its level moved) when
it has at least MIN_ANSWERS answers; else the identity (too few answers to say anything).

Printed: per source the counts and the map; the reliability table (answers by stated confidence
in tenths, share right with Wilson's 95% interval, the mean stated, and whether it lies within
±10 points, judged in bins of at least 20 answers) of the final answers' levels (model, class,
none: both none sources together, as score shows them): as stated (--calibration: through that
file's maps), with the maps fitted in-sample, and 2-fold held out by render (the tiles' truth
files: fit on one half of the renders, applied to the other)."""
import csv, math, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import wilson  # noqa: E402

SOURCES = ("model", "class", "none", "none-class", "none-dense", "none-coarse")
LEVEL = {"model": "model", "class": "class", "none": "none", "none-class": "none", "none-dense": "none",
         "none-coarse": "none"}
VERIFY_NONE = ("none", "none-dense", "none-coarse")  # the rows the none map is fitted on
COARSE_NONE_BELOW = 370.0  # collect --coarse-none-below (common/density_scale.h kDenseDensity)
MIN_EACH, MIN_ANSWERS = 10, 20


def read_matches(matches):
    """score's matches.csv: right[(tile, candidate)] for every answer judged, and the missed
    vehicles' positions per tile."""
    right, missed = {}, {}
    for r in csv.DictReader(open(matches)):
        t = int(r["tile"])
        if r["outcome"] == "missed":
            missed.setdefault(t, []).append((float(r["x"]), float(r["y"])))
        else:
            right[(t, r["candidate"])] = r["outcome"] == "right"
    return right, missed


def rejected_source(x):
    """A rejected candidate's map: "none" (the model chain's none, or no class answer) or
    "none-class" (classify refused it)."""
    chain = x.get("model_chain")
    classified = x["verdict"].endswith("class.json") or chain is not None
    return "none" if (not classified or chain == "none") else "none-class"


def index_density(det):
    """Object density per candidate id (documents::Candidate::object_density) of the index beside
    a run's detections (<run>/cands/index.json); {} when there is none."""
    path = os.path.join(os.path.dirname(det), "cands", "index.json")
    if not os.path.isfile(path):
        return {}
    out = {}
    for c in __import__("json").load(open(path))["candidates"]:
        if c.get("density") is not None:
            out[c["id"]] = c["density"]
        elif c.get("object_points") is not None and c["length"] * c["width"] > 0:
            out[c["id"]] = c["object_points"] / (c["length"] * c["width"])
    return out


def load(run, radius):
    manifest, matches = run.split(":")
    tiles = [line.split() for line in open(manifest) if line.strip()]
    right, missed = read_matches(matches)
    rows = []
    for t, (det, truth, _noise, _cover) in enumerate(tiles):
        d = __import__("json").load(open(det))
        dens = index_density(det)
        for x in d["detections"]:
            if x.get("confidence") is None:
                continue
            rows.append(dict(render=truth, source=x["level"], p=x["confidence"], right=right[(t, x["candidate"])]))
        for x in d["rejected"]:
            if x.get("confidence") is None:
                continue
            source = rejected_source(x)
            if source == "none" and COARSE_NONE_BELOW > 0:
                source = "none-coarse" if dens.get(x["candidate"], math.inf) < COARSE_NONE_BELOW else "none-dense"
            px, py = x["position"]["x"], x["position"]["y"]
            costs = any(math.hypot(vx - px, vy - py) <= radius for vx, vy in missed.get(t, []))
            rows.append(dict(render=truth, source=source, p=x["confidence"], right=not costs))
    return rows


def logit(p):
    p = min(max(p, 1e-9), 1 - 1e-9)
    return math.log(p / (1 - p))


def sig(z):
    return 1 / (1 + math.exp(-max(-50, min(50, z))))


def apply(m, p):
    bias, slope = m
    return p if (bias, slope) == (0.0, 1.0) else sig(bias + slope * logit(p))


def fit_platt(rows):
    """(bias, slope, how) for one source's rows (see the module's text)."""
    n_pos = sum(r["right"] for r in rows)
    n_neg = len(rows) - n_pos
    if len(rows) < MIN_ANSWERS:
        return (0.0, 1.0, f"identity ({len(rows)} answers < {MIN_ANSWERS})")
    t_pos, t_neg = (n_pos + 1) / (n_pos + 2), 1 / (n_neg + 2)
    xs = [logit(r["p"]) for r in rows]
    ts = [t_pos if r["right"] else t_neg for r in rows]
    both = n_pos >= MIN_EACH and n_neg >= MIN_EACH
    a, b = 0.0, 1.0
    # Newton's method on the cross-entropy (two parameters, or the bias alone).
    for _ in range(100):
        g0 = g1 = h00 = h01 = h11 = 0.0
        for x, t in zip(xs, ts):
            q = sig(a + b * x)
            w = q * (1 - q)
            g0 += q - t
            g1 += (q - t) * x
            h00 += w
            h01 += w * x
            h11 += w * x * x
        if both:
            det = h00 * h11 - h01 * h01
            if det <= 1e-12:
                break
            da, db = (h11 * g0 - h01 * g1) / det, (h00 * g1 - h01 * g0) / det
        else:
            da, db = g0 / max(h00, 1e-12), 0.0
        a, b = a - da, b - db
        if abs(da) + abs(db) < 1e-10:
            break
    how = f"bias and slope ({n_pos} right, {n_neg} wrong)" if both else \
        f"bias alone ({n_pos} right, {n_neg} wrong: fewer than {MIN_EACH} of one)"
    if not b > 0:
        return (0.0, 1.0, f"identity (the fitted slope {b:.3f} is not > 0)")
    return (round(a, 4), round(b, 4), how)


def fit(rows):
    return {s: fit_platt([r for r in rows if r["source"] == s or (s == "none" and r["source"] in VERIFY_NONE)])
            for s in SOURCES}


def read_ini(path):
    v = {}
    for line in open(path):
        line = line.split(";")[0].split("#")[0].strip()
        if line:
            k, x = (s.strip() for s in line.split("="))
            v[k] = float(x)
    # (a file of before verify.md §19 has no density maps: its none map, as collect used it)
    for s in ("none-dense", "none-coarse"):
        v.setdefault(f"{s}-bias", v["none-bias"])
        v.setdefault(f"{s}-slope", v["none-slope"])
    return {s: (v[f"{s}-bias"], v[f"{s}-slope"], path) for s in SOURCES}


def write_ini(path, maps, header):
    lines = [f"; {h}" for h in header]
    for s in SOURCES:
        lines += [f"; {s}: {maps[s][2]}", f"{s}-bias = {maps[s][0]:g}", f"{s}-slope = {maps[s][1]:g}"]
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def table(scored, title, header="| level | stated | answers | right | mean stated | within ±10 |\n|---|---|---|---|---|---|"):
    """scored: (level, stated, right) per answer; returns the bins of >= 20 answers outside ±10."""
    print(f"\n{title}\n{header}")
    fails = 0
    for level in ("model", "class", "none"):
        for b in range(10):
            lo, hi = b / 10, (b + 1) / 10
            xs = [(p, ok) for lv, p, ok in scored if lv == level and lo <= p and (p < hi or (b == 9 and p <= 1))]
            if not xs:
                continue
            n, k = len(xs), sum(ok for _, ok in xs)
            m = sum(p for p, _ in xs) / n
            w = wilson(k, n)
            within = "–" if n < 20 else ("yes" if abs(k / n - m) <= 0.10 else "**no**")
            fails += within == "**no**"
            print(f"| {level} | {lo:.1f}–{hi:.1f} | {n} | {k} = {100 * k / n:.1f}% [{100 * w[0]:.1f}, {100 * w[1]:.1f}] "
                  f"| {100 * m:.1f}% | {within} |")
    print(f"\nbins of >= 20 answers outside ±10 points: {fails}")
    return fails


def scored_with(rows, maps):
    return [(LEVEL[r["source"]], apply(maps[r["source"]][:2], r["p"]), r["right"]) for r in rows]


def main(argv):
    runs, radius, write, cal, do_fit = [], 1.5, None, None, False
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--radius", "--write", "--calibration", "--coarse-none-below"):
            if i + 1 >= len(argv):
                sys.exit(f"calibrate.py: {a} needs a value")
            v = argv[i + 1]
            i += 2
            if a == "--radius":
                radius = float(v)
            elif a == "--coarse-none-below":
                global COARSE_NONE_BELOW
                COARSE_NONE_BELOW = float(v)
            elif a == "--write":
                write, do_fit = v, True
            else:
                cal = v
            continue
        if a == "--fit":
            do_fit = True
        elif a.startswith("-"):
            sys.exit(__doc__)
        else:
            runs.append(a)
        i += 1
    if not runs:
        sys.exit(__doc__)
    rows = [r for run in runs for r in load(run, radius)]
    print("answers by source:", {s: (sum(r["source"] == s for r in rows),
                                     sum(r["source"] == s and not r["right"] for r in rows)) for s in SOURCES},
          "(answers, wrong)")
    ident = {s: (0.0, 1.0, "identity") for s in SOURCES}
    table(scored_with(rows, ident), "As stated (collect without --calibration)")
    if cal:
        table(scored_with(rows, read_ini(cal)), f"Through {cal}")
    if not do_fit:
        return
    maps = fit(rows)
    print("\nfitted maps (in-sample):")
    for s in SOURCES:
        print(f"  {s}: bias {maps[s][0]:g}, slope {maps[s][1]:g}: {maps[s][2]}")
    table(scored_with(rows, maps), "In-sample fit")
    renders = sorted({r["render"] for r in rows})
    half = [set(renders[0::2]), set(renders[1::2])]
    held = []
    for k in (0, 1):
        m = fit([r for r in rows if r["render"] in half[k]])
        print(f"  fold {k} (fit on {len(half[k])} renders):", {s: m[s][:2] for s in SOURCES})
        held += scored_with([r for r in rows if r["render"] in half[1 - k]], m)
    table(held, "2-fold held out by render (each half's answers through the other half's fit)")
    if write:
        write_ini(write, maps, [
            "The calibration of the confidence each final answer states (collect --calibration;",
            "docs/decisions/verify.md §16): p' = logistic(bias + slope ln(p / (1 - p))) per source.",
            "Fitted by bench/collect/calibrate.py on development tiles (" + " ".join(runs) + ").",
        ])
        print(f"\nwrote {write}")


if __name__ == "__main__":
    main(sys.argv[1:])
