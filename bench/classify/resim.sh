#!/usr/bin/env bash
# Re-classifies the candidates of finished simulated tiles with classify's parameters INI (plus
# options ARGS) and collects and scores them apart from the run's own answers: development only
# (docs/decisions/classify.md §22). Each candidate's answer goes beside its class.json as
# class-NAME.json (as SCENE_CLASSIFY_ABLATION's class-ablation.json does); the model chain's
# verdicts are the run's.
#
#   bench/classify/resim.sh BIN WORK NAME INI "ARGS" MODELBASE TILE_DIR...
#
# TILE_DIR holds truth.json and noise-0/cands/ (the scene experiment's layout); the cover is the
# name of TILE_DIR's parent. Writes WORK/<cover>-<tile>.json (detections), WORK/tiles.txt and
# WORK/score.json (+ CSVs).
set -euo pipefail
bin=$1 work=$2 name=$3 ini=$4 args=$5 mb=$6
shift 6
classes=${MODEL_CLASSES:-share/models/classes.csv}
mkdir -p "$work"
: >"$work/tiles.txt"
for tile in "$@"; do
  cover=$(basename "$(dirname "$tile")")
  cands=$tile/noise-0/cands
  for pcd in "$cands"/*.pcd; do
    id=$(basename "$pcd" .pcd)
    # shellcheck disable=SC2086
    "$bin/classify" --config "$ini" $args -i "$pcd" --index "$cands/index.json" --modelbase "$mb" \
      --model-classes "$classes" -o "$cands/$id/class-$name.json" 2>/dev/null
  done
  out=$work/$cover-$(basename "$tile").json
  "$bin/collect" -i "$cands/index.json" --class-name "class-$name.json" -o "$out" --modelbase "$mb" 2>/dev/null
  echo "$out $tile/truth.json 0 $cover" >>"$work/tiles.txt"
done
"$bin/score" --tiles "$work/tiles.txt" --model-classes "$classes" -o "$work/score.json" --csv "$work/" 2>&1 | tail -1
