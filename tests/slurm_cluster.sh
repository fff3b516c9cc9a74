#!/usr/bin/env bash
# A one-node Slurm cluster on this machine for tests (docs/platform_notes.md): munge (started only
# if it is not running), slurmctld and slurmd from a slurm.conf in DIR, on free ports so that it
# cannot meet another cluster here. Needs root, as the daemons do.
#   tests/slurm_cluster.sh start DIR   -> prints SLURM_CONF=DIR/slurm.conf once the node is idle
#   tests/slurm_cluster.sh stop DIR    -> scontrol shutdown; stops munged if start started it
set -euo pipefail
cmd=$1 dir=$(realpath -m "$2")
host=$(hostname -s)

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("",0)); print(s.getsockname()[1])'; }

if [ "$cmd" = start ]; then
  mkdir -p "$dir/state" "$dir/spool"
  # munge works when a credential round-trips (a dead munged can linger as a zombie here).
  if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    [ -f /etc/munge/munge.key ] || mungekey -c
    mkdir -p /run/munge && chown munge:munge /run/munge
    su -s /bin/sh munge -c "/usr/sbin/munged --force"
    touch "$dir/started-munged"
    for _ in $(seq 20); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.25; done
  fi
  cat > "$dir/slurm.conf" <<CONF
ClusterName=wavecamtest
SlurmctldHost=$host
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$(nproc) RealMemory=2000 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -f "$SLURM_CONF"
  slurmd -f "$SLURM_CONF"
  for _ in $(seq 60); do
    if sinfo -h -o %T 2>/dev/null | grep -q idle; then echo "SLURM_CONF=$SLURM_CONF"; exit 0; fi
    sleep 0.5
  done
  echo "slurm_cluster.sh: the node did not come up; see $dir/slurmctld.log and $dir/slurmd.log" >&2
  exit 1
elif [ "$cmd" = stop ]; then
  export SLURM_CONF=$dir/slurm.conf
  # alive = exists and is not a zombie (nothing reaps orphans on some machines)
  alive() { [ -r "/proc/$1/stat" ] && ! awk '{exit $3 == "Z" ? 0 : 1}' "/proc/$1/stat"; }
  timeout 20 scontrol shutdown >/dev/null 2>&1 || true
  for f in slurmctld.pid slurmd.pid; do
    [ -f "$dir/$f" ] || continue
    pid=$(cat "$dir/$f")
    for _ in $(seq 40); do alive "$pid" || break; sleep 0.25; done
    if alive "$pid"; then kill "$pid" 2>/dev/null || true; fi  # ours, by its pid file
  done
  if [ -f "$dir/started-munged" ] && [ -f /run/munge/munged.pid ]; then
    pid=$(cat /run/munge/munged.pid)
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 40); do alive "$pid" || break; sleep 0.25; done
  fi
else
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi
