#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz with clang (-fsanitize=fuzzer,address,undefined;
# only the modules they need) in build-fuzz/ and runs each for SECONDS (default 60) from its
# seed corpus in tests/fuzz/corpus/<harness>/, JOBS harnesses at a time. Fails on any crash,
# sanitizer report, leak, timeout (10 s per input) or out-of-memory (2 GB) other than the
# documented library signatures (tests/fuzz/lsan.supp, tests/fuzz/known_crashes.txt); the
# inputs are kept as build-fuzz/artifacts/<harness>-{crash,leak,oom,timeout}-* (reproduce:
# build-fuzz/tests/fuzz/<harness> FILE).
#
#   scripts/fuzz.sh [SECONDS]        # CI: scripts/test.sh runs it with 60
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
SECONDS_EACH="${1:-60}"
JOBS="${JOBS:-$(nproc)}"
HARNESSES=(fuzz_scene_obj fuzz_scene_ply fuzz_scene_gltf fuzz_scene_glb fuzz_vdb)
CC_BIN="${FUZZ_CC:-clang-14}" CXX_BIN="${FUZZ_CXX:-clang++-14}"
command -v "$CXX_BIN" >/dev/null || { echo "fuzz: $CXX_BIN not found (scripts/setup.sh installs clang-14 and libclang-rt-14-dev)"; exit 1; }

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" -DCMAKE_C_COMPILER="$CC_BIN" \
      -DCMAKE_CXX_COMPILER="$CXX_BIN" -DVDBLIGHT_FUZZ=ON -DVDBLIGHT_BUILD_TESTS=OFF -DVDBLIGHT_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target "${HARNESSES[@]}"

rm -rf "$BUILD/artifacts"
mkdir -p "$BUILD/artifacts" "$BUILD/logs"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
run_one() {
  local h="$1" work="$BUILD/corpus/$1"
  mkdir -p "$work"
  # Fork mode keeps fuzzing after a finding; every artifact is then re-run and must be a
  # leak covered by tests/fuzz/lsan.supp or a library signature in tests/fuzz/known_crashes.txt
  # (exact frames, documented). New inputs go to the scratch corpus; the seeds are only read.
  "$BUILD/tests/fuzz/$h" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -max_total_time="$SECONDS_EACH" \
      -timeout=10 -rss_limit_mb=2048 -seed=1 -artifact_prefix="$BUILD/artifacts/$h-" "$work" \
      "$ROOT/tests/fuzz/corpus/$h" >"$BUILD/logs/$h.log" 2>&1 || true
  if ! grep -q "INFO: fuzzed for" "$BUILD/logs/$h.log"; then
    echo "fuzz: $h did not run to its time limit (log $BUILD/logs/$h.log):"; tail -20 "$BUILD/logs/$h.log"; return 1
  fi
  echo "fuzz: $h: $(grep -oE '^#[0-9]+' "$BUILD/logs/$h.log" | tail -1 | tr -d '#') inputs in ${SECONDS_EACH} s"
  python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" "$BUILD/artifacts/$h-"
}
export -f run_one
export BUILD ROOT SECONDS_EACH
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one {}'
echo "fuzz: every harness ran ${SECONDS_EACH} s with no new finding"
