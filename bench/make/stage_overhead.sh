#!/usr/bin/env bash
# CPU of one experiment stage outside its tool (docs/decisions/cost.md §9, §19): a make of N
# targets, each `STAGE ART -- bin/true-tool ART` with progress on, against the same tool run by
# make alone. Usage: bench/make/stage_overhead.sh [STAGE] [N]   (default build/bin/stagerun, 200;
# STAGE may be any runner taking `ART -- COMMAND`, e.g. an older scripts/stage.sh)
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
stage=${1:-$here/build/bin/stagerun} n=${2:-200}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/bin" "$tmp/a" "$tmp/st"
printf '#!/bin/sh\n: > "$1"\n' >"$tmp/bin/true-tool"; chmod +x "$tmp/bin/true-tool"
cat >"$tmp/m.mk" <<MK
SHELL := /bin/bash
all: \$(foreach i,\$(shell seq $n),$tmp/a/a\$(i))
$tmp/a/a%:
	@\$(if \$(STAGE),\$(STAGE) \$@ --) $tmp/bin/true-tool \$@
MK
echo "0 $n 0 $n.000 $(date +%s.%N)" >"$tmp/st/p"; printf 'true-tool:a# 0.100\n* 1.000\n' >"$tmp/st/p-est"
CANOPY_PROGRESS=$tmp/st/p /usr/bin/time -f '%U %S' -o "$tmp/t" make -s -f "$tmp/m.mk" -j1 STAGE="$stage" >/dev/null
awk -v n="$n" -v s="$(basename "$stage")" '{ printf "through %s: %.1f ms CPU per stage\n", s, ($1 + $2) * 1000 / n }' "$tmp/t"
rm -rf "$tmp/a"/*
/usr/bin/time -f '%U %S' -o "$tmp/t" make -s -f "$tmp/m.mk" -j1 STAGE= >/dev/null
awk -v n="$n" '{ printf "the tool alone:   %.1f ms CPU per stage\n", ($1 + $2) * 1000 / n }' "$tmp/t"
