# The two commands of the README: `make demo` and `make test`.
SHELL := bash
.SHELLFLAGS := -eu -o pipefail -c
CARGO ?= cargo
DEMO_OUT ?= out/demo
EVAL_REPEATS ?= 10
# the four foreign-rig files: 120 repeats (480 outputs a row); 30 could not resolve the 1 % weights gate (EVALUATION.md)
EVAL_FOREIGN_REPEATS ?= 120

DATA_SRC ?= ../shared/data/bandai-namco

.PHONY: eval data demo test test-rust test-js setup-js bench fuzz clean pkg setup-wasm test-wasm bench-wasm

## demo: build the CLI and run it on the bundled clips: inspect, retarget onto the canonical rig and back, stylize
demo:
	$(CARGO) build --release --bin motion-stylizer
	mkdir -p $(DEMO_OUT)
	for f in tests/fixtures/foreign/*.bvh tests/fixtures/bandai/dataset-2_walk_elderly_001_f120.bvh; do \
	  name=$$(basename $$f .bvh); \
	  ./target/release/motion-stylizer inspect $$f; \
	  ./target/release/motion-stylizer retarget $$f -o $(DEMO_OUT)/$$name.canonical.bvh; \
	  ./target/release/motion-stylizer retarget $(DEMO_OUT)/$$name.canonical.bvh --onto $$f -o $(DEMO_OUT)/$$name.back.bvh; \
	done
	./target/release/motion-stylizer styles
	for label in old proud tired; do \
	  ./target/release/motion-stylizer stylize tests/fixtures/foreign/m21_walk.bvh --label $$label --seed 1 -o $(DEMO_OUT)/m21_walk.$$label.bvh; \
	done
	./target/release/motion-stylizer stylize tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh \
	  --style-motion tests/fixtures/bandai/dataset-2_walk_elderly_001_f120.bvh --unsupervised -o $(DEMO_OUT)/walk_normal.like_elderly.bvh
	./target/release/motion-stylizer stylize tests/fixtures/foreign/m21_walk.bvh --label old --seed 1 -o $(DEMO_OUT)/m21_walk.old.glb
	@echo "Demo outputs in $(DEMO_OUT)/ (open the .bvh files in any BVH viewer, the .glb in Blender or any glTF viewer)"
	$(MAKE) --no-print-directory www
	node scripts/serve-www.mjs out/www --port $(WWW_PORT)

## test: every test — Rust unit/integration tests, then the three.js compatibility check in Node, then the wasm package
test: test-rust test-js test-wasm test-www test-gpu

test-rust:
	$(CARGO) test --release

setup-js:
	cd tests/js && npm ci --no-audit --no-fund

test-js: setup-js
	node --test tests/js/

## pkg: build the npm package `motion-stylizer` into pkg/ (wasm32 + wasm-bindgen --target web, JS wrapper, weights)
pkg:
	scripts/build-pkg.sh

## setup-wasm: the wasm32 target and wasm-bindgen-cli at Cargo.lock's version (idempotent)
setup-wasm:
	scripts/setup-wasm.sh

## test-wasm: the wasm facade's tests in Node (flex, and the ndarray backend's build), the package vs the native CLI, npm pack
test-wasm: setup-wasm pkg
	$(CARGO) test --release --target wasm32-unknown-unknown --no-default-features --features model,wasm --test wasm_facade
	$(CARGO) test --release --target wasm32-unknown-unknown --no-default-features --features model,wasm,ndarray --test wasm_facade -- ndarray
	$(CARGO) build --release --bin motion-stylizer
	cd tests/npm && npm ci --no-audit --no-fund
	node --test tests/npm/

## www: build pkg/ and assemble the browser demo into out/www/ (static files: the page, the package, the sample clips)
.PHONY: www serve-www test-www www-screenshots
WWW_PORT ?= 8080
www: pkg
	scripts/build-www.sh out/www

## serve-www: serve out/www/ on localhost (what `make demo` ends with; WWW_PORT, default 8080, or the next free port)
serve-www: www
	node scripts/serve-www.mjs out/www --port $(WWW_PORT)

## test-www: the browser demo end to end in headless Chromium (Debian's chromium: scripts/setup-browser.sh; playwright-core),
## and the WebGPU engine on Chromium's software adapter (its Vulkan needs Mesa's drivers: scripts/setup-gpu.sh)
test-www: www
	scripts/setup-browser.sh >/dev/null
	scripts/setup-gpu.sh
	cd tests/www && npm ci --no-audit --no-fund
	node --test tests/www/

## www-screenshots: the README's screenshots of the demo (www/screenshots/, laptop and phone widths)
www-screenshots: www
	scripts/setup-browser.sh >/dev/null
	cd tests/www && npm ci --no-audit --no-fund
	node tests/www/screenshots.mjs

## bench-wasm: wasm (Node, one thread) vs native for one 160-frame stylization and for 10 samples; load time
bench-wasm: pkg
	$(CARGO) build --release --example stylize_bench
	node bench/wasm/run.mjs

## bench-perf: ours vs onnxruntime-web (wasm, Node, 1 thread) and vs PyTorch CPU on the same network at the shipped
## weights, after a parity check (outputs within 1e-4); BVH parsing vs three.js; writes bench/results.json (bench/README.md);
## then bench-train (the training step vs PyTorch)
.PHONY: bench-perf setup-bench
BENCH_ROUNDS ?= 5
BENCH_REPEATS ?= 5
BENCH_THREADS ?= 1
setup-bench:
	scripts/setup-bench.sh

bench-perf: setup-bench pkg
	$(CARGO) build --release --example perf_bench
	CARGO_TARGET_WASM32_WASIP1_RUSTFLAGS="-C target-feature=+simd128" \
	  $(CARGO) build --release --example perf_bench --target wasm32-wasip1 --no-default-features --features model
	node bench/perf/run.mjs --rounds $(BENCH_ROUNDS) --repeats $(BENCH_REPEATS) --threads $(BENCH_THREADS)
	$(MAKE) --no-print-directory bench-train

## bench-train: ours vs PyTorch CPU on one training step of each stage (autoencoder + regressor; supervised stylizer),
## batch 16 x 160 frames, at the shipped (0.5) and the paper's (1.0) width, after a parity check of the first 3 steps'
## losses (within 1e-4); merges train_step_vs_pytorch into bench/results.json (bench/README.md)
.PHONY: bench-train
BENCH_TRAIN_ROUNDS ?= 3
BENCH_TRAIN_REPEATS ?= 3
BENCH_TRAIN_THREADS ?= 2
BENCH_TRAIN_WIDTHS ?= 0.5,1
# Seconds to wait, before each timed run, for the machine to be idle (0: don't wait).
BENCH_TRAIN_QUIET_WAIT ?= 60
bench-train:
	bench/perf/.venv/bin/python -c 'import torch, numpy' 2>/dev/null || scripts/setup-bench.sh
	$(CARGO) build --release --example train_perf_bench
	node bench/perf/train_run.mjs --rounds $(BENCH_TRAIN_ROUNDS) --repeats $(BENCH_TRAIN_REPEATS) \
	  --threads $(BENCH_TRAIN_THREADS) --widths $(BENCH_TRAIN_WIDTHS) --quiet-wait $(BENCH_TRAIN_QUIET_WAIT)

## setup-gpu: a Vulkan driver for the wgpu device (Mesa's lavapipe when none is installed; idempotent)
## test-gpu: the wgpu device against the CPU (tests/device_wgpu.rs: the shipped weights' stylization, training steps);
## part of `make test` (issue 16): 34 s on lavapipe, after a second native build of Burn with `wgpu` (13 min here)
## bench-gpu: training steps (width 0.5, 1) and 160-frame stylizations (1, 10 samples) on wgpu and on the CPU
.PHONY: setup-gpu test-gpu bench-gpu
setup-gpu:
	scripts/setup-gpu.sh

test-gpu: setup-gpu
	$(CARGO) test --release --features wgpu --test device_wgpu

bench-gpu: setup-gpu
	$(CARGO) run --release --features wgpu --example gpu_bench

## bench: parse + retarget + features throughput, and BVH parsing against three.js
bench:
	$(CARGO) run --release --example pipeline_throughput
	bench/bvh_parse/run.sh

## eval: the evaluation of the shipped weights (needs `make data`): held-out takes and the foreign-rig files
eval:
	$(CARGO) build --release --bin motion-stylizer
	./target/release/motion-stylizer eval --data data --repeats $(EVAL_REPEATS) --seed 0 --json assets/eval/heldout.json
	./target/release/motion-stylizer eval --data data --content ../shared/data/foreign-rigs --repeats $(EVAL_FOREIGN_REPEATS) --seed 0 --json assets/eval/foreign.json

## data: unpack the Bandai-Namco archives into data/ (git-ignored; needed only for training, eval and the full-size benchmarks)
data:
	mkdir -p data
	for a in $(DATA_SRC)/dataset-1.tar.gz $(DATA_SRC)/dataset-2.tar.gz; do tar xzf $$a -C data; done

clean:
	$(CARGO) clean
	rm -rf out tests/js/node_modules tests/www/node_modules tests/npm/node_modules www/node_modules bench/perf/node_modules bench/perf/.venv
