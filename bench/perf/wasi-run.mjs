// `node wasi-run.mjs PERF_BENCH.wasm WEIGHTS_DIR WORK_DIR REPEATS [dump]`: runs the wasm32-wasip1 build of
// examples/perf_bench.rs under Node's WASI (one thread), WEIGHTS_DIR preopened as /weights and WORK_DIR
// (content.bvh, style.bvh; dump-wasm/ is written there with `dump`) as /work. Its JSON goes to stdout.
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { WASI } from 'node:wasi';

const [wasmPath, weights, work, repeats, dump] = process.argv.slice(2);
const args = ['perf_bench', '/weights', '/work/content.bvh', '/work/style.bvh', repeats];
if (dump) args.push('/work/dump-wasm');
const wasi = new WASI({
  version: 'preview1',
  args,
  preopens: { '/weights': resolve(weights), '/work': resolve(work) },
  returnOnExit: true,
});
const module = await WebAssembly.compile(readFileSync(wasmPath));
const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
process.exitCode = wasi.start(instance);
