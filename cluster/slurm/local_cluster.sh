#!/usr/bin/env bash
# Run a command against a Slurm cluster: the one configured on this machine when there is one,
# otherwise a real single-node cluster brought up here for the command and shut down after it.
#
#   cluster/slurm/local_cluster.sh [--local] [--keep] [--] COMMAND [ARGS...]
#
# A configured cluster is one where `sinfo` answers with the caller's environment (SLURM_CONF or
# /etc/slurm/slurm.conf or DNS SRV records). Otherwise, as root, with Debian's slurm-wlm and munge
# (installed with apt-get when missing), it starts in a fresh temporary folder:
#   - munged with its own key and socket (the machine's /etc/munge is not used or touched),
#   - slurmctld and slurmd on 127.0.0.1 with a generated slurm.conf (no accounting, no cgroups:
#     proctrack/linuxproc, task/none, select/cons_tres with CR_CPU, one partition "local"),
# waits until the node is idle, runs COMMAND with SLURM_CONF pointing at that slurm.conf, then
# cancels what is left in the queue, stops the daemons and removes the folder (also on error or
# Ctrl-C). Jobs inherit SLURM_CONF, so sbatch/squeue/scancel in COMMAND and in job scripts use it.
#
# Options: --local  bring up the local cluster even if one is configured
#          --keep   keep the temporary folder (logs, slurm.conf) after the shutdown
#                   (also LOCAL_CLUSTER_KEEP=1, e.g. through cluster/test_slurm.sh)
# Environment given to COMMAND: SLURM_CONF (local cluster only), PMU50_SLURM=local|configured,
#          PMU50_SLURM_PARTITION (the local partition; empty for a configured cluster).
#
# Exit status: COMMAND's; 77 when no cluster can be used here (one line on stderr says why:
# not root, packages missing and not installable, a daemon that does not start); 2 bad usage.
set -uo pipefail

SKIP=77
log() { printf 'local_cluster: %s\n' "$*" >&2; }
# The one line saying why; LOCAL_CLUSTER_SKIP_PREFIX replaces "local_cluster: " (test scripts).
skip() { printf '%scannot run a Slurm cluster here: %s\n' "${LOCAL_CLUSTER_SKIP_PREFIX-local_cluster: }" "$*" >&2; exit $SKIP; }

force_local=0 keep=${LOCAL_CLUSTER_KEEP:-0}
while [ $# -gt 0 ]; do
  case "$1" in
    --local) force_local=1; shift ;;
    --keep) keep=1; shift ;;
    --) shift; break ;;
    -h|--help) sed -n '2,/^set -uo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) log "unknown option $1 (valid: --local, --keep, --)"; exit 2 ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { log "no command given (usage: local_cluster.sh [--local] [--keep] [--] COMMAND [ARGS...])"; exit 2; }

# A configured cluster: sinfo answers without anything from us.
if [ "$force_local" = 0 ] && command -v sinfo >/dev/null 2>&1 \
   && timeout 20 sinfo -h -o '%P %a %D %T' >/dev/null 2>&1; then
  log "using the configured Slurm cluster ($(timeout 20 sinfo -h -o '%P:%D nodes %T' 2>/dev/null | tr '\n' ' '))"
  PMU50_SLURM=configured PMU50_SLURM_PARTITION= "$@"
  exit $?
fi

[ "$(id -u)" = 0 ] || skip "no Slurm cluster is configured and starting slurmd needs root (uid $(id -u))"

need="slurmctld:slurmctld slurmd:slurmd sbatch:slurm-client munged:munge mungekey:munge"
missing=""
for t in $need; do command -v "${t%%:*}" >/dev/null 2>&1 || missing="$missing ${t##*:}"; done
if [ -n "$missing" ]; then
  missing=$(printf '%s\n' $missing | sort -u | tr '\n' ' ')
  command -v apt-get >/dev/null 2>&1 || skip "missing commands from Debian packages: $missing(no apt-get)"
  log "installing Debian packages: $missing"
  # The packages' own services (munge, slurmctld, slurmd) are not started by the installation:
  # a policy-rc.d for its duration, unless the machine has one.
  policy=""
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    policy=/usr/sbin/policy-rc.d
    printf '#!/bin/sh\nexit 101\n' >"$policy" && chmod 755 "$policy"
  fi
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      $missing slurm-wlm-basic-plugins >/dev/null; } 2>/dev/null; apt_rc=$?
  [ -n "$policy" ] && rm -f "$policy"
  [ $apt_rc = 0 ] || skip "apt-get install $missing failed"
  for t in $need; do
    command -v "${t%%:*}" >/dev/null 2>&1 || skip "${t%%:*} not found on PATH after apt-get install ${t##*:}"
  done
