#!/bin/sh
# `vdblight slurm` on a real one-node Slurm (issue 17), started and stopped by this script:
# the default bake (a probe-to-probe pass, so two stages: array -> merge -> array -> merge,
# --direct occlusion): 4 tiles merged = the single bake; a stage-0 tile cancelled
# mid-run (scancel) leaves the chain waiting, and re-submitting redoes only that tile of
# stage 0 (then stage 1) and gives the identical file.
# Usage: slurm_cluster_test.sh VDBLIGHT SOURCE_DIR. Exit 77 (skipped) without Slurm or root.
set -u
B=$1; SRC=$2
for tool in slurmctld slurmd sbatch squeue scancel munged munge; do
  if ! command -v $tool >/dev/null 2>&1 && [ ! -x /usr/sbin/$tool ]; then
    echo "SKIPPED: Slurm is not installed ($tool missing; scripts/setup.sh installs slurmctld slurmd slurm-client munge)"; exit 77
  fi
done
[ "$(id -u)" -eq 0 ] || { echo "SKIPPED: the one-node Slurm needs root"; exit 77; }
W=$(mktemp -d /tmp/vdblight-slurm.XXXXXX)
HOST=$(hostname -s)
cleanup() {
  for p in "$W/slurmd.pid" "$W/slurmctld.pid"; do [ -f "$p" ] && kill "$(cat "$p")" 2>/dev/null; done
  [ -n "${MUNGE_STARTED:-}" ] && [ -f /run/munge/munged.pid ] && kill "$(cat /run/munge/munged.pid)" 2>/dev/null
  sleep 1; rm -rf "$W"
}
trap cleanup EXIT
fail() { echo "FAILED: $*"; for f in "$W"/*.log "$W"/world.vdb.tiles/*.log; do [ -f "$f" ] && { echo "== $f"; tail -5 "$f"; }; done; exit 1; }
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  mkdir -p /run/munge && chown munge:munge /run/munge
  su -s /bin/sh munge -c /usr/sbin/munged || fail "munged did not start"
  MUNGE_STARTED=1; sleep 1
fi
mkdir -p "$W/spool" "$W/state"
cat > "$W/slurm.conf" <<CONF
ClusterName=vdblight
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/slurmctld.log
SlurmdLogFile=$W/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
NodeName=$HOST CPUs=$(nproc) State=UNKNOWN
PartitionName=bake Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$W/slurm.conf"
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for i in $(seq 60); do sinfo -h -o %t 2>/dev/null | grep -q idle && break; sleep 1; done
sinfo -h -o %t | grep -q idle || fail "the node did not come up"

# The default bake's passes (uniform SH point gather, one probe-to-probe pass, --direct
# occlusion, depth moments) with seed 3, at the earlier default's 16 nodes on the longest axis
# and 256 rays (the default's ~16384 nodes x 768 rays would cost CI ~12x the time; the grid and
# ray count change no pass): a tile runs long enough (seconds) to be cancelled while it runs.
OPTS="--seed 3 --resolution 16 --rays 256"
SCENE="$SRC/data/cornell_box.obj"
wait_jobs() {  # until none of our jobs is pending or running (or 600 s)
  for i in $(seq 600); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && return 0; sleep 1; done; return 1
}
T0=$(date +%s.%N)
"$B" bake "$SCENE" -q -o "$W/whole.vdb" --threads 2 $OPTS || fail "single bake"
T1=$(date +%s.%N)
"$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 --submit $OPTS || fail "submit"
wait_jobs || fail "jobs did not finish"
T2=$(date +%s.%N)
cmp "$W/whole.vdb" "$W/world.vdb" || fail "4 tiles on Slurm differ from the single bake"
echo "single bake $(echo "$T1 - $T0" | bc) s; submit -> merged on Slurm $(echo "$T2 - $T1" | bc) s: identical"

# Cancel a stage-0 tile mid-run: the chain waits forever (afterok never satisfied); re-submit.
rm -rf "$W/world.vdb" "$W/world.vdb.tiles"
"$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 --submit $OPTS || fail "submit 2"
ID=$(cut -d' ' -f1 "$W/world.vdb.tiles/jobs"); LATER=$(cut -d' ' -f2- "$W/world.vdb.tiles/jobs")
for i in $(seq 100); do squeue -h -j "${ID}_2" -o %T 2>/dev/null | grep -q RUNNING && break; sleep 0.2; done
scancel "${ID}_2"
for i in $(seq 600); do [ -z "$(squeue -h -j "$ID" -o %i 2>/dev/null)" ] && break; sleep 1; done
[ -f "$W/world.vdb.tiles/stage-0-tile-2.vdb" ] && fail "the cancelled tile left a file"
[ -f "$W/world.vdb.tiles/stage-0.vdb" ] && fail "the stage-0 merge ran although a tile was cancelled"
[ -f "$W/world.vdb" ] && fail "the final merge ran although a tile was cancelled"
scancel $LATER
T3=$(date +%s.%N)
"$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 --submit $OPTS || fail "re-submit"
wait_jobs || fail "resumed jobs did not finish"
T4=$(date +%s.%N)
cmp "$W/whole.vdb" "$W/world.vdb" || fail "the resumed bake differs from the single bake"
SKIPPED=$(grep -l "already baked" "$W"/world.vdb.tiles/stage-0-tile-*.log | wc -l)
[ "$SKIPPED" -eq 3 ] || fail "expected 3 stage-0 tiles skipped on resume, got $SKIPPED"
echo "resumed after cancelling 1 of 4 stage-0 tiles: $(echo "$T4 - $T3" | bc) s, 3 skipped: identical"
echo PASSED
