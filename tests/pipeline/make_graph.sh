#!/usr/bin/env bash
# The experiment graph rebuilds only what changed: on a complete (fake) artifact tree for one
# trial, `make -q all` exits 0; after touching share/params/ncut.ini, `make -n` plans ncut and
# what follows (modelbase, gmatch, report, figures) and nothing before it. Exact rebuilds:
# touching a doc plans nothing; touching a source that relinks a tool to the same bytes plans
# no stage (content stamps); a tool whose bytes change re-plans its stage and what follows.
# Runs on a copy of the source tree (its mtimes are changed) with a fake CMake that "builds"
# a tool by writing $tmp/content/<tool> (default: a fixed text) to the binary.
# Options as prerequisites: a changed option variable (COLLECT_CALIBRATION, TILE_DENSITY_SCALE,
# TOP_RASTER, CRS, P) re-plans exactly the stages whose command it changes; the same command again
# plans nothing (on a fake scene run and a fake `make tile`).
set -u
src=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
tree="$tmp/src"
mkdir -p "$tree"
(cd "$src" && cp -a Makefile.experiments CMakeLists.txt common formats documents tools scripts share mk "$tree/") ||
  fail "cannot copy the source tree"
# (the scene experiment's classify ablations' parameter files, mk/scenes.mk SCENES_CLASSIFY_ABLATION[_2],
# and the density ladder's detect ablation's, mk/density.mk DENSITY_DETECT_ABLATIONS)
mkdir -p "$tree/bench/density" && cp -a "$src"/bench/density/classify-sim-*.ini "$src"/bench/density/detect-*.ini "$tree/bench/density/" ||
  fail "cannot copy bench/density's parameter files"
cd "$tree" || exit 1
# The fake build also leaves the records CMake's Makefile generator keeps, which
# scripts/tool-deps.sh reads (checked against the real build at the end): per target a
# DependInfo.cmake naming its sources, their depfiles and the targets it links. Every tool links
# canopy_documents, canopy_formats and canopy_common (tools/CMakeLists.txt); no tool links
# another tool's library (report read areas.json through tools/areas' library until issue 30). Depfiles name files relative to the target's build directory (as with
# ccache's base_dir) or, for common/, absolute (as without).
cat >"$tmp/records.sh" <<'REC'
#!/usr/bin/env bash
# records.sh BUILD TREE TARGET DIR LINKED-DIR...: the records of a target built from DIR's files.
b=$1 tree=$2 target=$3 dir=$4
shift 4
d="$b/$dir/CMakeFiles/$target.dir"
mkdir -p "$d"
{
  echo 'set(CMAKE_DEPENDS_DEPENDENCY_FILES'
  for src in $(cd "$tree" && find "$dir" -name '*.cpp' | sort); do
    o="$dir/CMakeFiles/$target.dir/$(basename "$src").o"
    echo "  \"$tree/$src\" \"$o\" \"gcc\" \"$o.d\""
    {
      echo "$o: \\"
      for h in "$src" $(cd "$tree" && find "$dir" -name '*.h' | sort); do
        case "$dir" in
          common) echo " $tree/$h \\" ;;
          *) echo " $(realpath -m --relative-to="$b/$dir" "$tree/$h") \\" ;;
        esac
      done
      echo " /usr/include/stdc-predef.h"
    } >"$b/$o.d"
  done
  echo '  )'
  echo 'set(CMAKE_TARGET_LINKED_INFO_FILES'
  for l in "$@"; do echo "  \"$b/$l/DependInfo.cmake\""; done
  echo '  )'
} >"$d/DependInfo.cmake"
REC
chmod +x "$tmp/records.sh"
cat >"$tmp/cmake" <<EOF
#!/usr/bin/env bash
# fake cmake --build DIR --target TOOL ...: writes the tool's content to DIR/bin/TOOL.
[ "\$1" = --build ] || exit 1
t=\$4
echo "\$t" >>"$tmp/cmake.calls"
if [ -f "$tmp/content/\$t" ]; then cat "$tmp/content/\$t"; else echo "binary \$t v1"; fi >"$tmp/build/bin/\$t.new"
# a real build leaves an unchanged binary alone; only a changed one is replaced
cmp -s "$tmp/build/bin/\$t.new" "$tmp/build/bin/\$t" && rm "$tmp/build/bin/\$t.new" || mv "$tmp/build/bin/\$t.new" "$tmp/build/bin/\$t"
libs="documents/CMakeFiles/canopy_documents.dir formats/CMakeFiles/canopy_formats.dir common/CMakeFiles/canopy_common.dir"
"$tmp/records.sh" "$tmp/build" "$tree" canopy_common common
"$tmp/records.sh" "$tmp/build" "$tree" canopy_formats formats common/CMakeFiles/canopy_common.dir
"$tmp/records.sh" "$tmp/build" "$tree" canopy_documents documents formats/CMakeFiles/canopy_formats.dir common/CMakeFiles/canopy_common.dir
# (the stage runner links none of canopy's libraries: tools/stagerun/CMakeLists.txt)
[ "\$t" != stagerun ] || libs=
"$tmp/records.sh" "$tmp/build" "$tree" "\$t" "tools/\$t" \$libs
mkdir -p "$tmp/build/CMakeFiles"
printf 'set(CMAKE_MAKEFILE_DEPENDS\n  "CMakeCache.txt"\n  "%s/CMakeLists.txt"\n  "%s/tools/CMakeLists.txt"\n  )\n' \
  "$tree" "$tree" >"$tmp/build/CMakeFiles/Makefile.cmake"
EOF
chmod +x "$tmp/cmake"
mk=(make -f Makefile.experiments OBJECTS=sedan SCENES=unoccluded NOISES=0 ABLATIONS= SCENE_EXPERIMENT=0 BASELINE=0 FAMILIES=0 REAL_TILES=0 OUT="$tmp/out"
    RES="$tmp/res" BUILD="$tmp/build" P="$tmp/params" CMAKE="$tmp/cmake")
tools=(rangetrace addnoise fitvox cocone ncut gmatch verify areas report figures)
# The tools this slice's graph runs: at 0 mm the noisy scan is a link to the render, so no
# artifact of NOISES=0 depends on addnoise and make never builds it.
used=(rangetrace fitvox cocone ncut gmatch verify areas report figures)

# Sources oldest, then parameters, binaries, their content stamps, and the artifacts in order.
now=$(date +%s)
at() { touch -d "@$1" "${@:2}"; }
find . -type f -exec touch -d "@$((now - 200))" {} +
mkdir -p "$tmp/build/bin" "$tmp/build/stamps" "$tmp/params" "$tmp/out/sedan/unoccluded/noise-0" \
  "$tmp/out/modelbase" "$tmp/res/figures" "$tmp/res/pictures" "$tmp/content"
