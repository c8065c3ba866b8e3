#!/usr/bin/env bash
# Builds the browser page (web/): the model compiled to WebAssembly with Debian's Emscripten
# into one static folder, build-web/site (index.html, skin.js and skin.wasm, skin-file.js, app.js,
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
# three.js for the 3D view (web/page/view3d.js), from the pinned npm package (web/package.json),
# into the site: the page loads nothing from the network.
three=web/node_modules/three
if [ ! -f "$three/build/three.module.js" ] && command -v npm >/dev/null; then
  (cd web && npm ci --no-audit --no-fund --loglevel=error)
fi
if [ -f "$three/build/three.module.js" ]; then
  rm -rf build-web/site/three
  mkdir -p build-web/site/three/build build-web/site/three/addons/controls build-web/site/three/addons/loaders \
    build-web/site/three/addons/utils build-web/site/three/addons/libs
  cp "$three/build/three.module.js" "$three/build/three.core.js" "$three/LICENSE" build-web/site/three/build/
  cp "$three/examples/jsm/controls/OrbitControls.js" build-web/site/three/addons/controls/
  cp "$three/examples/jsm/loaders/GLTFLoader.js" "$three/examples/jsm/loaders/OBJLoader.js" build-web/site/three/addons/loaders/
  cp "$three/examples/jsm/libs/fflate.module.js" build-web/site/three/addons/libs/  # (maps.js)
  cp "$three/examples/jsm/utils/BufferGeometryUtils.js" "$three/examples/jsm/utils/SkeletonUtils.js" \
    build-web/site/three/addons/utils/
else
  echo "web page: no three.js (npm ci in web/ failed): the page works without its 3D view"
fi
# The Lee Perry-Smith head scan (CC BY 3.0, credited on the page) when the shared data holds it;
# never committed. Without it the 3D view shows a sphere.
head_dir="${SKIN_HEAD_MESH_DIR:-../shared/data/meshes/LeePerrySmith}"
rm -rf build-web/site/mesh
if [ -f "$head_dir/LeePerrySmith.glb" ]; then
  mkdir -p build-web/site/mesh
  cp "$head_dir/LeePerrySmith.glb" build-web/site/mesh/
  [ -f "$head_dir/LeePerrySmith_License.txt" ] && cp "$head_dir/LeePerrySmith_License.txt" build-web/site/mesh/
else
  echo "web page: no head mesh at $head_dir (the 3D view shows a sphere)"
fi
echo "web page: $PWD/build-web/site/index.html (serve it: bash scripts/web.sh --serve)"
if [ "${1:-}" = "--serve" ]; then
  port="${2:-8000}"
  echo "serving http://localhost:$port/ (Ctrl-C stops)"
  exec /usr/bin/python3 -m http.server "$port" --bind 127.0.0.1 --directory build-web/site
fi
