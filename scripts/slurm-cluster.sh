#!/usr/bin/env bash
# A private one-node Slurm cluster in a scratch directory, for tests and for trying the
# examples/slurm scripts on one machine (Debian's slurmctld, slurmd, slurm-client, munge).
#
#   scripts/slurm-cluster.sh start DIR   # prints: export SLURM_CONF=DIR/slurm.conf
#   scripts/slurm-cluster.sh stop DIR    # cancels its jobs, stops its daemons
#
# start runs its own munged (key, socket, pid and log under DIR/munge), slurmctld and slurmd
# (state, spool, pid and log files under DIR), without cgroups or accounting, and waits until
# the node is idle. stop cancels the cluster's jobs and stops the three daemons by the pids
# in their pid files (never by name), then waits for them to exit. Needs root (slurmd starts
# jobs as their user). SLURMCTLD_PORT and SLURMD_PORT (default 6817, 6818) choose the ports,
# so two clusters can run side by side.
set -euo pipefail

usage() {
    echo "usage: $0 start|stop DIR" >&2
    exit 2
}
[ $# -eq 2 ] || usage
cmd=$1
dir=$2
log() { echo "slurm-cluster: $*" >&2; }

# Prints the pid in pid file $1 if that process is alive and its command is $2.
live_pid() {
    local pid
    [ -f "$1" ] || return 1
    pid=$( { tr -dc "0-9" <"$1"; } 2>/dev/null) || return 1
    [ -n "$pid" ] || return 1
    alive "$pid" "$2" || return 1
    echo "$pid"
}

# Whether process $1 is alive (a zombie is not: without an init system nobody may reap it)
# and its command is $2.
alive() {
    [ "$(cat "/proc/$1/comm" 2>/dev/null)" = "$2" ] &&
        ! grep -q '^State:[[:space:]]*Z' "/proc/$1/status" 2>/dev/null
}

# Stops the daemon whose pid file is $1 and command $2: TERM, then KILL after 10 s; returns
# once it has exited (daemons remove their pid file before they are done).
stop_daemon() {
    local pid i
    pid=$(live_pid "$1" "$2") || return 0
    kill -TERM "$pid" 2>/dev/null || return 0
    for i in $(seq 100); do
        alive "$pid" "$2" || return 0
        sleep 0.1
    done
    log "$2 (pid $pid) ignored TERM for 10 s; killing it"
    kill -KILL "$pid" 2>/dev/null || true
    for i in $(seq 50); do
        alive "$pid" "$2" || return 0
        sleep 0.1
    done
    log "$2 (pid $pid) is still there"
    return 1
}

start() {
    if [ "$(id -u)" -ne 0 ]; then
        log "needs root: slurmd starts jobs as their user"
        exit 1
    fi
    local b
    for b in munged mungekey slurmctld slurmd sinfo; do
        if ! command -v "$b" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$b" ]; then
            log "$b not found (apt-get install slurmctld slurmd slurm-client munge)"
            exit 1
        fi
    done
    export PATH="$PATH:/usr/sbin"
    umask 022
    mkdir -p "$dir"
    dir=$(cd "$dir" && pwd)
    mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
    # munge clients (every job's slurmstepd included) must reach the socket.
    chmod 755 "$dir" "$dir/munge"
    local conf="$dir/slurm.conf" host ncpu
    host=$(hostname -s)
    ncpu=$(nproc)
    [ -f "$dir/munge/munge.key" ] || mungekey -c -k "$dir/munge/munge.key"
    munged --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
        --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" \
        --seed-file="$dir/munge/munge.seed"
    cat >"$conf" <<EOF
# Written by scripts/slurm-cluster.sh: a private one-node cluster in $dir.
ClusterName=gpuphoton
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=${SLURMCTLD_PORT:-6817}
SlurmdPort=${SLURMD_PORT:-6818}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
# Without these a job waits about 3 s for each scheduling round.
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
# Finished jobs stay visible to scontrol for 10 minutes.
MinJobAge=600
# Slurm's default grace between SIGTERM and SIGKILL: a cancelled render finishes its pass in
# flight and writes it in that time.
KillWait=30
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$ncpu State=UNKNOWN
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
    export SLURM_CONF="$conf"
    slurmctld -f "$conf"
    slurmd -f "$conf"
    local i state=""
    for i in $(seq 300); do
        state=$(sinfo -h -o %T 2>/dev/null || true)
        if [ "$state" = "idle" ]; then
            log "up in $dir (node $host, $ncpu CPUs)"
            echo "export SLURM_CONF=$conf"
            return 0
        fi
        sleep 0.1
    done
    log "the node is not idle after 30 s (state '$state'); logs in $dir/log"
    exit 1
}

stop() {
    [ -d "$dir" ] || return 0
    export PATH="$PATH:/usr/sbin"
    export SLURM_CONF="$dir/slurm.conf"
    local i
    if live_pid "$dir/run/slurmctld.pid" slurmctld >/dev/null; then
        # Only this cluster's jobs: SLURM_CONF names it.
        scancel --full --quiet --user="$(id -un)" 2>/dev/null || true
        for i in $(seq 100); do
            [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
            sleep 0.1
        done
    fi
    local rc=0
    stop_daemon "$dir/run/slurmd.pid" slurmd || rc=1
    stop_daemon "$dir/run/slurmctld.pid" slurmctld || rc=1
    stop_daemon "$dir/run/munged.pid" munged || rc=1
    log "stopped ($dir)"
    return "$rc"
}

case "$cmd" in
start) start ;;
stop) stop ;;
*) usage ;;
esac
