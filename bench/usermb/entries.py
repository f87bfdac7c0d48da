#!/usr/bin/env python3
"""entries.py DEST LEVEL SPACING_MM MODEL SEED [DETECT_INI] : one density-matched modelbase entry
(docs/decisions/user-modelbase.md §9, a study; not part of any make rule).

The model alone in an open 20 m tile with the scene experiment's flight lines and looks (the open
set's single-vehicle crop recipe, mk/openset.mk) at the pixel spacing of a density-ladder level,
rendered by rangetrace; detect (DETECT_INI: the ladder's detect-ladder.ini on its class-level
rungs); the plan of `collect --plan --model-density 1` (every candidate gets the density rule's
options, measured on its own density); the candidate nearest the vehicle's true position;
its points (and sensor directions) moved from detect's candidate frame into the model's frame
(the crop's truth pose), so the entry has the dense entry's frame; then the tile chain's
fitvox (fitvox-tile.ini), cocone, ncut with the plan's options for that candidate.
Writes DEST/<model>-s<seed>/{recipe.scene,scan.pcd,truth.json,cands/,plan.mk,cand.pcd,
samples.pcd,mesh.ply,segments.json,segments.ply,entry.json} (entry.json: the candidate's
measured density, points, length against the truth, CPU seconds per stage).
BIN (default build/bin) names the tools."""
import json
import math
import os
import re
import struct
import subprocess
import sys
import time

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get('BIN', f'{SRC}/build/bin')
P = f'{SRC}/share/params'

RECIPE = """# density-matched entry (bench/usermb/entries.py): {model}, seed {seed}, level {level}
extent = 20m
terrain = flat
trees = 0
bushes = 0
vehicles = random 1 from {model}
flight_lines = 2
headings = 0deg 90deg
looks = 75deg/0deg 75deg/180deg
spacing = {spacing}mm
"""


def run(cmd, cpu):
    t0 = os.times()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t1 = os.times()
    cpu[os.path.basename(cmd[0])] = cpu.get(os.path.basename(cmd[0]), 0) + (t1.children_user - t0.children_user) + (
        t1.children_system - t0.children_system)


def read_pcd(path):
    data = open(path, 'rb').read()
    i = data.find(b'DATA binary\n')
    if i < 0:
        raise SystemExit(f'{path}: not DATA binary')
    header = data[:i].decode()
    fields = re.search(r'^FIELDS (.*)$', header, re.M).group(1).split()
    types = re.search(r'^TYPE (.*)$', header, re.M).group(1).split()
    sizes = re.search(r'^SIZE (.*)$', header, re.M).group(1).split()
    n = int(re.search(r'^POINTS (\d+)$', header, re.M).group(1))
    fmt = '<' + ''.join({('F', '4'): 'f', ('I', '4'): 'i', ('U', '4'): 'I', ('F', '8'): 'd'}[(t, s)] for t, s in zip(types, sizes))
    rec = struct.calcsize(fmt)
    body = data[i + len(b'DATA binary\n'):]
    rows = [list(struct.unpack_from(fmt, body, k * rec)) for k in range(n)]
    return data[:i], fields, fmt, rows


def write_pcd(path, header, fmt, rows):
    with open(path, 'wb') as f:
        f.write(header + b'DATA binary\n')
        for r in rows:
            f.write(struct.pack(fmt, *r))


def rot(h, p, r):
    # R = Rz(heading) Ry(pitch) Rx(roll) (truth.json "angles")
    ch, sh, cp, sp, cr, sr = math.cos(h), math.sin(h), math.cos(p), math.sin(p), math.cos(r), math.sin(r)
    return [[ch * cp, ch * sp * sr - sh * cr, ch * sp * cr + sh * sr],
            [sh * cp, sh * sp * sr + ch * cr, sh * sp * cr - ch * sr],
            [-sp, cp * sr, cp * cr]]


