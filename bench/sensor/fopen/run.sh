#!/usr/bin/env bash
# Issue 28: vehicles under canopy with the national-survey preset (README.md here).
#   bench/sensor/fopen/run.sh [OUT_DIR]      (BIN=build/bin, SEEDS="611 612 613 614",
#                                             SCENE=bench/sensor/fopen/fopen.scene)
# Renders the scene once per seed (nice, 2 threads; a tile is reused when present) and writes
# OUT_DIR/table.md: per vehicle and by nadir-cover bin, the share of the pulses over a vehicle
# that return from it (fopen.py).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../../.." && pwd)
bin=$(cd "${BIN:-$src/build/bin}" && pwd)
out=${1:-$src/build/bench-fopen}
scene=${SCENE:-$here/fopen.scene}
mkdir -p "$out"
out=$(cd "$out" && pwd)
args=()
for seed in ${SEEDS:-611 612 613 614}; do
  if [ ! -s "$out/t$seed.las" ]; then
    /usr/bin/time -v nice "$bin/rangetrace" --scene "$scene" --seed "$seed" --threads 2 \
      -o "$out/t$seed.las" --truth "$out/t$seed.truth.json" 2>"$out/t$seed.time" || { cat "$out/t$seed.time" >&2; exit 1; }
  fi
  args+=("$out/t$seed.las,$out/t$seed.truth.json")
done
python3 "$here/fopen.py" --md "$out/table.md" "${args[@]}"
