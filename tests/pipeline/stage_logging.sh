#!/usr/bin/env bash
# stagerun (tools/stagerun), the runner of every experiment stage, with fake tools: the tool's
# stderr (INFO lines) is kept in <artifact>.log, its times in <artifact>.time (GNU time's
# "%e %M %U %S", two decimals); the progress line shows N/M; --record-failure records the tool's
# own failure (exit 1) as an empty artifact and status 0, but a tool killed by a signal
# (SIGKILL, as the OOM killer sends) or a status >= 126 (126: not executable, 127: not found)
# fails with no artifact and no .time. SIGTERM or SIGINT to the runner alone stops the tool;
# glibc's huge pages are asked for unless HUGEPAGES=0 or the user's GLIBC_TUNABLES name them;
# scripts/stage.sh only execs the runner.
# Then through make, on a fake tree of the graph: no stage runs its tool with -q; an ablation
# stage killed by SIGKILL fails make, leaves no artifact and stays out of date; the same stage
# exiting 1 is recorded; a full run numbers its stages 1/M..M/M with M = the stages planned.
set -u
src=$1 bin=${2:-$1/build/bin}
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
stage="$bin/stagerun"
[ -x "$stage" ] || fail "$stage is not built"
cd "$tmp" || exit 1

# A fake tool: logs an INFO line, then does what FAKE_MODE says, else writes every output.
mkdir -p "$tmp/bin"
cat >"$tmp/bin/fake" <<'EOF'
#!/usr/bin/env bash
echo "$(basename "$0"): info: read 3 points" >&2
case "${FAKE_MODE:-ok}" in
  fail) echo "$(basename "$0"): error: no voxel passed the tests" >&2; exit 1 ;;
  kill) kill -KILL $$ ;;
  137) exit 137 ;;
  env) echo "GLIBC_TUNABLES=${GLIBC_TUNABLES-unset}" >&2 ;;
  lines) for i in 1 2 3 4 5 6 7; do echo "line $i" >&2; done; exit 3 ;;
  sleep) trap 'echo "fake: stopped by TERM" >&2; exit 143' TERM; sleep 30 & wait; exit 0 ;;
esac
while [ $# -gt 0 ]; do
  case "$1" in
    -o|--colored|--picture) echo "made by $(basename "$0")" >"$2"; shift ;;
    --results) mkdir -p "$2"; for f in report.md cases.csv scores.csv times.csv; do echo x >"$2/$f"; done; shift ;;
  esac
  shift
done
EOF
chmod +x "$tmp/bin/fake"

# Success: the INFO line in the log, wall seconds, KiB, user and system CPU seconds in .time,
# a "done" line with wall and CPU.
out=$("$stage" a/x -- "$tmp/bin/fake" -o a/x) || fail "a successful stage failed: $out"
[ "$(cat a/x)" = "made by fake" ] || fail "the artifact was not made"
grep -q "^fake: info: read 3 points" a/x.log || fail "the tool's INFO line is not in the log: $(cat a/x.log)"
grep -Eqx '[0-9]+\.[0-9]{2} [0-9]+ [0-9]+\.[0-9]{2} [0-9]+\.[0-9]{2}' a/x.time && [ "$(wc -l <a/x.time)" = 1 ] ||
  fail "a/x.time is not GNU time's '%e %M %U %S' (one line, two decimals): $(cat a/x.time)"
# (the peak memory of a tool that holds 60 MB, as GNU time reports it: KiB)
"$stage" a/mem -- python3 -c 'b = bytearray(60 << 20); b[::4096] = b"x" * len(b[::4096])' >/dev/null ||
  fail "the 60 MB stage failed"
awk '{ exit !($2 >= 60 * 1024 && $2 < 200 * 1024) }' a/mem.time || fail "a/mem.time's peak is not ≈ 60 MB in KiB: $(cat a/mem.time)"
echo "$out" | grep -Eq "^done  a/x +[0-9.]+ s +[0-9.]+ cpu +[0-9]+ MB$" || fail "no done line with wall and CPU: $out"
# A stage burning CPU: user CPU seconds recorded (GNU time's %U), not only wall.
"$stage" a/cpu -- bash -c 'i=0; while [ $i -lt 300000 ]; do i=$((i + 1)); done; : >a/cpu' >/dev/null ||
  fail "the CPU-burning stage failed"
