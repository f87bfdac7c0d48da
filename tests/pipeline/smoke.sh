#!/usr/bin/env bash
# Pipeline smoke test: every stage piped on the shell, as a user would run it. A two-model
# modelbase (sedan, tank) from unoccluded scans; then a sedan under foliage with 4 mm noise
# must be recognised as the sedan.
set -uo pipefail
src=$1 bin=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
export PATH="$bin:$PATH"
mkdir -p "$tmp/mb"
for m in sedan tank; do
  rangetrace -q --model "$m" --scene unoccluded --seed 11 | fitvox -q | cocone -q \
    | ncut -q --seed 11 -o "$tmp/mb/$m.json" || fail "building the $m model failed"
done
rangetrace -q --model sedan --scene circle --seed 12 | addnoise -q --sigma 4mm --seed 12 \
  | fitvox -q | cocone -q | ncut -q --seed 12 --colored "$tmp/seg.ply" \
  | gmatch --modelbase "$tmp/mb" -o "$tmp/match.json" 2>"$tmp/verdict.txt" || fail "the piped pipeline failed"
cat "$tmp/verdict.txt"
[ -s "$tmp/seg.ply" ] || fail "ncut --colored wrote no PLY"
best=$(grep -m1 '"model":' "$tmp/match.json" | sed 's/.*"model": *"\([^"]*\)".*/\1/')
[ "$best" = sedan ] || fail "the sedan was recognised as '$best'"
grep -q "best sedan" "$tmp/verdict.txt" || fail "the verdict line does not name the sedan"
echo "ok: pipeline smoke test"
