#!/usr/bin/env bash
# Start (or stop) a one-node Slurm on this machine, for trying perclod's
# sbatch array template without a cluster. Meant for a throw-away test box or
# container: it runs as root, needs no systemd, and starts the three daemons
# by hand.
#
#   scripts/slurm/start-local-slurm.sh          install if missing, configure, start, wait for the node
#   scripts/slurm/start-local-slurm.sh --stop   stop slurmd, slurmctld and munged
#
# Safe to run again: installed packages, an existing munge key and running
# daemons are left alone. It writes /etc/slurm/slurm.conf only when there is
# none or when the one there was written by this script (first line below), so
# a real cluster's configuration is never overwritten.
#
# What it sets up:
#   - munge (Slurm's authentication) with a key made here if there is none;
#   - one node named after this host with all its CPUs and most of its memory,
#     in one partition "local" (the default);
#   - no cgroups (proctrack/linuxproc, task/affinity) and no accounting database:
#     finished jobs are kept in slurmctld's memory for an hour (MinJobAge), so
#     `scontrol show job` still shows each array task's exit code after it
#     ends, and every finished job is also logged one line each to
#     /var/log/slurm/jobcomp.log (jobcomp/filetxt).
set -euo pipefail

MARKER="# Written by perclod scripts/slurm/start-local-slurm.sh"
CONF=/etc/slurm/slurm.conf
STATE=/var/lib/slurm            # slurmctld state and slurmd spool
LOGS=/var/log/slurm
RUN=/run/slurm                  # pid files
HOST=$(hostname -s)

log() { echo "start-local-slurm: $*" >&2; }
die() { log "$*"; exit 1; }

# True when the pid in file $1 is a running process.
alive() { [[ -s $1 ]] && kill -0 "$(cat "$1")" 2>/dev/null; }

# Send TERM to the daemon whose pid is in $2 and wait for it to exit.
stop_daemon() {
    local name=$1 pidfile=$2 pid
    if ! alive "$pidfile"; then log "$name not running"; rm -f "$pidfile"; return; fi
    pid=$(cat "$pidfile")
    kill "$pid"
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    if kill -0 "$pid" 2>/dev/null; then die "$name (pid $pid) did not stop"; fi
    rm -f "$pidfile"
    log "stopped $name (pid $pid)"
}

MUNGE_PID=/run/munge/munged.pid

if [[ ${1:-} == --stop ]]; then
    # Reverse order of starting: the node daemon, the controller, then munge.
    stop_daemon slurmd "$RUN/slurmd.pid"
    stop_daemon slurmctld "$RUN/slurmctld.pid"
    stop_daemon munged "$MUNGE_PID"
    exit 0
