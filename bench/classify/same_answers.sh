#!/usr/bin/env bash
# Do two classify binaries answer every candidate of finished tiles the same? (docs/decisions/
# classify.md §18: main's binary against a branch's on the real tiles' candidates, with
# classify.ini as make tile runs it.) Each TILE_DIR holds cands/index.json and cands/c*.pcd (make
# tile's layout); both binaries run with --config INI --index --modelbase MODELBASE --model-classes
# CLASSES (run from the source tree that holds MODELBASE and CLASSES if they are relative). Writes
# OUT/before|after/<tile>/<id>.json, then prints the number of answers compared, those that differ
# in any key but the provenance (each named), and the answers by class or reason.
#   bench/classify/same_answers.sh BEFORE_BIN AFTER_BIN INI MODELBASE CLASSES OUT TILE_DIR...
set -euo pipefail
[ $# -ge 7 ] || { echo "usage: $0 BEFORE_BIN AFTER_BIN INI MODELBASE CLASSES OUT TILE_DIR..." >&2; exit 2; }
before=$1 after=$2 ini=$3 mb=$4 classes=$5 out=$6
shift 6
for t in "$@"; do
  name=$(basename "$t")
  mkdir -p "$out/before/$name" "$out/after/$name"
  for c in "$t"/cands/c*.pcd; do
    id=$(basename "$c" .pcd)
    for v in before after; do
      bin=$before
      [ "$v" = after ] && bin=$after
      nice "$bin" -q --config "$ini" -i "$c" --index "$t/cands/index.json" --modelbase "$mb" \
        --model-classes "$classes" -o "$out/$v/$name/$id.json"
    done
  done
done
python3 - "$out" <<'EOF'
import collections, glob, json, sys
out = sys.argv[1]
n, differ, by = 0, 0, collections.Counter()
for f in sorted(glob.glob(f'{out}/before/*/*.json')):
    a, b = json.load(open(f)), json.load(open(f.replace('/before/', '/after/')))
    a.pop('provenance'), b.pop('provenance')
    n += 1
    by[a['class'] or a['reason']] += 1
    if a != b:
        differ += 1
        print('differs:', f, a['class'] or a['reason'], '->', b['class'] or b['reason'])
print(f'{n} answers compared, {differ} differ (every key but the provenance)')
print('before, by class or reason:', dict(sorted(by.items())))
EOF