def main():
    dest, level, spacing, model, seed = sys.argv[1:6]
    detect_ini = sys.argv[6] if len(sys.argv) > 6 else ''
    d = f'{dest}/{model}-s{seed}'
    os.makedirs(d, exist_ok=True)
    cpu = {}
    wall0 = time.time()
    open(f'{d}/recipe.scene', 'w').write(RECIPE.format(model=model, seed=seed, level=level, spacing=spacing))
    run([f'{BIN}/rangetrace', '--scene', f'{d}/recipe.scene', '--seed', seed, '--threads', '2', '-o', f'{d}/scan.pcd',
         '--truth', f'{d}/truth.json'], cpu)
    run([f'{BIN}/detect'] + (['--config', detect_ini] if detect_ini else []) + ['--no-classes', '-i', f'{d}/scan.pcd', '-o',
                                                                                 f'{d}/cands'], cpu)
    run([f'{BIN}/collect', '-i', f'{d}/cands/index.json', '--plan', f'{d}/plan.mk', '--plan-key', 'E', '--model-density', '1'],
        cpu)
    truth = json.load(open(f'{d}/truth.json'))['vehicles'][0]
    pose = truth['pose']
    index = json.load(open(f'{d}/cands/index.json'))
    if not index['candidates']:
        json.dump({'model': model, 'seed': seed, 'level': level, 'candidate': None}, open(f'{d}/entry.json', 'w'))
        print(f'{model} s{seed} d{level}: no candidate')
        return
    c = min(index['candidates'], key=lambda c: math.hypot(c['centre'][0] - pose['x'], c['centre'][1] - pose['y']))
    plan = open(f'{d}/plan.mk').read()

    def opts(stage):
        m = re.search(rf'^E_{stage}_{c["id"]} := (.*)$', plan, re.M)
        return m.group(1).split() if m else []

    # candidate frame -> tile (index transform) -> model frame (inverse truth pose)
    T = c['transform']
    R = rot(math.radians(pose['heading']), math.radians(pose['pitch']), math.radians(pose['roll']))
    t = (pose['x'], pose['y'], pose['z'])
    header, fields, fmt, rows = read_pcd(f'{d}/cands/{c["file"]}')
    ix = [fields.index(k) for k in ('x', 'y', 'z')]
    isx = [fields.index(k) for k in ('sensor_x', 'sensor_y', 'sensor_z')] if 'sensor_x' in fields else None
    for r in rows:
        p = [r[k] for k in ix]
        w = [sum(T[a][b] * p[b] for b in range(3)) + T[a][3] - t[a] for a in range(3)]
        m = [sum(R[b][a] * w[b] for b in range(3)) for a in range(3)]
        for k, v in zip(ix, m):
            r[k] = v
        if isx:
            s = [r[k] for k in isx]
            ws = [sum(T[a][b] * s[b] for b in range(3)) for a in range(3)]
            ms = [sum(R[b][a] * ws[b] for b in range(3)) for a in range(3)]
            for k, v in zip(isx, ms):
                r[k] = v
    write_pcd(f'{d}/cand.pcd', header, fmt, rows)
    xs = [r[ix[0]] for r in rows]
    ys = [r[ix[1]] for r in rows]
    run([f'{BIN}/fitvox', '--config', f'{P}/fitvox-tile.ini'] + opts('FITVOX') +
        ['--pcd-encoding', 'binary', '-i', f'{d}/cand.pcd', '-o', f'{d}/samples-raw.pcd'], cpu)
    # The dense entries' samples carry rangetrace's label (1: the vehicle), and verify takes a
    # labelled surface's label-1 samples as the model; a tile's candidate has no label (fitvox
    # writes 0). So label 1 for the samples inside the vehicle's true footprint (model frame,
    # 0.1 m margin) and above the flat ground (z > 0.05 m), 0 for the rest (the ground around).
    lx, ly = truth['size'][0] / 2 + 0.1, truth['size'][1] / 2 + 0.1
    header, sfields, sfmt, srows = read_pcd(f'{d}/samples-raw.pcd')
    sx, sy, sz, sl = (sfields.index(k) for k in ('x', 'y', 'z', 'label'))
    for r in srows:
        r[sl] = 1 if abs(r[sx]) <= lx and abs(r[sy]) <= ly and r[sz] > 0.05 else 0
    write_pcd(f'{d}/samples.pcd', header, sfmt, srows)
    os.remove(f'{d}/samples-raw.pcd')
    labelled = sum(r[sl] for r in srows)
    run([f'{BIN}/cocone', '--config', f'{P}/cocone.ini'] + opts('COCONE') + ['-i', f'{d}/samples.pcd', '-o', f'{d}/mesh.ply'],
        cpu)
    run([f'{BIN}/ncut', '--config', f'{P}/ncut.ini'] + opts('NCUT') +
        ['--seed', str(int(seed) * 7 + 1), '-i', f'{d}/mesh.ply', '-o', f'{d}/segments.json', '--colored',
         f'{d}/segments.ply'], cpu)
    nseg = len(json.load(open(f'{d}/segments.json'))['segments'])
    info = {'model': model, 'seed': seed, 'level': level, 'spacing_mm': spacing, 'candidates': len(index['candidates']),
            'candidate': c['id'], 'density': c['density'], 'points': len(rows), 'object_points': c.get('object_points'),
            'cand_length': c['length'], 'true_length': truth['size'][0], 'x_extent_model': [min(xs), max(xs)],
            'y_extent_model': [min(ys), max(ys)], 'heading_deg': pose['heading'],
            'offset_m': math.hypot(c['centre'][0] - pose['x'], c['centre'][1] - pose['y']), 'segments': nseg, 'samples': len(srows), 'samples_label1': labelled,
            'options': opts('FITVOX') + opts('COCONE') + opts('NCUT'), 'cpu_s': cpu, 'wall_s': time.time() - wall0}
    json.dump(info, open(f'{d}/entry.json', 'w'), indent=1)
    os.remove(f'{d}/scan.pcd')
    print(f'{model} s{seed} d{level}: {len(index["candidates"])} cands, {c["id"]} density {c["density"]:.0f}, '
          f'{len(rows)} pts, length {c["length"]:.2f}/{truth["size"][0]:.2f}, x {min(xs):.2f}..{max(xs):.2f}, '
          f'{nseg} segments, {labelled}/{len(srows)} samples on the vehicle, cpu {sum(cpu.values()):.1f}s')


if __name__ == '__main__':
    main()
