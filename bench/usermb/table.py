#!/usr/bin/env python3
"""table.py LABEL=SCORE.json ... : one markdown row per score and cover (all, light, medium) of
the study in docs/decisions/user-modelbase.md §9, every rate with its count and a 95% Wilson
interval. model right = model-level detections naming the vehicle's model / vehicles; identified
= of the vehicles found at the model level; found = at any level within 1.5 m; class right = of
the found at any level; FA = detections on no vehicle (model level; any level), counts."""
import json
import math
import sys


def wilson(k, n, z=1.959964):
    if n == 0:
        return '–'
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return f'{k}/{n} = {100 * p:.0f}% [{100 * max(0, c - h):.0f}, {100 * min(1, c + h):.0f}]'


def main():
    print('| level / modelbase | cover | vehicles | model-level answers (right + FA) | model right / vehicles | identified / model-level found |'
          ' found any level | class right / found | FA model | FA any | precision any level |')
    print('|---|---|---|---|---|---|---|---|---|---|---|')
    for arg in sys.argv[1:]:
        label, path = arg.split('=', 1)
        for s in json.load(open(path))['summary']:
            if s['noise_mm'] != 'all':
                continue
            fa_any = round(s['false_alarms_any_level_per_ha'] * s['area_ha'])
            found = s['found_any_level']
            print(f"| {label} | {s['cover']} | {s['true']} | {s['tp'] + s['fp']} | {wilson(s['identified'], s['true'])} | "
                  f"{wilson(s['identified'], s['tp'])} | {wilson(found, s['true'])} | {wilson(s['class_right_any_level'], found)} | "
                  f"{s['fp']} | {fa_any} | {wilson(found, found + fa_any)} |")


if __name__ == '__main__':
    main()
