#!/usr/bin/env bash
# Structure rules of tools/ (docs/decisions/structure.md, issue 30). Usage: check.sh <source dir>
# Fails (exit 1) and prints every offender, one line each, when
#   - a file under tools/<a>/ includes a file of tools/<b>/ ("b/x.h", <b/x.h> or "../b/x.h"),
#     or tools/<a>/CMakeLists.txt links canopy_<b>_lib (the same dependency by the link line);
#   - a file under tools/ names nlohmann (JSON is parsed and built in formats/ and documents/);
#   - a .cpp or .h file under tools/ has more than 700 lines.
set -uo pipefail
[ $# -eq 1 ] || { echo "usage: check.sh <source dir>" >&2; exit 2; }
tools=$1/tools
[ -d "$tools" ] || { echo "check.sh: $tools: no such directory" >&2; exit 2; }
max_lines=700
bad=0
offend() { echo "structure: $*"; bad=1; }

names=()
for d in "$tools"/*/; do names+=("$(basename "$d")"); done
is_tool() { local n; for n in "${names[@]}"; do [ "$n" = "$1" ] && return 0; done; return 1; }

for a in "${names[@]}"; do
  # Includes of another tool's files.
  while IFS=: read -r file line text; do
    target=$(sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]([^">]*)[">].*/\1/' <<<"$text")
    target=${target#../}
    b=${target%%/*}
    if [ "$b" != "$target" ] && [ "$b" != "$a" ] && is_tool "$b"; then
      offend "${file#"$1"/}:$line includes $target (a file of tools/$b/)"
    fi
  done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]' "$tools/$a" --include='*.cpp' \
             --include='*.h' --include='*.hpp' --include='*.inc' 2>/dev/null | sort -t: -k1,1 -k2,2n)
  # Link lines naming another tool's library.
  if [ -f "$tools/$a/CMakeLists.txt" ]; then
    while IFS=: read -r line text; do
      for b in $(grep -oE 'canopy_[A-Za-z0-9]+_lib' <<<"$text"); do
        b=${b#canopy_}; b=${b%_lib}
        if [ "$b" != "$a" ] && is_tool "$b"; then
          offend "tools/$a/CMakeLists.txt:$line links canopy_${b}_lib (the library of tools/$b/)"
        fi
      done
    done < <(grep -nE 'canopy_[A-Za-z0-9]+_lib' "$tools/$a/CMakeLists.txt")
  fi
done

while IFS=: read -r file line _; do
  offend "${file#"$1"/}:$line names nlohmann (JSON belongs to formats/ and documents/)"
done < <(grep -rn nlohmann "$tools" | sort -t: -k1,1 -k2,2n)

while IFS= read -r -d '' file; do
  n=$(wc -l <"$file")
  [ "$n" -le "$max_lines" ] || offend "${file#"$1"/} has $n lines (more than $max_lines)"
done < <(find "$tools" -type f \( -name '*.cpp' -o -name '*.h' \) -print0 | sort -z)

if [ $bad -ne 0 ]; then
  echo "FAIL: tools/ breaks the structure rules (offenders above)" >&2
  exit 1
fi
echo "ok: tools/ follows the structure rules"
