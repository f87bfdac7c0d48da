#!/usr/bin/env bash
# classify's object link on real tiles (docs/decisions/classify.md §21): per tile, detect's
# candidates (as `make tile` makes them), classify on every candidate with each variant, collect,
# score against TRUTH_DIR/<tile>.truth.json, and bench/classify/realcal.py --figures per variant;
# then the candidates whose answer differs from the first variant's.
#   TRUTH_DIR=DIR bench/classify/link.sh OUT_DIR TILE.laz [TILE.laz ...]
#   (BIN=build/bin; INI=share/params/classify.ini; VARIANTS="name:extra classify args" ...;
#   JOBS=2 classify processes; MODELBASE=DIR passes --modelbase DIR --model-classes share/models/classes.csv to classify and
#   --modelbase to collect, as `make tile` does)
# Development tiles only while developing (ahn3_delft_1, forest_bcts_1 from the shared data, the
# two AHN4 development tiles of stop 47); the held-out tiles once (docs/decisions/real-tiles.md).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OUT_DIR TILE.laz [TILE.laz ...]" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
out=$1
shift
ini=${INI:-$src/share/params/classify.ini}
truth_dir=${TRUTH_DIR:-$src/share/real}
variants=${VARIANTS:-"before:--bridge=0 bridge:--bridge=1m"}
mb=()
[ -z "${MODELBASE:-}" ] || mb=(--modelbase "$MODELBASE")
cls_mb=""
[ -z "${MODELBASE:-}" ] || cls_mb="--modelbase $MODELBASE --model-classes $src/share/models/classes.csv"
tiles=()
for laz in "$@"; do
  t=$(basename "$laz" .laz)
  tiles+=("$t")
  mkdir -p "$out/cands"
  [ -s "$out/cands/$t/index.json" ] || "$bin/detect" -q -i "$laz" -o "$out/cands/$t"
done
names=()
for v in $variants; do
  name=${v%%:*}
  names+=("$name")
  args=${v#*:}
  args=${args//,/ }
  args=${args//=/ }
  for t in "${tiles[@]}"; do
    d=$out/$name/$t
    mkdir -p "$d/cands"
    cp "$out/cands/$t/index.json" "$d/cands/"
    for p in "$out/cands/$t"/*.pcd; do ln -sf "$(cd "$(dirname "$p")" && pwd)/$(basename "$p")" "$d/cands/"; done
    for p in "$d/cands"/*.pcd; do
      id=$(basename "$p" .pcd)
      mkdir -p "$d/cands/$id"
      echo "$bin/classify -q --config $ini $args $cls_mb -i $p --index $d/cands/index.json -o $d/cands/$id/class.json"
    done | xargs -P"${JOBS:-2}" -I{} sh -c '{}'
    "$bin/collect" -q -i "$d/cands/index.json" -o "$d/detections.json" "${mb[@]}" 2>/dev/null
    truth=$truth_dir/$t.truth.json
    [ ! -f "$truth" ] || "$bin/score" -q -d "$d/detections.json" -t "$truth" -o "$d/score.json"
  done
  echo "== $name (${args:-defaults})"
  python3 "$src/bench/classify/realcal.py" "$out/$name" "$truth_dir" "${tiles[@]}" --figures
done
# Per candidate: the answers that differ from the first variant's.
python3 - "$out" "${names[@]}" -- "${tiles[@]}" <<'PY'
import json, os, sys
out = sys.argv[1]
k = sys.argv.index("--")
names, tiles = sys.argv[2:k], sys.argv[k + 1:]
def answer(n, t, c):
    j = json.load(open(os.path.join(out, n, t, "cands", c, "class.json")))
    m = j.get("measured") or {}
    size = "x".join("%.2f" % v for v in m.get("size") or [])
    return (j["class"] or j["reason"]), size
for t in tiles:
    ids = sorted(os.path.basename(p)[:-4] for p in os.listdir(os.path.join(out, "cands", t)) if p.endswith(".pcd"))
    for n in names[1:]:
        for c in ids:
            a, b = answer(names[0], t, c), answer(n, t, c)
            if a != b:
                print(f"{n} {t} {c}: {a[0]} {a[1]} -> {b[0]} {b[1]}")
PY
