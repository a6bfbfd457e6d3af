#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for trying the job-array scripts and for CI:
# munged, slurmctld and slurmd run as root in the foreground of this script's children, with a
# generated slurm.conf whose state, spool, logs and pid files live in DIR.
#
#   scripts/slurm/local-cluster.sh start DIR   # prints `export SLURM_CONF=DIR/slurm.conf`
#   scripts/slurm/local-cluster.sh stop DIR    # stops the daemons by the process ids in DIR/pids
#
# Needs root and Debian's slurm-wlm and munge (apt-get install slurm-wlm munge); the munge key is
# the package's /etc/munge/munge.key, created here if missing. Ports: SSS_SLURM_PORT (slurmctld,
# default 6817) and the next.
set -euo pipefail

cmd=${1:-}; dir=${2:-}
if [[ -z "$cmd" || -z "$dir" ]]; then
    echo "usage: $0 start|stop DIR" >&2; exit 2
fi

stop() {
    if [[ -f "$dir/pids" ]]; then
        while read -r pid; do kill "$pid" 2>/dev/null || true; done < "$dir/pids"
        for _ in $(seq 50); do
            alive=0
            while read -r pid; do kill -0 "$pid" 2>/dev/null && alive=1; done < "$dir/pids"
            [[ $alive == 0 ]] && break
            sleep 0.1
        done
        while read -r pid; do kill -9 "$pid" 2>/dev/null || true; done < "$dir/pids"
        rm -f "$dir/pids"
    fi
}

if [[ "$cmd" == stop ]]; then stop; exit 0; fi
if [[ "$cmd" != start ]]; then echo "usage: $0 start|stop DIR" >&2; exit 2; fi

for tool in munged slurmctld slurmd sbatch; do
    command -v "$tool" >/dev/null || { echo "$tool not found: apt-get install slurm-wlm munge" >&2; exit 3; }
done
[[ $(id -u) == 0 ]] || { echo "the local cluster's daemons run as root" >&2; exit 3; }
# Debian's munge package creates the key; create one where it did not.
if [[ ! -r /etc/munge/munge.key ]]; then
    mkdir -p /etc/munge
    mungekey --create --keyfile=/etc/munge/munge.key
    chown munge:munge /etc/munge/munge.key 2>/dev/null || true
    chmod 0600 /etc/munge/munge.key
fi

dir=$(mkdir -p "$dir" && cd "$dir" && pwd)
mkdir -p "$dir/state" "$dir/spool" /run/munge
port=${SSS_SLURM_PORT:-6817}
host=$(hostname -s)
cat > "$dir/slurm.conf" <<CONF
ClusterName=sss-local
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
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
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"

: > "$dir/pids"
if ! pgrep -x munged >/dev/null; then
    munged --foreground --force --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" \
        --seed-file="$dir/munged.seed" > /dev/null 2>&1 &
    echo $! >> "$dir/pids"
    for _ in $(seq 50); do [[ -S /run/munge/munge.socket.2 ]] && break; sleep 0.1; done
fi
slurmctld -D -i -f "$SLURM_CONF" > "$dir/slurmctld.out" 2>&1 &
echo $! >> "$dir/pids"
slurmd -D -f "$SLURM_CONF" > "$dir/slurmd.out" 2>&1 &
echo $! >> "$dir/pids"

# Ready when the node takes jobs.
for _ in $(seq 150); do
    if sinfo -h -o %t 2>/dev/null | grep -Eq '^(idle|mix|alloc)'; then
        echo "export SLURM_CONF=$SLURM_CONF"
        exit 0
    fi
    sleep 0.2
done
echo "the local cluster did not come up within 30 s; logs in $dir" >&2
stop
exit 4
