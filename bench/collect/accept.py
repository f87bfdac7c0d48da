#!/usr/bin/env python3
"""accept.py: collect and score again finished development runs with `collect --class-accept T`
for each T (docs/decisions/open-set.md "Seventeenth round"). No stage runs again: each tile's
collect is its own run's collect (the parameters its detections.json's provenance records: the
same verdicts, class.json, modelbase, calibration, ...) plus --class-accept T; each score is the
run's own score (its score.json's parameters) on the re-collected tiles. T = 0 must give the
run's own matches.csv byte for byte (checked: "T=0 reproduces" or a failure). Prints per set,
cover and T: found at either level of the true vehicles, class right of the found, wrong class of
the true vehicles (bench/rates.py's Wilson intervals), false alarms at either level (count, per ha
with poisson_exact's interval); and, per set, the class answers T removed by their outcome at
T = 0. Standard library only. Writes only under DEST; the runs are read only. Run from the source
tree (relative paths in the runs' provenance, share/params/calibration.ini, share/models/
classes.csv, are read from the working directory).

  bench/collect/accept.py --bin build/bin --dest DIR [--t 0,0.1,0.2,0.3,0.5] NAME=RES_DIR...
      RES_DIR: a score's --csv directory holding its score.json (e.g. RES/density/d25)
  bench/collect/accept.py --bin build/bin --dest DIR --real TILE_DIR...
      TILE_DIR: a real tile's `make tile` directory (detections.json, cands/, score.json when it
      has truth); prints per tile the detections, true positives, false alarms per T
  bench/collect/accept.py --dest DIR --rule NAME[:dense]...
      the seventeenth round's rule on the sets written under DEST (":dense": a set at 25 points/m²
      or more, whose targets count; docs/decisions/open-set.md)
"""
import argparse
import csv
import filecmp
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
from rates import rate, poisson_exact  # noqa: E402

# collect's options that say where its outputs go or that --plan reads: not re-given.
SKIP = {'geojson', 'plan', 'plan-key', 'model-density', 'no-density-scale', 'class-accept'}


def collect_args(det):
    """The collect command line (without -o) that wrote det, from its provenance."""
    prov = json.load(open(det))['provenance']
    args = ['-i', prov['inputs'][0]]
    for k, v in sorted(prov['parameters'].items()):
        if k in SKIP or v == '' and k not in ('class-name', 'calibration'):
            continue
        if k == 'size-only':
            if v not in ('', 'false', '0'):
                args.append('--size-only')
            continue
        args += [f'--{k}', v]
    return args


def score_args(score_json):
    p = json.load(open(score_json))['provenance']['parameters']
    args = []
    for k, v in sorted(p.items()):
        if k in ('csv', 'tiles', 'detections', 'truth') or v == '':
            continue
        args += [f'--{k}', v]
    return args


def fa_text(k, area):
    lo, hi = poisson_exact(k)
    return f'{k} = {k / area:.2f}/ha [{lo / area:.2f}, {hi / area:.2f}]'


def run_set(a, name, res, t):
    score_json = f'{res}/score.json'
    tiles = json.load(open(score_json))['provenance']['parameters']['tiles']
    out = f'{a.dest}/{name}/t{t}'
    os.makedirs(out, exist_ok=True)
    lines = []
    for k, line in enumerate(open(tiles)):
        if not line.strip():
            continue
        det, truth, noise, cover = line.split()
        o = f'{out}/{k:03d}.json'
        subprocess.run([f'{a.bin}/collect', '-q'] + collect_args(det) + ['--class-accept', str(t), '-o', o],
                       check=True, stderr=subprocess.DEVNULL)
        lines.append(f'{o} {truth} {noise} {cover}\n')
    open(f'{out}/tiles.txt', 'w').writelines(lines)
    subprocess.run([f'{a.bin}/score', '-q', '--tiles', f'{out}/tiles.txt', '-o', f'{out}/score.json', '--csv',
                    f'{out}/'] + score_args(score_json), check=True)
    return out


def summary(out):
    rows = {}
    for r in csv.DictReader(open(f'{out}/summary.csv')):
        if r['noise_mm'] != 'all':
            continue
        area = float(r['area_ha'])
        n, found, right = int(r['true']), int(r['found_any_level']), int(r['class_right_any_level'])
        fa = round(float(r['false_alarms_any_level_per_ha']) * area)
        rows[r['cover']] = dict(n=n, found=found, right=right, wrong=found - right, fa=fa, area=area,
                                cls=int(r['class_detections']))
    return rows


def sets_main(a):
    for spec in a.sets:
        name, res = spec.split('=', 1)
        base = None
        for t in a.t:
            out = run_set(a, name, res, t)
            if t == 0:
                same = filecmp.cmp(f'{out}/matches.csv', f'{res}/matches.csv', shallow=False)
                print(f'{name}: T=0 {"reproduces" if same else "DOES NOT reproduce"} {res}/matches.csv')
                base = list(csv.DictReader(open(f'{out}/matches.csv')))
            for cover, s in sorted(summary(out).items()):
                print(f'{name:10s} T={t:<4} {cover:6s} found {rate(s["found"], s["n"])}  class right '
                      f'{rate(s["right"], s["found"])}  wrong {rate(s["wrong"], s["n"])}  FA '
                      f'{fa_text(s["fa"], s["area"])} on {s["area"]:.2f} ha  (class-level detections {s["cls"]})')
            if base is not None and t > 0:
                gone = {}
                for r in base:
                    if r['level'] == 'class' and float(r['confidence']) < t:
                        gone[r['outcome']] = gone.get(r['outcome'], 0) + 1
                print(f'{name:10s} T={t:<4} class answers below T at T=0, by outcome: '
                      + (', '.join(f'{k} {v}' for k, v in sorted(gone.items())) or 'none'))


