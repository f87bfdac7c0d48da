#!/usr/bin/env python3
"""Re-runs classify on the candidates of finished tiles and prints every answer that changes.

Development only (docs/decisions/classify.md §13): compares the class.json a run left with a
new classify's answer on the same candidate, and names the nearest true vehicle (within 2 m of
the candidate's centre; 'other' otherwise) when the tile has a truth.json.

  bench/classify/reclass.py BIN/classify INI MODELBASE CLASSES_CSV 'out/density/d*/*/tile-10[0-9]'

A tile directory holds truth.json and noise-0/cands/ (the scene experiment's layout) or cands/
(make tile's)."""
import collections, glob, json, math, os, subprocess, sys, tempfile

binary, ini, modelbase, classes = sys.argv[1:5]
stats = collections.Counter()
out = os.path.join(tempfile.mkdtemp(), 'class.json')
for pattern in sys.argv[5:]:
    for tile in sorted(glob.glob(pattern)):
        cands = os.path.join(tile, 'noise-0', 'cands')
        if not os.path.isdir(cands):
            cands = os.path.join(tile, 'cands')
        index = os.path.join(cands, 'index.json')
        if not os.path.exists(index):
            continue
        truth = os.path.join(tile, 'truth.json')
        vehicles = json.load(open(truth))['vehicles'] if os.path.exists(truth) else []
        for c in json.load(open(index))['candidates']:
            old_path = os.path.join(cands, c['id'], 'class.json')
            if not os.path.exists(old_path):
                continue
            old = json.load(open(old_path))
            subprocess.run([binary, '--config', ini, '-i', os.path.join(cands, c['file']), '--index', index,
                            '--modelbase', modelbase, '--model-classes', classes, '-o', out],
                           check=True, stderr=subprocess.DEVNULL)
            new = json.load(open(out))
            near = min(((math.hypot(c['centre'][0] - v['pose']['x'], c['centre'][1] - v['pose']['y']), v['model'])
                        for v in vehicles), default=(99, 'other'))
            what = near[1] if near[0] < 2.0 else 'other'
            stats[(what, old.get('class') is not None, new.get('class') is not None)] += 1
            if old.get('class') != new.get('class'):
                print(tile, c['id'], what, old.get('class'), old.get('reason'), '->', new.get('class'),
                      new.get('reason'), (new.get('detail') or '')[:100])
print('(what, class before, class after): candidates')
for k, v in sorted(stats.items()):
    print(k, v)
