#!/usr/bin/env bash
# progress.sh: the experiment's "done N/M ... ~T left" count (Makefile.experiments, stagerun).
#
#   progress.sh plan STATE       stdin: a dry run of the goals (make -n). Counts its stages
#                                (stagerun lines) and estimates their wall seconds, then
#                                writes STATE ("N M D E T0": stages done, stages known, estimated
#                                seconds done, estimated seconds known, start time) and
#                                STATE-est (the estimate of each kind of stage). Prints M, and
#                                when the dry run failed a note on a second line (below).
#   progress.sh extend STATE PLAN KEY...
#                                detect has revealed a tile's candidates: PLAN is the candidate
#                                plan `collect --plan` just wrote (<key>_CANDS := c0001 ...), KEY
#                                the stages each candidate runs (tool:cand/<artifact name>, e.g.
#                                fitvox:cand/samples.pcd); adds them to M and E. A candidate
#                                the plan keeps at the class level (<key>_LEVEL_<id> := class)
#                                counts its classify:… stages only.
#   progress.sh add STATE MARK   stdin: a dry run of a sub-make about to run (a real tile's
#                                workflow, mk/real.mk): its stages join M and E, counted as plan
#                                counts them; MARK is written (the sub-make's start: the number
#                                of stages counted so far, the lines of STATE-counted). Prints the
#                                number added.
#   progress.sh drop STATE MARK  stdin: a dry run of the same sub-make after it stopped early (a
#                                real tile timed out or refused): the stages it still shows will
#                                not run in this make, so they leave M and E (never below N, D);
#                                except those that ran since MARK and were counted, failing
#                                (listed in STATE-counted after MARK's count: stagerun lists
#                                every stage it counts; one the time box killed is not listed).
#   progress.sh key ARTIFACT COMMAND...   prints the kind of a stage (see below).
#
# Known work only: a tile's candidates are not known before its detect has run, so the dry run
# cannot plan them; the plan step adds them (extend) and, so that none is counted twice, the
# dry run leaves out the candidate stages of every tile whose plan it shows being remade. A
# sub-make the dry run only prints (a real tile's, under a time box) is counted when it starts
# (add) and what it leaves undone is taken back (drop). N never passes M: stagerun raises M to
# N should a stage run that no plan counted. A stage line is one whose first command is the
# stage runner, .../stagerun (tools/stagerun; Makefile.experiments' $(STAGE)) or its wrapper
# scripts/stage.sh, also after a test (`[ ... ] || build/bin/stagerun ...`). A line
# "progress-plan-failed STATUS [LOG]" (Makefile.experiments: the dry run failed, its errors in
# LOG) gives the note "progress: the planning dry run ... failed ..." on plan's second output
# line, which Makefile.experiments prints on stderr once its own makefiles have been read: when
# they stop make first (a user's error such as `make tiles TILES=<no tiles>`, which the dry run
# met too), make's own message stands alone (until stop 67 the note came first).
#
# Estimates come from the stages' own history: a stage whose artifact has a .time file from an
# earlier run is estimated at that run's wall time; any other at the mean of its kind over the
# history file STATE-history (one "kind wall cpu" line per finished stage, appended by
# stagerun; recent runs weigh more), else of its tool, else of every stage, else 1 s. A kind is
# <tool>:<artifact name, each digit as #>, "cand/" before the name of a candidate's stage:
# fitvox:samples.pcd, rangetrace:scan.pcd, addnoise:scan.pcd, fitvox:cand/samples.pcd
# (stagerun computes the same kind: tools/stagerun/stagerun.cpp, stage_kind).
# Time left (stagerun) = elapsed * (E - D) / D: the estimates give the shares of the work, the
# run so far its pace (on however many cores and under whatever load).
set -euo pipefail

