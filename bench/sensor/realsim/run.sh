#!/usr/bin/env bash
# Issue 28, "Checks against physics": a real tile beside a simulated one of the same preset.
#   bench/sensor/realsim/run.sh [OUT_DIR]     (BIN=build/bin, REAL=/work/shared/data/real,
#                                              SEED=501, SCENE=bench/sensor/realsim/sim.scene)
# 1. The two IGN tiles (share/real/*.laz) are read by canopy's LAZ reader and written as plain
#    LAS by `addnoise --sigma 0` (an exact copy); if REAL/reference/ has laz-perf's decoding of
#    the same file, the figures of both decodings are computed and must be identical.
# 2. sim.scene (100 x 60 m, `sensor = als_qL1`, 8 parked vehicles, a few trees, 2 sheds, a
#    container) is rendered with seed 501 under nice, 2 threads.
# 3. lasstats.py (python3, standard library only) writes the same table for the three:
#    OUT_DIR/table.md (and figures.json).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../../.." && pwd)
bin=$(cd "${BIN:-$src/build/bin}" && pwd)
real=${REAL:-/work/shared/data/real}
out=${1:-$src/build/bench-realsim}
seed=${SEED:-501}
scene=${SCENE:-$here/sim.scene}
mkdir -p "$out"
out=$(cd "$out" && pwd)
tiles=(ign_lidarhd_870000_6618000 ign_stbarth_100m)
names=(lidarhd stbarth)
args=()
for k in 0 1; do
  t=${tiles[$k]}
  [ -s "$out/$t.las" ] || "$bin/addnoise" --sigma 0 -i "$src/share/real/$t.laz" -o "$out/$t.las"
  args+=("${names[$k]}=$out/$t.las,$src/share/real/$t.truth.json")
done
if [ ! -s "$out/sim.las" ]; then
  /usr/bin/time -v nice "$bin/rangetrace" --scene "$scene" --seed "$seed" --threads 2 \
    -o "$out/sim.las" --truth "$out/sim.truth.json" 2>"$out/sim.time" || { cat "$out/sim.time" >&2; exit 1; }
fi
args+=("sim_als_qL1=$out/sim.las,$out/sim.truth.json")
python3 "$here/lasstats.py" --md "$out/table.md" --json "$out/figures.json" "${args[@]}"
# the same figures from laz-perf's decoding (reference/): canopy's reader must agree
for k in 0 1; do
  t=${tiles[$k]}
  [ -s "$real/reference/$t.las" ] || continue
  python3 "$here/lasstats.py" "x=$out/$t.las,$src/share/real/$t.truth.json" | grep -v '^| file' >"$out/$t.canopy.md"
  python3 "$here/lasstats.py" "x=$real/reference/$t.las,$src/share/real/$t.truth.json" | grep -v '^| file' >"$out/$t.ref.md"
  if cmp -s "$out/$t.canopy.md" "$out/$t.ref.md"; then
    echo "$t: canopy's LAZ reader and laz-perf's LAS give the same figures"
  else
    echo "$t: figures differ between canopy's LAZ reader and laz-perf's LAS:" >&2
    diff "$out/$t.canopy.md" "$out/$t.ref.md" >&2 || true
    exit 1
  fi
done
