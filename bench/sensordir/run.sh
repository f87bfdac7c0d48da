#!/usr/bin/env bash
# Issue 26: what verify's answers cost when the direction toward the sensor is derived from what
# a LAS file has instead of the simulator's true sensor_x/y/z (docs/decisions/verify.md,
# "Sensor directions from what LAS has").
#   bench/sensordir/run.sh OUT_DIR [TILES_PER_LOOK [FOREST_TILES]]   (BIN=build/bin)
# Renders small tiles (one vehicle and one clutter object each; seeds 2611.. never used by the
# scene experiment), two look geometries: "across" (75 deg elevation, looks 90 and 270 deg from
# the flight heading: a scanner's swath edges, which a LAS scan angle can express) and "foreaft"
# (the scene experiment's 0/180 deg looks, whose tilt no LAS field carries), and "forest": the
# fore/aft looks with trees and bushes (occluders in the depth buffers). Each candidate goes
# detect | fitvox | cocone | ncut | gmatch once; then verify runs with the true columns and, on
# the same samples with the columns replaced by synth_las.py's gps_time / scan_angle /
# point_source_id, with --sensor-direction trajectory, scan-angle and vertical.
# tabulate.py prints the comparison (counts, Wilson 95 % intervals).
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(cd "${BIN:-$src/build/bin}" && pwd)
export PATH="$bin:$PATH"
P=$src/share/params
out=$1
n=${2:-4}
nf=${3:-0}
mkdir -p "$out/mb"
out=$(cd "$out" && pwd)
models=(sedan tank obj1 earthmover)
for m in "${models[@]}"; do
  [ -s "$out/mb/$m.json" ] && continue
  rangetrace -q --model "$m" --scene unoccluded --seed 2611 | fitvox -q -o "$out/mb/$m.pcd"
  cocone -q -i "$out/mb/$m.pcd" | ncut -q --seed 2611 -o "$out/mb/$m.json"
done
objects=(container boulder shed logs)
for look in across foreaft forest; do
  veg=('trees = 0' 'bushes = 0')
  count=$n
  case $look in
    across) looks='75deg/90deg 75deg/270deg' ;;
    foreaft) looks='75deg/0deg 75deg/180deg' ;;
    forest) looks='75deg/0deg 75deg/180deg' veg=('trees = 400' 'bushes = 300' 'hide = 2') count=$nf ;;
  esac
  for i in $(seq 1 "$count"); do
    d=$out/$look-$i
    [ -e "$d/done" ] && continue
    rm -rf "$d" && mkdir -p "$d"
    veh=${models[$(((i - 1) % ${#models[@]}))]}
    obj=${objects[$(((i - 1) % ${#objects[@]}))]}
    printf '%s\n' 'extent = 22m 16m' 'terrain = flat' "${veg[@]}" \
      "vehicle = $veh 8 8 $(((i * 47) % 180))" "object = $obj 18 5 $(((i * 31) % 180))" \
      'flight_lines = 1' 'headings = 0deg 90deg' "looks = $looks" 'spacing = 30mm' >"$d/tile.scene"
    seed=$((2620 + i))
    [ "$look" = forest ] && seed=$((2650 + i))
    rangetrace -q --scene "$d/tile.scene" --seed "$seed" -o "$d/tile.pcd" --truth "$d/truth.json"
    detect -q -i "$d/tile.pcd" -o "$d/cands" --no-classes
    for id in $(jq -r '.candidates[].id' "$d/cands/index.json"); do
      c=$d/cands/$id
      mkdir -p "$c"
      fitvox -q --config "$P/fitvox-tile.ini" --pcd-encoding ascii -i "$d/cands/$id.pcd" -o "$c/samples.pcd" &&
        cocone -q --config "$P/cocone.ini" -i "$c/samples.pcd" -o "$c/mesh.ply" &&
        ncut -q --config "$P/ncut.ini" --seed 2641 -i "$c/mesh.ply" -o "$c/segments.json" &&
        gmatch -q --config "$P/gmatch.ini" -i "$c/segments.json" --modelbase "$out/mb" -o "$c/match.json" ||
        { echo "$look-$i $id: chain failed" >>"$out/failed.txt"; continue; }
      tr=$(jq -r --arg id "$id" '.candidates[] | select(.id == $id) | .transform[0:3] | flatten | map(tostring) | join(",")' \
        "$d/cands/index.json")
      python3 "$src/bench/sensordir/synth_las.py" "$c/samples.pcd" "$d/cands/index.json" "$id" "$d/truth.json" \
        "$c/las.pcd" "$c/traj.txt"
      v=(verify -q --config "$P/verify.ini" -i "$c/match.json" --segments "$c/segments.json" --modelbase "$out/mb"
        --transform "$tr")
      "${v[@]}" --points "$c/samples.pcd" -o "$c/v-columns.json"
      "${v[@]}" --points "$c/las.pcd" --sensor-direction trajectory --trajectory "$c/traj.txt" -o "$c/v-trajectory.json"
      "${v[@]}" --points "$c/las.pcd" --sensor-direction scan-angle -o "$c/v-scan-angle.json"
      "${v[@]}" --points "$c/las.pcd" --sensor-direction vertical -o "$c/v-vertical.json"
    done
    touch "$d/done"
  done
done
python3 "$src/bench/sensordir/tabulate.py" "$out"
