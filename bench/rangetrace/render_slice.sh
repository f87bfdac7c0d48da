#!/usr/bin/env bash
# render_slice.sh: CPU seconds (user + system, POV-Ray included: /usr/bin/time -f) of a fixed
# slice of the experiment's renders, traced whole ("before") and in render windows ("after",
# docs/decisions/cost.md §11), and whether each pair of scans is byte-identical (cmp).
#
# Usage: render_slice.sh BIN_DIR [SLICE...] [-- OLD_BIN_DIR]
#   SLICE: thesis (the 15 renders of the thesis protocol: 5 models x circle, flyby, unoccluded,
#          as Makefile.experiments runs them), band (verify's 5 band renders, mk/verify.mk),
#          families (3 family test renders at the light cover, mk/families.mk's FAM_RENDER),
#          tiles (2 tiles like the scene experiment's light ones, 30 m at 40 mm); default: thesis.
#   "before" is BIN_DIR's rangetrace with CANOPY_RENDER_WINDOW=off, or OLD_BIN_DIR's rangetrace
#   (a build without windows) when given. Before and after alternate render by render, so a
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
    *) echo "render_slice.sh: unknown slice '$s' (thesis, band, families, tiles)" >&2; exit 2 ;;
  esac
done

printf '# %s; load average before: %s\n' "$(date -u +%FT%TZ)" "$(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-28s %10s %10s %9s %9s %9s\n' render before_cpu after_cpu before_s after_s identical
run() {  # run TAG BIN WINDOW ARGS: CPU and wall of one render into $tmp/TAG.{pcd,time}
  local tag=$1 b=$2 w=$3; shift 3
  # shellcheck disable=SC2086
  CANOPY_RENDER_WINDOW=$w /usr/bin/time -f '%e %M %U %S' -o "$tmp/$tag.time" "$b/rangetrace" -q $* \
    -o "$tmp/$tag.pcd"
}
tb=0; ta=0; same=0; n=0; status=0
for j in "${jobs[@]}"; do
  name=${j%%$'\t'*}; args=${j#*$'\t'}
  if [ -n "$old" ]; then run before "$old" on "$args"; else run before "$bin" off "$args"; fi
  run after "$bin" on "$args"
  read -r ws _ ub sb <"$tmp/before.time"
  read -r wa _ ua sa <"$tmp/after.time"
  cb=$(echo "$ub + $sb" | bc -l); ca=$(echo "$ua + $sa" | bc -l)
  if cmp -s "$tmp/before.pcd" "$tmp/after.pcd"; then id=yes; same=$((same + 1)); else id=NO; status=1; fi
  n=$((n + 1)); tb=$(echo "$tb + $cb" | bc -l); ta=$(echo "$ta + $ca" | bc -l)
  printf '%-28s %10.2f %10.2f %9.2f %9.2f %9s\n' "$name" "$cb" "$ca" "$ws" "$wa" "$id"
done
printf '%-28s %10.2f %10.2f %9s %9s %6d/%d\n' total "$tb" "$ta" "" "" "$same" "$n"
printf '# after/before CPU: %.3f; load average after: %s\n' "$(echo "$ta / $tb" | bc -l)" \
  "$(cut -d' ' -f1-3 /proc/loadavg)"
exit $status
