#!/usr/bin/env bash
# families at scale (issue 17; docs/decisions/families.md §11): the generated N-entry modelbase
# built by make, its cost per entry, and gmatch against it with and without the prefilter.
# Usage (from the source root): bench/families/run.sh BUILD_DIR OUT N TRIAL_DIR...
#   1. make -f Makefile.experiments family-modelbase FAM_MB_N=N OUT=OUT -j2 (what is already
#      built is kept), timed: CPU of the whole make; per-entry wall from the stages' .time files.
#   2. For each TRIAL_DIR (a families test trial: .../test/<class>-<n>/<cover>/noise-<mm>/ with
#      segments.json and samples.pcd, e.g. from `make families`): gmatch --threads 1 against
#      OUT/families/modelbase-N with --prefilter 64 (share/params/gmatch.ini) and --prefilter 0,
#      each followed by verify -k 5; CPU per candidate, rank-1 class and verify's class answer.
#      With BUILT=1 step 1 is skipped and OUT's modelbase-N is used as it is (to time tools
#      changed since it was built without re-running its stages).
#   3. With REPLICATE=M (e.g. 1000): gmatch's time per candidate against M models made by
#      repeating the N entries' graphs under other names (hard links in a temporary
#      directory): a timing of the search at M models, not an accuracy (the copies tie).
# Prints one line per trial and method and a summary; writes nothing outside a temporary
# directory and OUT.
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR OUT N TRIAL_DIR...}
out=${2:?usage: $0 BUILD_DIR OUT N TRIAL_DIR...}
n=${3:?usage: $0 BUILD_DIR OUT N TRIAL_DIR...}
shift 3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mb=$out/families/modelbase-$n

if [ "${BUILT:-0}" = 1 ]; then
  [ -d "$mb" ] || { echo "BUILT=1: no $mb" >&2; exit 1; }
  echo "$mb as built (BUILT=1): $(ls "$mb"/*.json | wc -l) entries"
else
  /usr/bin/time -f "%e %U %S" -o "$tmp/make.time" make -f Makefile.experiments family-modelbase FAM_MB_N="$n" \
    OUT="$out" BUILD="$build" -j2 PROGRESS=0 >"$tmp/make.log" 2>&1 || { tail -20 "$tmp/make.log"; exit 1; }
  read -r mw mu ms <"$tmp/make.time"
  built=$(grep -c '/train/.*/noise-0/segments.json' "$tmp/make.log" || true)
  entries=$(ls "$mb"/*.json | wc -l)
  echo "make family-modelbase FAM_MB_N=$n: $entries entries ($built chains run now), ${mw} s wall, $(echo "$mu + $ms" | bc) CPU-s"
  # Wall seconds per entry by stage (render, addnoise, fitvox, cocone, ncut), from .time files.
  for f in "$mb"/*.json; do
    d=$out/families/train/$(basename "$f" .json)
    printf '%s' "$(basename "$f" .json)"
    for s in scan.pcd noise-0/scan.pcd noise-0/samples.pcd noise-0/mesh.ply noise-0/segments.json; do
      printf ' %s' "$(cut -d' ' -f1 "$d/$s.time")"
    done
    echo
  done >"$tmp/entries"
  awk '{ n++; for (i = 2; i <= 6; i++) { s[i] += $i; t += $i } }
       END { printf "per entry (wall, mean of %d): render %.2f, addnoise %.2f, fitvox %.2f, cocone %.2f, ncut %.2f = %.2f s\n",
                    n, s[2] / n, s[3] / n, s[4] / n, s[5] / n, s[6] / n, t / n }' "$tmp/entries"
  du -sk "$mb" "$out/families/train" | awk '{ printf "disk: %s %.1f MB\n", $2, $1 / 1024 }'
fi
entries=$(ls "$mb"/*.json | wc -l)

[ $# -gt 0 ] || exit 0
for d in "$@"; do
  truth=$(echo "$d" | sed 's|.*/test/||' | cut -d/ -f1 | sed 's/-[0-9]*$//')
  for pf in 64 0; do
    /usr/bin/time -f "%U %S %e" -o "$tmp/g.time" "$build/bin/gmatch" --config share/params/gmatch.ini \
      --threads 1 --prefilter "$pf" -i "$d/segments.json" --modelbase "$mb" -o "$tmp/m.json" 2>/dev/null
    read -r u s w <"$tmp/g.time"
    "$build/bin/verify" --config share/params/verify.ini -k 5 -i "$tmp/m.json" --points "$d/samples.pcd" \
      --segments "$d/segments.json" --modelbase "$mb" -o "$tmp/v.json" 2>/dev/null
    rank1=$(jq -r '.models[0].model' "$tmp/m.json")
    echo "$d $truth prefilter=$pf rank1=$rank1 rank1_class=$(cat "$mb/$rank1.class") \
verify_class=$(jq -r '.class // "none"' "$tmp/v.json") cpu=$(echo "$u + $s" | bc)"
  done
done | tee "$tmp/rows"
awk -v n="$entries" '{ split($3, p, "="); split($4, r, "="); split($5, c, "="); split($6, v, "="); split($7, t, "=");
       k = p[2]; m[k]++; rc[k] += (c[2] == $2); vc[k] += (v[2] == $2); cpu[k] += t[2]
       if (t[2] > mx[k]) mx[k] = t[2]; r1[$1, k] = r[2] }
     END { for (k in m) printf "prefilter %s: %d trials, gmatch rank-1 class %d, verify class %d, CPU per candidate mean %.3f s (max %.3f) = %.2f ms per model\n",
                                k, m[k], rc[k], vc[k], cpu[k] / m[k], mx[k], 1000 * cpu[k] / m[k] / n
           same = 0; for (key in r1) { split(key, kk, SUBSEP); if (kk[2] == 64 && r1[kk[1], 0] == r1[key]) same++ }
           printf "same rank-1 model with and without the prefilter: %d of %d\n", same, m[64] }' "$tmp/rows"

[ -n "${REPLICATE:-}" ] || exit 0
rep=$tmp/replicated
mkdir -p "$rep"
ls "$mb"/*.json >"$tmp/graphs"
i=0
while [ "$i" -lt "$REPLICATE" ]; do
  while read -r g && [ "$i" -lt "$REPLICATE" ]; do
    ln "$g" "$rep/r$i-$(basename "$g")" 2>/dev/null || cp "$g" "$rep/r$i-$(basename "$g")"
    i=$((i + 1))
  done <"$tmp/graphs"
done
for d in "$@"; do
  for pf in 64 0; do
    /usr/bin/time -f "%U %S" -o "$tmp/g.time" "$build/bin/gmatch" --config share/params/gmatch.ini \
      --threads 1 --prefilter "$pf" -i "$d/segments.json" --modelbase "$rep" -o "$tmp/m.json" 2>/dev/null
    read -r u s <"$tmp/g.time"
    echo "$pf $(echo "$u + $s" | bc)"
  done
done | awk -v m="$REPLICATE" '{ n[$1]++; c[$1] += $2; if ($2 > x[$1]) x[$1] = $2 }
  END { for (k in n) printf "replicated to %d models, prefilter %s: %d candidates, CPU per candidate mean %.3f s (max %.3f)\n", m, k, n[k], c[k] / n[k], x[k] }'
