#!/usr/bin/env bash
# Builds the library and the given tests (default: the issue-8 tests) with AddressSanitizer
# and UndefinedBehaviorSanitizer in build-sanitize/ and runs them. A full run of every test
# is `scripts/test_sanitize.sh all` (slow: the whole project rebuilt with instrumentation).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${SANITIZE_BUILD_DIR:-$ROOT/build-sanitize}"
TESTS=(adaptive_test many_lights_test stress_test)
[ "${1:-}" = "all" ] && TESTS=()
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVDBLIGHT_SANITIZE=ON >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [ ${#TESTS[@]} -eq 0 ]; then
  cmake --build "$BUILD" -j "${JOBS:-$(nproc)}"
  (cd "$BUILD" && ctest --output-on-failure -j "${JOBS:-$(nproc)}")
else
  cmake --build "$BUILD" -j "${JOBS:-$(nproc)}" --target "${TESTS[@]}"
  for t in "${TESTS[@]}"; do "$BUILD/tests/$t"; done
fi
