// The package's JS API (pkg/index.js): loading, importing, every option, outputs, error codes.
import assert from 'node:assert/strict';
import { readFileSync, statSync } from 'node:fs';
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
  assert.deepEqual(s.loadedSettings(), ['supervised'], 'the unsupervised model is read when first used');
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

test('inspectBvh and importBvh({ map }): a manual mapping round trip', async () => {
  // The m21 walk with every joint renamed: the mapping by hand is m21's own match under the new names.
  const names = [];
  const renamed = walk.replace(/^(\s*(?:ROOT|JOINT)\s+)(\S+)/gm, (_, head, name) => {
    names.push(name);
    return `${head}j${names.length - 1}`;
  });
  const original = s.importBvh(walk);
  const byHand = {};
  for (const [canonical, joint] of original.rigReport().matched) byHand[canonical] = `j${names.indexOf(joint)}`;
  assert.equal(Object.keys(byHand).length, 21);

  const info = s.inspectBvh(renamed);
  assert.equal(Object.keys(info.map).length, 21, 'every canonical joint, ready to edit');
  assert.deepEqual(info.joint_names, names.map((_, i) => `j${i}`));
  const small = s.inspectBvh(read(fixture('small.bvh')));
  assert.equal(small.retargetable, false);
  assert.equal(small.error.code, 'RIG_UNMATCHED');
  assert.equal(Object.keys(small.map).length, 21);

  const mapped = s.inspectBvh(renamed, { map: byHand });
  assert.equal(mapped.retargetable, true, JSON.stringify(mapped.error));
  assert.equal(mapped.rig, 'manual');
  assert.deepEqual(mapped.map, byHand, 'the mapping used is the one given');
  const m = s.importBvh(renamed, { map: byHand });
  assert.equal(m.rig, 'manual');
  assert.equal(m.frames, original.frames);
  // The same canonical motion: the same stylization, bit for bit (the output's rig is the file's).
  const [a] = await s.stylize(original, { label: 'old', seed: 5 });
  const [b] = await s.stylize(m, { label: 'old', seed: 5 });
  assert.deepEqual(b.positions(), a.positions());
  // Kept across a fresh engine: the Motion is imported again with its map.
  m.free();
  assert.equal(m.rig, 'manual');

  await rejects(() => s.importBvh(renamed, { map: { Hips: 'no_such_joint' } }), 'BAD_MAP');
  await rejects(() => s.importBvh(renamed, { map: { Pelvis: 'j0' } }), 'BAD_MAP');
  await rejects(() => s.inspectBvh(renamed, { map: ['j0'] }), 'BAD_REQUEST');
  await rejects(() => s.importBvh(renamed, 'j0'), 'BAD_REQUEST');
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

test('stylize with parts: a style per body part, the content kept where asked, inferred labels per part', async () => {
  const content = s.importBvh(walk);
  const maxDiff = (a, b) => a.reduce((m, v, i) => Math.max(m, Math.abs(v - b[i])), 0);
  const [whole] = await s.stylize(content, { label: 'old', seed: 2, rig: 'canonical' });
  // Every part from the same source is the whole-body stylization.
  const [same] = await s.stylize(content, { label: 'old', seed: 2, rig: 'canonical', parts: { lower: { label: 'old' }, upper: { label: 'old' } } });
  assert.ok(maxDiff(same.positions(), whole.positions()) < 1e-3, 'the parts of one source make the whole');
  // The head kept: the same motion below the neck's joints' parents, another head.
  const [headKept] = await s.stylize(content, { label: 'old', seed: 2, rig: 'canonical', parts: { head: 'content' } });
  const names = headKept.skeleton.names;
  const at = (p, name, f) => p.slice((f * names.length + names.indexOf(name)) * 3, (f * names.length + names.indexOf(name)) * 3 + 3);
  const [kept, full] = [headKept.positions(), whole.positions()];
  let hand = 0;
  let head = 0;
  for (let f = 0; f < headKept.frames; f++) {
    hand = Math.max(hand, maxDiff(at(kept, 'Hand_L', f), at(full, 'Hand_L', f)));
    head = Math.max(head, maxDiff(at(kept, 'Head', f), at(full, 'Head', f)));
  }
  assert.ok(hand < 1e-3, `the arms are the style's: ${hand}`);
  assert.ok(head > 0.5, `the head is the content's, not the style's: ${head}`);
  // Upper body from a reference without a label: inferred for that part.
  const [mixed] = await s.stylize(content, { label: 'old', seed: 2, parts: { upper: { styleMotion: ref } } });
  assert.ok(typeof mixed.inferredLabels?.upper === 'string' && s.styles().includes(mixed.inferredLabels.upper));
  assert.equal(mixed.inferredLabel, undefined);

  await rejects(() => s.stylize(content, { parts: { upper: 'content' } }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', parts: { arms: { label: 'old' } } }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', parts: { upper: 5 } }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', parts: { upper: { label: 'no-such-style' } } }), 'UNKNOWN_LABEL');
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
  // Temperature 0: the label's centre code, whatever the seed; the default is 0.3.
  assert.deepEqual(await bvh({ label: 'old', seed: 1, temperature: 0 }), await bvh({ label: 'old', seed: 2, temperature: 0 }));
  assert.deepEqual(await bvh({ label: 'old', seed: 1 }), await bvh({ label: 'old', seed: 1, temperature: 0.3 }));
  // Strength: 0 is the content whatever the style, 1 the default, 2 another motion.
  assert.deepEqual(await bvh({ label: 'old', strength: 0 }), await bvh({ label: 'sad', seed: 3, strength: 0 }));
  assert.deepEqual(await bvh({ label: 'old', seed: 1, strength: 1 }), await bvh({ label: 'old', seed: 1 }));
  assert.notDeepEqual(await bvh({ label: 'old', seed: 1, strength: 2 }), await bvh({ label: 'old', seed: 1 }));
  // Guidance: the default is the library's, 0 the networks' output as trained (another motion).
  assert.deepEqual(await bvh({ label: 'old', seed: 1, guidance: 1 }), await bvh({ label: 'old', seed: 1 }));
  assert.notDeepEqual(await bvh({ label: 'old', seed: 1, guidance: 0 }), await bvh({ label: 'old', seed: 1 }));
  // A mix at t = 0 is its first source.
  assert.deepEqual(await bvh({ mix: { a: { label: 'old' }, b: { label: 'sad' }, t: 0 }, seed: 4 }), await bvh({ label: 'old', seed: 4 }));
});

test('supervised motion-based without a label: the reference label inferred and reported', async () => {
  const content = s.importBvh(walk);
  assert.equal(await s.inferLabel(ref), 'old');
  assert.equal(await s.inferLabel(read(fixture('bandai/dataset-1_walk_tired_001_f90.bvh'))), 'tired');
  const [inferred] = await s.stylize(content, { styleMotion: ref });
  const [given] = await s.stylize(content, { styleMotion: ref, label: 'old' });
  assert.equal(inferred.inferredLabel, 'old');
  assert.equal(given.inferredLabel, undefined);
  assert.equal(inferred.toBvh(), given.toBvh());
  const [unsup] = await s.stylize(content, { styleMotion: ref, unsupervised: true });
  assert.equal(unsup.inferredLabel, undefined, 'the unsupervised model takes no label');
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
  await rejects(() => s.stylize(content, { label: 'old', strength: 2.5 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', strength: -1 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', strength: '1' }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', guidance: 3.5 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', guidance: -0.5 }), 'BAD_REQUEST');
  await rejects(() => s.stylize(content, { label: 'old', guidance: '1' }), 'BAD_REQUEST');
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
  await rejects(() => Stylizer.load({ weights: 42 }), 'BAD_WEIGHTS');
  await rejects(() => Stylizer.load({ onProgress: 'yes' }), 'BAD_REQUEST');
});

/** The file's joint names (ROOT and JOINT lines) and its frame rows, as numbers. */
function bvhFile(text) {
  const names = [...text.matchAll(/^\s*(?:ROOT|JOINT)\s+(\S+)/gim)].map((m) => m[1]);
  const motion = text.slice(text.search(/^MOTION\s*$/m)).split(/\r?\n/);
  const frameTime = Number(/^Frame Time:\s*(\S+)/m.exec(text)[1]);
  const rows = motion.slice(3).filter((l) => l.trim() !== '').map((l) => l.trim().split(/\s+/).map(Number));
  return { names, frameTime, rows };
}

test('source(): the file as given, by the package forward kinematics, drawn at most at 60 fps', () => {
  for (const [rel, step] of [['foreign/m21_walk.bvh', 1], ['foreign/cmu31_xia_neutral_16_000.bvh', 2], ['bandai/dataset-2_walk_normal_001_f120.bvh', 1]]) {
    const text = read(fixture(rel));
    const file = bvhFile(text);
    const src = s.importBvh(text).source();
    assert.deepEqual(src.names, file.names, rel);
    assert.equal(src.parents.length, file.names.length);
    assert.equal(src.parents[0], -1);
    assert.ok(src.parents.every((p, i) => i === 0 || (p >= 0 && p < i)), rel);
    assert.deepEqual(src.file, { frames: file.rows.length, fps: 1 / file.frameTime }, rel);
    assert.equal(src.frames, Math.ceil(file.rows.length / step), rel);
    assert.equal(src.fps, 1 / (file.frameTime * step), rel);
    assert.ok(src.positions instanceof Float32Array);
    assert.equal(src.positions.length, src.frames * file.names.length * 3);
    assert.ok(src.positions.every(Number.isFinite));
    // The root's position channels (the first three) are its world position in every kept frame.
    for (let f = 0; f < src.frames; f++) {
      const root = Array.from(src.positions.subarray(f * file.names.length * 3, f * file.names.length * 3 + 3));
      assert.deepEqual(root, file.rows[f * step].slice(0, 3).map(Math.fround), `${rel} frame ${f}`);
    }
  }
  // Keywords in any case, as the reader accepts them, draw the same motion.
  const walk = read(fixture('foreign/m21_walk.bvh'));
  const mixedCase = walk.replace('ROOT', 'root').replaceAll('End Site', 'END site').replaceAll('JOINT', 'Joint');
  assert.notEqual(mixedCase, walk);
  assert.deepEqual(s.importBvh(mixedCase).source(), s.importBvh(walk).source());
});

/** FNV-1a (32 bits, hex) of the bytes of `parts`: the fingerprint the demo's share links carry. */
function fnv1a(...parts) {
  let h = 0x811c9dc5;
  for (const bytes of parts) for (const b of bytes) h = Math.imul(h ^ b, 0x01000193) >>> 0;
  return h.toString(16).padStart(8, '0');
}

test('load: onProgress reports the weights bytes as they arrive, up to the total; weightsId', async () => {
  const size = (f) => statSync(join(pkgDir, 'weights', f)).size;
  const check = (calls, total, what, setting) => {
    assert.ok(calls.length >= 1, `${what}: no progress`);
    for (let i = 1; i < calls.length; i++) assert.ok(calls[i].loaded > calls[i - 1].loaded, `${what}: not increasing at ${i}`);
    assert.deepEqual(calls.at(-1), { loaded: total, total, setting }, what);
    assert.ok(calls.slice(0, -1).every((c) => c.total === total && c.loaded < total && c.setting === setting), `${what}: a total before the end`);
  };
  // At load: the statistics, the shared networks and the supervised stylizer; the unsupervised
  // one when it is first used.
  const first = size('norm.json') + size('shared.bin') + size('supervised.bin');
  const fromFiles = [];
  const a = await Stylizer.load({ onProgress: (p) => fromFiles.push({ ...p }) });
  check(fromFiles, first, 'files', 'supervised');
  const later = [];
  fromFiles.length = 0;
  const one = [];
  await Stylizer.load({ settings: ['unsupervised'], onProgress: (p) => one.push({ ...p }) });
  check(one, size('norm.json') + size('shared.bin') + size('unsupervised.bin'), 'one setting', 'unsupervised');
  const server = await serve(pkgDir);
  try {
    const overHttp = [];
    const b = await Stylizer.load({ weights: `${server.base}/weights/`, onProgress: (p) => overHttp.push({ ...p }) });
    check(overHttp, first, 'HTTP', 'supervised');
    assert.ok(overHttp.length > 10, `HTTP: ${overHttp.length} calls (the bodies are streamed)`);
    assert.equal(b.weightsId, a.weightsId);
    overHttp.length = 0;
    await b.stylize(walk, { prior: true, unsupervised: true });
    check(overHttp, size('unsupervised.bin'), 'HTTP, unsupervised when first used', 'unsupervised');
  } finally {
    server.close();
  }
  // Weights already in memory: nothing to report.
  const none = [];
  const w = (f) => readFileSync(join(pkgDir, 'weights', f));
  const c = await Stylizer.load({ weights: { manifest: w('manifest.json'), norm: w('norm.json'), shared: w('shared.bin'), supervised: w('supervised.bin') }, onProgress: () => none.push(1) });
  await a.stylize(walk, { prior: true, unsupervised: true });
  check(fromFiles, size('unsupervised.bin'), 'files, unsupervised when first used', 'unsupervised');
  const d = await Stylizer.load({ weights: a, settings: ['unsupervised'], onProgress: () => none.push(1) });
  assert.deepEqual(none, []);
  assert.deepEqual(later, []);
  // The weights' fingerprint: FNV-1a of the manifest's and the statistics' bytes, however loaded.
  assert.equal(a.weightsId, fnv1a(w('manifest.json'), w('norm.json')));
  assert.match(a.weightsId, /^[0-9a-f]{8}$/);
  assert.equal(c.weightsId, a.weightsId);
  assert.equal(d.weightsId, a.weightsId);
  // Another Stylizer's weights, on the settings asked for: the same outputs.
  assert.deepEqual(d.settings(), ['unsupervised']);
  const opts = { prior: true, unsupervised: true, seed: 3 };
  assert.equal((await d.stylize(walk, opts))[0].toBvh(), (await s.stylize(walk, opts))[0].toBvh());
});

test('free(): memory released now; a Motion or Stylizer used again is rebuilt, a StylizedMotion is gone', async () => {
  const own = await Stylizer.load({ weights: s });
  const content = own.importBvh(walk);
  const [out] = await own.stylize(content, { label: 'old', seed: 2 });
  const expected = out.toBvh();
  out.free();
  out.free();
  await rejects(() => out.toBvh(), 'BAD_REQUEST');
  content.free();
  own.free();
  assert.equal((await own.stylize(content, { label: 'old', seed: 2 }))[0].toBvh(), expected);
  assert.equal(content.frames, 81);
  // A model added when first used is rebuilt too after free().
  const prior = { prior: true, unsupervised: true, seed: 4 };
  const unsup = (await own.stylize(content, prior))[0].toBvh();
  assert.deepEqual(own.loadedSettings(), ['supervised', 'unsupervised']);
  own.free();
  own.free();
  assert.equal((await own.stylize(content, prior))[0].toBvh(), unsup);
  assert.deepEqual(own.loadedSettings(), ['supervised', 'unsupervised']);
});

test('a panic in the engine: INTERNAL with its message; the same Stylizer and Motions carry on, same bytes', async () => {
  const own = await Stylizer.load();
  const content = own.importBvh(walk);
  const reference = own.importBvh(ref);
  const modes = [{ styleMotion: reference, label: 'old', samples: 2, seed: 4 }, { label: 'proud', seed: 1 }, { prior: true, unsupervised: true }];
  const stylizeAll = async (stylizer) => {
    const out = [];
    for (const m of modes) out.push(...(await stylizer.stylize(content, m)).map((o) => o.toBvh()));
    return out;
  };
  const before = await stylizeAll(own);
  const [result] = await own.stylize(content, { label: 'old' });
  const other = await Stylizer.load({ settings: ['supervised'] });
  assert.throws(
    () => own.__panicForTests(),
    (e) => {
      assert.ok(e instanceof Error && !(e instanceof WebAssembly.RuntimeError), String(e));
      assert.equal(e.code, 'INTERNAL');
      assert.match(e.message, /a deliberate panic for the tests \(Engine.__panicForTests\)/);
      assert.match(e.message, /src\/wasm\/engine\.rs:\d+:\d+/);
      return true;
    },
  );
  // A result of the trapped instance is gone; everything else runs on a fresh instance.
  await rejects(() => result.toBvh(), 'INTERNAL');
  assert.equal(content.frames, 81);
  assert.equal(content.rig, 'm21');
  assert.deepEqual(await stylizeAll(own), before);
  assert.deepEqual(own.styles(), s.styles());
  assert.equal((await other.stylize(walk, { label: 'old', seed: 5 }))[0].toBvh(), (await own.stylize(walk, { label: 'old', seed: 5 }))[0].toBvh());
  // And again: a second panic is reported the same way.
  assert.throws(() => own.__panicForTests(), { code: 'INTERNAL' });
  assert.deepEqual(await stylizeAll(own), before);
});

test('webgpu: falls back to the CPU with the reason', async () => {
  const g = await Stylizer.load({ backend: 'webgpu', settings: ['unsupervised'] });
  assert.equal(g.backend, 'cpu');
  assert.match(g.fallbackReason, /WebGPU/);
  assert.equal((await g.stylize(walk, { prior: true, unsupervised: true })).length, 1);
});

test('weights as bytes, from a folder path, and fetched over HTTP', async () => {
  const w = (f) => readFileSync(join(pkgDir, 'weights', f));
  const fromBytes = await Stylizer.load({ weights: { manifest: w('manifest.json'), norm: w('norm.json'), shared: w('shared.bin'), supervised: w('supervised.bin') } });
  assert.deepEqual(fromBytes.settings(), ['supervised']);
  await rejects(() => fromBytes.stylize(walk, { prior: true, unsupervised: true }), 'SETTING_UNAVAILABLE');
  await rejects(() => Stylizer.load({ weights: { manifest: w('manifest.json'), norm: w('norm.json'), supervised: w('supervised.bin') } }), 'BAD_WEIGHTS');
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
