#!/usr/bin/env bash
# gmatch against 1000-entry modelbases with and without the prefilter (docs/decisions/gmatch.md
# §9). Usage: bench/gmatch/scale.sh BUILD_DIR EXP_OUT SCRATCH
#   EXP_OUT  a finished experiment's out/ (its modelbase/*.json and trial segments.json)
#   SCRATCH  where the modelbases and the development queries go (never committed)
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR EXP_OUT SCRATCH}
exp=${2:?usage: $0 BUILD_DIR EXP_OUT SCRATCH}
scratch=${3:?usage: $0 BUILD_DIR EXP_OUT SCRATCH}
here=$(dirname "$0")
cmake --build "$build" --target bench_gmatch_scale rangetrace addnoise fitvox cocone ncut >/dev/null
bin=$build/bin/bench_gmatch_scale
mkdir -p "$scratch"
[ -d "$scratch/mb1000c" ] || "$bin" build "$scratch/mb1000c" "$exp"/modelbase/*.json
[ -d "$scratch/mb1000" ] || "$bin" build "$scratch/mb1000" "$exp"/modelbase/*.json \
  "$exp"/*/{circle,flyby,unoccluded}/noise-*/segments.json
"$here/dev_queries.sh" "$build" "$scratch/dev"
queries=()
for d in "$scratch"/dev/*/; do queries+=("$(cut -d' ' -f1 "$d/meta")=${d}segments.json"); done
for mb in mb1000c mb1000; do
  echo "== $mb"
  "$bin" run "$scratch/$mb" "${queries[@]}"
done
