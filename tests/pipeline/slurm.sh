#!/usr/bin/env bash
# The experiment graph on a real Slurm: a single-node cluster (munged, slurmctld, slurmd from
# Debian's packages; scripts/slurm/local-cluster.sh) started in a temp dir runs a slice of the
# experiment with LAUNCH=slurm; its artifacts must equal a local run's byte for byte; a stage
# that fails as a Slurm job fails make with its log named; SIGINT to make's process group (what
# Ctrl-C sends) cancels the running job. The daemons are stopped by their recorded pids, also
# when the test fails.
#
# Needs root and the slurm packages (scripts/install-deps.sh installs them; CI runs as root).
# Without them this test FAILS, it does not skip: the project's test command installs them,
# so their absence is a broken setup, not an optional feature (docs/decisions/cluster.md).
set -u
src=$1 bin=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || fail "the Slurm test needs root (slurmd starts jobs as the submitting user); run the tests as root, as CI does"
for b in srun sinfo squeue slurmctld slurmd munged mungekey; do
  command -v "$b" >/dev/null || [ -x "/usr/sbin/$b" ] ||
    fail "$b not installed: run scripts/install-deps.sh (Debian packages munge slurmctld slurmd slurm-client)"
done
for t in rangetrace addnoise fitvox cocone ncut gmatch report figures stagerun; do
  [ -x "$bin/$t" ] || fail "$bin/$t not built"
done
# A Slurm environment around the test (ctest run inside a job) must not leak into our cluster.
while read -r v; do unset "$v"; done < <(compgen -e | grep '^SLURM_')

tmp=$(mktemp -d)
cluster="$tmp/cluster"
cleanup() {
  local rc=$?
  "$src/scripts/slurm/local-cluster.sh" stop "$cluster" || rc=1
  if [ $rc -ne 0 ] && [ -d "$cluster/log" ]; then
    echo "--- last lines of the cluster's logs:" >&2
    tail -n 5 "$cluster"/log/*.log >&2 2>/dev/null
  fi
  rm -rf "$tmp"
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM
# Should this script be killed outright (SIGKILL, e.g. a test timeout), a watchdog outside its
# process group stops the daemons once the script is gone.
setsid bash -c 'while kill -0 "$1" 2>/dev/null; do sleep 1; done; "$2" stop "$3" >/dev/null 2>&1; rm -rf "$4"' \
  watchdog $$ "$src/scripts/slurm/local-cluster.sh" "$cluster" "$tmp" </dev/null >/dev/null 2>&1 &

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }   # secs START END
started=$(now)
conf=$("$src/scripts/slurm/local-cluster.sh" start "$cluster") || fail "the single-node cluster did not start"
eval "$conf"
[ "$SLURM_CONF" = "$cluster/slurm.conf" ] || fail "local-cluster.sh printed '$conf'"
echo "cluster up in $(secs "$started" "$(now)") s ($(sinfo -h -o '%N %c CPUs %t'))"

cd "$src" || exit 1
# The tools are the suite's build (-o: never rebuilt by this test); stamps go to the temp dir.
keep=(); for t in rangetrace addnoise fitvox cocone ncut gmatch report figures stagerun; do keep+=(-o "$bin/$t"); done
slice=(OBJECTS=sedan SCENES=unoccluded "NOISES=0 8" SCENE_EXPERIMENT=0 BASELINE=0 FAMILIES=0 REAL_TILES=0 BIN="$bin" BUILD="$tmp/build" "${keep[@]}")
mk() { make -f Makefile.experiments "${slice[@]}" "$@"; }

# Both runs write to the same paths (tools record their input paths in the artifacts'
# provenance), then move aside.
t0=$(now)
mk all -j2 OUT="$tmp/run/out" RES="$tmp/run/res" >"$tmp/local.log" 2>&1 ||
  fail "the local run failed: $(tail -n 15 "$tmp/local.log")"
mv "$tmp/run" "$tmp/local"
t1=$(now)
mk all -j2 LAUNCH=slurm OUT="$tmp/run/out" RES="$tmp/run/res" >"$tmp/slurm.log" 2>&1 ||
  fail "the Slurm run failed: $(tail -n 15 "$tmp/slurm.log")"
mv "$tmp/run" "$tmp/slurm"
t2=$(now)
echo "local $(secs "$t0" "$t1") s, slurm $(secs "$t1" "$t2") s (-j2)"

# Every artifact, byte for byte. Not compared: logs and .time files, times.csv, the progress
# state (.progress*), the wall-time columns of cases.csv (from addnoise_s on) and the "Time per
# stage" section of report.md, which hold wall times; POV-Ray's pictures, which carry their
# render date.
artifacts() {
  (cd "$1" && find . -type f ! -name '*.log' ! -name '*.time' ! -name 'times.csv' ! -name '.progress*' \
     ! -path './pictures/*' | sort)
}
comparable() {  # comparable FILE: the part of FILE that must not depend on the run
  case "$1" in
    */report.md) sed '/^## Time per stage/,$d' "$1" ;;
    */cases.csv) cut -d, -f1-21 "$1" ;;
    *) cat "$1" ;;
  esac
}
for d in out res; do
  a=$(artifacts "$tmp/local/$d"); b=$(artifacts "$tmp/slurm/$d")
  [ "$a" = "$b" ] || fail "$d/: the two runs made different files: $(diff <(echo "$a") <(echo "$b") | head -5)"
  n=0
  while read -r f; do
    cmp -s <(comparable "$tmp/local/$d/$f") <(comparable "$tmp/slurm/$d/$f") ||
      fail "$d/$f differs between the local and the Slurm run"
    n=$((n + 1))
  done <<<"$a"
  echo "$d/: $n artifacts identical"
