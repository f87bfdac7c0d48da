#!/bin/bash
# bench/make/slice.sh TAG [MAKE ARGS]: a small slice of `all -j2` (the progress_count test's, development
# seeds) on a fresh out/slice-TAG, linked binaries (CMAKE=true); prints the make's CPU, the stages'
# (.time files) and the difference (docs/decisions/cost.md §9). OLD_BASELINE=path links another baseline.
tag=$1; shift
src=$(cd "$(dirname "$0")/../.." && pwd); tmp=$src/out/slice-$tag
rm -rf $tmp; mkdir -p $tmp/build/bin $tmp/real; touch $tmp/build/CMakeCache.txt $tmp/build/.deps-stamp
for t in $src/build/bin/*; do ln -s $t $tmp/build/bin/; done
[ -z "${OLD_BASELINE:-}" ] || ln -sf $OLD_BASELINE $tmp/build/bin/baseline
cp $src/share/real/forest_lareunion.laz $tmp/real/
mk=(make -C $src --no-print-directory -f Makefile.experiments BUILD=$tmp/build CMAKE=true OUT=$tmp/out RES=$tmp/res
    OBJECTS="sedan tank" SCENES=unoccluded NOISES=0 ABLATIONS=fitvox-fixed-rms
    SCENE_SEEDS=101 SCENE_COVERS=light SCENE_NOISES="0 8" SCENE_MODELS=sedan,tank
    FAM_CLASSES=sedan FAM_TRAIN=0 FAM_TEST=1000 FAM_COVERS=light FAM_NOISES=0
    DENSITY_LEVELS="10 25" DENSITY_SEEDS=101 DENSITY_COVERS=light OPENSET_SEEDS=101 OPENSET_COVERS=light
    REAL_SHARE=$tmp/real REAL_FOREST=forest_lareunion REAL_URBAN= REAL_TIMEOUT=600 "$@")
/usr/bin/time -f "%e %U %S" -o $tmp/total.time "${mk[@]}" all -j2 > $tmp/make.out 2>&1; echo "status $?" >> $tmp/make.out
read -r w u s < $tmp/total.time
find $tmp/out $tmp/res -name '*.time' | xargs awk 'NF>=4 {c+=$3+$4; n++} END {printf "%d %.2f\n", n, c}' > $tmp/stages.sum
read -r n c < $tmp/stages.sum
echo "$tag: wall $w s, make total $u u + $s s = $(echo "$u + $s" | bc) CPU-s; stages $n .time files, $c CPU-s; outside $(echo "$u + $s - $c" | bc) CPU-s = $(echo "scale=1; 1000*($u + $s - $c)/$n" | bc) ms per stage; lines $(grep -c '^done\|^FAIL' $tmp/make.out)"
