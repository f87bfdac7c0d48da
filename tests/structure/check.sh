#!/usr/bin/env bash
# Structure rules of tools/ (docs/decisions/structure.md, issue 30). Usage: check.sh <source dir>
# Fails (exit 1) and prints every offender, one line each, when
#   - a file under tools/<a>/ includes a file of tools/<b>/ ("b/x.h", <b/x.h> or "../b/x.h"),
#     or tools/<a>/CMakeLists.txt links canopy_<b>_lib (the same dependency by the link line);
#   - a file under tools/ names nlohmann (JSON is parsed and built in formats/ and documents/);
#   - a .cpp or .h file under tools/ has more than 700 lines;
#   - a tool's face header declares its stage other than as
#       Outputs run(const Params& params, const Inputs& inputs);
#     The face header of tools/<t>/ is tools/<t>/stage.h when that file exists (rangetrace, whose
#     rangetrace.h is the renderer), else tools/<t>/<t>.h. Every line of it (comments removed)
#     naming an unqualified run( must be exactly that declaration; a face header without run( is
#     not checked (score, topview, figures have no stage function).
set -uo pipefail
[ $# -eq 1 ] || { echo "usage: check.sh <source dir>" >&2; exit 2; }
tools=$1/tools
[ -d "$tools" ] || { echo "check.sh: $tools: no such directory" >&2; exit 2; }
max_lines=700
stage_shape='Outputs run(const Params& params, const Inputs& inputs);'
bad=0

names=$(cd "$tools" && for d in */; do printf '%s ' "${d%/}"; done)
report=$(
  # Includes of another tool's files: one awk over every #include line.
  grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]' "$tools" --include='*.cpp' --include='*.h' \
      --include='*.hpp' --include='*.inc' |
    awk -v root="$1/" -v names="$names" '
      BEGIN { n = split(names, t, " "); for (i = 1; i <= n; i++) tool[t[i]] = 1 }
      {
        file = $0; sub(/:.*/, "", file)
        rest = substr($0, length(file) + 2); line = rest; sub(/:.*/, "", line)
        text = substr(rest, length(line) + 2)
        if (!match(text, /["<][^">]*[">]/)) next
        target = substr(text, RSTART + 1, RLENGTH - 2); sub(/^\.\.\//, "", target)
        rel = substr(file, length(root) + 1); split(rel, p, "/"); a = p[2]
        slash = index(target, "/"); if (slash == 0) next
        b = substr(target, 1, slash - 1)
        if (b != a && (b in tool))
          printf "%s\t%09d\tstructure: %s:%s includes %s (a file of tools/%s/)\n", rel, line, rel, line, target, b
      }'
  # Link lines naming another tool's library.
  for cm in "$tools"/*/CMakeLists.txt; do
    grep -noE 'canopy_[A-Za-z0-9]+_lib' "$cm" |
      awk -v a="$(basename "$(dirname "$cm")")" -v names="$names" '
        BEGIN { n = split(names, t, " "); for (i = 1; i <= n; i++) tool[t[i]] = 1 }
        {
          split($0, f, ":"); b = f[2]; sub(/^canopy_/, "", b); sub(/_lib$/, "", b)
          if (b != a && (b in tool))
            printf "tools/%s/CMakeLists.txt\t%09d\tstructure: tools/%s/CMakeLists.txt:%s links canopy_%s_lib (the library of tools/%s/)\n", a, f[1], a, f[1], b, b
        }'
  done
  # nlohmann anywhere under tools/.
  grep -rn nlohmann "$tools" | awk -v root="$1/" '{
      file = $0; sub(/:.*/, "", file); rest = substr($0, length(file) + 2); line = rest; sub(/:.*/, "", line)
      rel = substr(file, length(root) + 1)
      printf "%s\t%09d\tstructure: %s:%s names nlohmann (JSON belongs to formats/ and documents/)\n", rel, line, rel, line
    }'
  # Sources over the limit.
  find "$tools" -type f \( -name '*.cpp' -o -name '*.h' \) -print0 | xargs -0 -r wc -l |
    awk -v root="$1/" -v max="$max_lines" '$2 != "total" && $1 > max {
      rel = substr($2, length(root) + 1)
      printf "%s\t%09d\tstructure: %s has %d lines (more than %d)\n", rel, 999999999, rel, $1, max
    }'
  # The stage function's spelling in each tool's face header.
  for dir in "$tools"/*/; do
    t=$(basename "$dir")
    face=$dir/stage.h
    [ -f "$face" ] || face=$dir/$t.h
    [ -f "$face" ] || continue
    awk -v rel="tools/$t/$(basename "$face")" -v shape="$stage_shape" '
      {
        text = $0; sub(/\/\/.*/, "", text); gsub(/^[ \t]+|[ \t]+$/, "", text)
        if (text ~ /^(\/\*|\*)/) next
        if (text ~ /(^|[^A-Za-z0-9_:.>])run[ \t]*\(/ && text != shape)
          printf "%s\t%09d\tstructure: %s:%d declares run as \"%s\" (the stage shape is \"%s\")\n", rel, FNR, rel, FNR, text, shape
      }' "$face"
  done
)
report=$(printf '%s\n' "$report" | grep -v '^$' | LC_ALL=C sort -t"$(printf '\t')" -k1,1 -k2,2 | cut -f3-)

# Known offenders still being moved (<source dir>/tests/structure/pending.txt: "<file> <rule>"
# per line, rule = includes | links | nlohmann | lines | stage, '#' starts a comment): reported as
# pending, not failures. A pending entry that no longer matches an offender fails the check, so
# the list only shrinks. Hand-made trees without the file are checked strictly.
pending_file=$1/tests/structure/pending.txt
declare -A pending=()
if [ -f "$pending_file" ]; then
  while read -r file rule _; do
    [ -n "$file" ] && [ "${file:0:1}" != "#" ] && pending["$file $rule"]=0
  done <"$pending_file"
fi
rule_of() {
  case $1 in
    *" declares run as "*) echo stage ;; *" includes "*) echo includes ;; *" links "*) echo links ;;
    *"names nlohmann"*) echo nlohmann ;; *) echo lines ;;
  esac
}
if [ -n "$report" ]; then
  while IFS= read -r l; do
    f=${l#structure: }; f=${f%% *}; f=${f%%:*}
    key="$f $(rule_of "$l")"
    if [ -n "${pending[$key]+x}" ]; then
      pending[$key]=1
      echo "pending (tests/structure/pending.txt): ${l#structure: }"
    else
      echo "$l"
      bad=1
    fi
  done <<<"$report"
fi
for key in "${!pending[@]}"; do
  if [ "${pending[$key]}" = 0 ]; then
    echo "structure: tests/structure/pending.txt lists '$key', which is no longer an offender: remove it"
    bad=1
  fi
done

if [ $bad -ne 0 ]; then
  echo "FAIL: tools/ breaks the structure rules (offenders above)" >&2
  exit 1
fi
echo "ok: tools/ follows the structure rules${pending[*]:+ (apart from the pending list)}"
