#!/usr/bin/env bash
# slurm_cluster.sh - start/stop a private single-node Slurm cluster on 127.0.0.1,
# for tests. Needs root and the Debian packages: slurmctld slurmd slurm-client munge.
#
#   slurm_cluster.sh start  DIR   # DIR: a fresh folder (created if missing)
#   slurm_cluster.sh stop   DIR   # idempotent; touches only daemons started for DIR
#   slurm_cluster.sh status DIR   # exit 0 if the node answers and is usable
#
# After a successful start:  . DIR/env.sh   (exports SLURM_CONF, TEST_SLURM_*)
#
# Exit codes: 0 ok
#             1 start (or stop) failed; reason and log tails on stderr,
#               everything that had been started is stopped again
#             2 usage error, or a cluster is already running in DIR
#             77 cannot run here: not root, or packages / munge user missing
#
# Tunables (environment):
#   SLURM_CLUSTER_START_TIMEOUT  seconds to wait for an idle node (default 30)
#   SLURM_CLUSTER_EXTRA_CONF     slurm.conf lines; each replaces the default
#                                line(s) with the same key (e.g. "MinJobAge=600")
#
# Layout: DIR holds slurm.conf, env.sh, state/, log/, pid/. Unix sockets and
# munge's files live in a short private folder /tmp/slurm-cluster.XXXXXX (DIR/run
# links to it) because (a) socket paths must stay under 108 bytes and test temp
# folders can be long, and (b) munged runs as user munge and must be able to
# reach its files, which it cannot under e.g. pytest's 0700 /tmp/pytest-of-root.

set -euo pipefail

readonly PROG=slurm_cluster
readonly PARTITION=test
readonly NODE=localhost
readonly RUN_PREFIX=/tmp/slurm-cluster.
# Minimal, fixed environment for the daemons: nothing from the caller leaks in.
# (The daemons themselves are found in the caller's PATH, like the clients.)
DAEMON_ENV=(env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8)

msg() { printf '%s: %s\n' "$PROG" "$*" >&2; }
usage() { msg "usage: $0 start|stop|status DIR"; exit 2; }

# --- helpers ---------------------------------------------------------------

# Print the pid stored in pidfile $1 if that process is alive and its command
# line contains $2 (our config / socket path): guards against pid reuse and
# against ever touching daemons this script did not start.
our_pid() {
    local pid
    [[ -r $1 ]] || return 1
    read -r pid <"$1" 2>/dev/null || return 1
    [[ $pid =~ ^[0-9]+$ ]] || return 1
    tr '\0' ' ' 2>/dev/null <"/proc/$pid/cmdline" | grep -qF -- "$2" || return 1
    printf '%s\n' "$pid"
}

