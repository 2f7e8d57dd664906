#!/usr/bin/env bash
# Assembles the browser demo into a static folder (default out/www/, git-ignored): the page from
# www/, the npm package from pkg/ (build it first: `make pkg`; `make www` does both) and the sample
# clips from tests/fixtures/. Any static file server works; scripts/serve-www.mjs is one.
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

# The built-in samples (www/js/samples.js lists them, with their origins and licences).
for f in bandai/dataset-2_walk_normal_001_f120.bvh bandai/dataset-2_walk_elderly_001_f120.bvh \
  bandai/dataset-1_walk_tired_001_f90.bvh bandai/dataset-2_raise-up-both-hands_active_001.bvh \
  foreign/m21_walk.bvh foreign/cmu31_xia_neutral_16_000.bvh foreign/iclone100_cmu_002_04.bvh; do
  cp "tests/fixtures/$f" "$out/samples/"
done
cp tests/fixtures/README.md "$out/samples/README.md"
echo "www: $(du -sh "$out" | cut -f1) in $out/"
