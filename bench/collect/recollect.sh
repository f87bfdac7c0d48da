#!/usr/bin/env bash
# recollect.sh BIN MANIFEST MODELBASE CLASSES RES [collect options...]: collect again, from the
# verdict.json and class.json already there, every run of a score manifest (MANIFEST: detections
# truth noise cover per line, as mk/scenes.mk writes it; paths seen from the working directory),
# with mk/scenes.mk's tile_collect argv plus the options (e.g. --calibration FILE), then score it
# as mk/scenes.mk does (RES/score.json + CSVs). Overwrites each run's detections.json: run it on
# a copy (docs/decisions/verify.md §16 shows how the experiment's was made).
set -euo pipefail
[ $# -ge 5 ] || { echo "usage: recollect.sh BIN MANIFEST MODELBASE CLASSES RES [collect options...]" >&2; exit 2; }
bin=$1 manifest=$2 mb=$3 classes=$4 res=$5
shift 5
while read -r det _truth _noise _cover; do
  d=$(dirname "$det")
  "$bin/collect" -q -i "$d/cands/index.json" -o "$d/detections.json" --geojson "$d/detections.geojson" \
    --modelbase "$mb" "$@"
done <"$manifest"
mkdir -p "$res"
"$bin/score" -q --tiles "$manifest" --model-classes "$classes" -o "$res/score.json" --csv "$res/"