# Is process $1 alive? A zombie counts as gone: our daemons are orphans, and
# the container's init may take a second or more to reap them.
alive() {
    local stat
    read -r stat 2>/dev/null <"/proc/$1/stat" || return 1
    stat=${stat##*) }  # the field after "(comm) " is the state
    [[ ${stat:0:1} != Z ]]
}

# Wait up to $2 seconds (0.1 s steps) for process $1 to end.
wait_gone() {
    local i
    for ((i = 0; i < $2 * 10; i++)); do
        alive "$1" || return 0
        sleep 0.1
    done
    ! alive "$1"
}

# TERM, bounded wait, then KILL; returns non-zero if it still exists.
terminate() {
    local pid=$1 name=$2
    wait_gone "$pid" 0 && return 0
    kill -TERM "$pid" 2>/dev/null || true
    wait_gone "$pid" 5 && return 0
    msg "$name (pid $pid) ignored SIGTERM, sending SIGKILL"
    kill -KILL "$pid" 2>/dev/null || true
    wait_gone "$pid" 5
}

# A TCP port in 20000-32767 (below Linux's ephemeral range, so outgoing
# connections do not take it) that no IPv4/IPv6 socket uses right now.
# Ports given as arguments are excluded too.
free_port() {
    local used port hex i
    used=$(awk 'NR > 1 { split($2, a, ":"); print a[2] }' /proc/net/tcp /proc/net/tcp6 2>/dev/null || true)
    for ((i = 0; i < 200; i++)); do
        port=$((20000 + RANDOM % 12768))
        printf -v hex '%04X' "$port"
        grep -qx "$hex" <<<"$used" && continue
        [[ " $* " == *" $port "* ]] && continue
        printf '%s\n' "$port"
        return 0
    done
    return 1
}

tail_log() {
    [[ -s $1 ]] || return 0
    printf -- '--- last lines of %s ---\n' "$1" >&2
    tail -n "${2:-20}" "$1" >&2
}

# --- paths (set by set_paths) -----------------------------------------------

set_paths() {
    # slurm.conf values cannot hold blanks, and env.sh single-quotes paths.
    local bad="[[:space:]'\"\\\\]"
    if [[ $1 =~ $bad ]]; then msg "DIR must not contain blanks or quotes: $1"; exit 2; fi
    mkdir -p -- "$1"
    DIR=$(cd -- "$1" && pwd -P)
    if [[ $DIR =~ $bad ]]; then msg "DIR must not contain blanks or quotes: $DIR"; exit 2; fi
    CONF=$DIR/slurm.conf
    LOG=$DIR/log
    PID=$DIR/pid
    RUN_LINK=$DIR/run
}

# The private runtime folder, only if DIR/run points to one of ours.
run_dir() {
    local r
    r=$(readlink -- "$RUN_LINK" 2>/dev/null) || return 1
    [[ $r == "$RUN_PREFIX"* && -d $r ]] || return 1
    printf '%s\n' "$r"
}

# --- stop ------------------------------------------------------------------

stop_cluster() {
    local rc=0 ctld slurmd munged rd pid deadline jobs
    ctld=$(our_pid "$PID/slurmctld.pid" "$CONF") || ctld=
    slurmd=$(our_pid "$PID/slurmd.pid" "$CONF") || slurmd=

    if [[ -n $ctld ]]; then
        # Running jobs outlive `scontrol shutdown` (their slurmstepd keeps
        # going), so cancel them first and give them up to 10 s to end.
        deadline=$((SECONDS + 10))
        SLURM_CONF=$CONF timeout 5 scancel --partition="$PARTITION" >/dev/null 2>&1 || true
        while ((SECONDS < deadline)); do
            jobs=$(SLURM_CONF=$CONF timeout 5 squeue -h -o %i -t PD,R,CG,S 2>/dev/null) || break
            [[ -z $jobs ]] && break
            sleep 0.2
        done
        # Stops slurmctld, which tells every slurmd of the cluster to stop.
        SLURM_CONF=$CONF timeout 10 scontrol shutdown >/dev/null 2>&1 || true
        wait_gone "$ctld" 10 || terminate "$ctld" slurmctld || rc=1
        # slurmd got the shutdown too; it should follow at once.
        [[ -n $slurmd ]] && { wait_gone "$slurmd" 2 || terminate "$slurmd" slurmd || rc=1; }
    elif [[ -n $slurmd ]]; then
        terminate "$slurmd" slurmd || rc=1
    fi

    # Left-over step daemons of this cluster: slurmd gives them a clean
    # environment holding just SLURM_CONF, which names our config.
    for pid in $(pgrep -x slurmstepd || true); do
        if tr '\0' '\n' 2>/dev/null <"/proc/$pid/environ" | grep -qxF "SLURM_CONF=$CONF"; then
            terminate "$pid" slurmstepd || rc=1
        fi
    done

    if rd=$(run_dir); then
        munged=$(our_pid "$PID/munged.pid" "$rd/munge/munge.socket") || munged=
        [[ -n $munged ]] && { terminate "$munged" munged || rc=1; }
        if ((rc == 0)); then
            rm -rf -- "$rd"
            rm -f -- "$RUN_LINK"
        fi
    fi
    ((rc == 0)) && rm -f -- "$PID"/*.pid "$DIR/env.sh"
    return "$rc"
}

# --- start -----------------------------------------------------------------

START_OK=0
# Any unexpected exit during start (error, Ctrl-C) must not leave daemons.
cleanup_on_exit() {
    local rc=$?
    if ((START_OK == 0)); then
        stop_cluster || msg "cleanup after failed start was incomplete; see $DIR"
        ((rc == 0)) && rc=1
    fi
    exit "$rc"
}

fail() {
    msg "start failed: $1"
    shift
    local f
    for f in "$@"; do tail_log "$f"; done
    exit 1  # the EXIT trap stops whatever was started
}

preflight() {
    local missing=() b
    if [[ $(id -u) -ne 0 ]]; then msg "cannot start here: must run as root"; exit 77; fi
    for b in munged munge unmunge slurmctld slurmd sinfo scontrol squeue scancel sbatch setpriv flock timeout; do
        command -v "$b" >/dev/null 2>&1 || missing+=("$b")
    done
    if ((${#missing[@]})); then
        msg "cannot start here: missing commands: ${missing[*]}" \
            "(apt-get install -y --no-install-recommends slurmctld slurmd slurm-client munge)"
        exit 77
    fi
    if ! id munge >/dev/null 2>&1; then msg "cannot start here: no 'munge' user (is the munge package installed?)"; exit 77; fi
}

# Run "$@" as a detached daemon in its own session, stdio to $1's log file;
# prints its pid. setsid does not fork here (a background job of a
# non-interactive shell is no group leader), so $! is the daemon itself.
# fd 9 (our lock) is closed so the daemon does not hold it.
spawn() {
    local out=$1
    shift
    setsid "$@" </dev/null >>"$out" 2>&1 9>&- &
    printf '%s\n' "$!"
}

write_conf() {
    local rd=$1 ctld_port=$2 slurmd_port=$3 cpus mem_mb
    cpus=$(nproc)
    # Stay below what slurmd detects, or the node is drained "Low RealMemory".
    mem_mb=$(awk '/^MemTotal:/ { m = int($2 / 1024 * 0.9); print (m > 100 ? m : 100) }' /proc/meminfo)
    : >"$DIR/plugstack.conf"  # no SPANK plugins from /etc/slurm
    # Extra lines replace every default line with the same key (Slurm would
    # use the last value but log an error for each repeated key).
    awk -v extra="${SLURM_CLUSTER_EXTRA_CONF:-}" '
        function key(l) { return tolower(substr(l, 1, index(l, "=") - 1)) }
        BEGIN { n = split(extra, x, "\n"); for (i = 1; i <= n; i++) if (key(x[i]) != "") drop[key(x[i])] = 1 }
        !(key($0) in drop)
        END { if (n) { print "# From SLURM_CLUSTER_EXTRA_CONF:"; for (i = 1; i <= n; i++) print x[i] } }
    ' >"$CONF" <<EOF
# Generated by slurm_cluster.sh - private single-node test cluster on 127.0.0.1.
ClusterName=testcluster
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$rd/munge/munge.socket
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$rd/spool
SlurmctldPidFile=$PID/slurmctld.pid
SlurmdPidFile=$PID/slurmd.pid
SlurmctldLogFile=$LOG/slurmctld.log
SlurmdLogFile=$LOG/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig=$DIR/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
# CPUs only: memory is not a consumable, so jobs never wait for memory.
SelectTypeParameters=CR_CPU
MpiDefault=none
# No mail on this machine; an empty/missing MailProg only logs an error.
MailProg=/bin/true
ReturnToService=2
# Schedule batch jobs at once, not up to 3 s later: a throttled array
# (%2) then runs a new pair of tasks every ~1 s instead of every ~3 s.
SchedulerParameters=batch_sched_delay=0
# Finished jobs stay visible to 'scontrol show job' for 5 minutes.
MinJobAge=300
InactiveLimit=0
KillWait=5
SlurmdTimeout=300
NodeName=$NODE NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=$PARTITION Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
}

start_cluster() {
    local rd sock ctld_port slurmd_port timeout_s i state pid_m pid_c pid_d deadline
    if our_pid "$PID/slurmctld.pid" "$CONF" >/dev/null || our_pid "$PID/slurmd.pid" "$CONF" >/dev/null ||
        { rd=$(run_dir) && our_pid "$PID/munged.pid" "$rd/munge/munge.socket" >/dev/null; }; then
        msg "a cluster is already running in $DIR; stop it first"
        exit 2
    fi
    trap cleanup_on_exit EXIT
    trap 'exit 130' INT TERM
    stop_cluster >/dev/null 2>&1 || true  # remnants of an earlier failed start

    rm -rf -- "$DIR/state" "$LOG" "$PID"
    mkdir -p -- "$DIR/state" "$LOG" "$PID"

    rd=$(mktemp -d "${RUN_PREFIX}XXXXXX")
    chmod 0755 "$rd"  # munge must traverse it
    ln -sfn -- "$rd" "$RUN_LINK"
    # munged insists: socket folder owned by munge and searchable by all.
    mkdir -m 0755 "$rd/munge"
    mkdir -m 0700 "$rd/spool"
    chown munge:munge "$rd/munge"
    sock=$rd/munge/munge.socket

    # munge key, created by the munge user itself (0600 munge:munge).
    if command -v mungekey >/dev/null 2>&1; then
        setpriv --reuid=munge --regid=munge --init-groups mungekey --create --keyfile="$rd/munge/munge.key" \
            >>"$LOG/munged.out" 2>&1 || fail "cannot create munge key" "$LOG/munged.out"
    else
        # shellcheck disable=SC2016  # $1 expands in the inner shell
        setpriv --reuid=munge --regid=munge --init-groups sh -c 'umask 077 && head -c 128 /dev/urandom >"$1"' sh \
            "$rd/munge/munge.key" || fail "cannot create munge key"
    fi

    # munged as user munge, with its own socket, so a system munged (if any)
    # is neither used nor disturbed. In the foreground it logs to stderr,
    # i.e. to log/munged.out.
    pid_m=$(spawn "$LOG/munged.out" "${DAEMON_ENV[@]}" setpriv --reuid=munge --regid=munge --init-groups \
        "$(command -v munged)" --foreground --origin=127.0.0.1 --socket="$sock" --key-file="$rd/munge/munge.key" \
        --pid-file="$rd/munge/munged.pid" --seed-file="$rd/munge/munged.seed")
    echo "$pid_m" >"$PID/munged.pid"
    for ((i = 0; i < 100; i++)); do
        alive "$pid_m" || fail "munged exited" "$LOG/munged.out"
        [[ -S $sock ]] && munge -n -S "$sock" 2>/dev/null | unmunge -S "$sock" >/dev/null 2>&1 && break
        sleep 0.1
    done
    ((i < 100)) || fail "munged did not answer on $sock within 10 s" "$LOG/munged.out"

    ctld_port=$(free_port) || fail "no free TCP port found"
    slurmd_port=$(free_port "$ctld_port") || fail "no free TCP port found"
    write_conf "$rd" "$ctld_port" "$slurmd_port"

    # Foreground mode (-D) under setsid: we know the pids at once and see
    # early fatal errors in *.out.
    pid_c=$(spawn "$LOG/slurmctld.out" "${DAEMON_ENV[@]}" SLURM_CONF="$CONF" \
        "$(command -v slurmctld)" -D -f "$CONF")
    echo "$pid_c" >"$PID/slurmctld.pid"
    pid_d=$(spawn "$LOG/slurmd.out" "${DAEMON_ENV[@]}" SLURM_CONF="$CONF" \
        "$(command -v slurmd)" -D -f "$CONF" -N "$NODE")
    echo "$pid_d" >"$PID/slurmd.pid"

    timeout_s=${SLURM_CLUSTER_START_TIMEOUT:-30}
    deadline=$((SECONDS + timeout_s))
    while :; do
        alive "$pid_c" || fail "slurmctld exited" "$LOG/slurmctld.out" "$LOG/slurmctld.log"
        alive "$pid_d" || fail "slurmd exited" "$LOG/slurmd.out" "$LOG/slurmd.log"
        state=$(SLURM_CONF=$CONF timeout 5 sinfo -h -N -n "$NODE" -o '%T %E' 2>/dev/null || true)
        [[ $state == idle* ]] && break
        # Registered but rejected (e.g. fewer CPUs/memory than configured).
        [[ $state == inval* || $state == drain* ]] &&
            fail "node state: $state" "$LOG/slurmctld.log" "$LOG/slurmd.log"
        ((SECONDS < deadline)) || fail "node not idle after ${timeout_s} s (state: '${state:-no answer}')" \
            "$LOG/slurmctld.log" "$LOG/slurmd.log"
        sleep 0.2
    done

    cat >"$DIR/env.sh" <<EOF
# Source this to use the test cluster started in $DIR.
export SLURM_CONF='$CONF'
export TEST_SLURM_CLUSTER_DIR='$DIR'
export TEST_SLURM_PARTITION='$PARTITION'
EOF
    START_OK=1
    msg "cluster up in $DIR (slurmctld :$ctld_port, slurmd :$slurmd_port, $(nproc) CPUs); source $DIR/env.sh"
}

# --- main ------------------------------------------------------------------

[[ $# -eq 2 && -n $2 ]] || usage
case $1 in
    start | stop | status) ;;
    *) usage ;;
esac
[[ $1 == start || -d $2 ]] || { [[ $1 == stop ]] && exit 0; msg "no such folder: $2"; exit 1; }
[[ $1 == start ]] && preflight  # before touching DIR
set_paths "$2"

# One start/stop at a time per DIR.
exec 9>"$DIR/.lock"
flock -w 120 9 || { msg "timed out waiting for the lock on $DIR/.lock"; exit 1; }

case $1 in
    start) start_cluster ;;
    stop) stop_cluster || { msg "stop: some processes could not be stopped"; exit 1; } ;;
    status)
        our_pid "$PID/slurmctld.pid" "$CONF" >/dev/null && our_pid "$PID/slurmd.pid" "$CONF" >/dev/null || exit 1
        state=$(SLURM_CONF=$CONF timeout 5 sinfo -h -N -n "$NODE" -o %T 2>/dev/null) || exit 1
        printf '%s\n' "$state"
        [[ $state =~ ^(idle|mixed|allocated|completing)$ ]]
        ;;
esac
