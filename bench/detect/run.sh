#!/usr/bin/env bash
# detect benchmark: a 10^7-point tile (100 x 100 m, medium cover, 12 vehicles, 8 mm noise)
# timed through the CLI with peak memory, then the recall table (docs/decisions/detect.md).
#   bench/detect/run.sh [build dir] [tiles per recall configuration]
set -euo pipefail
build=${1:-build} tiles=${2:-6}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/bin/detect_bench" tile 1e7 "$tmp/tile.pcd"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for extra in "--no-classes" "" "--no-classes --clustering euclidean"; do
  echo "== detect $extra"
  # shellcheck disable=SC2086
  /usr/bin/time -v "$build/bin/detect" $extra -i "$tmp/tile.pcd" -o "$tmp/cands" 2>"$tmp/time.txt"
  grep -E 'detect:|Elapsed|Maximum resident|User time|System time' "$tmp/time.txt"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bin/detect_bench" recall "$tiles"