awk '{ exit !($3 >= 0.2 && $3 <= $1 + 0.05) }' a/cpu.time || fail "a/cpu.time has no user CPU near its wall time: $(cat a/cpu.time)"

# The tool's own failure, recorded: status 0, an empty artifact, the log named.
out=$(FAKE_MODE=fail "$stage" --record-failure a/f -- "$tmp/bin/fake" -o a/f) || fail "a recorded failure did not exit 0"
[ -f a/f ] && [ ! -s a/f ] || fail "a recorded failure left no empty artifact"
# One lower-case line (an expected outcome, not make's FAIL), with the log's last line.
[ "$(echo "$out" | wc -l)" -eq 1 ] || fail "a recorded failure printed more than one line: $out"
echo "$out" | grep -Eq "^fail  a/f +\(exit 1; recorded as a failed trial\): .*error: no voxel" ||
  fail "the recorded failure's line does not give the status and the log's last line: $out"
! echo "$out" | grep -q "FAIL" || fail "a recorded failure reads FAIL: $out"
grep -q "error: no voxel" a/f.log || fail "the error is not in the log"
# Without --record-failure the same failure is passed on.
FAKE_MODE=fail "$stage" a/g -- "$tmp/bin/fake" -o a/g >/dev/null && fail "a failure without --record-failure exited 0"
[ ! -e a/g ] || fail "a failed stage left an artifact"

# Killed by a signal (the OOM killer's SIGKILL): never recorded; non-zero status, no artifact.
rc=0; out=$(FAKE_MODE=kill "$stage" --record-failure a/k -- "$tmp/bin/fake" -o a/k) || rc=$?
[ $rc -eq 137 ] || fail "a tool killed by SIGKILL gave status $rc, not 137: $out"
[ ! -e a/k ] || fail "a tool killed by SIGKILL was recorded as a failed trial (a/k exists)"
echo "$out" | grep -q "terminated by signal 9.*last lines of a/k.log" || fail "the kill is not reported: $out"
echo "$out" | grep -q "not recorded" || fail "the output does not say the kill was not recorded: $out"
# A wrapper passing a signal on (status 128+n) is not recorded either; nor a tool not found.
rc=0; FAKE_MODE=137 "$stage" --record-failure a/w -- "$tmp/bin/fake" -o a/w >/dev/null || rc=$?
[ $rc -eq 137 ] && [ ! -e a/w ] || fail "status 137 was recorded (rc $rc)"
rc=0; out=$("$stage" --record-failure a/n -- "$tmp/bin/no-such-tool" -o a/n) || rc=$?
[ $rc -eq 127 ] && [ ! -e a/n ] || fail "a missing tool was recorded as a failed trial (rc $rc)"
echo "$out" | grep -q "^FAIL  a/n .*(exit 127, the command could not run)" || fail "a missing tool is not reported: $out"
grep -q "no-such-tool: No such file or directory" a/n.log || fail "a/n.log does not say the tool was not found: $(cat a/n.log)"
[ ! -e a/n.time ] || fail "a missing tool left a/n.time"
printf 'not a program\n' >"$tmp/bin/noexec"
rc=0; out=$("$stage" --record-failure a/e -- "$tmp/bin/noexec") || rc=$?
[ $rc -eq 126 ] && [ ! -e a/e ] && [ ! -e a/e.time ] || fail "a tool that cannot be executed gave status $rc, or left a/e: $out"
grep -q "Permission denied" a/e.log || fail "a/e.log does not say why the tool could not run: $(cat a/e.log)"
# A failing stage: the last 5 lines of its log, indented; no .time left (not even an earlier one).
echo "1.00 100 0.50 0.10" >a/l.time
rc=0; out=$(FAKE_MODE=lines "$stage" a/l -- "$tmp/bin/fake") || rc=$?
[ $rc -eq 3 ] && [ ! -e a/l.time ] || fail "a failing stage gave status $rc or left its .time"
[ "$(echo "$out" | tail -n +2 | tr '\n' '|')" = "      line 3|      line 4|      line 5|      line 6|      line 7|" ] ||
  fail "the failure does not show the log's last 5 lines: $out"
