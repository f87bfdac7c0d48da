#!/usr/bin/env python3
"""Every wrong-class answer and false alarm of a density rung (score's matches.csv, a rung of `make
density` run with SCENE_KEEP_TILE_SCANS=1 so that each tile's scan.pcd stays), one line each:
  cover|seed|candidate|outcome|true model|true class|true size|answered|size L x W x H|sigma|object
  points|plateau_share|end_high|rectangularity|notch_sampled|shoulder|rim|top_roughness|below_share|
  ground_through|confidence|class_margin|the three nearest family ranges (sigma)|the true class's
  family range (sigma)|what a false alarm fell on (a true vehicle's footprint, a clutter box, none)
  or the vehicle's canopy cover|for a wrong answer: the vehicle's scan points the crop holds, the
  scan's and the crop's extent of it along / across its heading, and which other candidates hold
  the rest.
The distances repeat classify's fit() (tools/classify/classify.cpp) on the family ranges only
(no modelbase entry, no flat-box filter): a reading aid, not classify's choice. Truth is read here
only, on development seeds (docs/decisions/density-ladder.md, stop 63).
  bench/density/wrong.py OUT/density/dL RES/density/dL"""
import csv, json, math, sys, os
import struct

RANGES = {  # tools/classify/classify.cpp class_ranges(): L, W, H, plateau, tail, hull
 "sedan": ((4.40,5.10),(1.72,1.90),(1.38,1.50),0,-1,None),
 "hatchback": ((3.55,4.40),(1.62,1.80),(1.42,1.56),0,1,None),
 "suv": ((4.40,5.30),(1.80,2.05),(1.65,1.95),0,1,None),
 "pickup": ((5.00,5.90),(1.80,2.05),(1.75,2.00),-1,-1,None),
 "van": ((4.90,6.00),(1.90,2.06),(1.95,2.75),1,1,None),
 "box-truck": ((7.00,10.00),(2.30,2.55),(3.00,3.90),1,0,None),
 "semi-tractor": ((5.80,7.50),(2.45,2.55),(3.00,4.00),-1,0,None),
 "bus": ((10.50,13.50),(2.50,2.55),(2.90,3.40),1,0,None),
 "wheeled-apc": ((6.40,8.00),(2.50,3.00),(2.30,2.90),0,0,None),
 "tracked-apc": ((4.90,7.00),(2.70,3.30),(1.90,2.70),0,0,None),
 "tank": ((8.70,11.40),(3.40,3.80),(2.20,3.00),0,0,(6.50,8.00)),
 "wheel-loader": ((6.80,9.00),(2.50,3.20),(3.00,3.70),-1,0,None),
}
MODEL_CLASS = {"earthmover":"wheel-loader","obj1":"wheeled-apc","sedan":"sedan","semi":"semi-tractor","tank":"tank"}

def miss(v, r, s): return max(0.0, r[0]-v, v-r[1]) / s

def dist(name, L, W, H, s, plateau, endh):
    l, w, h, pl, tl, hull = RANGES[name]
    dl = miss(L, l, s)
    if hull: dl = min(dl, miss(L, hull, s))
    d = math.sqrt(dl*dl + miss(W, w, s)**2 + miss(H, h, s)**2)
    p = 1 if plateau >= 0.6 else -1
    t = 1 if endh >= 0.75 else -1
    pen = (pl != 0 and pl != p) or (tl != 0 and tl != t)
    return d + (1.5 if pen else 0), (dl, miss(W, w, s), miss(H, h, s), pen)

def read_pcd(path):
    with open(path, 'rb') as f:
        hdr = {}
        while True:
            line = f.readline().decode('latin1').strip()
            if line.startswith('#') or not line: continue
            k, *v = line.split()
            hdr[k] = v
            if k == 'DATA': break
        n = int(hdr['POINTS'][0]); fields = hdr['FIELDS']; sizes = list(map(int, hdr['SIZE'])); types = hdr['TYPE']
        fmt = '<' + ''.join({('F',4):'f',('F',8):'d',('U',1):'B',('U',2):'H',('U',4):'I',('I',4):'i',('I',2):'h',('I',1):'b'}[(t,s)] for s, t in zip(sizes, types))
        st = struct.Struct(fmt); data = f.read(n * st.size)
        return [dict(zip(fields, st.unpack_from(data, i * st.size))) for i in range(n)]

