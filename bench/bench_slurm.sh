#!/bin/sh
# Issue 17's Slurm targets, measured on a one-node Slurm that this script starts and stops
# (tests/slurm_local.sh; root and the Slurm packages needed; only one such cluster at a time):
#   1. submit -> merged file of `vdblight slurm --tiles N` against a single process with 2
#      threads (target: within 1.15x for a bake of at least 30 s);
#   2. a resumed run after losing 1 of N tiles (the last stage's tile 1 and the merged file)
#      against the full run (target: <= 0.25x); and, for comparison, a tile of the first stage
#      lost before the later stages ran (a cancelled tile: every later stage then runs in full).
# Prints each time, the ratios, and where the tiled run's wall time went (sampled from squeue
# every 0.1 s: nothing running = scheduling and job start latency, a merge running, tiles
# running with a CPU idle).
# Usage: bench_slurm.sh VDBLIGHT SOURCE_DIR
# Environment: BENCH_TILES (8), BENCH_TILE_THREADS (1), BENCH_OPTS (bake options; default the default bake with 40 nodes
# on the longest axis (62 400) and 1024 rays, seed 3), BENCH_SBATCH (extra sbatch options, e.g. --cpus-per-task=2).
set -u
B=$1; SRC=$2
TILES_N=${BENCH_TILES:-8}
OPTS=${BENCH_OPTS:---seed 3 --resolution 40 --rays 1024}
SB=${BENCH_SBATCH:-}
. "$SRC/tests/slurm_local.sh"
slurm_local_check
W=$(mktemp -d /tmp/vdblight-slurm-bench.XXXXXX)
cleanup() { slurm_local_stop; rm -rf "$W"; }
trap cleanup EXIT
fail() { echo "FAILED: $*"; exit 1; }
slurm_local_start "$W" || fail "the one-node Slurm did not start"
SCENE="$SRC/data/cornell_box.obj"
TILES="$W/world.vdb.tiles"
now() { date +%s.%N; }
secs() { echo "scale=2; ($2 - $1) / 1" | bc; }
ratio() { echo "scale=3; $1 / $2" | bc; }
# Each tile bakes with --threads $TILE_THREADS (default 1: one thread per CPU Slurm gives a task,
# so that the tiled run uses no more threads than the single process on a shared machine).
TILE_THREADS=${BENCH_TILE_THREADS:-1}
submit() { "$B" slurm "$SCENE" -o "$W/world.vdb" --tiles "$TILES_N" ${SB:+--sbatch "$SB"} --submit $OPTS --threads "$TILE_THREADS" >/dev/null || fail "submit"; }
# Waits for the jobs while sampling what runs; prints "idle merge tail tiles" sample counts.
watch_jobs() {
  idle=0; merge=0; tail=0; full=0
  while :; do
    q=$(squeue -h -o '%T %j' 2>/dev/null)
    [ -z "$q" ] && break
    r=$(echo "$q" | grep '^RUNNING' || true)
    if [ -z "$r" ]; then idle=$((idle + 1))
    elif echo "$r" | grep -q merge; then merge=$((merge + 1))
    elif [ "$(echo "$r" | wc -l)" -lt "$(nproc)" ] && echo "$q" | grep -q '^PENDING.*tiles' ; then full=$((full + 1))
    elif [ "$(echo "$r" | wc -l)" -lt "$(nproc)" ]; then tail=$((tail + 1))
    else full=$((full + 1)); fi
    sleep 0.1
  done
  echo "$idle $merge $tail $full"
}
breakdown() {  # $1 = samples "idle merge tail full"
  set -- $1
  total=$(($1 + $2 + $3 + $4)); [ "$total" -gt 0 ] || total=1
  echo "    wall time sampled: nothing running (scheduling, job start) $((100 * $1 / total)) %, a merge $((100 * $2 / total)) %," \
       "fewer tiles than CPUs with none pending (tail) $((100 * $3 / total)) %, tiles on every CPU $((100 * $4 / total)) %"
}

echo "vdblight slurm benchmark: $(nproc) CPUs, $TILES_N tiles of $TILE_THREADS thread(s), bake options: $OPTS${SB:+, sbatch: $SB}; load average $(cut -d' ' -f1-3 /proc/loadavg)"
T0=$(now)
/usr/bin/time -f "%U %S" -o "$W/cpu" "$B" bake "$SCENE" -q -o "$W/whole.vdb" --threads 2 $OPTS || fail "single bake"
T1=$(now)
SINGLE=$(secs $T0 $T1)
echo "single process, 2 threads: $SINGLE s wall, $(awk '{print $1 + $2}' "$W/cpu") CPU s"

T2=$(now); submit; S=$(watch_jobs); T3=$(now)
FULL=$(secs $T2 $T3)
cmp -s "$W/whole.vdb" "$W/world.vdb" || fail "the merged file differs from the single bake"
echo "slurm --tiles $TILES_N, submit -> merged: $FULL s = $(ratio $FULL $SINGLE) x the single process (target <= 1.15), cmp-identical"
breakdown "$S"
STAGES=$(cut -d' ' -f2 "$TILES/tiles")
LAST=$((STAGES - 1))
PREFIX=$([ "$STAGES" -gt 1 ] && echo "stage-$LAST-" || echo "")
for f in "$TILES"/*tile-*.log; do grep -h "Baked tile" "$f"; done | sed 's/.*: \([0-9]* of [0-9]* nodes\).* in \(.*\)\. Wrote.*/\2/' |
  tr '\n' ' ' | sed 's/^/    tracing per tile (bake log): /'; echo

rm -f "$W/world.vdb" "$TILES/${PREFIX}tile-1.vdb"
T4=$(now); submit; S=$(watch_jobs); T5=$(now)
RESUME=$(secs $T4 $T5)
cmp -s "$W/whole.vdb" "$W/world.vdb" || fail "the resumed bake differs from the single bake"
echo "resumed, tile 1 of the last stage lost: $RESUME s = $(ratio $RESUME $FULL) x the full run (target <= 0.25), cmp-identical"
breakdown "$S"

if [ "$STAGES" -gt 1 ]; then  # a first-stage tile lost before the later stages ran
  rm -f "$W/world.vdb" "$TILES/stage-0-tile-1.vdb" "$TILES"/stage-0.vdb
  for s in $(seq 1 $LAST); do rm -f "$TILES"/stage-$s-tile-*.vdb "$TILES/stage-$s.vdb"; done
  T6=$(now); submit; S=$(watch_jobs); T7=$(now)
  EARLY=$(secs $T6 $T7)
  cmp -s "$W/whole.vdb" "$W/world.vdb" || fail "the resumed bake differs from the single bake"
  echo "resumed, tile 1 of stage 0 lost before stage 1 ran: $EARLY s = $(ratio $EARLY $FULL) x the full run"
  breakdown "$S"
fi
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