cp share/params/*.ini "$tmp/params/"
at $((now - 100)) "$tmp/params/"*.ini
touch "$tmp/build/.deps-stamp"
echo "CMAKE_HOME_DIRECTORY:INTERNAL=$tree" >"$tmp/build/CMakeCache.txt"
for t in "${tools[@]}" stagerun; do
  "$tmp/cmake" --build "$tmp/build" --target "$t" || fail "the fake cmake failed"
  sha256sum <"$tmp/build/bin/$t" | cut -d' ' -f1 >"$tmp/build/stamps/$t.sha"
  scripts/tool-deps.sh "$tmp/build" "$t" "$tmp/build/deps/$t.mk" || fail "tool-deps.sh $t failed"
  [ -s "$tmp/build/deps/$t.mk" ] || fail "tool-deps.sh wrote no record of $t's sources"
done
rm "$tmp/cmake.calls"
at $((now - 90)) "$tmp/build/bin/"*
at $((now - 89)) "$tmp/build/deps/"*
at $((now - 88)) "$tmp/build/stamps/"*
c="$tmp/out/sedan/unoccluded"
r="$tmp/res"
i=80
for f in "$c/scan.pcd" "$c/noise-0/scan.pcd" "$c/noise-0/samples.pcd" "$c/noise-0/mesh.ply" \
         "$c/noise-0/segments.json" "$c/noise-0/segments.ply" "$tmp/out/modelbase/sedan.json" \
         "$tmp/out/modelbase/sedan.pcd" "$c/noise-0/match.json" "$c/noise-0/verdict.json" "$c/noise-0/areas.json" \
         "$r/report.md" "$r/cases.csv" "$r/scores.csv" "$r/times.csv" "$r/areas.csv" "$r/verdicts.csv" \
         "$r/figures/sedan-unoccluded-0.png" "$r/figures/grid-unoccluded.png" "$r/figures/scores.png" \
         "$r/figures/areas.png" \
         "$r/pictures/sedan.png" "$r/pictures/tank-circle.png"; do
  : >"$f"; at $((now - i)) "$f"; i=$((i - 2))
done
# The experiment's manifest (written by make when its text changes), between the trials' last
# artifacts and the report that reads it.
"${mk[@]}" PROGRESS=0 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "make did not write the experiment's manifest"
at $((now - 59)) "$tmp/out/experiment.txt"
stages() { grep -c "^$tmp/build/bin/stagerun " || true; }
# plans TOOL: exit 0 when the plan in $plan runs TOOL as a stage.
plans() { echo "$plan" | grep "^$tmp/build/bin/stagerun " | grep -q "$1"; }

"${mk[@]}" -q all || fail "make -q all is not clean on a complete tree: $("${mk[@]}" -n all 2>&1 | head -5)"

# A deleted intermediate artifact is rebuilt, not silently skipped, and nothing before it.
cp -p "$c/noise-0/mesh.ply" "$tmp/mesh.keep" && rm "$c/noise-0/mesh.ply"
plan=$("${mk[@]}" -n all 2>&1)
plans "bin/cocone " || fail "a deleted mesh.ply is not rebuilt"
if plans "bin/fitvox "; then fail "fitvox re-planned, but only mesh.ply was deleted"; fi
mv "$tmp/mesh.keep" "$c/noise-0/mesh.ply"
"${mk[@]}" -q all || fail "make -q all not clean after restoring mesh.ply"

# Exact rebuilds. A doc is no source: touching formats/README.md plans nothing, not even a build.
[ -f formats/README.md ] || fail "formats/README.md missing from the tree"
touch formats/README.md $(find common tools -name '*.md')
plan=$("${mk[@]}" -n all 2>&1 | grep -v "Nothing to be done")
[ -z "$plan" ] || fail "touching formats/README.md plans work: $(echo "$plan" | head -3)"
[ ! -f "$tmp/cmake.calls" ] || fail "touching a doc rebuilt tools: $(cat "$tmp/cmake.calls")"
"${mk[@]}" -q all || fail "make -q all not clean after touching a doc"

# A source of every tool changes (as a comment edit in common/ does) and every tool relinks to
# the same bytes: the tools are rebuilt (also by make -n, which must know), no stage is planned,
# and the content stamps keep their times.
stamp_times() { stat -c '%n %Y' "$tmp/build/stamps/"*.sha; }
before=$(stamp_times)
cpp=$(find common -name '*.cpp' | head -1)
[ -n "$cpp" ] || fail "no .cpp in common/"
echo "// a comment" >>"$cpp"
plan=$("${mk[@]}" -n all 2>&1)
[ "$(echo "$plan" | stages)" -eq 0 ] || fail "a same-bytes relink plans stages: $(echo "$plan" | grep stagerun | head -3)"
[ "$(sort -u "$tmp/cmake.calls" | tr '\n' ' ')" = "$(printf '%s\n' "${used[@]}" | sort | tr '\n' ' ')" ] ||
  fail "not every tool of the graph was rebuilt after $cpp changed: $(sort -u "$tmp/cmake.calls" | tr '\n' ' ')"
[ "$(stamp_times)" = "$before" ] || fail "a content stamp was rewritten although no binary changed"
"${mk[@]}" -q all || fail "make -q all not clean after a same-bytes relink"
"${mk[@]}" all >"$tmp/run.log" 2>&1 || fail "make all failed after a same-bytes relink: $(tail -3 "$tmp/run.log")"
if grep -q '^done\|^FAIL' "$tmp/run.log"; then fail "make all ran stages after a same-bytes relink: $(head -3 "$tmp/run.log")"; fi

# fitvox's bytes change: fitvox and every stage after it is planned, nothing before it.
echo "binary fitvox v2" >"$tmp/content/fitvox"
echo "// another comment" >>"$(find tools/fitvox -name '*.cpp' | head -1)"
plan=$("${mk[@]}" -n all 2>&1)
for later in fitvox cocone ncut gmatch verify areas report; do
  plans "bin/$later " || fail "$later not re-planned after fitvox's binary changed"
done
for early in rangetrace addnoise; do
  if plans "bin/$early "; then fail "$early re-planned, but only fitvox changed"; fi
done
[ "$(cat "$tmp/build/stamps/fitvox.sha")" = "$(sha256sum <"$tmp/build/bin/fitvox" | cut -d' ' -f1)" ] ||
  fail "fitvox's content stamp does not hold the new binary's sha256"
# Put the old binary back (and its stamp, with the old time) for the checks below.
rm "$tmp/content/fitvox"
echo "binary fitvox v1" >"$tmp/build/bin/fitvox"
sha256sum <"$tmp/build/bin/fitvox" | cut -d' ' -f1 >"$tmp/build/stamps/fitvox.sha"
at $((now - 88)) "$tmp/build/stamps/fitvox.sha"
"${mk[@]}" -q all || fail "make -q all not clean after restoring fitvox"

# No stale binaries: a tool depends on every source it was compiled from, as CMake recorded it
# (scripts/tool-deps.sh), not on a hand-written list. No tool includes or links another tool:
# editing tools/areas/areas.cpp rebuilds areas and no other tool (report read areas.json through
# tools/areas' library until issue 30, and was rebuilt with it; the Makefile before listed only
# tools/report/ for report, so the experiment ran an old report).
built() { sort -u "$tmp/cmake.calls" 2>/dev/null | tr '\n' ' '; }
rm -f "$tmp/cmake.calls"
echo "// an edit" >>tools/areas/areas.cpp
plan=$("${mk[@]}" -n all 2>&1)
[ "$(built)" = "areas " ] || fail "editing tools/areas/areas.cpp rebuilt '$(built)', not 'areas '"
[ "$(echo "$plan" | stages)" -eq 0 ] || fail "a same-bytes relink of areas plans stages"
rm -f "$tmp/cmake.calls"
echo "// an edit" >>tools/areas/areas.h
"${mk[@]}" -n all >/dev/null 2>&1
[ "$(built)" = "areas " ] || fail "editing tools/areas/areas.h rebuilt '$(built)', not 'areas '"
# The stage runner (tools/stagerun) is built like a tool, before any stage, but a runner whose
# bytes change re-runs no stage (the stamps wait for it order-only), and a common/ edit does not
# rebuild it (it links none of canopy's libraries).
rm -f "$tmp/cmake.calls"
echo "binary stagerun v2" >"$tmp/content/stagerun"
echo "// an edit" >>tools/stagerun/main.cpp
plan=$("${mk[@]}" -n all 2>&1)
[ "$(built)" = "stagerun " ] || fail "editing tools/stagerun/main.cpp rebuilt '$(built)', not 'stagerun '"
[ "$(cat "$tmp/build/bin/stagerun")" = "binary stagerun v2" ] || fail "the stage runner was not rebuilt"
[ "$(echo "$plan" | stages)" -eq 0 ] || fail "a new stage runner plans stages: $(echo "$plan" | grep stagerun | head -3)"
"${mk[@]}" -q all || fail "make -q all not clean after a new stage runner"
rm "$tmp/content/stagerun"
# A document's source or header (documents/: areas writes areas.json, report reads it) rebuilds
# every tool that reads or writes it: every tool links canopy_documents, so every tool of the graph.
for f in documents/src/areas.cpp documents/include/canopy/documents/areas.h; do
  [ -f "$f" ] || fail "$f missing from the tree"
  rm -f "$tmp/cmake.calls"
  echo "// an edit" >>"$f"
  plan=$("${mk[@]}" -n all 2>&1)
  for t in areas report; do
    case " $(built)" in *" $t "*) ;; *) fail "editing $f did not rebuild $t (it reads or writes areas.json): '$(built)'" ;; esac
  done
  [ "$(built)" = "$(printf '%s\n' "${used[@]}" | sort | tr '\n' ' ')" ] ||
    fail "editing $f rebuilt '$(built)', not every tool of the graph"
  [ "$(echo "$plan" | stages)" -eq 0 ] || fail "same-bytes relinks after editing $f plan stages"
done
# ... and report's bytes change with it: report's stage runs, areas' does not.
rm -f "$tmp/cmake.calls"
echo "binary report v2" >"$tmp/content/report"
echo "// an edit" >>documents/src/areas.cpp
plan=$("${mk[@]}" -n all 2>&1)
plans "bin/report " || fail "report's stage not planned after its binary changed with documents/src/areas.cpp"
if plans "bin/areas "; then fail "areas' stage planned, but its binary did not change"; fi
rm "$tmp/content/report"
echo "binary report v1" >"$tmp/build/bin/report"
sha256sum <"$tmp/build/bin/report" | cut -d' ' -f1 >"$tmp/build/stamps/report.sha"
at $((now - 88)) "$tmp/build/stamps/report.sha"
"${mk[@]}" -q all || fail "make -q all not clean after restoring report"
# A formats/ source rebuilds every tool (all link canopy_formats).
rm -f "$tmp/cmake.calls"
echo "// an edit" >>"$(find formats -name '*.cpp' | head -1)"
"${mk[@]}" -n all >/dev/null 2>&1
[ "$(built)" = "$(printf '%s\n' "${used[@]}" | sort | tr '\n' ' ')" ] ||
  fail "editing a formats/ source rebuilt '$(built)', not every tool of the graph"
# A header that no longer exists (renamed) is no error: the tool is rebuilt and its record
# rewritten without it.
rm -f "$tmp/cmake.calls"
h=$(find tools/ncut -name '*.h' | head -1)
git_mv_target="${h%.h}_renamed.h"
mv "$h" "$git_mv_target"
"${mk[@]}" -n all >"$tmp/plan.log" 2>&1 || fail "a removed header breaks make: $(tail -3 "$tmp/plan.log")"
[ "$(built)" = "ncut " ] || fail "removing $h rebuilt '$(built)', not ncut"
grep -q "$git_mv_target" "$tmp/build/deps/ncut.mk" || fail "ncut's record does not name $git_mv_target"
# A binary built after its record (by scripts/build.sh, outside make) is handed to CMake once,
# which rewrites the record; then nothing is built.
rm -f "$tmp/cmake.calls"
touch "$tmp/build/bin/gmatch"
"${mk[@]}" -n all >/dev/null 2>&1
[ "$(built)" = "gmatch " ] || fail "a binary newer than its record: built '$(built)', not gmatch"
rm -f "$tmp/cmake.calls"
"${mk[@]}" -n all >/dev/null 2>&1
[ ! -f "$tmp/cmake.calls" ] || fail "a second run rebuilt '$(built)'"
"${mk[@]}" -q all || fail "make -q all not clean after the source edits"

# The Slurm resources are no prerequisite; LAUNCH=slurm only changes how stages are launched.
touch share/resources.ini
"${mk[@]}" -q all || fail "touching share/resources.ini made the tree stale"
rm "$c/noise-0/match.json"
"${mk[@]}" -n all LAUNCH=slurm 2>&1 | grep -q "^$tmp/build/bin/stagerun --launch slurm .*bin/gmatch " ||
  fail "LAUNCH=slurm does not pass --launch slurm to stagerun"
if "${mk[@]}" -n all LAUNCH=bogus >/dev/null 2>&1; then fail "LAUNCH=bogus accepted"; fi
: >"$c/noise-0/match.json"; at $((now - 66)) "$c/noise-0/match.json"
"${mk[@]}" -q all || fail "make -q all not clean after restoring match.json"

# `all` runs the real tiles (REAL_TILES=1, the default; mk/real.mk): each committed tile through
# the tile workflow, the labelled ones scored, and the report reads them; REAL_TILES=0 leaves
# them out. Under -n the tiles' sub-makes are printed, not run; under -q a stale tile is "out of
# date" without running anything.
plan=$("${mk[@]}" REAL_TILES=1 -n all 2>&1)
for t in forest_lareunion ign_lidarhd_870000_6618000 ahn3_delft_2 ign_stbarth_100m; do
  echo "$plan" | grep -q "timeout 180 make .* tile TILE=share/real/$t.laz MODELBASE=$tmp/out/modelbase OUT=$tmp/out/real/$t " ||
    fail "make -n all does not run the tile workflow on share/real/$t.laz: $(echo "$plan" | grep -m3 real)"
done
for t in ign_lidarhd_870000_6618000 ahn3_delft_2 ign_stbarth_100m; do
  echo "$plan" | grep -q "bin/score -d $tmp/out/real/$t/detections.json -t share/real/$t.truth.json " ||
    fail "make -n all does not score $t against its labels"
done
if echo "$plan" | grep -q "bin/score -d $tmp/out/real/forest_lareunion/"; then fail "a plot without labels is scored"; fi
echo "$plan" | grep -q "bin/report --manifest $tmp/out/experiment.txt .*--real-timeout 180" ||
  fail "the report does not read the experiment's manifest with the real tiles' time box"
[ ! -e "$tmp/out/real/forest_lareunion/tile.time" ] || fail "make -n all ran a real tile"
"${mk[@]}" REAL_TILES=1 -q all && fail "make -q all is clean without the real tiles"
[ ! -e "$tmp/out/real/forest_lareunion" ] || fail "make -q all ran a real tile"
"${mk[@]}" -n all 2>&1 | grep -q "share/real/" && fail "REAL_TILES=0 still runs the real tiles"
# The report finds the real tiles in the experiment's manifest (documents/experiment_manifest.h),
# in order, each labelled one with its labels; REAL_TILES=0 names none.
grep -q "^real " "$tmp/out/experiment.txt" && fail "REAL_TILES=0: the manifest names real tiles"
grep -q "^trial sedan unoccluded 0 $tmp/out/sedan/unoccluded/noise-0\$" "$tmp/out/experiment.txt" ||
  fail "the manifest does not name the trial: $(head -3 "$tmp/out/experiment.txt")"
"${mk[@]}" REAL_TILES=1 PROGRESS=0 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "the manifest with real tiles not written"
real=$(grep "^real " "$tmp/out/experiment.txt")
# The forest plots first (24 since stop 66, no labels), then the urban tiles, each with its labels.
[ "$(echo "$real" | head -1)" = "real forest_lareunion $tmp/out/real/forest_lareunion" ] &&
  [ "$(echo "$real" | sed -n 25p)" = "real ign_lidarhd_870000_6618000 $tmp/out/real/ign_lidarhd_870000_6618000 share/real/ign_lidarhd_870000_6618000.truth.json" ] &&
  [ "$(echo "$real" | grep -c '^real forest_[^ ]* [^ ]*$')" -eq 24 ] ||
  fail "the manifest's real tiles: $real"
# Each tile's classify ablations follow it, in order, each in its own directory (mk/real.mk
# REAL_CLASSIFY_ABLATIONS: three by default, then the model level's, TILE_MODEL_DENSITY=50), and
# `all` runs them.
bridge0=$tmp/out/params/classify-bridge-0.ini ground0=$tmp/out/params/classify-tile-ground-0.ini
first0=$tmp/out/params/classify-tile-first-0.ini
abl=$(grep "^real-ablation forest_lareunion " "$tmp/out/experiment.txt")
[ "$abl" = "real-ablation forest_lareunion $tmp/out/real-ablation/forest_lareunion $bridge0
real-ablation forest_lareunion $tmp/out/real-ablation-2/forest_lareunion $ground0
real-ablation forest_lareunion $tmp/out/real-ablation-3/forest_lareunion $first0
real-ablation forest_lareunion $tmp/out/real-ablation-4/forest_lareunion TILE_MODEL_DENSITY=50" ] ||
  fail "the manifest's real-tile ablations: $abl"
# The three files are written by make (mk/real.mk REAL_CLASSIFY_VARIANTS): the test's own
# classify.ini with a first comment line and the ablation's keys' lines changed, nothing else.
c=$tmp/params/classify.ini
[ "$(diff "$c" "$bridge0" | grep '^[<>]')" = "> # $c with bridge = 0; bridge-fill = 0; bridge-min-share = 0 (written by make: do not edit).
< $(grep '^bridge = ' "$c")
< $(grep '^bridge-fill = ' "$c")
< $(grep '^bridge-min-share = ' "$c")
> bridge = 0
> bridge-fill = 0
> bridge-min-share = 0" ] || fail "$bridge0 is not classify.ini with the bridge's keys alone: $(diff "$c" "$bridge0" 2>&1 | head -12)"
[ "$(diff "$c" "$ground0" | grep '^[<>]')" = "> # $c with fill-tile-ground = false (written by make: do not edit).
< $(grep '^fill-tile-ground = ' "$c")
> fill-tile-ground = false" ] || fail "$ground0 is not classify.ini with fill-tile-ground = false alone: $(diff "$c" "$ground0" 2>&1 | head -8)"
[ "$(diff "$c" "$first0" | grep '^[<>]')" = "> # $c with fill-tile-first = false (written by make: do not edit).
< $(grep '^fill-tile-first = ' "$c")
> fill-tile-first = false" ] || fail "$first0 is not classify.ini with fill-tile-first = false alone: $(diff "$c" "$first0" 2>&1 | head -8)"
for a in "real-ablation $bridge0" "real-ablation-2 $ground0" "real-ablation-3 $first0"; do
  set -- $a
  echo "$plan" | grep -q "OUT=$tmp/out/$1/forest_lareunion TILE_CLASSIFY=$2 " ||
    fail "make -n all does not run classify's ablation $2 into $1"
done
# canopy's tiles and classify's ablations at the model level's default (mk/scenes.mk
# TILE_MODEL_DENSITY, 20); the model level's ablation with canopy's classify.ini at 50.
for a in "real $c 20" "real-ablation $bridge0 20" "real-ablation-4 $c 50"; do
  set -- $a
  echo "$plan" | grep -q "OUT=$tmp/out/$1/forest_lareunion TILE_CLASSIFY=$2 TILE_MODEL_DENSITY=$3 " ||
    fail "make -n all does not run $1 with $2 and the model level $3: $(echo "$plan" | grep -o "OUT=$tmp/out/$1/forest_lareunion [^ ]* [^ ]*" | head -1)"
done
"${mk[@]}" REAL_TILES=1 -n all REAL_CLASSIFY_ABLATIONS="TILE_MODEL_DENSITY=abc" >/dev/null 2>&1 &&
  fail "REAL_CLASSIFY_ABLATIONS: a TILE_MODEL_DENSITY that is no number is not refused"
"${mk[@]}" REAL_TILES=1 -n all REAL_CLASSIFY_ABLATIONS="DETECT=1" >/dev/null 2>&1 &&
  fail "REAL_CLASSIFY_ABLATIONS: an assignment other than TILE_MODEL_DENSITY is not refused"
# The list's places by name (REAL_CLASSIFY_ABLATION_2=, tests/pipeline/progress_count.sh): the
# second emptied, the first and third run but not it; a list of one entry, the first alone.
for args in "REAL_CLASSIFY_ABLATION_2=" "REAL_CLASSIFY_ABLATIONS=$bridge0"; do
  plan=$("${mk[@]}" REAL_TILES=1 -n all $args 2>&1)
  echo "$plan" | grep -q "OUT=$tmp/out/real-ablation/forest_lareunion TILE_CLASSIFY=$bridge0 " ||
    fail "$args: make -n all does not run classify's first ablation"
  if echo "$plan" | grep -q "real-ablation-2"; then fail "$args: make -n all still runs the second"; fi
done
plan=$("${mk[@]}" REAL_TILES=1 -n all REAL_CLASSIFY_ABLATION_2= 2>&1)
echo "$plan" | grep -q "OUT=$tmp/out/real-ablation-3/forest_lareunion TILE_CLASSIFY=$first0 " ||
  fail "REAL_CLASSIFY_ABLATION_2=: make -n all does not run the third ablation"
# The manifest follows the experiment's shape: with the real tiles in it, the report (made
# without them) is stale for `make -q all` (REAL_TILES=0). Back to REAL_TILES=0's manifest, with
# its old time: the tree is complete again for the checks below. (Left with the real tiles, the
# options checks' `make scenes` wrote it back without them, newer than the report, and their
# last `make -q all` failed: the s50 failure, docs/decisions/experiment-graph.md §6.)
"${mk[@]}" -q all && fail "make -q all is clean although the manifest names real tiles the report was not made with"
"${mk[@]}" PROGRESS=0 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "the manifest without real tiles not written"
grep -q "^real " "$tmp/out/experiment.txt" && fail "REAL_TILES=0 again: the manifest still names real tiles"
at $((now - 59)) "$tmp/out/experiment.txt"
"${mk[@]}" -q all || fail "make -q all not clean after the manifest was written back without the real tiles"

# Options as prerequisites (docs/decisions/experiment-graph.md §6): a variable that changes a
# stage's command re-runs that stage and what follows through its kind's options file
# (<dir>/.opts/<kind>.txt), and nothing else; the same command again plans nothing. On the scene
# experiment's rules (`make scenes`) over one complete fake run with one model-level candidate,
# and on the `tile` workflow over one fake tile.
# The options makes below (their own scene run, tile and dry runs of `all` with other values)
# leave every file of the thesis slice as it is: same files, same times (the progress count's
# state aside).
thesis_files() {
  find "$tmp/out" "$tmp/res" \( -path "$tmp/out/scenes" -o -path "$tmp/res/scenes" \) -prune -o -type f ! -name '.progress*' -printf '%p %T@\n' |
    sort
}
thesis_before=$(thesis_files)
# The real tiles' options are written only by a make that can run them: no `make scenes` (a
# sub-make of `all`, which may be given other values: the open set's COLLECT_CALIBRATION) writes
# them, not even when they are missing (put back at the end).
mv "$tmp/out/.opts/real.txt" "$tmp/real.txt.keep" || fail "no options file of the real tiles after the runs of all"
for t in detect classify collect score topview; do
  "$tmp/cmake" --build "$tmp/build" --target "$t" || fail "the fake cmake failed"
  sha256sum <"$tmp/build/bin/$t" | cut -d' ' -f1 >"$tmp/build/stamps/$t.sha"
  scripts/tool-deps.sh "$tmp/build" "$t" "$tmp/build/deps/$t.mk" || fail "tool-deps.sh $t failed"
  at $((now - 90)) "$tmp/build/bin/$t"; at $((now - 89)) "$tmp/build/deps/$t.mk"; at $((now - 88)) "$tmp/build/stamps/$t.sha"
done
rm -f "$tmp/cmake.calls"
# fake_run DIR KEY FIRST: a complete run DIR (detect's candidates, the plan with one model-level
# candidate c0001, its class answer and model chain, the detections), times from now - FIRST on.
fake_run() {
  local d=$1 key=$2 i=$3 f
  mkdir -p "$d/cands/c0001"
  printf '%s\n' "${key}_CANDS := c0001" "${key}_TRANSFORM_c0001 := 1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1" \
    "${key}_LEVEL_c0001 := model" "${key}_FITVOX_c0001 := --voxel-size 0.2" >"$d/cands.mk"
  for f in "$d/cands/index.json" "$d/cands/c0001.pcd" "$d/cands.mk" "$d/cands/c0001/class.json" \
           "$d/cands/c0001/samples.pcd" "$d/cands/c0001/mesh.ply" "$d/cands/c0001/segments.json" \
           "$d/cands/c0001/segments.ply" "$d/cands/c0001/match.json" "$d/cands/c0001/verdict.json" \
           "$d/detections.json" "$d/detections.geojson"; do
    [ -e "$f" ] || : >"$f"; at $((now - i)) "$f"; i=$((i - 1))
  done
}
sd="$tmp/out/scenes"
st="$sd/light/tile-1"
sr="$st/noise-0"
# (sc: without collect's ablation, which a calibration brings by default: checked on its own below.)
sa=("${mk[@]}" PROGRESS=0 SCENE_SEEDS=1 SCENE_COVERS=light SCENE_NOISES=0 SCENE_BASELINE= SCENE_SIZE_ONLY=0 SCENE_PICTURES=0)
sc=("${sa[@]}" SCENE_COLLECT_ABLATION=)
mkdir -p "$sr" "$tmp/res/scenes"
for f in "$st/scan.pcd" "$st/truth.json" "$sr/scan.pcd"; do : >"$f"; done
at $((now - 50)) "$st/scan.pcd" "$st/truth.json"; at $((now - 49)) "$sr/scan.pcd"
fake_run "$sr" "S_$(printf '%s' "$sr" | tr '/.-' '___')" 48
# The recipe, the score's tile list and the options files are written by make when their text
# changes: a real run (its stages no-ops, STAGE=true, whose artifacts get their times below).
"${sc[@]}" scenes STAGE=true KEEP=1 >"$tmp/scenes.log" 2>&1 || fail "make scenes did not write the recipe: $(tail -3 "$tmp/scenes.log")"
at $((now - 51)) "$st/recipe.scene"
# The scene recipe outside the graph (mk/scene-recipe.mk on its own, bench/detect/recipes.sh) is
# the one `make scenes` wrote, byte for byte.
make --no-print-directory -f mk/scene-recipe.mk SCENE_RECIPES="$tmp/recipes" SCENE_SEEDS=1 SCENE_COVERS=light ||
  fail "make -f mk/scene-recipe.mk failed"
cmp "$tmp/recipes/light-1.scene" "$st/recipe.scene" || fail "mk/scene-recipe.mk's recipe differs from make scenes': $(diff "$tmp/recipes/light-1.scene" "$st/recipe.scene")"
at $((now - 30)) "$sd/tiles.txt"
: >"$tmp/res/scenes/score.json"; at $((now - 29)) "$tmp/res/scenes/score.json"
for k in detect plan classify models collect score; do
  [ "$(stat -c %Y "$sd/.opts/$k.txt" 2>/dev/null)" = 0 ] ||
    fail "the options file of $k was not written with the time 0 on a tree made before it: $(ls -l "$sd/.opts/" 2>&1)"
done
grep -qx "calibration = $tmp/params/calibration.ini" "$sd/.opts/collect.txt" ||
  fail "the collect options file does not hold the calibration: $(cat "$sd/.opts/collect.txt")"
"${sc[@]}" -q scenes || fail "make -q scenes is not clean on a complete run: $("${sc[@]}" -n scenes 2>&1 | head -5)"
# plans_list KIND VAR LIST: `make -n scenes VAR=LIST` on the complete run (KIND class: the
# classify ablations, sc; KIND collect: collect's, sa) plans, for each entry E of LIST at place K
# that is not "-", the variant V = KIND-ablation (K = 1) or KIND-ablation-K: for class, classify
# with the file E on the candidate (cands/c0001/V.json) and its collect (--class-name V.json); for
# collect, collect with the options E (joined by commas in the list, spaces on collect's command
# line) from the same verdicts; then V's score. No variant at another place (1 to 4), and nothing
# else (3 stages per class entry, 2 per collect entry). Leaves the plan in $plan.
plans_list() {
  local kind=$1 var=$2 list=$3 k=0 n=0 per=2 e v
  if [ "$kind" = class ]; then
    per=3
    plan=$("${sc[@]}" -n scenes "$var=$list" 2>&1)
  else
    plan=$("${sa[@]}" -n scenes "$var=$list" 2>&1)
  fi
  local planned=" "
  for e in $list; do
    k=$((k + 1))
    [ "$e" = - ] && continue
    v=$kind-ablation$([ $k -eq 1 ] || echo "-$k")
    planned+="$v "
    n=$((n + 1))
    if [ "$kind" = class ]; then
      plans "bin/classify --config $e -i $sr/cands/c0001.pcd .*-o $sr/cands/c0001/$v.json" ||
        fail "$var=\"$list\" does not plan classify with $e as $v: $(echo "$plan" | grep stagerun)"
      plans "bin/collect -i $sr/cands/index.json --class-name $v.json .*-o $sr/detections-$v.json" ||
        fail "$var=\"$list\" does not plan $v's collect"
    else
      plans "bin/collect -i $sr/cands/index.json .*-o $sr/detections-$v.json --modelbase [^ ]* ${e//,/ } --calibration" ||
        fail "$var=\"$list\" does not plan collect with ${e//,/ } as $v: $(echo "$plan" | grep stagerun)"
    fi
    plans "bin/score --tiles $sd/tiles-$v.txt .*-o $tmp/res/scenes/$v/score.json" ||
      fail "$var=\"$list\" does not plan $v's score"
  done
  for k in 1 2 3 4; do
    v=$kind-ablation$([ $k -eq 1 ] || echo "-$k")
    [[ "$planned" == *" $v "* ]] && continue
    if plans "$v\.json"; then fail "$var=\"$list\" plans $v, a place it leaves empty"; fi
  done
  [ "$(echo "$plan" | stages)" -eq $((per * n)) ] ||
    fail "$var=\"$list\" plans $(echo "$plan" | stages) stages, not $((per * n))"
}
# classify's ablations (mk/scenes.mk SCENE_CLASSIFY_ABLATIONS, the K-th entry the variant
# class-ablation[-K], "-" an empty place). A list of two: on a complete run it plans classify twice
# more on the candidate (class-ablation.json with the first file, class-ablation-2.json with the
# second), each one's collect and score, and nothing else; a dry run writes no options file for them.
sim=$tmp/params/classify-sim.ini
plans_list class SCENE_CLASSIFY_ABLATIONS "$sim $tmp/params/classify.ini"
[ ! -e "$sd/.opts/classify-ablation-2.txt" ] || fail "a dry run wrote the second ablation's options file"
"${sc[@]}" -q scenes SCENE_CLASSIFY_ABLATIONS="- $tmp/params/classify.ini" &&
  fail "make -q scenes is clean without the second classify ablation"
# An empty place keeps the later ones' names: "- - - FILE" is class-ablation-4 alone (the ladders'
# open-top gate off), the same three stages, and none of the others'.
plans_list class SCENE_CLASSIFY_ABLATIONS "- - - $tmp/params/classify.ini"
# The first three places by name, as mk/openset.mk gives them (SCENE_CLASSIFY_ABLATION_3 with
# _2 empty: the family entries alone 1 without the envelope): class-ablation-3, the same three
# stages; not together with the list.
plan=$("${sc[@]}" -n scenes SCENE_CLASSIFY_ABLATION_2= SCENE_CLASSIFY_ABLATION_3="$tmp/params/classify.ini" 2>&1)
plans "bin/classify --config $tmp/params/classify.ini -i $sr/cands/c0001.pcd .*-o $sr/cands/c0001/class-ablation-3.json" ||
  fail "SCENE_CLASSIFY_ABLATION_3 does not plan classify with its parameters: $(echo "$plan" | grep stagerun)"
plans "bin/collect -i $sr/cands/index.json --class-name class-ablation-3.json .*-o $sr/detections-class-ablation-3.json" ||
  fail "SCENE_CLASSIFY_ABLATION_3 does not plan its collect"
if plans "class-ablation\.json" || plans "class-ablation-2\.json"; then
  fail "SCENE_CLASSIFY_ABLATION_3 plans another ablation's variant"
fi
[ "$(echo "$plan" | stages)" -eq 3 ] || fail "SCENE_CLASSIFY_ABLATION_3 plans $(echo "$plan" | stages) stages, not 3"
"${sc[@]}" -n scenes SCENE_CLASSIFY_ABLATION_3="$sim" SCENE_CLASSIFY_ABLATIONS="$sim" >/dev/null 2>&1 &&
  fail "SCENE_CLASSIFY_ABLATIONS and SCENE_CLASSIFY_ABLATION_3 together are not refused"
# The scene experiment's own classify ablations (mk/scenes.mk SCENES_CLASSIFY_ABLATION[_2]: by
# default the roughness floor's and the shoulder's files; scene-experiment.md "Stop 56"): on the
# complete run `make -n all` plans, in the experiment's `make scenes`, classify twice more on the
# candidate (each with its file), each ablation's collect and score: 6 stages more than with both
# emptied, which plans none of them; the report is given both scores and their files.
se=("${sc[@]}" SCENE_EXPERIMENT=1 DENSITY_LADDER=0 OPENSET=0)
floor=$tmp/out/params/classify-sim-floor-100.ini shoulder=$tmp/out/params/classify-sim-shoulder-0.ini
# classify-sim.ini's ablations are written by make (Makefile.experiments CLASSIFY_SIM_VARIANTS,
# by the makes above): the test's own classify-sim.ini with a first comment line and one key's
# line changed, nothing else; a base without that key's line is an error naming it.
for v in floor-100:roughness-floor:100mm shoulder-0:min-shoulder:0 sampled-0:rectangularity-sampled:false \
  rim-0:max-rim:0 bed-0:min-bed:0; do
  IFS=: read -r n key value <<<"$v"
  f=$tmp/out/params/classify-sim-$n.ini
  old=$(grep "^$key = " "$tmp/params/classify-sim.ini")
  [ "$(diff "$tmp/params/classify-sim.ini" "$f" | grep '^[<>]')" = "> # $tmp/params/classify-sim.ini with $key = $value (written by make: do not edit).
< $old
> $key = $value" ] || fail "$f is not classify-sim.ini with $key = $value alone: $(diff "$tmp/params/classify-sim.ini" "$f" 2>&1 | head -8)"
done
mkdir -p "$tmp/params-nobed" && cp -a "$tmp/params/." "$tmp/params-nobed/" &&
  sed -i '/^min-bed = /d' "$tmp/params-nobed/classify-sim.ini" || fail "cannot copy the parameters"
if out=$("${se[@]}" -n all P="$tmp/params-nobed" 2>&1); then fail "a classify-sim.ini without min-bed is not refused"; fi
echo "$out" | grep -q 'ini_set: no line "min-bed = <one word>"' || fail "a classify-sim.ini without min-bed: $(echo "$out" | tail -2)"
plan=$("${se[@]}" -n all 2>&1)
plans "bin/classify --config $floor -i $sr/cands/c0001.pcd .*-o $sr/cands/c0001/class-ablation.json" ||
  fail "make -n all does not plan the scene experiment's floor ablation: $(echo "$plan" | grep stagerun)"
plans "bin/classify --config $shoulder -i $sr/cands/c0001.pcd .*-o $sr/cands/c0001/class-ablation-2.json" ||
  fail "make -n all does not plan the scene experiment's shoulder ablation"
for v in class-ablation class-ablation-2; do
  plans "bin/collect -i $sr/cands/index.json --class-name $v.json .*-o $sr/detections-$v.json" ||
    fail "make -n all does not plan $v's collect"
  plans "bin/score --tiles $sd/tiles-$v.txt .*-o $tmp/res/scenes/$v/score.json" || fail "make -n all does not plan $v's score"
done
abl_stages() { grep "^$tmp/build/bin/stagerun " | grep -v " -- $tmp/build/bin/report " | grep -c "class-ablation" || true; }
[ "$(echo "$plan" | abl_stages)" -eq 6 ] || fail "make -n all plans $(echo "$plan" | abl_stages) ablation stages, not 6"
plans "bin/report .*--tile-classify-ablation $tmp/res/scenes/class-ablation/score.json --tile-classify-ablation-config $floor --tile-classify-ablation-2 $tmp/res/scenes/class-ablation-2/score.json --tile-classify-ablation-2-config $shoulder" ||
  fail "the report is not given the scene experiment's classify ablations: $(echo "$plan" | grep bin/report)"
with=$(echo "$plan" | stages)
plan=$("${se[@]}" -n all SCENES_CLASSIFY_ABLATION= SCENES_CLASSIFY_ABLATION_2= 2>&1)
if plans "class-ablation"; then fail "SCENES_CLASSIFY_ABLATION= SCENES_CLASSIFY_ABLATION_2= still plan an ablation"; fi
plans "bin/report " || fail "make -n all plans no report"
[ $((with - $(echo "$plan" | stages))) -eq 6 ] ||
  fail "the ablations add $((with - $(echo "$plan" | stages))) stages to make -n all, not 6"
[ ! -e "$sd/.opts/classify-ablation.txt" ] && [ ! -e "$tmp/out/.opts/scene-report.txt" ] ||
  fail "a dry run of all wrote an options file of the ablations"
# The scene experiment's verify ablation (mk/scenes.mk SCENES_VERIFY_ABLATION, by default
# --top-k=3: verify on gmatch's top 3, the default before stop 65; scene-experiment.md "What gmatch
# adds"): `make -n all` plans, in the experiment's `make scenes`, verify with those options on the
# model-level candidate, the run's collect of those verdicts and their score, and gives the report
# the score and the options; emptied, none of it.
plan=$("${se[@]}" -n all 2>&1)
plans "bin/collect -i $sr/cands/index.json --verdict-name verdict-ablation.json .*-o $sr/detections-verify-ablation.json" ||
  fail "make -n all does not plan the scene experiment's verify ablation's collect: $(echo "$plan" | grep verify-ablation | head -3)"
plans "bin/verify --config [^ ]*verify.ini --top-k=3 -i $sr/cands/c0001/match.json .*-o $sr/cands/c0001/verdict-ablation.json" ||
  fail "make -n all does not plan the verify ablation on the model-level candidate: $(echo "$plan" | grep "bin/verify" | head -3)"
plans "bin/score --tiles $sd/tiles-verify-ablation.txt .*-o $tmp/res/scenes/verify-ablation/score.json" ||
  fail "make -n all does not plan the verify ablation's score"
plans "bin/report .*--tile-verify-ablation $tmp/res/scenes/verify-ablation/score.json --tile-verify-ablation-options='--top-k=3'" ||
  fail "the report is not given the scene experiment's verify ablation: $(echo "$plan" | grep bin/report)"
with=$(echo "$plan" | stages)
plan=$("${se[@]}" -n all SCENES_VERIFY_ABLATION= 2>&1)
if plans "verify-ablation"; then fail "SCENES_VERIFY_ABLATION= still plans the verify ablation"; fi
[ $((with - $(echo "$plan" | stages))) -eq 3 ] ||
  fail "the verify ablation adds $((with - $(echo "$plan" | stages))) stages to make -n all, not 3 (verify on the model-level c0001, the run's collect, the score)"
# The report reads only the baseline's methods that run (report --tile-baselines; mk/scenes.mk
# scene_bl_methods), so a method turned off is not shown from its old score: here vfh alone (no
# fpfh, so no FPFH poses verified; no size-only row).
plan=$("${se[@]}" -n all SCENE_BASELINE=vfh SCENE_SIZE_ONLY=0 2>&1)
plans "bin/report .*--tile-baselines=vfh " ||
  fail "the report is not told the baseline's methods that ran: $(echo "$plan" | grep -o -- '--tile-baselines=[^ ]*')"
# The density ladder's detect (mk/density.mk DENSITY_DETECT, DENSITY_DETECT_ABLATIONS;
# density-ladder.md, stop 61): the class-level rungs (at most DENSITY_CLASS_MAX = 50 points/m²)
# detect with share/params/detect-ladder.ini (end-gap = 1); each of them runs its chain a second
# time, rendered alike, into <rung>/detect-ablation with bench/density/detect-end-gap-0.ini
# (end-gap = 0); a model-level rung (100) takes detect's defaults and has no detect ablation; the
# manifest names the ablations (density-detect), the class-level rungs' only.
[ "$(grep -v '^#' share/params/detect-ladder.ini)" = "end-gap = 1" ] ||
  fail "share/params/detect-ladder.ini is not end-gap = 1 alone: $(grep -v '^#' share/params/detect-ladder.ini)"
[ "$(grep -v '^#' bench/density/detect-end-gap-0.ini)" = "end-gap = 0" ] ||
  fail "bench/density/detect-end-gap-0.ini is not end-gap = 0 alone"
dl0=("${mk[@]}" PROGRESS=0 DENSITY_LEVELS="10 25 100" DENSITY_SEEDS=1 DENSITY_COVERS=light DENSITY_SENSOR=
    DENSITY_VERIFY_ABLATION= DENSITY_CLASSIFY_ABLATIONS=)
# (detect's ablation alone here; the default list's second entry, the model level's, below)
dl=("${dl0[@]}" DENSITY_DETECT_ABLATIONS=bench/density/detect-end-gap-0.ini)
plan=$("${dl[@]}" -n density 2>&1)
dd="$tmp/out/density"
for l in 10 25; do
  plans "bin/detect --config share/params/detect-ladder.ini .*-i $dd/d$l/light/tile-1/noise-0/scan.pcd -o $dd/d$l/light/tile-1/noise-0/cands" ||
    fail "the class-level rung $l does not detect with detect-ladder.ini: $(echo "$plan" | grep "bin/detect" | head -3)"
  plans "bin/detect --config bench/density/detect-end-gap-0.ini .*-i $dd/d$l/detect-ablation/light/tile-1/noise-0/scan.pcd -o $dd/d$l/detect-ablation/light/tile-1/noise-0/cands" ||
    fail "the class-level rung $l has no detect ablation with end-gap 0"
  # (stop 62: the ablation renders nothing of its own; it links the rung's render, which the rung's
  # make keeps and the last ablation deletes once scored)
  if plans "bin/rangetrace .*-o $dd/d$l/detect-ablation/"; then fail "the rung $l's detect ablation renders a tile of its own"; fi
  # (nor does its dry run plan the rung's render again: the rung's make plans it, once)
  [ "$(echo "$plan" | grep "^$tmp/build/bin/stagerun " | grep -c "bin/rangetrace .*-o $dd/d$l/light/tile-1/scan.pcd")" -eq 1 ] ||
    fail "the rung $l's render is not planned once"
  echo "$plan" | grep -q "ln $dd/d$l/light/tile-1/scan.pcd $dd/d$l/detect-ablation/light/tile-1/noise-0/scan.pcd" ||
    fail "the rung $l's detect ablation does not read the rung's render"
  echo "$plan" | grep -qx "  --csv $tmp/res/density/d$l/ && rm -f $dd/d$l/light/tile-1/noise-0/scan.pcd" ||
    fail "the rung $l does not keep its render for its detect ablation: $(echo "$plan" | grep -- "--csv $tmp/res/density/d$l/ ")"
  echo "$plan" | grep -qx "  --csv $tmp/res/density/d$l/detect-ablation/ && rm -f $dd/d$l/light/tile-1/scan.pcd $dd/d$l/detect-ablation/light/tile-1/noise-0/scan.pcd" ||
    fail "the rung $l's detect ablation does not delete the render once scored"
  plans "bin/score --tiles $dd/d$l/detect-ablation/tiles.txt .*-o $tmp/res/density/d$l/detect-ablation/score.json" ||
    fail "the rung $l's detect ablation is not scored"
  if plans "bin/classify .*$dd/d$l/detect-ablation/.*class-ablation"; then fail "the detect ablation runs classify's ablation"; fi
done
plans "bin/detect --no-classes -i $dd/d100/light/tile-1/noise-0/scan.pcd" ||
  fail "the model-level rung 100 does not detect with detect's defaults: $(echo "$plan" | grep "bin/detect" | grep d100)"
if plans "d100/detect-ablation"; then fail "the model-level rung 100 has a detect ablation"; fi
echo "$plan" | grep -qx "  --csv $tmp/res/density/d100/ && rm -f $dd/d100/light/tile-1/scan.pcd $dd/d100/light/tile-1/noise-0/scan.pcd" ||
  fail "the model-level rung 100 keeps its render"
[ "$(echo "$plan" | grep "^$tmp/build/bin/stagerun " | grep -c "bin/detect ")" -eq 5 ] ||
  fail "make -n density plans $(echo "$plan" | grep "^$tmp/build/bin/stagerun " | grep -c "bin/detect ") detects, not 5"
plan=$("${dl[@]}" -n density DENSITY_DETECT_ABLATIONS="- bench/density/detect-end-gap-0.ini" DENSITY_CLASS_MAX=10 2>&1)
plans "bin/detect --config bench/density/detect-end-gap-0.ini .*-o $dd/d10/detect-ablation-2/light/tile-1/noise-0/cands" ||
  fail "\"- FILE\" does not plan detect-ablation-2"
if plans "detect-ablation/" || plans "d25/detect-ablation"; then fail "\"- FILE\" or DENSITY_CLASS_MAX=10 plans another detect ablation"; fi
plans "bin/detect --no-classes -i $dd/d25/light/tile-1/noise-0/scan.pcd" || fail "DENSITY_CLASS_MAX=10 still gives 25 detect-ladder.ini"
# Two ablations: each after the rung and the one before it; the first keeps the render, the last
# deletes it.
# (asked for the second ablation's score alone: it brings the rung and the first ablation first)
plan=$("${dl[@]}" -n "$tmp/res/density/d10/detect-ablation-2/score.json" DENSITY_LADDER=1 DENSITY_LEVELS=10 \
  DENSITY_DETECT_ABLATIONS="bench/density/detect-end-gap-0.ini bench/density/detect-end-gap-0.ini" 2>&1)
order=$(echo "$plan" | grep -- "--csv $tmp/res/density/d10/" | awk '{print $2}' | sed "s#^$tmp/res/density/d10/##; s#/\$##" | tr '\n' ' ')
[ "$order" = " detect-ablation detect-ablation-2 " ] ||
  fail "the rung and its two detect ablations are not scored in order: '$order' $(echo "$plan" | grep -v "^ " | cut -c1-160 | tail -5)"
echo "$plan" | grep -qx "  --csv $tmp/res/density/d10/detect-ablation/ && rm -f $dd/d10/detect-ablation/light/tile-1/noise-0/scan.pcd" ||
  fail "the first of two detect ablations deletes the rung's render"
echo "$plan" | grep -qx "  --csv $tmp/res/density/d10/detect-ablation-2/ && rm -f $dd/d10/light/tile-1/scan.pcd $dd/d10/detect-ablation-2/light/tile-1/noise-0/scan.pcd" ||
  fail "the last of two detect ablations does not delete the rung's render"
plan=$("${dl[@]}" -n density DENSITY_DETECT_ABLATIONS= DENSITY_DETECT= 2>&1)
if plans "detect-ablation" || plans "bin/detect --config"; then fail "DENSITY_DETECT_ABLATIONS= DENSITY_DETECT= still plan a detect ablation or parameters"; fi
"${dl[@]}" -n density DENSITY_DETECT_ABLATIONS=bench/density/none.ini >/dev/null 2>&1 &&
  fail "a missing detect ablation file is not refused"
# The default list: detect's ablation, then the model level's (TILE_MODEL_DENSITY=50, stop 69;
# density-scale.md): on each class-level rung the rung's chain again into model-ablation-2 with
# detect-ladder.ini, the rung's render (the last ablation deletes it) and collect's plan at 50;
# canopy's own plan at 20; the manifest names both.
plan=$("${dl0[@]}" -n density 2>&1)
for l in 10 25; do
  plans "bin/detect --config share/params/detect-ladder.ini .*-i $dd/d$l/model-ablation-2/light/tile-1/noise-0/scan.pcd -o $dd/d$l/model-ablation-2/light/tile-1/noise-0/cands" ||
    fail "the class-level rung $l has no model level ablation detecting with detect-ladder.ini"
  plans "bin/collect .*$dd/d$l/model-ablation-2/light/tile-1/noise-0/cands/index.json .*--model-density 50" ||
    fail "the rung $l's model level ablation does not plan at 50: $(echo "$plan" | grep "bin/collect .*d$l/model-ablation-2.*--plan" | head -1)"
  plans "bin/collect .*$dd/d$l/light/tile-1/noise-0/cands/index.json .*--model-density 20" ||
    fail "the rung $l does not plan at 20"
  echo "$plan" | grep -qx "  --csv $tmp/res/density/d$l/model-ablation-2/ && rm -f $dd/d$l/light/tile-1/scan.pcd $dd/d$l/model-ablation-2/light/tile-1/noise-0/scan.pcd" ||
    fail "the rung $l's model level ablation (the last) does not delete the render once scored"
done
if plans "d100/model-ablation"; then fail "the model-level rung 100 has a model level ablation"; fi
"${dl0[@]}" -n density DENSITY_DETECT_ABLATIONS="TILE_MODEL_DENSITY=x" >/dev/null 2>&1 &&
  fail "DENSITY_DETECT_ABLATIONS: a TILE_MODEL_DENSITY that is no number is not refused"
[ ! -e "$tmp/out/.opts/real.txt" ] || fail "make -n density wrote the real tiles' options"
"${dl[@]}" DENSITY_LADDER=1 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "the manifest with the density ladder not written"
[ "$(grep "^density-detect " "$tmp/out/experiment.txt")" = "density-detect pixel 10 bench/density/detect-end-gap-0.ini $tmp/res/density/d10/detect-ablation/score.json
density-detect pixel 25 bench/density/detect-end-gap-0.ini $tmp/res/density/d25/detect-ablation/score.json" ] ||
  fail "the manifest's density-detect records: $(grep "^density" "$tmp/out/experiment.txt")"
"${dl0[@]}" DENSITY_LADDER=1 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "the manifest with the density ladder (default) not written"
[ "$(grep "^density-detect pixel 25 " "$tmp/out/experiment.txt")" = "density-detect pixel 25 bench/density/detect-end-gap-0.ini $tmp/res/density/d25/detect-ablation/score.json
density-detect pixel 25 TILE_MODEL_DENSITY=50 $tmp/res/density/d25/model-ablation-2/score.json" ] ||
  fail "the manifest's density-detect records (default): $(grep "^density" "$tmp/out/experiment.txt")"
"${mk[@]}" PROGRESS=0 "$tmp/out/experiment.txt" >/dev/null 2>&1 || fail "the manifest without the ladder not written"
grep -q "^density" "$tmp/out/experiment.txt" && fail "DENSITY_LADDER=0 again: the manifest still names the ladder"
# (the manifest's makes write the real tiles' options too, as `all` does; the runs' own is kept aside
# until the check below that no other goal writes it)
rm -f "$tmp/out/.opts/real.txt"
at $((now - 59)) "$tmp/out/experiment.txt"
# collect's ablation by default (SCENE_COLLECT_ABLATION: --coarse-none-below=0 with a calibration;
# verify.md §19): on a complete run it plans one more collect, from the same verdicts, and its
# score; nothing upstream of collect, nor canopy's collect. Without a calibration there is none.
plan=$("${sa[@]}" -n scenes 2>&1)
plans "bin/collect -i $sr/cands/index.json .*-o $sr/detections-collect-ablation.json .*--coarse-none-below=0 --calibration" ||
  fail "the default does not plan collect's ablation: $(echo "$plan" | grep stagerun)"
plans "bin/score --tiles $sd/tiles-collect-ablation.txt" || fail "the default does not plan the ablation's score"
for t in rangetrace addnoise detect classify fitvox cocone ncut gmatch verify "collect -i $sr/cands/index.json --plan" \
  "collect -i $sr/cands/index.json -o $sr/detections.json"; do
  if plans "bin/$t "; then fail "collect's ablation re-plans $t"; fi
done
[ "$(echo "$plan" | stages)" -eq 2 ] || fail "collect's ablation plans $(echo "$plan" | stages) stages, not 2"
"${sa[@]}" -q scenes && fail "make -q scenes is clean without collect's ablation"
plan=$("${sa[@]}" -n scenes COLLECT_CALIBRATION= 2>&1)
if plans "collect-ablation"; then fail "without a calibration collect's ablation is planned"; fi
# collect's ablations as a list (mk/scenes.mk SCENE_COLLECT_ABLATIONS: an entry is collect's
# options joined by commas, the K-th the variant collect-ablation[-K], "-" an empty place; the
# open set's two): a list of two plans two collects from the same verdicts, each with its own
# options, and their scores, and nothing else; not together with SCENE_COLLECT_ABLATION.
plans_list collect SCENE_COLLECT_ABLATIONS "--contradicted-below=0,--refused-below=0 --contradiction-level=class"
if plans "coarse-none-below"; then fail "a list of collect ablations still plans SCENE_COLLECT_ABLATION's default"; fi
plans_list collect SCENE_COLLECT_ABLATIONS "- --contradiction-level=class"
"${sa[@]}" -n scenes SCENE_COLLECT_ABLATION=--coarse-none-below=0 SCENE_COLLECT_ABLATIONS=--contradiction-level=class \
  >/dev/null 2>&1 && fail "SCENE_COLLECT_ABLATIONS and SCENE_COLLECT_ABLATION together are not refused"
# The open set's default (mk/openset.mk OPENSET_COLLECT_ABLATIONS): its sub-makes are given both
# entries, the report both scores each with its options, and the tiles' sub-make plans both scores.
plan=$("${sa[@]}" -n all OPENSET=1 OPENSET_SEEDS=1 OPENSET_COVERS=light OPENSET_CROPS=0 2>&1)
echo "$plan" | grep -q "make .* scenes .*SCENE_COLLECT_ABLATION= SCENE_COLLECT_ABLATIONS='--contradicted-below=0,--refused-below=0 --contradiction-level=class'" ||
  fail "the open set's sub-make is not given its two collect ablations: $(echo "$plan" | grep "SCENE_COLLECT" | head -3)"
plans "bin/report .*--openset-collect-ablation $tmp/res/openset/collect-ablation/score.json --openset-collect-ablation-options=--contradicted-below=0,--refused-below=0 .*--openset-collect-ablation $tmp/res/openset/collect-ablation-2/score.json --openset-collect-ablation-options=--contradiction-level=class" ||
  fail "the report is not given the open set's two collect ablations: $(echo "$plan" | grep bin/report)"
for v in collect-ablation collect-ablation-2; do
  plans "bin/score --tiles $tmp/out/openset/tiles/tiles-$v.txt .*-o $tmp/res/openset/$v/score.json" ||
    fail "the open set's default does not plan $v's score"
done
# Its verify ablation (mk/openset.mk OPENSET_VERIFY_ABLATION, --max-tilt=180: no upright bound,
# verify.md §21): the tiles' sub-make is given it, the report its score and options; emptied, neither.
echo "$plan" | grep -q "make .* scenes .*SCENE_DIR=$tmp/out/openset/tiles .*SCENE_VERIFY_ABLATION='--max-tilt=180'" ||
  fail "the open set's sub-make is not given its verify ablation: $(echo "$plan" | grep -o "SCENE_VERIFY_ABLATION='[^']*'" | head -1)"
plans "bin/report .*--openset-verify-ablation $tmp/res/openset/verify-ablation/score.json --openset-verify-ablation-options='--max-tilt=180'" ||
  fail "the report is not given the open set's verify ablation: $(echo "$plan" | grep bin/report)"
plan=$("${sa[@]}" -n all OPENSET=1 OPENSET_SEEDS=1 OPENSET_COVERS=light OPENSET_CROPS=0 OPENSET_VERIFY_ABLATION= 2>&1)
if plans "openset-verify-ablation"; then fail "OPENSET_VERIFY_ABLATION= still gives the report a verify ablation"; fi
echo "$plan" | grep -q "make .* scenes .*SCENE_DIR=$tmp/out/openset/tiles .*SCENE_VERIFY_ABLATION=''" ||
  fail "OPENSET_VERIFY_ABLATION= still gives the sub-make one: $(echo "$plan" | grep -o "SCENE_VERIFY_ABLATION='[^']*'" | head -1)"
plan=$("${sa[@]}" -n all OPENSET=1 OPENSET_SEEDS=1 OPENSET_COVERS=light OPENSET_CROPS=0 2>&1)
# Its classify ablations, the fourth the bed cue alone off (mk/openset.mk OPENSET_CLASSIFY_ABLATION_4,
# classify.md §39): the sub-make gets the four as its list, the report the fourth's score;
# OPENSET_BED_ABLATION=0 leaves the fourth out and the other three in their places.
ob=$tmp/out/openset
echo "$plan" | grep -q "make .* scenes .*SCENE_CLASSIFY_ABLATIONS='$tmp/params/classify-sim.ini $ob/classify-envelope-0.ini $ob/classify-family-entries-1.ini $ob/classify-bed-0.ini'" ||
  fail "the open set's sub-make is not given its four classify ablations: $(echo "$plan" | grep -o "SCENE_CLASSIFY_ABLATIONS='[^']*'" | head -1)"
# The report: the four by name (report --openset-classify-ablation NAME=SCORE), in the places' order.
plans "bin/report .*--openset-classify-ablation every-family=$tmp/res/openset/class-ablation/score.json --openset-classify-ablation no-envelope=$tmp/res/openset/class-ablation-2/score.json --openset-classify-ablation family-entries-1=$tmp/res/openset/class-ablation-3/score.json --openset-classify-ablation no-bed=$tmp/res/openset/class-ablation-4/score.json --openset-collect-ablation" ||
  fail "the report is not given the open set's four classify ablations by name: $(echo "$plan" | grep bin/report)"
plans "bin/score --tiles $tmp/out/openset/tiles/tiles-class-ablation-4.txt .*-o $tmp/res/openset/class-ablation-4/score.json" ||
  fail "the open set's default does not plan the bed ablation's score"
plan=$("${sa[@]}" -n all OPENSET=1 OPENSET_SEEDS=1 OPENSET_COVERS=light OPENSET_CROPS=0 OPENSET_BED_ABLATION=0 2>&1)
echo "$plan" | grep -q "SCENE_CLASSIFY_ABLATIONS='$tmp/params/classify-sim.ini $ob/classify-envelope-0.ini $ob/classify-family-entries-1.ini -'" ||
  fail "OPENSET_BED_ABLATION=0 does not leave the fourth place empty: $(echo "$plan" | grep -o "SCENE_CLASSIFY_ABLATIONS='[^']*'" | head -1)"
if plans "openset/.*class-ablation-4\|no-bed="; then fail "OPENSET_BED_ABLATION=0 still plans the bed ablation"; fi
plans "bin/report .*--openset-classify-ablation family-entries-1=$tmp/res/openset/class-ablation-3/score.json --openset-collect-ablation" ||
  fail "OPENSET_BED_ABLATION=0 does not give the report the other three: $(echo "$plan" | grep bin/report)"
plan=$("${sa[@]}" -n all OPENSET=1 OPENSET_SEEDS=1 OPENSET_COVERS=light OPENSET_CROPS=0 OPENSET_COLLECT_ABLATION_2= 2>&1)
if plans "collect-ablation-2"; then fail "OPENSET_COLLECT_ABLATION_2= still plans collect-ablation-2"; fi
plans "bin/score --tiles $tmp/out/openset/tiles/tiles-collect-ablation.txt" || fail "OPENSET_COLLECT_ABLATION_2= drops the first"
# COLLECT_CALIBRATION emptied (the ablation): collect and the score, not detect, the plan,
# classify, the model chain nor the render; a dry run writes nothing.
plan=$("${sc[@]}" -n scenes COLLECT_CALIBRATION= 2>&1)
plans "bin/collect -i $sr/cands/index.json -o $sr/detections.json" || fail "COLLECT_CALIBRATION= does not re-plan collect: $plan"
plans "bin/score " || fail "COLLECT_CALIBRATION= does not re-plan the score"
for t in rangetrace addnoise detect classify fitvox cocone ncut gmatch verify "collect -i $sr/cands/index.json --plan"; do
  if plans "bin/$t "; then fail "COLLECT_CALIBRATION= re-plans $t"; fi
done
[ "$(echo "$plan" | stages)" -eq 2 ] || fail "COLLECT_CALIBRATION= plans $(echo "$plan" | stages) stages, not 2"
"${sc[@]}" -q scenes COLLECT_CALIBRATION= && fail "make -q scenes COLLECT_CALIBRATION= is clean"
[ "$(stat -c %Y "$sd/.opts/collect.txt")" = 0 ] || fail "a dry run rewrote the collect options file"
# A real run writes the new text (here a run whose goal is the options file: the stages are
# fakes), then collect and the score run (their artifacts touched); the same command again plans
# nothing, and reading the makefiles again does not rewrite the file.
"${sc[@]}" scenes STAGE=true KEEP=1 COLLECT_CALIBRATION= >/dev/null 2>&1 || fail "make did not write the options file"
grep -qx "calibration =" "$sd/.opts/collect.txt" || fail "the options file: $(cat "$sd/.opts/collect.txt")"
written=$(stat -c %Y "$sd/.opts/collect.txt")
[ "$written" -gt 0 ] || fail "the changed options file kept the time 0"
touch "$sr/detections.json" "$tmp/res/scenes/score.json"
plan=$("${sc[@]}" -n scenes COLLECT_CALIBRATION= 2>&1)
[ "$(echo "$plan" | stages)" -eq 0 ] || fail "the same COLLECT_CALIBRATION= again plans stages: $(echo "$plan" | grep stagerun)"
"${sc[@]}" -q scenes COLLECT_CALIBRATION= || fail "make -q scenes COLLECT_CALIBRATION= is not clean after its run"
sleep 1
"${sc[@]}" scenes STAGE=true KEEP=1 COLLECT_CALIBRATION= >/dev/null 2>&1 || fail "make failed"
[ "$(stat -c %Y "$sd/.opts/collect.txt")" = "$written" ] || fail "an unchanged options text was rewritten"
# ... and back to the default: collect and the score again.
plan=$("${sc[@]}" -n scenes 2>&1)
[ "$(echo "$plan" | stages)" -eq 2 ] && plans "bin/collect -i $sr/cands/index.json -o" && plans "bin/score " ||
  fail "COLLECT_CALIBRATION back to its default does not re-plan collect and the score: $(echo "$plan" | grep stagerun)"
# TILE_DENSITY_SCALE=0 (the density rule's ablation): the plan, the model chain, collect and the
# score; not detect nor classify.
plan=$("${sc[@]}" -n scenes COLLECT_CALIBRATION= TILE_DENSITY_SCALE=0 2>&1)
for t in "collect -i $sr/cands/index.json --plan" fitvox cocone ncut gmatch verify "collect -i $sr/cands/index.json -o" score; do
  plans "bin/$t " || fail "TILE_DENSITY_SCALE=0 does not re-plan $t: $(echo "$plan" | grep stagerun)"
done
for t in rangetrace detect classify; do
  if plans "bin/$t "; then fail "TILE_DENSITY_SCALE=0 re-plans $t"; fi
done
# Not tracked: how and where stages run, and what is kept (LAUNCH, KEEP, PROGRESS).
"${sc[@]}" -q scenes COLLECT_CALIBRATION= LAUNCH=slurm KEEP=1 PROGRESS=1 ||
  fail "LAUNCH, KEEP or PROGRESS made the scene run stale"
# The tile workflow (`make tile`, its own options files under OUT): TOP_RASTER=0 re-plans the
# picture alone; CRS the detections and the picture.
td="$tmp/tile"
: >"$tmp/tile.pcd"; at $((now - 60)) "$tmp/tile.pcd"
fake_run "$td" TILE 58
for f in classes.ply top.raster top.png; do : >"$td/$f"; at $((now - 40)) "$td/$f"; done
tl=("${mk[@]}" PROGRESS=0 tile TILE="$tmp/tile.pcd" MODELBASE="$tmp/out/modelbase" OUT="$td")
"${tl[@]}" STAGE=true >"$tmp/tile.log" 2>&1 || fail "make tile did not write its options files: $(tail -3 "$tmp/tile.log")"
[ "$(stat -c %Y "$td/.opts/topview.txt")" = 0 ] || fail "make tile wrote no options file for topview"
[ ! -e "$td/.opts/params.txt" ] || fail "make tile wrote the thesis graph's options into the tile's directory"
"${tl[@]}" -q || fail "make -q tile is not clean on a complete tile: $("${tl[@]}" -n 2>&1 | head -5)"
plan=$("${tl[@]}" -n TOP_RASTER=0 2>&1)
[ "$(echo "$plan" | stages)" -eq 1 ] && plans "bin/topview -i $tmp/tile.pcd --detections" ||
  fail "TOP_RASTER=0 does not plan the picture alone: $(echo "$plan" | grep stagerun)"
plan=$("${tl[@]}" -n CRS=EPSG:32633 2>&1)
[ "$(echo "$plan" | stages)" -eq 2 ] && plans "bin/collect .*--crs EPSG:32633" ||
  fail "CRS does not plan collect and the picture alone: $(echo "$plan" | grep stagerun)"
# `make tiles`: every .las, .laz and .pcd of the directory becomes a `tile` run (a directory of
# .laz tiles held "no .las or .pcd file" before stop 66).
mkdir -p "$tmp/tiles" && : >"$tmp/tiles/x.laz" && : >"$tmp/tiles/y.pcd" && : >"$tmp/tiles/z.las"
plan=$("${mk[@]}" -n PROGRESS=0 tiles TILES="$tmp/tiles/" MODELBASE="$tmp/out/modelbase" OUT="$tmp/batch/" 2>&1)
for f in x.laz y.pcd z.las; do
  echo "$plan" | grep -q "tile TILE=$tmp/tiles/$f OUT=$tmp/batch/${f%.*} " ||
    fail "make tiles does not run the tile $f: $(echo "$plan" | grep -m3 'tile TILE=\|tiles:')"
done
[ ! -e "$tmp/batch" ] || fail "make -n tiles wrote $tmp/batch"
rm -r "$tmp/tiles"
# The thesis graph: another parameter directory (P, the same files, older) re-plans its stages.
cp -rp "$tmp/params" "$tmp/params2"
plan=$("${mk[@]}" -n all P="$tmp/params2" 2>&1)
for t in rangetrace fitvox cocone ncut gmatch verify report; do
  plans "bin/$t " || fail "P=<another directory> does not re-plan $t"
done
rm -rf "$tmp/params2"
[ ! -e "$tmp/out/.opts/real.txt" ] || fail "a make of another goal wrote the real tiles' options: $(cat "$tmp/out/.opts/real.txt")"
mv "$tmp/real.txt.keep" "$tmp/out/.opts/real.txt"
[ "$(thesis_files)" = "$thesis_before" ] ||
  fail "the options checks changed the thesis slice's files: $(diff <(echo "$thesis_before") <(thesis_files) | head -5)"
"${mk[@]}" -q all || fail "make -q all not clean after the options checks"

at $((now - 10)) "$tmp/params/ncut.ini"
plan=$("${mk[@]}" -n all 2>&1)
plans "bin/ncut " || fail "ncut not re-planned after ncut.ini changed"
plans "bin/gmatch " || fail "gmatch not re-planned"
plans "bin/verify " || fail "verify not re-planned"
plans "bin/report " || fail "report not re-planned"
plans "figures mesh" || fail "segmentation figure not re-planned"
for early in rangetrace addnoise fitvox cocone; do
  if plans "bin/$early "; then fail "$early re-planned, but only ncut.ini changed"; fi
done

at $((now - 5)) "$tmp/params/fitvox.ini"
plan=$("${mk[@]}" -n all 2>&1)
plans "bin/fitvox " || fail "fitvox not re-planned after fitvox.ini changed"
plans "bin/cocone " || fail "cocone not re-planned after fitvox.ini changed"
if plans "bin/addnoise "; then fail "addnoise re-planned, but only fitvox.ini changed"; fi

# The records of the real build (the one these tests run from: <build>/bin is $2): report's
# record names the documents/ it reads (areas.json's reader) and the shared sources it
# includes, and no other tool's (not tools/areas); areas' names the same document (its writer);
# famscore's and rangetrace's name the simulator's (sim/) sources they link.
real_build=$(cd "${2:-}/.." 2>/dev/null && pwd)
if [ -n "$real_build" ] && [ -f "$real_build/CMakeFiles/Makefile.cmake" ]; then
  cd "$src" || exit 1
  scripts/tool-deps.sh "$real_build" report "$tmp/report.mk"
  for f in documents/src/areas.cpp documents/include/canopy/documents/areas.h tools/report/report.cpp tools/report/main.cpp \
           documents/src/stage_time.cpp documents/include/canopy/documents/stage_time.h common/CMakeLists.txt; do
    grep -q "^\$(BIN)/report:.* $f\( \|\$\)" "$tmp/report.mk" || fail "the real build's record of report misses $f"
  done
  # (every CMakeLists.txt is there: CMake reads them all to configure any target)
  if grep "^\$(BIN)/report:" "$tmp/report.mk" | tr ' ' '\n' | grep -q "^tools/\(fitvox\|areas\)/.*\.\(cpp\|h\)$\|^/\|\.md$"; then
    fail "the real build's record of report names a file it is not built from"
  fi
  scripts/tool-deps.sh "$real_build" areas "$tmp/areas.mk"
  for f in documents/src/areas.cpp documents/include/canopy/documents/areas.h tools/areas/areas.cpp; do
    grep -q "^\$(BIN)/areas:.* $f\( \|\$\)" "$tmp/areas.mk" || fail "the real build's record of areas misses $f"
  done
  # famscore and rangetrace link the simulator's library (sim/): a change there rebuilds both.
  scripts/tool-deps.sh "$real_build" famscore "$tmp/famscore.mk"
  for f in sim/src/families.cpp sim/include/canopy/sim/families.h sim/CMakeLists.txt; do
    grep -q "^\$(BIN)/famscore:.* $f\( \|\$\)" "$tmp/famscore.mk" || fail "the real build's record of famscore misses $f"
  done
  if grep "^\$(BIN)/famscore:" "$tmp/famscore.mk" | tr ' ' '\n' | grep -q "^tools/rangetrace/.*\.\(cpp\|h\)$"; then
    fail "the real build's record of famscore names a source of tools/rangetrace"
  fi
  scripts/tool-deps.sh "$real_build" rangetrace "$tmp/rangetrace.mk"
  for f in sim/src/povray_run.cpp sim/src/tile_placement.cpp sim/include/canopy/sim/tile.h tools/rangetrace/main.cpp; do
    grep -q "^\$(BIN)/rangetrace:.* $f\( \|\$\)" "$tmp/rangetrace.mk" || fail "the real build's record of rangetrace misses $f"
  done
else
  echo "note: no Makefile-generator build at ${2:-}/..: the real records are not checked"
fi

echo "ok: make graph"
