#!/usr/bin/env bash
# Quick start, command 2: set up (packages + build) and run the whole test suite (CTest),
# then a quick smoke run of the benchmark.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# CI must finish within 40 min on 2 cores: each stage prints its wall time, so a slow stage
# shows in the log (SECONDS is bash's clock since the stage began).
stage_done() { echo "test.sh: stage '$1' took $SECONDS s"; SECONDS=0; }
SECONDS=0
"$ROOT/scripts/setup.sh"
stage_done setup+build
cd "$ROOT/build"
ctest --output-on-failure -j "${JOBS:-$(nproc)}" --timeout 1200
stage_done ctest
# Quick smoke runs of every benchmark (the figures are noisy; full runs: drop --quick).
for bench in vdblight_bench vdblight_bench_photons vdblight_bench_antialiased vdblight_bench_layouts vdblight_bench_bins vdblight_bench_prt vdblight_bench_converge vdblight_bench_error vdblight_bench_bake_speed vdblight_bench_prt_scale vdblight_bench_accuracy; do
  "$ROOT/build/bin/$bench" --quick
done
stage_done benchmarks
# Sanitizers (issue 8): the whole suite again under ASan + UBSan (build-sanitize/, clang, any
# report fails), then every libFuzzer harness, built in the same tree: each seed and regression
# input replayed, then FUZZ_RUNS inputs from a fixed seed (500 here, to keep CI within its 40 min;
# scripts/fuzz.sh alone runs 1000), so the verdict is the same on every
# run (docs/fuzzing.md; exploratory, time-based fuzzing is scripts/fuzz_explore.sh).
"$ROOT/scripts/test_sanitize.sh" all
stage_done sanitizers
FUZZ_BUILD_DIR="$ROOT/build-sanitize" "$ROOT/scripts/fuzz.sh" "${FUZZ_RUNS:-500}"
stage_done fuzz
