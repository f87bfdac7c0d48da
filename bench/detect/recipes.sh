#!/usr/bin/env bash
# The density ladder's tile recipes outside make (docs/decisions/detect.md §16), for
# bench/detect/pieces.sh's RECIPES=DIR: make's own `scene_recipe` (mk/scene-recipe.mk: the scene
# experiment's extent, terrain, trees, hide, bushes, vehicle count and clutter kinds from
# scripts/cksum.sh, the five models) per cover and seed, written as
#   DIR/<cover>-<seed>.scene                the image looks (pieces.sh sets the level's spacing)
#   DIR/sensor-<L>/<cover>-<seed>.scene     the sensor ladder's als_qL1 at L = 10, 25, 50 pulses/m²
#                                           (pulse_rate and speed: mk/density.mk's own
#                                           density_sensor_keys, read from make, not copied)
#   bench/detect/recipes.sh DIR "101 102 103"
# (bench/classify/outline.sh takes its tiles' recipes from here too.)
# The recipes are make's own (mk/scene-recipe.mk writes them, the one copy, which `make scenes`
# renders: byte-identical to this script's own copy before, for seeds 101, 102, 105); the sensor
# levels' keys are mk/density.mk's (checked: rendered with pieces.sh's render seeds, the sensor
# tiles of seeds 21-23 hold 19/18/16 vehicles at 24.99 pulses/m², and with detect's option off
# they score what the stop-47 `make density` run scored, tile set for tile set).
# Seeds 1-8, 21-23 and 31-34 are experiments' seeds: do not develop on them.
set -euo pipefail
out=$1 seeds=$2
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
recipes() {
  make --no-print-directory -C "$src" -f mk/scene-recipe.mk SCENE_COVERS="light medium dense" SCENE_SEEDS="$seeds" "$@"
}
recipes SCENE_RECIPES="$out"
# LEVEL:PULSE_RATE:SPEED per level, as mk/density.mk computes them (DENSITY_SENSOR_L0, the preset).
# shellcheck disable=SC2016  # $(density_sensor_keys) is make's, not the shell's
keys=$(make --no-print-directory -s -C "$src" -f Makefile.experiments PROGRESS=0 DENSITY_SENSOR_LEVELS="10 25 50" \
  --eval 'canopy-sensor-keys: ; @echo $(density_sensor_keys)' canopy-sensor-keys)
[ -n "$keys" ] || { echo "recipes.sh: mk/density.mk gave no sensor keys" >&2; exit 1; }
for lv in $keys; do
  IFS=: read -r l r v _ <<<"$lv"  # LEVEL:PULSE_RATE:SPEED:CLASS (mk/density.mk)
  recipes SCENE_RECIPES="$out/sensor-$l" SCENE_SENSOR=als_qL1 SCENE_SENSOR_KEYS="pulse_rate=$r speed=$v"
done
