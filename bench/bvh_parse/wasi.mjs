// `node wasi.mjs BENCH.wasm FILE.bvh [ITERATIONS]`: runs the wasm32-wasip1 build of src/main.rs
// under Node's WASI (the file's folder is preopened as /data).
import { readFileSync } from 'node:fs';
import { WASI } from 'node:wasi';
import { basename, dirname, resolve } from 'node:path';

const [wasmPath, file, iters = '200'] = process.argv.slice(2);
const wasi = new WASI({
  version: 'preview1',
  args: ['bvh-parse-bench', `/data/${basename(file)}`, iters],
  preopens: { '/data': resolve(dirname(file)) },
});
const module = await WebAssembly.compile(readFileSync(wasmPath));
const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
wasi.start(instance);
