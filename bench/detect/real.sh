#!/usr/bin/env bash
# detect on the real development tiles at the class level (docs/decisions/detect.md §11): per tile
# of /work/shared/data/real/laz (REAL=DIR), detect with its defaults plus DETECT_ARGS into
# WORK/TAG/<tile>/cands, classify with share/params/classify.ini (the real tiles' thresholds) on
# every candidate, collect, score against share/real/<tile>.truth.json where there is one, then
# bench/classify/realcal.py --figures (clear and all recall, precision, class right, false alarms
# per ha on the forest plots). The model chain is not run: on these tiles (8-25 points/m²) a
# vehicle's object stays below the model level's 50 points/m², as in `make tile`.
#   bench/detect/real.sh [build dir] [work dir] [tiles] [modelbase]
#   e.g. TAG=off DETECT_ARGS="--row-max-height 0" bench/detect/real.sh build /tmp/real "ahn3_delft_1 forest_bcts_1" out/modelbase
# Development tiles only (docs/decisions/real-tiles.md: ahn3_delft_1, forest_bcts_1, the plots).
set -euo pipefail
build=${1:-build} work=${2:-/tmp/detect-real} tiles=${3:-ahn3_delft_1 forest_bcts_1} mb=${4:-out/modelbase}
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$build/bin
tag=${TAG:-default}
real=${REAL:-/work/shared/data/real/laz}
out=$work/$tag
for t in $tiles; do
  d=$out/$t
  mkdir -p "$d"
  # shellcheck disable=SC2086
  nice "$bin/detect" -q --no-classes ${DETECT_ARGS:-} -i "$real/$t.laz" -o "$d/cands"
  ids=$(python3 -c "import json,sys; print(' '.join(c['id'] for c in json.load(open(sys.argv[1]))['candidates']))" \
    "$d/cands/index.json")
  for id in $ids; do
    mkdir -p "$d/cands/$id"
    nice "$bin/classify" -q --config "$src/share/params/classify.ini" -i "$d/cands/$id.pcd" \
      --index "$d/cands/index.json" --modelbase "$mb" --model-classes "$src/share/models/classes.csv" \
      -o "$d/cands/$id/class.json"
  done
  "$bin/collect" -q -i "$d/cands/index.json" -o "$d/detections.json" --modelbase "$mb"
  if [ -s "$src/share/real/$t.truth.json" ]; then
    "$bin/score" -q -d "$d/detections.json" -t "$src/share/real/$t.truth.json" -o "$d/score.json"
  fi
done
# shellcheck disable=SC2086
python3 "$src/bench/classify/realcal.py" "$out" "$src/share/real" $tiles --figures
