#!/usr/bin/env bash
# check-format.sh FILE... | --all: exits 1 and lists the files that clang-format (with the repository's
# .clang-format) would change, with the diff; 0 when every given C++ file is formatted.
# Files that are not .cpp/.h/.hpp are ignored. Needs clang-format (scripts/install-deps.sh).
# Fix a file with: clang-format -i FILE
set -u
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
command -v clang-format >/dev/null || { echo "check-format.sh: clang-format not found (scripts/install-deps.sh)" >&2; exit 2; }
[ $# -gt 0 ] || { echo "usage: check-format.sh FILE... | --all" >&2; exit 2; }
if [ "$1" = "--all" ]; then
  # Every C++ file of the project (the test command runs this as the ctest `format_check`).
  mapfile -t all < <(cd "$here" && find common formats documents sim tools tests bench fuzz -type f \
    \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \) | LC_ALL=C sort)
  cd "$here" && set -- "${all[@]}"
fi
bad=0
for f in "$@"; do
  case "$f" in *.cpp|*.h|*.hpp) ;; *) continue ;; esac
  if [ ! -f "$f" ]; then echo "check-format.sh: $f: no such file" >&2; bad=1; continue; fi
  if ! clang-format --style="file:$here/.clang-format" "$f" | diff -u --label "$f" --label "$f (formatted)" "$f" -; then
    bad=1
  fi
done
exit $bad
