#!/usr/bin/env bash
# local-cluster.sh start DIR | stop DIR: a single-node Slurm cluster on this machine, all of
# its state inside DIR (for tests and measurements; not a production setup).
#
#   start  writes DIR/munge.key, DIR/slurm.conf, starts munged, slurmctld -D and slurmd -D in
#          the background, records their pids in DIR/pids and waits until the node is idle.
#          Prints the line to eval: export SLURM_CONF=DIR/slurm.conf
#   stop   signals the recorded pids (TERM, then KILL after 5 s) and waits for them.
#
# Needs root (slurmd launches jobs as the submitting user, which needs root; SlurmUser=root)
# and Debian's munge, slurmctld, slurmd and slurm-client (scripts/install-deps.sh installs
# them). No systemd, cgroups or accounting: proctrack/linuxproc, task/none. Two clusters
# started at once do not collide: each has its own DIR and its own two free TCP ports
# (random, checked against /proc/net/tcp).
set -euo pipefail
cmd=${1:-}; dir=${2:-}
usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ -n "$cmd" ] && [ -n "$dir" ] || usage
err() { echo "local-cluster: error: $*" >&2; exit 1; }

stop() {
  [ -f "$dir/pids" ] || return 0
  local pids alive i
  pids=$(cat "$dir/pids")
  # shellcheck disable=SC2086
  kill -TERM $pids 2>/dev/null || true
  for i in $(seq 50); do
    alive=""
    for p in $pids; do kill -0 "$p" 2>/dev/null && alive="$alive $p"; done
    [ -z "$alive" ] && break
    sleep 0.1
  done
  # shellcheck disable=SC2086
  [ -n "$alive" ] && kill -KILL $alive 2>/dev/null || true
  rm -f "$dir/pids"
}

# A TCP port nobody uses (from /proc/net/tcp{,6}; iproute2 may be absent), above the ports
# slurm uses by default.
free_port() {
  local p used
  used=$(awk 'FNR > 1 { split($2, a, ":"); print a[2] }' /proc/net/tcp /proc/net/tcp6 2>/dev/null |
         while read -r hex; do echo $((16#$hex)); done | sort -u)
  while :; do
    p=$((20000 + RANDOM % 30000))
    echo "$used" | grep -qx "$p" || { echo "$p"; return; }
  done
}

start() {
  [ "$(id -u)" -eq 0 ] || err "must run as root (slurmd starts jobs as the submitting user)"
  for b in munged mungekey slurmctld slurmd srun sinfo; do
    command -v "$b" >/dev/null || [ -x "/usr/sbin/$b" ] ||
      err "$b not found; run scripts/install-deps.sh (Debian packages munge slurmctld slurmd slurm-client)"
  done
  export PATH="$PATH:/usr/sbin"
  mkdir -p "$dir" && dir=$(cd "$dir" && pwd)
  [ -f "$dir/pids" ] && err "$dir already has a running cluster ($dir/pids)"
  mkdir -p "$dir/munge" "$dir/run" "$dir/ctld" "$dir/spool" "$dir/log"
  # munged insists that every client can reach its socket: search (x) rights for all on the
  # directories above it. Only added, never taken away (the parent may be /tmp or a home).
  chmod 711 "$dir"
  chmod a+x "$(dirname "$dir")" 2>/dev/null || true
  chmod 755 "$dir/run"
  chmod 700 "$dir/munge"
  mungekey --create --keyfile="$dir/munge/munge.key" --force
  chmod 400 "$dir/munge/munge.key"
  local host cport dport node
  host=$(hostname -s)
  cport=$(free_port); dport=$(free_port)
  while [ "$dport" = "$cport" ]; do dport=$(free_port); done
  node=$(slurmd -C | head -n 1)   # NodeName=<host> CPUs=... RealMemory=...
  : >"$dir/plugstack.conf"
  cat >"$dir/slurm.conf" <<EOF
ClusterName=canopy-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$cport
SlurmdPort=$dport
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/run/munge.socket
StateSaveLocation=$dir/ctld
SlurmdSpoolDir=$dir/spool/slurmd-%n
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
PlugStackConfig=$dir/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
KillWait=5
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  : >"$dir/pids"
  munged -F --socket="$dir/run/munge.socket" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/munged.seed" >"$dir/log/munged.out" 2>&1 &
  echo $! >>"$dir/pids"
  local i
  for i in $(seq 50); do [ -S "$dir/run/munge.socket" ] && break; sleep 0.1; done
  [ -S "$dir/run/munge.socket" ] || { stop; err "munged did not start: $(tail -n 3 "$dir/log/munged.log" "$dir/log/munged.out" 2>/dev/null)"; }
  slurmctld -D -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
  echo $! >>"$dir/pids"
  slurmd -D -f "$SLURM_CONF" >"$dir/log/slurmd.out" 2>&1 &
  echo $! >>"$dir/pids"
  local state=""
  for i in $(seq 100); do
    state=$(sinfo -h -o %t 2>/dev/null || true)
    [ "$state" = "idle" ] && break
    sleep 0.1
  done
  [ "$state" = "idle" ] || {
    stop
    err "the node did not become idle (state '$state'); logs in $dir/log: $(tail -n 3 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" 2>/dev/null)"
  }
  echo "export SLURM_CONF=$SLURM_CONF"
}

case $cmd in
  start) start ;;
  stop) stop ;;
  *) usage ;;
esac