# Usage errors exit 2 (no artifact, no command, an unknown option); stage.sh only execs the runner.
for args in "" "a/u" "a/u --" "--bogus a/u -- true" "--launch cloud a/u -- true"; do
  rc=0; read -ra words <<<"$args"; "$stage" "${words[@]}" >/dev/null 2>&1 || rc=$?
  [ $rc -eq 2 ] || fail "'stagerun $args' exited $rc, not 2"
done
[ ! -e a/u.log ] || fail "a usage error ran a stage"
out=$(CANOPY_BIN="$bin" "$src/scripts/stage.sh" a/s -- "$tmp/bin/fake" -o a/s) && [ -s a/s ] && [ -s a/s.time ] ||
  fail "scripts/stage.sh does not run the stage through stagerun: $out"
# Huge pages: asked for by default, not with CANOPY_HUGEPAGES=0, the user's own tunables kept
# and their hugetlb setting left as it is.
hp() { FAKE_MODE=env "$stage" a/hp -- "$tmp/bin/fake" >/dev/null && sed -n 's/^GLIBC_TUNABLES=//p' a/hp.log; }
[ "$(hp)" = "glibc.malloc.hugetlb=1" ] || fail "no huge pages by default: $(hp)"
[ "$(CANOPY_HUGEPAGES=0 hp)" = unset ] || fail "CANOPY_HUGEPAGES=0 still sets GLIBC_TUNABLES: $(CANOPY_HUGEPAGES=0 hp)"
[ "$(GLIBC_TUNABLES=glibc.malloc.arena_max=2 hp)" = "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1" ] ||
  fail "the user's GLIBC_TUNABLES are not kept: $(GLIBC_TUNABLES=glibc.malloc.arena_max=2 hp)"
[ "$(GLIBC_TUNABLES=glibc.malloc.hugetlb=0 hp)" = "glibc.malloc.hugetlb=0" ] ||
  fail "the user's hugetlb setting does not win: $(GLIBC_TUNABLES=glibc.malloc.hugetlb=0 hp)"
# The Slurm job's side, stagerun --measure FILE: GNU time -o FILE, its status line included.
rc=0; "$stage" --measure a/ms.time -- bash -c 'exit 3' || rc=$?
[ $rc -eq 3 ] && [ "$(sed -n 1p a/ms.time)" = "Command exited with non-zero status 3" ] &&
  sed -n 2p a/ms.time | grep -Eqx '[0-9]+\.[0-9]{2} [0-9]+ [0-9]+\.[0-9]{2} [0-9]+\.[0-9]{2}' ||
  fail "stagerun --measure: status $rc, a/ms.time: $(cat a/ms.time)"
rc=0; "$stage" --measure a/ms.time -- bash -c 'kill -KILL $$' || rc=$?
[ $rc -eq 137 ] && [ "$(sed -n 1p a/ms.time)" = "Command terminated by signal 9" ] ||
  fail "stagerun --measure of a killed command: status $rc, a/ms.time: $(cat a/ms.time)"

# N/M: a plan of three stages (a dry run's lines), two at once; each N from 1 to 3 exactly
# once; time left shown before the last.
progress="$src/scripts/progress.sh"
printf '%s\n' "built build/bin/fake" "build/bin/stagerun p/1 -- $tmp/bin/fake -o p/1" \
  "scripts/stage.sh --record-failure p/2 -- $tmp/bin/fake -o p/2" "mkdir -p p" \
  "scripts/stage.sh p/3 -- xvfb-run -a -s \"-screen 0\" $tmp/bin/fake -o p/3" |
  "$progress" plan "$tmp/progress" >"$tmp/plan.out" 2>"$tmp/plan.err" || fail "progress.sh plan failed"
