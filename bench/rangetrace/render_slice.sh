#!/usr/bin/env bash
# render_slice.sh: CPU seconds (user + system, POV-Ray included: /usr/bin/time -f) of a fixed
# slice of the experiment's renders, traced whole ("before") and in render windows ("after",
# docs/decisions/cost.md §11), and whether each pair of scans (and a tile's truth.json) is
# byte-identical (cmp).
#
# Usage: render_slice.sh BIN_DIR [SLICE...] [-- OLD_BIN_DIR]
#   SLICE: thesis (the 15 renders of the thesis protocol: 5 models x circle, flyby, unoccluded,
#          as Makefile.experiments runs them), band (verify's 5 band renders, mk/verify.mk),
#          families (3 family test renders at the light cover, mk/families.mk's FAM_RENDER),
#          tiles (2 tiles like the scene experiment's light ones, 30 m at 40 mm), covers (mk/scenes.mk's
#          recipe as it is now, unseen clutter included: light, medium, dense at development seeds
#          101, 102, 40 mm), ladder (the same recipe at seed 101 of each cover at mk/density.mk's
#          10, 200 and 800 points/m²: 667, 149, 75 mm); default: thesis.
#   "before" is BIN_DIR's rangetrace with CANOPY_RENDER_WINDOW=off, or OLD_BIN_DIR's rangetrace
#   (another build, e.g. main's) when given. Before and after alternate render by render, so a
#   change of the machine's load touches both. Prints one line per render and the totals;
#   exits 1 when a pair of scans differs.
set -eu
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$(cd "$1" && pwd); shift
slices=(); old=
while [ $# -gt 0 ]; do
  if [ "$1" = -- ]; then old=$(cd "$2" && pwd); shift 2; continue; fi
  slices+=("$1"); shift
done
[ ${#slices[@]} -gt 0 ] || slices=(thesis)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
seed() { printf '%s' "$1" | cksum | cut -d' ' -f1; }
ini=$here/share/params/rangetrace.ini

# Each job: a name and rangetrace's arguments (without -o).
jobs=()
add() { jobs+=("$1"$'\t'"$2"); }
for s in "${slices[@]}"; do
  case $s in
    thesis)
      for m in earthmover obj1 sedan semi tank; do
        for sc in circle flyby unoccluded; do
          add "$m/$sc" "--config $ini --model $m --scene $sc --seed $(seed "$m/$sc") --threads 2"
        done
      done ;;
    band)
      for m in earthmover obj1 sedan semi tank; do
        add "$m/band" "--config $ini --model $m --scene $here/share/scenes/band.scene --seed $(seed "$m/band") --threads 2"
      done ;;
    families)
      printf 'foliage_count = 250\nfoliage_radius = 100mm\nfoliage_band = 2m\nfoliage_square = 16m\nviews = circle 12 75deg\n' \
        >"$tmp/light.scene"
      for c in sedan bus tracked-apc; do
        key=$c-1000/light
        add "family:$c:1000/light" "--config $ini --size 640 --spacing 30mm --crop-length 15m --crop-width 5m \
--crop-height 4.6m --model family:$c:1000 --scene $tmp/light.scene \
--heading $(( $(seed "families/heading/$key") % 360 ))deg --seed $(seed "families/test/$key") --threads 2"
      done ;;
    tiles)
      # Like the scene experiment's light tiles (mk/scenes.mk scene_recipe), two seeds.
      for seedn in 101 102; do
        printf '%s\n' 'extent = 30m' 'terrain = rolling 1m 25m' 'trees = 100' 'hide = 0' 'bushes = 300' \
          'vehicles = random 5 from earthmover,obj1,sedan,semi,tank' 'clutter = boulder 2 container 1 logs 1' \
          'flight_lines = 2' 'headings = 0deg 90deg' 'looks = 75deg/0deg 75deg/180deg' 'spacing = 40mm' \
          >"$tmp/tile$seedn.scene"
        add "tile-$seedn" "--scene $tmp/tile$seedn.scene --seed $(seed "scenes/light/$seedn") --threads 2"
      done ;;
    covers | ladder)
      # mk/scenes.mk's scene_recipe: trees and hide per cover, 3-8 vehicles and two unseen clutter
      # kinds from the tile's place (cksum, as the makefile draws them); the seed is that place.
      if [ "$s" = covers ]; then tiles="light:101:40 light:102:40 medium:101:40 medium:102:40 dense:101:40 dense:102:40"
      else tiles="light:101:667 light:101:149 light:101:75 medium:101:667 medium:101:149 medium:101:75 dense:101:667 dense:101:149 dense:101:75"; fi
      for t in $tiles; do
        IFS=: read -r c seedn mm <<<"$t"
        case $c in light) trees=100 hide=0 ;; medium) trees=350 hide=1 ;; dense) trees=700 hide=2 ;; esac
        nv=$(( 3 + $(seed "vehicles/$c/$seedn") % 6 ))
        unseen=$(echo trailer_1_rock_1 caravan_1_tent_1 pipes_1_barriers_1 | cut -d' ' -f$(( 1 + $(seed "clutter/$c/$seedn") % 3 )) | tr _ ' ')
        printf '%s\n' 'extent = 30m' 'terrain = rolling 1m 25m' "trees = $trees" "hide = $hide" 'bushes = 300' \
          "vehicles = random $nv from earthmover,obj1,sedan,semi,tank" "clutter = boulder 2 container 1 logs 1 $unseen" \
          'flight_lines = 2' 'headings = 0deg 90deg' 'looks = 75deg/0deg 75deg/180deg' "spacing = ${mm}mm" \
          >"$tmp/$c-$seedn-$mm.scene"
        add "$c-$seedn-${mm}mm" "--scene $tmp/$c-$seedn-$mm.scene --seed $(seed "scenes/$c/$seedn") --threads 2"
      done ;;
    *) echo "render_slice.sh: unknown slice '$s' (thesis, band, families, tiles, covers, ladder)" >&2; exit 2 ;;
  esac
