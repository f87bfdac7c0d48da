#!/usr/bin/env bash
# Sanitizer build of canopy (g++, AddressSanitizer + UndefinedBehaviorSanitizer, -O1 -g) in
# build-asan/, then its tests. Any ASan or UBSan report fails the test that triggered it
# (UBSan halts on the first error); LeakSanitizer reports from the GL driver under VTK are
# suppressed by scripts/sanitize.supp where the driver's frames are named, and leak checking is
# off for the VTK-rendering tests where they are not (see below).
# Usage: scripts/sanitize.sh [ctest -R regex] [build target ...]
#   scripts/sanitize.sh                      everything
#   scripts/sanitize.sh test_formats test_formats pcd2ply   the formats tests only
#   SANITIZE_BUILD=0 scripts/sanitize.sh 'pipeline_'   the tests only, on build-asan/ as it is
#                                            (to continue a run, or beside a running build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
regex=${1:-}
shift || true
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
# EIGEN_MALLOC_ALREADY_ALIGNED=1: under __SANITIZE_ADDRESS__ Eigen 3.4 (Core/util/Memory.h)
# stops trusting glibc's 16-byte-aligned malloc and switches its aligned allocator to
# handmade_aligned_malloc, which returns an offset into a larger block. Debian's PCL is built
# without ASan and keeps std::malloc/std::free, so memory one side allocates the other frees
# (e.g. the point vectors in pcl::applyMorphologicalOperator, detect's ground filter): an ASan
# bad-free that is an artefact of the mixed build, not a canopy bug. The macro keeps the
# sanitized build on PCL's allocator; ASan's malloc also returns 16-byte-aligned blocks, which
# Eigen asserts in this (assertion-enabled) build.
flags="-O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
flags="$flags -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
if [ "${SANITIZE_BUILD:-1}" != 0 ]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCANOPY_BENCH=OFF -DCANOPY_WERROR=OFF \
    -DCMAKE_CXX_FLAGS_DEBUG="$flags" -DCMAKE_C_FLAGS_DEBUG="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" "${launcher[@]}" >/dev/null
  if [ $# -gt 0 ]; then
    cmake --build build-asan -j"$(nproc)" --target "$@"
  else
    cmake --build build-asan -j"$(nproc)"
  fi
fi
# alloc_dealloc_mismatch=0: Debian's PCL is built as C++14, where PCL_MAKE_ALIGNED_OPERATOR_NEW
# (EIGEN_MAKE_ALIGNED_OPERATOR_NEW) gives pcl::PointCloud a class operator new that calls
# malloc; canopy is C++17, where Eigen leaves that macro empty (EIGEN_HAS_CXX17_OVERALIGN), so a
# cloud PCL allocates (ProgressiveMorphologicalFilter::extract, detect's ground filter) is
# released by canopy's shared_ptr deleter with the global operator delete. ASan reports
# "alloc-dealloc-mismatch (malloc vs operator delete)"; libstdc++'s operator delete is free(),
# so the release build is unaffected. ASan suppressions cannot name this check, hence the option.
#
# ASan and LeakSanitizer reports go to a file (log_path), not to stderr: the pipeline tests run
# the tools through make and scripts/stage.sh, which keep a tool's stderr in a log that the test
# deletes, and record a failing ablation or tile stage (status 1..125) as a failed trial; unit
# tests expect exit 1 from tools on bad input. A report there would not fail the test. Each test
# gets its own report directory, build-asan/sanitizer-reports/<test>/; any file in it fails the
# run and is printed below. exitcode=86 (a status no canopy tool uses) also fails most tests at
# once. UBSan in g++'s combined runtime ignores log_path (its report goes to stderr whatever
# UBSAN_OPTIONS or ASAN_OPTIONS say; tried with a one-line overflow), so it aborts instead
# (SIGABRT, status 134): stage.sh never records a signal as a failed trial, and the test fails.
cd build-asan
reports=$PWD/sanitizer-reports
base_asan="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:alloc_dealloc_mismatch=0:exitcode=86"
base_ubsan="print_stacktrace=1:halt_on_error=1:abort_on_error=1"
export LSAN_OPTIONS="suppressions=$root/scripts/sanitize.supp:print_suppressions=0"
# figures renders with VTK, whose Mesa GL driver leaks 112 bytes and is unloaded before
# LeakSanitizer reports, so the report names no library a suppression could match: figures
# itself stops LeakSanitizer from counting what its thread allocates while a render window lives
# (tools/figures/gl_leaks.h). Every test, those that run figures included, runs with leak
# detection on.
# The pipeline tests get build-asan/bin as their bin dir and run the tools from there (smoke:
# PATH; families, scene_mini, scene_baseline: make with BUILD=<tmp> whose bin/ links to it and
# CMAKE=true, so nothing is rebuilt; slurm: BIN=<bin dir>, the tools given as -o). Refuse to
# run if any tool there is not the sanitized build.
for b in bin/*; do
  [[ $(ldd "$b") == *libasan* ]] || { echo "sanitize.sh: $b is not linked with ASan" >&2; exit 1; }
done
mapfile -t tests < <(ctest -N ${regex:+-R "$regex"} | sed -n 's/^ *Test *#[0-9]*: //p')
[ ${#tests[@]} -gt 0 ] || { echo "sanitize.sh: no test matches '$regex'" >&2; exit 2; }
rc=0 failed=() reported=()
started=$(date +%s)
for t in "${tests[@]}"; do
  rm -rf "$reports/$t" && mkdir -p "$reports/$t"
  asan="$base_asan:log_path=$reports/$t/asan"
  t0=$(date +%s)
  ASAN_OPTIONS=$asan UBSAN_OPTIONS=$base_ubsan \
    ctest --output-on-failure -R "^$t\$" || { rc=1; failed+=("$t"); }
  echo "sanitize.sh: $t: $(($(date +%s) - t0)) s"
  if [ -n "$(ls -A "$reports/$t")" ]; then
    rc=1 reported+=("$t")
    for f in "$reports/$t"/*; do echo "---- $f"; head -n 60 "$f"; done
  fi
done
echo "sanitize.sh: ${#tests[@]} tests in $(($(date +%s) - started)) s; failed: ${failed[*]:-none};" \
  "with sanitizer reports: ${reported[*]:-none}"
exit $rc
