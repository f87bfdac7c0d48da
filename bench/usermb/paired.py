#!/usr/bin/env python3
"""paired.py BASE_MATCHES.csv VARIANT_MATCHES.csv ... : per vehicle (tile, instance), the model-level
right answers of the base modelbase and of each variant (score's matches.csv): both, base only
(lost), variant only (gained); and the model-level false alarms of each (docs/decisions/
user-modelbase.md §9)."""
import csv
import sys


def right(path):
    rows = list(csv.DictReader(open(path)))
    r = {(x['tile'], x['instance']) for x in rows if x['level'] == 'model' and x['outcome'] == 'right'}
    fa = sum(1 for x in rows if x['level'] == 'model' and x['outcome'] not in ('right',))
    return r, fa


def main():
    base, fa0 = right(sys.argv[1])
    for p in sys.argv[2:]:
        v, fa = right(p)
        print(f'{p}: right {len(v)} (base {len(base)}); both {len(base & v)}, lost {len(base - v)}, gained {len(v - base)};'
              f' other model-level outcomes {fa} (base {fa0})')


if __name__ == '__main__':
    main()
