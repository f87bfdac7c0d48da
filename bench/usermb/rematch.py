#!/usr/bin/env python3
"""rematch.py LEVEL_DIR VARIANT MODELBASE RES [MODEL_DENSITY] : the model chain's last stages again
on a density-ladder level's candidates with another modelbase (docs/decisions/user-modelbase.md
§9, a study; not part of any make rule).

LEVEL_DIR is a ladder rung as `make density` left it (out/density/d<LEVEL>: <cover>/tile-<seed>/
noise-0 runs with cands/, cands.mk, class.json and the model chain's samples.pcd, segments.json).
For every model-level candidate of the run's plan: gmatch and verify exactly as mk/scenes.mk's
cand_rule (share/params/gmatch.ini, verify.ini, the plan's transform) but with --modelbase
MODELBASE, into cands/<id>/match-VARIANT.json and verdict-VARIANT.json (an empty file when a stage
fails, as stagerun --record-failure); then collect as the scene experiment's (calibration.ini)
with --verdict-name verdict-VARIANT.json into detections-VARIANT.json; then score over the rung's
tiles.txt into RES/VARIANT/score.json (+ CSVs). class.json is the rung's own (unchanged).

MODEL_DENSITY (optional): re-plan every run with `collect --plan --model-density MODEL_DENSITY`;
a candidate the rung left at the class level that the new plan sends to the model chain runs
fitvox | cocone | ncut with the new plan's density-rule options into cands/<id>/lo-*.{pcd,ply,json}
(the rung's own candidates keep their files). Prints (and writes RES/VARIANT/cpu.json) the CPU
seconds of each tool, as os.times() counts the children.
MERGE_MB=<dir> (environment): MODELBASE holds several entries per model, named <model>.<tag>;
each verdict's model (and its hypotheses' models) is renamed <model> before collect, which reads
MERGE_MB's <model>.pcd for the footprints.
BIN (default build/bin) names the tools."""
import json
import os
import re
import subprocess
import sys

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get('BIN', f'{SRC}/build/bin')
P = f'{SRC}/share/params'
CPU = {}


def run(cmd, out=None):
    t0 = os.times()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t1 = os.times()
    k = os.path.basename(cmd[0])
    CPU[k] = CPU.get(k, 0) + t1.children_user - t0.children_user + t1.children_system - t0.children_system
    if r.returncode != 0 and out:
        open(out, 'w').close()
    return r.returncode == 0


def plan_of(text):
    v = dict(re.findall(r'^(\S+) := (.*)$', text, re.M))
    key = next(k[:-len('_CANDS')] for k in v if k.endswith('_CANDS'))
    return key, v


def main():
    level_dir, variant, mb, res = sys.argv[1:5]
    model_density = sys.argv[5] if len(sys.argv) > 5 else None
    manifest = open(f'{level_dir}/tiles.txt').read().split('\n')
    lines = []
    for line in manifest:
        if not line.strip():
            continue
        det, truth, noise, cover = line.split()
        run_dir = os.path.dirname(det)
        key, v = plan_of(open(f'{run_dir}/cands.mk').read())
        cands = v[f'{key}_CANDS'].split()
        model = {c for c in cands if v.get(f'{key}_LEVEL_{c}', 'model') != 'class'}
        files = {c: ('samples.pcd', 'segments.json') for c in model}
        if model_density:
            run([f'{BIN}/collect', '-i', f'{run_dir}/cands/index.json', '--plan', f'{run_dir}/cands-{variant}.mk',
                 '--plan-key', key, '--model-density', model_density])
            _, w = plan_of(open(f'{run_dir}/cands-{variant}.mk').read())
            for c in cands:
                if c in model or w.get(f'{key}_LEVEL_{c}', 'model') == 'class':
                    continue
                d = f'{run_dir}/cands/{c}'
                os.makedirs(d, exist_ok=True)
                opt = lambda s: w.get(f'{key}_{s}_{c}', '').split()
                if not os.path.exists(f'{d}/lo-segments.json'):
                    run([f'{BIN}/fitvox', '--config', f'{P}/fitvox-tile.ini'] + opt('FITVOX') +
                        ['--pcd-encoding', 'binary_compressed', '-i', f'{run_dir}/cands/{c}.pcd', '-o',
                         f'{d}/lo-samples.pcd'], f'{d}/lo-samples.pcd')
                    run([f'{BIN}/cocone', '--config', f'{P}/cocone.ini'] + opt('COCONE') +
                        ['-i', f'{d}/lo-samples.pcd', '-o', f'{d}/lo-mesh.ply'], f'{d}/lo-mesh.ply')
                    run([f'{BIN}/ncut', '--config', f'{P}/ncut.ini'] + opt('NCUT') +
                        ['--seed', '1', '-i', f'{d}/lo-mesh.ply', '-o', f'{d}/lo-segments.json', '--colored',
                         f'{d}/lo-segments.ply'], f'{d}/lo-segments.json')
                files[c] = ('lo-samples.pcd', 'lo-segments.json')
        for c, (samples, segments) in sorted(files.items()):
            d = f'{run_dir}/cands/{c}'
            match, verdict = f'{d}/match-{variant}.json', f'{d}/verdict-{variant}.json'
            if run([f'{BIN}/gmatch', '--config', f'{P}/gmatch.ini', '-i', f'{d}/{segments}', '--modelbase', mb, '-o', match],
                   match):
                run([f'{BIN}/verify', '--config', f'{P}/verify.ini', '-i', match, '--points', f'{d}/{samples}', '--segments',
                     f'{d}/{segments}', '--modelbase', mb, '--transform', v[f'{key}_TRANSFORM_{c}'], '-o', verdict], verdict)
            else:
                open(verdict, 'w').close()
            if os.environ.get('MERGE_MB') and os.path.getsize(verdict):
                text = open(verdict).read()
                text = re.sub(r'"(model|name)": "([A-Za-z0-9_-]+)\.[A-Za-z0-9_-]+"', r'"\1": "\2"', text)
                open(verdict, 'w').write(text)
        out = f'{run_dir}/detections-{variant}.json'
        if not run([f'{BIN}/collect', '-i', f'{run_dir}/cands/index.json', '--verdict-name', f'verdict-{variant}.json', '-o', out,
                    '--modelbase', os.environ.get('MERGE_MB') or mb, '--calibration', f'{P}/calibration.ini']):
            raise SystemExit(f'collect failed on {run_dir}')
        lines.append(f'{out} {truth} {noise} {cover}')
    os.makedirs(f'{res}/{variant}', exist_ok=True)
    open(f'{level_dir}/tiles-{variant}.txt', 'w').write('\n'.join(lines) + '\n')
    subprocess.run([f'{BIN}/score', '--tiles', f'{level_dir}/tiles-{variant}.txt', '--model-classes',
                    f'{SRC}/share/models/classes.csv', '-o', f'{res}/{variant}/score.json', '--csv', f'{res}/{variant}/'],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    json.dump({k: round(x, 2) for k, x in CPU.items()}, open(f'{res}/{variant}/cpu.json', 'w'))
    print(variant, level_dir, 'cpu', {k: round(x, 1) for k, x in CPU.items()}, 'runs', len(lines))


if __name__ == '__main__':
    main()