elif [[ $# -gt 0 ]]; then
    die "usage: $0 [--stop]"
fi

[[ $(id -u) == 0 ]] || die "run as root (it installs packages and starts daemons)"

# --- 1. Packages -------------------------------------------------------------
# slurm-wlm pulls in slurmctld, slurmd, the client commands and munge. Their
# postinst scripts may try to start services; without systemd that fails
# harmlessly or does nothing, and we start the daemons ourselves below.
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
        || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurm-wlm and munge"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi

# --- 2. Munge ----------------------------------------------------------------
# Every Slurm message is signed with munge; one key is all a single node needs
# (on a cluster every node shares the same key).
install -d -o munge -g munge -m 0700 /etc/munge /var/lib/munge /var/log/munge
install -d -o munge -g munge -m 0755 /run/munge
if [[ ! -s /etc/munge/munge.key ]]; then
    log "creating /etc/munge/munge.key"
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
fi
chown munge:munge /etc/munge/munge.key
chmod 0400 /etc/munge/munge.key
if alive "$MUNGE_PID"; then
    log "munged already running"
else
    log "starting munged"
    runuser -u munge -- /usr/sbin/munged
fi
munge -n | unmunge >/dev/null || die "munge does not work (see /var/log/munge/munged.log)"

# --- 3. slurm.conf -----------------------------------------------------------
# CPUs: everything this machine has. RealMemory: 90% of physical memory, in
# MiB; slurmd drains a node whose configured memory is more than it finds, so
# stay below the real figure.
cpus=$(nproc)
mem_mib=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)

if [[ -e $CONF ]] && ! head -1 "$CONF" | grep -qxF "$MARKER"; then
    log "$CONF exists and was not written by this script: using it as it is"
else
    install -d /etc/slurm
    cat >"$CONF.new" <<EOF
$MARKER
# A single-node test cluster: controller and compute node are this host.
ClusterName=perclod-local
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge

# Where the daemons keep state, pid files and logs.
StateSaveLocation=$STATE/slurmctld
SlurmdSpoolDir=$STATE/slurmd
SlurmctldPidFile=$RUN/slurmctld.pid
SlurmdPidFile=$RUN/slurmd.pid
SlurmctldLogFile=$LOGS/slurmctld.log
SlurmdLogFile=$LOGS/slurmd.log

# No cgroups: track job processes through /proc. task/affinity pins each
# task to the CPUs it was given (sched_setaffinity, no cgroups needed), so a
# program that sizes its thread pool from its affinity mask, as oneTBB and so
# perclod do, uses --cpus-per-task threads instead of every core of the node.
# task/none also works but lets concurrent tasks oversubscribe the cores.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
MpiDefault=none
# No mail server here: job mail (--mail-type) goes nowhere.
MailProg=/bin/true

# Schedule cores and memory, so --cpus-per-task and --mem decide how many
# array tasks run at once.
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
# A job that asks for no memory gets its CPUs' share, not the whole node
# (which would run such array tasks one at a time).
DefMemPerCPU=$((mem_mib / cpus))

# No accounting database. Finished jobs stay visible to scontrol for an hour
# and are logged to a text file.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$LOGS/jobcomp.log
MinJobAge=3600

# A node that was down comes back by itself once slurmd registers again.
ReturnToService=2
SlurmdTimeout=300

NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mib State=UNKNOWN
PartitionName=local Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
    if [[ -e $CONF ]] && cmp -s "$CONF" "$CONF.new"; then
        rm "$CONF.new"
    else
        mv "$CONF.new" "$CONF"
        log "wrote $CONF ($HOST: $cpus CPUs, $mem_mib MiB)"
        # Running daemons must read the new file; some settings (plugins)
        # are only read at start, so restart them rather than reconfigure.
        stop_daemon slurmd "$RUN/slurmd.pid"
        stop_daemon slurmctld "$RUN/slurmctld.pid"
    fi
fi

# --- 4. Slurm daemons --------------------------------------------------------
install -d -m 0755 "$STATE/slurmctld" "$STATE/slurmd" "$LOGS" "$RUN"
if alive "$RUN/slurmctld.pid"; then
    log "slurmctld already running"
else
    log "starting slurmctld"
    slurmctld        # daemonizes; writes $RUN/slurmctld.pid
fi
if alive "$RUN/slurmd.pid"; then
    log "slurmd already running"
else
    log "starting slurmd"
    slurmd
fi

# --- 5. Wait for the node ----------------------------------------------------
# The node reports "unknown" until slurmd registers, then "idle" (or "mixed"/
# "allocated" if jobs already run). A node left "down" or "drained" by an
# earlier run is resumed once.
resumed=no
for _ in $(seq 60); do
    state=$(sinfo -h -N -n "$HOST" -o %T 2>/dev/null | head -1 || true)
    case $state in
        idle|mixed|allocated|completing)
            log "node $HOST is $state"
            sinfo
            exit 0 ;;
        down*|drain*|fail*)
            if [[ $resumed == no ]]; then
                log "node $HOST is $state: resuming it"
                scontrol update NodeName="$HOST" State=RESUME || true
                resumed=yes
            fi ;;
    esac
    sleep 1
done
sinfo -N -l || true
die "node $HOST did not become idle in 60 s (last state: ${state:-none}); see $LOGS/slurmctld.log and $LOGS/slurmd.log"
