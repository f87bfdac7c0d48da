#!/usr/bin/env bash
# Development crops for docs/decisions/classify.md §43: each mesh alone in an open 20 m tile (the
# open set's crop recipe, mk/openset.mk: flat, no trees or bushes, two flight lines per heading,
# headings 0 and 90 deg, looks 75 deg fore and aft, 40 mm spacing), rendered with each seed and
# detected; the scan is removed after detect. Writes OUT/<mesh>/seed-<s>/{recipe.scene,truth.json,
# cands/}. Development seeds only (>= 101).
#
#   bench/classify/roughcrops.sh BIN OUT "SEEDS" MESH.ply...
# e.g. for k in ladder rack boxes mixed; do bench/classify/roughen.py share/vehicles/truck/ch_mtv.ply \
#        DEV/mesh/ch_mtv_$k.ply $k 101; done; bench/classify/roughcrops.sh build/bin DEV/crops "101 102" DEV/mesh/*.ply
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: roughcrops.sh BIN OUT SEEDS MESH..." >&2; exit 2; }
bin=$1 out=$2 seeds=$3
shift 3
for m in "$@"; do
  [ -f "$m" ] || { echo "roughcrops.sh: $m: no such mesh" >&2; exit 1; }
  n=$(basename "$m" .ply)
  for s in $seeds; do
    r=$out/$n/seed-$s
    mkdir -p "$r"
    [ -f "$r/cands/index.json" ] && continue
    cat >"$r/recipe.scene" <<EOR
# development crop (classify.md §43): $n, seed $s
extent = 20m
terrain = flat
trees = 0
bushes = 0
vehicles = random 1 from $(readlink -f "$m")
flight_lines = 2
headings = 0deg 90deg
looks = 75deg/0deg 75deg/180deg
spacing = 40mm
EOR
    "$bin/rangetrace" --scene "$r/recipe.scene" --seed "$s" --threads 1 -o "$r/scan.pcd" --truth "$r/truth.json" 2>"$r/scan.log"
    "$bin/detect" -i "$r/scan.pcd" -o "$r/cands" 2>"$r/detect.log"
    rm -f "$r/scan.pcd"
  done
done
