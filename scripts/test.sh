#!/usr/bin/env bash
# Second command of the README: installs the Debian packages, builds everything with the tests
# and runs the whole suite with CTest. `scripts/test.sh --sanitize` does the same under
# AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
dir=build
opts=(-DCMAKE_BUILD_TYPE=Release)
if [ "${1:-}" = "--sanitize" ]; then
  dir=build-asan
  opts=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKIN_SANITIZE=ON -DSKIN_BUILD_BENCH=OFF)
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi
cmake -S . -B "$dir" -G Ninja -DSKIN_BUILD_TESTS=ON "${opts[@]}"
cmake --build "$dir"
ctest --test-dir "$dir" --output-on-failure -j 2
# The web page (scripts/web-test.sh: WebAssembly build, module and browser tests), once.
if [ "$dir" = build ]; then bash scripts/web-test.sh; fi
