#!/usr/bin/env bash
# baseline on scene candidates: CPU time per candidate of each method (`baseline --verdict vfh`,
# `--verdict fpfh`) and, on the same candidates, of canopy's chain after fitvox (cocone | ncut |
# gmatch | verify), each run alone and one after another (docs/decisions/baseline.md §4).
# Usage: bench/baseline/candidates.sh BUILD_DIR MODELBASE EVERY SAMPLES.pcd...
#   e.g. bench/baseline/candidates.sh build out/modelbase 8 out/scenes/*/tile-*/noise-*/cands/*/samples.pcd
#   EVERY: use every EVERY-th of the given candidates (1 = all).
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR MODELBASE EVERY SAMPLES.pcd...}
mb=${2:?usage: $0 BUILD_DIR MODELBASE EVERY SAMPLES.pcd...}
every=${3:?usage: $0 BUILD_DIR MODELBASE EVERY SAMPLES.pcd...}
shift 3
cmake --build "$build" --target baseline cocone ncut gmatch verify >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu() { /usr/bin/time -f "%U %S %M" -o "$tmp/t" "$@" 2>/dev/null && awk '{ printf "%.3f %d\n", $1 + $2, $3 / 1024 }' "$tmp/t"; }
i=0
for f in "$@"; do
  i=$((i + 1))
  [ $(((i - 1) % every)) -eq 0 ] && [ -s "$f" ] || continue
  b=$build/bin
  read -r vfh vfh_mb < <(cpu "$b/baseline" --config share/params/baseline.ini --verdict vfh -i "$f" --modelbase "$mb" -o "$tmp/v.json")
  read -r fpfh fpfh_mb < <(cpu "$b/baseline" --config share/params/baseline.ini --verdict fpfh -i "$f" --modelbase "$mb" -o "$tmp/f.json")
  canopy=0
  for st in "cocone --config share/params/cocone.ini -i $f -o $tmp/mesh.ply" \
            "ncut --config share/params/ncut.ini --seed 1 -i $tmp/mesh.ply -o $tmp/seg.json" \
            "gmatch --config share/params/gmatch.ini -i $tmp/seg.json --modelbase $mb -o $tmp/match.json" \
            "verify --config share/params/verify.ini -i $tmp/match.json --points $f --segments $tmp/seg.json --modelbase $mb -o $tmp/verdict.json"; do
    # shellcheck disable=SC2086
    read -r s _ < <(cpu $b/$st) || { canopy=; break; }
    canopy=$(echo "$canopy + $s" | bc)
  done
  echo "$f vfh=$vfh fpfh=$fpfh canopy=${canopy:-failed} peak_mb=$((vfh_mb > fpfh_mb ? vfh_mb : fpfh_mb))"
done | tee "$tmp/rows"
awk '{ split($2, v, "="); split($3, f, "="); split($4, c, "=");
       n++; vs += v[2]; fs += f[2]; if (c[2] != "failed") { cs += c[2]; cn++ } }
     END { printf "%d candidates: CPU s per candidate: VFH %.3f, FPFH %.3f, canopy after fitvox %.3f (%d whose chain ran)\n",
                  n, vs / n, fs / n, cn ? cs / cn : 0, cn }' "$tmp/rows"
