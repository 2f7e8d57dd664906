#!/usr/bin/env bash
# Builds pkg/, the npm package `motion-stylizer`: the crate compiled to wasm32-unknown-unknown
# (feature `wasm`, Burn flex with wasm SIMD: see .cargo/config.toml), wasm-bindgen --target web
# (Node ESM, browsers and Web Workers without a bundler), the JS wrapper and types from js/, and
# the shipped weights from assets/weights/.
#
#   scripts/build-pkg.sh                 # what `make pkg` runs
#   WASM_FEATURES=model,wasm,ndarray scripts/build-pkg.sh   # also the ndarray backend
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/setup-wasm.sh
features=${WASM_FEATURES:-model,wasm}
target_dir=${CARGO_TARGET_DIR:-target}
cargo build --release --lib --target wasm32-unknown-unknown --no-default-features --features "$features"

out=pkg
find "$out" -mindepth 1 ! -name .gitkeep -delete 2>/dev/null || true
mkdir -p "$out/weights"
wasm-bindgen --target web --out-dir "$out" --out-name engine \
  "$target_dir/wasm32-unknown-unknown/release/motion_stylizer.wasm"
rm -f "$out/.gitignore"
cp js/index.js js/index.d.ts js/README.md "$out/"
cp LICENSE* "$out/" 2>/dev/null || true

# The weights the manifest lists (manifest, statistics, one bundle per setting).
weights=assets/weights
cp "$weights/manifest.json" "$out/weights/"
node -e '
  const m = require(process.argv[1]);
  for (const f of [m.norm, ...m.models.map((e) => e.file)]) console.log(f);
' "$PWD/$weights/manifest.json" | while read -r f; do cp "$weights/$f" "$out/weights/"; done
cp "$weights/README.md" "$out/weights/" 2>/dev/null || true

# package.json with the crate's version.
version=$(awk -F'"' '/^version = / { print $2; exit }' Cargo.toml)
node -e '
  const fs = require("fs");
  const p = JSON.parse(fs.readFileSync("js/package.json", "utf8"));
  p.version = process.argv[1];
  fs.writeFileSync(process.argv[2], JSON.stringify(p, null, 2) + "\n");
' "$version" "$out/package.json"
echo "pkg: $(du -sh "$out" | cut -f1) in $out/ (motion-stylizer $version)"
