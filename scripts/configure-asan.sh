#!/usr/bin/env bash
# Configures the sanitizer build: the whole project built by clang with AddressSanitizer +
# UndefinedBehaviorSanitizer (SKIN_SANITIZE).
#   bash scripts/configure-asan.sh          build-asan/: the tests, and the fuzz harnesses with
#                                           coverage of their own code only (`scripts/test.sh
#                                           --sanitize`: the suite, then CI's short fuzz run)
#   bash scripts/configure-asan.sh --fuzz   build-fuzz/: the fuzz harnesses of fuzz/, every library
#                                           also with libFuzzer's coverage instrumentation
#                                           (SKIN_FUZZ; `scripts/fuzz.sh`, the campaigns)
# Two builds, because the coverage instrumentation makes the code it instruments ~3x slower
# (`skin fit --hex` 47 s instead of 17 s under ASan), which the tests need not pay; CI builds only
# the first. No benchmarks; no Python module (an instrumented module would need the sanitizer
# runtime preloaded into the interpreter; the bindings are thin and tested in Release).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=build-asan
flags=(-DSKIN_FUZZ=OFF -DSKIN_BUILD_TESTS=ON)
if [ "${1:-}" = "--fuzz" ]; then
  dir=build-fuzz
  flags=(-DSKIN_FUZZ=ON -DSKIN_BUILD_TESTS=OFF)
fi
# A build configured with another compiler (an older GCC sanitizer build) starts afresh.
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$dir/CMakeCache.txt"; then
  rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
fi
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"  # (scripts/test.sh)
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSKIN_SANITIZE=ON "${flags[@]}" -DSKIN_BUILD_BENCH=OFF -DSKIN_BUILD_PYTHON=OFF "${launcher[@]}" >/dev/null
