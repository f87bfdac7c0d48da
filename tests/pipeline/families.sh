#!/usr/bin/env bash
# Families mini protocol (issue 17): two classes (pickup, van), one modelbase instance each,
# two OTHER test instances each under light foliage, through `make -f Makefile.experiments
# families` (rangetrace family:<class>:<n> | addnoise | fitvox | cocone | ncut | gmatch |
# verify | famscore, and the PCL baseline's VFH and FPFH on the same samples). Checks: the modelbase entries carry their classes; every verdict names a
# class and a nearest instance; confusion.csv's counts equal the counts of (true class,
# verdict class) pairs read from the verdicts here (jq), accuracy.csv's totals agree with
# them; the scans carry their class; methods.csv's class answers of gmatch, verify, VFH and FPFH
# equal those read from match.json, the verdicts and baseline-{vfh,fpfh}.json (jq) and
# methods-confusion.csv agrees; the modelbase renders were deleted after use; a second make runs
# nothing. Small images and six views
# keep it under a minute.
set -uo pipefail
src=$1 bin=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
for t in rangetrace addnoise fitvox cocone ncut gmatch verify baseline famscore; do
  [ -x "$bin/$t" ] || fail "$bin/$t is not built"
done
command -v jq >/dev/null || fail "jq not found (scripts/install-deps.sh installs it)"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

