#!/usr/bin/env bash
# First command of the README: installs the Debian packages, builds Spectral Skin (Release) and
# runs the main job on its built-in default: a render of the default scene (three skin types,
# a key light and a back light showing translucency) and the spectrum of the caucasian preset.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSKIN_BUILD_TESTS=OFF -DSKIN_BUILD_BENCH=ON
cmake --build build
build/bin/skin spectrum --preset caucasian --lambda-step 20 --format table --plot skin-spectrum.png
build/bin/skin render -o skin-default.png
echo "Wrote skin-default.png (render of the default scene) and skin-spectrum.png."
