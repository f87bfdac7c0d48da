#!/usr/bin/env bash
# detect's pieces on the density ladder's scenes (docs/decisions/detect.md §10): per level, cover
# and seed, the scene experiment's recipe (mk/scenes.mk, as the ladder writes it: out/density/
# d<level>/<cover>/tile-<seed>/recipe.scene, or RECIPES=DIR holding <cover>-<seed>.scene) at the
# level's pixel spacing (mk/density.mk: sqrt(4.45 / level)), rendered once into WORK with the
# render seed make uses (cksum of scenes/<cover>/<seed>); then detect with its defaults plus
# DETECT_ARGS into cands-TAG/, and bench/detect/pieces.py: vehicles whole (one candidate holding
# >= 80%), merged with a neighbour, in pieces, missed.
#   bench/detect/pieces.sh [build dir] [work dir] [levels] [seeds] [covers]
#   e.g. TAG=old DETECT_ARGS="--min-split-share 0 --merge-gap 0" bench/detect/pieces.sh build /tmp/pieces "25 100" "101 102" light
# A recipe with a `sensor =` line (the sensor ladder's, density-ladder.md) is rendered as it is
# (its density is its sensor keys: the level names the directory only) and detect gets the
# trajectory rangetrace wrote beside the scan (--trajectory), as the ladder's runs do.
# Seeds 1-8, 21-23 and 31-34 are experiments' seeds: do not develop on them.
# Each run runs detect again (it is timed) and replaces cands-TAG/ whole: what bench/detect/
# classlevel.sh wrote inside it (class.json) goes with it; use a new TAG to keep both.
set -euo pipefail
build=${1:-build} work=${2:-/tmp/detect-pieces} levels=${3:-25 100} seeds=${4:-101 102} covers=${5:-light}
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$build/bin
tag=${TAG:-default}
recipes=${RECIPES:-}
mkdir -p "$work"
runs=()
for lv in $levels; do
  mm=$(awk -v l="$lv" 'BEGIN { printf "%d", int(1000 * sqrt(4.45 / l) + 0.5) }')
  for cover in $covers; do
    for seed in $seeds; do
      d=$work/d$lv-$cover-$seed
      mkdir -p "$d"
      if [ ! -s "$d/truth.json" ]; then
        base=${recipes:+$recipes/$cover-$seed.scene}
        [ -n "$base" ] || base=$(ls "$src"/out/density/d*/"$cover"/tile-"$seed"/recipe.scene 2>/dev/null | head -1)
        [ -s "$base" ] || { echo "pieces.sh: no recipe for $cover seed $seed (RECIPES=DIR)" >&2; exit 1; }
        if grep -q '^sensor = ' "$base"; then cp "$base" "$d/recipe.scene"; else
          sed "s/^spacing = .*/spacing = ${mm}mm/" "$base" >"$d/recipe.scene"
        fi
        rseed=$(printf '%s' "scenes/$cover/$seed" | cksum | cut -d' ' -f1)
        nice "$bin/rangetrace" -q --scene "$d/recipe.scene" --seed "$rseed" --threads 1 \
          -o "$d/scan.pcd" --truth "$d/truth.json"
      fi
      traj=()
      [ ! -s "$d/scan.traj" ] || traj=(--trajectory "$d/scan.traj")
      # shellcheck disable=SC2086
      /usr/bin/time -f '%e %U %S %M' -o "$d/time-$tag.txt" \
        "$bin/detect" -q --no-classes ${DETECT_ARGS:-} "${traj[@]}" -i "$d/scan.pcd" -o "$d/cands-$tag"
      runs+=("$d")
    done
  done
done
python3 "$src/bench/detect/pieces.py" --tag "$tag" ${LIST:+--list} "${runs[@]}"
