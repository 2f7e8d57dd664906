// Your own styles in the package (issue 18): `train all` on a tiny folder of generated clips on two
// rigs with two labels the shipped weights do not know (tiny networks, a handful of steps), then
// the exported weights folder loaded by the package in Node as a `file:` URL and as a path, and
// stylized with a new label and motion-based — the same motion as the native CLI gives from the
// same folder (joint positions within 1e-5 of the motion's size, as tests/npm/native_equality).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { positionDifference } from './bvh_positions.mjs';
import { cli, fixture, loadPackage, read, tempDir } from './helpers.mjs';

/** A generated clip: the source's frames from `start`, played at `speed`, on the same rig. */
function generate(source, start, speed) {
  const at = source.indexOf('MOTION');
  const lines = source.slice(at).split('\n').slice(1).filter((l) => l.trim() !== '');
  const dt = lines[1].split(':')[1].trim();
  const rows = lines.slice(2);
  const src = rows.slice(Math.min(start, rows.length - 1));
  const n = Math.floor(src.length / speed);
  const out = [...Array(n).keys()].map((i) => src[Math.min(Math.floor(i * speed), src.length - 1)]);
  return `${source.slice(0, at)}MOTION\nFrames: ${out.length}\nFrame Time: ${dt}\n${out.join('\n')}\n`;
}

const TINY = ['--steps', '2', '--width', '0.125', '--window', '32', '--batch', '2', '--threads', '1', '--seed', '3'];

test('weights trained by `train all` on your own folder: loaded from a file: URL, new labels, the CLI\'s motion', async () => {
  const root = tempDir('ms-own-');
  const data = join(root, 'data');
  let csv = 'file,style\n';
  const rigs = { bandai: read(fixture('bandai/dataset-2_walk_normal_001_f120.bvh')), m21: read(fixture('foreign/m21_walk.bvh')) };
  for (const [rig, source] of Object.entries(rigs)) {
    mkdirSync(join(data, rig), { recursive: true });
    for (const [label, speed] of [['slowmo', 0.5], ['hurried', 2]]) {
      for (const [take, start] of [0, 10].entries()) {
        const file = `${rig}/${label}_${take}.bvh`;
        writeFileSync(join(data, file), generate(source, start, speed));
        csv += `${file},${label}\n`;
      }
    }
    writeFileSync(join(data, `${rig}/plain.bvh`), generate(source, 0, 1));
  }
  writeFileSync(join(data, 'labels.csv'), csv);
  const run = join(root, 'run');
  cli(['train', 'all', '--data', data, '--out', run, ...TINY]);
  const weights = join(run, 'weights');

  const { Stylizer } = await loadPackage();
  const shipped = await Stylizer.load({ settings: ['supervised'] });
  const own = await Stylizer.load({ weights: pathToFileURL(`${weights}/`).href });
  assert.deepEqual(own.styles(), ['hurried', 'slowmo']);
  assert.match(own.weightsId, /^[0-9a-f]{8}$/);
  assert.notEqual(own.weightsId, shipped.weightsId, 'another fingerprint than the shipped weights');
  const fromPath = await Stylizer.load({ weights, settings: ['supervised'] });
  assert.equal(fromPath.weightsId, own.weightsId, 'a path loads the same folder');
  shipped.free();

  const content = fixture('foreign/m21_walk.bvh');
  const reference = join(data, 'bandai/slowmo_1.bvh');
  const modes = [
    { name: 'label slowmo', cli: ['--label', 'slowmo'], js: { label: 'slowmo' } },
    { name: 'label hurried, strength 1.5', cli: ['--label', 'hurried', '--strength', '1.5'], js: { label: 'hurried', strength: 1.5 } },
    { name: 'motion, unsupervised', cli: ['--style-motion', reference, '--unsupervised'], js: { styleMotion: read(reference), unsupervised: true } },
  ];
  const motion = own.importBvh(read(content));
  const outputs = [];
  for (const mode of modes) {
    const out = join(root, 'out.bvh');
    cli(['stylize', content, ...mode.cli, '--weights', weights, '--seed', '5', '-o', out]);
    const [wasm] = await own.stylize(motion, { ...mode.js, seed: 5 });
    const bvh = wasm.toBvh();
    if (bvh !== read(out)) {
      const d = positionDifference(own, bvh, read(out));
      assert.ok(d.relative <= 1e-5, `${mode.name}: joint positions differ from the CLI's by ${d.relative} of the motion's size`);
    }
    assert.equal(wasm.frames, motion.frames, `${mode.name}: on the content's frames`);
    outputs.push(bvh);
  }
  // The new labels are styles of their own: the two labels give different motions.
  assert.ok(positionDifference(own, outputs[0], outputs[1]).relative > 1e-3, 'slowmo and hurried differ');
  // A shipped label is unknown to these weights, and says which labels there are.
  await assert.rejects(() => own.stylize(motion, { label: 'old' }), (e) => /slowmo/.test(e.message));
  own.free();
  fromPath.free();
});
