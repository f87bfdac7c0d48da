#!/usr/bin/env bash
# The model level's density threshold on real development tiles (docs/decisions/density-scale.md,
# "The model level at 20 points/m², re-measured", stop 68): `make tile` on each tile with each
# TILE_MODEL_DENSITY, timed (GNU time of the whole sub-make: wall s, peak KiB, user and system
# CPU s of it and every stage under it, as mk/real.mk's tile.time), then `score` against the
# tile's labels when it has some (a tile without labels is a plot without vehicles).
#   bench/real/modellevel.sh OUT_DIR MODELBASE TILE.laz [TILE.laz ...]
#   (DENSITIES="50 20"; TRUTH_DIR=DIR of <tile>.truth.json; BIN=build/bin; JOBS=2;
#    TILE_CLASSIFY=share/params/classify.ini, the real tiles' default)
# Development tiles only (docs/decisions/real-tiles.md: the split); then
#   bench/real/modellevel.py OUT_DIR TRUTH_DIR TILE ... per density.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 OUT_DIR MODELBASE TILE.laz [TILE.laz ...]" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
out=$(mkdir -p "$1" && cd "$1" && pwd)
mb=$(cd "$2" && pwd)
shift 2
truth_dir=${TRUTH_DIR:-$src/share/real}
for laz in "$@"; do
  t=$(basename "$laz" .laz)
  laz=$(cd "$(dirname "$laz")" && pwd)/$(basename "$laz")
  for d in ${DENSITIES:-50 20}; do
    o=$out/$d/$t
    rm -rf "$o" && mkdir -p "$o"
    s=0
    (cd "$src" && /usr/bin/time -f '%e %M %U %S' -o "$o/tile.time" make --no-print-directory \
      -f Makefile.experiments tile TILE="$laz" MODELBASE="$mb" OUT="$o" TILE_MODEL_DENSITY="$d" \
      TILE_CLASSIFY="${TILE_CLASSIFY:-$src/share/params/classify.ini}" BIN="$bin" PROGRESS=0 \
      SCENE_EXPERIMENT=0 FAMILIES=0 REAL_TILES=0 -j"${JOBS:-2}" >"$o/make.log" 2>&1) || s=$?
    truth=$truth_dir/$t.truth.json
    [ ! -f "$truth" ] || [ ! -f "$o/detections.json" ] || "$bin/score" -q -d "$o/detections.json" -t "$truth" -o "$o/score.json"
    echo "$t $d: exit $s, $(tail -n 1 "$o/tile.time") (wall s, peak KiB, user s, sys s)"
  done
done
