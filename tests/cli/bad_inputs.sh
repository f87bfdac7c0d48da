#!/usr/bin/env bash
# Bad data inputs to every canopy tool (hardening.md, "Bad inputs, every tool", stop 68).
# Usage: bad_inputs.sh BIN_DIR SOURCE_DIR [TOOL...]   (no TOOL: every tool of the matrix)
#
# Each case runs one tool on one broken input (a missing path, an empty file, a directory, a file
# cut short at several points, garbage behind the right magic, a header declaring ~4e9 items
# over a few bytes, JSON of the wrong type or shape, a broken modelbase) and asserts the project's
# standard (README, CONVENTIONS): exit 1, stderr names the file and the problem, the output the
# command line names is untouched (a pre-existing file keeps its bytes; nothing else appears in its
# directory: no temporary file), no crash (exit >= 128, a sanitizer's 86), and bounded memory: every
# run is under `ulimit -v` of 2 GB (not for a sanitizer build, whose shadow memory needs more) and
# a 60 s timeout. Inputs are generated here, into a temporary directory; the tools write only there.
set -u
bin=$1
src=$2
shift 2
only=" $* "
tmp=$(mktemp -d)
[ -n "${BAD_INPUTS_KEEP:-}" ] || trap 'rm -rf "$tmp"' EXIT  # BAD_INPUTS_KEEP=1: keep the inputs
export LC_ALL=C
fails=0
cases=0
limit_kb=2097152
if ldd "$bin/fitvox" 2>/dev/null | grep -q libasan; then limit_kb=unlimited; fi

# --- inputs -------------------------------------------------------------------------------------
in=$tmp/in
mkdir -p "$in/adir"
: >"$in/empty"
cp "$in/empty" "$in/empty.pcd"
cp "$in/empty" "$in/empty.ply"
cp "$in/empty" "$in/empty.las"
cp "$in/empty" "$in/empty.json"
cp "$in/empty" "$in/empty.txt"
mkdir -p "$in/dir.pcd" "$in/dir.ply" "$in/dir.las" "$in/dir.json" "$in/dir.txt"

pcd_header() { # FIELDS-LINE SIZE TYPE COUNT N DATA
  printf '# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\nCOUNT %s\nWIDTH %s\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %s\nDATA %s\n' \
    "$1" "$2" "$3" "$4" "$5" "$5" "$6"
}
# A valid binary PCD of 40 points x y z (float32), then broken copies.
{
  pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 40 binary
  head -c 480 /dev/zero | tr '\0' '\100'  # 0x40404040 = 3.0 as float32
} >"$in/good.pcd"
head -c 30 "$in/good.pcd" >"$in/cut-mid-header.pcd"
pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 40 binary >"$in/cut-after-header.pcd"
head -c $(($(stat -c %s "$in/good.pcd") - 200)) "$in/good.pcd" >"$in/cut-mid-data.pcd"
{ printf '# .PCD v0.7\nVERSION 0.7\nFIELDS \x01\xff\xfe\n'; head -c 300 /dev/urandom; } >"$in/garbage.pcd"
{ pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 4000000000 binary; head -c 480 /dev/zero; } >"$in/huge.pcd"
{ pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 4000000000 ascii; printf '1 2 3\n4 5 6\n'; } >"$in/huge-ascii.pcd"
{ pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 300000000 binary_compressed
  printf '\x10\x00\x00\x00\x00\xa4\x93\xd6'; head -c 16 /dev/zero; } >"$in/huge-compressed.pcd"
{ pcd_header "x y z" "4 4 4" "F F F" "1 1 1" 4 ascii; printf '1 2 3\n4 5\n'; } >"$in/ascii-short-row.pcd"

