#!/usr/bin/env python3
"""Issue 28, "a real tile beside a simulated one": the same figures for LAS files, real or simulated.

  lasstats.py [--md OUT.md] [--json OUT.json] NAME=LAS[,TRUTH.json] ...

Plain LAS only (1.2 - 1.4, point formats 0-10; the real tiles' LAZ is read through
reference/*.las, laz-perf's decoding, or through canopy's reader: run.sh converts with
`addnoise`); python3 standard library only (Debian's python3 here has no numpy).

Per file: points/m^2 over occupied 1 m cells (all, first returns, last returns), on open
ground (1 m cells whose every point is ASPRS class 2), pulses (first returns) by their
number_of_returns (1, 2, 3, 4+), the same for pulses whose first return is vegetation
(class 3-5) and for pulses whose first return is ground (class 2), the scan-angle range, and
points per vehicle:
  * a hand-labelled real tile (truth.json with "footprint" and "points"): points inside the
    label's footprint rectangle with height above ground 0.25 m .. cut (2.4 m for cars,
    2.9 m for vans: real-tiles.md's cuts), ground = a plane fitted to the class-2 points within
    3 m around the rectangle (the ASPRS classification is used for measurement only);
  * a simulated tile (truth.json from rangetrace, points with an `instance` extra-bytes
    field): the points carrying each vehicle's instance, and for comparison the same
    rectangle count as for the real tiles (footprint from the truth's pose and size).
"""
import json
import math
import statistics
import struct
import sys

# ---------------------------------------------------------------- LAS reading

EB_TYPES = {1: 'B', 2: 'b', 3: 'H', 4: 'h', 5: 'I', 6: 'i', 7: 'Q', 8: 'q', 9: 'f', 10: 'd'}


