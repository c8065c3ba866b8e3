#!/usr/bin/env bash
# Second command of the README: installs the Debian packages, builds everything with the tests
# and runs the whole suite with CTest (Release, build/).
#   bash scripts/test.sh --sanitize   the same suite under AddressSanitizer +
#       UndefinedBehaviorSanitizer (clang, build-asan/, scripts/configure-asan.sh), then a short
#       run of every fuzz harness from the same build (scripts/fuzz.sh, SKIN_FUZZ_SECONDS per
#       target, default 5).
# CI (.ci/run) runs both.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
if [ "${1:-}" = "--sanitize" ]; then
  bash scripts/configure-asan.sh
  cmake --build build-asan
  # (print_suppressions=0: the fontconfig leak suppression of src/app/main.cpp stays silent, so
  # that commands print only their own lines)
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS=print_suppressions=0 \
    ctest --test-dir build-asan --output-on-failure -j 2
  bash scripts/fuzz.sh "${SKIN_FUZZ_SECONDS:-5}"
  exit 0
fi
cmake -S . -B build -G Ninja -DSKIN_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure -j 2
