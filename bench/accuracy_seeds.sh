#!/usr/bin/env bash
# The accuracy benchmark over several bake seeds (issue 32): one vdblight_bench_accuracy process
# per seed (--config try, --no-decompose --no-noise), then per --try row its mean RMS, its
# largest, the seeds over a target, its mean bias and its mean wall and CPU seconds. The ground
# truth and its points do not depend on --seed (accuracy_truth.cpp), so only the bakes change:
# this is the seed-to-seed spread of a preset that docs/time_to_accuracy.md's "ten seeds" tables
# give.
# Usage: bench/accuracy_seeds.sh SCENE "SPEC;SPEC..." SEEDS [TARGET_PERCENT] [BUILD_DIR]
#   e.g. bench/accuracy_seeds.sh two_rooms "preset=preview;preset=preview,extrapaths=192" 10 5
#   SCENE: office, cornell, two_rooms or outdoor; SEEDS: runs seeds 1..SEEDS;
#   TARGET_PERCENT: count the seeds whose RMS is above it (default: none).
set -euo pipefail
if [ $# -lt 3 ]; then
    sed -n '8,11p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
scene=$1 specs=$2 seeds=$3 target=${4:-0} build=${5:-build}
bench="$build/bin/vdblight_bench_accuracy"
[ -x "$bench" ] || { echo "accuracy_seeds.sh: no $bench (build the benchmarks first)" >&2; exit 2; }
[[ "$seeds" =~ ^[1-9][0-9]*$ ]] || { echo "accuracy_seeds.sh: SEEDS must be a positive count, got '$seeds'" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for s in $(seq 1 "$seeds"); do
    if ! "$bench" --config try --try "$specs" --scene "$scene" --no-decompose --no-noise --seed "$s" \
        --cache "$build/accuracy_cache" --csv "$work/seed$s.csv" >"$work/seed$s.log" 2>&1; then
        echo "accuracy_seeds.sh: the benchmark failed at seed $s:" >&2
        tail -n 3 "$work/seed$s.log" >&2
        exit 1
    fi
    # A row the benchmark refuses (e.g. options a preset cannot take) says why and has no CSV line.
    grep " failed" "$work/seed$s.log" >&2 || true
    grep "^$scene,try" "$work/seed$s.csv" >>"$work/all.csv" || true
done
[ -s "$work/all.csv" ] || { echo "accuracy_seeds.sh: no row was baked" >&2; exit 1; }
echo "$scene over seeds 1..$seeds (RMS, bias in %; seconds of the bake, means over the seeds)"
# CSV columns: scene, config, rms, p95, max, bias, bake_seconds, cpu_seconds, ...
awk -F, -v target="$target" '
    !($2 in n) { order[++rows] = $2 }
    { n[$2]++; sum[$2] += $3; bias[$2] += $6; wall[$2] += $7; cpu[$2] += $8
      if ($3 > top[$2]) top[$2] = $3
      if (target > 0 && 100 * $3 > target) over[$2]++ }
    END {
        for (r = 1; r <= rows; r++) {
            k = order[r]
            line = sprintf("  %-50s mean %.2f  max %.2f", k, 100 * sum[k] / n[k], 100 * top[k])
            if (target > 0) line = line sprintf("  over %g: %d of %d", target, over[k] + 0, n[k])
            printf "%s  bias %+.2f  wall %.3f s  CPU %.3f s\n", line, 100 * bias[k] / n[k], wall[k] / n[k], cpu[k] / n[k]
        }
    }' "$work/all.csv"
