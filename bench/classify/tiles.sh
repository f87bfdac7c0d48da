#!/bin/bash
# Renders classify's development tiles and runs detect on them (docs/decisions/classify.md §5).
#   bench/classify/tiles.sh BUILD WORK "SEEDS" "DENSITIES" [TREES] [SENSOR] [HIDE]
# SEEDS: never the scene experiment's (1-8) nor detect's (101-124): 900-950. DENSITIES: target
# points/m² (10 25 50 100), turned into a pixel spacing for the sensor below (measured:
# 2.64 / spacing² points/m² for `als`, 4.45 / spacing² for `scene`). Each run is
# WORK/<sensor>-t<trees>/d<density>/s<seed>/ with recipe.scene, scan.pcd, truth.json, cands/.
# detect: --min-planarity 0 (its planarity test needs ~21 points/m², detect.md §3b) and a voxel
# of 1.9 / sqrt(density) (>= 0.2 m) so that a sparse vehicle stays one object.
set -euo pipefail
build=$1; work=$2; seeds=$3; densities=$4; trees=${5:-100}; sensor=${6:-als}; hide=${7:-0}
bin=$build/bin
case $sensor in
  als) k=2.64; sens=$'flight_lines = 3\nswath_overlap = 0.5\nheadings = 0deg\nlooks = 80deg/90deg 80deg/270deg' ;;
  nadir) k=1.5; sens=$'flight_lines = 3\nswath_overlap = 0.5\nheadings = 0deg\nlooks = 90deg' ;;
  scene) k=4.45; sens=$'flight_lines = 2\nheadings = 0deg 90deg\nlooks = 75deg/0deg 75deg/180deg' ;;
  *) echo "sensor: als, nadir or scene" >&2; exit 2 ;;
esac
classes="sedan hatchback suv pickup van box-truck semi-tractor bus wheeled-apc tracked-apc tank wheel-loader"
for d in $densities; do
  spacing=$(python3 -c "import math; print('%dmm' % round(1000 * math.sqrt($k / $d)))")
  voxel=$(python3 -c "import math; print('%.2f' % max(0.2, 1.9 / math.sqrt($d)))")
  for seed in $seeds; do
    run=$work/$sensor-t$trees$([ "$hide" = 0 ] || echo "-h$hide")/d$d/s$seed
    mkdir -p "$run"
    if [ ! -s "$run/truth.json" ]; then
      list=""; i=0
      for c in $classes; do for kk in 0 1; do
        list="$list,family:$c:$(( 900 + (seed * 7 + i * 13 + kk * 29) % 100 ))"; i=$((i + 1)); done; done
      cat > "$run/recipe.scene" <<R
# classify development tile (bench/classify/tiles.sh), seed $seed, about $d points/m^2
extent = 90m 90m
terrain = rolling 1m 25m
trees = $trees
hide = $hide
bushes = 300
vehicles = random 22 from ${list#,}
clutter = boulder 4 shed 2 container 2 fence 2 logs 2
$sens
spacing = $spacing
R
      nice "$bin/rangetrace" -q --scene "$run/recipe.scene" --seed "$seed" --threads 2 -o "$run/scan.pcd" \
        --truth "$run/truth.json"
    fi
    if [ ! -s "$run/cands/index.json" ]; then
      nice "$bin/detect" -q -i "$run/scan.pcd" -o "$run/cands" --no-classes --voxel "$voxel" --min-planarity 0
    fi
    echo "$run"
  done
done
