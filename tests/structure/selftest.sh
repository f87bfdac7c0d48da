#!/usr/bin/env bash
# check.sh on hand-made trees: a clean one passes; one with each kind of offender fails and
# names every offender (and nothing else). Usage: selftest.sh <source dir>
set -uo pipefail
src=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
check=$src/tests/structure/check.sh

lines() { local i; for ((i = 0; i < $1; i++)); do echo "// $i"; done; }

# Clean: own-tool, common/ and system includes; exactly 700 lines.
mkdir -p "$tmp/clean/tools/alpha" "$tmp/clean/tools/beta"
printf '#include "alpha/alpha.h"\n#include "canopy/common/errors.h"\n#include <vector>\n' >"$tmp/clean/tools/alpha/alpha.cpp"
lines 700 >"$tmp/clean/tools/beta/long.cpp"
echo 'canopy_add_tool(beta SOURCES long.cpp LIBS canopy_beta_lib)' >"$tmp/clean/tools/beta/CMakeLists.txt"
# The stage shape: the one spelling (a trailing comment allowed), run() in comments and calls;
# a face header without run( (beta.h); tools/gamma/stage.h is gamma's face, so gamma.h is not
# checked.
mkdir -p "$tmp/clean/tools/gamma"
printf '// run(): the stage.\nstruct Inputs {};\n  Outputs run(const Params& params, const Inputs& inputs);  // the stage\n' \
  >"$tmp/clean/tools/alpha/alpha.h"
printf 'inline int twice() { return tool.run(2) + common::run(1) + r->run(); }\n' >"$tmp/clean/tools/beta/beta.h"
printf 'Outputs run(const Params& params, const Inputs& inputs);\n' >"$tmp/clean/tools/gamma/stage.h"
printf 'Surface run();\n' >"$tmp/clean/tools/gamma/gamma.h"
out=$(bash "$check" "$tmp/clean" 2>&1) || fail "a clean tree was refused: $out"

# Offenders: one of each kind (reported sorted by file, then line).
mkdir -p "$tmp/bad/tools/alpha" "$tmp/bad/tools/beta"
printf '#include <vector>\n#include "beta/beta.h"\n' >"$tmp/bad/tools/alpha/a.cpp"
printf '#include "alpha/alpha.h"\n  #  include "../beta/beta.h"\n' >"$tmp/bad/tools/alpha/alpha.h"
printf 'int x;\n#include <nlohmann/json.hpp>\n' >"$tmp/bad/tools/beta/beta.h"
echo 'canopy_add_tool(beta SOURCES b.cpp LIBS canopy_alpha_lib)' >"$tmp/bad/tools/beta/CMakeLists.txt"
lines 701 >"$tmp/bad/tools/beta/b.cpp"
# Stage shapes other than the one spelling: parameters swapped, a multi-line declaration, an
# extra argument in stage.h (the face of gamma).
printf 'Outputs run(const Inputs& inputs, const Params& params);\n' >>"$tmp/bad/tools/alpha/alpha.h"
mkdir -p "$tmp/bad/tools/gamma" "$tmp/bad/tools/delta"
printf 'Outputs run(const Params& params, const Inputs& inputs, bool keep_all);\n' >"$tmp/bad/tools/gamma/stage.h"
printf '// Samples -> mesh.\nResult run(const Scan& scan,\n           const Params& params);\n' >"$tmp/bad/tools/delta/delta.h"
out=$(bash "$check" "$tmp/bad" 2>/dev/null)
rc=$?
[ $rc -eq 1 ] || fail "offending tree: exit $rc, expected 1"
shape='(the stage shape is "Outputs run(const Params& params, const Inputs& inputs);")'
expected="structure: tools/alpha/a.cpp:2 includes beta/beta.h (a file of tools/beta/)
structure: tools/alpha/alpha.h:2 includes beta/beta.h (a file of tools/beta/)
structure: tools/alpha/alpha.h:3 declares run as \"Outputs run(const Inputs& inputs, const Params& params);\" $shape
structure: tools/beta/CMakeLists.txt:1 links canopy_alpha_lib (the library of tools/alpha/)
structure: tools/beta/b.cpp has 701 lines (more than 700)
structure: tools/beta/beta.h:2 names nlohmann (JSON belongs to formats/ and documents/)
structure: tools/delta/delta.h:2 declares run as \"Result run(const Scan& scan,\" $shape
structure: tools/gamma/stage.h:1 declares run as \"Outputs run(const Params& params, const Inputs& inputs, bool keep_all);\" $shape"
[ "$out" = "$expected" ] || fail "offenders reported as
$out
expected
$expected"

# Pending offenders (tests/structure/pending.txt): listed ones are reported but pass; one not
# listed still fails; a listed entry that no longer offends fails.
mkdir -p "$tmp/bad/tests/structure"
printf '# comment\ntools/beta/beta.h nlohmann\ntools/beta/b.cpp lines\ntools/gamma/stage.h stage\n' \
  >"$tmp/bad/tests/structure/pending.txt"
out=$(bash "$check" "$tmp/bad" 2>/dev/null)
[ $? -eq 1 ] || fail "pending list: the unlisted includes and link did not fail"
echo "$out" | grep -qx 'pending (tests/structure/pending.txt): tools/beta/beta.h:2 names nlohmann (JSON belongs to formats/ and documents/)' ||
  fail "a pending offender not reported as pending: $out"
echo "$out" | grep -q '^pending (tests/structure/pending.txt): tools/gamma/stage.h:1 declares run as ' ||
  fail "a pending stage offender not reported as pending: $out"
if echo "$out" | grep -q '^structure: tools/beta/b.cpp'; then fail "a pending offender reported as a failure"; fi
rm "$tmp/bad/tools/alpha/a.cpp" "$tmp/bad/tools/alpha/alpha.h" "$tmp/bad/tools/delta/delta.h"
echo 'canopy_add_tool(beta SOURCES b.cpp)' >"$tmp/bad/tools/beta/CMakeLists.txt"
out=$(bash "$check" "$tmp/bad" 2>/dev/null) || fail "only pending offenders left, still refused: $out"
lines 10 >"$tmp/bad/tools/beta/b.cpp"
out=$(bash "$check" "$tmp/bad" 2>/dev/null)
[ $? -eq 1 ] || fail "a pending entry that no longer offends did not fail"
echo "$out" | grep -qx "structure: tests/structure/pending.txt lists 'tools/beta/b.cpp lines', which is no longer an offender: remove it" ||
  fail "the stale pending entry not named: $out"

# Usage errors.
bash "$check" >/dev/null 2>&1
[ $? -eq 2 ] || fail "no argument: expected exit 2"
bash "$check" "$tmp/none" >/dev/null 2>&1
[ $? -eq 2 ] || fail "missing tree: expected exit 2"
echo "ok: structure check self-test"
