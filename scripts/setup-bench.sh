#!/usr/bin/env bash
# Installs what `make bench-perf` compares against and builds with, into git-ignored places (idempotent):
#   - the wasm32-wasip1 Rust target (our side in wasm runs under Node's WASI);
#   - bench/perf/.venv: PyTorch (CPU use; the PyPI wheel, which on Linux pulls in the CUDA runtime
#     wheels, ~5 GB in all, none of it loaded on a machine without a GPU), onnx, numpy;
#   - bench/perf/node_modules: onnxruntime-web from npm (package-lock.json pins it).
set -euo pipefail
cd "$(dirname "$0")/.."

rustup target list --installed 2>/dev/null | grep -q '^wasm32-wasip1$' || rustup target add wasm32-wasip1

venv=bench/perf/.venv
torch_version=${TORCH_VERSION:-2.15.0}
[[ -x $venv/bin/python ]] || python3 -m venv "$venv"
py=$venv/bin/python
if ! "$py" -c 'import torch, onnx, numpy' 2>/dev/null; then
  df -h "$venv" | tail -1 | awk '{ print "setup-bench: installing PyTorch " "'"$torch_version"'" " (~5 GB) into bench/perf/.venv, " $4 " free" }'
  "$py" -m pip install --quiet "torch==$torch_version" numpy onnx
fi
"$py" -c 'import torch; print("setup-bench: torch", torch.__version__)'

(cd bench/perf && npm ci --no-audit --no-fund --silent)
