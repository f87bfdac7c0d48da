#!/usr/bin/env bash
# PCD reading: canopy's read_pcd against PCL's loadPCDFile (into PCLPointCloud2, as PCL's
# tools do, and into PointCloud<PointXYZL>) on a scan-like cloud, binary and
# binary_compressed, 3 runs each, every read in its own process (peak RSS is the reader's).
# LAZ reading: read_points on each LAZ file against read_points on the LAS it decompresses to
# (the same records), 5 runs each, best CPU time per point and the ratio LAZ / LAS. Files:
# tests/las/data/*.laz and ../shared/data/real/laz/*.laz (CANOPY_REAL_DATA) when present, else
# the committed share/real/*.laz;
# files under 10 000 points are too quick to time and are skipped.
# LAS reading against a plain read (issue 31; docs/decisions/cost.md sections 5 and 7),
# "lasread": the reads the tools do — read points F (read_points, every field: detect,
# pcd2ply), read xyz F (x y z only, as doubles: topview), read detect F (every field, then x y z
# and return_number as doubles) — against the plainest correct read of the same LAS (read
# plain F: the header, then every record in one block), each 3 times in its own process,
# min / median CPU s, median peak RSS as a multiple of the file size after the process's own
# RSS before reading (base, ~23 MB); the checksum (x+y+z, intensity+classification) shows
# they read the same values. Files: a synthetic
# 3-million-point LAS 1.4 format 6 tile with 4 Extra Bytes fields (make-las, i.e. write_las),
# the LAS references in ../shared/data/real/reference (CANOPY_REAL_DATA) and the LAS canopy
# decodes from the real LAZ that have no reference; under 10 000 points skipped. With
# LASREAD_BEFORE=<another formats_bench> its read points runs in the same rounds ("before:" at
# the end of each line: CPU min/median, before/plain, peak x file).
# Usage: bench/formats/run.sh [points=8000000 | laz | lasread [las points=3000000]] [build dir=build]
#   ("laz": LAZ part only; "lasread": LAS reader against a plain read only)
set -euo pipefail
cd "$(dirname "$0")/../.."
points=${1:-8000000}
build=${2:-build}
[ "$points" != lasread ] || build=${3:-build}
cmake --build "$build" --target formats_bench >/dev/null
bin="$build/bin/formats_bench"
dir=$(mktemp -d "${TMPDIR:-/tmp}/formats-bench.XXXXXX")
trap 'rm -rf "$dir"' EXIT
real=${CANOPY_REAL_DATA:-../shared/data/real}
if [ "$points" = lasread ]; then
  "$bin" make-las "$dir/synthetic_pf6.las" "${2:-3000000}"
  files=("$dir/synthetic_pf6.las")
  for f in "$real"/reference/*.las; do [ -e "$f" ] && files+=("$f"); done
  for laz in "$real"/laz/*.laz; do
    [ -e "$laz" ] && [ ! -e "$real/reference/$(basename "$laz" .laz).las" ] || continue
    "$bin" unlaz "$laz" "$dir/$(basename "$laz" .laz).las"
    files+=("$dir/$(basename "$laz" .laz).las")
  done
  echo "== LAS: read_points against a plain read, 3 runs each, own process ($(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
  echo "   CPU s (user+sys) min/median; ratios of medians to plain; peak: (median peak RSS - base) / file size; base = RSS before reading"
  echo "   points: every field (detect, pcd2ply); xyz: x y z only, as doubles (topview); detect: every field + x y z return_number as doubles"
  printf '%-28s %8s %4s %6s %13s %13s %13s %13s %5s %5s %5s %5s %5s %5s %5s %5s %s\n' file points rec fileMB \
    points_cpu xyz_cpu detect_cpu plain_cpu pt/p xyz/p det/p base pt/f xyz/f det/f pln/f same
  for f in "${files[@]}"; do
    n=$(od -An -tu4 -j107 -N4 "$f" | tr -d ' ')
    [ "$n" != 0 ] || n=$(od -An -tu8 -j247 -N8 "$f" | tr -d ' ')  # LAS 1.4's 64-bit count
    [ "$n" -ge 10000 ] || continue
    cksum "$f" > "$dir/cksum"  # page cache warm for every reader
    for run in 1 2 3; do
      for reader in points xyz detect plain; do "$bin" read "$reader" "$f"; done
      # LASREAD_BEFORE: another build's formats_bench (e.g. before a reader change), its
      # read_points timed in the same rounds, as "before".
      [ -z "${LASREAD_BEFORE:-}" ] || "$LASREAD_BEFORE" read points "$f" | sed 's/^points/before/'
    done > "$dir/runs"
    rec=$(od -An -tu2 -j105 -N2 "$f" | tr -d ' ')
    awk -v f="$(basename "$f")" -v rec="$rec" -v mb="$(stat -c %s "$f")" '
      function mn(a, k) { return a[k, 1] < a[k, 2] ? (a[k, 1] < a[k, 3] ? a[k, 1] : a[k, 3]) : (a[k, 2] < a[k, 3] ? a[k, 2] : a[k, 3]) }
      function mx(a, k) { return a[k, 1] > a[k, 2] ? (a[k, 1] > a[k, 3] ? a[k, 1] : a[k, 3]) : (a[k, 2] > a[k, 3] ? a[k, 2] : a[k, 3]) }
      function med(a, k) { return a[k, 1] + a[k, 2] + a[k, 3] - mn(a, k) - mx(a, k) }
      function xyzsum(k) { split(sum[k], p, "+"); return p[1] }
      { r = ++runs[$1]; cpu[$1, r] = $2; peak[$1, r] = $4; n = $5; base[$1, r] = $6; sum[$1] = $7 }
      END { mb /= 1048576; b = med(base, "points"); pl = med(cpu, "plain")
            printf "%-28s %8d %4d %6.1f", f, n, rec, mb
            printf " %6.3f/%6.3f %6.3f/%6.3f", mn(cpu, "points"), med(cpu, "points"), mn(cpu, "xyz"), med(cpu, "xyz")
            printf " %6.3f/%6.3f %6.3f/%6.3f", mn(cpu, "detect"), med(cpu, "detect"), mn(cpu, "plain"), pl
            printf " %5.2f %5.2f %5.2f %5.1f", med(cpu, "points") / pl, med(cpu, "xyz") / pl, med(cpu, "detect") / pl, b
            printf " %5.2f %5.2f %5.2f %5.2f %s", (med(peak, "points") - b) / mb, (med(peak, "xyz") - b) / mb,
              (med(peak, "detect") - b) / mb, (med(peak, "plain") - b) / mb,
              sum["points"] == sum["plain"] && sum["detect"] == sum["plain"] && xyzsum("xyz") == xyzsum("plain") &&
              (!("before" in sum) || sum["before"] == sum["points"]) ? "yes" : "NO"
            if ("before" in sum)
              printf "  before: %6.3f/%6.3f b/p %5.2f %5.2f x file", mn(cpu, "before"), med(cpu, "before"),
                med(cpu, "before") / pl, (med(peak, "before") - b) / mb
            printf "\n" }' "$dir/runs"
  done
  exit 0
fi
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
