#!/usr/bin/env bash
# PCD reading: canopy's read_pcd against PCL's loadPCDFile (into PCLPointCloud2, as PCL's
# tools do, and into PointCloud<PointXYZL>) on a scan-like cloud, binary and
# binary_compressed, 3 runs each, every read in its own process (peak RSS is the reader's).
# LAZ reading: read_points on each LAZ file against read_points on the LAS it decompresses to
# (the same records), 5 runs each, best CPU time per point and the ratio LAZ / LAS. Files:
# tests/las/data/*.laz and ../shared/data/real/laz/*.laz (CANOPY_REAL_DATA) when present, else
# the committed share/real/*.laz;
# files under 10 000 points are too quick to time and are skipped.
# Usage: bench/formats/run.sh [points=8000000 | laz] [build dir=build]   ("laz": LAZ part only)
set -euo pipefail
cd "$(dirname "$0")/../.."
points=${1:-8000000}
build=${2:-build}
cmake --build "$build" --target formats_bench >/dev/null
bin="$build/bin/formats_bench"
dir=$(mktemp -d "${TMPDIR:-/tmp}/formats-bench.XXXXXX")
trap 'rm -rf "$dir"' EXIT
if [ "$points" != laz ]; then
  echo "points: $points  ($(nproc) cores; CPU seconds of one read, peak RSS of the process)"
  for enc in binary binary_compressed; do
    "$bin" make "$dir/scan.pcd" "$points" "$enc"
    echo "== DATA $enc, $(du -m "$dir/scan.pcd" | cut -f1) MB"
    echo "reader    cpu_s  wall_s  peak_MB points"
    cksum "$dir/scan.pcd" > "$dir/cksum"  # page cache warm for every reader
    for run in 1 2 3; do
      for reader in canopy pcl-blob pcl-xyzl; do
        "$bin" read "$reader" "$dir/scan.pcd"
      done
    done
  done
fi
real=${CANOPY_REAL_DATA:-../shared/data/real}
files=(tests/las/data/*.laz)
if [ -d "$real/laz" ]; then files+=("$real"/laz/*.laz); else files+=(share/real/*.laz); fi
echo "== LAZ vs LAS: read_points, best of 5 runs each, CPU ns per point ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
printf '%-36s %9s %6s %8s %8s %6s %8s %8s\n' file points rec las_ns laz_ns ratio las_MB laz_MB
for laz in "${files[@]}"; do
  las="$dir/$(basename "$laz" .laz).las"
  "$bin" unlaz "$laz" "$las"
  n=$(od -An -tu4 -j107 -N4 "$las" | tr -d ' ')
  [ "$n" != 0 ] || n=$(od -An -tu8 -j247 -N8 "$las" | tr -d ' ')  # LAS 1.4's 64-bit count
  [ "$n" -ge 10000 ] || continue
  cksum "$laz" "$las" > "$dir/cksum"
  for run in 1 2 3 4 5; do
    "$bin" read las "$las"
    "$bin" read laz "$laz"
  done > "$dir/runs"
  rec=$(od -An -tu2 -j105 -N2 "$las" | tr -d ' ')
  awk -v f="$(basename "$laz")" -v rec="$rec" '
    { n = $5; ns = 1e9 * $2 / n; mb = $4
      if (!($1 in best) || ns < best[$1]) best[$1] = ns
      if (!($1 in mem) || mb > mem[$1]) mem[$1] = mb }
    END { printf "%-36s %9d %6d %8.0f %8.0f %6.2f %8.0f %8.0f\n", f, n, rec, best["las"], best["laz"],
                 best["laz"] / best["las"], mem["las"], mem["laz"] }' "$dir/runs"
done
