// The package's JS API (pkg/index.js): loading, importing, every option, outputs, error codes.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { spawn } from 'node:child_process';
import { join } from 'node:path';
import { test } from 'node:test';
import { Worker } from 'node:worker_threads';
import { fixture, loadPackage, pkgDir, read, serve } from './helpers.mjs';

const { Stylizer, Motion, StylizedMotion } = await loadPackage();
const s = await Stylizer.load();
const walk = read(fixture('foreign/m21_walk.bvh'));
const ref = read(fixture('bandai/dataset-2_walk_elderly_001_f120.bvh'));

/** Asserts that `f` throws (or rejects with) an Error whose code is `code`. */
async function rejects(f, code) {
  await assert.rejects(async () => f(), (e) => {
    assert.ok(e instanceof Error, `not an Error: ${e}`);
    assert.equal(e.code, code, e.message);
    assert.ok(e.message.length > 0);
    return true;
  });
}

test('load: bundled weights, both models, the CPU backend', () => {
  assert.deepEqual(s.settings(), ['supervised', 'unsupervised']);
  assert.equal(s.styles().length, 16);
  assert.ok(s.styles().includes('old'));
  assert.equal(s.backend, 'cpu');
  assert.equal(s.fallbackReason, null);
  assert.ok(s.loadMs > 0);
});

test('importBvh: rig, frames, report', () => {
  const m = s.importBvh(walk);
  assert.ok(m instanceof Motion);
  assert.equal(m.rig, 'm21');
  assert.equal(m.fps, 30);
  assert.equal(m.frames, 81);
  assert.equal(m.rigReport().missing.length, 0);
});

test('stylize: outputs with BVH, positions and skeleton, on either rig', async () => {
  const content = s.importBvh(walk);
  const outs = await s.stylize(content, { label: 'old', samples: 2, seed: 3 });
  assert.equal(outs.length, 2);
  for (const o of outs) {
    assert.ok(o instanceof StylizedMotion);
    assert.equal(o.frames, 81);
    assert.equal(o.fps, 30);
    const joints = o.skeleton.names.length;
    assert.equal(joints, 21, 'the m21 rig');
    assert.equal(o.skeleton.parents[0], -1);
    const p = o.positions();
    assert.ok(p instanceof Float32Array);
    assert.equal(p.length, 81 * joints * 3);
    assert.ok(p.every(Number.isFinite));
    assert.ok(o.toBvh().startsWith('HIERARCHY'));
    s.importBvh(o.toBvh());
  }
  const [canonical] = await s.stylize(walk, { label: 'old', rig: 'canonical' });
  assert.equal(canonical.skeleton.names.length, 21);
  assert.equal(canonical.skeleton.names[0], 'Hips');
});

test('stylize: every style source; seeds are deterministic', async () => {
  const content = s.importBvh(walk);
  const reference = s.importBvh(ref);
  const bvh = async (o) => (await s.stylize(content, o)).map((x) => x.toBvh());
  const sources = [
    { label: 'old' },
    { styleMotion: reference, label: 'old' },
    { styleMotion: ref, unsupervised: true },
    { prior: true },
    { prior: true, unsupervised: true },
    { mix: { a: { label: 'old' }, b: { styleMotion: reference, label: 'proud' }, t: 0.25 } },
    { mix: { a: { prior: true }, b: { mix: { a: { styleMotion: reference }, b: { prior: true }, t: 0.5 } }, t: 0.5 }, unsupervised: true },
  ];
  for (const o of sources) {
    const a = await bvh({ ...o, seed: 9, samples: 2 });
    assert.deepEqual(a, await bvh({ ...o, seed: 9, samples: 2 }), JSON.stringify(o));
    assert.deepEqual(a, await bvh({ ...o, seed: 9n, samples: 2 }), 'a BigInt seed is the same seed');
  }
  assert.notDeepEqual(await bvh({ label: 'old', seed: 1 }), await bvh({ label: 'old', seed: 2 }));
  // Temperature 0: the label's zero code, whatever the seed; the default is 0.3.
  assert.deepEqual(await bvh({ label: 'old', seed: 1, temperature: 0 }), await bvh({ label: 'old', seed: 2, temperature: 0 }));
  assert.deepEqual(await bvh({ label: 'old', seed: 1 }), await bvh({ label: 'old', seed: 1, temperature: 0.3 }));
  // A mix at t = 0 is its first source.
  assert.deepEqual(await bvh({ mix: { a: { label: 'old' }, b: { label: 'sad' }, t: 0 }, seed: 4 }), await bvh({ label: 'old', seed: 4 }));
});

