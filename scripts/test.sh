#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DCANOPY_BENCH=OFF
cd build
ctest --output-on-failure -j"$(nproc)"
