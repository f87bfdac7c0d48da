#!/usr/bin/env python3
"""Per candidate of finished tile runs (score's tiles.txt manifest), one tab-separated row: what
stands there in the truth (V:<model> when the candidate's centre lies in a vehicle's footprint
+ 0.5 m, C:<kind> in a clutter object's box, else nothing), the final answer (detections.json),
verify's verdict (model, confidence, class and class score, explained, free-space violation,
the best hypothesis's score, the plain box's, the lead, roll and pitch) and classify's
class.json (class, reason/refused_on, confidence, measured L x W x H, its largest relative
difference from the answered model's size in the catalogue, rectangularity, plateau share,
detail). docs/decisions/open-set.md "Seventh round". Development runs only.

  bench/openset/cases.py TILES_TXT share/vehicles/catalogue.csv [DETECTIONS_NAME] > cases.tsv
  MIRROR=DEST/<variant>/<set> ...   class.json from reclass.py's mirror of the runs instead"""
import csv, json, math, os, sys

man, cat = sys.argv[1], sys.argv[2]
detname = sys.argv[3] if len(sys.argv) > 3 else None
size = {}
for r in csv.DictReader(open(cat)):
    size[r['name']] = (float(r['length_m']), float(r['width_m']), float(r['height_m']))
    size[r['class'] + '__' + r['name']] = size[r['name']]
cls_of = {r['name']: r['class'] for r in csv.DictReader(open(cat))}


def inside(pt, centre, heading, L, W, margin=0.5):
    dx, dy = pt[0] - centre[0], pt[1] - centre[1]
    h = math.radians(heading)
    u = dx * math.cos(h) + dy * math.sin(h)
    v = -dx * math.sin(h) + dy * math.cos(h)
    return abs(u) <= L / 2 + margin and abs(v) <= W / 2 + margin


w = csv.writer(sys.stdout, delimiter='\t')
w.writerow(['tile', 'cand', 'truth', 'answer', 'level', 'ans_conf', 'v_model', 'v_conf', 'v_class', 'v_cscore',
            'v_expl', 'v_fsv', 'v_score', 'box', 'lead', 'roll', 'pitch', 'k_class', 'k_reason', 'k_conf', 'meas',
            'msize_diff', 'rect', 'plateau', 'detail'])
for line in open(man):
    det, truthp, noise, cover = line.split()
    run = os.path.dirname(det)
    if detname:
        det = os.path.join(run, detname)
    t = json.load(open(truthp))
    tile = os.path.relpath(run, os.path.dirname(man))
    d = json.load(open(det))
    ans = {x['candidate']: x for x in d['detections']}
    idx = json.load(open(f'{run}/cands/index.json'))
    for c in idx['candidates']:
        cid = c['id']
        pos = c['centre'][:2]
        truth = 'nothing'
        if pos:
            for v in t['vehicles']:
                p = v['pose']
                if inside(pos, (p['x'], p['y']), p['heading'], v['size'][0], v['size'][1]):
                    truth = 'V:' + v['model']
            if truth == 'nothing':
                for k in t.get('clutter', []):
                    b = k['box']
                    if inside(pos, b['centre'], b['heading'], b['size'][0], b['size'][1]):
                        truth = 'C:' + k['kind']
        vp = f'{run}/cands/{cid}/verdict.json'
        kp = f'{run}/cands/{cid}/class.json'
        if os.environ.get('MIRROR'):
            kp = f"{os.environ['MIRROR']}/{tile}/{cid}/class.json"
        V = json.load(open(vp)) if os.path.exists(vp) and os.path.getsize(vp) else None
        K = json.load(open(kp)) if os.path.exists(kp) and os.path.getsize(kp) else None
        a = ans.get(cid)
        row = [tile, cid, truth, (a.get('model') or a.get('class')) if a else '-', a['level'] if a else '',
               f"{a['confidence']:.3f}" if a else '']
        if V:
            box = (V.get('box') or {}).get('score')
            hy = V.get('hypotheses') or []
            best = max((h['score'] for h in hy), default=None)
            pose = V.get('pose') or (hy[0]['pose'] if hy else None)
            row += [V.get('model') or 'none', f"{V['confidence']:.3f}", V.get('class') or '',
                    f"{V.get('class_score', 0):.2f}", f"{V['explained']:.2f}" if V.get('explained') is not None else '',
                    f"{V['free_space_violation']:.2f}" if V.get('free_space_violation') is not None else '',
                    f"{best:.3f}" if best is not None else '', f"{box:.3f}" if box is not None else '',
                    f"{best - box:.3f}" if best is not None and box is not None else '',
                    f"{pose['roll_deg']:.0f}" if pose else '', f"{pose['pitch_deg']:.0f}" if pose else '']
        else:
            row += ['-'] * 11
        if K:
            m = (K.get('measured') or {}).get('size')
            diff = ''
            if m and V and V.get('model') and V['model'] in size:
                s = size[V['model']]
                diff = f"{max(abs(m[i] - s[i]) / s[i] for i in range(3)):.2f}"
            f = K.get('features') or {}
            row += [K.get('class') or '', (K.get('reason') or '') + ('/' + K['refused_on'] if K.get('refused_on') else ''), f"{K['confidence']:.2f}",
                    'x'.join(f'{x:.2f}' for x in m) if m else '', diff,
                    f"{f['rectangularity']:.2f}" if f.get('rectangularity') is not None else '',
                    f"{f['plateau_share']:.2f}" if f.get('plateau_share') is not None else '',
                    (K.get('detail') or '')[:90]]
        else:
            row += ['-'] * 8
        w.writerow(row)
