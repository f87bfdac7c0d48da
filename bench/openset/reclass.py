#!/usr/bin/env python3
"""classify again, with each variant's options, every candidate of finished tile runs (the open
set's tiles and crops, the density ladder's levels: each a `tiles.txt` of score's manifest),
collect with the runs' own model-level verdicts (verify, unchanged), score, and print per variant
and set the found vehicles at either level, the class right of the found and the wrong classes of
all vehicles (bench/rates.py's Wilson intervals), then every wrong class answer with its cues
(docs/decisions/classify.md §18; ALL=1: every answer on a vehicle). Development seeds only.

  bench/openset/reclass.py --dest DIR --modelbase MB --score-classes CSV [--classes-only] \\
      --set NAME=TILES_TXT [--set ...] VARIANT...
  VARIANT = name=opt,opt (`name=` alone: the parameters as they are; an option written
            collect:--opt=value goes to collect instead of classify)

The open set: `--modelbase OUT/openset/modelbase --score-classes OUT/openset/classes.csv
--classes-only --set tiles=OUT/openset/tiles/tiles.txt --set crops=OUT/openset/crops/tiles.txt`
(mk/openset.mk's classify.ini: classify-sim.ini + `modelbase-classes-only = 1` + `class-envelope =
0.05`, OPENSET_CLASS_ENVELOPE's default, + `family-entries = 2`, OPENSET_FAMILY_ENTRIES's; a
variant `off=--class-envelope=0` is the open set before the eighth round of
docs/decisions/open-set.md, `one=--family-entries=1` before the eleventh); the ladder:
`--modelbase OUT/modelbase --score-classes share/models/classes.csv --set
d25=OUT/density/d25/tiles.txt` (classify-sim.ini). classify's parameters: SRC/share/params/
classify-sim.ini (+ the open set's line), then the variant's options. Writes only under DEST
(DEST/<variant>/<set>/...); the runs' directories are read only (their verdicts are linked)."""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import rate  # noqa: E402

