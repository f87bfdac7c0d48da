#!/usr/bin/env bash
# Benchmark of rangetrace: wall seconds per scene and per view, points per scan and peak memory
# (GNU time), CPU seconds (user + system, POV-Ray included) for each model and scene.
# Usage: bench_rangetrace.sh BIN_DIR [THREADS] [MODELS...]   (prints a table to stdout)
set -eu
bin=$1; threads=${2:-2}; shift $(( $# >= 2 ? 2 : $# ))
models=${*:-earthmover obj1 sedan semi tank}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '# load average before: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-11s %-11s %5s %9s %8s %8s %9s %9s\n' model scene views seconds s/view cpu_s points peak_MB
total_sedan=0
for m in $models; do
  for s in unoccluded circle flyby; do
    /usr/bin/time -f '%e %M %U %S' -o "$tmp/time" "$bin/rangetrace" -q --model "$m" --scene "$s" \
      --seed 7 --threads "$threads" -o "$tmp/scan.pcd"
    read -r secs kb user sys <"$tmp/time"
    pts=$(grep -a -m1 '^POINTS' "$tmp/scan.pcd" | cut -d' ' -f2)
    case $s in unoccluded) v=10;; circle) v=12;; flyby) v=20;; esac
    printf '%-11s %-11s %5d %9.2f %8.3f %8.2f %9d %9.1f\n' "$m" "$s" "$v" "$secs" \
      "$(echo "$secs / $v" | bc -l)" "$(echo "$user + $sys" | bc -l)" "$pts" "$(echo "$kb / 1024" | bc -l)"
  done
done
