#!/usr/bin/env python3
"""Counts classify's answers per variant on simulated development tiles by what each candidate
holds (docs/decisions/classify.md §16; bench/classify/outline.sh makes OUT).

  bench/classify/outline.py OUT VARIANT [VARIANT ...]     (the first variant is the baseline
                                                           the others are compared with: "on")

A candidate is a vehicle's when its centre (index.json) is within 2 m of the vehicle's position
(truth.json), else a clutter object's when within its box grown by 1 m, else 'other'
(vegetation, ground, fragments). Prints per label: candidates, answered as a vehicle per
variant, and every candidate whose answer differs between the first two variants. Reads the
truth only here (classify never does)."""
import collections, json, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from rates import wilson  # noqa: E402

out, variants = sys.argv[1], sys.argv[2:]


def label(c, truth):
    x, y = c['centre'][0], c['centre'][1]
    best = (2.0, None)
    for v in truth['vehicles']:
        d = math.hypot(x - v['pose']['x'], y - v['pose']['y'])
        if d < best[0]:
            best = (d, 'vehicle:' + v['model'])
    if best[1]:
        return best[1]
    for k in truth.get('clutter', []):
        b = k['box']
        h = b['heading']
        dx, dy = x - b['centre'][0], y - b['centre'][1]
        u = dx * math.cos(h) + dy * math.sin(h)
        w = -dx * math.sin(h) + dy * math.cos(h)
        if abs(u) <= b['size'][0] / 2 + 1 and abs(w) <= b['size'][1] / 2 + 1:
            return 'clutter:' + k['kind']
    return 'other'


answered = collections.defaultdict(collections.Counter)  # label -> variant -> answered
total = collections.Counter()
changes = []
for line in open(os.path.join(out, 'tiles.txt')):
    d = line.split()[0]
    truth = json.load(open(os.path.join(d, 'truth.json')))
    for c in json.load(open(os.path.join(d, 'cands', 'index.json')))['candidates']:
        what = label(c, truth)
        total[what] += 1
        docs = {}
        for v in variants:
            p = os.path.join(d, v, c['id'] + '.json')
            docs[v] = json.load(open(p))
            answered[what][v] += docs[v].get('class') is not None
        if len(variants) >= 2:
            a, b = docs[variants[0]], docs[variants[1]]
            if a.get('class') != b.get('class'):
                f = a['features']
                changes.append((what, os.path.basename(d), c['id'], b.get('class'), a.get('class'), a.get('reason'),
                                f.get('notch'), f.get('tip_width'), f.get('tip_level'), (a.get('detail') or '')[:90]))


def kind_of(what):
    return what.split(':')[0]


print('label | candidates | ' + ' | '.join('answered as vehicle, ' + v for v in variants))
for what in sorted(total):
    print(what, total[what], *[answered[what][v] for v in variants], sep=' | ')
for group in ['vehicle', 'clutter', 'other']:
    n = sum(total[w] for w in total if kind_of(w) == group)
    print('all ' + group, n, *[sum(answered[w][v] for w in total if kind_of(w) == group) for v in variants], sep=' | ')
if len(variants) >= 2:
    print('\nchanged (label, tile, candidate, %s -> %s, reason, notch, tip_width, tip_level, detail):'
          % (variants[1], variants[0]))
    for c in sorted(changes):
        print(*c, sep=' | ')
    a, b = variants[0], variants[1]
    print('\nrefused by the change (%s answered, %s not), of those %s answered, 95%% Wilson:' % (b, a, b))
    for what in sorted(total):
        base = answered[what][b]
        if not base:
            continue
        gone = sum(1 for c in changes if c[0] == what and c[3] is not None and c[4] is None)
        lo, hi = wilson(gone, base)
        print('%s: %d/%d [%.1f, %.1f]%%' % (what, gone, base, 100 * lo, 100 * hi))
