#!/usr/bin/env bash
# run.sh BIN MODELBASE DIR...: CPU seconds (user + sys) and wall seconds of one verify run per
# candidate directory (each holding match.json, samples.pcd, segments.json, e.g. the trial
# directories of trials.sh), best of --repeat 3, with the shipped share/params/verify.ini.
# Extra verify options after "--". Prints one line per candidate and the median.
set -u
bin=$1 mb=$2
shift 2
dirs=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do dirs+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
src=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for d in "${dirs[@]}"; do
  best=
  for r in 1 2 3; do
    /usr/bin/time -f '%U %S %e' -o "$tmp/t" "$bin/verify" -q --config "$src/share/params/verify.ini" "$@" \
      -i "$d/match.json" --points "$d/samples.pcd" --segments "$d/segments.json" --modelbase "$mb" \
      -o "$tmp/v.json" || exit 1
    read -r u s e <"$tmp/t"
    cpu=$(echo "$u + $s" | bc)
    if [ -z "$best" ] || [ "$(echo "$cpu < $best" | bc)" = 1 ]; then best=$cpu; wall=$e; fi
  done
  echo "$d cpu $best s wall $wall s"
done | tee "$tmp/all"
awk '{print $3}' "$tmp/all" | sort -n | awk '{a[NR]=$1} END {print "median cpu", a[int((NR+1)/2)], "s over", NR, "candidates"}'
