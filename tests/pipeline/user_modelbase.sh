#!/usr/bin/env bash
# user-modelbase (issue 27; mk/usermb.mk, docs/decisions/user-modelbase.md): a modelbase from a
# directory of the user's meshes in one make. Two meshes of share/vehicles, copied as
# car__hatch.ply (class car from its name) and truck__pick.ply (class pickup: classes.csv
# overrides the name), with the default renders (rangetrace.ini, `unoccluded`). Checks: the
# three files per entry, the classes, the graphs are canopy segment graphs of >= 2 segments, the
# scans are deleted and every stage has its .log and .time; gmatch and verify read the
# modelbase (an entry's own samples are recognised as that entry, with its class); a second
# make runs nothing and `make -q` exits 0; touching one mesh re-runs that entry only, to the
# same bytes; a classes.csv edit re-writes that .class only; a mesh without a class gets no
# .class (with a warning); a removed mesh's entry is removed; a bad mesh name, an empty or
# missing MESHES and a missing MODELBASE stop make with exit 2 and a message naming the problem;
# a mesh in millimetres without MESH_UNITS=mm is refused with that hint, and one in metres given
# MESH_UNITS=mm too; a second MESHES directory into the same MODELBASE keeps the first's entries;
# an entry whose chain fails after fitvox leaves neither its .json nor its .pcd.
set -uo pipefail
src=$1 bin=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
for t in meshsize rangetrace fitvox cocone ncut gmatch verify; do
  [ -x "$bin/$t" ] || fail "$bin/$t is not built"
done
command -v jq >/dev/null || fail "jq not found (scripts/install-deps.sh installs it)"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

