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
# The Python package as users install it: pip into a fresh virtual environment (Debian's
# interpreter; no package index), reusing the module built above; its tests run on that copy.
if [ -z "${1:-}" ]; then
  venv="$PWD/$dir/venv"
  /usr/bin/python3 -m venv --system-site-packages --clear "$venv"
  SKIN_BUILD_DIR="$dir" "$venv/bin/pip" install --no-build-isolation --no-index -q .
  (cd "$dir" && SKIN_EXPECT_INSTALLED=1 SKIN_BINARY="$PWD/bin/skin" \
    "$venv/bin/python" ../tests/python/test_spectral_skin.py)
fi
# The web page (scripts/web-test.sh: WebAssembly build, module and browser tests), once.
if [ "$dir" = build ]; then bash scripts/web-test.sh; fi
