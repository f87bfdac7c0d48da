#!/usr/bin/env bash
# classify's object link on real tiles (docs/decisions/classify.md §21): per tile, detect's
# candidates (as `make tile` makes them), classify on every candidate with each variant, collect,
# score against TRUTH_DIR/<tile>.truth.json, and bench/classify/realcal.py --figures per variant;
# then the candidates whose answer differs from the first variant's.
#   TRUTH_DIR=DIR bench/classify/link.sh OUT_DIR TILE.laz [TILE.laz ...]
#   (BIN=build/bin; INI=share/params/classify.ini; VARIANTS="name:extra classify args" ...;
#   JOBS=2 classify processes; MODELBASE=DIR passes --modelbase DIR --model-classes share/models/classes.csv to classify and
#   --modelbase to collect, as `make tile` does)
# Development tiles only while developing (ahn3_delft_1, forest_bcts_1 from the shared data, the
# two AHN4 development tiles of stop 47); the held-out tiles once (docs/decisions/real-tiles.md).
set -euo pipefail
# bench/classify/passes.sh with this section's variants and the per-candidate differences.
VARIANTS=${VARIANTS:-"before:--bridge=0 bridge:--bridge=1m"} DIFF=1 exec "$(dirname "$0")/passes.sh" "$@"