[ "$(cat "$tmp/plan.out")" = 3 ] || fail "progress.sh plan counted $(cat "$tmp/plan.out") stages, not 3"
grep -qx "built build/bin/fake" "$tmp/plan.err" || fail "progress.sh plan does not pass 'built' lines on"
export CANOPY_PROGRESS="$tmp/progress"
{ "$stage" p/1 -- "$tmp/bin/fake" -o p/1 & "$stage" p/2 -- "$tmp/bin/fake" -o p/2 & wait
  "$stage" p/3 -- "$tmp/bin/fake" -o p/3; } >"$tmp/p.out"
[ "$(sed -n 's/^done  \([0-9]*\/3\) .*/\1/p' "$tmp/p.out" | sort | tr '\n' ' ')" = "1/3 2/3 3/3 " ] ||
  fail "progress is not 1/3 2/3 3/3: $(cat "$tmp/p.out")"
grep -q '^done  [12]/3 .* MB  ~[0-9]* s left$' "$tmp/p.out" || fail "no time left before the last stage: $(cat "$tmp/p.out")"
grep -q '^done  3/3 .* MB$' "$tmp/p.out" || fail "the last stage shows time left: $(cat "$tmp/p.out")"
[ "$(cut -d' ' -f1 "$tmp/progress-history" | sort -u)" = "fake:#" ] ||
  fail "the history does not hold the stages' kind fake:#: $(cat "$tmp/progress-history")"
[ "$(wc -l <"$tmp/progress-history")" -eq 3 ] || fail "the history does not hold 3 stages"

# The estimates come from the history: a plan of one kind seen at 2 s and one never seen.
printf 'slow:#.pcd 2.00 1.90\nslow:#.pcd 2.00 1.90\nquick:#.pcd 0.10 0.10\n' >"$tmp/progress-history"
printf '%s\n' "scripts/stage.sh q/1.pcd -- $tmp/bin/slow" "scripts/stage.sh q/2.pcd -- /x/bin/other" |
  "$progress" plan "$tmp/progress" >/dev/null
read -r n m d e t0 <"$tmp/progress"
[ "$n $m $d" = "0 2 0" ] || fail "the plan's state is '$n $m $d', not '0 2 0'"
# slow: 2 s; other (never seen): the mean of the history, 1.367 s
awk -v e="$e" 'BEGIN { exit !(e > 3.36 && e < 3.37) }' || fail "the plan's estimate is $e s, not 2 + 1.367"

# Candidates revealed by detect join M (progress.sh extend): 2 candidates x 2 stages; one of
# them has a .time from an earlier run, which is its estimate.
printf '%s\n' "scripts/stage.sh t/detect -- $tmp/bin/fake" "scripts/stage.sh t/cands.mk -- $tmp/bin/fake" \
  "scripts/stage.sh t/cands/old1/samples.pcd -- $tmp/bin/fitvox" "scripts/stage.sh t/detections.json -- $tmp/bin/fake" |
  "$progress" plan "$tmp/progress" >"$tmp/plan.out"
