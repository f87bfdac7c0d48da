#!/usr/bin/env bash
# A user's mistakes in the tile workflow end with the real error alone (docs/decisions/
# hardening.md, stop 67):
# - `make tile` on a truncated LAZ (a cut copy of share/real/ign_lidarhd_870000_6618000.laz) or a
#   truncated PCD: detect's message naming the file and make's "Error" line for the detect step,
#   exit 2, and no "No rule to make target '<OUT>/cands/index.json', needed by '<OUT>/cands.mk'"
#   (GNU make's word for a file that failed while it remade the included plan), with and without
#   -j, on a first run and again; `make -q` then answers 1; the same tile made whole then runs
#   (the plan left by the failure is remade) and `make -q` answers 0;
# - `make tiles` on a directory holding no tile: make's own message alone, without the progress
#   count's "the planning dry run (make -n) failed" before it; on a directory holding the cut
#   tile: detect's message, no "No rule";
# - a planning dry run that fails on something else (the tools' build) still says so;
# - TRAJECTORY= naming a file that is not a trajectory is refused before detect runs, naming the
#   file and the problem (stop 71: detect, classify and every model chain ran, every verify
#   failed, exit 0); a trajectory runs as before;
# - a second `make tile` with nothing to do shows collect's summary and warning again, the same
#   lines (stop 71: "Nothing to be done for 'tile'");
# - an entry added to MODELBASE as an older file, or removed, re-runs the stages that read the
#   modelbase, not detect (stop 71, review F21: "up to date", answers naming a model gone);
# - TILE_DETECT, TILE_FITVOX, TILE_CLASSIFY, MODEL_CLASSES naming no file and a TILE_MODEL_DENSITY
#   that is no number are refused before anything is written (stop 71, review F12: a missing
#   TILE_FITVOX ran detect, then "No rule to make target"; the others left OUT/.progress*).
set -uo pipefail
src=$1 bin=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
for t in detect collect topview stagerun verify; do
  [ -x "$bin/$t" ] || fail "$bin/$t is not built"
done
laz=$src/share/real/ign_lidarhd_870000_6618000.laz
[ -f "$laz" ] || fail "$laz missing"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# A build directory of links to the tested binaries (no cmake run, no dependency install).
mkdir -p "$tmp/build/bin" && touch "$tmp/build/CMakeCache.txt" "$tmp/build/.deps-stamp"
for t in "$bin"/*; do ln -s "$t" "$tmp/build/bin/"; done
mk=(make -C "$src" --no-print-directory -f Makefile.experiments BUILD="$tmp/build" CMAKE=true)
# A modelbase directory (the workflow requires a <model>.json; detect fails before any reads it).
mkdir -p "$tmp/mb" && echo '{}' >"$tmp/mb/m.json"

# refused LOG TILE: the run failed in detect, saying so once, as it should.
refused() {
  local log=$1 tile=$2
  grep -q "detect: error: $tile: " "$log" || fail "$log: no detect message naming $tile: $(tail -3 "$log")"
  ! grep -q "No rule to make target" "$log" || fail "$log: $(grep -m1 'No rule' "$log")"
  ! grep -q "No such file or directory" "$log" || fail "$log: $(grep -m1 'No such file' "$log")"
  tail -1 "$log" | grep -qE "^make: \*\*\* \[[^]]*: $tmp/out[^]]*/cands/index.json\] Error 1$" \
    || fail "$log: the last line is not make's Error line of detect: $(tail -1 "$log")"
}

head -c 300000 "$laz" >"$tmp/cut.laz"
for j in -j2 ""; do
  for run in first again; do
    "${mk[@]}" $j tile TILE="$tmp/cut.laz" MODELBASE="$tmp/mb" OUT="$tmp/out-laz$j/" >"$tmp/laz.log" 2>&1
    rc=$?
    [ $rc -eq 2 ] || fail "make tile $j on a cut LAZ ($run run) exits $rc, want 2: $(tail -3 "$tmp/laz.log")"
    refused "$tmp/laz.log" "$tmp/cut.laz"
  done
done
echo "ok: a cut LAZ ends with detect's message and make's Error line"

