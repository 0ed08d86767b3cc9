# A one-node Slurm cluster on this machine, started and stopped by the caller (issue 17):
# sourced by tests/slurm_cluster_test.sh and scripts/bench_slurm.sh. Needs root and the Debian
# packages slurmctld, slurmd, slurm-client and munge (scripts/setup.sh installs them).
#   slurm_local_check        exit 77 (skipped) with a message where that is missing
#   slurm_local_start DIR    munged (if not running), slurmctld and slurmd with state in DIR;
#                            exports SLURM_CONF; returns non-zero if the node does not come up
#   slurm_local_stop         stops what slurm_local_start started
#   slurm_local_wait         until none of the cluster's jobs is pending or running (or 600 s;
#                            fails at once if a job's dependency can never be satisfied)
# Only one such cluster may run at a time (ports 6817/6818); the daemons carry "vdblight-slurm"
# in their state directory's path, so that `pgrep -f vdblight-slurm` finds orphans.

slurm_local_check() {
  for tool in slurmctld slurmd sbatch squeue scancel scontrol munged munge; do
    if ! command -v $tool >/dev/null 2>&1 && [ ! -x /usr/sbin/$tool ]; then
      echo "SKIPPED: Slurm is not installed ($tool missing; scripts/setup.sh installs slurmctld slurmd slurm-client munge)"; exit 77
    fi
  done
  [ "$(id -u)" -eq 0 ] || { echo "SKIPPED: the one-node Slurm needs root"; exit 77; }
}

slurm_local_start() {
  SLURM_LOCAL_DIR=$1
  SLURM_LOCAL_MUNGE=
  if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    mkdir -p /run/munge && chown munge:munge /run/munge
    su -s /bin/sh munge -c /usr/sbin/munged || return 1
    SLURM_LOCAL_MUNGE=1; sleep 1
  fi
  mkdir -p "$SLURM_LOCAL_DIR/spool" "$SLURM_LOCAL_DIR/state"
  # Job start latency (docs/scaling.md, "Measured"): the scheduler runs at every submit and job
  # end without the default 3 s batch delay, its periodic pass every second instead of 60 s
  # (dependent jobs become eligible there), backfill every second; a cancelled or requeued job
  # gets SIGKILL 1 s after SIGTERM (KillWait, default 30 s).
  cat > "$SLURM_LOCAL_DIR/slurm.conf" <<CONF
ClusterName=vdblight
SlurmctldHost=$(hostname -s)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$SLURM_LOCAL_DIR/state
SlurmdSpoolDir=$SLURM_LOCAL_DIR/spool
SlurmctldPidFile=$SLURM_LOCAL_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_LOCAL_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_LOCAL_DIR/slurmctld.log
SlurmdLogFile=$SLURM_LOCAL_DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0,sched_interval=1,bf_interval=1
KillWait=1
ReturnToService=2
MpiDefault=none
NodeName=$(hostname -s) CPUs=$(nproc) State=UNKNOWN
PartitionName=bake Nodes=$(hostname -s) Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$SLURM_LOCAL_DIR/slurm.conf"
  slurmctld -f "$SLURM_CONF" || return 1
  slurmd -f "$SLURM_CONF" || return 1
  for i in $(seq 60); do sinfo -h -o %t 2>/dev/null | grep -q idle && return 0; sleep 1; done
  return 1
}

slurm_local_stop() {
  for p in "$SLURM_LOCAL_DIR/slurmd.pid" "$SLURM_LOCAL_DIR/slurmctld.pid"; do
    [ -f "$p" ] && kill "$(cat "$p")" 2>/dev/null
  done
  [ -n "${SLURM_LOCAL_MUNGE:-}" ] && [ -f /run/munge/munged.pid ] && kill "$(cat /run/munge/munged.pid)" 2>/dev/null
  sleep 1
}

slurm_local_wait() {
  for i in $(seq 3000); do
    q=$(squeue -h -o "%i %r" 2>/dev/null)
    [ -z "$q" ] && return 0
    # A job whose dependency failed waits forever: say so now rather than after 600 s.
    case "$q" in *DependencyNeverSatisfied*) echo "$q"; return 1;; esac
    sleep 0.2
  done; return 1
}
