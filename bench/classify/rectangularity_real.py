#!/usr/bin/env python3
"""Rectangularity on real development tiles (docs/decisions/classify.md §17): per passes.sh
variant run with the gate off, every answered candidate's rectangularity by what the labels say
is there (a labelled vehicle within 1.5 m of the candidate's centre: its visibility; else
'other', a false alarm), and what --min-rectangularity on car-group answers would refuse.

  bench/classify/rectangularity_real.py OUT LABELS VARIANT TILE [TILE ...]
  THRESHOLDS="0.8 0.82 0.85" (default)
Development tiles only (docs/decisions/real-tiles.md: the split)."""
import json, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from rates import rate  # noqa: E402

out, labels, variant, tiles = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
thresholds = [float(t) for t in os.environ.get('THRESHOLDS', '0.8 0.82 0.85').split()]
notch_max = float(os.environ.get('NOTCH', '1'))  # 0.08: --rectangularity-notch
rows = []  # (tile, id, what, class, group, rectangularity, density)
for tile in tiles:
    truth = os.path.join(labels, tile + '.truth.json')
    vehicles = json.load(open(truth))['vehicles'] if os.path.exists(truth) else []
    for c in json.load(open(os.path.join(out, 'cands', tile, 'index.json')))['candidates']:
        a = json.load(open(os.path.join(out, variant, tile, 'cands', c['id'], 'class.json')))
        if not a.get('class'):
            continue
        near = min(((math.hypot(c['centre'][0] - v['pose']['x'], c['centre'][1] - v['pose']['y']),
                     v.get('visibility')) for v in vehicles), default=(99, None))
        what = 'vehicle/' + str(near[1]) if near[0] <= 1.5 else 'other/' + tile
        f = a['features']
        rows.append((tile, c['id'], what, a['class'], a['group'], f[os.environ.get('KEY', 'rectangularity')], a['density'],
                     f['notch']))


def q(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))]


print('answered as | n | rectangularity min / 10% / median / max | car-group answers n: min')
for what in sorted({r[2] for r in rows}):
    v = [r[5] for r in rows if r[2] == what]
    car = [r[5] for r in rows if r[2] == what and r[4] == 'car']
    print(what, len(v), '%.3f / %.3f / %.3f / %.3f' % (min(v), q(v, 0.1), q(v, 0.5), max(v)),
          '%d: %s' % (len(car), '%.3f' % min(car) if car else '-'), sep=' | ')
print('\nthreshold | ' + ' | '.join('%s answered refused' % w for w in sorted({r[2] for r in rows})))
for t in thresholds:
    print(t, *[rate(sum(1 for r in rows if r[2] == w and r[4] == 'car' and r[5] < t and r[7] < notch_max), sum(1 for r in rows if r[2] == w))
               for w in sorted({r[2] for r in rows})], sep=' | ')
print('\ncar-group answers under the largest threshold (tile, id, what, class, rectangularity, density, notch):')
for r in sorted(rows, key=lambda r: r[5]):
    if r[4] == 'car' and r[5] < max(thresholds):
        print(r[0], r[1], r[2], r[3], '%.3f' % r[5], '%.1f' % r[6], '%.3f' % r[7], sep=' | ')
