#!/usr/bin/env bash
# The 30 development queries of docs/decisions/gmatch.md §9 and baseline.md §3 (NOT the thesis
# trials): the 5 objects x 6, seeds 7001-7030, headings (37 * seed) mod 360 deg, circle/flyby
# alternating, 4 mm (k = 1-3) and 16 mm (k = 4-6), through the pipeline with the shipped
# parameters. Usage: bench/gmatch/dev_queries.sh BUILD_DIR OUT_DIR
# Writes OUT_DIR/<object>-<k>/{samples.pcd, mesh.ply, segments.json, meta}.
set -euo pipefail
B=$(cd "${1:?usage: $0 BUILD_DIR OUT_DIR}" && pwd)/bin
D=${2:?usage: $0 BUILD_DIR OUT_DIR}
cd "$(dirname "$0")/../.."
P=share/params
i=0
for o in earthmover obj1 sedan semi tank; do
  for k in 1 2 3 4 5 6; do
    i=$((i + 1))
    seed=$((7000 + i))
    scene=$([ $((k % 2)) = 0 ] && echo flyby || echo circle)
    noise=$([ $k -le 3 ] && echo 4 || echo 16)
    heading=$(((seed * 37) % 360))
    d=$D/$o-$k
    mkdir -p "$d"
    [ -f "$d/segments.json" ] && continue
    nice "$B/rangetrace" --config $P/rangetrace.ini --model $o --scene $scene --heading ${heading}deg \
      --seed $seed --threads 1 -o "$d/raw.pcd" 2>"$d/log"
    nice "$B/addnoise" --config $P/addnoise.ini --sigma ${noise}mm --seed $seed -i "$d/raw.pcd" \
      -o "$d/scan.pcd" 2>>"$d/log"
    nice "$B/fitvox" --config $P/fitvox.ini -i "$d/scan.pcd" -o "$d/samples.pcd" 2>>"$d/log"
    nice "$B/cocone" --config $P/cocone.ini -i "$d/samples.pcd" -o "$d/mesh.ply" 2>>"$d/log"
    nice "$B/ncut" --config $P/ncut.ini --seed $seed -i "$d/mesh.ply" -o "$d/segments.json" 2>>"$d/log"
    rm -f "$d/raw.pcd" "$d/scan.pcd"
    echo "$o $k $scene $noise $heading" >"$d/meta"
  done
done
