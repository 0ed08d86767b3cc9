#!/usr/bin/env bash
# The fuzz stage of the test command (scripts/test.sh, CI): the same verdict on every run of
# the same commit, on any machine. Builds the libFuzzer harnesses of tests/fuzz with clang
# (-fsanitize=fuzzer,address,undefined; only the modules they need) in build-fuzz/, then for
# each harness
#   1. replays every seed and saved regression input of tests/fuzz/corpus/<harness>/ once;
#   2. fuzzes from those seeds with a fixed seed (-seed=1) for a fixed number of inputs
#      (RUNS, default 2000; FUZZ_RUNS), never for a wall-clock budget, from a fresh copy of
#      the corpus, so that what it tries depends only on the commit.
# Every input that fails (crash, sanitizer report, leak, timeout, an allocation over the
# malloc limit) is re-run by tests/fuzz/triage.py: it passes only as a documented library
# signature (tests/fuzz/known_crashes.txt, lsan.supp); anything else fails the stage.
# Exploratory fuzzing (long, time-based, fork mode) is scripts/fuzz_explore.sh (docs/fuzzing.md).
#
#   scripts/fuzz.sh [RUNS]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
RUNS="${1:-${FUZZ_RUNS:-2000}}"
JOBS="${JOBS:-$(nproc)}"
source "$ROOT/tests/fuzz/harnesses.sh"   # HARNESSES, MALLOC_LIMIT_MB, RSS_LIMIT_MB
"$ROOT/scripts/fuzz_build.sh"

rm -rf "$BUILD/artifacts" "$BUILD/corpus"
mkdir -p "$BUILD/artifacts" "$BUILD/logs"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
run_one() {
  local h="$1" seeds="$ROOT/tests/fuzz/corpus/$1" work="$BUILD/corpus/$1" status=0
  # 1. Replay: each seed and regression input on its own, through the same triage.
  python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" --inputs "$seeds" || status=1
  # 2. Fixed-seed, fixed-count fuzzing (non-fork mode: it stops at the first failing input,
  #    which is then triaged; with the same seed it is the same input on every machine).
  mkdir -p "$work"
  "$BUILD/tests/fuzz/$h" -seed=1 -runs="$RUNS" -timeout=10 -rss_limit_mb="$RSS_LIMIT_MB" \
      -malloc_limit_mb="$MALLOC_LIMIT_MB" -artifact_prefix="$BUILD/artifacts/$h-" "$work" "$seeds" \
      >"$BUILD/logs/$h.log" 2>&1 || true
  local done_line
  done_line="$(grep -E '^#[0-9]+[[:space:]]+DONE' "$BUILD/logs/$h.log" | tail -1 || true)"
  if [ -n "$done_line" ]; then
    echo "fuzz: $h: $RUNS inputs from seed 1: $(echo "$done_line" | grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' || true)"
  else
    echo "fuzz: $h: stopped at a failing input (triaged below)"
  fi
  python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" "$BUILD/artifacts/$h-" || status=1
  return $status
}
export -f run_one
export BUILD ROOT RUNS RSS_LIMIT_MB MALLOC_LIMIT_MB
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one {}'
echo "fuzz: every harness replayed its seeds and ran $RUNS inputs from seed 1 with no new finding"