test('errors: stable codes', async () => {
  const content = s.importBvh(walk);
  await rejects(() => s.importBvh('HIERARCHY\nROOT'), 'BVH_PARSE');
  await rejects(() => s.importBvh(42), 'BAD_REQUEST');
  await rejects(() => s.importBvh(read(fixture('small.bvh'))), 'RIG_UNMATCHED');
  assert.throws(() => s.importBvh(read(join(fixture('..'), 'malformed/duplicate_joint.bvh'))), {
    code: 'BVH_PARSE',
    line: 6,
    kind: 'DuplicateJoint',
  });
  await rejects(() => s.stylize(content, {}), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'grumpy' }), 'UNKNOWN_LABEL');
  await rejects(() => s.stylize(content, { label: 7 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', prior: true }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', unsupervised: true }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { styleMotion: ref }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { styleMotion: {} }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', samples: 0 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', samples: 65 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', samples: 1.5 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', samples: '2' }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', seed: -1 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', seed: 2 ** 60 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', seed: 2n ** 64n }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', rig: 'mine' }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', temperature: 5 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', temperature: '1' }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { mix: { a: { label: 'old' }, b: { label: 'sad' }, t: 2 } }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { mix: { a: { label: 'old' }, t: 0.5 } }), 'BAD_REQUEST');
  let deep = { prior: true };
  for (let i = 0; i < 100000; i++) deep = { mix: { a: deep, b: { prior: true }, t: 0.5 } };
  await rejects(() => s.stylize(content, { ...deep, unsupervised: true }), 'BAD_REQUEST');
  const only = await Stylizer.load({ settings: ['supervised'] });
  assert.deepEqual(only.settings(), ['supervised']);
  await rejects(() => only.stylize(content, { prior: true, unsupervised: true }), 'SETTING_UNAVAILABLE');
  await rejects(() => Stylizer.load({ weights: { manifest: '{', norm: '{}' } }), 'BAD_WEIGHTS');
  await rejects(() => Stylizer.load({ weights: 'file:///nonexistent/' }), 'FETCH');
  await rejects(() => Stylizer.load({ backend: 'cuda' }), 'BACKEND_UNAVAILABLE');
});

test('webgpu: falls back to the CPU with the reason', async () => {
  const g = await Stylizer.load({ backend: 'webgpu', settings: ['unsupervised'] });
  assert.equal(g.backend, 'cpu');
  assert.match(g.fallbackReason, /WebGPU/);
  assert.equal((await g.stylize(walk, { prior: true, unsupervised: true })).length, 1);
});

test('weights as bytes, from a folder path, and fetched over HTTP', async () => {
  const w = (f) => readFileSync(join(pkgDir, 'weights', f));
  const fromBytes = await Stylizer.load({ weights: { manifest: w('manifest.json'), norm: w('norm.json'), supervised: w('supervised.bin') } });
  assert.deepEqual(fromBytes.settings(), ['supervised']);
  const fromPath = await Stylizer.load({ weights: join(pkgDir, 'weights'), settings: ['unsupervised'] });
  assert.deepEqual(fromPath.settings(), ['unsupervised']);
  const server = await serve(pkgDir);
  try {
    const base = server.base;
    const fetched = await Stylizer.load({ weights: `${base}/weights/` });
    const a = (await fetched.stylize(walk, { label: 'old', seed: 5 }))[0].toBvh();
    assert.equal(a, (await s.stylize(walk, { label: 'old', seed: 5 }))[0].toBvh());
    await rejects(() => Stylizer.load({ weights: `${base}/nowhere/` }), 'FETCH');
  } finally {
    server.close();
  }
});

test('works in a worker thread', async () => {
  const code = `
    import { parentPort, workerData } from 'node:worker_threads';
    const { Stylizer } = await import(workerData.index);
    const s = await Stylizer.load({ settings: ['unsupervised'] });
    const [out] = await s.stylize(workerData.walk, { prior: true, unsupervised: true, seed: 2 });
    parentPort.postMessage(out.toBvh());`;
  const index = new URL(`file://${join(pkgDir, 'index.js')}`).href;
  const worker = new Worker(new URL(`data:text/javascript,${encodeURIComponent(code)}`), { workerData: { index, walk } });
  const text = await new Promise((resolve, reject) => {
    worker.once('message', resolve);
    worker.once('error', reject);
  });
  await worker.terminate();
  assert.equal(text, (await s.stylize(walk, { prior: true, unsupervised: true, seed: 2 }))[0].toBvh());
});

test('the browser code path: the package imported from http:, wasm and weights fetched', async () => {
  // Node's network imports stand in for a browser: import.meta.url is http:, so the wasm is
  // instantiated from fetch (streaming) and the weights are fetched, as in a page or a worker.
  const server = await serve(pkgDir);
  try {
    const code = `const { Stylizer } = await import('${server.base}/index.js');
      const s = await Stylizer.load();
      const [o] = await s.stylize(process.argv[1], { label: 'old', seed: 5 });
      process.stdout.write(o.toBvh());`;
    const child = spawn(process.execPath, ['--experimental-network-imports', '--no-warnings', '--input-type=module', '-e', code, walk]);
    let out = '';
    let err = '';
    child.stdout.on('data', (d) => (out += d));
    child.stderr.on('data', (d) => (err += d));
    const status = await new Promise((r) => child.on('close', r));
    assert.equal(status, 0, err);
    assert.equal(out, (await s.stylize(walk, { label: 'old', seed: 5 }))[0].toBvh());
  } finally {
    server.close();
  }
});
