#!/usr/bin/env python3
"""report.py RES [COVER] : the table of docs/decisions/user-modelbase.md §9 from rematch.py's
scores under RES/d<LEVEL>/<VARIANT>/ (score.json, matches.csv, cpu.json), COVER all (default),
light or medium. Per level and modelbase: model-level answers, model right / vehicles,
identified / found at the model level, the vehicles right at the model level against the dense
modelbase's (lost, gained), found at any level, class right / found, false alarms (model level;
any level), gmatch + verify CPU-s of the level. Wilson 95% intervals (table.py)."""
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table import wilson  # noqa: E402

ROWS = [('d50', 'dense'), ('d50', 'matched'), ('d50', 'mixed'), ('d50', 'seeds'), ('d50', 'unionown'),
        ('d50', 'dense-md20'), ('d50', 'matched-md20'), ('d50', 'mixed-md20'), ('d50', 'mixseeds-md20'),
        ('d50', 'union-md20'), ('d50', 'unionown-md20'),
        ('d100', 'dense'), ('d100', 'matched'), ('d100', 'mixed'), ('d100', 'seeds'), ('d100', 'mixseeds'),
        ('d100', 'union'), ('d100', 'unionown'), ('d100', 'mixedB'), ('d100', 'seedsB'), ('d100', 'unionownB'), ('d100', 'dense-md20'),
        ('d200', 'dense'), ('d200', 'matched'), ('d200', 'mixed'), ('d200', 'seeds'), ('d200', 'mixseeds'),
        ('d200', 'union'), ('d200', 'unionown'), ('d200', 'mixedB'), ('d200', 'seedsB'), ('d200', 'unionownB'), ('d200', 'dense-md20')]


def right(path, cover):
    return {(x['tile'], x['instance']) for x in csv.DictReader(open(path))
            if x['level'] == 'model' and x['outcome'] == 'right'}


def main():
    res = sys.argv[1]
    cover = sys.argv[2] if len(sys.argv) > 2 else 'all'
    covers = None
    print('| level | modelbase | vehicles | model-level answers | model right / vehicles | identified / model-level found |'
          ' vs dense: lost, gained | found any level | class right / found | FA model | FA any | gmatch + verify CPU-s |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|')
    for level, variant in ROWS:
        d = f'{res}/{level}/{variant}'
        if not os.path.exists(f'{d}/score.json'):
            continue
        score = json.load(open(f'{d}/score.json'))
        s = next(x for x in score['summary'] if x['cover'] == cover and x['noise_mm'] == 'all')
        if covers is None:
            covers = {}
        base = f"{res}/{level}/{'dense-md20' if variant.endswith('md20') else 'dense'}"
        tiles = [t['cover'] if isinstance(t, dict) and 'cover' in t else None for t in score.get('tiles', [])]
        keep = lambda k: cover == 'all' or (tiles and tiles[int(k[0])] == cover)
        b = {k for k in right(f'{base}/matches.csv', cover) if keep(k)}
        v = {k for k in right(f'{d}/matches.csv', cover) if keep(k)}
        cpu = json.load(open(f'{d}/cpu.json')) if os.path.exists(f'{d}/cpu.json') else {}
        fa_any = round(s['false_alarms_any_level_per_ha'] * s['area_ha'])
        found = s['found_any_level']
        print(f"| {level}{' (model level from 20)' if variant.endswith('md20') else ''} | {variant.replace('-md20', '')} | "
              f"{s['true']} | {s['tp'] + s['fp']} | {wilson(s['identified'], s['true'])} | {wilson(s['identified'], s['tp'])} | "
              f"{'–' if d == base else f'{len(b - v)}, {len(v - b)}'} | {wilson(found, s['true'])} | "
              f"{wilson(s['class_right_any_level'], found)} | {s['fp']} | {fa_any} | "
              f"{cpu.get('gmatch', 0) + cpu.get('verify', 0):.1f} |")


if __name__ == '__main__':
    main()
