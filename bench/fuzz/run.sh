#!/usr/bin/env bash
# Long fuzzing run of every reader target in fuzz/ (the test command runs them a few seconds):
# fuzz/run.sh with a bigger budget, same memory limits, corpus kept in build-fuzz/corpus/.
# Usage: bench/fuzz/run.sh [seconds per target = 600] [target name ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-600}
shift || true
exec nice fuzz/run.sh "$secs" "$@"