CUES = ('plateau_share', 'end_low', 'end_high', 'notch', 'rectangularity', 'fill', 'below_share', 'ground_through')
SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run_set(a, ini, opts, dest, manifest_path, collect_opts=()):
    """classify, collect, score one set into dest; returns (summary row, matches rows, run dirs)."""
    base = os.path.dirname(manifest_path)
    manifest = []
    for line in open(manifest_path):
        if not line.strip():
            continue
        det, truth, noise, cover = line.split()
        run = os.path.dirname(det)
        cands = f'{run}/cands'
        mirror = f'{dest}/{os.path.relpath(run, base)}'
        os.makedirs(mirror, exist_ok=True)
        for c in json.load(open(f'{cands}/index.json'))['candidates']:
            d = f'{mirror}/{c["id"]}'
            os.makedirs(d, exist_ok=True)
            verdict = os.path.abspath(f'{cands}/{c["id"]}/verdict.json')
            if os.path.exists(verdict) and not os.path.lexists(f'{d}/verdict.json'):
                os.symlink(verdict, f'{d}/verdict.json')
            subprocess.run([f'{a.bin}/classify', '-q', '--config', ini, '-i', f'{cands}/{c["file"]}', '--index',
                            f'{cands}/index.json', '--modelbase', a.modelbase, '--model-classes', a.model_classes,
                            '-o', f'{d}/class.json'] + opts, check=True)
        subprocess.run([f'{a.bin}/collect', '-q', '-i', f'{cands}/index.json', '--verdicts', mirror, '--modelbase',
                        a.modelbase, '-o', f'{mirror}/detections.json'] + list(collect_opts), check=True,
                       stderr=subprocess.DEVNULL)
        manifest.append(f'{mirror}/detections.json {truth} {noise} {cover}\n')
    with open(f'{dest}/tiles.txt', 'w') as f:
        f.writelines(manifest)
    subprocess.run([f'{a.bin}/score', '-q', '--tiles', f'{dest}/tiles.txt', '--model-classes', a.score_classes,
                    '-o', f'{dest}/score.json', '--csv', f'{dest}/'], check=True)
    summary = {r['cover']: r for r in csv.DictReader(open(f'{dest}/summary.csv')) if r['noise_mm'] == 'all'}
    rows = list(csv.DictReader(open(f'{dest}/matches.csv')))
    return summary, rows, [os.path.dirname(m.split()[0]) for m in manifest]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--bin', default=f'{SRC}/build/bin')
    ap.add_argument('--dest', required=True)
    ap.add_argument('--modelbase', required=True)
    ap.add_argument('--model-classes', default=f'{SRC}/share/models/classes.csv')
    ap.add_argument('--score-classes', required=True)
    ap.add_argument('--classes-only', action='store_true')
    ap.add_argument('--set', action='append', required=True)
    ap.add_argument('variants', nargs='+')
    a = ap.parse_args()
    os.makedirs(a.dest, exist_ok=True)
    ini = f'{a.dest}/classify.ini'
    with open(ini, 'w') as f:
        f.write(open(f'{SRC}/share/params/classify-sim.ini').read())
        if a.classes_only:
            f.write('# The open set (mk/openset.mk): only the modelbase\'s classes (OPENSET_CLASSES_ONLY).\n'
                    'modelbase-classes-only = 1\n'
                    '# and the class envelopes (OPENSET_CLASS_ENVELOPE).\n'
                    'class-envelope = 0.05\n'
                    '# A family is a class only when two entries name it (OPENSET_FAMILY_ENTRIES).\n'
                    'family-entries = 2\n')
    truth_class = {r['model']: r['class'] for r in csv.DictReader(open(a.score_classes))}
    for variant in a.variants:
        name, args = variant.split('=', 1)
        opts = [o for o in args.split(',') if o and not o.startswith('collect:')]
        collect_opts = [o[len('collect:'):] for o in args.split(',') if o.startswith('collect:')]
        for s in a.set:
            which, manifest = s.split('=', 1)
            summary, rows, runs = run_set(a, ini, opts, f'{a.dest}/{name}/{which}', manifest, collect_opts)
            for cover, row in sorted(summary.items()):
                n, found = int(row['true']), int(row['found_any_level'])
                right = int(row['class_right_any_level'])
                print(f'{name:8s} {which:6s} {cover:6s} found {rate(found, n)}  class right {rate(right, found)}  '
                      f'wrong {rate(found - right, n)}  FA/ha {float(row["false_alarms_any_level_per_ha"]):.1f}')
            for r in rows:
                if not r['true_model'] or not r['level']:
                    continue
                # a procedural family instance (<class>-<n>) is of its family's class
                want = truth_class.get(r['true_model'], re.sub(r'-[0-9]+$', '', r['true_model']))
                got, group, cues = r['class'], '', ''
                if r['level'] == 'class':
                    v = json.load(open(f'{runs[int(r["tile"])]}/{r["candidate"]}/class.json'))
                    group = v.get('group') or ''
                    ft = v['features']
                    cues = ' '.join(f'{k[:6]}={ft[k]:.2f}' for k in CUES if ft.get(k) is not None)
                    cues = (f'{v["size"][0]:.2f}x{v["size"][1]:.2f}x{v["size"][2]:.2f} dens={v["density"]:.0f} '
                            f'margin={v["class_margin"]:.2f} {cues} {v.get("detail") or ""}')
                right = want in (got, group) or r['true_model'] in (got, group)
                if right and not os.environ.get('ALL'):
                    continue
                print(f'  {"right" if right else "WRONG"} {which} {os.path.relpath(runs[int(r["tile"])], a.dest)}/'
                      f'{r["candidate"]} {r["true_model"]} ({want}) -> {r["level"]} {got} {group} {cues}')


if __name__ == '__main__':
    main()
