#!/usr/bin/env bash
# Second command of the README: installs the Debian packages, builds everything with the tests
# and runs the whole suite with CTest (Release, build/), then the Python package as users install
# it and the web page's tests.
#   bash scripts/test.sh --sanitize   the same suite under AddressSanitizer +
#       UndefinedBehaviorSanitizer (clang, build-asan/, scripts/configure-asan.sh), then a short
#       run of every fuzz harness built there (scripts/fuzz.sh, SKIN_FUZZ_SECONDS per target,
#       default 3; the campaigns' fully instrumented build-fuzz/ is not built).
# CI (.ci/run) runs both.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each step's wall time is printed after it ("[time] step: N s"), so that every run, CI's
# included, gives its own breakdown.
timed() {
  local name=$1 t0=$SECONDS
  shift
  "$@"
  echo "[time] $name: $((SECONDS - t0)) s"
}
timed "install dependencies" bash scripts/install-deps.sh
# ccache (when installed) keys compilations by paths relative to the checkout, so that a fresh
# clone elsewhere on the same machine (CI) reuses them.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
export CCACHE_NOHASHDIR=1  # (the sanitizer build's debug info then names the first checkout)
if [ "${1:-}" = "--sanitize" ]; then
  # Tests left to the Release suite: accuracy and bit-identity checks whose code cheaper tests run
  # under the sanitizers (tests/release-only.txt: the list and its reasons).
  listed=$(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^$/d' tests/release-only.txt | sort)
  release_only="^($(sed 's/\./\\./g' <<<"$listed" | paste -sd '|'))\$"
  bash scripts/configure-asan.sh
  timed "sanitizer build" cmake --build build-asan
  # A name that matches no test (renamed, removed) would leave nothing out: refused.
  stale=$(comm -23 <(echo "$listed") <(ctest --test-dir build-asan -N | sed -n 's/^ *Test *#[0-9]*: \([^ ]*\).*/\1/p' | sort))
  if [ -n "$stale" ]; then
    echo "tests/release-only.txt names tests that do not exist: $stale" >&2
    exit 1
  fi
  # (print_suppressions=0: the fontconfig leak suppression of src/app/main.cpp stays silent, so
  # that commands print only their own lines)
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS=print_suppressions=0 \
    timed "sanitizer suite" ctest --test-dir build-asan --output-on-failure -j 2 -E "$release_only"
  SKIN_FUZZ_DIR=build-asan timed "fuzz smoke" bash scripts/fuzz.sh "${SKIN_FUZZ_SECONDS:-3}"
  exit 0
fi
dir=build
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$dir" -G Ninja -DSKIN_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
timed "Release build" cmake --build "$dir"
timed "Release suite" ctest --test-dir "$dir" --output-on-failure -j 2
# The Python package as users install it: pip into a fresh virtual environment (Debian's
# interpreter; no package index), reusing the module built above; its tests run on that copy.
venv="$PWD/$dir/venv"
/usr/bin/python3 -m venv --system-site-packages --clear "$venv"
SKIN_BUILD_DIR="$dir" "$venv/bin/pip" install --no-build-isolation --no-index -q .
(cd "$dir" && SKIN_EXPECT_INSTALLED=1 SKIN_BINARY="$PWD/bin/skin" \
  timed "Python package tests" "$venv/bin/python" ../tests/python/test_spectral_skin.py)
# The web page (scripts/web-test.sh: WebAssembly build, module and browser tests).
timed "web tests" bash scripts/web-test.sh