def read_las(path):
    with open(path, 'rb') as f:
        data = f.read()
    if data[:4] != b'LASF':
        raise SystemExit(f'{path}: not a LAS file (LAZ? give the plain LAS)')
    vmaj, vmin = data[24], data[25]
    header_size, = struct.unpack_from('<H', data, 94)
    offset_points, n_vlr = struct.unpack_from('<II', data, 96)
    fmt = data[104]
    if fmt & 0xC0:
        raise SystemExit(f'{path}: LAZ-compressed; give the plain LAS')
    reclen, legacy_n = struct.unpack_from('<HI', data, 105)
    scale = struct.unpack_from('<3d', data, 131)
    offset = struct.unpack_from('<3d', data, 155)
    n = legacy_n
    evlr_start, n_evlr = 0, 0
    if vmin >= 4:
        evlr_start, n_evlr, n = struct.unpack_from('<QIQ', data, 235)
    # extra bytes descriptors (VLR or EVLR LASF_Spec/4)
    extra = []
    pos = header_size
    records = []
    for _ in range(n_vlr):
        _, uid, rid, ln = struct.unpack_from('<H16sHH', data, pos)
        records.append((uid, rid, pos + 54, ln))
        pos += 54 + ln
    if n_evlr:
        pos = evlr_start
        for _ in range(n_evlr):
            _, uid, rid, ln = struct.unpack_from('<H16sHQ', data, pos)
            records.append((uid, rid, pos + 60, ln))
            pos += 60 + ln
    for uid, rid, start, ln in records:
        if uid.rstrip(b'\0') == b'LASF_Spec' and rid == 4:
            for k in range(ln // 192):
                d = start + 192 * k
                dtype, _opt = data[d + 2], data[d + 3]
                name = data[d + 4:d + 36].split(b'\0')[0].decode('ascii', 'replace')
                extra.append((name, dtype))
    if fmt <= 5:
        base = '<iiiHBBbBH' + ('d' if fmt in (1, 3, 4, 5) else '')
    else:
        base = '<iiiHBBBBhHd'
    base_len = struct.calcsize(base)
    eb_fmt, eb_names, used = '', [], base_len
    for name, dtype in extra:
        if dtype in EB_TYPES:
            eb_fmt += EB_TYPES[dtype]
            eb_names.append(name)
            used += struct.calcsize('<' + EB_TYPES[dtype])
        else:  # undocumented bytes: stop describing
            break
    std_len = {0: 20, 1: 28, 2: 26, 3: 34, 4: 57, 5: 63, 6: 30, 7: 36, 8: 38, 9: 59, 10: 67}[fmt]
    # extra bytes follow the whole standard record (rgb, nir, waveform), not only our prefix
    full = base + 'x' * (std_len - base_len) + eb_fmt
    full += 'x' * (reclen - struct.calcsize(full))
    buf = data[offset_points:offset_points + n * reclen]
    cols = {k: [] for k in ('x', 'y', 'z', 'intensity', 'rn', 'nr', 'cls', 'angle', 'psid', 'gps')}
    for name in eb_names:
        cols[name] = []
    sx, sy, sz = scale
    ox, oy, oz = offset
    X, Y, Z, I, RN, NR, C, A = (cols[k] for k in ('x', 'y', 'z', 'intensity', 'rn', 'nr', 'cls', 'angle'))
    ebl = [cols[nm] for nm in eb_names]
    PS = cols['psid']
    G = cols['gps']
    ne = len(eb_names)
    for rec in struct.iter_unpack(full, buf):
        # rounded to 0.1 mm: the same coordinates written with another scale and offset
        # (canopy's writer: 1 mm, whole-metre offset) give the same doubles
        X.append(round(rec[0] * sx + ox, 4))
        Y.append(round(rec[1] * sy + oy, 4))
        Z.append(round(rec[2] * sz + oz, 4))
        I.append(rec[3])
        if fmt <= 5:
            RN.append(rec[4] & 7)
            NR.append((rec[4] >> 3) & 7)
            C.append(rec[5] & 31)
            A.append(float(rec[6]))
            PS.append(rec[8])
            k = 9 if fmt in (1, 3, 4, 5) else 8
            G.append(rec[9] if k == 9 else 0.0)
        else:
            RN.append(rec[4] & 15)
            NR.append(rec[4] >> 4)
            C.append(rec[6])
            A.append(rec[8] * 0.006)
            PS.append(rec[9])
            G.append(rec[10])
            k = 11
        for j in range(ne):
            ebl[j].append(rec[k + j])
    cols['n'] = n
    cols['format'] = f'LAS {vmaj}.{vmin}, point format {fmt}'
    return cols


# ---------------------------------------------------------------- geometry helpers

def inside(poly, x, y):
    """Convex polygon, counter-clockwise."""
    for i in range(len(poly)):
        ax, ay = poly[i]
        bx, by = poly[(i + 1) % len(poly)]
        if (bx - ax) * (y - ay) - (by - ay) * (x - ax) < 0:
            return False
    return True


def rect(cx, cy, heading_deg, length, width):
    c, s = math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg))
    hl, hw = length / 2, width / 2
    return [(cx + c * a - s * b, cy + s * a + c * b) for a, b in ((-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw))]


def solve3(m, v):
    """Gaussian elimination, 3x3."""
    a = [row[:] + [v[i]] for i, row in enumerate(m)]
    for i in range(3):
        p = max(range(i, 3), key=lambda r: abs(a[r][i]))
        a[i], a[p] = a[p], a[i]
        if abs(a[i][i]) < 1e-12:
            return None
        for r in range(3):
            if r != i:
                f = a[r][i] / a[i][i]
                for c in range(i, 4):
                    a[r][c] -= f * a[i][c]
    return [a[i][3] / a[i][i] for i in range(3)]


def ground_plane(pts, x0, y0):
    """Least-squares plane z = a + b (x - x0) + c (y - y0)."""
    s = [[0.0] * 3 for _ in range(3)]
    t = [0.0] * 3
    for x, y, z in pts:
        r = (1.0, x - x0, y - y0)
        for i in range(3):
            t[i] += r[i] * z
            for j in range(3):
                s[i][j] += r[i] * r[j]
    return solve3(s, t)


def summary(values):
    if not values:
        return '–'
    v = sorted(values)
    return f'{statistics.median(v):.0f} ({v[0]}–{v[-1]}, {len(v)})'


def pct(a, b):
    return 100.0 * a / b if b else float('nan')


# ---------------------------------------------------------------- figures

