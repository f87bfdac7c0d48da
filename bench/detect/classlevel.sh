#!/usr/bin/env bash
# The ladder's class level on bench/detect/pieces.sh runs (docs/decisions/detect.md §16): classify
# with share/params/classify-sim.ini on every candidate of RUN/cands-TAG (RUN/cands-TAG/<id>/
# class.json), collect with share/params/calibration.ini, and one score over the runs: found at
# either level per cover, false alarms, class right (OUT/score.json + CSVs), as mk/scenes.mk's
# chain answers a candidate below the model level (every candidate at 10-50 points/m²).
#   bench/detect/classlevel.sh BIN OUT TAG MODELBASE RUN...   (RUN = WORK/d<level>-<cover>-<seed>)
# CLASSIFY_INI (default share/params/classify-sim.ini) and CLASSIFY_ARGS (options after it) change
# classify's parameters (docs/decisions/classify.md §25).
# (score's closing line counts model-level detections, none here: read score.json's
# found_any_level, recall_any_level and false_alarms_any_level_per_ha per cover.)
set -euo pipefail
shopt -s nullglob  # a tile with no candidate (dense cover at 10 points/m²) has no crop to classify
bin=$1 out=$2 tag=$3 mb=$4
shift 4
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mkdir -p "$out"
: >"$out/tiles.txt"
for run in "$@"; do
  c=$run/cands-$tag
  for pcd in "$c"/*.pcd; do
    id=$(basename "$pcd" .pcd)
    mkdir -p "$c/$id"
    if [ -s "$c/$id/class.json" ] && [ "$c/$id/class.json" -nt "$c/index.json" ]; then continue; fi
    # shellcheck disable=SC2086
    nice "$bin/classify" -q --config "${CLASSIFY_INI:-$src/share/params/classify-sim.ini}" ${CLASSIFY_ARGS:-} \
      -i "$pcd" --index "$c/index.json" \
      --modelbase "$mb" --model-classes "$src/share/models/classes.csv" -o "$c/$id/class.json"
  done
  b=$(basename "$run")
  cover=$(echo "$b" | cut -d- -f2)
  "$bin/collect" -q -i "$c/index.json" -o "$out/$b.json" --modelbase "$mb" \
    --calibration "$src/share/params/calibration.ini"
  echo "$out/$b.json $run/truth.json 0 $cover" >>"$out/tiles.txt"
done
"$bin/score" --tiles "$out/tiles.txt" --model-classes "$src/share/models/classes.csv" -o "$out/score.json" \
  --csv "$out/" 2>&1 | tail -1
