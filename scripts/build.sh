#!/usr/bin/env bash
# Installs missing packages, configures and builds canopy into build/ (Release).
# Extra arguments go to CMake's configure step (e.g. -DCANOPY_BENCH=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"