done
[ -s "$tmp/slurm/out/sedan/unoccluded/noise-8/match.json" ] || fail "the slice made no match.json"
grep -q '^fitvox: ' "$tmp/slurm/out/sedan/unoccluded/noise-8/samples.pcd.log" ||
  fail "samples.pcd.log does not hold fitvox's INFO lines (written by the job)"
grep -q '^done  [0-9]*/[0-9]* ' "$tmp/slurm.log" || fail "no N/M progress in the Slurm run's lines"
# Each stage was a job: the controller's log holds one allocation per stage of the plan.
stages=$(grep -c '^\(done\|FAIL\|fail\)  [0-9]*/[0-9]* ' "$tmp/slurm.log")
jobs=$(grep -c 'sched: _slurm_rpc_allocate_resources' "$cluster/log/slurmctld.log")
[ "$jobs" -ge "$stages" ] || fail "$stages stages but only $jobs Slurm allocations"
echo "$stages stages ran as $jobs Slurm jobs"

# A stage that fails as a Slurm job fails make and names its log; its artifact is not made.
mkdir -p "$tmp/bad"
cp -p share/params/*.ini "$tmp/bad/"
sed -i "s/^max-rms = .*/max-rms = -3mm/" "$tmp/bad/fitvox.ini"
grep -q "^max-rms = -3mm" "$tmp/bad/fitvox.ini" || fail "could not make a bad fitvox.ini"
target="$tmp/slurm/out/sedan/unoccluded/noise-0/samples.pcd"
rm -f "$target"
if mk LAUNCH=slurm OUT="$tmp/slurm/out" RES="$tmp/slurm/res" P="$tmp/bad" "$target" >"$tmp/fail.log" 2>&1; then
  fail "make succeeded although fitvox failed: $(tail -n 5 "$tmp/fail.log")"
fi
grep -q "^FAIL  .*samples.pcd .*last lines of $target.log" "$tmp/fail.log" ||
  fail "the failure does not name the stage's log: $(head -n 5 "$tmp/fail.log")"
grep -q "fitvox: error: .*max-rms" "$target.log" || fail "the log does not hold fitvox's error: $(cat "$target.log")"
grep -q "Error " "$tmp/fail.log" || fail "make did not report the failed recipe"
[ ! -e "$target" ] || fail "a failed job left $target"
echo "a failing job fails make: $(grep '^FAIL' "$tmp/fail.log" | cut -c1-60)..."

# Ctrl-C: SIGINT to make's process group while a stage runs as a job cancels the job at once.
setsid make -f Makefile.experiments "${slice[@]}" LAUNCH=slurm OUT="$tmp/intr/out" RES="$tmp/intr/res" \
  "$tmp/intr/out/sedan/unoccluded/scan.pcd" >"$tmp/intr.log" 2>&1 &
pg=$!
# The signal goes once the tool itself runs inside the job, not merely once the job is R: a
# cancel that slurmctld sends while slurmstepd is still launching the step's task can be lost
# (seen once in CI: the step was logged CANCELLED 0.15 s after its launch request, its task
# ran to the end all the same, srun passed on its 0 and make, which ignores SIGINT as any
# background job of a script does, exited 0). An interactive Ctrl-C also reaches make itself,
# which dies of it whatever srun returns.
# tool_runs EXE TEXT: a process runs EXE with TEXT in one of its arguments (read from /proc
# with bash's own mapfile: no process per entry, so the poll stays quick under load; procps
# may be absent).
tool_runs() {
  local f args
  for f in /proc/[0-9]*/cmdline; do
    mapfile -d '' -t args 2>/dev/null <"$f" || continue
    [ "${args[0]:-}" = "$1" ] && [[ "${args[*]}" == *"$2"* ]] && return 0
  done
  return 1
}
running=""
for _ in $(seq 1200); do
  running=$(squeue -h -t R -o %i)
  [ -n "$running" ] && tool_runs "$bin/rangetrace" "$tmp/intr/" && break
  kill -0 "$pg" 2>/dev/null || break   # make ended first: the render was never seen running
  running=""
  sleep 0.05
done
[ -n "$running" ] || { kill -TERM -- -"$pg" 2>/dev/null; fail "the rendering job never ran: $(cat "$tmp/intr.log")"; }
kill -INT -- -"$pg"
t3=$(now)
wait "$pg" && fail "make exited 0 after SIGINT"
left=""
for _ in $(seq 100); do
  left=$(squeue -h -o '%i %t')
  [ -z "$left" ] && break
  sleep 0.05
done
[ -z "$left" ] || fail "jobs still in the queue after SIGINT: $left"
echo "SIGINT cancelled job $running; queue empty after $(secs "$t3" "$(now)") s"
[ ! -e "$tmp/intr/out/sedan/unoccluded/scan.pcd" ] || fail "an interrupted job left its artifact"
echo "ok: slurm"
