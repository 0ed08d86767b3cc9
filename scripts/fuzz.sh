#!/usr/bin/env bash
# The fuzz stage of the test command (scripts/test.sh, CI): the same verdict on every run of
# the same commit, on any machine. Builds the libFuzzer harnesses of tests/fuzz with clang
# (-fsanitize=fuzzer,address,undefined; only the modules they need) in build-fuzz/, or, given
# FUZZ_BUILD_DIR=build-sanitize (the test command), only links them in the sanitizer tree that
# scripts/test_sanitize.sh built with them (scripts/fuzz_build.sh), then for each harness
#   1. replays every seed and saved regression input of tests/fuzz/corpus/<harness>/ once;
#   2. fuzzes from those seeds with fixed seeds (-seed=1, then 2, ... after each documented
#      library finding) for a fixed number of inputs (RUNS, default 1000; FUZZ_RUNS), never
#      for a wall-clock budget, from a fresh corpus, so what it tries depends only on the commit.
# Every input that fails (crash, sanitizer report, leak, timeout, an allocation over the
# malloc limit) is re-run by tests/fuzz/triage.py: it passes only as a documented library
# signature (tests/fuzz/known_crashes.txt, lsan.supp); anything else fails the stage.
# Exploratory fuzzing (long, time-based, fork mode) is scripts/fuzz_explore.sh (docs/fuzzing.md).
#
#   scripts/fuzz.sh [RUNS]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
RUNS="${1:-${FUZZ_RUNS:-1000}}"
JOBS="${JOBS:-$(nproc)}"
source "$ROOT/tests/fuzz/harnesses.sh"   # HARNESSES, MALLOC_LIMIT_MB, RSS_LIMIT_MB
"$ROOT/scripts/fuzz_build.sh"

rm -rf "$BUILD/artifacts" "$BUILD/corpus" "$BUILD/tmp"
mkdir -p "$BUILD/artifacts" "$BUILD/logs" "$BUILD/tmp"
# The harnesses write each input to a private temporary directory that they remove at exit,
# but a harness that aborts (a sanitizer report, a known library finding) never reaches its
# exit handlers: keep those directories under build-fuzz/tmp, emptied here and at the end,
# instead of leaving them in /tmp.
export TMPDIR="$BUILD/tmp"
trap 'rm -rf "$BUILD/tmp"' EXIT
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
run_one() {
  local h="$1" seeds="$ROOT/tests/fuzz/corpus/$1" work="$BUILD/corpus/$1" status=0
  # 1. Replay: each seed and regression input on its own, through the same triage.
  python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" --inputs "$seeds" || status=1
  # 2. Fixed-seed, fixed-count fuzzing. Non-fork mode stops at the first failing input; a
  #    documented library finding is triaged and the run resumes from the corpus it has
  #    grown, with the next seed, for the runs that are left (at most MAX_RESUMES times).
  #    Each segment depends only on its seed and corpus (and, through libFuzzer's own
  #    allocations, on the checkout path), so the whole sequence is the same on every run
  #    (docs/fuzzing.md: what was measured, and the four things that made it differ).
  mkdir -p "$work"
  local done_runs=0 seed=1 log="$BUILD/logs/$h.log"
  : >"$log"
  while ((done_runs < RUNS && seed <= MAX_RESUMES)); do
    local artifacts="$BUILD/artifacts/$h-seed$seed-"
    LSAN_OPTIONS="suppressions=$ROOT/tests/fuzz/lsan.supp" $NO_ASLR \
    "$BUILD/tests/fuzz/$h" -seed="$seed" -runs="$((RUNS - done_runs))" -reload=0 -timeout=10 -rss_limit_mb="$RSS_LIMIT_MB" \
        -malloc_limit_mb="$MALLOC_LIMIT_MB" -artifact_prefix="$artifacts" "$work" "$seeds" >"$log.$seed" 2>&1 || true
    cat "$log.$seed" >>"$log"
    local last
    last="$(grep -oE '^#[0-9]+' "$log.$seed" | tail -1 | tr -d '#')"
    done_runs=$((done_runs + ${last:-0}))
    python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" "$artifacts" || { status=1; break; }
    grep -qE '^#[0-9]+[[:space:]]+DONE' "$log.$seed" && break
    seed=$((seed + 1))
  done
  echo "fuzz: $h: $done_runs inputs from seeds 1..$seed: $(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' "$log" | tail -1)"
  return $status
}
export -f run_one
MAX_RESUMES="${FUZZ_MAX_RESUMES:-20}"
# Address-space randomisation changes the order of pointer-keyed containers in the libraries,
# and so the coverage an input reaches and the corpus a seed grows (measured: the same glTF run
# reached cov 1093 or 1095): run the fuzzer with it off where setarch can (util-linux).
NO_ASLR=""
if setarch "$(uname -m)" -R true 2>/dev/null; then NO_ASLR="setarch $(uname -m) -R"; fi
export BUILD ROOT RUNS RSS_LIMIT_MB MALLOC_LIMIT_MB MAX_RESUMES NO_ASLR
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one {}'
echo "fuzz: every harness replayed its seeds and regression inputs and ran $RUNS inputs from fixed seeds with no new finding"
