#!/usr/bin/env python3
"""loo.py BIN SRC RUNS VARIANT... (bench/openset/loo.sh): classify every candidate of each
left-out run with classify-sim.ini + the variant's options (VARIANT = name=opt,opt), print each
run's answer and, per variant and spacing, the class right (answer's class or group = the
instance's class) with its Wilson 95% interval, the none and the wrong answers; then the same
over the instances whose class has another modelbase instance (the others cannot be right when
only the modelbase's classes are answered)."""
import collections
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rates import rate  # noqa: E402


def main():
    bin_, src, runs_file = sys.argv[1:4]
    variants = [v.split('=', 1) for v in sys.argv[4:]]
    runs = [line.split() for line in open(runs_file)]
    per_class = collections.Counter(cls for name, cls in {(r[0], r[1]) for r in runs})
    tally = collections.defaultdict(collections.Counter)
    for name, cls, d, mb in runs:
        spacing = d.rsplit('-', 1)[1]
        cands = json.load(open(f'{d}/cands/index.json'))['candidates']
        for vname, args in variants:
            answer = {}
            for c in cands:
                out = f'{d}/cands/{c["id"]}.{vname}.json'
                subprocess.run([f'{bin_}/classify', '-q', '--config', f'{src}/share/params/classify-sim.ini',
                                '-i', f'{d}/cands/{c["id"]}.pcd', '--index', f'{d}/cands/index.json',
                                '--modelbase', mb, '--model-classes', f'{src}/share/models/classes.csv',
                                '-o', out] + (args.split(',') if args else []), check=True)
                v = json.load(open(out))
                if not answer or (v.get('class') and not answer.get('class')):
                    answer = v
            got, group = answer.get('class') or 'none', answer.get('group') or ''
            right = cls in (got, group)
            print(f'{vname:8s} {spacing:6s} {name:22s} {cls:7s} -> {got:14s} {group:8s} {"right" if right else ""}')
            for scope in ('all', 'shared') if per_class[cls] > 1 else ('all',):
                t = tally[(vname, spacing, scope)]
                t['n'] += 1
                t['right'] += right
                t['none'] += got == 'none'
    for key in sorted(tally):
        t = tally[key]
        print(f'{key[0]:8s} {key[1]:6s} {key[2]:6s} right {rate(t["right"], t["n"])}  none {t["none"]}  '
              f'wrong {t["n"] - t["right"] - t["none"]}')


if __name__ == '__main__':
    main()
