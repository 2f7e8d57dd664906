// The Web Worker that runs the model: loads the package (wasm + weights, with download progress),
// imports BVH files into named slots ('content', 'ref'), and stylizes. The page talks to it through
// engine.js; every request is answered in order with {id, result} or {id, error: {code, message}}.

import { Stylizer } from '../pkg/index.js';
import { bvhPositions } from './bvh-fk.js';

const WEIGHTS = new URL('../pkg/weights/', import.meta.url);
let stylizer = null;
let weights = null;
const slots = new Map();

const coded = (code, message) => Object.assign(new Error(message), { code });

/** Bytes of a URL, reporting progress as {loaded} deltas. */
async function fetchBytes(url, onBytes) {
  let response;
  try {
    response = await fetch(url);
  } catch (e) {
    throw coded('FETCH', `cannot fetch ${url.pathname}: ${e.message}`);
  }
  if (!response.ok) throw coded('FETCH', `cannot fetch ${url.pathname}: HTTP ${response.status}`);
  const reader = response.body.getReader();
  const chunks = [];
  let size = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    chunks.push(value);
    size += value.length;
    onBytes(value.length);
  }
  const bytes = new Uint8Array(size);
  let at = 0;
  for (const c of chunks) {
    bytes.set(c, at);
    at += c.length;
  }
  return bytes;
}

/** The package's weight files, fetched here so that the page can show download progress. */
async function fetchWeights(progress) {
  const manifestBytes = await fetchBytes(new URL('manifest.json', WEIGHTS), () => {});
  const manifest = JSON.parse(new TextDecoder().decode(manifestBytes));
  const files = [['norm', manifest.norm], ...manifest.models.map((m) => [m.setting, m.file])];
  const sizes = await Promise.all(
    files.map(async ([, file]) => {
      const r = await fetch(new URL(file, WEIGHTS), { method: 'HEAD' }).catch(() => null);
      return Number(r?.headers.get('content-length') ?? 0);
    }),
  );
  const total = sizes.reduce((a, b) => a + b, 0);
  let loaded = 0;
  const bytes = await Promise.all(
    files.map(([, file]) =>
      fetchBytes(new URL(file, WEIGHTS), (n) => {
        loaded += n;
        progress({ stage: 'weights', loaded, total });
      }),
    ),
  );
  const out = { manifest: manifestBytes };
  files.forEach(([key], i) => {
    out[key] = bytes[i];
  });
  return out;
}

function styleOf(src) {
  switch (src?.kind) {
    case 'label':
      return { label: src.label };
    case 'motion': {
      const m = slots.get('ref');
      if (!m) throw coded('BAD_REQUEST', 'load a reference motion first');
      return src.label ? { styleMotion: m, label: src.label } : { styleMotion: m };
    }
    case 'prior':
      return { prior: true };
    case 'mix':
      return { mix: { a: styleOf(src.a), b: styleOf(src.b), t: src.t } };
    default:
      throw coded('BAD_REQUEST', 'unknown style source');
  }
}

/** A short fingerprint of the weights (FNV-1a of the manifest and statistics): share links carry it. */
function fingerprint(...parts) {
  let h = 0x811c9dc5;
  for (const bytes of parts) for (const b of bytes) h = Math.imul(h ^ b, 0x01000193) >>> 0;
  return h.toString(16).padStart(8, '0');
}

const ops = {
  async load({ backend }, progress) {
    const t0 = performance.now();
    weights ??= await fetchWeights(progress);
    const fetchMs = performance.now() - t0;
    progress({ stage: 'compile' });
    stylizer?.engine?.free?.();
    stylizer = null;
    stylizer = await Stylizer.load({ weights, backend });
    return {
      styles: stylizer.styles(),
      settings: stylizer.settings(),
      backend: stylizer.backend,
      fallbackReason: stylizer.fallbackReason,
      loadMs: stylizer.loadMs,
      weightsId: fingerprint(weights.manifest, weights.norm),
      fetchMs,
      totalMs: performance.now() - t0,
    };
  },

  async import({ slot, text }) {
    if (!stylizer) throw coded('INTERNAL', 'the model is not loaded yet');
    const motion = stylizer.importBvh(text);
    const old = slots.get(slot);
    slots.set(slot, motion);
    old?.content?.free?.();
    const report = motion.rigReport();
    const display = bvhPositions(text);
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
        report: { up: report.up_axis, forward: report.forward_axis, scale: report.scale, missing: report.missing, pairs },
        display,
      },
      transfer: [display.positions.buffer],
    };
  },

  async stylize({ source, unsupervised, samples, seed, temperature, rig, only }) {
    const content = slots.get('content');
    if (!content) throw coded('BAD_REQUEST', 'load a content motion first');
    const t0 = performance.now();
    const outputs = await stylizer.stylize(content, { ...styleOf(source), unsupervised, samples, seed, temperature, rig });
    const ms = performance.now() - t0;
    const picked = only == null ? outputs : [outputs[only]];
    const result = picked.map((o) => ({
      bvh: o.toBvh(),
      positions: only == null ? o.positions() : null,
      names: o.skeleton.names,
      parents: o.skeleton.parents,
      frames: o.frames,
      fps: o.fps,
    }));
    for (const o of outputs) o.output?.free?.();
    return { result: { outputs: result, ms }, transfer: result.filter((o) => o.positions).map((o) => o.positions.buffer) };
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
