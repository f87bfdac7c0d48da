#!/usr/bin/env bash
# classify's outline gates on simulated development tiles (docs/decisions/classify.md §16): the
# scene experiment's recipe (mk/scene-recipe.mk, the same clutter rule and seed keys) for
# development seeds only, rendered, detected, then classify (classify-sim.ini, as the scene
# experiment runs it) on every candidate with each variant, and bench/classify/outline.py to
# count vehicles and clutter kinds answered as vehicles.
#   bench/classify/outline.sh OUT_DIR
#   (BIN=build/bin; SEEDS="101 102 103 104 105 106"; COVERS="light medium dense";
#    EXTRA_TILES="name:recipe.scene:seed ..." more tiles of your own; MODELBASE=dir CLASSES=csv
#    as make tile passes them; VARIANTS="name:extra classify args" ..., default: the ini's
#    outline gates, every gate off, and the ini's with --min-notch 0.05; outline.py compares the
#    first two)
# Never the experiment's seeds (1-8) or the open set's (31-34): development seeds only.
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 OUT_DIR" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
out=$1
mkdir -p "$out"
ini=${INI:-$src/share/params/classify-sim.ini}
seeds=${SEEDS:-"101 102 103 104 105 106"}
covers=${COVERS:-"light medium dense"}
variants=${VARIANTS:-"on: off:--max-notch=0,--drawbar-width=0 notch:--min-notch=0.05"}
mb_args=()
[ -z "${MODELBASE:-}" ] || mb_args=(--modelbase "$MODELBASE" --model-classes "${CLASSES:-$src/share/models/classes.csv}")
# The scene experiment's recipes, written by the one copy outside make (bench/detect/recipes.sh).
bash "$src/bench/detect/recipes.sh" "$out/recipes" "$seeds"
tiles=()
for c in $covers; do
  for s in $seeds; do
    d=$out/tiles/$c-$s
    mkdir -p "$d"
    cp "$out/recipes/$c-$s.scene" "$d/recipe.scene"
    echo "$d $(printf '%s' "scenes/$c/$s" | cksum | awk '{ print $1 }')"
    tiles+=("$d")
  done
done >"$out/tiles.txt"
for t in ${EXTRA_TILES:-}; do
  IFS=: read -r name recipe seed <<<"$t"
  d=$out/tiles/$name
  mkdir -p "$d"
  cp "$recipe" "$d/recipe.scene"
  echo "$d $seed" >>"$out/tiles.txt"
done
while read -r d seed; do
  [ -s "$d/truth.json" ] || "$bin/rangetrace" -q --scene "$d/recipe.scene" --seed "$seed" --threads 2 \
    -o "$d/scan.pcd" --truth "$d/truth.json"
  [ -s "$d/cands/index.json" ] || "$bin/detect" -q --no-classes -i "$d/scan.pcd" -o "$d/cands"
  rm -f "$d/scan.pcd"
done <"$out/tiles.txt"
for v in $variants; do
  name=${v%%:*}
  args=${v#*:}
  args=${args//,/ }
  args=${args//=/ }
  while read -r d seed; do
    for p in "$d/cands"/*.pcd; do
      id=$(basename "$p" .pcd)
      mkdir -p "$d/$name"
      echo "$bin/classify -q --config $ini $args ${mb_args[*]} -i $p --index $d/cands/index.json -o $d/$name/$id.json"
    done
  done <"$out/tiles.txt" | xargs -P2 -I{} sh -c '{}'
done
python3 "$src/bench/classify/outline.py" "$out" $(for v in $variants; do echo "${v%%:*}"; done)
