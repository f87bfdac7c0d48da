#!/usr/bin/env bash
# Recall against density on the real development tiles, by thinning (docs/decisions/real-tiles.md,
# "Recall against density on the real development tiles, by thinning", stop 71): per seed, fraction
# and tile, las_thin keeps that fraction of the tile's pulses (every return of a kept pulse; point by
# point where gps_time does not separate the pulses), then the whole `make tile` workflow runs on the
# thinned LAS as mk/real.mk runs a real tile (classify.ini, the model level's default), timed by GNU
# time of the sub-make (wall s, peak KiB, user and system CPU s of it and every stage under it, as
# mk/real.mk's tile.time), and `score` against the tile's labels when it has some (a tile without
# labels is a plot without vehicles).
#   bench/real/thin.sh OUT_DIR MODELBASE TILE.laz [TILE.laz ...]
#   (FRACTIONS="1 0.75 0.5 0.35 0.25 0.125"; SEEDS="1"; TRUTH_DIR=DIR of <tile>.truth.json;
#    BIN=build/bin; JOBS=2; TILE_CLASSIFY=share/params/classify.ini, the real tiles' default;
#    KEEP=1 keeps the thinned LAS files, else each is deleted after its run; MAKE_ARGS="VAR=value ..."
#    more variables for the tile workflow, e.g. TILE_DETECT=<ini> for a diagnostic run;
#    THIN_ARGS="--systematic" more las_thin options)
# into OUT_DIR/s<seed>/f<fraction>/<tile>/ (the tile's run; thin.log: las_thin's line). Then
#   bench/real/thin.py OUT_DIR TRUTH_DIR TILE ...   (the tables)
# Development tiles only (docs/decisions/real-tiles.md: the split).
# shellcheck disable=SC2086  # MAKE_ARGS, THIN_ARGS: words
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 OUT_DIR MODELBASE TILE.laz [TILE.laz ...]" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
out=$(mkdir -p "$1" && cd "$1" && pwd)
mb=$(cd "$2" && pwd)
shift 2
truth_dir=${TRUTH_DIR:-$src/share/real}
[ -x "$bin/las_thin" ] || { echo "$0: $bin/las_thin not built (cmake --build build --target las_thin)" >&2; exit 1; }
for seed in ${SEEDS:-1}; do
  for f in ${FRACTIONS:-1 0.75 0.5 0.35 0.25 0.125}; do
    for laz in "$@"; do
      t=$(basename "$laz" .laz)
      o=$out/s$seed/f$f/$t
      las=$out/s$seed/f$f/las/$t.las
      rm -rf "$o" && mkdir -p "$o" "$(dirname "$las")"
      "$bin/las_thin" -i "$laz" -o "$las" --fraction "$f" --seed "$seed" ${THIN_ARGS:-} 2>"$o/thin.log"
      s=0
      (cd "$src" && /usr/bin/time -f '%e %M %U %S' -o "$o/tile.time" make --no-print-directory \
        -f Makefile.experiments tile TILE="$las" MODELBASE="$mb" OUT="$o" \
        TILE_CLASSIFY="${TILE_CLASSIFY:-$src/share/params/classify.ini}" BIN="$bin" PROGRESS=0 \
        SCENE_EXPERIMENT=0 FAMILIES=0 REAL_TILES=0 ${MAKE_ARGS:-} -j"${JOBS:-2}" >"$o/make.log" 2>&1) || s=$?
      truth=$truth_dir/$t.truth.json
      [ ! -f "$truth" ] || [ ! -f "$o/detections.json" ] || "$bin/score" -q -d "$o/detections.json" -t "$truth" -o "$o/score.json"
      [ "${KEEP:-0}" = 1 ] || rm -f "$las"
      echo "s$seed f$f $t: exit $s, $(tail -n 1 "$o/tile.time") (wall s, peak KiB, user s, sys s)"
    done
  done
done