[ "$(cat "$tmp/plan.out")" = 3 ] || fail "a remade plan's old candidate was counted: $(cat "$tmp/plan.out") stages, not 3"
mkdir -p t/cands/c0001 && echo "5.00 100 4.00 0.50" >t/cands/c0001/samples.pcd.time
printf '# plan\nK_CANDS := c0001 c0002\nK_TRANSFORM_c0001 := 1\n' >t/cands.mk
read -r _ _ _ e0 _ <"$tmp/progress"
"$progress" extend "$tmp/progress" t/cands.mk fitvox:cand/samples.pcd cocone:cand/mesh.ply || fail "progress.sh extend failed"
read -r n m d e _ <"$tmp/progress"
[ "$n/$m" = "0/7" ] || fail "after extend the count is $n/$m, not 0/7"
awk -v a="$e0" -v b="$e" 'BEGIN { exit !(b - a > 5) }' || fail "extend did not add c0001's earlier 5 s ($e0 -> $e)"
# A candidate the plan keeps at the class level runs classify only (mk/scenes.mk): two
# model-level candidates x 2 kinds + one class-level candidate x 1 = 5 more stages.
cp "$tmp/progress" "$tmp/progress2" && cp "$tmp/progress-est" "$tmp/progress2-est"
printf '# plan\nK_CANDS := c0001 c0002 c0003\nK_LEVEL_c0001 := model\nK_LEVEL_c0002 := model\nK_LEVEL_c0003 := class\n' >t/cands2.mk
"$progress" extend "$tmp/progress2" t/cands2.mk classify:cand/class.json fitvox:cand/samples.pcd ||
  fail "progress.sh extend failed on a plan with levels"
read -r _ m2 _ _ _ <"$tmp/progress2"
[ "$m2" = $((m + 5)) ] || fail "a class-level candidate counted as the model chain: M $m -> $m2, not $((m + 5))"
for a in t/detect t/cands.mk t/cands/c0001/samples.pcd t/cands/c0001/mesh.ply t/cands/c0002/samples.pcd \
         t/cands/c0002/mesh.ply t/detections.json t/extra; do
  "$stage" "$a" -- "$tmp/bin/fake" -o "$a"
done >"$tmp/t.out"
[ "$(sed -n 's/^done  \([0-9]*\/[0-9]*\) .*/\1/p' "$tmp/t.out" | tr '\n' ' ')" = "1/7 2/7 3/7 4/7 5/7 6/7 7/7 8/8 " ] ||
  fail "N passes M or M is not extended: $(sed -n 's/^done  \([0-9]*\/[0-9]*\) .*/\1/p' "$tmp/t.out" | tr '\n' ' ')"
unset CANOPY_PROGRESS

# A sub-make the dry run only prints (a real tile's, mk/real.mk) joins M when it starts
# (progress.sh add: a dry run of it; a stage after a test's "||" counts; MARK is touched) and
# what it left undone when stopped early leaves M again (drop), except a stage that ran since
# MARK and failed (counted by stage.sh: listed in STATE-counted after MARK's count); a stage the
# time box killed (not listed) is dropped, and so is one listed before MARK (an earlier run).
printf '%s\n' "scripts/stage.sh s/a -- $tmp/bin/fake" | "$progress" plan "$tmp/progress3" >/dev/null
echo r/cands.mk >>"$tmp/progress3-counted"
sub=("scripts/stage.sh r/detect -- $tmp/bin/detect" "scripts/stage.sh r/cands.mk -- $tmp/bin/collect"
     "[ ! -f r/detections.json ] || scripts/stage.sh r/score.json -- $tmp/bin/score")
[ "$(printf '%s\n' "${sub[@]}" | "$progress" add "$tmp/progress3" "$tmp/progress3-mark")" = 3 ] ||
  fail "progress.sh add did not count the sub-make's 3 stages"
read -r n m _ <"$tmp/progress3"
[ "$n/$m" = "0/4" ] && [ -f "$tmp/progress3-mark" ] || fail "after add the count is $n/$m, not 0/4, or no mark"
echo r/detect >>"$tmp/progress3-counted"
printf '%s\n' "${sub[@]}" | "$progress" drop "$tmp/progress3" "$tmp/progress3-mark" >/dev/null
read -r n m _ <"$tmp/progress3"
[ "$n/$m" = "0/2" ] || fail "after drop the count is $n/$m, not 0/2 (s/a and the failed r/detect)"