fi

# The folder must be searchable by all (munged refuses a socket below a 0700 folder) and short
# (a Unix socket path has at most 107 bytes).
D=$(mktemp -d "${TMPDIR:-/tmp}/pmu50-slurm.XXXXXX") || skip "mktemp failed"
chmod 755 "$D"
mkdir -p "$D/state" "$D/spool"
CONF=$D/slurm.conf
SOCK=$D/munge.sock
[ ${#SOCK} -lt 100 ] || skip "temporary folder path too long for a socket: $SOCK (set TMPDIR)"
slurm_pids="" munged_pid=""

# Everything started here has SLURM_CONF=$CONF in its environment (daemons, job steps, tasks):
# that is how leftovers are found at the end, by process id.
ours() {
  local p
  for p in /proc/[0-9]*; do
    p=${p#/proc/}
    [ "$p" = $$ ] || [ "$p" = "$BASHPID" ] && continue
    grep -qxF "SLURM_CONF=$CONF" <<< "$(tr '\0' '\n' 2>/dev/null <"/proc/$p/environ")" && echo "$p"
  done
}

cleanup() {
  local rc=$? left i
  [ -n "${PMU50_SLURM_TRACE:-}" ] && set -x
  trap - EXIT INT TERM HUP
  if [ -f "$CONF" ] && SLURM_CONF=$CONF timeout 5 scontrol ping >/dev/null 2>&1; then
    jobs=$(SLURM_CONF=$CONF timeout 10 squeue -h -o %A 2>/dev/null | sort -u)
    if [ -n "$jobs" ]; then
      # shellcheck disable=SC2086
      SLURM_CONF=$CONF timeout 10 scancel $jobs 2>/dev/null
      for i in $(seq 20); do
        [ -z "$(SLURM_CONF=$CONF timeout 5 squeue -h -o %A 2>/dev/null)" ] && break; sleep 0.5
      done
    fi
    SLURM_CONF=$CONF timeout 10 scontrol shutdown >/dev/null 2>&1
  fi
  for i in $(seq 40); do
    left=""; for p in $slurm_pids; do kill -0 "$p" 2>/dev/null && left="$left $p"; done
    [ -z "$left" ] && break; sleep 0.25
  done
  # shellcheck disable=SC2086
  [ -n "$left" ] && kill -TERM $left 2>/dev/null
  [ -n "$munged_pid" ] && kill -TERM "$munged_pid" 2>/dev/null
  # Job steps and tasks that outlived slurmd (they do not when it shuts down cleanly).
  left=$(ours)
  # shellcheck disable=SC2086
  [ -n "$left" ] && { log "stopping leftover processes $(echo $left)"; kill -KILL $left 2>/dev/null; }
  wait 2>/dev/null
  if [ "$keep" = 1 ]; then log "kept $D"; else rm -rf "$D"; fi
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM HUP

fail_start() {
  local f
  for f in "$D"/*.log "$D"/*.out; do [ -s "$f" ] && { echo "--- $f" >&2; tail -n 15 "$f" >&2; }; done
  skip "$*"
}

# munged: a fresh key, its own socket, pid, log and seed files.
mungekey -c -k "$D/munge.key" -b 1024 >/dev/null 2>&1 \
  || dd if=/dev/urandom of="$D/munge.key" bs=128 count=1 status=none
chmod 600 "$D/munge.key"
SLURM_CONF=$CONF munged -F --key-file="$D/munge.key" --socket="$SOCK" --pid-file="$D/munged.pid" \
  --log-file="$D/munged.log" --seed-file="$D/munged.seed" >"$D/munged.out" 2>&1 &
munged_pid=$!
for i in $(seq 40); do munge -n -S "$SOCK" 2>/dev/null | unmunge -S "$SOCK" >/dev/null 2>&1 && break; sleep 0.25; done
munge -n -S "$SOCK" 2>/dev/null | unmunge -S "$SOCK" >/dev/null 2>&1 || fail_start "munged did not start"

# Two free TCP ports on 127.0.0.1 for slurmctld and slurmd.
free_port() {
  local p
  for _ in $(seq 50); do
    p=$((20000 + (RANDOM * 32768 + RANDOM) % 40000))
    [ -n "$(ss -Hltn "sport = :$p" 2>/dev/null)" ] && continue
    (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null && continue
    echo "$p"; return 0
  done
  return 1
}
PCTLD=$(free_port) || fail_start "no free TCP port"
PD=$(free_port) || fail_start "no free TCP port"
[ "$PD" != "$PCTLD" ] || PD=$((PCTLD + 1))

NODE=$(hostname -s 2>/dev/null || echo localhost)
# The node as slurmd sees it (CPUs, sockets, cores, memory), addressed on 127.0.0.1.
HW=$(slurmd -C 2>/dev/null | sed -n 's/^NodeName=[^ ]* //p' | head -n 1)
[ -n "$HW" ] || HW="CPUs=$(nproc)"
# Leave memory unchecked (jobs ask for none): a container's figure may differ from the host's.
HW=$(echo "$HW" | sed 's/RealMemory=[0-9]*//')
cat >"$CONF" <<EOF
# Generated by cluster/slurm/local_cluster.sh: a single-node cluster on 127.0.0.1.
ClusterName=pmu50local
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$PCTLD
SlurmdPort=$PD
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$SOCK
CredType=cred/munge
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/slurmctld.log
SlurmdLogFile=$D/slurmd.log
PlugStackConfig=$D/plugstack.conf
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
# sbatch --wait polls every 2 s only while that is below MinJobAge/2; finished jobs are
# forgotten after MinJobAge seconds (no accounting here: the results are in the output folders).
MinJobAge=4
MaxArraySize=100001
MaxJobCount=200000
SlurmdTimeout=60
NodeName=$NODE NodeAddr=127.0.0.1 $HW State=UNKNOWN
PartitionName=local Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
: >"$D/plugstack.conf"

SLURM_CONF=$CONF slurmctld -D -c -f "$CONF" >"$D/slurmctld.out" 2>&1 &
slurm_pids="$slurm_pids $!"
for i in $(seq 60); do grep -q UP <<< "$(SLURM_CONF=$CONF scontrol ping 2>/dev/null)" && break; sleep 0.25; done
grep -q UP <<< "$(SLURM_CONF=$CONF scontrol ping 2>/dev/null)" || fail_start "slurmctld did not start"
SLURM_CONF=$CONF slurmd -D -f "$CONF" -N "$NODE" >"$D/slurmd.out" 2>&1 &
slurm_pids="$slurm_pids $!"
state=""
for i in $(seq 120); do
  state=$(SLURM_CONF=$CONF sinfo -h -n "$NODE" -o %T 2>/dev/null)
  [ "$state" = idle ] && break; sleep 0.25
done
[ "$state" = idle ] || fail_start "node $NODE is '${state:-unknown}', not idle, 30 s after slurmd started"
log "local Slurm cluster up: node $NODE idle, partition local, SLURM_CONF=$CONF"

# In the background so that a signal to this script tears the cluster down at once (a trap
# waits for a foreground command); the signal is passed on to the command.
SLURM_CONF=$CONF PMU50_SLURM=local PMU50_SLURM_PARTITION=local "$@" &
cmd_pid=$!
stop() { kill -TERM "$cmd_pid" 2>/dev/null; wait "$cmd_pid" 2>/dev/null; exit "$1"; }
trap 'stop 130' INT
trap 'stop 143' TERM HUP
wait "$cmd_pid"