# A valid binary PLY mesh (4 vertices, 2 faces), then broken copies.
ply_header() { # FORMAT NV NF
  printf 'ply\nformat %s 1.0\nelement vertex %s\nproperty float x\nproperty float y\nproperty float z\nelement face %s\nproperty list uchar int vertex_indices\nend_header\n' "$1" "$2" "$3"
}
{
  ply_header ascii 4 2
  printf '0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n'
} >"$in/good.ply"
head -c 25 "$in/good.ply" >"$in/cut-mid-header.ply"
ply_header binary_little_endian 4 2 >"$in/cut-after-header.ply"
{ ply_header binary_little_endian 4 2; head -c 30 /dev/zero; } >"$in/cut-mid-data.ply"
{ printf 'ply\nformat binary_little_endian 1.0\nelement \xff\xfe\x01 3\n'; head -c 300 /dev/urandom; } >"$in/garbage.ply"
{ ply_header binary_little_endian 4000000000 1; head -c 100 /dev/zero; } >"$in/huge-vertices.ply"
{ ply_header binary_little_endian 3 4000000000; head -c 100 /dev/zero; } >"$in/huge-faces.ply"
{ ply_header ascii 4000000000 0; printf '0 0 0\n1 0 0\n'; } >"$in/huge-ascii.ply"
# A PLY point set (no faces) and its huge variant, for the point-set readers.
{ printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n'; } >"$in/good-points.ply"

# LAS: the repository's LAS 1.2 (1065 points of 34 bytes from byte 227) and LAZ, then broken copies.
cp "$src/tests/las/data/simple.las" "$in/good.las"
cp "$src/tests/las/data/simple.laz" "$in/good.laz"
head -c 100 "$in/good.las" >"$in/cut-mid-header.las"
head -c 227 "$in/good.las" >"$in/cut-after-header.las"
head -c 20000 "$in/good.las" >"$in/cut-mid-data.las"
{ printf 'LASF'; head -c 4000 /dev/urandom; } >"$in/garbage.las"
cp "$in/good.las" "$in/huge.las"  # legacy point count (offset 107) = 4 000 000 000
printf '\x00\x28\x6b\xee' | dd of="$in/huge.las" bs=1 seek=107 conv=notrunc status=none
head -c 9000 "$in/good.laz" >"$in/cut-mid-data.laz"
cp "$in/good.laz" "$in/garbage-data.laz"  # the compressed points overwritten
head -c 6000 /dev/urandom | dd of="$in/garbage-data.laz" bs=1 seek=2000 conv=notrunc status=none

# OBJ and STL meshes (rangetrace --model, meshsize).
: >"$in/empty.obj"
: >"$in/empty.stl"
mkdir -p "$in/dir.obj"
printf 'v 1 2\nf 1 2 3\n\x00\xff' >"$in/garbage.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 999999999\n' >"$in/bad-index.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' >"$in/no-faces.obj"
{ head -c 80 /dev/zero; printf '\x00\x28\x6b\xee'; head -c 50 /dev/zero; } >"$in/huge.stl"  # 4e9 triangles
{ head -c 80 /dev/zero; printf '\x02\x00\x00\x00'; head -c 50 /dev/zero; } >"$in/cut-binary.stl"
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n' >"$in/cut-ascii.stl"

# JSON documents of the wrong kind.
printf '{"format": "canopy.segment_graph", "version": 1, "segm' >"$in/cut.json"
printf '\x00\xff\xfe garbage' >"$in/garbage.json"
printf '[1, 2, 3]\n' >"$in/array.json"
printf '"a string"\n' >"$in/string.json"
printf '{"format": "canopy.nothing_known", "version": 1}\n' >"$in/unknown-format.json"
printf '{"format": 7, "version": "one", "segments": {"a": 1}, "candidates": 3, "results": "x", "detections": 1, "vehicles": null}\n' >"$in/wrong-types.json"
{ head -c 200000 /dev/zero | tr '\0' '['; } >"$in/deep.json"

# Modelbases: missing, a file, an empty directory, one whose graph is garbage.
mkdir -p "$in/mb-empty" "$in/mb-bad"
cp "$in/garbage.json" "$in/mb-bad/m1.json"
cp "$in/garbage.pcd" "$in/mb-bad/m1.pcd"
printf 'car\n' >"$in/mb-bad/m1.class"

# Paths that are not plain files: a link to itself, a dangling link.
ln -s loop "$in/loop"
ln -s nowhere "$in/dangling.pcd"

# Text inputs (manifests, lists, CSV).
printf '\x00\x01\xff\xfe garbage\nmore garbage here\n' >"$in/garbage.txt"
printf 'a b c d e f g h i j\n' >"$in/wrong-columns.txt"

# Valid companions, so that a tool reaches the broken input it is given beside them: a 10 x 10
# grid mesh, its segment graph (ncut), a one-model modelbase of it, gmatch's result.
{
  printf 'ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nelement face 162\nproperty list uchar int vertex_indices\nend_header\n'
  for j in 0 1 2 3 4 5 6 7 8 9; do for i in 0 1 2 3 4 5 6 7 8 9; do echo "0.$i 0.$j 1.$((i * j % 3))"; done; done
  for j in 0 1 2 3 4 5 6 7 8; do for i in 0 1 2 3 4 5 6 7 8; do
    a=$((j * 10 + i))
    echo "3 $a $((a + 1)) $((a + 11))"
    echo "3 $a $((a + 11)) $((a + 10))"
  done; done
} >"$in/grid.ply"
mkdir -p "$in/mb"
"$bin/ncut" -q -i "$in/grid.ply" -o "$in/graph.json" || { echo "FAIL: ncut on the grid mesh"; exit 1; }
cp "$in/graph.json" "$in/mb/m1.json"
"$bin/gmatch" -q -i "$in/graph.json" --modelbase "$in/mb" -o "$in/match.json" \
  || { echo "FAIL: gmatch on the grid's graph"; exit 1; }
cp "$in/good.pcd" "$in/pcd-named.ply"
cp "$in/garbage.json" "$in/json-named.ply"
{
  pcd_header "x y z normal_x normal_y normal_z" "4 4 4 4 4 4" "F F F F F F" "1 1 1 1 1 1" 40 ascii
  for i in $(seq 40); do echo "0.$i 0.$((i % 7)) 1.$((i % 3)) 0 0 1"; done
} >"$in/normals.pcd"
# A tile's candidates index (detect on the LAS: no candidates) and its detections (collect).
"$bin/detect" -q -i "$in/good.las" -o "$in/det" || { echo "FAIL: detect on $in/good.las"; exit 1; }
"$bin/collect" -q -i "$in/det/index.json" -o "$in/detections.json" \
  || { echo "FAIL: collect on the index"; exit 1; }
# Detections of another tile: their one footprint km away from good.las's points (topview, stop 70).
printf '{"format":"canopy.detections","version":1,"tile":"other.laz","detections":[{"candidate":"c1",%s}]}\n' \
  '"footprint":[[10,10],[12,10],[12,11],[10,11]]' >"$in/far-detections.json"
# Trajectories (formats/README.md, "Trajectory"): header only, a row short.
printf '# canopy trajectory 1\n' >"$in/header-only.traj"
printf '# canopy trajectory 1\ntime x y z roll pitch heading\n1 2 3\n' >"$in/short-row.traj"
# Scene recipes (share/scenes/README.md).
printf 'views = circle 2 75\nfoliage_count = \x01\xff\n' >"$in/garbage.scene"
printf 'views = circle 4000000000 75\n' >"$in/huge-views.scene"
printf 'no_such_key = 1\n' >"$in/unknown-key.scene"
mkdir -p "$in/dir.scene"
: >"$in/empty.scene"

# CSV of figures plot.
printf 'object,scene,noise_mm,score,rank,entropy\n' >"$in/header-only.csv"
printf 'object,scene,noise_mm,score,rank,entropy\nsedan,circle,abc,0.5,1,0\n' >"$in/bad-number.csv"
printf 'a,b\n1,2,3\n' >"$in/wrong-header.csv"
# baseline's model cache (baseline --prepare), then broken copies.
mkdir -p "$in/mb-surfaces"
cp "$in/graph.json" "$in/mb-surfaces/m1.json"
cp "$in/normals.pcd" "$in/mb-surfaces/m1.pcd"
"$bin/baseline" -q --prepare --modelbase "$in/mb-surfaces" -o "$in/cache.bin" || { echo "FAIL: baseline --prepare"; exit 1; }
head -c 100 "$in/cache.bin" >"$in/cache-cut-header.bin"
head -c $(($(stat -c %s "$in/cache.bin") / 2)) "$in/cache.bin" >"$in/cache-cut-body.bin"
sed 's/^body [0-9]* /body 4000000000000 /' "$in/cache.bin" >"$in/cache-huge-body.bin"
sed 's/^models 1$/models 4000000000/' "$in/cache.bin" >"$in/cache-huge-models.bin"
# The experiment's manifest (report) naming a trial whose match.json is garbage.
mkdir -p "$in/trial1"
cp "$in/garbage.json" "$in/trial1/match.json"
printf 'trial sedan circle 0 %s\nmodel sedan %s\n' "$in/trial1" "$in/graph.json" >"$in/manifest-bad-trial.txt"

# --- the check ----------------------------------------------------------------------------------
# bad TOOL LABEL NAMED PROBLEM-ERE OUT-EXT -- ARGS...
#   ARGS may hold @OUT@ (the output: a pre-existing file, which must keep its bytes) and
#   @OUTDIR@ (an output directory that does not exist and must not appear), @OUTD@ (an existing
#   output directory holding the pre-existing file, where nothing may appear), @OUT2@ (a second
#   output, which must not appear). The tool's standard input is $stdin_file (default /dev/null).
#   NAMED: a string stderr must contain (the input's path); PROBLEM-ERE: an extended regular
#   expression (case-insensitive) stderr must match once NAMED is taken out of it (so that a
#   word of the file's name cannot pass for the problem).
bad() {
  local tool=$1 label=$2 named=$3 problem=$4 ext=$5
  shift 6
  case "$only" in "  ") ;; *" $tool "*) ;; *) return 0 ;; esac
  cases=$((cases + 1))
  local d=$tmp/run$cases
  mkdir -p "$d/out"
  local out=$d/out/result.$ext
  printf 'pre-existing output\n' >"$out"
  local args=() a
  for a in "$@"; do
    a=${a//@OUT@/$out}
    a=${a//@OUTDIR@/$d/out/newdir}
    a=${a//@OUTD@/$d/out}
    a=${a//@OUT2@/$d/out/second.$ext}
    args+=("$a")
  done
  (
    ulimit -v "$limit_kb"
    exec timeout 60 "$bin/$tool" "${args[@]}"
  ) <"${stdin_file:-/dev/null}" >"$d/stdout" 2>"$d/stderr"
  local rc=$? why=""
  if [ $rc -eq 124 ]; then
    why="timed out (60 s)"
  elif [ $rc -ge 128 ] || [ $rc -eq 86 ]; then
    why="crashed (exit $rc)"
  elif [ $rc -ne 1 ]; then
    why="exit $rc, want 1"
  elif ! grep -qF -- "$named" "$d/stderr"; then
    why="stderr does not name '$named'"
  elif ! grep -vF -- "$bin/$tool" "$d/stderr" | awk -v p="$named" '{ while ((i = index($0, p)) > 0) $0 = substr($0, 1, i - 1) substr($0, i + length(p)); print }' |
    grep -qiE -- "$problem"; then
    why="stderr does not match /$problem/"
  elif [ "$(cat "$out")" != "pre-existing output" ]; then
    why="the pre-existing output was changed"
  elif [ "$(ls -A "$d/out")" != "result.$ext" ]; then
    why="left in the output directory: $(ls -A "$d/out" | grep -vx "result.$ext" | tr '\n' ' ')"
  fi
  if grep -qE 'AddressSanitizer|runtime error:|LeakSanitizer' "$d/stderr"; then
    why="sanitizer report"
  fi
  if [ -n "$why" ]; then
    fails=$((fails + 1))
    echo "FAIL [$tool] $label: $why"
    echo "     $tool ${args[*]}"
    sed -n '1,3s/^/     stderr: /p' "$d/stderr" | cut -c1-300
  else
    [ -n "${BAD_INPUTS_VERBOSE:-}" ] && echo "ok [$tool] $label: $(head -1 "$d/stderr" | cut -c1-200)"
  fi
  rm -rf "$d"
  return 0
}

# Problems, as the messages must state them.
P_MISSING='no such file|does not exist|cannot open|not found'
P_EMPTY='empty'
P_DIR='directory'
P_TRUNC='truncat|end of file|ends |short|incomplete|, not a PCD file'
P_GARBAGE='control byte|supported|corrupt|signature|not a|unknown|invalid|unexpected|bad|parse|malformed|unsupported|header|expected|magic|property|field|format'
P_HUGE='truncat|exceed|too (many|large|big)|more than|limit|declares|says|holds|short|bytes|, not a PCD file'
P_JSON='json|parse|expected|format|must be|not an? |type|missing|unknown|document|depth|nest'

# split_args ARGS-BEFORE -- ARGS-AFTER: into the calling matrix's pre and post arrays (bash's
# dynamic scope: the caller declares them local).
split_args() {
  local seen=0 a
  for a in "$@"; do
    if [ "$a" = "--" ]; then seen=1; elif [ $seen -eq 0 ]; then pre+=("$a"); else post+=("$a"); fi
  done
}

# try LABEL FILE PROBLEM: one case of the calling matrix (its tool, ext, pre and post), FILE
# given between pre and post and named in the message.
try() { bad "$tool" "$1" "$2" "$3" "$ext" -- "${pre[@]}" "$2" "${post[@]}"; }

# point_cloud_matrix TOOL OUT-EXT ARGS-BEFORE-INPUT... -- ARGS-AFTER...: the input's option is
# the last word before the input path (e.g. -i).
point_cloud_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  local f
  try "missing PCD" "$in/missing.pcd" "$P_MISSING"
  for f in empty.pcd empty.las empty.ply; do
    try "$f" "$in/$f" "$P_EMPTY"
  done
  try "directory" "$in/dir.pcd" "$P_DIR"
  for f in cut-mid-header.pcd cut-after-header.pcd cut-mid-data.pcd ascii-short-row.pcd \
    cut-mid-header.ply cut-after-header.ply cut-mid-data.ply \
    cut-mid-header.las cut-after-header.las cut-mid-data.las cut-mid-data.laz; do
    try "$f" "$in/$f" "$P_TRUNC"
  done
  for f in garbage.pcd garbage.ply garbage.las garbage-data.laz garbage.json; do
    try "$f" "$in/$f" "$P_GARBAGE"
  done
  for f in huge.pcd huge-ascii.pcd huge-compressed.pcd huge-vertices.ply huge-ascii.ply huge.las; do
    try "$f" "$in/$f" "$P_HUGE"
  done
}

# json_matrix TOOL OUT-EXT ARGS-BEFORE -- ARGS-AFTER (as point_cloud_matrix)
json_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  local f
  try "missing JSON" "$in/missing.json" "$P_MISSING"
  try "empty JSON" "$in/empty.json" "$P_EMPTY"
  try "directory" "$in/dir.json" "$P_DIR"
  for f in cut.json garbage.json array.json string.json unknown-format.json wrong-types.json deep.json good.pcd; do
    try "$f" "$in/$f" "$P_JSON"
  done
}

# modelbase_matrix TOOL OUT-EXT ARGS-BEFORE -- ARGS-AFTER
modelbase_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  try "missing modelbase" "$in/mb-missing" "$P_MISSING"
  try "modelbase a file" "$in/good.pcd" 'is not a directory'
  try "empty modelbase" "$in/mb-empty" 'no model|empty|holds no|no .*(json|pcd)'
  bad "$tool" "modelbase with a garbage model" "$in/mb-bad/m1." "$P_JSON|$P_GARBAGE" "$ext" -- "${pre[@]}" "$in/mb-bad" "${post[@]}"
}

