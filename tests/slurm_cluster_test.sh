#!/bin/sh
# `vdblight slurm` on a real one-node Slurm (issue 17), started and stopped by this script
# (tests/slurm_local.sh): the default bake (a probe-to-probe pass, so two stages: array -> merge
# -> array -> merge, --direct occlusion), 4 tiles.
#  1. Merged = the single bake, byte for byte, although one stage-0 tile's bake process was
#     killed mid-run (SIGKILL: the tile script requeues its task) and another stage-0 tile was
#     requeued by Slurm mid-run (`scontrol requeue`).
#  2. A stage-0 tile cancelled mid-run (scancel) leaves the chain waiting; re-submitting redoes
#     only that tile (3 skipped) and gives the identical file.
#  3. After a complete run, one stage-1 tile and the merged file lost: re-submitting redoes
#     only that tile (4 + 3 skipped) and gives the identical file.
# Usage: slurm_cluster_test.sh VDBLIGHT SOURCE_DIR (absolute: the single bake and the tiles must
# record the same scene path). Exit 77 (skipped) without Slurm or root. KEEP_SLURM_DIR=1 keeps
# the work directory (logs, tiles) for a look after a failure.
set -u
B=$1; SRC=$2
. "$SRC/tests/slurm_local.sh"
slurm_local_check
W=$(mktemp -d /tmp/vdblight-slurm.XXXXXX)
cleanup() { slurm_local_stop; [ -n "${KEEP_SLURM_DIR:-}" ] && echo "kept $W" || rm -rf "$W"; }
trap cleanup EXIT
fail() { echo "FAILED: $*"; for f in "$W"/*.log "$W"/world.vdb.tiles/*.log; do [ -f "$f" ] && { echo "== $f"; tail -5 "$f"; }; done; exit 1; }
slurm_local_start "$W" || fail "the one-node Slurm did not start"

# The default bake's passes (uniform SH point gather, one probe-to-probe pass, --direct
# occlusion, depth moments) with seed 3, at the earlier default's 16 nodes on the longest axis
# and 256 rays (the default's ~16384 nodes x 1024 rays would cost CI ~12x the time; the grid and
# ray count change no pass). A tile bakes in under a second, so the tiles the test kills,
# requeues or cancels are held (hold_tiles): their job script waits, in the process the test
# kills, until the test removes a hold file; no race with a tile that finishes first (issue 29).
OPTS="--seed 3 --resolution 16 --rays 256"
SCENE="$SRC/data/cornell_box.obj"
TILES="$W/world.vdb.tiles"
now() { date +%s.%N; }
secs() { echo "$2 - $1" | bc; }
skipped() { grep -l "already baked" "$TILES"/stage-$1-tile-*.log 2>/dev/null | wc -l; }
# Writes the scripts of a tiled bake (`vdblight slurm` without --submit) and makes the stage-0
# tiles $1 (a list of task ids) wait before their bake, on their first run only, while the file
# $W/hold-<id> exists: the wait runs in the process that then execs the bake, with the bake's
# arguments on its command line, so that bake_pid finds it and a SIGKILL of it is a killed bake
# to the job script (which requeues the task). Then submits the jobs.
submit_holding() {
  held=$1; shift
  "$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 "$@" $OPTS >/dev/null || fail "slurm (scripts)"
  for t in $held; do : >"$W/hold-$t"; done
  # The tile line starts with the quoted vdblight path followed by " bake ".
  sed -i "s|^\('[^']*'\) bake |sh -c 'h=\$0; [ \"\${SLURM_RESTART_COUNT:-0}\" = 0 ] \&\& while [ -e \"\$h\" ]; do sleep 0.05; done; exec \"\$@\"' '$W/hold-'\$SLURM_ARRAY_TASK_ID \1 bake |" \
    "$TILES/tiles-0.sbatch"
  grep -q "hold-" "$TILES/tiles-0.sbatch" || fail "could not hold the stage-0 tiles (script format changed?)"
  sh "$TILES/submit.sh" >/dev/null || fail "submit"
}
release_tile() { rm -f "$W/hold-$1"; }

# Waits until array task $1 runs a bake (its process is up), then prints the bake's pid.
bake_pid() {
  for i in $(seq 600); do
    p=$(pgrep -f -- "$TILES/stage-0-tile-$1.vdb --tiles 4" | head -1)
    [ -n "$p" ] && { echo "$p"; return 0; }
    sleep 0.05
  done
  return 1
}

T0=$(now)
"$B" bake "$SCENE" -q -o "$W/whole.vdb" --threads 2 $OPTS || fail "single bake"
T1=$(now)
echo "single bake, 2 threads: $(secs $T0 $T1) s"

# 1. Kill one tile's process, requeue another through Slurm: both run again, the chain goes on.
# Tiles 1 and 2 are held until then (submit_holding).
submit_holding "1 2"
ID=$(cut -d' ' -f1 "$TILES/jobs")
P1=$(bake_pid 1) || fail "stage-0 tile 1 never ran"
kill -KILL "$P1"
release_tile 1
bake_pid 2 >/dev/null || fail "stage-0 tile 2 never ran"
scontrol requeue "${ID}_2" || fail "scontrol requeue ${ID}_2"
release_tile 2
# Slurm holds a requeued job for 120 s (its BeginTime); start both as soon as they are back in
# the queue, so that CI does not wait. But not within the second of the requeue: slurmd revokes
# the old run's credential with a time stamp in whole seconds and refuses a restart whose
# credential was made in that same second ("Job credential revoked": the task fails and the
# chain never finishes).
for t in 1 2; do
  for i in $(seq 300); do squeue -h -j "${ID}_$t" -o %T 2>/dev/null | grep -q PENDING && break; sleep 0.1; done
  sleep 1.1
  scontrol update JobId="${ID}_$t" StartTime=now || fail "tile $t was not requeued"
done
slurm_local_wait || fail "jobs did not finish"
T2=$(now)
[ -f "$W/world.vdb" ] || fail "no merged file after the requeued tiles"
cmp "$W/whole.vdb" "$W/world.vdb" || fail "4 tiles on Slurm (one killed, one requeued) differ from the single bake"
grep -q "requeueing tile 1" "$TILES/stage-0-tile-1.log" || fail "tile 1 was not requeued after its bake was killed"
for t in 1 2; do
  R=$(sacct -n -X -D -j "${ID}_$t" -o State 2>/dev/null | grep -c REQUEUED)
  [ "$R" -ge 1 ] || scontrol show job "${ID}_$t" 2>/dev/null | grep -q "Restarts=[1-9]" ||
    fail "stage-0 tile $t shows no requeue in sacct or scontrol"
done
echo "submit -> merged on Slurm, tile 1's bake killed (requeued by its script), tile 2 requeued (scontrol): $(secs $T1 $T2) s: identical"

# 3. Lose one stage-1 tile and the merged file: only that tile is baked again.
rm -f "$W/world.vdb" "$TILES/stage-1-tile-3.vdb"
T3=$(now)
"$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 --submit $OPTS >/dev/null || fail "re-submit after a lost tile"
slurm_local_wait || fail "resumed jobs did not finish"
T4=$(now)
cmp "$W/whole.vdb" "$W/world.vdb" || fail "the bake resumed after a lost stage-1 tile differs from the single bake"
[ "$(skipped 0)" -eq 4 ] || fail "expected 4 stage-0 tiles skipped on resume, got $(skipped 0)"
[ "$(skipped 1)" -eq 3 ] || fail "expected 3 stage-1 tiles skipped on resume, got $(skipped 1)"
grep -q "already baked" "$TILES/stage-1-tile-3.log" && fail "the lost stage-1 tile was not baked again"
echo "resumed after losing 1 of 4 stage-1 tiles: $(secs $T3 $T4) s, 7 of 8 tiles skipped: identical"

# 2. Cancel a stage-0 tile mid-run: the chain waits forever (afterok never satisfied); re-submit.
rm -rf "$W/world.vdb" "$TILES"
submit_holding 2
ID=$(cut -d' ' -f1 "$TILES/jobs"); LATER=$(cut -d' ' -f2- "$TILES/jobs")
bake_pid 2 >/dev/null || fail "stage-0 tile 2 never ran"
scancel "${ID}_2"
release_tile 2
for i in $(seq 600); do [ -z "$(squeue -h -j "$ID" -o %i 2>/dev/null)" ] && break; sleep 0.2; done
[ -f "$TILES/stage-0-tile-2.vdb" ] && fail "the cancelled tile left a file"
grep -q "requeueing" "$TILES/stage-0-tile-2.log" && fail "the cancelled tile was requeued"
[ -f "$TILES/stage-0.vdb" ] && fail "the stage-0 merge ran although a tile was cancelled"
[ -f "$W/world.vdb" ] && fail "the final merge ran although a tile was cancelled"
scancel $LATER
T5=$(now)
"$B" slurm "$SCENE" -o "$W/world.vdb" --tiles 4 --submit $OPTS >/dev/null || fail "re-submit"
slurm_local_wait || fail "resumed jobs did not finish"
T6=$(now)
cmp "$W/whole.vdb" "$W/world.vdb" || fail "the resumed bake differs from the single bake"
[ "$(skipped 0)" -eq 3 ] || fail "expected 3 stage-0 tiles skipped on resume, got $(skipped 0)"
echo "resumed after cancelling 1 of 4 stage-0 tiles: $(secs $T5 $T6) s, 3 skipped: identical"
echo PASSED
