// Share links: everything needed to reproduce a result (the motions — a sample's id, or the BVH
// text compressed —, style source, model, labels, seed, samples, temperature, strength, guidance, mix t, the picked
// sample, and a fingerprint of the weights that made it) as JSON, deflate-raw compressed and base64url-encoded into the URL fragment (#s=...).
// Decoding is defensive: size limits before and while inflating, and every field validated; the
// BVH text itself is validated later by the package's importer.

export const MAX_LINK_CHARS = 120_000; // a link longer than this is refused (most apps mangle longer URLs)
const MAX_INFLATED = 16 * 1024 * 1024;
const MAX_BVH_CHARS = 8 * 1024 * 1024;
const PREFIX = '#s=';

async function pipe(bytes, stream, limit) {
  const reader = new Blob([bytes]).stream().pipeThrough(stream).getReader();
  const chunks = [];
  let size = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    size += value.length;
    if (size > limit) {
      await reader.cancel();
      throw new Error('the link expands to too much data');
    }
    chunks.push(value);
  }
  const out = new Uint8Array(size);
  let at = 0;
  for (const c of chunks) {
    out.set(c, at);
    at += c.length;
  }
  return out;
}

function toBase64Url(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(text) {
  const s = atob(text.replace(/-/g, '+').replace(/_/g, '/'));
  const bytes = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
  return bytes;
}

/** The fragment ('#s=...') of a state; {fragment, chars}; fragment is null when it would be too long. */
export async function encodeState(state) {
  const json = new TextEncoder().encode(JSON.stringify({ v: 1, ...state }));
  const packed = await pipe(json, new CompressionStream('deflate-raw'), Infinity);
  const fragment = PREFIX + toBase64Url(packed);
  return { fragment: fragment.length <= MAX_LINK_CHARS ? fragment : null, chars: fragment.length };
}

export const hasState = (hash) => typeof hash === 'string' && hash.startsWith(PREFIX);

const oneOf = (value, options, fallback) => (options.includes(value) ? value : fallback);
const text = (value, max = 64) => (typeof value === 'string' && value.length <= max ? value : null);
const number = (value, lo, hi, fallback) => (typeof value === 'number' && Number.isFinite(value) && value >= lo && value <= hi ? value : fallback);

/** A manual joint mapping from a link: {canonical joint: file joint | null} (names checked by the importer). */
function jointMap(value) {
  const entries = typeof value === 'object' && !Array.isArray(value) ? Object.entries(value) : null;
  if (!entries || entries.length > 32 || !entries.every(([k, v]) => text(k) && (v === null || text(v, 120)))) {
    throw new Error('a motion in the link has a joint mapping that is not one');
  }
  return Object.fromEntries(entries);
}

function motionRef(value, sampleIds) {
  if (value == null || typeof value !== 'object') return null;
  if (typeof value.sample === 'string') {
    if (!sampleIds.includes(value.sample)) throw new Error(`unknown sample "${value.sample.slice(0, 40)}"`);
    return { sample: value.sample };
  }
  if (typeof value.bvh === 'string') {
    if (value.bvh.length > MAX_BVH_CHARS) throw new Error('a motion in the link is too large');
    const ref = { bvh: value.bvh, name: text(value.name, 120) ?? 'shared.bvh' };
    if (value.map != null) ref.map = jointMap(value.map);
    return ref;
  }
  throw new Error('a motion in the link is neither a sample nor BVH text');
}

const KINDS = ['label', 'motion', 'prior'];
/** A body part's choice: '' (the style), 'content', 'motion' or 'label:NAME' (the label checked by the page). */
const partChoice = (v) => (v === 'content' || v === 'motion' ? v : typeof v === 'string' && /^label:/.test(v) && text(v, 70) ? v : '');
const part = (p) => ({ kind: oneOf(p?.kind, KINDS, 'label'), label: text(p?.label) ?? 'normal' });

/** The state of a fragment, validated; throws an Error with a readable message when it is not usable. */
export async function decodeState(hash, sampleIds) {
  if (!hasState(hash)) throw new Error('not a share link');
  const body = hash.slice(PREFIX.length);
  if (body.length > MAX_LINK_CHARS) throw new Error('the link is too long');
  if (!/^[A-Za-z0-9_-]+$/.test(body)) throw new Error('the link has characters a share link never has');
  let raw;
  try {
    const json = await pipe(fromBase64Url(body), new DecompressionStream('deflate-raw'), MAX_INFLATED);
    raw = JSON.parse(new TextDecoder('utf-8', { fatal: true }).decode(json));
  } catch (e) {
    throw new Error(`the link is damaged (${e.message})`);
  }
  if (raw == null || typeof raw !== 'object' || raw.v !== 1) throw new Error('the link is not a version-1 share link');
  const content = motionRef(raw.content, sampleIds);
  if (!content) throw new Error('the link has no content motion');
  return {
    content,
    ref: motionRef(raw.ref, sampleIds),
    model: oneOf(raw.model, ['supervised', 'unsupervised'], 'supervised'),
    mode: oneOf(raw.mode, ['label', 'motion', 'prior', 'mix'], 'label'),
    label: text(raw.label) ?? 'normal',
    refLabel: text(raw.refLabel) ?? 'normal',
    mixA: part(raw.mixA),
    mixB: part(raw.mixB),
    t: number(raw.t, 0, 1, 0.5),
    seed: Math.floor(number(raw.seed, 0, 4294967295, 0)),
    samples: Math.floor(number(raw.samples, 1, 8, 1)),
    temperature: number(raw.temperature, 0, 4, 0.3),
    // Links from before the strength control reproduce the default, 1.
    strength: number(raw.strength, 0, 2, 1),
    // Links from before the guidance control reproduce what they made: no guidance.
    guidance: number(raw.guidance, 0, 3, 0),
    pick: Math.floor(number(raw.pick, 0, 7, 0)),
    rig: oneOf(raw.rig, ['content', 'canonical'], 'content'),
    // Links from before body parts: every part takes the style.
    parts: Object.fromEntries(['lower', 'upper', 'head'].map((p) => [p, partChoice(raw.parts?.[p])])),
    weights: typeof raw.weights === 'string' && /^[0-9a-f]{8}$/.test(raw.weights) ? raw.weights : null,
  };
}
