#!/usr/bin/env bash
# classify's flight-pass rule on real tiles (docs/decisions/classify.md §14): per tile, detect's
# candidates (as `make tile` makes them), classify on every candidate with the defaults and with
# each ablation, collect, score, and bench/classify/realcal.py --figures per variant.
#   bench/classify/passes.sh OUT_DIR TILE.laz [TILE.laz ...]
#   (BIN=build/bin; VARIANTS="name:extra classify args" ...; default: the new defaults, the
#   measurement alone, the threshold alone and main's "every pass, 0.40"; MODELBASE=DIR passes
#   --modelbase DIR --model-classes share/models/classes.csv to classify and --modelbase to collect,
#   as `make tile` and bench/detect/real.sh do; INI=classify.ini to use; TRUTH_DIR=DIR of
#   <tile>.truth.json, default share/real; JOBS=2 classify processes; DIFF=1 then lists the
#   candidates whose answer differs from the first variant's; DETECT_ARGS="--opt value ..." extra
#   detect arguments, default none)
# Development tiles only while developing (ahn3_delft_1, forest_bcts_1 from the shared data);
# the held-out tiles once (docs/decisions/real-tiles.md: the split).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OUT_DIR TILE.laz [TILE.laz ...]" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$src/build/bin}
out=$1
shift
ini=${INI:-$src/share/params/classify.ini}
truth_dir=${TRUTH_DIR:-$src/share/real}
variants=${VARIANTS:-"defaults: measurement:--max-ground-through=0.40 threshold:--by-pass=false every-pass-0.40:--by-pass=false,--max-ground-through=0.40"}
mb=()
[ -z "${MODELBASE:-}" ] || mb=(--modelbase "$MODELBASE")
cls_mb=""
[ -z "${MODELBASE:-}" ] || cls_mb="--modelbase $MODELBASE --model-classes $src/share/models/classes.csv"
tiles=()
for laz in "$@"; do
  t=$(basename "$laz" .laz)
  tiles+=("$t")
  mkdir -p "$out/cands"
  # shellcheck disable=SC2086  # DETECT_ARGS: words
  [ -s "$out/cands/$t/index.json" ] || "$bin/detect" -q ${DETECT_ARGS:-} -i "$laz" -o "$out/cands/$t"
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
# DIFF=1: per candidate, the answers that differ from the first variant's.
[ "${DIFF:-0}" = 1 ] || exit 0
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
