#!/usr/bin/env python3
"""Issue 28: the share of a covered vehicle's pulses that return from it (bench/sensor/fopen/).

  fopen.py [--md OUT.md] TILE.las,TILE.truth.json ...

Per vehicle of rangetrace's truth.json (canopy_cover = share of its footprint hidden from
nadir): the pulses over it = the pulses (point source id, GPS time) whose last return lies
inside its footprint rectangle (near nadir, so the pulse's axis meets the ground there); of
those, the pulses with at least one return from the vehicle (`instance`) and with the vehicle
as first return. Rates pooled by cover bin with Wilson 95 % intervals.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'realsim'))
from lasstats import inside, read_las, rect  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..'))
from rates import wilson  # noqa: E402  (bench/rates.py)


def vehicles_of(las_path, truth_path):
    t = json.load(open(truth_path))
    c = read_las(las_path)
    o = t.get('origin') or [0, 0]
    last, veh, first_veh = {}, {}, {}
    for i in range(c['n']):
        key = (c['psid'][i], c['gps'][i])
        if c['rn'][i] == c['nr'][i]:
            last[key] = (c['x'][i], c['y'][i])
        inst = c['instance'][i]
        if inst:
            veh.setdefault(key, set()).add(inst)
            if c['rn'][i] == 1:
                first_veh[key] = inst
    rows = []
    for v in t['vehicles']:
        p = v['pose']
        L, W = v['size'][:2]
        poly = rect(p['x'] + o[0], p['y'] + o[1], p['heading'], L, W)
        xs = [a for a, _ in poly]
        ys = [b for _, b in poly]
        over = [k for k, (x, y) in last.items()
                if min(xs) <= x <= max(xs) and min(ys) <= y <= max(ys) and inside(poly, x, y)]
        n = len(over)
        hit = sum(1 for k in over if v['instance'] in veh.get(k, ()))
        first = sum(1 for k in over if first_veh.get(k) == v['instance'])
        rows.append({'tile': os.path.basename(las_path), 'instance': v['instance'], 'model': v['model'],
                     'cover': v['canopy_cover'], 'pulses': n, 'hit': hit, 'first': first})
    return rows


def main(argv):
    md = None
    if len(argv) > 2 and argv[1] == '--md':
        md, argv = argv[2], argv[:1] + argv[3:]
    if len(argv) < 2:
        raise SystemExit(__doc__)
    rows = []
    for a in argv[1:]:
        las, truth = a.split(',')
        rows.extend(vehicles_of(las, truth))
    out = ['| tile | vehicle | model | nadir cover | pulses over it | with a vehicle return | as first return |',
           '|---|---|---|---|---|---|---|']
    for r in sorted(rows, key=lambda r: r['cover']):
        out.append(f"| {r['tile']} | {r['instance']} | {r['model']} | {r['cover']:.2f} | {r['pulses']} | "
                   f"{r['hit']} ({r['hit'] / max(1, r['pulses']):.2f}) | {r['first']} ({r['first'] / max(1, r['pulses']):.2f}) |")
    out += ['', '| nadir cover | vehicles | pulses | share with a vehicle return [95 % CI] | as first return [95 % CI] | 1 − cover (mean) |',
            '|---|---|---|---|---|---|']
    for lo, hi in ((0, 0.15), (0.15, 0.6), (0.6, 0.8), (0.8, 1.01)):
        b = [r for r in rows if lo <= r['cover'] < hi]
        n = sum(r['pulses'] for r in b)
        k = sum(r['hit'] for r in b)
        f = sum(r['first'] for r in b)
        if not b:
            out.append(f'| {lo:.2f} – {min(hi, 1):.2f} | 0 | – | – | – | – |')
            continue
        a, z = wilson(k, n)
        fa, fz = wilson(f, n)
        gap = sum(1 - r['cover'] for r in b) / len(b)
        out.append(f'| {lo:.2f} – {min(hi, 1):.2f} | {len(b)} | {n} | {k / n:.3f} [{a:.3f}, {z:.3f}] | '
                   f'{f / n:.3f} [{fa:.3f}, {fz:.3f}] | {gap:.2f} |')
    text = '\n'.join(out) + '\n'
    if md:
        with open(md, 'w') as fh:
            fh.write(text)
    sys.stdout.write(text)


if __name__ == '__main__':
    main(sys.argv)
