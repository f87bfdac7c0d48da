#!/usr/bin/env bash
# A 1 ha tile through `make tile` (issue 31: "≤ 60 s wall on 2 cores at the experiment's density
# with other work on the machine"; docs/decisions/cost.md §16).
#
#   bench/make/tile1ha.sh -o DIR -m MODELBASE [-s SPACING] [-c COVER] [-S SEED] [-j JOBS] [-r RUNS]
#
# Renders once (kept in DIR/tile.pcd, re-used by later calls with the same recipe) a 100 × 100 m
# tile of the scene experiment's recipe (mk/scenes.mk: rolling terrain, bushes, the cover level's
# trees and bushes per hectare; 12 of the five thesis models, 12 seen clutter objects; two flight
# lines, two 75° looks) at
# SPACING (default 44 mm: the finest that the recipe's 8 images allow on 1 ha under rangetrace's
# 3·10⁷ pixel bound, 3.3·10⁷ at the scene experiment's own 40 mm), then runs
# `make -f Makefile.experiments tile TILE=DIR/tile.pcd MODELBASE=… OUT=DIR/run-N -jJOBS` RUNS
# times from scratch (default 1) under GNU time. Prints per run: wall, user + system CPU of
# make and everything under it, peak RSS of the largest process, stages run, candidates.
# MODELBASE: graphs and surfaces (`make -f Makefile.experiments verify-modelbase`, or an
# experiment's out/modelbase). The render is not part of `make tile` and is not timed here.
set -euo pipefail
out= mb= spacing=44mm cover=light seed=7 jobs=2 runs=1
usage() { sed -n '4,5p' "$0" >&2; exit 2; }
while getopts "o:m:s:c:S:j:r:" o; do
  case $o in
    o) out=$OPTARG ;; m) mb=$OPTARG ;; s) spacing=$OPTARG ;; c) cover=$OPTARG ;;
    S) seed=$OPTARG ;; j) jobs=$OPTARG ;; r) runs=$OPTARG ;; *) usage ;;
  esac
done
[ -n "$out" ] && [ -n "$mb" ] || usage
case $cover in
  light) trees=100 hide=0 ;; medium) trees=350 hide=1 ;; dense) trees=700 hide=2 ;;
  *) echo "tile1ha.sh: -c $cover: light, medium or dense" >&2; exit 2 ;;
esac
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
[ -x "$bin/rangetrace" ] || { echo "tile1ha.sh: $bin/rangetrace is not built" >&2; exit 1; }
[ -d "$mb" ] || { echo "tile1ha.sh: -m $mb is not a directory" >&2; exit 1; }
mkdir -p "$out"
out=$(cd "$out" && pwd) mb=$(cd "$mb" && pwd)
recipe="# bench/make/tile1ha.sh: the scene experiment's recipe on 1 ha, cover $cover
extent = 100m
terrain = rolling 1m 25m
trees = $trees
hide = $hide
bushes = 300
vehicles = random 12 from earthmover,obj1,sedan,semi,tank
clutter = boulder 6 container 3 logs 3
flight_lines = 2
headings = 0deg 90deg
looks = 75deg/0deg 75deg/180deg
spacing = $spacing"
if ! [ -f "$out/tile.pcd" ] || [ "$(cat "$out/recipe.scene" 2>/dev/null)" != "$recipe" ] || \
   [ "$(cat "$out/seed" 2>/dev/null)" != "$seed" ]; then
  printf '%s\n' "$recipe" >"$out/recipe.scene"
  echo "rendering $out/tile.pcd (once)" >&2
  /usr/bin/time -f "render: %e s wall, %U + %S CPU-s, %M KB" "$bin/rangetrace" --scene "$out/recipe.scene" \
    --seed "$seed" --threads "$jobs" -o "$out/tile.pcd" --truth "$out/truth.json" -q
  echo "$seed" >"$out/seed"
fi
for ((i = 1; i <= runs; i++)); do
  rm -rf "$out/run-$i"
  log=$out/run-$i.log
  /usr/bin/time -o "$out/run-$i.time" -f "%e %U %S %M" make -s -C "$src" -f Makefile.experiments tile \
    TILE="$out/tile.pcd" MODELBASE="$mb" OUT="$out/run-$i" PROGRESS=0 -j"$jobs" >"$log" 2>&1 ||
    { echo "tile1ha.sh: make tile failed, see $log" >&2; exit 1; }
  read -r wall user sys rss <"$out/run-$i.time"
  stages=$(find "$out/run-$i" -name '*.time' | wc -l)
  cands=$(find "$out/run-$i/cands" -maxdepth 1 -name '*.pcd' | wc -l)
  points=$(awk '/^POINTS / { print $2; exit } /^DATA / { exit }' "$out/tile.pcd")  # the header only
  printf 'run %d: %s points, %d candidates, %d stages: %.1f s wall, %.1f CPU-s (user %.1f + sys %.1f), peak %.0f MB, load %s\n' \
    "$i" "$points" "$cands" "$stages" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" "$user" "$sys" "$((rss / 1024))" \
    "$(cut -d' ' -f1-3 /proc/loadavg)"
done
