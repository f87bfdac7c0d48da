#!/usr/bin/env bash
# gmatch timing (time per scene vs models, X, B) and the measurements of
# docs/decisions/gmatch.md. Usage: bench/gmatch/run.sh BUILD_DIR
set -euo pipefail
build=${1:?usage: $0 BUILD_DIR}
cmake --build "$build" --target bench_gmatch gmatch_decisions >/dev/null
"$build/bin/bench_gmatch"
echo
"$build/bin/gmatch_decisions"
