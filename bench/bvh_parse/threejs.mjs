// `node threejs.mjs FILE.bvh [ITERATIONS]`: times three.js's BVHLoader.parse on FILE the way
// src/main.rs times ours (warm-up, then ITERATIONS parses of the same text); last line
// `RESULT ms_per_parse=…` for run.sh. three.js comes from tests/js/node_modules (npm ci there).
import { readFileSync } from 'node:fs';
import { BVHLoader } from '../../tests/js/node_modules/three/examples/jsm/loaders/BVHLoader.js';

const [path, itersArg] = process.argv.slice(2);
if (!path) {
  console.error('usage: node threejs.mjs FILE.bvh [ITERATIONS]');
  process.exit(2);
}
const iters = Number(itersArg ?? 200);
const text = readFileSync(path, 'utf8');
const loader = new BVHLoader();
let sink = 0;
for (let i = 0; i < 20; i++) sink += loader.parse(text).skeleton.bones.length; // JIT warm-up
const t0 = performance.now();
let frames = 0;
for (let i = 0; i < iters; i++) {
  const { clip } = loader.parse(text);
  frames += clip.tracks[0].times.length;
}
const s = (performance.now() - t0) / 1000 / iters;
const mb = Buffer.byteLength(text) / 1e6;
console.log(
  `three.js ${(await import('../../tests/js/node_modules/three/package.json', { with: { type: 'json' } })).default.version} ` +
    `BVHLoader.parse (node ${process.version}): ${iters} runs: ${(s * 1e3).toFixed(3)} ms/parse, ` +
    `${(mb / s).toFixed(0)} MB/s, ${(frames / iters / s).toFixed(0)} frames/s` + (sink < 0 ? '!' : ''),
);
console.log(`RESULT ms_per_parse=${s * 1e3}`);
