#!/usr/bin/env bash
# BVH parsing, ours vs three.js, on the same text:
#   bench/bvh_parse/run.sh [FILE.bvh] [ITERATIONS]
# FILE defaults to the full Bandai dataset-2 walk (data/dataset-2/data/dataset-2_walk_normal_001.bvh, see `make data`)
# when present, else its 120-frame cut in tests/fixtures. Prints each side's ms/parse, MB/s, frames/s and
# the ratio ours ÷ three.js (lower is better). With the wasm32-wasip1 target installed
# (rustup target add wasm32-wasip1), also times our reader compiled to wasm, run in Node.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
full="$repo/data/dataset-2/data/dataset-2_walk_normal_001.bvh"
file="${1:-$([ -f "$full" ] && echo "$full" || echo "$repo/tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh")}"
iters="${2:-200}"
target_dir="$repo/target/bvh-parse-bench"

cargo build --release --quiet --manifest-path "$here/Cargo.toml" --target-dir "$target_dir"
[ -d "$repo/tests/js/node_modules/three" ] || (cd "$repo/tests/js" && npm ci --no-audit --no-fund --silent)

echo "file: $file ($(wc -c < "$file") bytes)"
# Shows a run's report and keeps its `RESULT ms_per_parse=` number in $ms.
run() {
  local out
  out=$("$@")
  grep -v '^RESULT' <<< "$out"
  ms=$(sed -n 's/^RESULT ms_per_parse=//p' <<< "$out")
}
run "$target_dir/release/bvh-parse-bench" "$file" "$iters"
ours=$ms
run node "$here/threejs.mjs" "$file" "$iters"
three=$ms
awk -v o="$ours" -v t="$three" 'BEGIN { printf "ratio ours (native) / three.js: %.4f (three.js takes %.1fx as long)\n", o / t, t / o }'

if rustup target list --installed 2>/dev/null | grep -q '^wasm32-wasip1$'; then
  cargo build --release --quiet --manifest-path "$here/Cargo.toml" --target-dir "$target_dir" --target wasm32-wasip1
  run node --no-warnings "$here/wasi.mjs" "$target_dir/wasm32-wasip1/release/bvh-parse-bench.wasm" "$file" "$iters"
  wasm=$ms
  awk -v o="$wasm" -v t="$three" 'BEGIN { printf "ratio ours (wasm32) / three.js: %.4f (three.js takes %.1fx as long)\n", o / t, t / o }'
else
  echo "(wasm32-wasip1 target not installed: wasm timing skipped)"
fi
