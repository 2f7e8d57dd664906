#!/usr/bin/env bash
# Builds pkg/, the npm package `motion-stylizer`: the crate compiled to wasm32-unknown-unknown
# (feature `wasm`, Burn flex with wasm SIMD: see .cargo/config.toml; and again with `wgpu`, the
# WebGPU engine), wasm-bindgen --target web
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
# --experimental-reset-state-function: engine.js's __wbg_reset_state, with which the JS wrapper
# replaces an instance that trapped (the panic backstop, js/index.js) by a fresh one.
wasm-bindgen --target web --experimental-reset-state-function --out-dir "$out" --out-name engine \
  "$target_dir/wasm32-unknown-unknown/release/motion_stylizer.wasm"
# The WebGPU engine (issue 16): the same crate with Burn's wgpu runtime (feature `wgpu` on
# wasm32: WebGPU through navigator.gpu), a second wasm file the JS imports only for
# `backend: 'webgpu'`. Its own target folder: the two feature sets' Burn builds stay side by side.
# WEBGPU=0 leaves it out (the package then falls back to the CPU, saying so). Built for size
# (Cargo.toml's `wasm-size` profile: its arithmetic runs on the GPU) and without its name section:
# 12.8 MB, 2.6 MB gzipped, against 28.6 and 4.5 as a release build (bench/README.md).
if [[ "${WEBGPU:-1}" != 0 ]]; then
  gpu_target=${WEBGPU_TARGET_DIR:-$target_dir/webgpu}
  cargo build --profile wasm-size --lib --target wasm32-unknown-unknown --no-default-features --features "$features,wgpu" \
    --target-dir "$gpu_target"
  wasm-bindgen --target web --experimental-reset-state-function --remove-name-section --out-dir "$out" --out-name engine-webgpu \
    "$gpu_target/wasm32-unknown-unknown/wasm-size/motion_stylizer.wasm"
fi
rm -f "$out/.gitignore"
cp js/index.js js/index.d.ts js/README.md "$out/"
cp LICENSE* "$out/" 2>/dev/null || true

# The shipped weights: every file of assets/weights/ (manifest, statistics, one bundle per setting,
# their README). The package's JS is the one reader of the manifest.
find assets/weights -maxdepth 1 -type f -exec cp {} "$out/weights/" \;
# Their fingerprint (FNV-1a 32 of manifest.json, which lists every other file's size and FNV-1a
# 64) into index.js: a browser with them in its cache fetches nothing, not even the manifest.
node -e '
  const fs = require("fs");
  let h = 0x811c9dc5;
  for (const b of fs.readFileSync(process.argv[1])) h = Math.imul(h ^ b, 0x01000193) >>> 0;
  const id = h.toString(16).padStart(8, "0");
  const js = fs.readFileSync(process.argv[2], "utf8");
  const line = "const BUNDLED_WEIGHTS_ID = null;";
  if (!js.includes(line)) throw new Error("index.js has no " + line);
  fs.writeFileSync(process.argv[2], js.replace(line, `const BUNDLED_WEIGHTS_ID = "${id}";`));
' "$out/weights/manifest.json" "$out/index.js"

# package.json with the crate's version.
version=$(awk -F'"' '/^version = / { print $2; exit }' Cargo.toml)
node -e '
  const fs = require("fs");
  const p = JSON.parse(fs.readFileSync("js/package.json", "utf8"));
  p.version = process.argv[1];
  fs.writeFileSync(process.argv[2], JSON.stringify(p, null, 2) + "\n");
' "$version" "$out/package.json"
echo "pkg: $(du -sh "$out" | cut -f1) in $out/ (motion-stylizer $version)"
