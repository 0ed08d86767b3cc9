#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz with clang 14 in build-fuzz/ (FUZZ_BUILD_DIR).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${JOBS:-$(nproc)}"
source "$ROOT/tests/fuzz/harnesses.sh"
CC_BIN="${FUZZ_CC:-clang-14}" CXX_BIN="${FUZZ_CXX:-clang++-14}"
command -v "$CXX_BIN" >/dev/null || { echo "fuzz: $CXX_BIN not found (scripts/setup.sh installs clang-14 and libclang-rt-14-dev)"; exit 1; }
# The sanitizer tree of the test command (scripts/test_sanitize.sh: clang, VDBLIGHT_FUZZ on)
# already holds the harnesses: only (re)build them there, with its own flags.
if [ -f "$BUILD/CMakeCache.txt" ] && grep -q "^VDBLIGHT_SANITIZE:BOOL=ON" "$BUILD/CMakeCache.txt"; then
  grep -q "^VDBLIGHT_FUZZ:BOOL=ON" "$BUILD/CMakeCache.txt" ||
    { echo "fuzz: $BUILD is a sanitizer tree without the harnesses (built with gcc?): run scripts/test_sanitize.sh with clang"; exit 1; }
else
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" -DCMAKE_C_COMPILER="$CC_BIN" \
        -DCMAKE_CXX_COMPILER="$CXX_BIN" -DVDBLIGHT_FUZZ=ON -DVDBLIGHT_BUILD_TESTS=OFF -DVDBLIGHT_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$BUILD" -j "$JOBS" --target "${HARNESSES[@]}"
