// `node pkg-run.mjs WORK_DIR REPEATS`: the npm package itself (pkg/, `make pkg`) in a fresh Node process, one
// thread: the cold start (import and compile the wasm, Stylizer.load() with the bundled weights, then the first
// stylization of WORK_DIR/content.bvh, BVH text in → BVH text out), then warm medians of the benchmark's work
// from BVH text (motion-based with WORK_DIR/style.bvh as the reference, label-based with 1 and 10 samples).
// One JSON line on stdout.
import { readFileSync } from 'node:fs';
import { join } from 'node:path';

const [work, repeats = '5'] = process.argv.slice(2);
const content = readFileSync(join(work, 'content.bvh'), 'utf8');
const style = readFileSync(join(work, 'style.bvh'), 'utf8');
const t0 = performance.now();
const { Stylizer } = await import(new URL('../../pkg/index.js', import.meta.url));
const s = await Stylizer.load();
const t1 = performance.now();
const first = await s.stylize(content, { label: 'old', seed: 7 });
first[0].toBvh();
const t2 = performance.now();

const jobs = {
  e2e_motion: () => s.stylize(content, { styleMotion: style, label: 'old' }),
  e2e_label1: () => s.stylize(content, { label: 'old', seed: 7 }),
  e2e_label10: () => s.stylize(content, { label: 'old', samples: 10, seed: 7 }),
};
const out = { cold_load_ms: t1 - t0, cold_first_stylization_ms: t2 - t1, cold_total_ms: t2 - t0, all: {} };
for (let i = 0; i < 2; i++) for (const f of Object.values(jobs)) (await f()).map((m) => m.toBvh());
for (const [name, f] of Object.entries(jobs)) {
  const ms = [];
  for (let i = 0; i < Number(repeats); i++) {
    const t = performance.now();
    (await f()).map((m) => m.toBvh());
    ms.push(performance.now() - t);
  }
  out.all[name] = ms;
  out[`${name}_ms`] = [...ms].sort((a, b) => a - b)[Math.floor(ms.length / 2)];
}
console.log(JSON.stringify(out));
