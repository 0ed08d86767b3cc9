#!/usr/bin/env bash
# Builds the library and the given tests (default: the issue-8 tests) with AddressSanitizer
# and UndefinedBehaviorSanitizer in build-sanitize/ and runs them. A full run of every test
# is `scripts/test_sanitize.sh all` (slow: the whole project rebuilt with instrumentation).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SANITIZE_BUILD_DIR:-$ROOT/build-sanitize}"
TESTS=(adaptive_test many_lights_test stress_test)
[ "${1:-}" = "all" ] && TESTS=()
# -O1 (ASan's recommended level) compiles the OpenVDB- and Eigen-heavy files in about half the
# time of -O2, and CI must stay within 40 min; line tables only (file:line in reports); no
# benchmarks. clang 14 (scripts/setup.sh installs it) compiles this tree in 0.5-0.8 of gcc's
# CPU time (measured on vdb_read.cpp, bake/gather.cpp and cli_tiles_test.cpp), and with it the
# same tree also builds the libFuzzer harnesses (VDBLIGHT_FUZZ: coverage instrumentation too),
# so the fuzz stage of the test command reuses this build (scripts/fuzz.sh with
# FUZZ_BUILD_DIR=build-sanitize) instead of compiling the library a third time.
# SANITIZE_CXX=g++ builds with gcc instead (no harnesses).
CXX_BIN="${SANITIZE_CXX:-clang++-14}"
CC_BIN="${SANITIZE_CC:-$([ "$CXX_BIN" = g++ ] && echo gcc || echo clang-14)}"
command -v "$CXX_BIN" >/dev/null || { echo "sanitize: $CXX_BIN not found (scripts/setup.sh installs clang-14 and libclang-rt-14-dev; or SANITIZE_CXX=g++)"; exit 1; }
FUZZ=ON
[ "$CXX_BIN" = g++ ] && FUZZ=OFF
# A tree configured with another compiler cannot be switched in place: start it again.
if [ -f "$BUILD/CMakeCache.txt" ] && ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*$(basename "$CXX_BIN")\$" "$BUILD/CMakeCache.txt"; then
  rm -rf "$BUILD"
fi
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
      -DCMAKE_C_COMPILER="$CC_BIN" -DCMAKE_CXX_COMPILER="$CXX_BIN" \
      -DVDBLIGHT_SANITIZE=ON -DVDBLIGHT_FUZZ="$FUZZ" -DVDBLIGHT_BUILD_BENCH=OFF >/dev/null
# Any report stops the process with SIGABRT (UBSan is built with -fno-sanitize-recover), so a
# test fails, and so does a test whose spawned (sanitized) vdblight CLI reports.
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:abort_on_error=1
# gold (CMakeLists.txt) warns "Cannot export local symbol '__asan_...'" for every program
# clang's ASan runtime is linked into (thousands of lines, harmless: those helpers are local
# to the runtime): keep them out of the log.
build() { cmake --build "$BUILD" -j "${JOBS:-$(nproc)}" "$@" 2>&1 | { grep -v "Cannot export local symbol '__asan_" || true; }; }
if [ ${#TESTS[@]} -eq 0 ]; then
  build
  # The tests left out here run in the Release suite (scripts/sanitize_exclusions.sh says which
  # and why); the GPU-driver checks do run here (45 test-seconds; llvmpipe itself is not
  # instrumented).
  source "$ROOT/scripts/sanitize_exclusions.sh"
  (cd "$BUILD" && ctest --output-on-failure -j "${JOBS:-$(nproc)}" -LE "$SANITIZE_SKIP_LABELS" -E "$SANITIZE_SKIP_TESTS")
else
  build --target "${TESTS[@]}"
  for t in "${TESTS[@]}"; do "$BUILD/tests/$t"; done
fi
