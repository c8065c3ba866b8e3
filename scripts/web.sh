#!/usr/bin/env bash
# Builds the browser page (web/): the model compiled to WebAssembly with Debian's Emscripten
# into one static folder, build-web/site (index.html, skin.js with the .wasm inside, app.js,
# style.css; no network access at run time). `scripts/web.sh --serve [PORT]` also serves it at
# http://localhost:PORT/ (default 8000) until interrupted.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v emcmake >/dev/null || [ ! -d /usr/share/nodejs/acorn ]; then
  bash scripts/install-deps.sh
fi
# Emscripten 3.1.6's JavaScript optimizer needs acorn (Debian node-acorn).
export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
# Emscripten finds no system headers: a folder holding only the header-only libraries.
third_party=build-web/third-party
mkdir -p "$third_party"
ln -sfn /usr/include/eigen3/Eigen "$third_party/Eigen"
ln -sfn /usr/include/boost "$third_party/boost"
ln -sfn /usr/include/nlohmann "$third_party/nlohmann"
gen=(); command -v ninja >/dev/null && gen=(-G Ninja)
# ccache (when installed) caches the compilations: emcc runs clang through it, and it keys them
# by paths relative to the checkout, so that a fresh build-web or clone reuses them (CI).
if command -v ccache >/dev/null; then
  export EM_COMPILER_WRAPPER=ccache CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
fi
emcmake cmake -S web -B build-web "${gen[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DSKIN_WEB_THIRD_PARTY="$PWD/$third_party" >/dev/null
cmake --build build-web
echo "web page: $PWD/build-web/site/index.html (serve it: bash scripts/web.sh --serve)"
if [ "${1:-}" = "--serve" ]; then
  port="${2:-8000}"
  echo "serving http://localhost:$port/ (Ctrl-C stops)"
  exec /usr/bin/python3 -m http.server "$port" --bind 127.0.0.1 --directory build-web/site
fi