def figures(name, las_path, truth_path):
    p = read_las(las_path)
    truth = json.load(open(truth_path)) if truth_path else None
    n = p['n']
    idx = range(n)
    X, Y, Z, RN, NR, C, A = p['x'], p['y'], p['z'], p['rn'], p['nr'], p['cls'], p['angle']
    simulated = 'instance' in p
    if simulated and truth and 'extent' in truth:
        ex, ey = truth['extent'][:2]
        ox, oy = (truth.get('origin') or [0, 0])[:2]
        idx = [i for i in idx if ox <= X[i] < ox + ex and oy <= Y[i] < oy + ey]
    idx = list(idx)
    cells = {}
    for i in idx:
        cells.setdefault((math.floor(X[i]), math.floor(Y[i])), []).append(i)
    area = len(cells)
    first = [i for i in idx if RN[i] == 1]
    last = [i for i in idx if RN[i] == NR[i]]
    ground_cells = [c for c, l in cells.items() if all(C[i] == 2 for i in l)]
    ground_pts = sum(len(cells[c]) for c in ground_cells)
    f = {'name': name, 'file': las_path, 'format': p['format'], 'points': len(idx), 'area_m2': area}
    f['density_all'] = len(idx) / area
    f['density_first'] = len(first) / area
    f['density_last'] = len(last) / area
    f['open_ground_cells'] = len(ground_cells)
    f['density_open_ground'] = ground_pts / len(ground_cells) if ground_cells else float('nan')
    # open surfaces: cells whose points are all single returns within 0.3 m of height (roads,
    # lawns, flat roofs): there points = pulses, whatever the classification
    open_cells = [c for c, l in cells.items()
                  if all(NR[i] == 1 for i in l) and max(Z[i] for i in l) - min(Z[i] for i in l) < 0.3]
    f['open_cells'] = len(open_cells)
    f['density_open'] = (sum(len(cells[c]) for c in open_cells) / len(open_cells)) if open_cells else float('nan')

    def hist(pulses):
        h = [0, 0, 0, 0]
        for i in pulses:
            h[min(max(NR[i], 1), 4) - 1] += 1
        tot = sum(h)
        return [pct(k, tot) for k in h], tot

    f['pulses_by_returns'], f['pulses'] = hist(first)
    f['pulses_by_returns_last'], f['pulses_last'] = hist(last)
    f['veg_pulses_by_returns'], f['veg_pulses'] = hist([i for i in first if C[i] in (3, 4, 5)])
    f['ground_pulses_by_returns'], f['ground_pulses'] = hist([i for i in first if C[i] == 2])
    f['max_returns'] = max(NR[i] for i in idx)
    f['returns_per_pulse'] = len(idx) / len(first) if first else float('nan')
    ang = sorted(A[i] for i in idx)
    f['scan_angle'] = [ang[0], ang[-1]]
    absang = sorted(abs(a) for a in ang)
    f['scan_angle_abs_p50_p95'] = [absang[len(absang) // 2], absang[int(0.95 * (len(absang) - 1))]]
    f['scan_angle_values'] = len(set(ang))
    inten = sorted(p['intensity'][i] for i in idx)
    f['intensity_p50'] = inten[len(inten) // 2]
    f['sources'] = sorted(set(p['psid'][i] for i in idx))
    f['classes'] = {}
    for i in idx:
        f['classes'][C[i]] = f['classes'].get(C[i], 0) + 1
    f['classes'] = dict(sorted(f['classes'].items()))

    # points per vehicle
    vehicles = (truth or {}).get('vehicles', [])
    grid = {}
    for i in idx:
        grid.setdefault((math.floor(X[i] / 2), math.floor(Y[i] / 2)), []).append(i)

    def near(xmin, ymin, xmax, ymax):
        out = []
        for gx in range(math.floor(xmin / 2), math.floor(xmax / 2) + 1):
            for gy in range(math.floor(ymin / 2), math.floor(ymax / 2) + 1):
                out.extend(grid.get((gx, gy), ()))
        return out

    rows = []
    for v in vehicles:
        pose = v['pose']
        if 'footprint' in v and not simulated:
            poly = [tuple(c) for c in v['footprint']]
            cut = 2.9 if v.get('model') == 'van' else 2.4
            vis = v.get('visibility', '')
            area_fp = v['size'][0] * v['size'][1]
        else:
            # rangetrace truth: pose x y in the tile frame plus origin, size L W H
            o = truth.get('origin') or [0, 0]
            L, W, H = v['size'][:3]
            poly = rect(pose['x'] + o[0], pose['y'] + o[1], pose['heading'], L, W)
            cut = H + 0.3
            vis = 'clear' if v.get('canopy_cover', 0) < 0.15 else 'partial'
            area_fp = L * W
        xs = [q[0] for q in poly]
        ys = [q[1] for q in poly]
        cand = near(min(xs) - 3, min(ys) - 3, max(xs) + 3, max(ys) + 3)
        inpoly = [i for i in cand if inside(poly, X[i], Y[i])]
        gnd = [(X[i], Y[i], Z[i]) for i in cand if C[i] == 2 and i not in set(inpoly)]
        cx, cy = sum(xs) / 4, sum(ys) / 4
        plane = ground_plane(gnd, cx, cy) if len(gnd) >= 10 else None
        if plane is None:
            plane = [pose.get('z', 0.0), 0.0, 0.0]
        cnt = multi = 0
        for i in inpoly:
            hag = Z[i] - (plane[0] + plane[1] * (X[i] - cx) + plane[2] * (Y[i] - cy))
            if 0.25 <= hag <= cut:
                cnt += 1
                multi += NR[i] > 1
        row = {'instance': v['instance'], 'model': v.get('model'), 'visibility': vis, 'rect_points': cnt, 'rect_multi': multi,
               'footprint_m2': area_fp, 'label_points': v.get('points'), 'canopy_cover': v.get('canopy_cover')}
        if simulated:
            row['instance_points'] = sum(1 for i in idx if p['instance'][i] == v['instance'])
            row['instance_points_first'] = sum(1 for i in idx if p['instance'][i] == v['instance'] and RN[i] == 1)
        rows.append(row)
    f['vehicles'] = rows
    return f


# ---------------------------------------------------------------- table

def markdown(figs):
    def r(label, fn):
        return f'| {label} | ' + ' | '.join(fn(f) for f in figs) + ' |'

    def h4(v):
        return '–' if any(math.isnan(x) for x in v) else ' / '.join(f'{x:.1f}' for x in v)

    out = ['| | ' + ' | '.join(f'`{f["name"]}`' for f in figs) + ' |', '|---' * (len(figs) + 1) + '|']
    out.append(r('file', lambda f: f['format']))
    out.append(r('points (in the tile) / occupied 1 m cells', lambda f: f'{f["points"]:,} / {f["area_m2"]:,}'.replace(',', ' ')))
    out.append(r('points/m², all / first / last returns',
                 lambda f: f'{f["density_all"]:.1f} / {f["density_first"]:.1f} / {f["density_last"]:.1f}'))
    out.append(r('points/m² on open ground (cells of class 2 only; cells)',
                 lambda f: f'{f["density_open_ground"]:.1f} ({f["open_ground_cells"]:,})'.replace(',', ' ')))
    out.append(r('points/m² on open surfaces (cells of single returns within 0.3 m; cells)',
                 lambda f: f'{f["density_open"]:.1f} ({f["open_cells"]:,})'.replace(',', ' ')))
    out.append(r('returns per pulse (points / first returns)', lambda f: f'{f["returns_per_pulse"]:.2f}'))
    out.append(r('most returns of a pulse', lambda f: str(f['max_returns'])))
    out.append(r('pulses with 1 / 2 / 3 / 4+ returns, % (by first returns)', lambda f: h4(f['pulses_by_returns'])))
    out.append(r('the same, by last returns', lambda f: h4(f['pulses_by_returns_last'])))
    out.append(r('pulses whose first return is vegetation (3–5): 1 / 2 / 3 / 4+, % (pulses)',
                 lambda f: h4(f['veg_pulses_by_returns']) + f' ({f["veg_pulses"]:,})'.replace(',', ' ')))
    out.append(r('pulses whose first return is ground (2): 1 / 2 / 3 / 4+, % (pulses)',
                 lambda f: h4(f['ground_pulses_by_returns']) + f' ({f["ground_pulses"]:,})'.replace(',', ' ')))
    out.append(r('scan angle, min … max (°)', lambda f: f'{f["scan_angle"][0]:.1f} … {f["scan_angle"][1]:.1f}'
                 + f' ({f["scan_angle_values"]} distinct values)'))
    out.append(r('\\|scan angle\\|, median / 95th percentile (°)',
                 lambda f: f'{f["scan_angle_abs_p50_p95"][0]:.1f} / {f["scan_angle_abs_p50_p95"][1]:.1f}'))
    out.append(r('intensity, median', lambda f: f'{f["intensity_p50"]}'))
    out.append(r('flight lines (point source ids)', lambda f: ', '.join(str(k) for k in f['sources'])))
    out.append(r('ASPRS classes (points)', lambda f: ', '.join(f'{k}: {v}' for k, v in f['classes'].items())))

    def veh(f, vis=None, key='rect_points'):
        return [v[key] for v in f['vehicles'] if (vis is None or v['visibility'] == vis) and v.get(key) is not None]

    out.append(r('vehicles (clear / other)', lambda f: f'{len(veh(f, "clear"))} / {len(f["vehicles"]) - len(veh(f, "clear"))}'))
    out.append(r('points per clear vehicle, rectangle 0.25 m – cut: median (range, n)', lambda f: summary(veh(f, 'clear'))))
    out.append(r('the same, real-tiles.md `points` of the labels', lambda f: summary(veh(f, 'clear', 'label_points')) if not f['vehicles'] or f['vehicles'][0]['label_points'] is not None else '–'))
    out.append(r('points per clear vehicle from `instance` (sim only)',
                 lambda f: summary(veh(f, 'clear', 'instance_points')) if f['vehicles'] and 'instance_points' in f['vehicles'][0] else '–'))

    def per_m2(f):
        v = [x['rect_points'] / x['footprint_m2'] for x in f['vehicles'] if x['visibility'] == 'clear']
        return f'{statistics.median(v):.1f}' if v else '–'

    out.append(r('clear vehicles: rectangle points per m² of footprint, median', per_m2))

    def per_first(f):
        v = [x['rect_points'] / x['footprint_m2'] / f['density_first'] for x in f['vehicles'] if x['visibility'] == 'clear']
        return f'{statistics.median(v):.2f}' if v else '–'

    out.append(r('the same ÷ first returns per m² of the tile', per_first))

    def multi(f):
        v = [x for x in f['vehicles'] if x['visibility'] == 'clear']
        a, b = sum(x['rect_multi'] for x in v), sum(x['rect_points'] for x in v)
        return f'{pct(a, b):.1f}' if b else '–'

    out.append(r('clear vehicles: % of their rectangle points from multi-return pulses', multi))
    return '\n'.join(out) + '\n'


def vehicle_rows(figs):
    out = ['| tile | vehicle | model | visibility | footprint (m²) | rectangle points (multi-return) | label `points` | `instance` points (first returns) |',
           '|---|---|---|---|---|---|---|---|']
    for f in figs:
        for v in f['vehicles']:
            ip = f'{v["instance_points"]} ({v["instance_points_first"]})' if 'instance_points' in v else '–'
            lp = v['label_points'] if v['label_points'] is not None else '–'
            out.append(f'| `{f["name"]}` | {v["instance"]} | {v["model"]} | {v["visibility"]} | {v["footprint_m2"]:.1f} | '
                       f'{v["rect_points"]} ({v["rect_multi"]}) | {lp} | {ip} |')
    return '\n'.join(out) + '\n'


def main(argv):
    md = js = None
    specs = []
    it = iter(argv)
    for a in it:
        if a == '--md':
            md = next(it)
        elif a == '--json':
            js = next(it)
        else:
            specs.append(a)
    figs = []
    for s in specs:
        name, rest = s.split('=', 1)
        parts = rest.split(',')
        figs.append(figures(name, parts[0], parts[1] if len(parts) > 1 else None))
    text = markdown(figs) + '\n' + vehicle_rows(figs)
    if md:
        open(md, 'w').write(text)
    if js:
        def clean(o):  # NaN (nothing to measure) as null: strict JSON
            if isinstance(o, float) and math.isnan(o):
                return None
            if isinstance(o, dict):
                return {str(k): clean(v) for k, v in o.items()}
            if isinstance(o, list):
                return [clean(v) for v in o]
            return o
        json.dump(clean(figs), open(js, 'w'), indent=1, allow_nan=False)
    sys.stdout.write(text)


if __name__ == '__main__':
    main(sys.argv[1:])