# The kind of a stage from its artifact and its command words (awk, shared by all modes).
kind_awk='
function kind(artifact, tool,    name, cand) {
  name = artifact; sub(/.*\//, "", name); gsub(/[0-9]/, "#", name)
  cand = index(artifact, "/cands/") ? "cand/" : ""
  sub(/.*\//, "", tool)
  return tool ":" cand name
}
# The tool of a command: its first word under a bin/ directory, else its first word.
function tool_of(first, last, words,    i) {
  for (i = first; i <= last; i++) if (index(words[i], "/bin/")) return words[i]
  return words[first]
}
# The estimates of STATE-history: kinds and tools as exponentially weighted means.
function read_history(file,    line, f, t) {
  while ((getline line < file) > 0) {
    if (split(line, f, " ") < 2 || f[2] !~ /^[0-9.]+$/) continue
    # (the value first: awk may create est[k] before it evaluates the right-hand side)
    v = (f[1] in est) ? 0.7 * est[f[1]] + 0.3 * f[2] : f[2]; est[f[1]] = v
    t = f[1]; sub(/:.*/, "", t)
    v = (t in est) ? 0.7 * est[t] + 0.3 * f[2] : f[2]; est[t] = v
    all += f[2]; n_all++
  }
  close(file)
  default_est = n_all ? all / n_all : 1
}
function estimate(k,    t) {
  if (k in est) return est[k]
  t = k; sub(/:.*/, "", t)
  if (t in est) return est[t]
  return default_est
}
# The wall seconds of an earlier run of the stage that makes artifact, or -1.
function earlier(artifact,    line, w) {
  line = ""
  if ((getline line < (artifact ".time")) > 0 && split(line, w, " ") >= 2 && w[1] ~ /^[0-9.]+$/) {
    close(artifact ".time"); return w[1]
  }
  close(artifact ".time")
  return -1
}
'

mode=${1:-}
case "$mode" in
  key)
    artifact=$2; shift 2
    printf '%s\n' "$@" | awk -v a="$artifact" "$kind_awk"'{ w[NR] = $0 } END { print kind(a, tool_of(1, NR, w)) }'
    ;;
  plan | add | drop)
    state=$2 mark=${3:-}
    # (add and drop change the state under the lock that stagerun and extend take)
    if [ "$mode" != plan ]; then
      [ -f "$state" ] || exit 0
      exec 9>>"$state.lock"
      flock 9
      if [ "$mode" = add ] && [ -n "$mark" ]; then
        counted=0
        [ ! -f "$state-counted" ] || counted=$(wc -l <"$state-counted")
        echo "$counted" >"$mark"
      fi
    fi
    awk -v mode="$mode" -v state="$state" -v mark="$mark" -v now="$(date +%s.%N)" "$kind_awk"'
      /^built / { print > "/dev/stderr"; next }
      /^progress-plan-failed / {
        failed = "progress: the planning dry run (make -n) failed with status " $2 "; the total counts only the stages it showed before that (" ($3 != "" ? "its errors: " $3 : "make -n shows why") ")"
        next
      }
      # .../stagerun (or scripts/stage.sh) [--launch slurm] [--record-failure] ARTIFACT --
      # COMMAND..., first in the line or after "||", "&&" or ";"
      {
        for (i = 1; i <= NF; i++) if ($i ~ /(^|\/)(stagerun|stage\.sh)$/ && (i == 1 || $(i - 1) ~ /^(\|\||&&|;)$/)) break
        if (i > NF) next
        i++
        while ($i == "--launch" || $i == "--record-failure") i += ($i == "--launch") ? 2 : 1
        artifact = $i
        if ($(i + 1) == "--") i++
        for (j = i + 1; j <= NF; j++) w[j] = $j
        n++; art[n] = artifact; k[n] = kind(artifact, tool_of(i + 1, NF, w))
        if (artifact ~ /\/cands\.mk$/) { d = artifact; sub(/\/cands\.mk$/, "", d); replanned[d] = 1 }
      }
      END {
        if (mode == "plan") read_history(state "-history")
        else {
          while ((getline line < (state "-est")) > 0) {
            split(line, f, " "); if (f[1] == "*") default_est = f[2]; else est[f[1]] = f[2]
          }
          if (default_est == "") default_est = 1
        }
        if (mode == "drop" && mark != "") {
          # the stages counted since MARK: the lines of STATE-counted after the count MARK holds
          skip = 0
          if ((getline line < mark) > 0 && line ~ /^[0-9]+$/) skip = line + 0
          close(mark)
          c = 0
          while ((getline line < (state "-counted")) > 0) if (++c > skip) counted[line] = 1
          close(state "-counted")
        }
        m = 0; e = 0
        for (i = 1; i <= n; i++) {
          d = art[i]
          if (sub(/\/cands\/[^\/]+\/[^\/]+$/, "", d) && (d in replanned)) continue
          if (mode == "drop" && mark != "" && (art[i] in counted)) continue
          s = earlier(art[i])
          e += s >= 0 ? s : estimate(k[i])
          m++
        }
        if (mode == "plan") {
          printf "0 %d 0 %.3f %s\n", m, e, now > state
          for (x in est) printf "%s %.3f\n", x, est[x] > (state "-est")
          printf "* %.3f\n", default_est > (state "-est")
          printf "" > (state "-counted")
        } else {
          if ((getline line < state) <= 0 || split(line, f, " ") < 5) exit
          close(state)
          sign = mode == "add" ? 1 : -1
          sm = f[2] + sign * m; se = f[4] + sign * e
          if (sm < f[1]) sm = f[1]
          if (se < f[3]) se = f[3]
          printf "%d %d %.3f %.3f %s\n", f[1], sm, f[3], se, f[5] > (state ".tmp")
          close(state ".tmp")
          system("mv -f \"" state ".tmp\" \"" state "\"")
        }
        print m
        if (failed != "") print failed
      }'
    ;;
  extend)
    state=$2 plan=$3; shift 3
    [ -f "$state" ] || exit 0
    # (bash reads the plan and one awk under the lock does the rest: this runs once per run of
    # a tile, ≈ 250 times in `all`, and every process costs ≈ 8 ms of CPU; cost.md §18)
    dir=.
    case "$plan" in */*) dir=${plan%/*} ;; esac
    # the candidates, and those the plan keeps at the class level (<key>_LEVEL_<id> := class),
    # which run classify only; the others every KEY
    cands="" classonly=""
    while IFS= read -r line || [ -n "$line" ]; do
      if [[ $line =~ ^[A-Za-z0-9_]*_CANDS\ :=(.*)$ ]]; then cands+=" ${BASH_REMATCH[1]}"
      elif [[ $line =~ ^[A-Za-z0-9_]*_LEVEL_([A-Za-z0-9]*)\ :=\ class$ ]]; then classonly+="${BASH_REMATCH[1]} "; fi
    done <"$plan"
    [ -n "${cands// /}" ] || exit 0
    {
      flock 9
      printf -v keys '%s\n' "$@"
      keys=${keys%$'\n'}
      awk -v state="$state" -v dir="$dir" -v cands="$cands" -v classonly="$classonly" -v keylist="$keys" "$kind_awk"'
        BEGIN {
          if ((getline line < state) <= 0 || split(line, st, " ") < 5) exit
          close(state)
          while ((getline line < (state "-est")) > 0) { split(line, f, " "); if (f[1] == "*") default_est = f[2]; else est[f[1]] = f[2] }
          nk = split(keylist, keys, "\n")
          nc = split(cands, c, " ")
          nco = split(classonly, co, " ")
          for (i = 1; i <= nco; i++) only[co[i]] = 1
          for (i = 1; i <= nc; i++) for (j = 1; j <= nk; j++) {
            if ((c[i] in only) && keys[j] !~ /^classify:/) continue
            name = keys[j]; sub(/^[^:]*:cand\//, "", name)
            s = earlier(dir "/cands/" c[i] "/" name)
            # (a kind writes each digit as #: classify:cand/class-ablation-#.json)
            k = keys[j]; gsub(/[0-9]/, "#", k)
            sum += s >= 0 ? s : estimate(k); cnt++
          }
          # (rewritten in place, under the lock, as stagerun does)
          printf "%d %d %.3f %.3f %s\n", st[1], st[2] + cnt, st[3], st[4] + sprintf("%.3f", sum), st[5] > state
        }'
    } 9>>"$state.lock"
    ;;
  *)
    echo "progress.sh: usage: progress.sh plan|add|drop STATE | extend STATE PLAN KEY... | key ARTIFACT COMMAND..." >&2
    exit 2
    ;;
esac
