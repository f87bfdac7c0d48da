#!/usr/bin/env bash
# The density ladder's tile recipes outside make (docs/decisions/detect.md §16), for
# bench/detect/pieces.sh's RECIPES=DIR: mk/scenes.mk's `scene_recipe` per cover and seed (the
# scene experiment's extent, terrain, trees, hide, bushes, vehicle count and clutter kinds from
# scripts/cksum.sh, the five models) written as
#   DIR/<cover>-<seed>.scene                the image looks (pieces.sh sets the level's spacing)
#   DIR/sensor-<L>/<cover>-<seed>.scene     the sensor ladder's als_qL1 at L = 10, 25, 50 pulses/m²
#                                           (mk/density.mk's pulse_rate and speed for L0 = 26.5)
#   bench/detect/recipes.sh DIR "101 102 103"
# (bench/classify/outline.sh takes its tiles' recipes from here too.)
# Keep in step with mk/scenes.mk and mk/density.mk (checked: rendered with pieces.sh's render
# seeds, the sensor tiles of seeds 21-23 hold 19/18/16 vehicles at 24.99 pulses/m², and with
# detect's option off they score what the stop-47 `make density` run scored, tile set for tile set).
# Seeds 1-8, 21-23 and 31-34 are experiments' seeds: do not develop on them.
set -euo pipefail
out=$1 seeds=$2
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
declare -A trees=([light]=100 [medium]=350 [dense]=700) hide=([light]=0 [medium]=1 [dense]=2)
mkdir -p "$out"
for cover in light medium dense; do
  for s in $seeds; do
    nv=$(bash "$src/scripts/cksum.sh" --mod 6 --add 3 "vehicles/$cover/$s")
    k=$(bash "$src/scripts/cksum.sh" --mod 3 --add 1 "clutter/$cover/$s")
    un=$(echo "trailer_1_rock_1 caravan_1_tent_1 pipes_1_barriers_1" | cut -d' ' -f"$k" | tr _ ' ')
    head="# scene experiment tile (mk/scenes.mk): cover $cover, seed $s
extent = 30m
terrain = rolling 1m 25m
trees = ${trees[$cover]}
hide = ${hide[$cover]}
bushes = 300
vehicles = random $nv from earthmover,obj1,sedan,semi,tank
clutter = boulder 2 container 1 logs 1 $un"
    printf '%s\nflight_lines = 2\nheadings = 0deg 90deg\nlooks = 75deg/0deg 75deg/180deg\nspacing = 40mm\n' \
      "$head" >"$out/$cover-$s.scene"
    for lv in 10:307148:97.67 25:485643:61.77 50:686803:43.68; do
      IFS=: read -r l r v <<<"$lv"
      mkdir -p "$out/sensor-$l"
      printf '%s\nheadings = 0deg 90deg\nsensor = als_qL1\nsensor.pulse_rate = %s\nsensor.speed = %s\n' \
        "$head" "$r" "$v" >"$out/sensor-$l/$cover-$s.scene"
    done
  done
done
