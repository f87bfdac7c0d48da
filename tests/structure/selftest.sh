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
out=$(bash "$check" "$tmp/clean" 2>&1) || fail "a clean tree was refused: $out"

# Offenders: one of each kind (reported sorted by file, then line).
mkdir -p "$tmp/bad/tools/alpha" "$tmp/bad/tools/beta"
printf '#include <vector>\n#include "beta/beta.h"\n' >"$tmp/bad/tools/alpha/a.cpp"
printf '#include "alpha/alpha.h"\n  #  include "../beta/beta.h"\n' >"$tmp/bad/tools/alpha/alpha.h"
printf 'int x;\n#include <nlohmann/json.hpp>\n' >"$tmp/bad/tools/beta/beta.h"
echo 'canopy_add_tool(beta SOURCES b.cpp LIBS canopy_alpha_lib)' >"$tmp/bad/tools/beta/CMakeLists.txt"
lines 701 >"$tmp/bad/tools/beta/b.cpp"
out=$(bash "$check" "$tmp/bad" 2>/dev/null)
rc=$?
[ $rc -eq 1 ] || fail "offending tree: exit $rc, expected 1"
expected="structure: tools/alpha/a.cpp:2 includes beta/beta.h (a file of tools/beta/)
structure: tools/alpha/alpha.h:2 includes beta/beta.h (a file of tools/beta/)
structure: tools/beta/CMakeLists.txt:1 links canopy_alpha_lib (the library of tools/alpha/)
structure: tools/beta/b.cpp has 701 lines (more than 700)
structure: tools/beta/beta.h:2 names nlohmann (JSON belongs to formats/ and documents/)"
[ "$out" = "$expected" ] || fail "offenders reported as
$out
expected
$expected"

# Pending offenders (tests/structure/pending.txt): listed ones are reported but pass; one not
# listed still fails; a listed entry that no longer offends fails.
mkdir -p "$tmp/bad/tests/structure"
printf '# comment\ntools/beta/beta.h nlohmann\ntools/beta/b.cpp lines\n' >"$tmp/bad/tests/structure/pending.txt"
out=$(bash "$check" "$tmp/bad" 2>/dev/null)
[ $? -eq 1 ] || fail "pending list: the unlisted includes and link did not fail"
echo "$out" | grep -qx 'pending (tests/structure/pending.txt): tools/beta/beta.h:2 names nlohmann (JSON belongs to formats/ and documents/)' ||
  fail "a pending offender not reported as pending: $out"
if echo "$out" | grep -q '^structure: tools/beta/b.cpp'; then fail "a pending offender reported as a failure"; fi
rm "$tmp/bad/tools/alpha/a.cpp" "$tmp/bad/tools/alpha/alpha.h"
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
