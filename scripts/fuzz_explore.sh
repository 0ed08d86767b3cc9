#!/usr/bin/env bash
# Exploratory fuzzing, NOT part of the test command (docs/fuzzing.md): every harness of
# tests/fuzz for SECONDS of wall-clock time (default 600) in fork mode, which keeps going
# after a finding, from the seeds plus a scratch corpus kept in build-fuzz/explore/<harness>/
# across runs. What it finds depends on the machine and on luck, which is why CI does not
# run it. Every artifact is re-run by tests/fuzz/triage.py; a NEW finding becomes a
# regression input (copy it to tests/fuzz/corpus/<harness>/regression-<what>.<ext>) plus a
# fix, or, when it is inside a library and cannot be guarded from our side, an entry in
# tests/fuzz/known_crashes.txt with its reason.
#
#   scripts/fuzz_explore.sh [SECONDS] [HARNESS...]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
SECONDS_EACH="${1:-600}"
shift || true
JOBS="${JOBS:-$(nproc)}"
source "$ROOT/tests/fuzz/harnesses.sh"
if (($#)); then HARNESSES=("$@"); fi
"$ROOT/scripts/fuzz_build.sh"

rm -rf "$BUILD/explore-artifacts" "$BUILD/explore-tmp"
mkdir -p "$BUILD/explore-artifacts" "$BUILD/logs" "$BUILD/explore-tmp"
# Aborted harness processes skip their exit handlers: their input directories go here, not /tmp.
export TMPDIR="$BUILD/explore-tmp"
trap 'rm -rf "$BUILD/explore-tmp"' EXIT
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
run_one() {
  local h="$1" work="$BUILD/explore/$1"
  mkdir -p "$work"
  "$BUILD/tests/fuzz/$h" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -max_total_time="$SECONDS_EACH" \
      -timeout=10 -rss_limit_mb="$RSS_LIMIT_MB" -malloc_limit_mb="$MALLOC_LIMIT_MB" \
      -artifact_prefix="$BUILD/explore-artifacts/$h-" "$work" "$ROOT/tests/fuzz/corpus/$h" \
      >"$BUILD/logs/explore-$h.log" 2>&1 || true
  echo "fuzz_explore: $h: $(grep -oE '^#[0-9]+' "$BUILD/logs/explore-$h.log" | tail -1 | tr -d '#') inputs in ${SECONDS_EACH} s"
  python3 "$ROOT/tests/fuzz/triage.py" "$BUILD/tests/fuzz/$h" "$BUILD/explore-artifacts/$h-"
}
export -f run_one
export BUILD ROOT SECONDS_EACH RSS_LIMIT_MB MALLOC_LIMIT_MB
printf '%s\n' "${HARNESSES[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_one {}'
echo "fuzz_explore: no new finding (artifacts: $BUILD/explore-artifacts)"
