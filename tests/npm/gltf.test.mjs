// The package's glTF and three.js exports: StylizedMotion.toGlb() and toThreeClip(THREE).
//
// Every .glb goes through the Khronos glTF validator (npm gltf-validator): zero errors. three.js's
// GLTFLoader loads it and an AnimationMixer poses it at every keyframe: every joint's world
// position must be the BVH's (positions(), the package's forward kinematics), scaled to metres and
// turned Y up as the scene's extras say (0.01 and no turn on the canonical rig; the importer's
// scale on the content's rig), within 0.1 mm. toThreeClip's Skeleton and AnimationClip must pose
// the same, without warnings from three.js (every track finds its bone).
//
// Needs `make pkg` and `cd tests/npm && npm ci` (three, gltf-validator).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import validator from 'gltf-validator';
import { fixture, loadPackage, read } from './helpers.mjs';

const TOLERANCE_M = 1e-4;
const { Stylizer } = await loadPackage();
const s = await Stylizer.load();

const CONTENTS = [
  'foreign/m21_walk.bvh',
  'foreign/cmu31_xia_neutral_16_000.bvh',
  'foreign/iclone100_cmu_002_04.bvh',
  'bandai/dataset-2_walk_normal_001_f120.bvh',
];

/** The validator's report of `glb`, with its errors listed in the assertion message. */
async function validate(glb, name) {
  const report = await validator.validateBytes(new Uint8Array(glb), { uri: name, format: 'glb', maxIssues: 100 });
  const errors = report.issues.messages.filter((m) => m.severity === 0).map((m) => `${m.code} ${m.pointer ?? ''}: ${m.message}`);
  assert.equal(report.issues.numErrors, 0, `${name}: ${errors.join('; ')}`);
  return report;
}

/** GLTFLoader's result for `glb` bytes. */
function load(glb) {
  const buffer = glb.buffer.slice(glb.byteOffset, glb.byteOffset + glb.byteLength);
  return new Promise((resolve, reject) => new GLTFLoader().parse(buffer, '', resolve, reject));
}

/** Where joint `j` of frame `f` must be: the BVH position `p` (positions()), scaled and turned. */
function expected(positions, joints, f, j, scale, turn) {
  const i = (f * joints + j) * 3;
  return new THREE.Vector3(positions[i], positions[i + 1], positions[i + 2]).multiplyScalar(scale).applyQuaternion(turn);
}

/**
 * Poses `root` with `clip` at every frame and returns the worst distance of `objects[j]` (joint j)
 * from where the BVH puts it.
 */
function worstError(root, clip, objects, o, scale, turn) {
  const mixer = new THREE.AnimationMixer(root);
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  const positions = o.positions();
  const joints = o.skeleton.names.length;
  let worst = 0;
  const at = new THREE.Vector3();
  for (let f = 0; f < o.frames; f++) {
    mixer.setTime(f / o.fps);
    root.updateMatrixWorld(true);
    for (let j = 0; j < joints; j++) {
      objects[j].getWorldPosition(at);
      worst = Math.max(worst, at.distanceTo(expected(positions, joints, f, j, scale, turn)));
    }
  }
  return worst;
}

/** Fails on any warning three.js prints while `f` runs (e.g. a track that finds no bone). */
async function noWarnings(f) {
  const warnings = [];
  const warn = console.warn;
  console.warn = (...args) => warnings.push(args.join(' '));
  try {
    return await f();
  } finally {
    console.warn = warn;
    assert.deepEqual(warnings, []);
  }
}

