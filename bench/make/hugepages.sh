#!/usr/bin/env bash
# One stage's CPU with and without glibc's transparent huge pages (scripts/stage.sh sets
# GLIBC_TUNABLES=glibc.malloc.hugetlb=1 for every stage; docs/decisions/cost.md section 15):
# runs COMMAND ROUNDS times each way, alternating, every run in its own process, and prints
# user, system and their sum (CPU-s), wall and peak RSS per run, then the median CPU of each
# way. COMMAND's outputs are compared between the two ways when OUTPUT is given (a file or
# directory COMMAND writes; it must be the same bytes: the tunable only changes where memory
# lives).
# Usage: bench/make/hugepages.sh [-r ROUNDS=3] [-o OUTPUT] -- COMMAND...
# e.g. bench/make/hugepages.sh -o /tmp/c -- build/bin/detect -i tile.pcd -o /tmp/c
set -euo pipefail
rounds=3 output=
while [ $# -gt 0 ]; do
  case "$1" in
    -r) rounds=$2; shift 2 ;;
    -o) output=$2; shift 2 ;;
    --) shift; break ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { echo "usage: $0 [-r ROUNDS] [-o OUTPUT] -- COMMAND..." >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for ((r = 1; r <= rounds; r++)); do
  for way in off on; do
    tunables=${GLIBC_TUNABLES:-}
    [ "$way" = off ] || tunables=${tunables:+$tunables:}glibc.malloc.hugetlb=1
    GLIBC_TUNABLES=$tunables /usr/bin/time -f '%U %S %e %M' -o "$tmp/t" "$@" >/dev/null 2>"$tmp/err" ||
      { cat "$tmp/err" >&2; exit 1; }
    read -r u s e m <"$tmp/t"
    cpu=$(awk -v u="$u" -v s="$s" 'BEGIN { print u + s }')
    printf '%-4s round %d: user %6.2f  sys %6.2f  cpu %6.2f s  wall %6.2f s  peak %6d MB\n' \
      "$way" "$r" "$u" "$s" "$cpu" "$e" $((m / 1024))
    echo "$cpu" >>"$tmp/$way"
    if [ -n "$output" ]; then
      rm -rf "$tmp/out-$way"
      cp -r "$output" "$tmp/out-$way"
    fi
  done
  if [ -n "$output" ] && ! diff -r "$tmp/out-off" "$tmp/out-on" >/dev/null; then
    echo "outputs differ between the two ways: $output" >&2
    exit 1
  fi
done
median() { sort -n "$1" | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "median cpu: off $(median "$tmp/off") s, on $(median "$tmp/on") s"