# text_matrix TOOL OUT-EXT ARGS-BEFORE -- ARGS-AFTER
text_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  try "missing text" "$in/missing.txt" "$P_MISSING"
  try "directory" "$in/dir.txt" "$P_DIR"
  try "garbage text" "$in/garbage.txt" "$P_GARBAGE|line|column|field|expected"
}

# mesh_matrix TOOL OUT-EXT ARGS-BEFORE -- ARGS-AFTER: PLY meshes (and what is not one).
mesh_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  local f
  try "missing PLY" "$in/missing.ply" "$P_MISSING"
  try "empty PLY" "$in/empty.ply" "$P_EMPTY"
  try "directory" "$in/dir.ply" "$P_DIR"
  for f in cut-mid-header.ply cut-after-header.ply cut-mid-data.ply; do
    try "$f" "$in/$f" "$P_TRUNC"
  done
  for f in garbage.ply pcd-named.ply json-named.ply; do
    try "$f" "$in/$f" "$P_GARBAGE"
  done
  for f in huge-vertices.ply huge-faces.ply huge-ascii.ply; do
    try "$f" "$in/$f" "$P_HUGE"
  done
}

# obj_stl_matrix TOOL OUT-EXT ARGS-BEFORE -- ARGS-AFTER: OBJ and STL meshes.
obj_stl_matrix() {
  local tool=$1 ext=$2
  shift 2
  local pre=() post=()
  split_args "$@"
  local f
  for f in empty.obj empty.stl; do
    try "$f" "$in/$f" "$P_EMPTY"
  done
  try "directory" "$in/dir.obj" "$P_DIR"
  try "garbage.obj" "$in/garbage.obj" "line 1: malformed vertex"
  try "bad-index.obj" "$in/bad-index.obj" "line 4: face index out of range"
  try "no-faces.obj" "$in/no-faces.obj" "no faces"
  for f in huge.stl cut-binary.stl cut-ascii.stl; do
    try "$f" "$in/$f" "$P_TRUNC"
  done
}

