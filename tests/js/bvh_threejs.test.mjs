// three.js compatibility of our BVH writer.
//
// `cargo run --release --example bvh_dump` reads fixtures, writes them back with our writer
// (Bvh::to_bvh_string) and dumps world joint positions computed by our Bvh::global_pose on the
// *original* files. Here three.js's BVHLoader loads the written files; an AnimationMixer poses the
// skeleton at the dumped frames, and every joint (matched by name) and every End Site (three.js makes
// them extra bones named "ENDSITE"; matched by parent name) must sit where our kinematics put it.
//
// Tolerance: 1e-3 cm, absolute. three.js stores keyframes as float32 (relative precision ~6e-8: about
// 3e-5 cm at the 5 m the Bandai root walks away from the origin), so that is the realistic bar.
//
// Run from the repository root: `cd tests/js && npm ci && cd ../.. && node --test tests/js/`.
// The test fails (it does not skip) when cargo, the fixtures or three.js are missing.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { AnimationMixer, LoopOnce, Vector3 } from 'three';
import { BVHLoader } from 'three/addons/loaders/BVHLoader.js';

const TOLERANCE_CM = 1e-3;
const repo = join(dirname(fileURLToPath(import.meta.url)), '..', '..');

const bvhIn = (dir) =>
  readdirSync(join(repo, 'tests/fixtures', dir))
    .filter((f) => f.endsWith('.bvh'))
    .sort()
    .map((f) => `tests/fixtures/${dir}/${f}`);
const cases = ['tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh', ...bvhIn('foreign')];

let dumped = null;
/** Runs the Rust side once; returns the output folder. */
function dumpDir() {
  if (dumped === null) {
    const out = mkdtempSync(join(tmpdir(), 'bvh-threejs-'));
    process.on('exit', () => rmSync(out, { recursive: true, force: true }));
    const cargo = process.env.CARGO ?? 'cargo';
    execFileSync(cargo, ['run', '--release', '--quiet', '--example', 'bvh_dump', '--', out, ...cases], {
      cwd: repo,
      stdio: ['ignore', 'inherit', 'inherit'],
    });
    dumped = out;
  }
  return dumped;
}

test('the fixtures are there', () => {
  assert.ok(bvhIn('foreign').length >= 4, 'tests/fixtures/foreign/*.bvh missing');
  const manifest = JSON.parse(readFileSync(join(dumpDir(), 'manifest.json'), 'utf8'));
  assert.equal(manifest.cases.length, cases.length);
});

for (const path of cases) {
  const stem = path.split('/').pop().replace(/\.bvh$/, '');
  test(`three.js BVHLoader poses our ${stem}.bvh like Bvh::global_pose`, () => {
    const out = dumpDir();
    const text = readFileSync(join(out, `${stem}.bvh`), 'utf8');
    const dump = JSON.parse(readFileSync(join(out, `${stem}.json`), 'utf8'));

    // BVHLoader reports problems with console.error / console.warn and carries on: count them as failures.
    const complaints = [];
    const { error, warn } = console;
    console.error = console.warn = (...args) => complaints.push(args.join(' '));
    let loaded;
    try {
      loaded = new BVHLoader().parse(text);
    } finally {
      Object.assign(console, { error, warn });
    }
    assert.deepEqual(complaints, []);
    const { skeleton, clip } = loaded;

    const byName = new Map(skeleton.bones.filter((b) => b.name !== 'ENDSITE').map((b) => [b.name, b]));
    assert.equal(byName.size, dump.names.length, 'joint count');
    for (const name of dump.names) assert.ok(byName.has(name), `joint ${name} missing in three.js`);
    const endSites = new Map(skeleton.bones.filter((b) => b.name === 'ENDSITE').map((b) => [b.parent.name, b]));
    assert.equal(endSites.size, Object.keys(dump.end_sites[0]).length, 'End Site count');
    const frameTime = dump.frame_time;
    assert.ok(Math.abs(clip.duration - (dump.num_frames - 1) * frameTime) < 1e-5, 'clip duration');

    const root = skeleton.bones[0];
    const v = new Vector3();
    let worst = 0;
    let checked = 0;
    const compare = (bone, want, what) => {
      bone.getWorldPosition(v);
      const err = Math.hypot(v.x - want[0], v.y - want[1], v.z - want[2]);
      assert.ok(err <= TOLERANCE_CM, `${what}: three.js ${v.toArray()} vs ours ${want} (${err} cm)`);
      worst = Math.max(worst, err);
      checked += 1;
    };
    dump.frames.forEach((frame, k) => {
      // A fresh mixer per frame: LoopOnce + clampWhenFinished pauses the action at the end.
      const mixer = new AnimationMixer(root);
      const action = mixer.clipAction(clip);
      action.setLoop(LoopOnce, 1);
      action.clampWhenFinished = true;
      action.play();
      // Key times are float32 in three.js: hit the key exactly.
      mixer.setTime(Math.fround(frame * frameTime));
      root.updateMatrixWorld(true);
      dump.names.forEach((name, j) => compare(byName.get(name), dump.joints[k][j], `frame ${frame} ${name}`));
      for (const [parent, want] of Object.entries(dump.end_sites[k])) {
        compare(endSites.get(parent), want, `frame ${frame} End Site of ${parent}`);
      }
      mixer.stopAllAction();
      mixer.uncacheRoot(root);
    });
    assert.equal(checked, dump.frames.length * (dump.names.length + Object.keys(dump.end_sites[0]).length));
    console.log(`${stem}: ${checked} positions over ${dump.frames.length} frames, worst ${worst.toExponential(2)} cm`);
  });
}
