#!/usr/bin/env python3
"""detect's shape test, measured: the planarity and planar area of every candidate of detect
runs with the test off (`--min-planarity 0`), by what the candidate's object is: a labelled
vehicle (index.json truth), else the majority label of its crop's points above 0.3 m
(2 vegetation, 4 clutter). Prints percentiles per class, the lowest "best candidate" of each
vehicle, and recall / candidates per vehicle for a grid of thresholds.
  bench/detect/shape.py WORK TAG     (the directories of bench/detect/tiles.sh, TAG of the off run)
"""
import glob, json, os, struct, sys

def crop_labels(path):
    b = open(path, 'rb').read(); hdr = {}; pos = 0
    while True:
        e = b.index(b'\n', pos); line = b[pos:e].decode(errors='replace'); pos = e + 1
        if line.startswith('#'): continue
        k, *v = line.split(); hdr[k] = v
        if k == 'DATA': break
    if hdr['DATA'][0] != 'binary': raise SystemExit(path + ': not a binary PCD')
    codes = {('F', 4): 'f', ('F', 8): 'd', ('I', 4): 'i', ('U', 4): 'I', ('U', 1): 'B', ('I', 2): 'h', ('U', 2): 'H', ('I', 1): 'b'}
    fmt = '<' + ''.join(codes[(t, int(s))] for s, t in zip(hdr['SIZE'], hdr['TYPE']))
    n = int(hdr['POINTS'][0]); rec = struct.calcsize(fmt)
    zi, li = hdr['FIELDS'].index('z'), hdr['FIELDS'].index('label')
    counts = {}
    for r in struct.iter_unpack(fmt, b[pos:pos + n * rec]):
        if r[zi] > 0.3: counts[r[li]] = counts.get(r[li], 0) + 1
    return max(counts, key=counts.get) if counts else 0

def pct(v, q):
    v = sorted(v); return v[min(len(v) - 1, int(q / 100 * (len(v) - 1) + 0.5))] if v else float('nan')

work, tag = sys.argv[1], sys.argv[2]
rows, tiles = [], []
for idxp in sorted(glob.glob(f'{work}/*/cands-{tag}-*/index.json')):
    d = os.path.dirname(idxp); idx = json.load(open(idxp))
    truth = json.load(open(os.path.join(os.path.dirname(d), 'truth.json')))
    tiles.append((idxp, [v['instance'] for v in truth['vehicles']]))
    for c in idx['candidates']:
        inst = (c.get('truth') or {}).get('instance', 0)
        cls = 'vehicle' if inst else {2: 'vegetation', 4: 'clutter', 3: 'ground'}.get(crop_labels(os.path.join(d, c['file'])), 'other')
        rows.append(dict(idx=idxp, cls=cls, inst=inst, share=c['planarity'], area=c['planar_area'], L=c['length']))
print(f'{len(tiles)} runs, {len(rows)} candidates')
print('| class | candidates | planarity min / 5% / 50% / 95% / max | planar area (m^2) min / 5% / 50% / 95% / max |')
print('|---|---|---|---|')
for cls in ('vehicle', 'vegetation', 'clutter', 'ground', 'other'):
    R = [r for r in rows if r['cls'] == cls]
    if not R: continue
    s = ' / '.join('%.2f' % pct([r['share'] for r in R], q) for q in (0, 5, 50, 95, 100))
    a = ' / '.join('%.2f' % pct([r['area'] for r in R], q) for q in (0, 5, 50, 95, 100))
    print(f'| {cls} | {len(R)} | {s} | {a} |')
best = []
for idxp, vehicles in tiles:
    for v in vehicles:
        rs = [r for r in rows if r['idx'] == idxp and r['inst'] == v]
        if rs: best.append(max(rs, key=lambda r: (r['share'], r['area'])))
print('each recalled vehicle, its candidate of highest planarity: lowest planarity %.2f (its area %.2f m^2), '
      'lowest area %.2f m^2' % (min(r['share'] for r in best), min(best, key=lambda r: r['share'])['area'],
                               min(r['area'] for r in best)))
nveh = sum(len(v) for _, v in tiles)
print('| min planarity | min planar area | recall | candidates / vehicle | vegetation / vehicle |')
print('|---|---|---|---|---|')
for t in (0, 0.1, 0.15, 0.2, 0.25, 0.3):
    for A in (0.5, 1.0, 2.0, float('inf')):
        if t == 0 and A != float('inf'): continue
        keep = [r for r in rows if t == 0 or r['share'] >= t or r['area'] >= A]
        got = {(r['idx'], r['inst']) for r in keep if r['inst']}
        rec = sum(1 for idxp, vs in tiles for v in vs if (idxp, v) in got)
        veg = sum(1 for r in keep if r['cls'] == 'vegetation')
        print(f'| {t} | {A} | {rec}/{nveh} | {len(keep) / nveh:.2f} | {veg / nveh:.2f} |')
