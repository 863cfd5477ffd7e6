#!/usr/bin/env bash
# A throwaway single-node SLURM cluster on this machine, for tests/cluster (make test-cluster).
#
#   tests/cluster/slurm-up.sh start   # install (as root, from Debian) if needed, boot, wait for an idle node
#   tests/cluster/slurm-up.sh stop    # stop exactly the daemons `start` started, remove the sandbox
#   tests/cluster/slurm-up.sh env     # print the export line the clients need (SLURM_CONF)
#
# Everything lives in one sandbox directory ($THESIS_SLURM_DIR, default /tmp/thesis-slurm):
# its own slurm.conf, its own munge socket, state, spool, logs and pid files, so a system
# SLURM or munge on the machine is never touched. One node with this machine's cores and
# memory, one partition, no accounting daemon: the executor plugin asks for job states
# with `squeue` (profiles/slurm sets `slurm-status-command: squeue`), which sees finished
# jobs for MinJobAge seconds; the plugin itself falls back to `sacct` when MinJobAge is
# below three status intervals (120 s), and `sacct` without slurmdbd fails, so MinJobAge is
# kept at 300 s. The scheduler's record of every finished job is
# $DIR/jobcomp.log (jobcomp/filetxt), which tests/cluster reads. Memory is a consumable resource (CR_Core_Memory): a job that asks for
# no memory would take the whole node.
set -euo pipefail

DIR=${THESIS_SLURM_DIR:-/tmp/thesis-slurm}
CONF=$DIR/slurm.conf
SYSCONF=/etc/slurm/slurm.conf
HOST=$(hostname -s)

log() { echo "slurm-up: $*" >&2; }

install_packages() {
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null \
    && command -v sbatch >/dev/null && return 0
  if [ "$(id -u)" != 0 ]; then
    log "slurmctld/slurmd/munged missing and not root: install Debian's slurm-wlm and munge"
    exit 1
  fi
  log "installing slurm-wlm and munge from Debian"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
}

write_conf() {
  local cpus mem
  cpus=$(nproc)
  # leave 1 GiB of the machine to the daemons and snakemake itself
  mem=$(( $(awk '/MemTotal/ {print int($2 / 1024)}' /proc/meminfo) - 1024 ))
  mkdir -p "$DIR/state" "$DIR/spool"
  cat > "$CONF" <<CONF
# Written by tests/cluster/slurm-up.sh: a throwaway single-node cluster.
ClusterName=thesis
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$DIR/munge.socket
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
SlurmctldPort=6917
SlurmdPort=6918
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$DIR/jobcomp.log
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=300
KillWait=5
NodeName=$HOST CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=thesis Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
}

alive() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }

start() {
  install_packages
  if alive "$DIR/slurmctld.pid"; then log "already running in $DIR"; return 0; fi
  if [ -e "$SYSCONF" ] || [ -L "$SYSCONF" ]; then
    if [ "$(readlink "$SYSCONF" 2>/dev/null)" != "$CONF" ]; then
      log "$SYSCONF exists and is not this sandbox's: a SLURM of this machine's own; not starting"
      exit 1
    fi
  fi
  rm -rf "$DIR"; mkdir -p "$DIR"
  write_conf
  mkdir -p "$(dirname "$SYSCONF")"
  ln -sfn "$CONF" "$SYSCONF"
  local key=/etc/munge/munge.key
  [ -r "$key" ] || { log "no readable $key (create one with mungekey --create as root)"; exit 1; }
  munged --force --socket="$DIR/munge.socket" --pid-file="$DIR/munged.pid" \
    --log-file="$DIR/munged.log" --seed-file="$DIR/munged.seed" --key-file="$key"
  slurmctld -f "$CONF"
  slurmd -f "$CONF"
  export SLURM_CONF=$CONF
  for _ in $(seq 1 60); do
    state=$(sinfo -h -o %T 2>/dev/null || true)
    if [ "$state" = idle ]; then log "node $HOST idle ($DIR)"; return 0; fi
    sleep 1
  done
  log "the node did not become idle within 60 s (state: ${state:-none}); logs in $DIR"
  stop
  exit 1
}

stop() {
  local pf pid
  for d in slurmd slurmctld munged; do
    pf=$DIR/$d.pid
    if alive "$pf"; then
      pid=$(cat "$pf")
      kill "$pid"
      for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
      kill -0 "$pid" 2>/dev/null && kill -9 "$pid"
    fi
  done
  if [ "$(readlink "$SYSCONF" 2>/dev/null)" = "$CONF" ]; then rm -f "$SYSCONF"; fi
  rm -rf "$DIR"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  env) echo "export SLURM_CONF=$CONF" ;;
  *) echo "usage: $0 start|stop|env" >&2; exit 2 ;;
esac