done

printf '# %s; load average before: %s\n' "$(date -u +%FT%TZ)" "$(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-28s %10s %10s %9s %9s %9s\n' render before_cpu after_cpu before_s after_s identical
run() {  # run TAG BIN WINDOW ARGS: CPU and wall of one render into $tmp/TAG.{pcd,time} (+ .json: a tile's truth)
  local tag=$1 b=$2 w=$3 truth=(); shift 3
  # A tile's truth.json under one name for both runs (the scan records its path), then moved.
  case " $* " in *" --model "*) ;; *) truth=(--truth "$tmp/truth.json") ;; esac
  # shellcheck disable=SC2086
  CANOPY_RENDER_WINDOW=$w /usr/bin/time -f '%e %M %U %S' -o "$tmp/$tag.time" "$b/rangetrace" -q $* \
    -o "$tmp/$tag.pcd" "${truth[@]}"
  rm -f "$tmp/$tag.json"
  if [ ${#truth[@]} -gt 0 ]; then mv "$tmp/truth.json" "$tmp/$tag.json"; fi
}
tb=0; ta=0; same=0; n=0; status=0
for j in "${jobs[@]}"; do
  name=${j%%$'\t'*}; args=${j#*$'\t'}
  if [ -n "$old" ]; then run before "$old" on "$args"; else run before "$bin" off "$args"; fi
  run after "$bin" on "$args"
  read -r ws _ ub sb <"$tmp/before.time"
  read -r wa _ ua sa <"$tmp/after.time"
  cb=$(echo "$ub + $sb" | bc -l); ca=$(echo "$ua + $sa" | bc -l)
  if cmp -s "$tmp/before.pcd" "$tmp/after.pcd" && { [ ! -f "$tmp/before.json" ] && [ ! -f "$tmp/after.json" ] ||
    cmp -s "$tmp/before.json" "$tmp/after.json"; }; then id=yes; same=$((same + 1)); else id=NO; status=1; fi
  n=$((n + 1)); tb=$(echo "$tb + $cb" | bc -l); ta=$(echo "$ta + $ca" | bc -l)
  printf '%-28s %10.2f %10.2f %9.2f %9.2f %9s\n' "$name" "$cb" "$ca" "$ws" "$wa" "$id"
done
printf '%-28s %10.2f %10.2f %9s %9s %6d/%d\n' total "$tb" "$ta" "" "" "$same" "$n"
printf '# after/before CPU: %.3f; load average after: %s\n' "$(echo "$ta / $tb" | bc -l)" \
  "$(cut -d' ' -f1-3 /proc/loadavg)"
exit $status