# --- the matrix ---------------------------------------------------------------------------------
point_cloud_matrix addnoise pcd -o @OUT@ -i --
point_cloud_matrix fitvox pcd -o @OUT@ -i --
point_cloud_matrix cocone ply -o @OUT@ -i --
point_cloud_matrix pcd2ply ply -o @OUT@ -i --
point_cloud_matrix classify json -o @OUT@ -i --
point_cloud_matrix baseline json -o @OUT@ --modelbase "$in/mb" -i --
point_cloud_matrix areas json -o @OUT@ --samples "$in/good.pcd" --mesh "$in/grid.ply" --segments "$in/graph.json" --scan --
point_cloud_matrix detect txt -o @OUTDIR@ -i --
point_cloud_matrix verify json -o @OUT@ -i "$in/match.json" --segments "$in/graph.json" --modelbase "$in/mb" --points --
point_cloud_matrix topview json --raster-out @OUT@ -i --
mesh_matrix ncut json -o @OUT@ -i --
mesh_matrix rangetrace pcd -o @OUT@ --scene circle --model --
mesh_matrix meshsize txt -o @OUT@ -i --
obj_stl_matrix rangetrace pcd -o @OUT@ --scene circle --model --
obj_stl_matrix meshsize txt -o @OUT@ -i --
mesh_matrix figures png mesh -o @OUT@ -i --
json_matrix gmatch json -o @OUT@ --modelbase "$in/mb" -i --
json_matrix verify json -o @OUT@ --points "$in/good.pcd" --modelbase "$in/mb" -i --
json_matrix verify json -o @OUT@ --points "$in/good.pcd" --modelbase "$in/mb" -i "$in/match.json" --segments --
json_matrix classify json -o @OUT@ -i "$in/good.pcd" --index --
json_matrix collect json -o @OUT@ -i --
# An index with no candidates and a missing or wrong --modelbase / --verdicts: the directories
# were read only per candidate, so collect wrote detections.json with exit 0 (stop 68).
bad collect "no candidates, modelbase missing" "$in/missing-mb" "does not exist" json -- -o @OUT@ -i "$in/det/index.json" --modelbase "$in/missing-mb"
bad collect "no candidates, modelbase a file" "$in/good.pcd" "is not a directory" json -- -o @OUT@ -i "$in/det/index.json" --modelbase "$in/good.pcd"
bad collect "no candidates, verdicts missing" "$in/missing-verdicts" "does not exist" json -- -o @OUT@ -i "$in/det/index.json" --verdicts "$in/missing-verdicts"
bad collect "no candidates, verdicts a file" "$in/good.pcd" "is not a directory" json -- -o @OUT@ -i "$in/det/index.json" --verdicts "$in/good.pcd"
text_matrix collect json -o @OUT@ -i "$in/det/index.json" --calibration --
bad collect "empty calibration" "$in/empty.txt" "has no model-bias" json -- -o @OUT@ -i "$in/det/index.json" --calibration "$in/empty.txt"
text_matrix collect json -o @OUT@ -i "$in/det/index.json" --model-classes --
bad collect "model classes without a header" "$in/empty.txt" "no header line" json -- -o @OUT@ -i "$in/det/index.json" --model-classes "$in/empty.txt"
json_matrix candtruth json -o @OUT@ --tile "$in/good.pcd" -i --
json_matrix score json -o @OUT@ -t "$in/missing-truth.json" -d --
json_matrix score json -o @OUT@ -d "$in/detections.json" -t --
point_cloud_matrix candtruth json -o @OUT@ -i "$in/det/index.json" --tile --
json_matrix topview png -o @OUT@ -i "$in/good.pcd" --detections --
# --index and --truth beside detections that reject nothing (the index was not read then).
json_matrix topview png -o @OUT@ -i "$in/good.las" --detections "$in/detections.json" --index --
json_matrix topview png -o @OUT@ -i "$in/good.las" --detections "$in/detections.json" --truth --
bad topview "detections of another tile" "$in/far-detections.json" "none of its 1 footprints .* lies within 10 m of the points of .*good.las.*another tile\? \(they record the tile other.laz\)" png -- \
  -o @OUT@ -i "$in/good.las" --detections "$in/far-detections.json"
