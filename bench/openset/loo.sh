#!/usr/bin/env bash
# classify's class on the open set's MODELBASE instances, each left out (docs/decisions/open-set.md,
# fourth round): development data that is not the test instances. Each modelbase instance of
# share/vehicles (split.csv) is rendered alone with the open set's crop recipe (mk/openset.mk) at
# each spacing and seed, detect makes its candidate, and classify (classify-sim.ini + each
# variant's options) answers with a modelbase of the OTHER instances (links to MODELBASE's
# entries); loo.py prints the answers and the class right per variant and spacing.
#   bench/openset/loo.sh OUT_DIR MODELBASE   (MODELBASE: `make openset`'s out/openset/modelbase)
#   (BIN=build/bin; SEEDS="101 102 103"; SPACINGS="40mm 422mm" (2 680 and 25 points/m²);
#    VARIANTS="name=opt,opt ..." default "ranges= only=--modelbase-classes-only=1")
# Never the open set's seeds (31-34).
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 OUT_DIR MODELBASE" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin} out=$1 mb=$(cd "$2" && pwd)
seeds=${SEEDS:-101 102 103} spacings=${SPACINGS:-40mm 422mm}
mkdir -p "$out"
: >"$out/runs.txt"
while IFS=, read -r name cls split; do
  [ "$split" = modelbase ] || continue
  file=$(awk -F, -v n="$name" '$1 == n { print $3 }' "$src/share/vehicles/catalogue.csv")
  lmb=$out/mb-$name
  mkdir -p "$lmb"
  for f in "$mb"/*; do
    b=$(basename "$f")
    [[ $b == "${cls}__${name}".* ]] || ln -sf "$f" "$lmb/$b"
  done
  for seed in $seeds; do
    for sp in $spacings; do
      d=$out/$name/s$seed-$sp
      mkdir -p "$d"
      if [ ! -s "$d/cands/index.json" ]; then
        printf '%s\n' "extent = 20m" "terrain = flat" "trees = 0" "bushes = 0" \
          "vehicles = random 1 from $src/share/vehicles/$file" "flight_lines = 2" \
          "headings = 0deg 90deg" "looks = 75deg/0deg 75deg/180deg" "spacing = $sp" >"$d/recipe.scene"
        nice "$bin/rangetrace" -q --scene "$d/recipe.scene" --seed "$(printf '%s' "loo/$name/$seed" | cksum | cut -d' ' -f1)" \
          --threads 1 -o "$d/scan.pcd" --truth "$d/truth.json"
        nice "$bin/detect" -q --no-classes -i "$d/scan.pcd" -o "$d/cands"
        rm -f "$d/scan.pcd"
      fi
      echo "$name $cls $d $lmb" >>"$out/runs.txt"
    done
  done
done < <(tail -n +2 "$src/share/vehicles/split.csv")
# shellcheck disable=SC2086
python3 "$src/bench/openset/loo.py" "$bin" "$src" "$out/runs.txt" ${VARIANTS:-ranges= only=--modelbase-classes-only=1}
