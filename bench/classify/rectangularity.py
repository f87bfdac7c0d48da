#!/usr/bin/env python3
"""Rectangularity (the top view's convex hull area over its minimum-area rectangle's; class.json
features) per thing a candidate holds, on simulated development tiles made by
bench/classify/outline.sh (docs/decisions/classify.md §17), and what a --min-rectangularity gate
on car-group answers would refuse at each threshold.

  bench/classify/rectangularity.py VARIANT OUT [OUT ...]   (VARIANT: the run with the gate off,
                                                            e.g. "on")
  THRESHOLDS="0.8 0.83 0.85 0.87 0.9" (default); NOTCH=1 (default: the outline alone; 0.08:
  --rectangularity-notch, only answers whose notch is under it are refused)

Per label (outline.py's: a vehicle's when within 2 m of it, a clutter object's when within its
box + 1 m): every measured candidate's rectangularity (min / 10% / median / max), the answered
ones', the car-group answers'; then per threshold the answers refused, 95% Wilson. Reads the
truth only here (classify never does)."""
import collections, json, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from rates import rate  # noqa: E402

variant, outs = sys.argv[1], sys.argv[2:]
KEY = os.environ.get('KEY', 'rectangularity')
thresholds = [float(t) for t in os.environ.get('THRESHOLDS', '0.8 0.83 0.85 0.87 0.9').split()]
notch_max = float(os.environ.get('NOTCH', '1'))
sys.argv = [sys.argv[0], outs[0], variant]  # outline.py reads its own argv when imported


def label_fn():
    src = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'outline.py')).read()
    code = src.split('\nanswered = ')[0]  # its label() only, not its report
    ns = {'__file__': os.path.join(os.path.dirname(os.path.abspath(__file__)), 'outline.py')}
    exec(code, ns)
    return ns['label']


label = label_fn()
rows = []  # (out, tile, id, label, class, group, rectangularity, density, reason)
for out in outs:
    for line in open(os.path.join(out, 'tiles.txt')):
        d = line.split()[0]
        d = os.path.join(out, 'tiles', os.path.basename(d))
        truth = json.load(open(os.path.join(d, 'truth.json')))
        for c in json.load(open(os.path.join(d, 'cands', 'index.json')))['candidates']:
            doc = json.load(open(os.path.join(d, variant, c['id'] + '.json')))
            f = doc.get('features') or {}
            what = label(c, truth)
            if what.startswith('vehicle:'):
                what = 'vehicle:' + os.path.basename(what[8:]).replace('.ply', '')
            rows.append((os.path.basename(out), os.path.basename(d), c['id'], what, doc.get('class'),
                         doc.get('group'), f.get(KEY), doc.get('density') or 0, doc.get('reason'),
                         f.get('notch', 0)))


def q(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))]


def stats(v):
    return '%.3f / %.3f / %.3f / %.3f' % (min(v), q(v, 0.1), q(v, 0.5), max(v)) if v else '-'


print('label | measured n: min / 10% / median / max | answered n: ... | car-group answers n: ...')
for what in sorted({r[3] for r in rows}):
    sel = [r for r in rows if r[3] == what and r[6] is not None and r[6] > 0]
    ans = [r[6] for r in sel if r[4]]
    car = [r[6] for r in sel if r[5] == 'car']
    print(what, '%d: %s' % (len(sel), stats([r[6] for r in sel])), '%d: %s' % (len(ans), stats(ans)),
          '%d: %s' % (len(car), stats(car)), sep=' | ')


def kind(what):
    return 'rock' if what == 'clutter:rock' else what.split(':')[0]


print('\nnotch under %g and rectangularity under the threshold:' % notch_max)
print('threshold | vehicles answered lost | rocks answered refused | other clutter answered refused')
for t in thresholds:
    out = []
    for k in ['vehicle', 'rock', 'clutter']:
        sel = [r for r in rows if r[4] and kind(r[3]) == k]
        gone = [r for r in sel if r[5] == 'car' and r[6] < t and r[9] < notch_max]
        out.append(rate(len(gone), len(sel)))
    print(t, *out, sep=' | ')
print('\ncar-group answers under the largest threshold (out, tile, id, label, class, rectangularity, '
      'density):')
for r in sorted(rows, key=lambda r: r[6] or 0):
    if r[5] == 'car' and r[6] < max(thresholds):
        print(r[0], r[1], r[2], r[3], r[4], '%.3f' % r[6], '%.1f' % r[7], sep=' | ')
print('\nby object density (points/m² of its rectangle), threshold %.2f: vehicles answered lost | rocks '
      'answered refused | car-group vehicle answers min | rocks max' % thresholds[len(thresholds) // 2])
t = thresholds[len(thresholds) // 2]
for lo, hi in [(0, 15), (15, 30), (30, 100), (100, 1e9)]:
    veh = [r for r in rows if r[4] and kind(r[3]) == 'vehicle' and lo <= r[7] < hi]
    rock = [r for r in rows if r[4] and kind(r[3]) == 'rock' and lo <= r[7] < hi]
    cv = [r[6] for r in veh if r[5] == 'car']
    print('%g-%g' % (lo, hi), rate(sum(1 for r in veh if r[5] == 'car' and r[6] < t and r[9] < notch_max), len(veh)),
          rate(sum(1 for r in rock if r[5] == 'car' and r[6] < t and r[9] < notch_max), len(rock)),
          '%.3f' % min(cv) if cv else '-', '%.3f' % max(r[6] for r in rock) if rock else '-', sep=' | ')