json_matrix areas json -o @OUT@ --scan "$in/good.pcd" --samples "$in/good.pcd" --mesh "$in/grid.ply" --segments --
modelbase_matrix gmatch json -o @OUT@ -i "$in/graph.json" --modelbase --
modelbase_matrix verify json -o @OUT@ --points "$in/normals.pcd" -i "$in/match.json" --segments "$in/graph.json" --modelbase --
modelbase_matrix classify json -o @OUT@ -i "$in/good.pcd" --modelbase --
modelbase_matrix baseline json -o @OUT@ -i "$in/normals.pcd" --modelbase --
text_matrix famscore csv --modelbase "$in/mb" --confusion @OUT@ --accuracy @OUT2@ -i --
text_matrix score json -o @OUT@ --tiles --
text_matrix detect txt -o @OUTDIR@ -i "$in/good.las" --trajectory --
bad detect "trajectory: header line only" "$in/header-only.traj" "no header line|time x y z" txt -- -o @OUTDIR@ -i "$in/good.las" --trajectory "$in/header-only.traj"
text_matrix verify json -o @OUT@ --points "$in/normals.pcd" -i "$in/match.json" --segments "$in/graph.json" --modelbase "$in/mb" --trajectory --
bad verify "trajectory: header line only" "$in/header-only.traj" "no header line|time x y z" json -- -o @OUT@ --points "$in/normals.pcd" -i "$in/match.json" --segments "$in/graph.json" --modelbase "$in/mb" --trajectory "$in/header-only.traj"
bad verify "trajectory: a short row" "$in/short-row.traj" "line 3|column|values|expected" json -- -o @OUT@ --points "$in/normals.pcd" -i "$in/match.json" --segments "$in/graph.json" --modelbase "$in/mb" --trajectory "$in/short-row.traj"
text_matrix report md --results @OUTD@ --manifest --
text_matrix classify json -o @OUT@ -i "$in/good.pcd" --modelbase "$in/mb" --model-classes --
# A JSON file with a NUL byte: the library read it as the end of input ("unexpected end of input").
bad gmatch "JSON with a NUL byte" "$in/garbage.json" "NUL byte at byte 0" json -- -o @OUT@ --modelbase "$in/mb" -i "$in/garbage.json"
# A runs manifest naming a class the families do not know: exit 2 naming no file.
mkdir -p "$in/mb-classes"
cp "$in/graph.json" "$in/mb-classes/m1.json"
printf 'sedan\n' >"$in/mb-classes/m1.class"
printf '%s car 1 light 0\n' "$in/missing-verdict.json" >"$in/runs-unknown-class.txt"
bad famscore "runs manifest with an unknown class" "$in/runs-unknown-class.txt" "line 1: unknown vehicle class 'car'" csv -- \
  --modelbase "$in/mb-classes" --confusion @OUT@ --accuracy @OUT2@ -i "$in/runs-unknown-class.txt"