for (const rel of CONTENTS) {
  for (const rig of ['content', 'canonical']) {
    test(`toGlb: ${rel} on the ${rig} rig validates, and GLTFLoader poses every joint like the BVH`, async () => {
      const content = s.importBvh(read(fixture(rel)));
      const [o] = await s.stylize(content, { label: 'old', seed: 5, rig });
      const glb = o.toGlb();
      assert.ok(glb instanceof Uint8Array);
      const report = await validate(glb, rel);
      assert.equal(report.info.animationCount, 1);
      assert.equal(report.info.skinCount ?? 1, 1);

      const gltf = await noWarnings(() => load(glb));
      const json = gltf.parser.json;
      const joints = o.skeleton.names.length;
      assert.equal(json.nodes.length, joints + 1, 'one node per joint and the skinned mesh');
      json.nodes.slice(0, joints).forEach((n, j) => assert.equal(n.name, o.skeleton.names[j]));
      const { metresPerUnit, orientation, frames } = json.scenes[0].extras;
      assert.equal(frames, o.frames);
      const scale = rig === 'canonical' ? 0.01 : content.rigReport().scale / 100;
      assert.ok(Math.abs(metresPerUnit - scale) < 1e-12, `metresPerUnit ${metresPerUnit} vs ${scale}`);
      if (rig === 'canonical') assert.deepEqual(orientation, [0, 0, 0, 1]);
      const turn = new THREE.Quaternion(...orientation);

      assert.equal(gltf.animations.length, 1);
      const clip = gltf.animations[0];
      assert.ok(Math.abs(clip.duration - (o.frames - 1) / o.fps) < 1e-4);
      // The loader's objects of nodes 0 … joints−1, by its node associations.
      const byNode = new Map();
      gltf.scene.traverse((obj) => {
        const a = gltf.parser.associations.get(obj);
        if (a?.nodes !== undefined && !byNode.has(a.nodes)) byNode.set(a.nodes, obj);
      });
      const objects = Array.from({ length: joints }, (_, j) => byNode.get(j));
      assert.ok(objects.every((b) => b?.isBone), 'every joint is a bone of the skin');
      let skinned = null;
      gltf.scene.traverse((obj) => (skinned ??= obj.isSkinnedMesh ? obj : null));
      assert.ok(skinned, 'a skinned mesh');
      assert.equal(skinned.skeleton.bones.length, joints);

      const worst = worstError(gltf.scene, clip, objects, o, scale, turn);
      assert.ok(worst < TOLERANCE_M, `worst joint error ${worst} m`);

      // Upright: the head above the hips in Y (glTF is Y up), on every rig. An orientation check
      // (a wrong up axis puts the head level with or below the hips), not a posture one: `old` on
      // the crouching CMU-31 content hunches to 0.24-0.31 m over its frames.
      const names = o.skeleton.names.map((n) => n.toLowerCase());
      const head = names.findIndex((n) => n.includes('head'));
      const hips = names.findIndex((n) => n.includes('hip') || n.includes('pelvis'));
      const p = o.positions();
      assert.ok(expected(p, joints, 0, head, scale, turn).y - expected(p, joints, 0, hips, scale, turn).y > 0.2, 'head above hips');
      o.free();
    });
  }
}

test('toThreeClip: a Skeleton and an AnimationClip that pose every joint like the BVH', async () => {
  for (const rel of CONTENTS) {
    for (const rig of ['content', 'canonical']) {
      const content = s.importBvh(read(fixture(rel)));
      const [o] = await s.stylize(content, { label: 'proud', seed: 2, rig });
      const three = o.toThreeClip(THREE, { name: 'proud' });
      const { root, bones, skeleton, clip, metresPerUnit, orientation } = three;
      const joints = o.skeleton.names.length;
      assert.ok(root instanceof THREE.Group);
      assert.ok(skeleton instanceof THREE.Skeleton);
      assert.ok(clip instanceof THREE.AnimationClip);
      assert.equal(clip.name, 'proud');
      assert.equal(bones.length, joints);
      assert.equal(skeleton.bones.length, joints);
      assert.equal(new Set(bones.map((b) => b.name)).size, joints, 'unique bone names');
      bones.forEach((b, j) => {
        const parent = o.skeleton.parents[j];
        assert.equal(b.parent, parent < 0 ? root : bones[parent], `bone ${j}'s parent`);
      });
      assert.ok(clip.validate(), 'the clip validates');
      assert.ok(clip.tracks.length >= joints - 1, `${clip.tracks.length} tracks`);
      const scale = rig === 'canonical' ? 0.01 : content.rigReport().scale / 100;
      assert.ok(Math.abs(metresPerUnit - scale) < 1e-12);
      const worst = await noWarnings(() => worstError(root, clip, bones, o, scale, new THREE.Quaternion(...orientation)));
      assert.ok(worst < TOLERANCE_M, `${rel} (${rig}): worst joint error ${worst} m`);

      // The same as the .glb's: GLTFLoader's clip drives the same bone values.
      const gltf = await load(o.toGlb());
      assert.equal(gltf.animations[0].tracks.length, clip.tracks.length);
      o.free();
    }
  }
});

test('toThreeClip and toGlb: bad arguments and freed results are coded errors', async () => {
  const [o] = await s.stylize(read(fixture('foreign/m21_walk.bvh')), { label: 'old' });
  for (const bad of [undefined, null, {}, { Bone: THREE.Bone }]) {
    assert.throws(() => o.toThreeClip(bad), (e) => e.code === 'BAD_REQUEST' && /three\.js module/.test(e.message));
  }
  o.free();
  assert.throws(() => o.toGlb(), (e) => e.code === 'BAD_REQUEST');
  assert.throws(() => o.toThreeClip(THREE), (e) => e.code === 'BAD_REQUEST');
});
