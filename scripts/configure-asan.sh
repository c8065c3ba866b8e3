#!/usr/bin/env bash
# Configures build-asan/: the whole project (tests and the fuzz harnesses of fuzz/) built by clang
# with AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer's coverage instrumentation
# (SKIN_SANITIZE, SKIN_FUZZ). One instrumented build serves `scripts/test.sh --sanitize` and
# `scripts/fuzz.sh`. No benchmarks; no Python module (an instrumented module would need the
# sanitizer runtime preloaded into the interpreter; the bindings are thin and tested in Release).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=build-asan
# A build-asan/ configured with another compiler (an older GCC sanitizer build) starts afresh.
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$dir/CMakeCache.txt"; then
  rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
fi
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"  # (scripts/test.sh)
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSKIN_SANITIZE=ON -DSKIN_FUZZ=ON -DSKIN_BUILD_TESTS=ON -DSKIN_BUILD_BENCH=OFF \
  -DSKIN_BUILD_PYTHON=OFF "${launcher[@]}" >/dev/null
