#!/usr/bin/env python3
"""modelbases.py ENT DENSE OUT : the study's modelbases of one level (docs/decisions/user-modelbase.md
§9) from bench/usermb/entries.py's entries under ENT (<model>-s<seed>/) and the dense modelbase
DENSE (out/modelbase):
  OUT/matched/<model>.{json,pcd}      one render per model: of its seeds, the one with the median
                                      number of candidate points, among the seeds whose crop gave one
                                      candidate (detect did not split the vehicle; at 50 points/m²
                                      the tank's candidate is its hull, 6.9 m of 9.45: the gun is
                                      not resolved, and that is what a tile candidate shows too)
  OUT/mixed/<model>.{json,pcd}        that render's graph, the dense entry's surface
  OUT/seeds/<model>.s<seed>.{json,pcd} every seed's graph and surface (rematch.py MERGE_MB)
  OUT/mixseeds/<model>.s<seed>.{json,pcd} every seed's graph, the dense entry's surface
  OUT/union/<model>.dense.json, <model>.s<seed>.json (+ .pcd each: the dense entry's surface)
                                      the dense graph beside every seed's graph
  OUT/unionown/<model>.dense.{json,pcd} (the dense entry), <model>.s<seed>.{json,pcd} (every seed's own)
Hard links. Prints the choice."""
import collections
import glob
import json
import os
import sys


def link(src, dst):
    if os.path.exists(dst):
        os.remove(dst)
    os.link(src, dst)


def main():
    ent, dense, out = sys.argv[1:4]
    for k in ('matched', 'mixed', 'seeds', 'mixseeds', 'union', 'unionown'):
        os.makedirs(f'{out}/{k}', exist_ok=True)
    by_model = collections.defaultdict(list)
    for f in sorted(glob.glob(f'{ent}/*/entry.json')):
        e = json.load(open(f))
        e['dir'] = os.path.dirname(f)
        if e.get('candidate') is None or e['candidates'] != 1:
            print(f'{f}: {e.get("candidates", 0)} candidates (split or none), left out')
            continue
        by_model[e['model']].append(e)
    for model, es in sorted(by_model.items()):
        es.sort(key=lambda e: e['points'])
        pick = es[(len(es) - 1) // 2]
        link(f"{pick['dir']}/segments.json", f'{out}/matched/{model}.json')
        link(f"{pick['dir']}/samples.pcd", f'{out}/matched/{model}.pcd')
        link(f"{pick['dir']}/segments.json", f'{out}/mixed/{model}.json')
        link(f'{dense}/{model}.pcd', f'{out}/mixed/{model}.pcd')
        link(f'{dense}/{model}.json', f'{out}/union/{model}.dense.json')
        link(f'{dense}/{model}.pcd', f'{out}/union/{model}.dense.pcd')
        link(f'{dense}/{model}.json', f'{out}/unionown/{model}.dense.json')
        link(f'{dense}/{model}.pcd', f'{out}/unionown/{model}.dense.pcd')
        for e in es:
            for k in ('mixseeds', 'union'):
                link(f"{e['dir']}/segments.json", f"{out}/{k}/{model}.s{e['seed']}.json")
                link(f'{dense}/{model}.pcd', f"{out}/{k}/{model}.s{e['seed']}.pcd")
            link(f"{e['dir']}/segments.json", f"{out}/seeds/{model}.s{e['seed']}.json")
            link(f"{e['dir']}/samples.pcd", f"{out}/seeds/{model}.s{e['seed']}.pcd")
            link(f"{e['dir']}/segments.json", f"{out}/unionown/{model}.s{e['seed']}.json")
            link(f"{e['dir']}/samples.pcd", f"{out}/unionown/{model}.s{e['seed']}.pcd")
        print(f"{model}: seed {pick['seed']} ({pick['points']} points, density {pick['density']:.0f}, {pick['segments']} segments;"
              f" seeds {[(e['seed'], e['points'], e['segments']) for e in es]})")


if __name__ == '__main__':
    main()
