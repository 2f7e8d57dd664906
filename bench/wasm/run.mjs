// wasm (Node, one thread) vs native: one 160-frame stylization and 10 samples of it, label-based
// (supervised), BVH text on the content's rig; median and best of REPEATS after a warm-up, both sides.
// Also: weights load time, package size. Run by `make bench-wasm` (after `make pkg`).
//
//   node bench/wasm/run.mjs [REPEATS]        (MOTION_STYLIZER_NATIVE_BENCH: the native command)

import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { clip160 } from './clip.mjs';

const root = new URL('../../', import.meta.url).pathname;
const repeats = Number(process.argv[2] ?? 5);
const dir = mkdtempSync(join(tmpdir(), 'ms-bench-'));
const contentPath = join(dir, 'walk160.bvh');
writeFileSync(contentPath, clip160(readFileSync(join(root, 'tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh'), 'utf8')));

// wasm
const { Stylizer } = await import(pathToFileURL(join(root, 'pkg/index.js')));
const stylizer = await Stylizer.load();
const content = stylizer.importBvh(readFileSync(contentPath, 'utf8'));
async function time(samples) {
  const once = async () => {
    const t = performance.now();
    const outs = await stylizer.stylize(content, { label: 'old', samples, seed: 7 });
    outs.map((o) => o.toBvh());
    return performance.now() - t;
  };
  await once();
  const ms = [];
  for (let i = 0; i < repeats; i++) ms.push(await once());
  ms.sort((a, b) => a - b);
  return [ms[Math.floor(ms.length / 2)], ms[0]];
}
const [one, oneBest] = await time(1);
const [ten, tenBest] = await time(10);
const wasm = { frames: content.frames, load_ms: stylizer.loadMs, one_ms: one, ten_ms: ten, one_best_ms: oneBest, ten_best_ms: tenBest };

// native, one thread (as the wasm) and all threads
const targetDir = resolve(root, process.env.CARGO_TARGET_DIR ?? 'target');
const nativeCmd = (process.env.MOTION_STYLIZER_NATIVE_BENCH ?? join(targetDir, 'release/examples/stylize_bench')).split(' ');
const native = (threads) =>
  JSON.parse(
    execFileSync(nativeCmd[0], [...nativeCmd.slice(1), contentPath, String(repeats)], {
      env: { ...process.env, RAYON_NUM_THREADS: String(threads) },
      encoding: 'utf8',
    }),
  );
const n1 = native(1);
const nAll = native(0);

const f = (x) => x.toFixed(1).padStart(8);
const r = (a, b) => (a / b).toFixed(2).padStart(6);
console.log(`content: ${wasm.frames} frames (30 fps), label-based, ${repeats} runs after a warm-up: median (best)`);
console.log(`                      wasm (Node)        native 1 thread    native all threads  wasm ÷ native 1T: median (best)`);
for (const [name, k] of [['1 stylization (ms) ', 'one'], ['10 samples (ms)    ', 'ten']]) {
  const [w, n, a] = [wasm, n1, nAll].map((x) => `${f(x[`${k}_ms`])} (${f(x[`${k}_best_ms`]).trim()})`);
  console.log(`${name}   ${w}   ${n}   ${a}   ${r(wasm[`${k}_ms`], n1[`${k}_ms`])} (${r(wasm[`${k}_best_ms`], n1[`${k}_best_ms`]).trim()})`);
}
console.log(`weights load (ms)     ${f(wasm.load_ms)}     ${f(n1.load_ms)}   (wasm: module start-up + reading + loading both models)`);
const pkgWasm = readFileSync(join(root, 'pkg/engine_bg.wasm')).length;
console.log(`engine_bg.wasm: ${(pkgWasm / 1e6).toFixed(2)} MB`);