def real_main(a):
    for tile in a.real:
        name = os.path.basename(os.path.normpath(tile))
        det = f'{tile}/detections.json'
        has_score = os.path.exists(f'{tile}/score.json')
        for t in a.t:
            out = f'{a.dest}/real/{name}/t{t}'
            os.makedirs(out, exist_ok=True)
            subprocess.run([f'{a.bin}/collect', '-q'] + collect_args(det) + ['--class-accept', str(t), '-o',
                           f'{out}/detections.json'], check=True, stderr=subprocess.DEVNULL)
            d = json.load(open(f'{out}/detections.json'))
            line = f'{name:20s} T={t:<4} detections {d["found"]:3d} (low_confidence {d["by_reason"].get("low_confidence", 0)})'
            if has_score:
                sp = json.load(open(f'{tile}/score.json'))['provenance']['parameters']
                subprocess.run([f'{a.bin}/score', '-q', '--detections', f'{out}/detections.json', '--truth',
                                sp['truth'], '-o', f'{out}/score.json'], check=True)
                s = json.load(open(f'{out}/score.json'))['summary']
                s = s[0] if isinstance(s, list) else s
                line += (f'  true {s["true"]} found {s["found_any_level"]} class right {s["class_right_any_level"]} '
                         f'FA {round(s["false_alarms_any_level_per_ha"] * s["area_ha"])} on {s["area_ha"]:.2f} ha')
            print(line)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--bin', default='build/bin')
    ap.add_argument('--dest', required=True)
    ap.add_argument('--t', default='0,0.1,0.2,0.3,0.5')
    ap.add_argument('--real', nargs='*', default=[])
    ap.add_argument('--rule', nargs='*', default=[])
    ap.add_argument('sets', nargs='*')
    a = ap.parse_args()
    a.t = [float(x) if '.' in x else int(x) for x in a.t.split(',')]
    if a.rule:
        rule_main(a)
    elif a.real:
        real_main(a)
    else:
        sets_main(a)


def rule_main(a):
    """The seventeenth round's rule (docs/decisions/open-set.md), stated before the table: over the
    sets already written under DEST (NAME or NAME:dense for a set at 25 points/m² or more)."""
    sets = [s.split(':') for s in a.rule]
    ts = [t for t in a.t if t > 0]
    base = {n: summary(f'{a.dest}/{n}/t0') for n, *_ in sets}
    qualified = []
    for t in ts:
        now = {n: summary(f'{a.dest}/{n}/t{t}') for n, *_ in sets}
        ok, lost_all, bad_all, notes = True, 0, 0, []
        for n, *flag in sets:
            b, c = base[n]['all'], now[n]['all']
            lost = b['right'] - c['right']
            bad = (b['wrong'] + b['fa']) - (c['wrong'] + c['fa'])
            lost_all, bad_all = lost_all + lost, bad_all + bad
            if lost > b['right'] / 100:
                ok = False
                notes.append(f'(a) {n} loses {lost} right of {b["right"]}')
            if not flag:
                continue
            for cover in sorted(base[n]):
                if cover == 'all':
                    continue
                b, c = base[n][cover], now[n][cover]
                checks = [('class right >= 85%', lambda s: s['found'] and s['right'] / s['found'] >= 0.85),
                          ('FA <= 1/ha', lambda s: s['fa'] / s['area'] <= 1)]
                if cover in ('light', 'medium'):
                    need = 0.90 if cover == 'light' else 0.75
                    checks.append((f'recall >= {need:.0%}', lambda s, need=need: s['found'] / s['n'] >= need))
                if n.startswith('openset'):
                    checks += [('wrong <= 5% of vehicles', lambda s: s['wrong'] / s['n'] <= 0.05),
                               ('class right >= 90%', lambda s: s['found'] and s['right'] / s['found'] >= 0.90)]
                for what, f in checks:
                    if f(b) and not f(c):
                        ok = False
                        notes.append(f'(c) {n} {cover}: {what} met at T=0, missed at T={t}')
        if not (bad_all >= 2 and bad_all >= 2 * lost_all):
            ok = False
            notes.append(f'(b) removes {bad_all} bad, {lost_all} right')
        print(f'T={t}: removes {bad_all} bad (wrong class or false alarm) and {lost_all} right answers over '
              f'the sets: {"QUALIFIES" if ok else "does not qualify"}' + ''.join(f'\n    {x}' for x in notes))
        if ok:
            qualified.append(t)
    print(f'adopt: T = {max(qualified)}' if qualified else 'adopt: none (the option stays off)')


if __name__ == '__main__':
    main()
