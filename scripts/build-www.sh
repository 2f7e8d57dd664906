#!/usr/bin/env bash
# Assembles the browser demo into a static folder (default out/www/, git-ignored): the page from
# www/, the npm package from pkg/ (build it first: `make pkg`; `make www` does both), three.js
# (npm, www/package.json) and the sample clips from tests/fixtures/. Any static file server works;
# scripts/serve-www.mjs is one.
#
#   scripts/build-www.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:-out/www}
if [[ ! -f pkg/index.js || ! -f pkg/engine_bg.wasm ]]; then
  echo "build-www: pkg/ is not built (run make pkg)" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out/samples"
cp www/index.html www/style.css "$out/"
cp -r www/js "$out/js"
cp -r pkg "$out/pkg"
rm -f "$out/pkg/.gitkeep"

# three.js for the 3D view, from npm at www/package-lock.json's version (installed once), copied
# into the site (no CDN: the demo works offline); index.html's import map points at it.
three=www/node_modules/three
locked=$(node -p 'require("./www/package-lock.json").packages["node_modules/three"].version')
esbuild=www/node_modules/.bin/esbuild
if [[ ! -f $three/package.json || $(node -p "require('./$three/package.json').version") != "$locked" || ! -x $esbuild || ! -f www/node_modules/fflate/esm/browser.js ]]; then
  (cd www && npm ci --no-audit --no-fund)
fi
# Minified (esbuild, www/package.json's devDependency): three.module.js with the three.core.js it
# imports in one file, 2.1 MB -> 0.7 MB (gzip 0.42 -> 0.17 MB), counted in the page's byte budget
# (bench/README.md); OrbitControls imports 'three' through index.html's import map.
mkdir -p "$out/vendor/three/addons/controls"
"$esbuild" "$three/build/three.module.js" --bundle --minify --format=esm --log-level=warning \
  --outfile="$out/vendor/three/three.module.js"
"$esbuild" "$three/examples/jsm/controls/OrbitControls.js" --bundle --minify --format=esm --external:three --log-level=warning \
  --outfile="$out/vendor/three/addons/controls/OrbitControls.js"
cp "$three/LICENSE" "$out/vendor/three/"
# fflate reads a weights .zip dropped on the page (loaded only then, not counted before the first result).
mkdir -p "$out/vendor/fflate"
cp www/node_modules/fflate/esm/browser.js www/node_modules/fflate/LICENSE "$out/vendor/fflate/"

# The built-in samples (www/js/samples.js lists them, with their origins and licences).
for f in bandai/dataset-2_walk_normal_001_f120.bvh bandai/dataset-2_walk_elderly_001_f120.bvh \
  bandai/dataset-1_walk_tired_001_f90.bvh bandai/dataset-2_raise-up-both-hands_active_001.bvh \
  foreign/m21_walk.bvh foreign/cmu31_xia_neutral_16_000.bvh foreign/iclone100_cmu_002_04.bvh; do
  cp "tests/fixtures/$f" "$out/samples/"
done
cp tests/fixtures/README.md "$out/samples/README.md"
echo "www: $(du -sh "$out" | cut -f1) in $out/"
