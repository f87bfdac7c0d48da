#!/usr/bin/env bash
# PCD reading: canopy's read_pcd against PCL's loadPCDFile (into PCLPointCloud2, as PCL's
# tools do, and into PointCloud<PointXYZL>) on a scan-like cloud, binary and
# binary_compressed, 3 runs each, every read in its own process (peak RSS is the reader's).
# Usage: bench/formats/run.sh [points=8000000] [build dir=build]
set -euo pipefail
cd "$(dirname "$0")/../.."
points=${1:-8000000}
build=${2:-build}
cmake --build "$build" --target formats_bench >/dev/null
bin="$build/bin/formats_bench"
dir=$(mktemp -d "${TMPDIR:-/tmp}/formats-bench.XXXXXX")
trap 'rm -rf "$dir"' EXIT
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
