#!/usr/bin/env bash
# Quick start, command 2: set up (packages + build) and run the whole test suite (CTest),
# then a quick smoke run of the benchmark.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/setup.sh"
cd "$ROOT/build"
ctest --output-on-failure -j "${JOBS:-$(nproc)}" --timeout 1200
"$ROOT/build/bin/vdblight_bench" --quick
"$ROOT/build/bin/vdblight_bench_photons" --quick
"$ROOT/build/bin/vdblight_bench_antialiased" --quick
"$ROOT/build/bin/vdblight_bench_layouts" --quick
"$ROOT/build/bin/vdblight_bench_bins" --quick
"$ROOT/build/bin/vdblight_bench_prt" --quick
"$ROOT/build/bin/vdblight_bench_converge" --quick
"$ROOT/build/bin/vdblight_bench_error" --quick
