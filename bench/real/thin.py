#!/usr/bin/env python3
"""Recall against density on the real development tiles, by thinning (bench/real/thin.sh's runs;
docs/decisions/real-tiles.md, stop 71).

  thin.py RUN_DIR TRUTH_DIR TILE [TILE ...]

RUN_DIR/s<seed>/f<fraction>/<tile>/ (a `make tile` run each on the thinned tile; thin.log,
tile.time, cands/index.json, detections.json, score.json). Prints, per seed and fraction: the
measured density (detect's index: all / first / ground points per m², per tile), the outcome as
the report counts it (bench/classify/realcal.py --figures: clear and all recall, precision
without the detections on uncertain objects, class right by group; forest false alarms per ha on
the area detect measures at fraction 1, the same ground at every fraction), the clear vehicles'
fates (bench/detect/realloss.py: detect's no_candidate, pieces, merged; classify's refused;
off_centre), and wall and CPU time; then per tile the clear recall and density at each fraction,
and clear recall pooled over tiles and fractions by the tile's measured density. Every rate with
its count and Wilson 95% interval (bench/rates.py), false alarms with the exact Poisson one.
Development tiles only.
"""
import collections, json, math, os, re, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, os.path.join(HERE, "..", "classify"))
from rates import poisson_exact, rate  # noqa: E402
from realcal import tile_outcome  # noqa: E402

REALLOSS = os.path.join(HERE, "..", "detect", "realloss.py")


def fnum(name):
    return float(name[1:])


def fates(run, labels, tile):
    """realloss.py's clear fates of one tile: {fate: count}."""
    p = subprocess.run([sys.executable, REALLOSS, run, labels, tile, "--visibility", "clear"], check=True,
                       capture_output=True, text=True)
    r = collections.Counter()
    for line in p.stdout.splitlines()[1:]:
        m = re.match(r"\s+(\S+): (\d+)$", line)
        if m:
            r[m.group(1)] += int(m.group(2))
    return r


def stage(fate):
    if fate in ("no_candidate", "pieces") or fate.startswith("merged"):
        return "detect"
    if fate.startswith("refused"):
        return "classify"
    return "answer"


def density(d):
    x = json.load(open(os.path.join(d, "cands", "index.json")))
    den = x.get("density") or {}
    return den, x