# A cut PCD, then the same file whole: the plan the failure left is remade.
awk 'BEGIN { n = 3600; print "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " n \
  "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " n "\nDATA ascii"
  for (i = 0; i < 60; i++) for (j = 0; j < 60; j++) printf "%.2f %.2f 100\n", 500000 + i / 2, 5400000 + j / 2 }' \
  >"$tmp/flat.pcd"
head -c 2000 "$tmp/flat.pcd" >"$tmp/tile.pcd"
"${mk[@]}" -j2 tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >"$tmp/pcd.log" 2>&1
rc=$?
[ $rc -eq 2 ] || fail "make tile on a cut PCD exits $rc, want 2: $(tail -3 "$tmp/pcd.log")"
refused "$tmp/pcd.log" "$tmp/tile.pcd"
"${mk[@]}" -q tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >/dev/null 2>&1
rc=$?
[ $rc -eq 1 ] || fail "make -q tile after a failed detect exits $rc, want 1"
cp "$tmp/flat.pcd" "$tmp/tile.pcd"
"${mk[@]}" -j2 tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >"$tmp/pcd2.log" 2>&1 \
  || fail "make tile on the whole tile after a failed one failed: $(tail -3 "$tmp/pcd2.log")"
grep -qx "TILE_CANDS :=" "$tmp/out-pcd/cands.mk" || fail "the plan was not remade: $(cat "$tmp/out-pcd/cands.mk")"
[ "$(jq '.candidates' "$tmp/out-pcd/detections.json")" = 0 ] || fail "a flat tile has candidates"
# A tile without candidates says why (stop 70: it said nothing), on make's output and in the file.
grep -q "^$tmp/out-pcd: warning: no candidate on this tile of 0\.[0-9]* ha" "$tmp/pcd2.log" \
  || fail "no warning for a tile without candidates: $(grep -v '^done' "$tmp/pcd2.log" | tail -3)"
jq -e '.warning | startswith("no candidate on this tile")' "$tmp/out-pcd/detections.json" >/dev/null \
  || fail "detections.json has no warning for a tile without candidates"
# Shown once, after the run's stages; and again, the same lines, by a run with nothing to do.
grep "^$tmp/out-pcd: " "$tmp/pcd2.log" >"$tmp/said1.txt"
[ "$(grep -c "^$tmp/out-pcd: 0 candidates: 0 vehicles found (0 model level, 0 class level)$" "$tmp/said1.txt")" = 1 ] \
  || fail "the summary is not shown once: $(cat "$tmp/said1.txt")"
"${mk[@]}" -j2 tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >"$tmp/pcd3.log" 2>&1 \
  || fail "make tile again failed: $(tail -3 "$tmp/pcd3.log")"
! grep -q "^done\|Nothing to be done" "$tmp/pcd3.log" || fail "make tile with nothing to do: $(head -3 "$tmp/pcd3.log")"
grep -v "^built \|^new " "$tmp/pcd3.log" >"$tmp/said2.txt"
cmp -s "$tmp/said1.txt" "$tmp/said2.txt" \
  || fail "a second make tile does not show the first one's summary and warning: $(cat "$tmp/said2.txt")"
"${mk[@]}" -q tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >/dev/null 2>&1 \
  || fail "make -q tile after the run exits $?, want 0"
echo "ok: after a cut PCD, the whole one runs and is then up to date, and a re-run shows its summary again"

# TRAJECTORY= a file that is not a trajectory: refused before detect, naming the file and the
# problem in verify's own words, exit 2; a trajectory: the run as without the check.
printf '%s\n' 'time,x,y,z' '0,500000,5400000,300' >"$tmp/notes.csv"
"${mk[@]}" -j2 tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-traj/" TRAJECTORY="$tmp/notes.csv" \
  >"$tmp/traj.log" 2>&1
rc=$?
[ $rc -eq 2 ] || fail "make tile TRAJECTORY=<not a trajectory> exits $rc, want 2: $(tail -3 "$tmp/traj.log")"
grep -q "^verify: error: $tmp/notes.csv: line 1: " "$tmp/traj.log" \
  && grep -q "^tile: TRAJECTORY=$tmp/notes.csv is not a canopy trajectory" "$tmp/traj.log" \
  || fail "no error naming the trajectory and its problem: $(cat "$tmp/traj.log")"
