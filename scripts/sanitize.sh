#!/usr/bin/env bash
# Sanitizer build of canopy (g++, AddressSanitizer + UndefinedBehaviorSanitizer, -O1 -g) in
# build-asan/, then its tests. Any ASan or UBSan report fails the test that triggered it
# (UBSan halts on the first error); LeakSanitizer reports from the GL driver under VTK are
# suppressed by scripts/sanitize.supp.
# Usage: scripts/sanitize.sh [ctest -R regex] [build target ...]
#   scripts/sanitize.sh                      everything
#   scripts/sanitize.sh test_formats test_formats pcd2ply   the formats tests only
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
regex=${1:-}
shift || true
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
flags="-O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCANOPY_BENCH=OFF -DCANOPY_WERROR=OFF \
  -DCMAKE_CXX_FLAGS_DEBUG="$flags" -DCMAKE_C_FLAGS_DEBUG="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" "${launcher[@]}" >/dev/null
if [ $# -gt 0 ]; then
  cmake --build build-asan -j"$(nproc)" --target "$@"
else
  cmake --build build-asan -j"$(nproc)"
fi
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/scripts/sanitize.supp:print_suppressions=0"
cd build-asan
if [ -n "$regex" ]; then
  ctest --output-on-failure -R "$regex"
else
  ctest --output-on-failure
fi
