// The Web Worker that runs the model: loads the package (wasm + weights, with download progress),
// imports BVH files into named slots ('content', 'ref'), and stylizes (BVH, joint positions, .glb).
// The page talks to it through worker-client.js; every request is answered in order with
// {id, result} or {id, error: {code, message}}.

import { Stylizer } from '../pkg/index.js';

/** When this worker's modules had loaded (the engine's package among them): ms since the epoch, as the page can compare. */
const started = performance.timeOrigin + performance.now();
let stylizer = null;
const slots = new Map();
/** Where the package's download progress goes: the request in progress (load, or a stylize that fetches a model). */
let reportProgress = null;

const coded = (code, message) => Object.assign(new Error(message), { code });

/** The package's style source; `inferred`: the reference's label where the supervised model needs one and none was chosen. */
function styleOf(src, inferred) {
  switch (src?.kind) {
    case 'label':
      return { label: src.label };
    case 'motion': {
      const m = slots.get('ref');
      if (!m) throw coded('BAD_REQUEST', 'load a reference motion first');
      const label = src.label ?? inferred;
      return label ? { styleMotion: m, label } : { styleMotion: m };
    }
    case 'prior':
      return { prior: true };
    case 'mix':
      return { mix: { a: styleOf(src.a), b: styleOf(src.b), t: src.t } };
    default:
      throw coded('BAD_REQUEST', 'unknown style source');
  }
}

const ops = {
  async load({ backend, weights, settings, shipped }, progress) {
    const t0 = performance.now();
    let fetchMs = 0;
    // The package fetches the weights (with progress); a reload (another backend) reuses the
    // bytes the previous Stylizer keeps; `weights`: a user's weights folder as bytes. The previous
    // Stylizer stays in use until the new one has loaded (weights that cannot be used change nothing);
    // `shipped`: the package's own weights again.
    const previous = stylizer;
    if (previous || weights) progress({ stage: 'compile' });
    let loading = true;
    reportProgress = progress;
    const onProgress = ({ loaded, total, setting }) => {
      reportProgress?.({ stage: 'weights', loaded, total, setting });
      if (loading && loaded === total) {
        fetchMs = performance.now() - t0;
        reportProgress?.({ stage: 'compile' });
      }
    };
    const next = await Stylizer.load({ weights: weights ?? (shipped ? undefined : previous ?? undefined), backend, settings, onProgress });
    loading = false;
    stylizer = next;
    if (previous) previous.free();
    return {
      styles: stylizer.styles(),
      settings: stylizer.settings(),
      backend: stylizer.backend,
      fallbackReason: stylizer.fallbackReason,
      loadMs: stylizer.loadMs - fetchMs, // after the download (the wasm starts during it): loading the weights
      weightsId: stylizer.weightsId,
      fetchMs,
      totalMs: performance.now() - t0,
      // On the page's clock (ms since epoch): when this worker's modules had loaded, and the load began.
      clock: { workerReady: started, loadBegan: performance.timeOrigin + t0 },
    };
  },

  async inspect({ text, map }) {
    if (!stylizer) throw coded('INTERNAL', 'the model is not loaded yet');
    return stylizer.inspectBvh(text, { map });
  },

  async import({ slot, text, map }) {
    if (!stylizer) throw coded('INTERNAL', 'the model is not loaded yet');
    const motion = stylizer.importBvh(text, { map });
    const old = slots.get(slot);
    slots.set(slot, motion);
    old?.free();
    const report = motion.rigReport();
    const display = motion.source();
    // The user's joints matched to the canonical hips and upper arms: the views face the character's front.
    const user = Object.fromEntries(report.matched ?? []);
    const index = (canonical) => display.names.indexOf(user[canonical]);
    const pairs = [['UpperLeg_L', 'UpperLeg_R'], ['UpperArm_L', 'UpperArm_R']]
      .map(([l, r]) => [index(l), index(r)])
      .filter(([l, r]) => l >= 0 && r >= 0);
    return {
      result: {
        frames: motion.frames,
        rig: motion.rig,
        report: { up: report.up_axis, forward: report.forward_axis, scale: report.scale, missing: report.missing, matched: report.matched, pairs },
        display,
      },
      transfer: [display.positions.buffer],
    };
  },

  async stylize({ source, parts, unsupervised, samples, seed, temperature, strength, guidance, rig, only, glb }, progress) {
    // The unsupervised model is fetched when it is first used: its download is this request's progress.
    reportProgress = progress;
    const content = slots.get('content');
    if (!content) throw coded('BAD_REQUEST', 'load a content motion first');
    const t0 = performance.now();
    const needsLabel = (src) => (src?.kind === 'mix' ? needsLabel(src.a) || needsLabel(src.b) : src?.kind === 'motion' && !src.label);
    const ref = slots.get('ref');
    const inferredLabel = !unsupervised && ref && needsLabel(source) ? await stylizer.inferLabel(ref) : undefined;
    // Parts of their own: 'content', or a source (a reference without a label: the package infers it per part).
    const own = parts && Object.fromEntries(Object.entries(parts).map(([p, v]) => [p, v === 'content' ? 'content' : styleOf(v)]));
    const outputs = await stylizer.stylize(content, { ...styleOf(source, inferredLabel), parts: own, unsupervised, samples, seed, temperature, strength, guidance, rig });
    const ms = performance.now() - t0;
    const picked = only == null ? outputs : [outputs[only]];
    const result = picked.map((o) => ({
      bvh: o.toBvh(),
      positions: only == null ? o.positions() : null,
      names: o.skeleton.names,
      parents: o.skeleton.parents,
      frames: o.frames,
      fps: o.fps,
      glb: glb ? o.toGlb() : null,
    }));
    for (const o of outputs) o.free();
    const transfer = result.flatMap((o) => [o.positions?.buffer, o.glb?.buffer]).filter(Boolean);
    return { result: { outputs: result, ms, inferredLabel }, transfer };
  },
};

let queue = Promise.resolve();
self.onmessage = ({ data }) => {
  const { id, op, args } = data;
  queue = queue.then(async () => {
    try {
      if (!ops[op]) throw coded('BAD_REQUEST', `unknown operation ${op}`);
      const answer = await ops[op](args ?? {}, (progress) => self.postMessage({ id, progress }));
      const { result, transfer } = answer && 'transfer' in answer ? answer : { result: answer, transfer: [] };
      self.postMessage({ id, result }, transfer);
    } catch (e) {
      self.postMessage({ id, error: { code: e?.code ?? 'INTERNAL', message: String(e?.message ?? e), line: e?.line, kind: e?.kind } });
    }
  });
};
