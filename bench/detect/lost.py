#!/usr/bin/env python3
"""Where the lost vehicles of a class-level run went, and what the false alarms fell on.

  lost.py OUT TAG COVER

OUT is a bench/detect/classlevel.sh output (score.json, tiles.txt); TAG the candidates' tag
(RUN/cands-TAG). For every vehicle of cover COVER that score counts missed (neither a model nor a
class answer within reach): the candidates holding >= 10% of its points (bench/detect/pieces.py's
count inside each crop box), best first, with the candidate's size, the other vehicles it holds,
classify's answer or refusal (class.json `reason` and `detail`) and three of its cues
(late_returns, echo_widening, ground_through). No line under a vehicle: no candidate holds 10%
of it. Then every false alarm (any cover) with the vehicles its candidate holds (an answer off its
vehicle's centre holds one; clutter or vegetation none). Truth is read only here (evaluation).
(docs/decisions/density-ladder.md, "Light cover at 25 and 50 pulses/m²", stop 63.)
"""
import json, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pieces import held_by  # noqa: E402


def main():
    out, tag, cover = sys.argv[1], sys.argv[2], sys.argv[3]
    s = json.load(open(os.path.join(out, "score.json")))
    tiles = [line.split() for line in open(os.path.join(out, "tiles.txt"))]
    for ti, (_, truth, _, cov) in enumerate(tiles):
        run = os.path.dirname(truth)
        name = os.path.basename(run)
        ms = [m for m in s["matches"] if m["tile"] == ti]
        lost = [m for m in ms if m["outcome"] == "missed" and cov == cover]
        fa = [m for m in ms if m["outcome"] == "false_alarm"]
        if not lost and not fa:
            continue
        idx = json.load(open(os.path.join(run, "cands-" + tag, "index.json")))
        tr = json.load(open(truth))
        total, held = held_by(idx, run)

        def verdict(cid):
            p = os.path.join(run, "cands-" + tag, cid, "class.json")
            return json.load(open(p)) if os.path.exists(p) else None

        for m in lost:
            i = m["instance"]
            v = [x for x in tr["vehicles"] if x["instance"] == i][0]
            tot = total.get(i, 0)
            share = sorted(((h.get(i, 0) / tot if tot else 0, k) for k, h in enumerate(held)), reverse=True)
            print(f"{name} {v['model']}/{i} canopy {v.get('canopy_cover', 0):.2f} "
                  f"size {v['size'][0]:.2f} x {v['size'][1]:.2f} x {v['size'][2]:.2f} m, {tot} points")
            for sh, k in share[:3]:
                if sh < 0.1:
                    break
                c = idx["candidates"][k]
                r = verdict(c["id"])
                f = r["features"] if r else {}
                others = {o: round(n / total[o], 2) for o, n in held[k].items()
                          if o != i and total[o] and n / total[o] > 0.1}
                answer = (f"{r['level']} {r.get('class')}" if r and r.get("class") else
                          (f"{r['reason']}: {r['detail']}" if r else "no class.json"))
                print(f"    {c['id']} holds {sh:.2f}, {c['length']:.2f} x {c['width']:.2f} x {c['height']:.2f} m, "
                      f"other vehicles {others or '-'} -> {answer} | late {f.get('late_returns')} "
                      f"echo {f.get('echo_widening')} ground_through {f.get('ground_through')}")
        for m in fa:
            k = [j for j, c in enumerate(idx["candidates"]) if c["id"] == m["candidate"]]
            on = {o: round(n / total[o], 2) for o, n in held[k[0]].items() if total[o] and n / total[o] > 0.1} if k else {}
            c = idx["candidates"][k[0]] if k else {"length": 0, "width": 0, "height": 0}
            print(f"false alarm {name} {m['candidate']} {m['class'] or m['model']} at ({m['x']:.1f}, {m['y']:.1f}), "
                  f"{c['length']:.2f} x {c['width']:.2f} x {c['height']:.2f} m, on vehicles {on or '-'}")


if __name__ == "__main__":
    main()