def fmt_d(v):
    return "–" if v is None else f"{v:.1f}"


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: thin.py RUN_DIR TRUTH_DIR TILE [TILE ...]")
    run, labels, tiles = sys.argv[1], sys.argv[2], sys.argv[3:]
    urban = [t for t in tiles if os.path.exists(os.path.join(labels, t + ".truth.json"))]
    forest = [t for t in tiles if t not in urban]
    seeds = sorted((s for s in os.listdir(run) if re.fullmatch(r"s\d+", s)), key=lambda s: int(s[1:]))
    rows, per_tile = [], {}
    for s in seeds:
        fr = sorted((f for f in os.listdir(os.path.join(run, s)) if re.fullmatch(r"f[0-9.]+", f)), key=fnum,
                    reverse=True)
        # forest area: detect's occupied cells on the whole tile (fraction 1, any seed; else this
        # seed's largest fraction): the same ground at every fraction
        whole = [os.path.join(run, q, "f1") for q in seeds if os.path.isdir(os.path.join(run, q, "f1"))]
        area = {}
        for t in forest:
            x = json.load(open(os.path.join(whole[0] if whole else os.path.join(run, s, fr[0]), t, "cands", "index.json")))
            area[t] = x["density"]["cell"] ** 2 * x["density"]["occupied_cells"] / 1e4
        for f in fr:
            base = os.path.join(run, s, f)
            tot = {"clear": [0, 0], "all": [0, 0], "prec": [0, 0], "cls": [0, 0]}
            fa, ha, fate, wall, cpu, missing = 0, 0.0, collections.Counter(), 0.0, 0.0, []
            for t in tiles:
                d = os.path.join(base, t)
                w, _, u, sy = (float(v) for v in open(os.path.join(d, "tile.time")).read().split()[-4:])
                wall += w
                cpu += u + sy
                den, _ = density(d) if os.path.exists(os.path.join(d, "cands", "index.json")) else ({}, None)
                thin = open(os.path.join(d, "thin.log")).read()
                m = re.search(r"kept (\d+) \(([0-9.]+)\) with (\d+) points", thin)
                rec = {"den": den, "wall": w, "cpu": u + sy, "kept_points": int(m.group(3)) if m else None}
                if not os.path.exists(os.path.join(d, "detections.json")):
                    missing.append(t)
                    per_tile[(s, f, t)] = rec
                    continue
                if t in urban:
                    o = tile_outcome(d, os.path.join(labels, t + ".truth.json"))
                    for k, v in o.items():
                        tot[k][0] += v[0]
                        tot[k][1] += v[1]
                    rec["clear"] = o["clear"]
                    rec["all"] = o["all"]
                    fc = fates(base, labels, t)
                    rec["fates"] = fc
                    fate.update(fc)
                else:
                    k = len(json.load(open(os.path.join(d, "detections.json")))["detections"])
                    fa += k
                    ha += area[t]
                    rec["fa"] = k
                per_tile[(s, f, t)] = rec
            rows.append((s, f, tot, fa, ha, fate, wall, cpu, missing))

    print("| seed | fraction | density all / first / ground (urban tiles, points/m²) | clear recall | all recall "
          "| precision | class right (group) | forest false alarms | clear lost: detect / classify / answer "
          "| clear lost by fate | wall s / CPU s (all tiles) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for s, f, tot, fa, ha, fate, wall, cpu, missing in rows:
        dens = []
        for t in urban:
            den = per_tile[(s, f, t)]["den"]
            dens.append(f"{fmt_d(den.get('all'))}/{fmt_d(den.get('first'))}/{fmt_d(den.get('ground'))}")
        lo, hi = poisson_exact(fa)
        fas = f"{fa} on {ha:.2f} ha = {fa / ha:.2f}/ha [{lo / ha:.2f}, {hi / ha:.2f}]" if ha else "–"
        by = collections.Counter()
        for k, v in fate.items():
            if k != "found":
                by[stage(k)] += v
        lost = " ".join(f"{k} {v}" for k, v in sorted(fate.items(), key=lambda t: -t[1]) if k != "found")
        miss = f" (not finished: {', '.join(missing)})" if missing else ""
        print(f"| {s[1:]} | {f[1:]} | {'; '.join(dens)} | {rate(*tot['clear'])} | {rate(*tot['all'])} | "
              f"{rate(*tot['prec'])} | {rate(*tot['cls'])} | {fas} | {by['detect']} / {by['classify']} / "
              f"{by['answer']} | {lost or '–'} | {wall:.0f} / {cpu:.0f}{miss} |")
    print()
    print("Urban tiles in the density column:", ", ".join(urban))
    print()
    print("| seed | fraction | tile | points kept | density all / first / ground | clear recall | all recall "
          "| forest false alarms | wall s / CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for (s, f, t), r in per_tile.items():
        den = r["den"]
        print(f"| {s[1:]} | {f[1:]} | {t} | {r['kept_points']} | {fmt_d(den.get('all'))} / {fmt_d(den.get('first'))} / "
              f"{fmt_d(den.get('ground'))} | {rate(*r['clear']) if 'clear' in r else ''} | "
              f"{rate(*r['all']) if 'all' in r else ''} | {r.get('fa', '')} | {r['wall']:.1f} / {r['cpu']:.1f} |")
    print()
    # clear recall pooled by the tile's measured density (every urban tile at every fraction)
    bins = [0, 4, 6, 8, 11, 15, 20, 30, 1e9]
    pooled = collections.OrderedDict((i, [0, 0, 0]) for i in range(len(bins) - 1))
    for (s, f, t), r in per_tile.items():
        if "clear" not in r or r["den"].get("all") is None:
            continue
        a = r["den"]["all"]
        i = max(k for k in range(len(bins) - 1) if a >= bins[k])
        pooled[i][0] += r["clear"][0]
        pooled[i][1] += r["clear"][1]
        pooled[i][2] += 1
    print("| tile density all (points/m²) | tile runs | clear recall |")
    print("|---|---|---|")
    for i, (k, n, runs) in pooled.items():
        if runs:
            hi = "" if bins[i + 1] >= 1e9 else f"{bins[i + 1]:g}"
            print(f"| {bins[i]:g}–{hi} | {runs} | {rate(k, n)} |")


if __name__ == "__main__":
    main()
