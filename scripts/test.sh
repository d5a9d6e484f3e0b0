#!/usr/bin/env bash
# The whole test suite, as CI runs it, stage by stage with the time each took:
#   setup     install the Debian packages (scripts/setup.sh)
#   release   build and run every test (fast, e2e and slow labels)
#   asan      AddressSanitizer + UBSan build of the unit and parser tests, run (the e2e
#             runs of the binary stay in the release stage: what a sanitizer finds
#             there, the unit tests and the fuzzers reach more cheaply)
#   tsan      ThreadSanitizer build of the concurrent parts (the tsan preset's filter)
#   fuzz      the libFuzzer targets (clang, ASan + UBSan), each for SPECHT_FUZZ_SECONDS
#             (default 30) on seed corpora from the data directory (scripts/fuzz.sh)
# Evaluation data is read from ../shared/data when it exists (override with
# SPECHT_DATA_DIR); tests that need it skip without it, or fail with
# SPECHT_REQUIRE_DATA=1 (.ci/run sets it). SPECHT_CCACHE=OFF compiles without the
# compiler cache (a cold build); SPECHT_SKIP_SANITIZERS=1 runs the release stage only.
# The sanitizer builds carry line tables only (-g1, CMakePresets.json): enough for
# their reports' stack traces, at a fraction of the disk full debug info takes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

stages=()
start=$SECONDS
stage() {  # stage NAME: closes the previous stage's clock and opens this one
  local now=$SECONDS
  if [[ -n "${current:-}" ]]; then stages+=("$(printf '%-8s %5d s' "$current" $((now - stage_start)))"); fi
  current=$1
  stage_start=$now
  [[ $1 == done ]] || echo "== $1"
}
summary() {
  stage done
  echo "== stages (wall clock)"
  printf '  %s\n' "${stages[@]}"
  printf '  %-8s %5d s\n' total $((SECONDS - start))
}
trap summary EXIT

stage setup
"$root/scripts/setup.sh"

args=()
if [[ -n "${SPECHT_DATA_DIR:-}" ]]; then args+=(-DSPECHT_DATA_DIR="$SPECHT_DATA_DIR"); fi
if [[ -n "${SPECHT_CCACHE:-}" ]]; then args+=(-DSPECHT_CCACHE="$SPECHT_CCACHE"); fi

stage release
cmake --preset release "${args[@]}" > /dev/null
cmake --build --preset release
ctest --preset release

if [[ "${SPECHT_SKIP_SANITIZERS:-0}" != "1" ]]; then
  stage asan
  cmake --preset asan "${args[@]}" > /dev/null
  cmake --build --preset asan
  ctest --preset asan
  stage tsan
  cmake --preset tsan "${args[@]}" > /dev/null
  cmake --build --preset tsan
  ctest --preset tsan
  stage fuzz
  cmake --preset fuzz "${args[@]}" > /dev/null
  cmake --build --preset fuzz
  scripts/fuzz.sh "${SPECHT_FUZZ_SECONDS:-30}"
fi