def inside(poly, x, y):
    c = False
    for i in range(len(poly)):
        x1, y1 = poly[i]; x2, y2 = poly[(i+1) % len(poly)]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1): c = not c
    return c

def fell_on(truth, x, y):
    best = None
    for v in truth['vehicles']:
        if v.get('footprint') and inside(v['footprint'], x, y):
            d = math.hypot(x - v['pose']['x'], y - v['pose']['y'])
            if best is None or d < best[0]: best = (d, 'vehicle %s #%d, %.2f m off its centre' % (v['model'], v['instance'], d))
    if best: return best[1]
    for c in truth['clutter']:
        b = c['box']; h = math.radians(b['heading']); dx, dy = x - b['centre'][0], y - b['centre'][1]
        u = dx*math.cos(h) + dy*math.sin(h); w = -dx*math.sin(h) + dy*math.cos(h)
        if abs(u) <= b['size'][0]/2 and abs(w) <= b['size'][1]/2:
            return 'clutter %s %.1fx%.1fx%.1f' % (c['kind'], *b['size'])
    near = sorted((math.hypot(x-c['box']['centre'][0], y-c['box']['centre'][1]), c['kind']) for c in truth['clutter'])
    if near and near[0][0] <= 1.5: return 'near clutter %s (%.2f m)' % (near[0][1], near[0][0])
    return 'none (terrain/vegetation)'

def crop_share(tile_dir, cand, cls, inst):
    scan = os.path.join(tile_dir, 'scan.pcd')
    if not os.path.exists(scan) or inst is None: return ''
    s = read_pcd(scan); c = read_pcd(os.path.join(tile_dir, 'noise-0', 'cands', cand + '.pcd'))
    M = cls['transform']['matrix']
    grid = {}
    for j, p in enumerate(s):
        grid.setdefault((round(p['x'] * 20), round(p['y'] * 20)), []).append(j)
    hit = set()
    for p in c:
        x = M[0]*p['x'] + M[1]*p['y'] + M[2]*p['z'] + M[3]
        y = M[4]*p['x'] + M[5]*p['y'] + M[6]*p['z'] + M[7]
        z = M[8]*p['x'] + M[9]*p['y'] + M[10]*p['z'] + M[11]
        for gx in (-1, 0, 1):
            for gy in (-1, 0, 1):
                for j in grid.get((round(x * 20) + gx, round(y * 20) + gy), []):
                    q = s[j]
                    if (q['x']-x)**2 + (q['y']-y)**2 + (q['z']-z)**2 < 1e-4: hit.add(j)
    veh = [j for j, q in enumerate(s) if q['label'] == 1 and q['instance'] == inst]
    tv = [v for v in TRUTH['vehicles'] if v['instance'] == inst][0]
    h = math.radians(tv['pose']['heading'])
    def along(j): return (s[j]['x'] - tv['pose']['x']) * math.cos(h) + (s[j]['y'] - tv['pose']['y']) * math.sin(h)
    def across(j): return -(s[j]['x'] - tv['pose']['x']) * math.sin(h) + (s[j]['y'] - tv['pose']['y']) * math.cos(h)
    a_all = [along(j) for j in veh]; a_in = [along(j) for j in veh if j in hit]
    w_all = [across(j) for j in veh]; w_in = [across(j) for j in veh if j in hit]
    z_all = [s[j]['z'] for j in veh]; z_in = [s[j]['z'] for j in veh if j in hit]
    # where the missing points went: another candidate's crop?
    lost = set(j for j in veh if j not in hit); other = {}
    cdir = os.path.join(tile_dir, 'noise-0', 'cands')
    for fn in sorted(os.listdir(cdir)):
        if not fn.endswith('.pcd') or fn == cand + '.pcd' or not lost: continue
        oc = os.path.join(cdir, fn[:-4], 'class.json')
        if not os.path.exists(oc): continue
        Mo = json.load(open(oc))['transform']['matrix']
        for p in read_pcd(os.path.join(cdir, fn)):
            x = Mo[0]*p['x'] + Mo[1]*p['y'] + Mo[2]*p['z'] + Mo[3]
            y = Mo[4]*p['x'] + Mo[5]*p['y'] + Mo[6]*p['z'] + Mo[7]
            z = Mo[8]*p['x'] + Mo[9]*p['y'] + Mo[10]*p['z'] + Mo[11]
            for gx in (-1, 0, 1):
                for gy in (-1, 0, 1):
                    for j in grid.get((round(x * 20) + gx, round(y * 20) + gy), []):
                        if j in lost and (s[j]['x']-x)**2 + (s[j]['y']-y)**2 + (s[j]['z']-z)**2 < 1e-4:
                            other.setdefault(fn[:-4], set()).add(j)
    rng = lambda v: (max(v) - min(v)) if v else 0
    # the missing points with foliage (label 2) above them within 1 m in plan: hidden under a crown
    fol = [q for q in s if q['label'] == 2]
    under = sum(1 for j in lost if any(f['z'] > s[j]['z'] and (f['x'] - s[j]['x'])**2 + (f['y'] - s[j]['y'])**2 < 1.0 for f in fol))
    return 'in crop %d/%d (missing under foliage %d); scan L %.2f W %.2f Hmax %.2f; crop-held L %.2f W %.2f Hmax %.2f; missing in %s' % (
        len(a_in), len(veh), under, rng(a_all), rng(w_all), max(z_all) if z_all else 0, rng(a_in), rng(w_in), max(z_in) if z_in else 0,
        ','.join('%s:%d' % (k, len(v)) for k, v in other.items()) or '-')

