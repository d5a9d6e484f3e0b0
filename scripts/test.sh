#!/usr/bin/env bash
# The whole test suite, as CI runs it: install packages, build release and run every
# test (fast, e2e and slow labels), then build with AddressSanitizer + UBSan and run
# all but the slow tests again, then the concurrent parts (the tsan preset's filter) under
# ThreadSanitizer. Evaluation data is read from ../shared/data when it
# exists (override with SPECHT_DATA_DIR); tests that need it skip without it.
# The sanitizer builds carry line tables only (-g1, CMakePresets.json): enough for
# their reports' stack traces, at a fraction of the disk full debug info takes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

"$root/scripts/setup.sh"

data_args=()
if [[ -n "${SPECHT_DATA_DIR:-}" ]]; then data_args=(-DSPECHT_DATA_DIR="$SPECHT_DATA_DIR"); fi

echo "== release build and tests"
cmake --preset release "${data_args[@]}" > /dev/null
cmake --build --preset release
ctest --preset release

if [[ "${SPECHT_SKIP_SANITIZERS:-0}" != "1" ]]; then
  echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
  cmake --preset asan "${data_args[@]}" > /dev/null
  cmake --build --preset asan
  ctest --preset asan
  echo "== ThreadSanitizer build and tests (the concurrent parts)"
  cmake --preset tsan "${data_args[@]}" > /dev/null
  cmake --build --preset tsan
  ctest --preset tsan
fi