! grep -q "^done\|^detect: " "$tmp/traj.log" && [ ! -e "$tmp/out-traj/cands" ] \
  || fail "a stage ran before the trajectory was refused: $(grep -m1 '^done\|^detect: ' "$tmp/traj.log")"
printf '%s\n' '# canopy trajectory 1' 'time x y z roll pitch heading' '0 500000 5399950 500 0 0 0' \
  '10 500000 5400050 500 0 0 0' >"$tmp/good.traj"
"${mk[@]}" -j2 tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-traj/" TRAJECTORY="$tmp/good.traj" \
  >"$tmp/traj2.log" 2>&1 || fail "make tile with a trajectory failed: $(tail -3 "$tmp/traj2.log")"
[ "$(jq '.candidates' "$tmp/out-traj/detections.json")" = 0 ] || fail "make tile with a trajectory: no detections.json"
! grep -q "trajectory" "$tmp/traj2.log" || fail "a trajectory said something: $(grep -m1 trajectory "$tmp/traj2.log")"
"${mk[@]}" -q tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-traj/" TRAJECTORY="$tmp/good.traj" \
  >/dev/null 2>&1 || fail "make -q tile with a trajectory after its run exits $?, want 0"
echo "ok: a TRAJECTORY that is not a trajectory is refused before detect"

# Another tile into the same OUT, older than the first run's files: detect and what follows run
# again on it (stop 70: "Nothing to be done" and the first tile's results); the same again: nothing.
awk 'NR <= 10 { sub(/^WIDTH .*/, "WIDTH 3000"); sub(/^POINTS .*/, "POINTS 3000"); print; next } NR <= 3010' \
  "$tmp/flat.pcd" >"$tmp/older.pcd"
touch -d @1000000000 "$tmp/older.pcd"
"${mk[@]}" -j2 tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >"$tmp/older.log" 2>&1 \
  || fail "make tile on another tile into the same OUT failed: $(tail -3 "$tmp/older.log")"
[ "$(jq -r '.tile' "$tmp/out-pcd/detections.json")" = "$tmp/older.pcd" ] ||
  fail "an older tile into the same OUT kept the first tile's detections: $(jq -r '.tile' "$tmp/out-pcd/detections.json")"
grep -q "^done .*out-pcd/detect " "$tmp/older.log" || fail "detect did not run on the other tile: $(head -3 "$tmp/older.log")"
"${mk[@]}" -q tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-pcd/" >/dev/null 2>&1 \
  || fail "make -q tile after the other tile's run exits $?, want 0"
# Another modelbase: the stages that read it run again (collect), detect does not.
mkdir -p "$tmp/mb2" && echo '{}' >"$tmp/mb2/m.json" && touch -d @1000000000 "$tmp/mb2/m.json"
"${mk[@]}" -j2 tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb2" OUT="$tmp/out-pcd/" >"$tmp/mb2.log" 2>&1 \
  || fail "make tile with another modelbase failed: $(tail -3 "$tmp/mb2.log")"
