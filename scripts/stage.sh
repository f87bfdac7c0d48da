#!/bin/bash
# stage.sh [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND...: runs one
# experiment stage for make.
# The tool's stderr (its INFO lines, warnings, errors) goes to ARTIFACT.log; wall seconds, peak
# memory (KiB), user and system CPU seconds to ARTIFACT.time (GNU time's "%e %M %U %S", read by
# the report through formats/stage_time.h); one progress line is printed,
# "done  N/M ARTIFACT ..." where M is the number of stages make planned (CANOPY_PROGRESS_TOTAL)
# and N counts the stages finished so far in this make run (a counter file,
# CANOPY_PROGRESS, incremented under flock). On failure the log tail is shown and the status
# is passed on (the tool itself never leaves a partial ARTIFACT).
#
# --launch slurm: the command runs as a Slurm job through srun, with the CPUs, memory and
# time limit of its tool's section in share/resources.ini (the first word of COMMAND whose
# name has a section there; else [default]). CANOPY_SRUN_FLAGS adds site options (partition,
# account). ARTIFACT.log, ARTIFACT.time and ARTIFACT itself are written by the job, on the
# filesystem shared by all nodes; srun passes the exit status on, and Ctrl-C (SIGINT to make's
# process group) makes srun cancel the job at once (--quit-on-interrupt).
#
# --record-failure: for ablation variants, where a stage failing is a result (e.g. the
# thesis's fixed RMS bound keeps no voxel at 32 mm): when the tool itself exits with a status
# from 1 to 125 (its own error; canopy's tools exit 1 or 2), the failure is logged, ARTIFACT
# is created empty as an explicit "failed" marker, and the status is 0. Later stages fail on
# the empty input in turn, so the trial's match.json is empty and counts as not recognised. A tool killed by a signal
# (Ctrl-C, SIGTERM, the OOM killer's SIGKILL, a Slurm time limit), a status of 126 or more
# (could not execute, not found, a signal passed on by a wrapper), or a launch that never ran
# the tool (srun could not get an allocation) is never a result: it fails make and leaves no
# ARTIFACT. GNU time's report ("Command terminated by signal 9") tells the cases apart.
set -u
# (Forks are counted here: this runs once per stage, ≈ 2000 times in the experiment. What bash
# can do itself (dirname, reading a line, the CPU sum, the clock, emptying a file) it does, and
# the shebang names bash directly, not through env.)
launch=local
record=0
while :; do
  case "${1:-}" in
    --launch) launch=${2:-}; shift 2 ;;
    --record-failure) record=1; shift ;;
    *) break ;;
  esac