# Stopped during its run (a time box's SIGTERM to the process group): no .time left (not even
# the previous run's), no artifact, not counted, and the script ends by the signal.
printf '%s\n' "scripts/stage.sh s/t -- sleep" | "$progress" plan "$tmp/progress4" >/dev/null
mkdir -p s && echo "1.00 100 0.50 0.10" >s/t.time
CANOPY_PROGRESS="$tmp/progress4" setsid "$stage" s/t -- sleep 5 >/dev/null &
pid=$!
for _ in $(seq 50); do [ -s s/t.time ] || break; sleep 0.1; done
sleep 0.3
kill -TERM -- -"$pid"
rc=0; wait "$pid" || rc=$?
[ $rc -eq 143 ] || fail "a stage stopped by SIGTERM gave status $rc, not 143"
[ ! -e s/t.time ] && [ ! -e s/t ] || fail "a stopped stage left s/t.time or s/t"
[ ! -s "$tmp/progress4-counted" ] || fail "a stopped stage was counted: $(cat "$tmp/progress4-counted")"
read -r n _ <"$tmp/progress4"
[ "$n" = 0 ] || fail "a stopped stage was counted (N = $n)"
# SIGTERM to the runner alone (not its process group: `kill PID`) is passed on to the tool,
# which stops (its TERM trap logs it) long before its 30 s; then the same ending as above.
echo "1.00 100 0.50 0.10" >s/t.time
CANOPY_PROGRESS="$tmp/progress4" FAKE_MODE=sleep "$stage" s/t -- "$tmp/bin/fake" >/dev/null &
pid=$!
for _ in $(seq 50); do [ -s s/t.time ] || break; sleep 0.1; done
sleep 0.5
started=$SECONDS
kill -TERM "$pid"
rc=0; wait "$pid" || rc=$?
[ $rc -eq 143 ] && [ $((SECONDS - started)) -lt 10 ] || fail "the runner alone stopped by SIGTERM gave status $rc after $((SECONDS - started)) s"
grep -q "stopped by TERM" s/t.log || fail "SIGTERM was not passed on to the tool: $(cat s/t.log)"
[ ! -e s/t.time ] && [ ! -e s/t ] && [ ! -s "$tmp/progress4-counted" ] || fail "the stage stopped by SIGTERM left its .time or artifact, or was counted"
# SIGINT (Ctrl-C) likewise: status 130 (the runner ends by SIGINT). (A background job of this
# script ignores SIGINT from its start, so the runner is started with SIGINT at its default.)
python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execv(sys.argv[1], sys.argv[1:])' \
  "$stage" s/i -- sleep 30 >/dev/null &
pid=$!
for _ in $(seq 50); do [ -e s/i.time ] && break; sleep 0.1; done
sleep 0.5
kill -INT "$pid"
rc=0; wait "$pid" || rc=$?
[ $rc -eq 130 ] && [ ! -e s/i.time ] || fail "a stage stopped by SIGINT gave status $rc, or left s/i.time"

# ---- through make, on a fake tree: every tool is the fake, artifacts are fresh ------------
cd "$src" || exit 1
b="$tmp/build"
mkdir -p "$b/bin" "$b/stamps"
touch "$b/.deps-stamp" "$b/CMakeCache.txt"
newest=$(find common formats tools share CMakeLists.txt -type f -printf '%T@\n' | sort -n | tail -1)
now=$(( $(date +%s) > ${newest%.*} + 100 ? $(date +%s) : ${newest%.*} + 100 ))
for t in rangetrace addnoise fitvox cocone ncut gmatch verify areas report figures; do
  cp "$tmp/bin/fake" "$b/bin/$t"
  sha256sum <"$b/bin/$t" | cut -d' ' -f1 >"$b/stamps/$t.sha"
done
cp "$stage" "$b/bin/stagerun"
touch -d "@$((now - 90))" "$b/bin/"*
touch -d "@$((now - 80))" "$b/stamps/"*
mk=(make -f Makefile.experiments OBJECTS=sedan SCENES=unoccluded NOISES=0 ABLATIONS=fitvox-fixed-rms SCENE_EXPERIMENT=0 BASELINE=0 FAMILIES=0 REAL_TILES=0
    OUT="$tmp/out" RES="$tmp/res" BUILD="$b" CMAKE=true DISPLAY=:99 KEEP=1)