grep -q "^done .*out-pcd/detections.json " "$tmp/mb2.log" || fail "collect did not run with another modelbase: $(cat "$tmp/mb2.log")"
! grep -q "^done .*out-pcd/detect " "$tmp/mb2.log" || fail "another modelbase re-ran detect"
# The same modelbase with an entry added as an older file (cp -p, mv, tar x), then removed again
# (stop 71, review F21: both left the tile "up to date", its answers naming a model gone): the
# stages that read the modelbase run again, detect does not; the options texts of the kinds that
# read it name its entries, the others do not.
cp -p "$tmp/mb2/m.json" "$tmp/mb2/n.json" && printf 'x\n' >"$tmp/mb2/n.class" && touch -d @1000000000 "$tmp/mb2/n.class"
for change in added removed; do
  "${mk[@]}" -q tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb2" OUT="$tmp/out-pcd/" >/dev/null 2>&1 &&
    fail "make -q tile exits 0 after an entry was $change in the modelbase"
  "${mk[@]}" -j2 tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb2" OUT="$tmp/out-pcd/" >"$tmp/mb3.log" 2>&1 \
    || fail "make tile after an entry was $change failed: $(tail -3 "$tmp/mb3.log")"
  grep -q "^done .*out-pcd/detections.json " "$tmp/mb3.log" || fail "collect did not run after an entry was $change: $(cat "$tmp/mb3.log")"
  ! grep -q "^done .*out-pcd/detect " "$tmp/mb3.log" || fail "an entry $change re-ran detect"
  "${mk[@]}" -q tile TILE="$tmp/older.pcd" MODELBASE="$tmp/mb2" OUT="$tmp/out-pcd/" >/dev/null 2>&1 \
    || fail "make -q tile after the run with an entry $change exits $?, want 0"
  want="entry = m.json 3 1000000000"
  [ $change = added ] && want="$want|entry = n.class 2 1000000000|entry = n.json 3 1000000000"
  for k in classify collect tile-modelbase; do
    [ "$(grep '^entry = ' "$tmp/out-pcd/.opts/$k.txt" | paste -sd'|')" = "$want" ] ||
      fail "entry $change: .opts/$k.txt: $(cat "$tmp/out-pcd/.opts/$k.txt")"
  done
  ! grep -q '^entry' "$tmp/out-pcd/.opts/detect.txt" "$tmp/out-pcd/.opts/models.txt" || fail "detect's or the model chain's options name the entries"
  rm -f "$tmp/mb2/n.json" "$tmp/mb2/n.class"
done
echo "ok: another tile or modelbase into the same OUT runs again, and so does a modelbase that lost or gained an entry"

# Arguments refused before anything is written (stop 70: OUT and OUT/.progress* were left behind).
"${mk[@]}" tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" >"$tmp/noout.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "tile: give OUT=<the output directory>" "$tmp/noout.log" ||
  fail "make tile without OUT exits $rc: $(tail -2 "$tmp/noout.log")"
"${mk[@]}" tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/nomb" OUT="$tmp/out-refused" >"$tmp/nomb.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "MODELBASE=$tmp/nomb holds no <model>.json" "$tmp/nomb.log" ||
  fail "make tile without a modelbase exits $rc: $(tail -2 "$tmp/nomb.log")"
[ ! -e "$tmp/out-refused" ] || fail "a refused make tile left $tmp/out-refused: $(ls -A "$tmp/out-refused")"
# The stages' parameters (stop 71, review F12: a missing TILE_FITVOX ran detect and the plan,
# then stopped on make's "No rule to make target"; the other four left OUT/.progress*).
for bad in "TILE_DETECT=$tmp/nofile.ini|tile: TILE_DETECT=$tmp/nofile.ini does not exist (detect's parameters)" \
    "TILE_FITVOX=$tmp/nofile.ini|tile: TILE_FITVOX=$tmp/nofile.ini does not exist (fitvox's parameters" \
    "TILE_CLASSIFY=$tmp/nofile.ini|tile: TILE_CLASSIFY=$tmp/nofile.ini does not exist (classify's parameters)" \
    "MODEL_CLASSES=$tmp/nofile.csv|tile: MODEL_CLASSES=$tmp/nofile.csv does not exist" \
    "TILE_FITVOX=|tile: TILE_FITVOX is empty" \
    "TILE_MODEL_DENSITY=abc|tile: TILE_MODEL_DENSITY=abc must be a number of points/m²"; do
  "${mk[@]}" -j2 tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-refused" "${bad%%|*}" >"$tmp/param.log" 2>&1
  rc=$?
  [ $rc -eq 2 ] && grep -qF "${bad#*|}" "$tmp/param.log" || fail "make tile ${bad%%|*} exits $rc: $(tail -2 "$tmp/param.log")"
  [ ! -e "$tmp/out-refused" ] || fail "make tile ${bad%%|*} left $tmp/out-refused: $(ls -A "$tmp/out-refused")"