done
artifact=${1:-}
[ -n "$artifact" ] || { echo "stage.sh: usage: stage.sh [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND..." >&2; exit 2; }
shift
[ "${1:-}" = "--" ] && shift
[ $# -gt 0 ] || { echo "stage.sh: $artifact: no command given" >&2; exit 2; }
log="$artifact.log"
# GNU time writes ARTIFACT.time itself (no temporary file renamed afterwards: one `mv` process
# less a stage, ≈ 10 ms of CPU on the experiment machine, docs/decisions/cost.md §18); a stage
# that does not finish removes it (below), so no partial or stale .time is left beside an
# artifact. (The previous run's wall time, this stage's progress estimate, is read first.)
timing="$artifact.time"
case "$artifact" in */*) [ -d "${artifact%/*}" ] || mkdir -p "${artifact%/*}" ;; esac

# resource KEY: the value of KEY in the tool's section of the resources file, else [default].
resources=${CANOPY_RESOURCES:-}
[ -n "$resources" ] || { here=${BASH_SOURCE[0]%/*}; [ "$here" != "${BASH_SOURCE[0]}" ] || here=.; resources=$here/../share/resources.ini; }
ini_get() {  # ini_get SECTION KEY
  awk -v sec="$1" -v key="$2" '
    /^[ \t]*[#;]/ { next }
    /^[ \t]*\[/ { s = $0; gsub(/[][ \t]/, "", s); next }
    s == sec { split($0, kv, "="); k = kv[1]; gsub(/[ \t]/, "", k)
               if (k == key) { v = substr($0, index($0, "=") + 1); gsub(/^[ \t]+|[ \t]+$/, "", v); print v; exit } }
  ' "$resources"
}
section=default
if [ "$launch" = slurm ]; then
  [ -r "$resources" ] || { echo "stage.sh: error: $resources: cannot read the resources file" >&2; exit 1; }
  for word in "$@"; do
    name=$(basename -- "$word")
    if grep -qxF "[$name]" "$resources" 2>/dev/null; then section=$name; break; fi
  done
fi
resource() { local v; v=$(ini_get "$section" "$1"); [ -n "$v" ] || v=$(ini_get default "$1"); echo "$v"; }

# Large blocks in transparent huge pages (glibc >= 2.35 madvises its heap and mmap'd blocks):
# a tile's scan of millions of points then spends far less in page faults and TLB misses
# (detect on a 2.5 M point tile: 4.8 -> 2.6 CPU-s); outputs do not change (cost.md §15).
# CANOPY_HUGEPAGES=0 (make HUGEPAGES=0) leaves glibc's default; the user's own GLIBC_TUNABLES
# are kept, and one of theirs naming hugetlb wins.
if [ "${CANOPY_HUGEPAGES:-1}" != 0 ]; then
  case ":${GLIBC_TUNABLES:-}" in
    *:glibc.malloc.hugetlb=*) ;;
    *) export GLIBC_TUNABLES="${GLIBC_TUNABLES:+$GLIBC_TUNABLES:}glibc.malloc.hugetlb=1" ;;
  esac
fi
run=(/usr/bin/time -f '%e %M %U %S' -o "$timing" "$@")
case "$launch" in
  local) ;;
  slurm)
    command -v srun >/dev/null || { echo "stage.sh: error: srun not found (Debian package slurm-client)" >&2; exit 1; }
    cpus=$(resource cpus); mem=$(resource mem); limit=$(resource time)
    for v in cpus mem limit; do
      [ -n "${!v}" ] || { echo "stage.sh: error: $resources: no '${v/limit/time}' for [$section] or [default]" >&2; exit 1; }
    done
    # shellcheck disable=SC2206  # site flags are words, split on purpose
    run=(srun --quiet --quit-on-interrupt --input=none --job-name="canopy-$section"
         --nodes=1 --ntasks=1 --cpus-per-task="$cpus" --mem="$mem" --time="$limit"
         ${CANOPY_SRUN_FLAGS:-} "${run[@]}") ;;
  *) echo "stage.sh: error: unknown --launch '$launch' (local or slurm)" >&2; exit 2 ;;
esac

# progress: "N/M " once the stage is finished, and "  ~T left" (scripts/progress.sh
# keeps the state: N and M, the estimated seconds done and known, the start). This stage's
# share of the estimate is its artifact's previous wall time, else the estimate of its kind.
# Every finished stage appends "<kind> <wall s> <cpu s>" to the history the estimates come from.
tool=$1
for word in "$@"; do
  case "$word" in */bin/*) tool=$word; break ;; esac
done
name=${artifact##*/}
kind="${tool##*/}:"
case "$artifact" in */cands/*) kind+="cand/" ;; esac
kind+=${name//[0-9]/#}
previous=""
[ -f "$timing" ] && read -r previous _ <"$timing" 2>/dev/null
# progress sets n_m ("N/M " or "") and left.
# (In bash alone, under the lock: no subshell and no awk per stage, only flock; cost.md §9.
# Seconds are handled as integer milliseconds: the state and the estimates hold three decimals,
# the .time files two, so the sums are exact and the state reads back as before.)
n_m="" left=""
# ms VAR TEXT: VAR = TEXT (a number of seconds, digits with an optional fraction) in whole
# milliseconds (further decimals dropped); status 1 when TEXT is no such number.
ms() {
  [[ $2 =~ ^([0-9]*)(\.([0-9]*))?$ ]] && [ -n "${BASH_REMATCH[1]}${BASH_REMATCH[3]}" ] || return 1
  local frac="${BASH_REMATCH[3]}000"
  printf -v "$1" '%d' $((10#${BASH_REMATCH[1]:-0} * 1000 + 10#${frac:0:3}))
}
progress() {
  # (the state is read only under the lock: another stage rewrites it in place)
  [ -n "${CANOPY_PROGRESS:-}" ] && [ -e "$CANOPY_PROGRESS" ] || return 0
  { exec 9>>"$CANOPY_PROGRESS.lock"; } 2>/dev/null && flock 9 2>/dev/null || { exec 9>&-; return 0; }
  local n m d e t0 rest x t="" all="" k v tool now elapsed left_ms text=""
  read -r n m d e t0 rest <"$CANOPY_PROGRESS" 2>/dev/null
  if ! [[ $n =~ ^[0-9]+$ && $m =~ ^[0-9]+$ ]] || [ -z "$t0" ] || ! ms d "$d" || ! ms e "$e"; then
    exec 9>&-
    return 0
  fi
  n=$((n + 1))
  # (the stages counted so far, one artifact a line: progress.sh drop finds the stages of a
  # stopped sub-make that ran and were counted)
  echo "$artifact" >>"$CANOPY_PROGRESS-counted"
  # this stage's share: its artifact's previous wall time, else its kind's estimate, its
  # tool's, every stage's, else 1 s
  if [[ $previous =~ ^[0-9]+([.][0-9]*)?$ ]]; then
    ms x "$previous"
  else
    tool=${kind%%:*}
    x=-1
    while read -r k v _; do
      if [ "$k" = "$kind" ]; then ms x "$v" || x=-1
      elif [ "$k" = "$tool" ]; then t=$v
      elif [ "$k" = "*" ]; then all=$v; fi
    done 2>/dev/null <"$CANOPY_PROGRESS-est"
    if [ "$x" -lt 0 ]; then ms x "$t" || ms x "$all" || x=1000; fi
  fi
  d=$((d + x))
  [ "$m" -ge "$n" ] || m=$n
  [ "$e" -ge "$d" ] || e=$d
  printf '%d %d %d.%03d %d.%03d %s\n' "$n" "$m" $((d / 1000)) $((d % 1000)) $((e / 1000)) $((e % 1000)) "$t0" \
    >"$CANOPY_PROGRESS"
  exec 9>&-
  # (shown once 1% of the estimated work is done: before, the pace is mostly noise)
  if [ "$d" -gt 0 ] && [ "$n" -lt "$m" ] && [ $((100 * d)) -ge "$e" ] && ms now "$EPOCHREALTIME" && ms t0 "$t0"; then
    elapsed=$((now - t0))
    if [ "$elapsed" -ge 0 ]; then
      left_ms=$((elapsed * (e - d) / d))
      if [ "$left_ms" -lt 90000 ]; then text="~$(((left_ms + 500) / 1000)) s left"
      elif [ "$left_ms" -lt 5400000 ]; then text="~$(((left_ms + 30000) / 60000)) min left"
      else printf -v text '~%d h %02d min left' $((left_ms / 3600000)) $(((left_ms % 3600000 + 30000) / 60000)); fi
    fi
  fi
  [ -z "$text" ] || left="  $text"
  n_m="$n/$m "
}
# A time box or Ctrl-C (SIGTERM, SIGINT) during the run: ARTIFACT.time goes (GNU time had
# opened it, or written a "terminated by signal" report), the stage is not counted, and the
# script ends by the same signal, as make expects.
stopped() { trap - "$1"; rm -f "$timing"; kill -s "$1" $$; }
trap 'stopped TERM' TERM
trap 'stopped INT' INT
# (emptied first, so a launch that never ran GNU time is told apart from the previous run's times)
: >"$timing"
if "${run[@]}" 2>"$log"; then
  rc=0
else
  rc=$?
fi
# From here to the end SIGTERM and SIGINT are ignored (by the few commands below too): a time
# box or Ctrl-C that stops make now leaves the stage either counted (its artifact in
# $CANOPY_PROGRESS-counted) or, stopped before this line, uncounted and without its .time,
# which is how progress.sh drop tells the two apart (mk/real.mk), and never half-written
# progress state.
trap '' TERM INT
# GNU time's first line says how the tool ended when it did not exit 0.
how=""
[ -s "$timing" ] && read -r how <"$timing"
if [ $rc -eq 0 ] && [ -s "$timing" ] && [ "${how#Command}" = "$how" ]; then
  read -r secs kib user sys <"$timing"
  # user + system: GNU time prints both with two decimals; summed in hundredths
  cs=0
  [[ "${user:-} ${sys:-}" =~ ^[0-9]+\.[0-9]{2}\ [0-9]+\.[0-9]{2}$ ]] && cs=$((10#${user/./} + 10#${sys/./}))
  printf -v cpu '%d.%02d' $((cs / 100)) $((cs % 100))
  [ -z "${CANOPY_PROGRESS:-}" ] || echo "$kind $secs $cpu" >>"$CANOPY_PROGRESS-history"
  progress
  printf 'done  %s%-58s %7.2f s %7.2f cpu %6d MB%s\n' "$n_m" "$artifact" "$secs" "$cpu" "$((kib / 1024))" "$left"
  exit 0
fi
rm -f "$timing"
[ $rc -ne 0 ] || rc=1
status=""
case "$how" in
  "Command exited with non-zero status "*) status=${how##* } ;;
esac
# The tool's own failure: a status from 1 to 125. 126 and 127 are "cannot execute" and "not
# found" (from time or a shell), 128 and more a signal passed on by a wrapper.
tool_failed=0
[ -n "$status" ] && [ "$status" -le 125 ] && tool_failed=1
if [ $tool_failed -eq 1 ]; then
  why="exit $status"
elif [ -n "$status" ] && [ "$status" -le 127 ]; then
  why="exit $status, the command could not run"
elif [ -n "$status" ]; then
  why="exit $status, a signal"
elif [ -n "$how" ]; then
  why="${how#Command }"   # "terminated by signal 9"
else
  why="exit $rc; the tool did not finish"
fi
progress
printf 'FAIL  %s%-58s (%s); last lines of %s:\n' "$n_m" "$artifact" "$why" "$log"
tail -n 5 "$log" | sed 's/^/      /'
if [ $record -eq 1 ]; then
  if [ $tool_failed -eq 1 ]; then
    : >"$artifact" && echo "      recorded as a failed trial (empty $artifact)"
    exit 0
  fi
  echo "      not recorded as a failed trial: the tool did not exit by itself"
fi
exit "$rc"
