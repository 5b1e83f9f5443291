#!/bin/bash
# A single-node Slurm cluster of its own in a folder, for the tests of
# `rigel batch --slurm`: munge with its own key and socket, slurmctld and
# slurmd on free ports, a generated slurm.conf; nothing of the machine's
# own Slurm or munge is used or changed.
#
#   slurm_cluster.sh start DIR   # prints the slurm.conf to point SLURM_CONF at, once the node is idle
#   slurm_cluster.sh stop DIR    # stops what start started
#
# Exit 3 when it cannot run here (Slurm or munge not installed, not root:
# slurmd runs as root; or the daemons do not come up on this machine, as in
# a chroot without what they need: their logs are printed).
set -euo pipefail

cmd=${1:?start or stop}
dir=$(realpath -m "${2:?a folder}")

stop() {
  for name in slurmd slurmctld munged; do
    local pidfile="$dir/$name.pid"
    [ -f "$pidfile" ] || continue
    local pid
    pid=$(cat "$pidfile")
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 1 100); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -9 "$pid" 2>/dev/null || true
    rm -f "$pidfile"
  done
}

case "$cmd" in
  stop)
    stop
    ;;
  start)
    for p in mungekey munged slurmctld slurmd sbatch squeue sinfo; do
      if ! command -v "$p" >/dev/null 2>&1; then
        echo "slurm_cluster: $p is not installed (Debian: apt-get install slurm-wlm munge)" >&2
        exit 3
      fi
    done
    if [ "$(id -u)" != 0 ]; then
      echo "slurm_cluster: slurmd runs as root; run the tests as root for the Slurm path" >&2
      exit 3
    fi
    mkdir -p "$dir/state" "$dir/spool"
    cannot() {
      echo "slurm_cluster: $1" >&2
      tail -n 5 "$dir"/*.log >&2 2>/dev/null || true
      stop
      exit 3
    }
    mungekey -c -f -k "$dir/munge.key" || cannot "mungekey failed"
    munged --force --key-file="$dir/munge.key" --socket="$dir/munge.socket" --pid-file="$dir/munged.pid" \
      --log-file="$dir/munged.log" --seed-file="$dir/munged.seed" || cannot "munged did not start"
    read -r ctld_port slurmd_port < <(python3 -c '
import socket
ports = []
socks = []
for _ in range(2):
    s = socket.socket(); s.bind(("127.0.0.1", 0)); socks.append(s); ports.append(s.getsockname()[1])
print(*ports)')
    host=$(hostname)
    cpus=$(nproc)
    # batch_sched_delay=0: a finished task's CPU goes to the next task at
    # the next scheduling pass (every second) rather than after Slurm's
    # default 3 s batching delay, which made a 50-task array wait 2.5 s
    # per pair of tasks (71 s for 50 bakes of 0.3 s; 26 s without it).
    cat > "$dir/slurm.conf" <<CONF
ClusterName=rigeltest
SlurmctldHost=$host
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$dir/munge.socket
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=batch Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF="$dir/slurm.conf"
    slurmctld -f "$SLURM_CONF" || cannot "slurmctld did not start"
    slurmd -f "$SLURM_CONF" || cannot "slurmd did not start"
    for _ in $(seq 1 300); do
      if [ "$(sinfo -h -o %T 2>/dev/null | head -1)" = idle ]; then
        echo "$SLURM_CONF"
        exit 0
      fi
      sleep 0.1
    done
    cannot "the node did not become idle in 30 s"
    ;;
  *)
    echo "slurm_cluster: start DIR or stop DIR" >&2
    exit 2
    ;;
esac