out_dir, res_dir = sys.argv[1], sys.argv[2]
tiles = [l.split() for l in open(os.path.join(out_dir, 'tiles.txt'))]
rows = list(csv.DictReader(open(os.path.join(res_dir, 'matches.csv'))))
for r in rows:
    if r['outcome'] not in ('wrong', 'false_alarm'): continue
    det, truthp, _, cover = tiles[int(r['tile'])]
    tile_dir = os.path.dirname(truthp); seed = tile_dir.split('tile-')[1]
    cls = json.load(open(os.path.join(tile_dir, 'noise-0', 'cands', r['candidate'], 'class.json')))
    f = cls['features']; L, W, H = cls['size']; sp = cls['measured']['spacing']
    s = math.sqrt(0.15**2 + (0.5*sp)**2)
    truth = json.load(open(truthp)); global TRUTH; TRUTH = truth
    ds = sorted((dist(n, L, W, H, s, f['plateau_share'], f['end_high'])[0], n) for n in RANGES)
    top = ', '.join('%s %.1f' % (n, d) for d, n in ds[:3])
    tm = r['true_model']; tc = MODEL_CLASS.get(tm, '')
    tdist = ('%.1f' % dist(tc, L, W, H, s, f['plateau_share'], f['end_high'])[0]) if tc else ''
    tsz = ''
    inst = int(r['instance']) if r['instance'] else None
    if inst is not None:
        v = [v for v in truth['vehicles'] if v['instance'] == inst][0]; tsz = '%.2fx%.2fx%.2f' % tuple(v['size'])
        what = 'cover %.2f' % v['canopy_cover']
    else:
        what = fell_on(truth, float(r['x']), float(r['y']))
        # what is near (nearest vehicle centre)
    try: share = crop_share(tile_dir, r['candidate'], cls, inst)
    except Exception as e: share = 'err %s' % e
    print('|'.join(map(str, [cover, seed, r['candidate'], r['outcome'], tm, tc, tsz, r['class'],
          '%.2fx%.2fx%.2f' % (L, W, H), '%.2f' % s, f['object_points'], '%.2f' % f['plateau_share'], '%.2f' % f['end_high'],
          '%.2f' % f['rectangularity'], '%.2f' % f['notch_sampled'], f['shoulder'] and '%.2f' % f['shoulder'], f['rim'] and '%.2f' % f['rim'],
          '%.3f' % f['top_roughness'], '%.2f' % f['below_share'], '%.2f' % f['ground_through'], '%.2f' % cls['confidence'], '%.1f' % cls['class_margin'],
          top, tdist, what, share])))