printf '%s sedan 1 light 0\n' "$in/garbage.json" >"$in/runs-garbage-verdict.txt"
bad famscore "runs manifest naming a garbage verdict" "$in/garbage.json" "not valid JSON" csv -- \
  --modelbase "$in/mb-classes" --confusion @OUT@ --accuracy @OUT2@ -i "$in/runs-garbage-verdict.txt"
for f in missing.csv empty.txt dir.txt header-only.csv bad-number.csv wrong-header.csv; do
  case $f in
    missing.csv) p=$P_MISSING ;; empty.txt) p=$P_EMPTY ;; dir.txt) p=$P_DIR ;;
    header-only.csv) p="no row" ;; bad-number.csv) p="line 2: noise_mm 'abc' is not a number" ;;
    *) p="header lacks the column 'object'" ;;
  esac
  bad figures "plot: $f" "$in/$f" "$p" png -- plot -o @OUT@ -i "$in/$f"
done
for f in cache-cut-header.bin cache-cut-body.bin cache-huge-body.bin; do
  bad baseline "model cache $f" "$in/$f" "$P_TRUNC" json -- -o @OUT@ -i "$in/normals.pcd" --modelbase "$in/mb-surfaces" --model-cache "$in/$f"
done
bad baseline "model cache of 4e9 models" "$in/cache-huge-models.bin" "4000000000 models" json -- -o @OUT@ -i "$in/normals.pcd" --modelbase "$in/mb-surfaces" --model-cache "$in/cache-huge-models.bin"
bad baseline "model cache: garbage" "$in/garbage.txt" "not a canopy.baseline-models file" json -- -o @OUT@ -i "$in/normals.pcd" --modelbase "$in/mb-surfaces" --model-cache "$in/garbage.txt"
bad report "manifest naming a garbage match.json" "$in/trial1/match.json" "not valid JSON" md -- --results @OUTD@ --manifest "$in/manifest-bad-trial.txt"
# Standard input, /dev/null, a link loop, a dangling link.
stdin_file=$in/cut-mid-data.pcd bad fitvox "stdin: a cut PCD" "<stdin>" "$P_TRUNC" pcd -- -o @OUT@ -i -
stdin_file=$in/cut-mid-header.ply bad ncut "stdin: a PLY cut in its header" "<stdin>" "$P_TRUNC" json -- -o @OUT@ -i -
stdin_file=$in/garbage.json bad gmatch "stdin: JSON with a NUL byte" "<stdin>" "NUL byte at byte 0" json -- -o @OUT@ --modelbase "$in/mb" -i -
stdin_file=$in/huge.las bad addnoise "stdin: LAS declaring 4e9 points" "<stdin>" "$P_HUGE" pcd -- -o @OUT@ -i -
bad fitvox "/dev/null" "/dev/null" "$P_EMPTY" pcd -- -o @OUT@ -i /dev/null
bad gmatch "/dev/null" "/dev/null" "$P_EMPTY" json -- -o @OUT@ --modelbase "$in/mb" -i /dev/null
bad fitvox "a link loop" "$in/loop" "too many levels of symbolic links" pcd -- -o @OUT@ -i "$in/loop"
bad fitvox "a dangling link" "$in/dangling.pcd" "$P_MISSING" pcd -- -o @OUT@ -i "$in/dangling.pcd"
bad gmatch "modelbase: a link loop" "$in/loop" "too many levels of symbolic links" json -- -o @OUT@ -i "$in/graph.json" --modelbase "$in/loop"
# A NUL byte quoted from a line: the message went on only to the NUL ("unknown record '").
bad report "manifest line with a NUL byte" "$in/garbage.txt" "unknown record '\\\\x00\\\\x01" md -- --results @OUTD@ --manifest "$in/garbage.txt"
bad classify "model classes line with a NUL byte" "$in/garbage.txt" "got '\\\\x00\\\\x01" json -- -o @OUT@ -i "$in/good.pcd" --modelbase "$in/mb" --model-classes "$in/garbage.txt"
bad rangetrace "missing scene" "$in/missing.scene" "$P_MISSING" pcd -- -o @OUT@ --model sedan --scene "$in/missing.scene"
bad rangetrace "empty scene" "$in/empty.scene" "$P_EMPTY|no views" pcd -- -o @OUT@ --model sedan --scene "$in/empty.scene"
bad rangetrace "scene a directory" "$in/dir.scene" "$P_DIR" pcd -- -o @OUT@ --model sedan --scene "$in/dir.scene"
bad rangetrace "garbage scene" "$in/garbage.scene" "$P_GARBAGE" pcd -- -o @OUT@ --model sedan --scene "$in/garbage.scene"
bad rangetrace "scene of 4e9 views" "$in/huge-views.scene" "$P_HUGE|views" pcd -- -o @OUT@ --model sedan --scene "$in/huge-views.scene"
bad rangetrace "scene with an unknown key" "$in/unknown-key.scene" "unknown|no_such_key" pcd -- -o @OUT@ --model sedan --scene "$in/unknown-key.scene"

echo "bad_inputs: $cases cases, $fails failed"
[ $fails -eq 0 ]
