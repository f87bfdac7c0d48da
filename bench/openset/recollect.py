#!/usr/bin/env python3
"""collect and score again, with each variant's collect options and no stage re-run, finished tile
runs (score's tiles.txt manifests): the class.json of reclass.py's mirror DEST/BASE/<set>/ (BASE
"-": the runs' own cands/) and the runs' verify verdicts; prints per variant, set and cover the
found vehicles at either level, class right, wrong class (bench/rates.py's Wilson intervals) and
the false alarms at the model level and at either level. reclass.py's loop without its classify
(docs/decisions/open-set.md "Seventh round"). Writes only under DEST/<variant>/<set>/.

  bench/openset/recollect.py BIN DEST BASE SCORE_CLASSES MODELBASE SET=TILES_TXT... -- NAME=opt,opt ...
  e.g. ... build/bin D base OUT/openset/classes.csv OUT/openset/modelbase tiles=OUT/openset/tiles/tiles.txt \
         -- off=--refused-below=0 rule="""
import csv, os, subprocess, sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
from rates import rate

bin_, dest, base, classes, mb = sys.argv[1:6]
rest = sys.argv[6:]
k = rest.index('--')
sets, variants = rest[:k], rest[k + 1:]
for v in variants:
    name, opts = v.split('=', 1)
    opts = [o for o in opts.split(',') if o]
    for s in sets:
        which, manifest = s.split('=', 1)
        mbase = os.path.dirname(manifest)
        out = f'{dest}/{name}/{which}'
        os.makedirs(out, exist_ok=True)
        lines = []
        for line in open(manifest):
            det, truth, noise, cover = line.split()
            run = os.path.dirname(det)
            mirror = f'{run}/cands' if base == '-' else f'{dest}/{base}/{which}/{os.path.relpath(run, mbase)}'
            o = f'{out}/{os.path.relpath(run, mbase).replace("/", "_")}.json'
            subprocess.run([f'{bin_}/collect', '-q', '-i', f'{run}/cands/index.json', '--verdicts', mirror,
                            '--modelbase', mb, '-o', o] + opts, check=True, stderr=subprocess.DEVNULL)
            lines.append(f'{o} {truth} {noise} {cover}\n')
        open(f'{out}/tiles.txt', 'w').writelines(lines)
        subprocess.run([f'{bin_}/score', '-q', '--tiles', f'{out}/tiles.txt', '--model-classes', classes, '-o',
                        f'{out}/score.json', '--csv', f'{out}/'], check=True)
        for r in csv.DictReader(open(f'{out}/summary.csv')):
            if r['noise_mm'] != 'all':
                continue
            n, found, right = int(r['true']), int(r['found_any_level']), int(r['class_right_any_level'])
            fa_model = int(r['fp'])
            fa_any = round(float(r['false_alarms_any_level_per_ha']) * float(r['area_ha']))
            print(f'{name:10s} {which:6s} {r["cover"]:6s} found {rate(found, n)}  class right {rate(right, found)}  '
                  f'wrong {rate(found - right, n)}  FA model {fa_model} any {fa_any} on {float(r["area_ha"]):.2f} ha '
                  f'= {float(r["false_alarms_any_level_per_ha"]):.2f}/ha')
