#!/usr/bin/env bash
# stage.sh ARTIFACT -- COMMAND...: runs one experiment stage for make.
# The tool's stderr goes to ARTIFACT.log; wall seconds and peak memory (KiB) to ARTIFACT.time
# (read by the report); one progress line is printed. On failure the log tail is shown and
# the status is passed on (the tool itself never leaves a partial ARTIFACT).
# stage.sh --record-failure ARTIFACT -- ...: for ablation variants, where a stage failing is a
# result (e.g. the thesis's fixed RMS bound keeps no voxel at 32 mm): the failure is logged,
# ARTIFACT is created empty as an explicit "failed" marker, and the status is 0. Later stages
# fail on the empty input in turn, so the trial's match.json is empty and counts as not
# recognised.
set -u
record=0
if [ "${1:-}" = "--record-failure" ]; then record=1; shift; fi
artifact=$1; shift
[ "${1:-}" = "--" ] && shift
log="$artifact.log"
mkdir -p "$(dirname "$artifact")"
if /usr/bin/time -f '%e %M' -o "$artifact.time.tmp" "$@" 2>"$log"; then
  mv -f "$artifact.time.tmp" "$artifact.time"
  read -r secs kib <"$artifact.time"
  printf 'done  %-58s %7.2f s %6d MB\n' "$artifact" "$secs" "$((kib / 1024))"
else
  rc=$?
  rm -f "$artifact.time.tmp" "$artifact.time"
  printf 'FAIL  %-58s (exit %d); last lines of %s:\n' "$artifact" "$rc" "$log"
  tail -n 5 "$log" | sed 's/^/      /'
  if [ $record -eq 1 ]; then
    : >"$artifact" && echo "      recorded as a failed trial (empty $artifact)"
    exit 0
  fi
  exit "$rc"
fi
