#!/usr/bin/env bash
# The experiment graph rebuilds only what changed: on a complete (fake) artifact tree for one
# trial, `make -q all` exits 0; after touching share/params/ncut.ini, `make -n` plans ncut and
# what follows (modelbase, gmatch, report, figures) and nothing before it.
set -u
src=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cd "$src" || exit 1
mk=(make -f Makefile.experiments OBJECTS=sedan SCENES=unoccluded NOISES=0 ABLATIONS= OUT="$tmp/out"
    RES="$tmp/res" BUILD="$tmp/build" P="$tmp/params")

# Fake binaries must be newer than every source file, artifacts newer than the binaries.
newest=$(find common formats tools share CMakeLists.txt -type f -printf '%T@\n' | sort -n | tail -1)
now=$(( $(date +%s) > ${newest%.*} + 100 ? $(date +%s) : ${newest%.*} + 100 ))
at() { touch -d "@$1" "${@:2}"; }
mkdir -p "$tmp/build/bin" "$tmp/params" "$tmp/out/sedan/unoccluded/noise-0" "$tmp/out/modelbase" \
  "$tmp/res/figures" "$tmp/res/pictures"
cp share/params/*.ini "$tmp/params/"
at $((now - 100)) "$tmp/params/"*.ini
touch "$tmp/build/.deps-stamp" "$tmp/build/CMakeCache.txt"
for t in rangetrace addnoise fitvox cocone ncut gmatch report figures; do : >"$tmp/build/bin/$t"; done
at $((now - 90)) "$tmp/build/bin/"*
c="$tmp/out/sedan/unoccluded"
r="$tmp/res"
i=80
for f in "$c/scan.pcd" "$c/noise-0/scan.pcd" "$c/noise-0/samples.pcd" "$c/noise-0/mesh.ply" \
         "$c/noise-0/segments.json" "$c/noise-0/segments.ply" "$tmp/out/modelbase/sedan.json" \
         "$c/noise-0/match.json" "$r/report.md" "$r/cases.csv" "$r/scores.csv" "$r/times.csv" \
         "$r/figures/sedan-unoccluded-0.png" "$r/figures/grid-unoccluded.png" "$r/figures/scores.png" \
         "$r/pictures/sedan.png" "$r/pictures/tank-circle.png"; do
  : >"$f"; at $((now - i)) "$f"; i=$((i - 2))
done

"${mk[@]}" -q all || fail "make -q all is not clean on a complete tree: $("${mk[@]}" -n all 2>&1 | head -5)"

# A deleted intermediate artifact is rebuilt, not silently skipped, and nothing before it.
cp -p "$c/noise-0/mesh.ply" "$tmp/mesh.keep" && rm "$c/noise-0/mesh.ply"
plan=$("${mk[@]}" -n all 2>&1)
echo "$plan" | grep -q "bin/cocone " || fail "a deleted mesh.ply is not rebuilt"
if echo "$plan" | grep -q "bin/fitvox "; then fail "fitvox re-planned, but only mesh.ply was deleted"; fi
mv "$tmp/mesh.keep" "$c/noise-0/mesh.ply"
"${mk[@]}" -q all || fail "make -q all not clean after restoring mesh.ply"

at $((now - 10)) "$tmp/params/ncut.ini"
plan=$("${mk[@]}" -n all 2>&1)
echo "$plan" | grep -q "bin/ncut " || fail "ncut not re-planned after ncut.ini changed"
echo "$plan" | grep -q "bin/gmatch " || fail "gmatch not re-planned"
echo "$plan" | grep -q "bin/report " || fail "report not re-planned"
echo "$plan" | grep -q "figures mesh" || fail "segmentation figure not re-planned"
for early in rangetrace addnoise fitvox cocone; do
  if echo "$plan" | grep -q "bin/$early "; then fail "$early re-planned, but only ncut.ini changed"; fi
done

at $((now - 5)) "$tmp/params/fitvox.ini"
plan=$("${mk[@]}" -n all 2>&1)
echo "$plan" | grep -q "bin/fitvox " || fail "fitvox not re-planned after fitvox.ini changed"
echo "$plan" | grep -q "bin/cocone " || fail "cocone not re-planned after fitvox.ini changed"
if echo "$plan" | grep -q "bin/addnoise "; then fail "addnoise re-planned, but only fitvox.ini changed"; fi
echo "ok: make graph"
