#!/usr/bin/env python3
"""Candidates of real development tiles whose class answer differs between two passes.sh
variants (docs/decisions/classify.md §16), with what the labels say is there (a labelled vehicle
within 1.5 m of the candidate's centre: its visibility; else 'other') and the outline cues.

  bench/classify/outline_real.py OUT LABELS VARIANT_A VARIANT_B TILE [TILE ...]
Development tiles only (docs/decisions/real-tiles.md: the split)."""
import json, math, os, sys

out, labels, va, vb = sys.argv[1:5]
for tile in sys.argv[5:]:
    truth = os.path.join(labels, tile + '.truth.json')
    vehicles = json.load(open(truth))['vehicles'] if os.path.exists(truth) else []
    index = json.load(open(os.path.join(out, 'cands', tile, 'index.json')))
    for c in index['candidates']:
        a = json.load(open(os.path.join(out, va, tile, 'cands', c['id'], 'class.json')))
        b = json.load(open(os.path.join(out, vb, tile, 'cands', c['id'], 'class.json')))
        if a.get('class') == b.get('class'):
            continue
        near = min(((math.hypot(c['centre'][0] - v['pose']['x'], c['centre'][1] - v['pose']['y']),
                     v.get('visibility')) for v in vehicles), default=(99, None))
        what = 'vehicle/' + str(near[1]) if near[0] <= 1.5 else 'other'
        f = a['features']
        print(tile, c['id'], what, '%s -> %s' % (b.get('class'), a.get('class')),
              'notch %.3f dents %d tip %.2f/%.2f size %s' % (f['notch'], f['dents'], f['tip_width'], f['tip_level'],
                                                            a['measured'].get('size') if a.get('measured') else ''),
              (a.get('detail') or '')[:80], sep=' | ')