done
"${mk[@]}" -j2 tiles TILES="$tmp/none" MODELBASE="$tmp/mb" OUT="$tmp/out-refused" TILE_FITVOX="$tmp/nofile.ini" >"$tmp/param.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -qF "tiles: TILE_FITVOX=$tmp/nofile.ini does not exist" "$tmp/param.log" && [ ! -e "$tmp/out-refused" ] ||
  fail "make tiles TILE_FITVOX=<missing> exits $rc: $(tail -2 "$tmp/param.log")"
mkdir -p "$tmp/in dir" && cp "$tmp/flat.pcd" "$tmp/in dir/my tile.pcd"
"${mk[@]}" tile TILE="$tmp/in dir/my tile.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-blank" >"$tmp/blank.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "TILE=$tmp/in dir/my tile.pcd holds a blank: make cannot handle file names with spaces" \
  "$tmp/blank.log" || fail "a tile name with a blank exits $rc: $(tail -2 "$tmp/blank.log")"
"${mk[@]}" tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out blank" >"$tmp/blank2.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "OUT=$tmp/out blank holds a blank" "$tmp/blank2.log" && [ ! -e "$tmp/out" ] ||
  fail "an OUT with a blank exits $rc or made $tmp/out: $(tail -2 "$tmp/blank2.log")"
echo "ok: make tile's arguments refused before anything is written"

# make tiles: an empty directory (make's message alone), one with the cut tile.
mkdir -p "$tmp/none" "$tmp/bad"
"${mk[@]}" tiles TILES="$tmp/none" MODELBASE="$tmp/mb" OUT="$tmp/out-none/" >"$tmp/none.log" 2>&1
rc=$?
[ $rc -eq 2 ] || fail "make tiles on an empty directory exits $rc, want 2"
[ "$(wc -l <"$tmp/none.log")" -eq 1 ] && grep -q "tiles: TILES=$tmp/none holds no .las, .laz or .pcd file" "$tmp/none.log" \
  || fail "make tiles on an empty directory does not say so alone: $(cat "$tmp/none.log")"
cp "$tmp/cut.laz" "$tmp/bad/"
"${mk[@]}" -j2 tiles TILES="$tmp/bad" MODELBASE="$tmp/mb" OUT="$tmp/out-bad/" >"$tmp/bad.log" 2>&1
rc=$?
[ $rc -eq 2 ] || fail "make tiles on a cut tile exits $rc, want 2"
grep -q "detect: error: $tmp/bad/cut.laz: " "$tmp/bad.log" || fail "make tiles: no detect message: $(tail -3 "$tmp/bad.log")"
! grep -q "No rule to make target\|planning dry run" "$tmp/bad.log" || fail "make tiles: $(grep -m1 'No rule\|planning' "$tmp/bad.log")"
echo "ok: make tiles on an empty directory and on a cut tile"

# make tiles takes an extension in upper case (stop 70: "holds no .las, .laz or .pcd file").
mkdir -p "$tmp/upper" && cp "$tmp/flat.pcd" "$tmp/upper/PLOT1.PCD"
"${mk[@]}" -j2 tiles TILES="$tmp/upper" MODELBASE="$tmp/mb" OUT="$tmp/out-upper/" >"$tmp/upper.log" 2>&1 ||
  fail "make tiles on PLOT1.PCD failed: $(tail -3 "$tmp/upper.log")"
[ -f "$tmp/out-upper/PLOT1/detections.json" ] || fail "make tiles did not run PLOT1.PCD: $(tail -3 "$tmp/upper.log")"
echo "ok: make tiles on an upper-case extension"

# A planning dry run that fails on the tools' build still says so, naming its log.
"${mk[@]}" tile TILE="$tmp/flat.pcd" MODELBASE="$tmp/mb" OUT="$tmp/out-cmake/" CMAKE=false >"$tmp/cmake.log" 2>&1 \
  && fail "make tile with CMAKE=false succeeded"
grep -q "^progress: the planning dry run (make -n) failed with status 2; .*(its errors: $tmp/out-cmake/.progress-plan.log)" \
  "$tmp/cmake.log" || fail "a failing planning dry run was not reported: $(head -3 "$tmp/cmake.log")"
echo "ok: tile errors"
