#!/usr/bin/env python3
"""own_entry.py RUNS MODELBASE DEST : how far a vehicle's top profile lies from its OWN modelbase
entry's (docs/decisions/classify.md §18, the tolerance of --entry-profile). RUNS is
bench/openset/loo.sh's runs.txt (each open-set modelbase instance rendered alone at 40 and 422 mm);
each run's candidate is classified with classify-sim.ini + `modelbase-classes-only = 1` and the
FULL modelbase (its own entry included), and each entry's surface as a candidate (as classify's
read_modelbase measures it). Prints per run the differences of plateau share, lower and higher end
level and notch (candidate - entry), the answer, and the largest absolute difference per spacing.
Writes only under DEST. (BIN=build/bin.)"""
import json
import os
import subprocess
import sys

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
KEYS = ('plateau_share', 'end_low', 'end_high', 'notch')


def main():
    runs, mb, dest = sys.argv[1:4]
    bin_ = os.environ.get('BIN', f'{SRC}/build/bin')
    os.makedirs(dest, exist_ok=True)
    ini = f'{dest}/classify.ini'
    with open(ini, 'w') as f:
        f.write(open(f'{SRC}/share/params/classify-sim.ini').read() + 'modelbase-classes-only = 1\n')

    def classify(points, out, extra):
        subprocess.run([f'{bin_}/classify', '-q', '--config', ini, '-i', points, '-o', out] + extra, check=True)
        return json.load(open(out))

    entry = {}
    for f in sorted(os.listdir(mb)):
        if f.endswith('.pcd'):
            entry[f[:-4].split('__', 1)[1]] = classify(f'{mb}/{f}', f'{dest}/entry-{f[:-4]}.json', [])['features']
    worst = {}
    for line in open(runs):
        name, _cls, d, _lmb = line.split()
        spacing = d.rsplit('-', 1)[1]
        for c in json.load(open(f'{d}/cands/index.json'))['candidates']:
            out = f'{dest}/{name}-{os.path.basename(d)}-{c["id"]}.json'
            v = classify(f'{d}/cands/{c["file"]}', out, ['--index', f'{d}/cands/index.json', '--modelbase', mb,
                                                          '--model-classes', f'{SRC}/share/models/classes.csv'])
            f = v['features']
            if f['object_points'] < 20:
                continue
            diff = {k: f[k] - entry[name][k] for k in KEYS}
            for k in KEYS[:3]:
                worst[(spacing, k)] = max(worst.get((spacing, k), (0, '')), (abs(diff[k]), name))
            print(f'{name:20s} {spacing:6s} {c["id"]} ' + ' '.join(f'd{k}={diff[k]:+.2f}' for k in KEYS) +
                  f' -> {v["class"] or v["reason"]}')
    for (spacing, k), (value, name) in sorted(worst.items()):
        print(f'largest |difference| {spacing:6s} {k:14s} {value:.2f} ({name})')


if __name__ == '__main__':
    main()
