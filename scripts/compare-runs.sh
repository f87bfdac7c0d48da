#!/usr/bin/env bash
# scripts/compare-runs.sh A B: two runs of the experiment compared file by file — each of A and
# B a directory holding the run's out/ and results/ (relative OUT and RES, as the README's
# command leaves them, so the paths inside the files are the same in both). Logs, .time files
# and make's progress state are left out (they hold times). Prints the files only in A, only in
# B, and the ones that differ, grouped by name with digits collapsed (c0012/verdict.json and
# c0345/verdict.json are one group), then a summary line; exit 0 when nothing differs, 1 else.
# Usage in docs/decisions/structure.md ("The whole experiment before and after").
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 RUN_A RUN_B (directories holding out/ and results/)" >&2; exit 2; }
a=$1 b=$2
for d in "$a" "$b"; do
  [ -d "$d/out" ] && [ -d "$d/results" ] || { echo "$0: $d: no out/ and results/ in it" >&2; exit 2; }
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
list() {
  (cd "$1" && find out results -type f ! -name '*.log' ! -name '*.time' ! -name '.progress*' | LC_ALL=C sort)
}
list "$a" >"$tmp/a"
list "$b" >"$tmp/b"
LC_ALL=C comm -23 "$tmp/a" "$tmp/b" >"$tmp/only-a"
LC_ALL=C comm -13 "$tmp/a" "$tmp/b" >"$tmp/only-b"
LC_ALL=C comm -12 "$tmp/a" "$tmp/b" >"$tmp/both"
same=0
: >"$tmp/differ"
while IFS= read -r f; do
  if cmp -s "$a/$f" "$b/$f"; then same=$((same + 1)); else echo "$f" >>"$tmp/differ"; fi
done <"$tmp/both"
groups() { sed -E 's/[0-9]+/#/g' "$1" | LC_ALL=C sort | uniq -c | sort -k1,1nr -k2; }
for kind in only-a only-b differ; do
  n=$(wc -l <"$tmp/$kind")
  [ "$n" -eq 0 ] && continue
  echo "## $kind: $n files"
  groups "$tmp/$kind"
done
echo "identical $same, differ $(wc -l <"$tmp/differ"), only in A $(wc -l <"$tmp/only-a"), only in B $(wc -l <"$tmp/only-b")"
if [ -s "$tmp/differ" ] || [ -s "$tmp/only-a" ] || [ -s "$tmp/only-b" ]; then exit 1; fi
