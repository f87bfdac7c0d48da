#!/usr/bin/env bash
# detect on rangetrace forest tiles (issue 13's scene recipes): the table "On rangetrace tiles"
# of docs/decisions/detect.md. Per cover level (light: trees 200, hide 0; medium: the recipe's
# 600 / 2; dense: 1200 / 4), pixel spacing and seed, one tile of share/scenes/forest.scene is
# rendered once (cached in WORK), noised with addnoise at 0, 8 and 32 mm, and run through
# detect with its defaults plus DETECT_ARGS. Prints one row per cover x noise x spacing:
# recall, candidates per vehicle, true candidates per vehicle (candidates whose object holds
# mostly one labelled vehicle), detect wall seconds per tile.
#   bench/detect/tiles.sh [build dir] [work dir] [seeds] [spacings]
#   e.g. DETECT_ARGS="--min-planarity 0" TAG=off bench/detect/tiles.sh build /tmp/tiles "101 102 103 104" "80 40"
# TAG names the detect runs (cands-TAG-N/), COVERS limits the cover levels (light medium dense).
# bench/detect/shape.py WORK TAG then gives the shape test's feature distributions.
# Seeds 1-12 are the scene experiment's (issue 16): do not develop on them.
set -euo pipefail
build=${1:-build} work=${2:-/tmp/detect-tiles} seeds=${3:-101 102 103 104} spacings=${4:-80 40}
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$build/bin
tag=${TAG:-default}
mkdir -p "$work"
cover_keys() {  # cover -> "trees hide"
  case $1 in light) echo "200 0" ;; medium) echo "600 2" ;; dense) echo "1200 4" ;; esac
}
for sp in $spacings; do
  for cover in ${COVERS:-light medium dense}; do
    read -r trees hide <<<"$(cover_keys $cover)"
    recipe=$work/$cover-$sp.scene
    sed -e "s/^trees = .*/trees = $trees/" -e "s/^hide = .*/hide = $hide/" -e "s/^spacing = .*/spacing = ${sp}mm/" \
      "$src/share/scenes/forest.scene" >"$recipe.tmp" && mv "$recipe.tmp" "$recipe"
    for seed in $seeds; do
      d=$work/$cover-$sp-$seed
      mkdir -p "$d"
      if [ ! -s "$d/truth.json" ]; then
        nice "$bin/rangetrace" -q --scene "$recipe" --seed "$seed" -o "$d/scan.pcd" --truth "$d/truth.json"
      fi
      for n in 0 8 32; do
        if [ ! -s "$d/scan-$n.pcd" ]; then
          if [ "$n" = 0 ]; then cp "$d/scan.pcd" "$d/scan-$n.pcd"
          else nice "$bin/addnoise" -q --sigma "${n}mm" --seed "$seed" -i "$d/scan.pcd" -o "$d/scan-$n.pcd"; fi
        fi
        out=$d/cands-$tag-$n
        # shellcheck disable=SC2086
        /usr/bin/time -f '%e %M' -o "$d/time-$tag-$n.txt" \
          "$bin/detect" -q --no-classes ${DETECT_ARGS:-} -i "$d/scan-$n.pcd" -o "$out"
      done
    done
  done
done
python3 - "$work" "$tag" "$spacings" "$seeds" "${COVERS:-light medium dense}" <<'PY'
import json, sys
work, tag, spacings, seeds, covers = sys.argv[1], sys.argv[2], sys.argv[3].split(), sys.argv[4].split(), sys.argv[5].split()
print("| cover | noise | spacing | vehicles | mean canopy cover | recall | candidates / vehicle | true candidates / vehicle | detect s / tile | peak MB |")
print("|---|---|---|---|---|---|---|---|---|---|")
for sp in spacings:
    for cover in covers:
        for n in ("0", "8", "32"):
            veh = rec = cands = true = 0
            cov = []; secs = []; mem = []
            for seed in seeds:
                d = f"{work}/{cover}-{sp}-{seed}"
                truth = json.load(open(f"{d}/truth.json"))
                idx = json.load(open(f"{d}/cands-{tag}-{n}/index.json"))
                vs = truth["vehicles"]
                veh += len(vs)
                cov += [v["canopy_cover"] for v in vs]
                covered = {i["instance"] for i in idx.get("instances", []) if i["candidates"]}
                rec += sum(1 for v in vs if v["instance"] in covered)
                cands += len(idx["candidates"])
                true += sum(1 for c in idx["candidates"] if c.get("truth"))
                t, m = open(f"{d}/time-{tag}-{n}.txt").read().split()[-2:]
                secs.append(float(t)); mem.append(int(m) / 1024)
            print(f"| {cover} | {n} mm | {sp} mm | {veh} | {sum(cov)/len(cov):.2f} | {100*rec/veh:.0f}% ({rec}/{veh}) | "
                  f"{cands/veh:.2f} | {true/veh:.2f} | {sum(secs)/len(secs):.1f} | {max(mem):.0f} |")
PY
