#!/usr/bin/env bash
# Installs the Debian packages Spectral Skin builds with. Idempotent; safe to re-run.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config ccache  # ccache: rebuilds (CI reuses this machine's cache)
  libgtest-dev libgmock-dev libbenchmark-dev       # tests, benchmarks
  libeigen3-dev libboost-dev                       # linear algebra, Boost.Math (quadrature, Bessel)
  libcli11-dev nlohmann-json3-dev                  # command line, JSON
  libtbb-dev libembree-dev                         # threads, ray intersection (renderer, Monte Carlo)
  libtinyobjloader-dev libtinygltf-dev libstb-dev  # meshes and texture decoding
  libopenexr-dev libpng-dev libjpeg62-turbo-dev    # image output; JPEG textures (libjpeg-turbo)
  libcairo2-dev                                    # plots (PNG and SVG)
  pybind11-dev python3-dev                         # Python module
  blender                                          # proves `skin export --target cycles` in Cycles
  python3-numpy python3-pybind11 python3-setuptools python3-venv python3-pip python3-wheel
                                                   # Python package: numpy results, pip install
                                                   # into a venv (scripts/test.sh)
  python3-hypothesis                               # property-based tests of the Python API
  python3-dask python3-distributed                 # spectral_skin.distributed (fits, sweeps on a Dask cluster)
  python3-matplotlib                               # Python example (examples/melanin_sweep.py)
  emscripten node-acorn                            # web page: WebAssembly build (acorn: its JS optimizer)
  chromium                                         # web page: the browser test (headless)
  clang libclang-rt-14-dev llvm-14                 # sanitizer build, libFuzzer, symbolized reports (configure-asan.sh)
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# The web page's tests run Node.js and npm (puppeteer-core): Debian's, unless a Node.js that
# brings its own npm is installed (NodeSource's conflicts with Debian's npm package).
if ! command -v npm >/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm
fi
