#!/usr/bin/env bash
# A real single-node Slurm cluster (munged + slurmctld + slurmd from Debian 12's packages),
# started by hand in one temporary directory, for the farm integration test. No systemd, no
# cgroups, no DNS, no slurmdbd, nothing outside DIR. Needs root (the daemons run as root).
# Each pitfall of running Slurm this way is marked PITFALL below, where it is handled.
#
#   slurm-local.sh start DIR   configure and start the daemons in DIR; writes DIR/env.sh (SLURM_CONF)
#   slurm-local.sh stop DIR    cancel our jobs, stop the daemons we started, by the PIDs in DIR
#
# SLURM_LOCAL_CTLD_PORT / SLURM_LOCAL_SLURMD_PORT: ports (default: the first free pair from 16817).
set -euo pipefail

log() { printf '[slurm-local %s] %s\n' "$(date +%T.%3N)" "$*" >&2; }
die() { log "FATAL: $*"; exit 1; }

wait_for() {  # wait_for SECONDS DESCRIPTION COMMAND...  (polls every 0.2 s)
  local limit=$1 what=$2; shift 2
  local end=$(( $(date +%s) + limit ))
  until "$@" >/dev/null 2>&1; do
    [ "$(date +%s)" -lt "$end" ] || { log "timed out after ${limit}s waiting for $what"; return 1; }
    sleep 0.2
  done
}

port_free() { ! ss -Htln "sport = :$1" 2>/dev/null | grep -q .; }

do_start() {
  local dir=${1:?usage: start DIR}
  mkdir -p "$dir"/{munge,state,spool,log}
  # PITFALL: munged refuses a socket whose parent directories are not world-executable; mktemp -d makes 0700.
  chmod 755 "$dir" "$dir/munge"
  local ctld=${SLURM_LOCAL_CTLD_PORT:-} slurmd_port=${SLURM_LOCAL_SLURMD_PORT:-}
  if [ -z "$ctld" ]; then  # not 6817/6818, so a system Slurm (or another test's cluster) cannot clash
    for p in $(seq 16817 2 16899); do
      if port_free "$p" && port_free $((p + 1)); then ctld=$p; slurmd_port=$((p + 1)); break; fi
    done
    [ -n "$ctld" ] || die "no free port pair in 16817-16900"
  fi

  # munge: our own key, socket, pid and log, so a system munged (if any) is untouched.
  mungekey --create --keyfile="$dir/munge/munge.key" 2>/dev/null ||
    dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 600 "$dir/munge/munge.key"  # PITFALL: the key must be 0600 and owned by munged's user
  munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
         --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
         --seed-file="$dir/munge/munged.seed" --origin=127.0.0.1
  wait_for 10 munged munge -S "$dir/munge/munge.socket" -n || { tail -5 "$dir/log/munged.log" >&2; die "munged did not come up"; }

  # PITFALL: the node line must match the machine (name, CPUs, RealMemory): take it from slurmd -C.
  local nodeline node
  nodeline=$(slurmd -C | head -n1)
  node=$(sed -E 's/^NodeName=([^ ]+).*/\1/' <<<"$nodeline")
  cat > "$dir/slurm.conf" <<CONF
# single-node test cluster of meshtour's tests/slurm, everything under $dir
ClusterName=meshtourtest
SlurmctldHost=${node}(127.0.0.1)
SlurmctldPort=${ctld}
SlurmdPort=${slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# PITFALL: a private munged; clients, slurmctld, slurmd and slurmstepd all read this.
AuthInfo=socket=${dir}/munge/munge.socket
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/log/slurmctld.log
SlurmdLogFile=${dir}/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# PITFALL: proctrack/cgroup + task/cgroup fail at job launch without systemd, and silently
# (jobs "COMPLETED 0:0", node drained): linuxproc + task/none need no cgroups.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=${dir}/log/jobcomp.txt
MinJobAge=300
MpiDefault=none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
# PITFALL (latency): batch jobs are scheduled at most every batch_sched_delay (3 s by default).
SchedulerParameters=batch_sched_delay=0
ReturnToService=2
${nodeline} NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  printf 'export SLURM_CONF=%q\n' "$dir/slurm.conf" > "$dir/env.sh"
  export SLURM_CONF="$dir/slurm.conf"
  slurmctld -c -f "$SLURM_CONF"
  wait_for 20 slurmctld bash -c 'scontrol ping | grep -q "is UP"' || { tail -20 "$dir/log/slurmctld.log" >&2; die "slurmctld not UP"; }
  slurmd -f "$SLURM_CONF"
  wait_for 30 "node idle" bash -c "sinfo -h -n '$node' -o %T | grep -qx idle" ||
    { sinfo -R >&2; tail -20 "$dir/log/slurmd.log" >&2; die "node $node not idle"; }
  log "cluster up in $dir (node $node, ports $ctld/$slurmd_port)"
}

stop_pid() {  # stop_pid NAME PIDFILE : SIGTERM that PID if it is that daemon, SIGKILL after 15 s
  local name=$1 f=$2 pid
  [ -s "$f" ] || return 0
  pid=$(cat "$f")
  [ "$(ps -o comm= -p "$pid" 2>/dev/null)" = "$name" ] || return 0  # stale pid file: not ours
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 150); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  log "$name (pid $pid) ignored SIGTERM; SIGKILL"
  kill -9 "$pid" 2>/dev/null || true
}

do_stop() {
  local dir=${1:?usage: stop DIR}
  if [ -f "$dir/env.sh" ]; then
    # shellcheck disable=SC1091
    . "$dir/env.sh"
    if scontrol ping 2>/dev/null | grep -q "is UP"; then
      # PITFALL: running jobs outlive slurmd (slurmstepd): cancel ours first.
      local ids; ids=$(squeue -h -o %A 2>/dev/null | sort -u)
      if [ -n "$ids" ]; then
        # shellcheck disable=SC2086
        scancel $ids || true
        wait_for 20 "jobs gone" bash -c '! squeue -h | grep -q .' || true
      fi
    fi
  fi
  # PITFALL: slurmd deletes its pid file on exit (stop_pid reads it first); munged goes last,
  # the other two still need it while they shut down.
  stop_pid slurmd "$dir/slurmd.pid"
  stop_pid slurmctld "$dir/slurmctld.pid"
  stop_pid munged "$dir/munge/munged.pid"
}

cmd=${1:-}; shift || true
case "$cmd" in
  start) do_start "$@" ;;
  stop) do_stop "$@" ;;
  *) die "usage: $0 start|stop DIR" ;;
esac
