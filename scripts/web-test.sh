#!/usr/bin/env bash
# The web page's tests (called by scripts/test.sh after CTest; needs build/bin/skin): installs
# the pinned npm packages (`npm ci` in web/: puppeteer-core, gltf-validator, three, axe-core), then
#   web/test/gltf.test.js     `skin export --target gltf` through Khronos' glTF-Validator (0
#                             errors) and three.js's GLTFLoader (the material's values)
# and builds the page (scripts/web.sh), then
#   web/test/module.test.js   the WebAssembly module against `skin` (random parameter sets, fit)
#   web/test/browser.test.js  the page in headless Chromium (puppeteer-core; it downloads no
#                             browser), screenshots and update time in build-web/screenshots.
#   web/test/inputs.test.js   bad text typed into every parameter field of the page (the same
#                             browser): flagged, results dimmed, nothing computed; restored.
#   web/test/page.test.js     the page's usability: log sliders, file picker, state in the URL,
#                             legends and plot text, fit bound markers and poor-fit warning,
#                             layout at 390 and 1280 px, axe-core (0 violations), and the median
#                             frame time of 40 slider updates from a Chrome trace (printed;
#                             SKIN_FRAME_BUDGET_MS=16 makes it a limit).
#   web/test/head.test.js     the 3D view (#view3d, WebGL2 on SwiftShader): a lit head (a sphere
#                             without the mesh), the realtime export's kernels, melanin changes
#                             the pixels (input-to-frame time printed; SKIN_VIEW_LATENCY_MS=50
#                             makes it a limit), the lit patch within 1 dE2000 of every preset,
#                             the blush/pallor brush, a mesh of one's own (picker, drop, bad files).
#   web/test/head-render.test.js  the 3D view against `skin render` of its own scene (camera,
#                             lights, scale): mean dE2000 <= 3 over the skin pixels (caucasian,
#                             african), the shadow edge's 10-90 % width per channel within 20 %;
#                             skipped without the head mesh. Writes head-vs-render.png (the
#                             README's figure) to build-web/screenshots.
# Skips with a message only where Emscripten or the browser cannot be installed. Each step's wall
# time is printed after it.
set -euo pipefail
cd "$(dirname "$0")/.."
timed() {
  local t0=$SECONDS
  "$@"
  echo "[$* took $((SECONDS - t0)) s]"
}
(cd web && timed npm ci --no-audit --no-fund --loglevel=error)
timed node web/test/gltf.test.js
if ! command -v emcmake >/dev/null; then
  echo "SKIP web tests: Debian's emscripten is not installed (scripts/install-deps.sh installs it)"
  exit 0
fi
timed bash scripts/web.sh
timed node web/test/module.test.js
if [ ! -x /usr/bin/chromium ]; then
  echo "SKIP browser test: Debian's chromium is not installed (scripts/install-deps.sh installs it)"
  exit 0
fi
timed node web/test/browser.test.js
timed node web/test/inputs.test.js
timed node web/test/page.test.js
timed node web/test/head.test.js
timed node web/test/head-render.test.js
