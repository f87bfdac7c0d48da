#!/usr/bin/env bash
# Benchmark of a rangetrace tile (issue 13): share/scenes/forest.scene (40 x 40 m, 6 vehicles,
# the default forest, 8 images) for a few seeds: wall and CPU seconds, peak memory (GNU time),
# points, points per square metre per image and in all, canopy cover.
# Usage: bench_tile.sh BIN_DIR [THREADS] [SEEDS...]   (prints a table to stdout)
set -eu
bin=$1; threads=${2:-2}; shift $(( $# >= 2 ? 2 : $# ))
seeds=${*:-1 2 3}
here=$(cd "$(dirname "$0")" && pwd)
scene=$here/../../share/scenes/forest.scene
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '# load average before: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-5s %8s %8s %8s %9s %11s %9s %10s %11s\n' seed wall_s cpu_s peak_MB points per_m2_img per_m2 cover_tile cover_veh
for s in $seeds; do
  /usr/bin/time -f '%e %U %S %M' -o "$tmp/time" "$bin/rangetrace" --scene "$scene" --seed "$s" \
    --threads "$threads" -o "$tmp/tile.pcd" --truth "$tmp/truth.json" 2>"$tmp/log"
  read -r wall user sys kb <"$tmp/time"
  pts=$(grep -a -m1 '^POINTS' "$tmp/tile.pcd" | cut -d' ' -f2)
  img=$(sed -n 's/.*; \([0-9.]*\) points per m^2 per image.*/\1/p' "$tmp/log")
  all=$(sed -n 's/.*image, \([0-9.]*\) per m^2 in all.*/\1/p' "$tmp/log")
  ctile=$(sed -n 's/.*canopy cover \([0-9.]*\) over the tile, \([0-9.]*\) on average.*/\1/p' "$tmp/log")
  cveh=$(sed -n 's/.*canopy cover \([0-9.]*\) over the tile, \([0-9.]*\) on average.*/\2/p' "$tmp/log")
  printf '%-5s %8.1f %8.1f %8.1f %9d %11s %9s %10s %11s\n' "$s" "$wall" "$(echo "$user + $sys" | bc -l)" \
    "$(echo "$kb / 1024" | bc -l)" "$pts" "$img" "$all" "$ctile" "$cveh"
done
printf '# load average after: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