mkdir -p "$tmp/build/bin" "$tmp/meshes" && touch "$tmp/build/CMakeCache.txt" "$tmp/build/.deps-stamp"
for t in "$bin"/*; do ln -s "$t" "$tmp/build/bin/"; done
cp -r "$src/share/params" "$tmp/params"
cp "$src/share/vehicles/car/gz_hatchback.ply" "$tmp/meshes/car__hatch.ply"
cp "$src/share/vehicles/pickup/gz_pickup.ply" "$tmp/meshes/truck__pick.ply"
printf 'name,class\ntruck__pick,pickup\n' >"$tmp/meshes/classes.csv"
mb=$tmp/mb work=$tmp/mb/.work
mk=(make -C "$src" -f Makefile.experiments BUILD="$tmp/build" CMAKE=true P="$tmp/params" PROGRESS=0
    OUT="$tmp/out" RES="$tmp/res")
umb=("${mk[@]}" user-modelbase MESHES="$tmp/meshes" MODELBASE="$mb")
# ran LOG: the artifacts a make run made ("done  <artifact> ..." lines), one a line.
ran() { grep '^done' "$1" | awk '{ print $2 }'; }

"${umb[@]}" -j2 >"$tmp/make.log" 2>&1 || fail "make user-modelbase failed: $(tail -8 "$tmp/make.log")"
for e in car__hatch truck__pick; do
  for x in json pcd class; do [ -s "$mb/$e.$x" ] || fail "no $mb/$e.$x"; done
  [ "$(jq -r .format "$mb/$e.json")" = canopy.segment_graph ] || fail "$e.json is not a canopy segment graph"
  n=$(jq '.segments | length' "$mb/$e.json") || fail "$e.json does not parse"
  [ "$n" -ge 2 ] || fail "$e.json has $n segments, want >= 2"
  echo "  $e: $n segments, class $(cat "$mb/$e.class")"
  [ ! -e "$work/$e/scan.pcd" ] && [ ! -e "$work/$e/noise-0/scan.pcd" ] || fail "$e: a scan was kept"
  for a in size.txt scan.pcd noise-0/samples.pcd noise-0/mesh.ply noise-0/segments.json; do
    [ -s "$work/$e/$a.log" ] && [ -s "$work/$e/$a.time" ] || fail "$e: no .log or .time for $a"
  done
  cmp -s "$mb/$e.json" "$work/$e/noise-0/segments.json" && cmp -s "$mb/$e.pcd" "$work/$e/noise-0/samples.pcd" \
    || fail "$e: the entry differs from its work files"
done
[ "$(cat "$mb/car__hatch.class")" = car ] || fail "car__hatch.class = '$(cat "$mb/car__hatch.class")', want car"
[ "$(cat "$mb/truck__pick.class")" = pickup ] || fail "truck__pick.class = '$(cat "$mb/truck__pick.class")', want pickup (classes.csv)"
[ "$(ls "$mb" | wc -l)" = 6 ] || fail "the modelbase holds $(ls "$mb" | tr '\n' ' '), want 6 files"
# The crop box: both meshes fit rangetrace.ini's (no option); the bus's extent (meshsize of
# share/vehicles/bus/gz_bus.ply) grows the length and height and the image; MESH_CROP_LENGTH.
crop=("$src/scripts/usermb-crop.sh")
for e in car__hatch truck__pick; do
  [ -z "$("${crop[@]}" "$work/$e/size.txt" "$tmp/params/rangetrace.ini")" ] || fail "$e: a crop option for a mesh that fits"
done
"$bin/meshsize" -q -i "$src/share/vehicles/bus/gz_bus.ply" -o "$tmp/bus.txt" || fail "meshsize on the bus failed"
[ "$(cat "$tmp/bus.txt")" = "12.4861 2.7077 3.6983" ] || fail "meshsize: the bus is $(cat "$tmp/bus.txt")"
printf 'v 0 0 0\nv 4000 1500 2000\nv 0 1500 0\nf 1 2 3\n' >"$tmp/tri.obj"  # y up, mm: 4 x 2 x 1.5 m
[ "$("$bin/meshsize" -q --units mm --up y -i "$tmp/tri.obj")" = "4.0000 2.0000 1.5000" ] \
  || fail "meshsize --units mm --up y: $("$bin/meshsize" -q --units mm --up y -i "$tmp/tri.obj")"
[ "$("${crop[@]}" "$tmp/bus.txt" "$tmp/params/rangetrace.ini")" = "--crop-length 14m --crop-height 5m --size 580" ] \
  || fail "the bus's options: $("${crop[@]}" "$tmp/bus.txt" "$tmp/params/rangetrace.ini")"
[ "$("${crop[@]}" "$work/car__hatch/size.txt" "$tmp/params/rangetrace.ini" 16m)" = "--crop-length 16m --size 633" ] \
  || fail "MESH_CROP_LENGTH=16m: $("${crop[@]}" "$work/car__hatch/size.txt" "$tmp/params/rangetrace.ini" 16m)"
# A mesh in millimetres read as metres (no MESH_UNITS=mm): refused with the hint, exit 2, not
# rangetrace's "need 8 <= --size <= 8192" on a 173 252-pixel image.
printf '4366.9280 1956.6940 2018.0900\n' >"$tmp/mm.txt"
"${crop[@]}" "$tmp/mm.txt" "$tmp/params/rangetrace.ini" >"$tmp/mm.out" 2>"$tmp/mm.err"; rc=$?
[ $rc -eq 2 ] && [ ! -s "$tmp/mm.out" ] || fail "a 4367 m mesh: usermb-crop.sh exits $rc, prints '$(cat "$tmp/mm.out")'"
grep -q "$tmp/mm.txt: the mesh measures 4366.9280 x 1956.6940 x 2018.0900 m .*MESH_UNITS=mm" "$tmp/mm.err" \
  || fail "a 4367 m mesh: no MESH_UNITS hint: $(cat "$tmp/mm.err")"

# gmatch and verify read it: an entry's own samples and segments are recognised as that entry.
d=$work/car__hatch/noise-0
"$bin/gmatch" -q -i "$d/segments.json" --modelbase "$mb" -o "$tmp/match.json" || fail "gmatch on the modelbase failed"
[ "$(jq -r '.models[0].model' "$tmp/match.json")" = car__hatch ] || fail "gmatch ranks $(jq -r '.models[0].model' "$tmp/match.json") first"
"$bin/verify" -q -i "$tmp/match.json" --points "$d/samples.pcd" --segments "$d/segments.json" --modelbase "$mb" \
  -o "$tmp/verdict.json" || fail "verify on the modelbase failed"
[ "$(jq -r '.model' "$tmp/verdict.json")" = car__hatch ] && [ "$(jq -r '.class' "$tmp/verdict.json")" = car ] \
  || fail "verify answers model $(jq -r .model "$tmp/verdict.json") class $(jq -r .class "$tmp/verdict.json")"

# Up to date: -q exits 0 and a second make runs nothing.
"${umb[@]}" -q >/dev/null 2>&1 || fail "make -q user-modelbase after a run exits $?, want 0"
"${umb[@]}" -j2 >"$tmp/again.log" 2>&1 || fail "second make failed: $(tail -3 "$tmp/again.log")"
if grep -q '^done\|^FAIL' "$tmp/again.log"; then fail "a second make ran stages: $(head -3 "$tmp/again.log")"; fi
# Other units: every entry is out of date (-q; nothing rendered here).
"${umb[@]}" -q MESH_UNITS=cm >/dev/null 2>&1 && fail "make -q exits 0 with MESH_UNITS=cm"
[ "$("${umb[@]}" -n MESH_UNITS=cm 2>/dev/null | grep -c 'rangetrace --config')" = 2 ] || fail "MESH_UNITS=cm does not re-render both"

# Touching one mesh re-runs its entry only (6 stages, the 0 mm link and the .json and .pcd
# links), to the same bytes.
cp "$mb/car__hatch.json" "$tmp/before.json" && cp "$mb/car__hatch.pcd" "$tmp/before.pcd"
touch "$tmp/meshes/car__hatch.ply"
"${umb[@]}" -q >/dev/null 2>&1 && fail "make -q exits 0 after a mesh was touched"
"${umb[@]}" -j2 >"$tmp/touch.log" 2>&1 || fail "make after touch failed: $(tail -3 "$tmp/touch.log")"
ran "$tmp/touch.log" | grep -v car__hatch && fail "touching car__hatch.ply re-ran another entry"
[ "$(ran "$tmp/touch.log" | wc -l)" = 8 ] || fail "touching car__hatch.ply ran $(ran "$tmp/touch.log" | wc -l) steps, want 8: $(ran "$tmp/touch.log")"
cmp -s "$tmp/before.json" "$mb/car__hatch.json" && cmp -s "$tmp/before.pcd" "$mb/car__hatch.pcd" \
  || fail "the same mesh gave other bytes"

# A classes.csv edit re-writes that entry's .class, nothing else.
printf 'name,class\ntruck__pick,truck\n' >"$tmp/meshes/classes.csv"
"${umb[@]}" -q >/dev/null 2>&1 && fail "make -q exits 0 after classes.csv changed"
"${umb[@]}" >"$tmp/class.log" 2>&1 || fail "make after the classes.csv edit failed: $(tail -3 "$tmp/class.log")"
[ "$(ran "$tmp/class.log")" = "$mb/truck__pick.class" ] || fail "the classes.csv edit ran: $(ran "$tmp/class.log")"
[ "$(cat "$mb/truck__pick.class")" = truck ] || fail "truck__pick.class not rewritten"

# A mesh without a class: a warning, no .class (a dry run only: nothing is rendered).
ln "$tmp/meshes/car__hatch.ply" "$tmp/meshes/plain.ply"
"${umb[@]}" -n >"$tmp/plain.log" 2>&1 || fail "make -n with an unclassed mesh failed: $(tail -3 "$tmp/plain.log")"
grep -q "plain.ply has no class" "$tmp/plain.log" || fail "no warning for the unclassed mesh"
grep -v 'is not written' "$tmp/plain.log" | grep -q 'plain\.class' && fail "a dry run would write plain.class"
rm "$tmp/meshes/plain.ply"

# A removed mesh's entry is removed; the other stays as it was.
rm "$tmp/meshes/truck__pick.ply"
"${umb[@]}" -q >/dev/null 2>&1 && fail "make -q exits 0 after a mesh was removed"
"${umb[@]}" >"$tmp/rm.log" 2>&1 || fail "make after a mesh was removed failed: $(tail -3 "$tmp/rm.log")"
[ ! -e "$mb/truck__pick.json" ] && [ ! -e "$mb/truck__pick.pcd" ] && [ ! -e "$mb/truck__pick.class" ] \
  && [ ! -e "$work/truck__pick" ] || fail "the removed mesh's entry stayed: $(ls "$mb")"
[ -z "$(ran "$tmp/rm.log")" ] || fail "removing a mesh ran: $(ran "$tmp/rm.log")"
"${umb[@]}" -q >/dev/null 2>&1 || fail "make -q not clean after the entry was removed"

grep -qF "user-modelbase: removing $work/truck__pick " "$tmp/rm.log" && grep -qF "(mesh gone from $tmp/meshes)" "$tmp/rm.log" \
  || fail "no message naming the removed entry and its directory: $(cat "$tmp/rm.log")"

# A second MESHES directory into the same MODELBASE (stop 71, review F8: its run removed the first
# directory's entries, "mesh gone from <the second>"): the first's entry stays; an entry of the
# second whose mesh leaves it is removed, naming that directory; a mesh of the first's name is
# said to replace it (a dry run here: nothing renders). Two meshes that fail at meshsize (not
# meshes) make the second directory's entries without a render.
mkdir -p "$tmp/meshes2" && printf 'not a mesh\n' >"$tmp/meshes2/bad1.ply" && printf 'not a mesh\n' >"$tmp/meshes2/bad2.ply"
umb2=("${mk[@]}" user-modelbase MESHES="$tmp/meshes2/" MODELBASE="$mb" MESH_UP=y)
"${umb2[@]}" -k -j2 >"$tmp/m2.log" 2>&1 && fail "make user-modelbase on two non-meshes succeeded"
grep -q "meshsize: error: $tmp/meshes2/bad1.ply: not a PLY file" "$tmp/m2.log" || fail "no meshsize error: $(tail -3 "$tmp/m2.log")"
! grep -q "removing" "$tmp/m2.log" || fail "a second MESHES directory removed entries: $(grep removing "$tmp/m2.log")"
for x in json pcd class; do [ -s "$mb/car__hatch.$x" ] || fail "a second MESHES directory removed $mb/car__hatch.$x"; done
rm "$tmp/meshes2/bad2.ply"
"${umb2[@]}" -k >"$tmp/m2b.log" 2>&1
grep -qxF "user-modelbase: removing $work/bad2 (mesh gone from $tmp/meshes2/)" "$tmp/m2b.log" && [ ! -e "$work/bad2" ] \
  && [ -d "$work/bad1" ] && [ -s "$mb/car__hatch.json" ] || fail "the second directory's gone mesh: $(grep -v '^FAIL' "$tmp/m2b.log" | head -3)"
"${umb[@]}" -q >/dev/null 2>&1 || fail "make -q for the first directory exits $? once a second one has built into MODELBASE"
cp "$tmp/meshes2/bad1.ply" "$tmp/meshes2/car__hatch.ply"
"${umb2[@]}" -n >"$tmp/m2c.log" 2>&1
grep -qF "$mb/car__hatch was built from $tmp/meshes/car__hatch.ply, another MESHES directory: $tmp/meshes2/car__hatch.ply replaces it" \
  "$tmp/m2c.log" || fail "no warning for a mesh of another directory's entry name: $(head -3 "$tmp/m2c.log")"
rm -r "$tmp/meshes2" "$work/bad1"

# A mesh in metres given MESH_UNITS=mm (review F17): refused before the render with the hint,
# exit 2 (before: a 5 mm vehicle rendered as bare ground and cocone failed, "coplanar").
printf '0.0049 0.0022 0.0015\n' >"$tmp/tiny.txt"
"${crop[@]}" "$tmp/tiny.txt" "$tmp/params/rangetrace.ini" >"$tmp/tiny.out" 2>"$tmp/tiny.err"; rc=$?
[ $rc -eq 2 ] && [ ! -s "$tmp/tiny.out" ] || fail "a 5 mm mesh: usermb-crop.sh exits $rc, prints '$(cat "$tmp/tiny.out")'"
grep -q "$tmp/tiny.txt: the mesh measures 0.0049 x 0.0022 x 0.0015 m as read .*a mesh in metres given MESH_UNITS=mm" \
  "$tmp/tiny.err" || fail "a 5 mm mesh: no MESH_UNITS hint: $(cat "$tmp/tiny.err")"
printf '0.6 0.3 0.2\n' >"$tmp/small.txt"
"${crop[@]}" "$tmp/small.txt" "$tmp/params/rangetrace.ini" >/dev/null 2>&1 || fail "a 0.6 m mesh is refused"
# An entry whose chain fails after fitvox (a cocone parameter file cocone refuses) leaves no
# half entry in MODELBASE: its .pcd is placed only with its .json (before: the .pcd alone).
rm "$mb/car__hatch.json" "$mb/car__hatch.pcd"
echo 'no-such-key = 1' >>"$tmp/params/cocone.ini"
"${umb[@]}" -k >"$tmp/half.log" 2>&1 && fail "make user-modelbase with a broken cocone.ini succeeded"
grep -q "cocone: error: .*unknown key 'no-such-key'" "$tmp/half.log" || fail "cocone did not fail: $(tail -3 "$tmp/half.log")"
[ ! -e "$mb/car__hatch.pcd" ] && [ ! -e "$mb/car__hatch.json" ] || fail "a failed chain left half an entry: $(ls "$mb")"

# Refusals: make stops at parse time with exit 2 and says why.
refuse() {  # refuse WHAT PATTERN MAKE-ARGS...: make must exit 2 and print PATTERN
  local what=$1 pattern=$2; shift 2
  "${mk[@]}" user-modelbase "$@" >"$tmp/refuse.log" 2>&1; local rc=$?
  [ $rc = 2 ] || fail "$what: make exits $rc, want 2: $(tail -2 "$tmp/refuse.log")"
  grep -q -- "$pattern" "$tmp/refuse.log" || fail "$what: no message '$pattern': $(tail -2 "$tmp/refuse.log")"
}
mkdir -p "$tmp/bad" "$tmp/empty"
cp "$src/share/vehicles/car/gz_hatchback.ply" "$tmp/bad/car__good.ply"
cp "$src/share/vehicles/car/gz_hatchback.ply" "$tmp/bad/my car.ply"
refuse "a mesh name with a space" "mesh '$tmp/bad/my car.ply': its name must be a word" MESHES="$tmp/bad" MODELBASE="$tmp/mb2"
rm "$tmp/bad/my car.ply" && cp "$src/share/vehicles/car/gz_hatchback.ply" "$tmp/bad/car#2.obj"
refuse "a mesh name with '#'" "car#2.obj': its name must be a word" MESHES="$tmp/bad" MODELBASE="$tmp/mb2"
refuse "an empty MESHES" "MESHES=$tmp/empty holds no mesh" MESHES="$tmp/empty" MODELBASE="$tmp/mb2"
refuse "a missing MESHES" "MESHES=$tmp/nothing is not a directory" MESHES="$tmp/nothing" MODELBASE="$tmp/mb2"
refuse "no MESHES" "give MESHES=" MODELBASE="$tmp/mb2"
refuse "no MODELBASE" "give MODELBASE=" MESHES="$tmp/meshes"
refuse "MESH_UNITS=inch" "MESH_UNITS=inch: must be mm, cm or m" MESHES="$tmp/meshes" MODELBASE="$mb" MESH_UNITS=inch
[ ! -e "$tmp/mb2" ] || fail "a refused make created MODELBASE"
echo ok