"${mk[@]}" -n all | grep "^$b/bin/stagerun " | grep -q -- ' -q ' &&
  fail "a stage still runs its tool with -q: $("${mk[@]}" -n all | grep "^$b/bin/stagerun " | grep -- ' -q ' | head -1)"

# A full run: stages numbered 1/M..M/M, M = the stages make -n plans.
m=$("${mk[@]}" -n all | grep -c "^$b/bin/stagerun ")
[ "$m" -gt 5 ] || fail "make -n all plans $m stages through $b/bin/stagerun"
"${mk[@]}" all -j2 >"$tmp/make.out" 2>&1 || fail "make all on the fake tree failed: $(tail -n 5 "$tmp/make.out")"
got=$(sed -n 's/^\(done\|FAIL\|fail\)  \([0-9]*\)\/\([0-9]*\) .*/\2 \3/p' "$tmp/make.out")
[ "$(echo "$got" | awk '{print $2}' | sort -u)" = "$m" ] || fail "M is not $m: $(head -n 3 "$tmp/make.out")"
[ "$(echo "$got" | awk '{print $1}' | sort -n | tr '\n' ' ')" = "$(seq "$m" | tr '\n' ' ')" ] ||
  fail "N does not run 1..$m once each: $(echo "$got" | awk '{print $1}' | sort -n | tr '\n' ' ')"
"${mk[@]}" -q all || fail "make -q all not clean after a full run"

# Without KEEP=1 the trial's scans (render and noisy scan) are deleted once the report is
# written; the tree stays up to date (they are .SECONDARY) and a second run runs nothing.
prune=("${mk[@]}" KEEP=0 OUT="$tmp/out2" RES="$tmp/res2")
"${prune[@]}" all -j2 >"$tmp/prune.out" 2>&1 || fail "make all KEEP=0 failed: $(tail -n 5 "$tmp/prune.out")"
for f in sedan/unoccluded/scan.pcd sedan/unoccluded/noise-0/scan.pcd; do
  [ ! -e "$tmp/out2/$f" ] || fail "KEEP=0 left $f"
done
[ -s "$tmp/out2/sedan/unoccluded/noise-0/samples.pcd" ] || fail "KEEP=0 deleted the samples"
"${prune[@]}" -q all || fail "make -q all not clean after the scans were deleted"
"${prune[@]}" all >"$tmp/prune2.out" 2>&1 || fail "a second make all KEEP=0 failed"
if grep -q '^done\|^FAIL' "$tmp/prune2.out"; then fail "a second make all re-ran stages: $(head -3 "$tmp/prune2.out")"; fi

# The ablation's fitvox killed by SIGKILL: make fails, names the log, leaves no artifact, and
# the trial stays out of date (a later make re-runs it).
abl="$tmp/out/ablation/fitvox-fixed-rms/sedan/unoccluded/noise-0/samples.pcd"
rm "$abl"
if FAKE_MODE=kill "${mk[@]}" "$abl" >"$tmp/kill.out" 2>&1; then fail "make succeeded although the stage was killed"; fi
grep -q "^FAIL  .*samples.pcd .*terminated by signal 9.*last lines of $abl.log" "$tmp/kill.out" ||
  fail "the killed stage is not reported with its log: $(cat "$tmp/kill.out")"
[ ! -e "$abl" ] || fail "a killed ablation stage left $abl (recorded as a failed trial)"
"${mk[@]}" -q "$abl" && fail "after a kill, make -q calls the trial up to date"
# The same stage failing by itself (exit 1) is a result: recorded, make succeeds, up to date.
FAKE_MODE=fail "${mk[@]}" "$abl" >"$tmp/fail.out" 2>&1 || fail "a recorded failure failed make: $(cat "$tmp/fail.out")"
[ -f "$abl" ] && [ ! -s "$abl" ] || fail "the failed trial was not recorded as an empty artifact"
"${mk[@]}" -q "$abl" || fail "a recorded failed trial is not up to date"
echo "ok: stage logging"
