#!/usr/bin/env bash
# The shell and make answer alike: every key of a shipped defaults file share/params/<tool>.ini
# equals the built-in default the tool's --help shows, for the tools the README's shell pipe
# runs without --config (rangetrace | addnoise | fitvox, cocone | ncut, gmatch | verify) while
# make passes the file. Until stop 67 verify's built-in --top-k was 3 and verify.ini's 5, so
# the README's pipe could answer otherwise than make (docs/decisions/hardening.md, stop 67).
#
#   ini_defaults.sh BIN_DIR PARAMS_DIR [TOOL[=KEY,KEY...]...]     (default tools: the README pipe's)
#
# TOOL=KEY,KEY...: the ini differs from the built-in defaults in exactly these keys, on purpose
# (classify: five rules measured on real tiles are off in its built-ins; the README says so).
#
# Values are compared by meaning: lengths in metres (128mm = 0.128m), angles in degrees,
# true/false as 1/0, numbers to 6 significant digits (--help prints 0.833333), else as text.
# Exit 1 listing every key that differs or that --help shows no default for.
set -u
bin=$1 params=$2
shift 2
tools=("$@")
[ ${#tools[@]} -gt 0 ] || tools=(rangetrace addnoise fitvox cocone ncut gmatch verify)

# norm VALUE: the value in canonical form (awk).
norm_awk='
function norm(v,    n, u, x) {
  gsub(/^[ \t"]+|[ \t"]+$/, "", v)
  if (v == "true") return "1"
  if (v == "false") return "0"
  if (match(v, /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?/)) {
    n = substr(v, 1, RLENGTH) + 0; u = substr(v, RLENGTH + 1)
    if (u == "mm") x = n / 1000
    else if (u == "cm") x = n / 100
    else if (u == "m" || u == "deg" || u == "") x = n
    else if (u == "rad") x = n * 180 / 3.141592653589793
    else return v
    return sprintf("%.6g", x)
  }
  return v
}'

bad=0
for arg in "${tools[@]}"; do
  t=${arg%%=*} expect=
  [ "$t" = "$arg" ] || expect=$(printf '%s\n' "${arg#*=}" | tr , '\n' | sort | tr '\n' ' ')
  ini=$params/$t.ini
  [ -f "$ini" ] || { echo "FAIL [$t]: no $ini" >&2; bad=1; continue; }
  help=$("$bin/$t" --help 2>&1) || { echo "FAIL [$t]: --help exited $?" >&2; bad=1; continue; }
  out=$(awk -v tool="$t" "$norm_awk"'
    # the --help lines: "  [-x,]--key[ TYPE]=DEFAULT   help text"
    FNR == NR {
      if (match($0, /^ +(-[A-Za-z],)?--[a-z0-9-]+/)) {
        line = substr($0, RSTART, RLENGTH); sub(/^ +(-[A-Za-z],)?--/, "", line); key = line
        rest = substr($0, RSTART + RLENGTH)
        if (match(rest, /^( [^ =]+)?=/)) {
          rest = substr(rest, RLENGTH + 1); sub(/ .*$/, "", rest); def[key] = rest
        } else if (match(rest, /^ [A-Z]+:[^=]*\]=/)) {
          rest = substr(rest, RLENGTH + 1); sub(/ .*$/, "", rest); def[key] = rest
        }
      }
      next
    }
    /^[ \t]*[;#]/ || !/=/ { next }
    {
      k = $0; sub(/=.*/, "", k); gsub(/[ \t]/, "", k)
      v = $0; sub(/^[^=]*=/, "", v)
      if (!(k in def)) { printf "FAIL [%s]: %s = %s: --help shows no default for --%s\n", tool, k, v, k; next }
      if (norm(v) != norm(def[k])) {
        printf "FAIL [%s]: %s: the ini says %s, the built-in default is %s\n", tool, k, v, def[k]
      }
    }' <(printf '%s\n' "$help") "$ini")
  if [ -n "$expect" ]; then
    got=$(printf '%s\n' "$out" | sed -n 's/^FAIL \[[^]]*\]: \([a-z0-9-]*\): the ini says .*/\1/p' | sort | tr '\n' ' ')
    other=$(printf '%s\n' "$out" | grep -v ': the ini says ' | grep . || true)
    if [ "$got" != "$expect" ] || [ -n "$other" ]; then
      printf '%s\n' "$out" >&2
      echo "FAIL [$t]: the keys that differ are '$got', expected exactly '$expect'" >&2
      bad=1
    else
      echo "ok [$t]: $ini differs from the built-in defaults in exactly: $got"
    fi
  elif [ -n "$out" ]; then
    printf '%s\n' "$out" >&2
    bad=1
  else
    echo "ok [$t]: $(grep -cE '^[a-z0-9-]+ *=' "$ini") keys of $ini equal the built-in defaults"
  fi
done
exit $bad
