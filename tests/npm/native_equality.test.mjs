// The package (pkg/, wasm) and the native CLI give the same motion for the same content, style,
// mode and seed: every foreign-rig fixture and a Bandai clip, in every mode the CLI has. Outputs
// are compared as BVH text, and where the text differs, as joint positions (the package's forward
// kinematics of both texts, Motion.source()) within 1e-5 of the motion's size: the native matrix kernels (gemm) pick FMA and wider
// SIMD at run time, which wasm simd128 lacks, so the last bits differ.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { basename, join } from 'node:path';
import { positionDifference } from './bvh_positions.mjs';
import { cli, fixture, loadPackage, read, tempDir } from './helpers.mjs';

const CONTENTS = [
  'foreign/cmu31_rest.bvh',
  'foreign/cmu31_xia_neutral_16_000.bvh',
  'foreign/iclone100_cmu_002_04.bvh',
  'foreign/m21_walk.bvh',
  'bandai/dataset-1_walk_tired_001_f90.bvh',
];
const REF = fixture('bandai/dataset-2_walk_elderly_001_f120.bvh');
const MODES = [
  { name: 'label', cli: ['--label', 'old'], js: { label: 'old' } },
  { name: 'label, temperature 1', cli: ['--label', 'tired', '--temperature', '1'], js: { label: 'tired', temperature: 1 } },
  { name: 'label, strength 1.6', cli: ['--label', 'angry', '--strength', '1.6'], js: { label: 'angry', strength: 1.6 } },
  { name: 'label, canonical rig', cli: ['--label', 'proud', '--canonical'], js: { label: 'proud', rig: 'canonical' } },
  { name: 'motion + label', cli: ['--style-motion', REF, '--label', 'old'], js: { styleMotion: read(REF), label: 'old' } },
  { name: 'motion, unsupervised', cli: ['--style-motion', REF, '--unsupervised'], js: { styleMotion: read(REF), unsupervised: true } },
  {
    name: 'motion, unsupervised, 2 posterior samples',
    cli: ['--style-motion', REF, '--unsupervised', '--samples', '2'],
    js: { styleMotion: read(REF), unsupervised: true, samples: 2 },
  },
  { name: 'prior, supervised, 3 samples', cli: ['--prior', '--samples', '3'], js: { prior: true, samples: 3 } },
  { name: 'prior, unsupervised, 2 samples', cli: ['--prior', '--unsupervised', '--samples', '2'], js: { prior: true, unsupervised: true, samples: 2 } },
];
const SEED = 7;

test('wasm package output equals the native CLI output', async () => {
  const { Stylizer } = await loadPackage();
  const s = await Stylizer.load();
  const dir = tempDir('ms-native-');
  let compared = 0;
  let exact = 0;
  let worst = 0;
  let worstAbs = 0;
  for (const rel of CONTENTS) {
    const content = s.importBvh(read(fixture(rel)));
    for (const mode of MODES) {
      const samples = mode.js.samples ?? 1;
      const out = join(dir, `${basename(rel, '.bvh')}.bvh`);
      cli(['stylize', fixture(rel), ...mode.cli, '--seed', String(SEED), '-o', out]);
      const native = samples === 1 ? [read(out)] : [...Array(samples).keys()].map((i) => read(out.replace(/\.bvh$/, `_${i}.bvh`)));
      const wasm = (await s.stylize(content, { ...mode.js, seed: SEED })).map((o) => o.toBvh());
      assert.equal(wasm.length, native.length, `${rel} ${mode.name}`);
      for (let i = 0; i < wasm.length; i++) {
        compared++;
        if (wasm[i] === native[i]) {
          exact++;
          continue;
        }
        const d = positionDifference(s, wasm[i], native[i]);
        worst = Math.max(worst, d.relative);
        worstAbs = Math.max(worstAbs, d.absolute);
        assert.ok(d.relative <= 1e-5, `${rel} ${mode.name} #${i}: joint positions differ by ${d.relative} of the motion's size`);
      }
    }
  }
  // The measure sees a real difference: another seed's motion is far outside the tolerance.
  const content = s.importBvh(read(fixture(CONTENTS[3])));
  const bvh = async (seed) => (await s.stylize(content, { label: 'old', seed }))[0].toBvh();
  const other = positionDifference(s, await bvh(1), await bvh(2)).relative;
  assert.ok(other > 100 * 1e-5, `two seeds' motions differ by only ${other} of the motion's size`);
  console.log(
    `native vs wasm: ${exact} of ${compared} outputs bit-identical BVH text; worst joint-position difference ` +
      `${worst.toExponential(2)} of the motion's size (${worstAbs.toExponential(2)} rig units); two seeds differ by ${other.toExponential(2)}`,
  );
});
