#!/usr/bin/env bash
# recollect_into.sh BIN MANIFEST MODELBASE CLASSES RES [collect options...]: as recollect.sh, but
# leaves the runs untouched: collect again, from the verdict.json and class.json already there,
# every run of a score manifest (MANIFEST: detections truth noise cover per line, paths seen from
# the working directory) into RES/<k>/detections.json (k = the manifest's line, from 0; RES/<k>/cands
# links to the run's cands/, so bench/collect/calibrate.py finds each index), with mk/scenes.mk's
# tile_collect argv plus the options, then score RES/tiles.txt as mk/scenes.mk does (RES/score.json
# + CSVs). RES is made afresh. docs/decisions/verify.md §19.
set -euo pipefail
[ $# -ge 5 ] || { echo "usage: recollect_into.sh BIN MANIFEST MODELBASE CLASSES RES [collect options...]" >&2; exit 2; }
bin=$1 manifest=$2 mb=$3 classes=$4 res=$5
shift 5
[ -f "$manifest" ] || { echo "recollect_into.sh: $manifest: no such manifest" >&2; exit 1; }
rm -rf "$res"
mkdir -p "$res"
k=0
while read -r det truth noise cover; do
  [ -n "$det" ] || continue
  d=$(realpath "$(dirname "$det")")
  o="$res/$k"
  mkdir -p "$o"
  ln -s "$d/cands" "$o/cands"
  "$bin/collect" -q -i "$d/cands/index.json" -o "$o/detections.json" --modelbase "$mb" "$@"
  echo "$(realpath "$o")/detections.json $(realpath "$truth") $noise $cover" >>"$res/tiles.txt"
  k=$((k + 1))
done <"$manifest"
"$bin/score" -q --tiles "$res/tiles.txt" --model-classes "$classes" -o "$res/score.json" --csv "$res/"
