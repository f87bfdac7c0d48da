#!/usr/bin/env bash
# The baseline with and without the prepared models' side (--prepare / --model-cache; issue 31,
# docs/decisions/baseline.md §7, cost.md §12): each candidate through OLD_BIN (computes the
# models' side itself) and NEW_BIN --model-cache, in the modes the experiment runs
# (`--verdict vfh`, `--verdict fpfh`, `--methods fpfh`, `--methods vfh`; MODES overrides), one
# after the other per candidate; plus NEW_BIN without the cache (UNCACHED=1). CPU = user + sys
# by GNU time; every output compared with cmp.
# Usage: bench/baseline/cache.sh OLD_BIN NEW_BIN MODELBASE OUT_DIR SAMPLES.pcd...
#   e.g. bench/baseline/cache.sh /tmp/baseline.main build/bin/baseline out/modelbase /tmp/cmp \
#          out/scenes/*/tile-*/noise-*/cands/*/samples.pcd
set -euo pipefail
old=${1:?usage: $0 OLD_BIN NEW_BIN MODELBASE OUT_DIR SAMPLES.pcd...}
new=${2:?usage}
mb=${3:?usage}
out=${4:?usage}
shift 4
modes=${MODES:-"--verdict=vfh --verdict=fpfh --methods=fpfh --methods=vfh"}
mkdir -p "$out"
cpu() { /usr/bin/time -f "%U %S" -o "$out/t" "$@" 2>/dev/null && awk '{ printf "%.2f\n", $1 + $2 }' "$out/t"; }
cfg=share/params/baseline.ini
prep=$(cpu "$new" --config $cfg --prepare --modelbase "$mb" -o "$out/models.bin")
echo "prepare: $prep CPU-s, $(stat -c %s "$out/models.bin") bytes"
i=0
for f in "$@"; do
  [ -s "$f" ] || continue
  i=$((i + 1))
  for m in $modes; do
    tag=${m#--}; tag=${tag/=/-}
    a=$(cpu "$old" --config $cfg "${m%%=*}" "${m#*=}" -i "$f" --modelbase "$mb" -o "$out/$i-$tag.old.json")
    b=$(cpu "$new" --config $cfg "${m%%=*}" "${m#*=}" -i "$f" --modelbase "$mb" --model-cache "$out/models.bin" \
      -o "$out/$i-$tag.new.json")
    c=-
    if [ "${UNCACHED:-0}" = 1 ]; then
      c=$(cpu "$new" --config $cfg "${m%%=*}" "${m#*=}" -i "$f" --modelbase "$mb" -o "$out/$i-$tag.unc.json")
      cmp -s "$out/$i-$tag.old.json" "$out/$i-$tag.unc.json" && c="$c same" || c="$c DIFFERENT"
    fi
    same=DIFFERENT
    cmp -s "$out/$i-$tag.old.json" "$out/$i-$tag.new.json" && same=same
    echo "$f $tag old=$a new=$b $same uncached=$c"
  done
done | tee "$out/rows"
awk -v prep="$prep" '{ split($3, a, "="); split($4, b, "="); n[$2]++; o[$2] += a[2]; w[$2] += b[2]; s[$2] += ($5 == "same") }
     END { for (m in n) { printf "%s: %d runs, %d byte-identical; CPU-s old %.2f -> new %.2f (%.3f -> %.3f per run, %+.1f %%)\n",
                           m, n[m], s[m], o[m], w[m], o[m] / n[m], w[m] / n[m], 100 * (w[m] - o[m]) / o[m] }
           printf "(the prepare, once per modelbase: %.2f CPU-s)\n", prep }' "$out/rows"