mkdir -p "$tmp/build/bin" && touch "$tmp/build/CMakeCache.txt" "$tmp/build/.deps-stamp"
for t in "$bin"/*; do ln -s "$t" "$tmp/build/bin/"; done
cp -r "$src/share/params" "$tmp/params"
mk=(make -C "$src" -f Makefile.experiments BUILD="$tmp/build" CMAKE=true P="$tmp/params" PROGRESS=0
    OUT="$tmp/out" RES="$tmp/res" FAM_CLASSES="pickup van" FAM_TRAIN=0 FAM_TEST="1000 1001"
    FAM_COVERS=light FAM_NOISES=0 FAM_VIEWS="circle 6 75deg"
    FAM_RENDER="--size 320 --spacing 30mm --crop-length 7m --crop-width 3m --crop-height 3m" KEEP=1)

"${mk[@]}" -j2 families >"$tmp/make.log" 2>&1 || fail "make families failed: $(tail -8 "$tmp/make.log")"
res=$tmp/res/families mb=$tmp/out/families/modelbase
for f in confusion.csv accuracy.csv methods.csv methods-confusion.csv; do [ -s "$res/$f" ] || fail "no $f"; done
[ "$(cat "$mb/pickup-0.class")" = pickup ] && [ "$(cat "$mb/van-0.class")" = van ] || fail "modelbase classes wrong"
grep -aq '^# class van' "$tmp/out/families/test/van-1001/light/scan.pcd" || fail "scan carries no class comment"

# The confusion matrix, recomputed from the verdicts.
declare -A want
trials=0 right=0
while read -r verdict cls inst cover noise; do
  got=$(jq -r '.class // "none"' "$verdict") || fail "$verdict does not parse"
  nearest=$(jq -r '.nearest_instance // ""' "$verdict")
  case $nearest in "$got"-*) ;; *) [ "$got" = none ] || fail "$verdict: nearest instance $nearest is not of class $got" ;; esac
  want[$cls,$got]=$(( ${want[$cls,$got]:-0} + 1 ))
  trials=$((trials + 1))
  [ "$got" = "$cls" ] && right=$((right + 1))
done <"$tmp/out/families/runs.txt"
[ "$trials" = 4 ] || fail "runs.txt has $trials trials, not 4"
[ "$(head -1 "$res/confusion.csv")" = "true_class,pickup,van,none" ] || fail "confusion header: $(head -1 "$res/confusion.csv")"
for row in pickup van; do
  line=$(grep "^$row," "$res/confusion.csv") || fail "confusion.csv has no row $row"
  IFS=, read -r _ p v n <<<"$line"
  [ "$p" = "${want[$row,pickup]:-0}" ] && [ "$v" = "${want[$row,van]:-0}" ] && [ "$n" = "${want[$row,none]:-0}" ] \
    || fail "confusion row $row = $line, verdicts say pickup ${want[$row,pickup]:-0} van ${want[$row,van]:-0} none ${want[$row,none]:-0}"
done
IFS=, read -r c z t r _ <<<"$(grep '^all,all,' "$res/accuracy.csv")"
[ "$t" = "$trials" ] && [ "$r" = "$right" ] || fail "accuracy.csv all,all: $t trials $r right; verdicts: $trials, $right"
echo "families mini: $right/$trials classes right"; cat "$res/confusion.csv"

# Every method's class answers, recomputed from its files.
class_of() { if [ -n "$1" ] && [ -f "$mb/$1.class" ]; then cat "$mb/$1.class"; else echo none; fi; }
declare -A mright mcell
while read -r verdict cls inst cover noise; do
  d=$(dirname "$verdict")
  for m in gmatch verify vfh fpfh; do
    case $m in
      gmatch) model=$(jq -r '.models[0].model // ""' "$d/match.json") || fail "$d/match.json"; got=$(class_of "$model") ;;
      verify) got=$(jq -r '.class // "none"' "$verdict") ;;
      *) [ -f "$d/baseline-$m.json.time" ] || fail "no $d/baseline-$m.json.time"
         model=$(jq -r --arg m "$m" '.methods[] | select(.method == $m) | .models[0] | select(.score > 0) | .model' \
           "$d/baseline-$m.json") || fail "$d/baseline-$m.json does not parse"; got=$(class_of "$model") ;;
    esac
    [ "$got" = "$cls" ] && mright[$m]=$(( ${mright[$m]:-0} + 1 ))
    mcell[$m,$cls,$got]=$(( ${mcell[$m,$cls,$got]:-0} + 1 ))
  done
done <"$tmp/out/families/runs.txt"
for m in gmatch verify vfh fpfh; do
  IFS=, read -r _ _ _ _ t r _ _ _ f n sec <<<"$(grep "^$m,all,all,all," "$res/methods.csv")"
  [ "$t" = "$trials" ] && [ "$r" = "${mright[$m]:-0}" ] || fail "methods.csv $m: $t trials $r right; files: $trials, ${mright[$m]:-0}"
  [ "$n" = "$trials" ] && [ -n "$sec" ] || fail "methods.csv $m: $n of $trials trials timed, mean '$sec'"
  for row in pickup van; do
    IFS=, read -r _ _ p v n <<<"$(grep "^$m,$row," "$res/methods-confusion.csv")"
    [ "$p" = "${mcell[$m,$row,pickup]:-0}" ] && [ "$v" = "${mcell[$m,$row,van]:-0}" ] && [ "$n" = "${mcell[$m,$row,none]:-0}" ] \
      || fail "methods-confusion $m $row = $p $v $n, files say ${mcell[$m,$row,pickup]:-0} ${mcell[$m,$row,van]:-0} ${mcell[$m,$row,none]:-0}"
  done
  echo "  $m: ${mright[$m]:-0}/$trials classes right, $sec s per trial"
done
# The modelbase renders are deleted once read (their .time stays); the entries are there.
for e in pickup-0 van-0; do
  d=$tmp/out/families/train/$e
  [ ! -e "$d/scan.pcd" ] && [ ! -e "$d/noise-0/scan.pcd" ] && [ -s "$d/scan.pcd.time" ] || fail "$e: scans kept or no .time"
done

"${mk[@]}" -j2 families >"$tmp/again.log" 2>&1 || fail "second make families failed"
if grep -q '^done\|^FAIL\|^fail  ' "$tmp/again.log"; then fail "a second make ran stages: $(head -3 "$tmp/again.log")"; fi
# Inside `all` (FAMILIES=1) the tables come from a recursive `make families`: up to date now,
# `make -q` asks the sub-make and exits 0, and the recursive step runs nothing; after a change
# to the baseline's parameters -q exits 1 and the step re-runs the baseline and famscore only.
"${mk[@]}" -q SCENE_EXPERIMENT=0 FAMILIES=1 "$res/confusion.csv" || fail "make -q (FAMILIES=1) after a run exits $?, want 0"
"${mk[@]}" SCENE_EXPERIMENT=0 FAMILIES=1 "$res/confusion.csv" >"$tmp/rec.log" 2>&1 || fail "recursive families failed: $(tail -3 "$tmp/rec.log")"
if grep -q '^done\|^FAIL\|^fail  ' "$tmp/rec.log"; then fail "the recursive step ran stages: $(head -3 "$tmp/rec.log")"; fi
echo '; touched by the test' >>"$tmp/params/baseline.ini"
if "${mk[@]}" -q SCENE_EXPERIMENT=0 FAMILIES=1 "$res/confusion.csv"; then fail "make -q after a parameter change exits 0"; fi
"${mk[@]}" SCENE_EXPERIMENT=0 FAMILIES=1 "$res/confusion.csv" >"$tmp/rec2.log" 2>&1 || fail "recursive families failed: $(tail -3 "$tmp/rec2.log")"
# (The baseline's two methods per trial, the models' side it reads, baseline-models.bin, and famscore.)
ran=$(grep -c '^done' "$tmp/rec2.log"); want=$(( 2 * trials + 2 ))
[ "$ran" = "$want" ] && ! grep '^done' "$tmp/rec2.log" | grep -qv 'baseline-\|confusion.csv' \
  && grep '^done' "$tmp/rec2.log" | grep -q 'baseline-models.bin' \
  || fail "after baseline.ini changed: $ran stages ran (want $want: the baseline's, its models' side and famscore): $(head -5 "$tmp/rec2.log")"

# The generated modelbase (family-modelbase): entries pickup-0, van-0 (built above, linked),
# pickup-1, van-1 (new) with their classes; with FAM_MB_WINDOW=1 van-1's render waits for
# pickup-1's chain to be done (without the window -j2 renders both at once).
"${mk[@]}" -j2 family-modelbase FAM_MB_N=4 FAM_MB_WINDOW=1 >"$tmp/big.log" 2>&1 || fail "family-modelbase failed: $(tail -5 "$tmp/big.log")"
big=$tmp/out/families/modelbase-4
for e in pickup-0 van-0 pickup-1 van-1; do
  [ -s "$big/$e.json" ] && [ -s "$big/$e.pcd" ] && [ "$(cat "$big/$e.class")" = "${e%-*}" ] || fail "modelbase-4: entry $e missing or wrong class"
done
[ "$(ls "$big" | wc -l)" = 12 ] || fail "modelbase-4 holds $(ls "$big" | wc -l) files, want 12"
cmp -s "$big/van-0.json" "$mb/van-0.json" || fail "modelbase-4's van-0 differs from the protocol's"
grep -q "^done.*train/van-0/scan.pcd" "$tmp/big.log" && fail "family-modelbase re-rendered van-0"
order=$(grep -n "^done.*train/\(pickup-1/noise-0/segments.json\|van-1/scan.pcd\)" "$tmp/big.log" | cut -d: -f2 | awk '{ print $2 }')
[ "$(echo "$order" | sed 's|.*/train/||' | tr '\n' ' ')" = "pickup-1/noise-0/segments.json van-1/scan.pcd " ] \
  || fail "FAM_MB_WINDOW=1: van-1 rendered before pickup-1 was done: $order"
# Without KEEP=1 the test renders are deleted once famscore has run; the protocol stays up to
# date (they are .SECONDARY) and a second run runs nothing.
rm "$res/confusion.csv"
"${mk[@]}" -j2 families KEEP=0 >"$tmp/prune.log" 2>&1 || fail "make families KEEP=0 failed: $(tail -5 "$tmp/prune.log")"
[ "$(grep -c '^done' "$tmp/prune.log")" = 1 ] || fail "re-making confusion.csv ran more than famscore: $(head -5 "$tmp/prune.log")"
for d in "$tmp"/out/families/test/*/light; do [ ! -e "$d/scan.pcd" ] || fail "KEEP=0 left $d/scan.pcd"; done
"${mk[@]}" -q families KEEP=0 || fail "make -q families not clean after the renders were deleted"
"${mk[@]}" -j2 families KEEP=0 >"$tmp/prune2.log" 2>&1 || fail "a second make families KEEP=0 failed"
if grep -q '^done\|^FAIL\|^fail  ' "$tmp/prune2.log"; then fail "a second make families KEEP=0 ran stages: $(head -3 "$tmp/prune2.log")"; fi
echo ok
