#!/usr/bin/env bash
# baseline: CPU time per trial and rank-1 per method (docs/decisions/baseline.md §3).
# Usage: bench/baseline/run.sh BUILD_DIR MODELBASE TRIAL_DIR...
#   each TRIAL_DIR holds samples.pcd; the true object is the first path component after the
#   last "out/" (out/<object>/<scene>/noise-<mm>) or, for the development queries of
#   bench/gmatch/dev_queries.sh, the first word of TRIAL_DIR/meta.
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR MODELBASE TRIAL_DIR...}
mb=${2:?usage: $0 BUILD_DIR MODELBASE TRIAL_DIR...}
shift 2
cmake --build "$build" --target baseline >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
n=0
for d in "$@"; do
  if [ -f "$d/meta" ]; then truth=$(cut -d' ' -f1 "$d/meta"); else truth=$(echo "$d" | sed 's|.*out/||' | cut -d/ -f1); fi
  /usr/bin/time -f "%U %S %e %M" -o "$tmp/time" "$build/bin/baseline" --config share/params/baseline.ini \
    -i "$d/samples.pcd" --modelbase "$mb" -o "$tmp/b.json" 2>/dev/null
  read -r u s w kb <"$tmp/time"
  vfh=$(jq -r '.methods[] | select(.method == "vfh") | .models[0].model' "$tmp/b.json")
  fpfh=$(jq -r '.methods[] | select(.method == "fpfh") | .models[0].model' "$tmp/b.json")
  echo "$d $truth vfh=$vfh fpfh=$fpfh cpu=$(echo "$u + $s" | bc) wall=$w peak_kb=$kb"
  n=$((n + 1))
done | tee "$tmp/rows"
awk '{ split($3, v, "="); split($4, f, "="); split($5, c, "=");
       n++; vr += (v[2] == $2); fr += (f[2] == $2); cpu += c[2] }
     END { printf "%d trials: VFH rank-1 %d, FPFH rank-1 %d, mean CPU %.2f s per trial\n", n, vr, fr, cpu / n }' "$tmp/rows"
