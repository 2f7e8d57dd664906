// The page: wires the controls, the worker (worker-client.js), the views, playback, share links and files.

import { PARTS, fillSelect, partOptions, readControls, requestOf, styleName, syncControls, usesReference, writeControls } from './controls.js';
import { WorkerClient } from './worker-client.js';
import { Player } from './player.js';
import { SAMPLES, fetchSample, sampleById } from './samples.js';
import { MAX_LINK_CHARS, decodeState, encodeState, hasState } from './share.js';
import { Thumbs } from './thumbs.js';
import { onFileDrop, progress, showError, status } from './ui.js';
import { MAPPABLE, askMapping, initMapping } from './mapping.js';
import { fromFolder, fromZip } from './weights.js';
import { Views, toDisplay } from './views.js';
import { canonicalIndices } from './canonical.js';

const el = (id) => document.getElementById(id);
/** Milliseconds since navigation of the boot's steps (state.timings.marks: the budget test prints them). */
const marks = { app: Math.round(performance.now()) };
const mark = (name) => (marks[name] ??= Math.round(performance.now()));
const MAX_FILE_BYTES = 32 * 1024 * 1024;
const DEFAULT = { content: 'walk-normal', ref: 'walk-elderly', label: 'old' };

// The engine (the worker: wasm and weights) starts loading first: the first result waits for it, not
// for the page. The page's head has usually started it already (index.html); boot() awaits its answer.
const worker = new WorkerClient(window.__engineStart, (p) => loadProgress(p));
delete window.__engineStart;
const firstLoad = worker.first
  ? { t0: worker.firstStarted, call: worker.first }
  : { t0: performance.now(), call: worker.call('load', { backend: 'cpu' }, (p) => loadProgress(p)) };
const views = new Views({ front: el('view-front'), side: el('view-side'), top: el('view-top') });
/**
 * The 3D view (three.js): created after the first result, so that neither loading three.js nor its
 * first frames (WebGL shaders compiling, on a CPU where there is no GPU) hold the first result
 * back; until then it gathers what it is to show.
 */
let view3d = null;
let view3dShows = {};
/** Both the orthographic views and the 3D view show the same motions in the same layout. */
const showMotions = (options) => {
  views.set(options);
  if (view3d) view3d.set(options);
  else view3dShows = { ...view3dShows, ...options };
};
let view3dStarted = null;
/** Starts the 3D view (once); resolves when it shows what the page shows. */
function startView3D() {
  view3dStarted ??= import('./view3d.js')
    .then(({ View3D }) => {
      view3d = new View3D(el('view-3d'), el('view-3d-note'));
      state.view3d = view3d;
      view3d.set(view3dShows);
      view3d.draw(player.time);
      mark('view3d');
    })
    .catch((e) => showError('The 3D view could not start', { code: 'INTERNAL', message: e.message }));
  return view3dStarted;
}
const thumbs = new Thumbs(el('thumbs-box'), el('thumbs'), (i) => pickResult(i));
const player = new Player((time) => showTime(time));

/** What the page holds: the two motions (with where they came from), the results and what made them. */
const state = {
  styles: [],
  content: null, // {source: {sample} | {bvh, name}, name, display, report}
  ref: null,
  results: [], // [{bvh, display}]
  pick: 0,
  made: null, // {controls, request, content, ref}: what produced `results`
  busy: 0,
  rerun: false,
  timings: { marks },
  custom: null, // a user's weights: {name, settings}
};
window.__demo = state; // for the end-to-end tests and the curious (read-only use); state.view3d once it starts

function setBusy(delta) {
  state.busy += delta;
  document.body.dataset.busy = String(state.busy > 0);
  el('stylize').disabled = state.busy > 0 || !state.content || !state.styles.length;
  el('download').disabled = state.busy > 0 || !state.results.length;
  el('share').disabled = state.busy > 0 || !state.results.length;
}

// ---------- playback ----------

function showTime(time) {
  views.draw(time);
  view3d?.draw(time);
  thumbs.draw(time);
  // Frame k covers [k/fps, (k+1)/fps): floor, clamped to the last frame (a looping one-frame clip's
  // clock runs in [0, 1/fps) and must read 0 / 0).
  const fps = 30;
  const last = Math.max(0, Math.round(player.duration * fps) - 1);
  const frame = Math.min(last, Math.floor(time * fps + 1e-6));
  el('scrub').value = String(frame);
  el('frame-label').textContent = `${frame} / ${last}`;
}

function updateDuration() {
  const d = (m) => (m ? m.frames / m.fps : 0);
  const duration = Math.max(d(state.content?.display), d(state.results[state.pick]?.display));
  el('scrub').max = String(Math.max(0, Math.round(duration * 30) - 1));
  player.setDuration(duration);
}

player.onState = (playing) => {
  el('play').textContent = playing ? 'Pause' : 'Play';
  el('play').setAttribute('aria-pressed', String(playing));
};
el('play').addEventListener('click', () => player.setPlaying(!player.playing));
el('scrub').addEventListener('input', () => {
  player.setPlaying(false);
  player.seek(Number(el('scrub').value) / 30);
});
el('speed').addEventListener('change', () => (player.speed = Number(el('speed').value)));
el('loop').addEventListener('change', () => (player.loop = el('loop').checked));
const viewOptions = () => ({ layout: el('layout').value, showContent: el('show-content').checked, showResult: el('show-result').checked });
for (const id of ['layout', 'show-content', 'show-result']) el(id).addEventListener('change', () => showMotions(viewOptions()));

document.addEventListener('keydown', (e) => {
  const t = e.target;
  if (t instanceof HTMLInputElement || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement || e.ctrlKey || e.metaKey || e.altKey) return;
  if ((e.key === ' ' && !(t instanceof HTMLButtonElement)) || e.key === 'k') {
    e.preventDefault();
    player.setPlaying(!player.playing);
  } else if (e.key === ',' || e.key === '.') {
    player.setPlaying(false);
    player.seek(player.time + (e.key === '.' ? 1 : -1) / 30);
  }
});

// ---------- motions ----------

function describe(m) {
  const { frames, fps } = m.file;
  const missing = m.report.missing?.length ? ` · unmatched: ${m.report.missing.join(', ')}` : '';
  return `${m.name} · ${m.rig} rig, ${m.display.parents.length} joints · ${frames} frames at ${Math.round(fps)} fps (${(frames / fps).toFixed(1)} s)${missing}`;
}

/**
 * Imports BVH text into the worker's slot ('content' or 'ref'); returns the motion, or null after
 * showing the error. A file whose rig does not match opens the joint-mapping panel, prefilled with
 * the importer's guesses, and is imported again with the mapping chosen (kept in `source.map`,
 * and so in share links).
 */
async function loadMotion(slot, text, source, name) {
  for (;;) {
    const motion = await importMotion(slot, text, source, name);
    const e = state.lastError;
    if (motion || source.bvh == null || !MAPPABLE.has(e?.code)) return motion;
    let info;
    try {
      info = await worker.call('inspect', { text, map: e.code === 'BAD_MAP' ? undefined : source.map });
    } catch {
      return null; // the error shown stands
    }
    status(`${name}: choose its joints below, or cancel.`);
    const map = await askMapping(name, info);
    if (!map) {
      status(slot === 'content' && state.content ? `Still showing ${state.content.name}.` : 'Ready.');
      return null;
    }
    source = { ...source, map };
  }
}

async function importMotion(slot, text, source, name) {
  setBusy(1);
  status(`Reading ${name}…`);
  progress('busy');
  try {
    const r = await worker.call('import', { slot, text, map: source.map });
    const display = { ...toDisplay(r.display, r.report), canonical: canonicalIndices(r.display.names, r.report.matched) };
    const motion = { source, name, rig: r.rig, report: r.report, file: r.display.file, display };
    state[slot] = motion;
    showError(null);
    if (slot === 'content') {
      state.results = [];
      state.made = null;
      thumbs.show([], null, 0);
      showMotions({ content: motion.display, result: null, ...viewOptions() });
      updateDuration();
      el('content-info').textContent = describe(motion);
      el('share-url').hidden = true;
      el('share-info').textContent = '';
    } else {
      el('ref-info').textContent = describe(motion);
    }
    status(`Loaded ${name}.`);
    return motion;
  } catch (e) {
    state.lastError = e;
    showError(`Could not load ${name}`, e);
    status(slot === 'content' && state.content ? `Still showing ${state.content.name}.` : 'Ready.');
    return null;
  } finally {
    progress(null);
    setBusy(-1);
  }
}

/** Loads a built-in sample into `slot`; `text`: its text, already being fetched. */
async function loadSample(slot, id, text = null) {
  const sample = sampleById(id);
  if (!sample) return null;
  try {
    text = await (text ?? fetchSample(sample));
    const m = await loadMotion(slot, text, { sample: id }, sample.file);
    if (m && slot === 'ref' && sample.label && state.styles.includes(sample.label)) el('ref-label').value = sample.label;
    if (m) el(slot === 'content' ? 'content-sample' : 'ref-sample').value = id;
    return m;
  } catch (e) {
    showError(`Could not fetch ${sample.file}`, e);
    return null;
  }
}

async function loadFile(slot, file) {
  if (!file) return null;
  if (file.size > MAX_FILE_BYTES) {
    showError(`Could not load ${file.name}`, { code: 'TOO_LONG', message: `the file is ${(file.size / 1048576).toFixed(1)} MB; this page reads BVH files up to 32 MB` });
    return null;
  }
  const text = await file.text();
  const m = await loadMotion(slot, text, { bvh: text, name: file.name }, file.name);
  if (m) markUploaded(slot, `uploaded: ${file.name}`);
  return m;
}

el('content-file').addEventListener('change', (e) => {
  loadFile('content', e.target.files[0]);
  e.target.value = '';
});
el('ref-file').addEventListener('change', (e) => {
  loadFile('ref', e.target.files[0]);
  e.target.value = '';
});
el('content-sample').addEventListener('change', (e) => e.target.value && loadSample('content', e.target.value));
el('ref-sample').addEventListener('change', (e) => e.target.value && loadSample('ref', e.target.value));

// Drag and drop anywhere on the page: the content motion.
onFileDrop((file) => loadFile('content', file));
initMapping();

// ---------- stylizing ----------

function pickResult(i) {
  state.pick = Math.max(0, Math.min(state.results.length - 1, i));
  thumbs.select(state.pick);
  showMotions({ result: state.results[state.pick]?.display ?? null });
  updateDuration();
}

async function stylize() {
  if (!state.content) return;
  if (state.busy) {
    state.rerun = true;
    return;
  }
  const controls = readControls();
  if (usesReference(controls) && !state.ref) {
    showError('Cannot stylize', { code: 'BAD_REQUEST', message: 'load a reference motion first' });
    return;
  }
  const request = requestOf(controls);
  setBusy(1);
  progress('busy');
  const n = request.samples;
  status(`Stylizing ${state.content.name}${n > 1 ? ` (${n} samples)` : ''}…`);
  const started = performance.now();
  try {
    const { outputs, ms, inferredLabel } = await worker.call('stylize', request, (p) => {
      if (p.stage === 'weights' && p.total) {
        status(`Downloading the ${p.setting ?? ''} model: ${(p.loaded / 1048576).toFixed(1)} of ${(p.total / 1048576).toFixed(1)} MB…`);
        progress(p.loaded / p.total);
      }
    });
    const report = state.content.report;
    const turn = state.content.display.turn;
    state.results = outputs.map((o) => ({ bvh: o.bvh, display: { ...toDisplay(o, report, turn), canonical: canonicalIndices(o.names, report.matched) } }));
    state.made = { controls, request, content: state.content, ref: usesReference(controls) ? state.ref : null };
    state.timings.lastStylizeMs = ms;
    state.timings.lastRoundTripMs = performance.now() - started;
    state.timings.firstResultMs ??= performance.now();
    mark('result');
    showError(null);
    thumbs.show(state.results.map((r) => r.display), state.content.display, 0);
    pickResult(Math.min(state.pendingPick ?? 0, state.results.length - 1));
    thumbs.select(state.pick);
    state.pendingPick = null;
    const inferred = inferredLabel ? ` (the reference's label, inferred: ${inferredLabel})` : '';
    status(`Stylized as “${styleName(controls)}”${inferred} in ${Math.round(ms)} ms (${state.results[0].display.frames} frames).`);
    document.body.dataset.results = String((Number(document.body.dataset.results) || 0) + 1);
  } catch (e) {
    showError('Stylization failed', e);
    status('Ready.');
  } finally {
    progress(null);
    setBusy(-1);
  }
  if (state.rerun) {
    state.rerun = false;
    stylize();
  }
}

el('stylize').addEventListener('click', stylize);
document.querySelector('.panel').addEventListener('change', syncControls);
el('mix-t').addEventListener('input', syncControls);
el('temperature').addEventListener('input', syncControls);
el('strength').addEventListener('input', syncControls);
el('guidance').addEventListener('input', syncControls);
// The mix, strength and guidance sliders restyle as they are released (one request at a time; the latest
// position wins).
el('mix-t').addEventListener('change', () => state.made && stylize());
el('strength').addEventListener('change', () => state.made && stylize());
el('guidance').addEventListener('change', () => state.made && stylize());

// ---------- download, share ----------

function saveText(text, name, type = 'text/plain') {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

el('download').addEventListener('click', async () => {
  const made = state.made;
  if (!made || !state.results.length) return;
  const base = `${made.content.name.replace(/\.bvh$/i, '')}.${styleName(made.controls)}${state.results.length > 1 ? `.${state.pick + 1}` : ''}`;
  const rig = el('rig').value;
  const glb = el('format').value === 'glb';
  if (rig === 'content' && !glb) {
    saveText(state.results[state.pick].bvh, `${base}.bvh`);
    return;
  }
  // The canonical rig or glTF: the same request again (same seed, same bits), written on the
  // rig and in the format asked for.
  setBusy(1);
  progress('busy');
  const name = `${base}${rig === 'canonical' ? '.canonical' : ''}.${glb ? 'glb' : 'bvh'}`;
  status(`Writing ${name}…`);
  try {
    const { outputs } = await worker.call('stylize', { ...made.request, rig, only: state.pick, glb });
    if (glb) saveText(outputs[0].glb, name, 'model/gltf-binary');
    else saveText(outputs[0].bvh, name);
    status('Downloaded.');
  } catch (e) {
    showError('Download failed', e);
  } finally {
    progress(null);
    setBusy(-1);
  }
});

el('share').addEventListener('click', async () => {
  const made = state.made;
  if (!made) return;
  const motionRef = (m) => m && (m.source.sample ? { sample: m.source.sample } : { bvh: m.source.bvh, name: m.source.name, ...(m.source.map ? { map: m.source.map } : {}) });
  const payload = {
    ...made.controls,
    rig: el('rig').value,
    pick: state.pick,
    content: motionRef(made.content),
    ref: motionRef(made.ref),
    weights: state.timings.load?.weightsId,
  };
  const { fragment, chars } = await encodeState(payload);
  const input = el('share-url');
  if (!fragment) {
    input.hidden = true;
    el('share-info').textContent = `This motion is too large to share in a link: ${Math.round(chars / 1000)} kB once compressed, links hold ${MAX_LINK_CHARS / 1000} kB. Use a built-in sample or a shorter clip.`;
    return;
  }
  const url = `${location.origin}${location.pathname}${fragment}`;
  history.replaceState(null, '', fragment);
  input.value = url;
  input.hidden = false;
  input.select();
  try {
    await navigator.clipboard.writeText(url);
    el('share-info').textContent = `Link copied (${Math.round(url.length / 100) / 10} kB). Opening it reproduces this result.`;
  } catch {
    el('share-info').textContent = 'Copy the link above (the clipboard is not available here).';
  }
});

let linkError = null;

/** Applies a share link's state: motions, controls, then stylizes. */
async function openShared(hash) {
  let shared;
  try {
    shared = await decodeState(hash, SAMPLES.map((s) => s.id));
    const partLabels = Object.values(shared.parts).filter((v) => v.startsWith('label:')).map((v) => v.slice('label:'.length));
    for (const l of [shared.label, shared.refLabel || 'normal', shared.mixA.label, shared.mixB.label, ...partLabels]) {
      if (!state.styles.includes(l)) throw new Error(`unknown style label "${l}"`);
    }
  } catch (e) {
    linkError = { code: 'BAD_LINK', message: e.message };
    showError('This share link cannot be opened', linkError);
    return false;
  }
  const load = (slot, ref) => (ref.sample ? loadSample(slot, ref.sample) : loadMotion(slot, ref.bvh, ref, ref.name).then((m) => m && markUploaded(slot, `shared: ${ref.name}`) && m));
  for (const slot of ['content', 'ref']) {
    if (!shared[slot] || (await load(slot, shared[slot]))) continue;
    const e = state.lastError;
    linkError = { code: e?.code ?? 'BAD_LINK', message: `its ${slot === 'ref' ? 'reference' : 'content'} motion could not be loaded: ${e?.message}`, line: e?.line };
    showError('This share link cannot be opened', linkError);
    return false;
  }
  writeControls(shared);
  state.pendingPick = shared.pick;
  await stylize();
  const here = state.timings.load?.weightsId;
  el('share-info').textContent =
    shared.weights && shared.weights !== here
      ? `This link was made with other model weights (${shared.weights}; these are ${here}): the result may differ from the one shared.`
      : 'Opened a share link: this is the shared result.';
  return true;
}

/** Shows a file's name as the chosen entry of the slot's sample picker. */
function markUploaded(slot, text) {
  const select = el(slot === 'content' ? 'content-sample' : 'ref-sample');
  const option = select.querySelector('option[value=""]') ?? select.appendChild(document.createElement('option'));
  option.value = '';
  option.textContent = text;
  select.value = '';
  return true;
}

window.addEventListener('hashchange', () => hasState(location.hash) && state.styles.length && openShared(location.hash));

// ---------- engine ----------

/** A load's progress (the weights' download, then the engine starting) on the status line and the bar. */
function loadProgress(p) {
  if (p.stage === 'weights' && p.total) {
    status(`Downloading the model: ${(p.loaded / 1048576).toFixed(1)} of ${(p.total / 1048576).toFixed(1)} MB…`);
    progress(p.loaded / p.total);
  } else if (p.stage === 'compile') {
    status('Starting the engine…');
    progress('busy');
  }
}

/**
 * Starts the engine on `backend`; `weights`: {weights, settings} of a user's folder, or {shipped: true};
 * `started`: the worker's answer to a load already asked for (the page's first, with its start time).
 */
async function loadEngine(backend, weights = { settings: state.custom?.settings }, started = null) {
  setBusy(1);
  const t0 = started?.t0 ?? performance.now();
  try {
    const info = await (started?.call ?? worker.call('load', { backend, ...weights }, loadProgress));
    state.styles = info.styles;
    state.timings.load = { ...info, roundTripMs: performance.now() - t0 };
    const gpu = 'gpu' in navigator ? 'this browser has WebGPU' : 'this browser has no WebGPU';
    el('backend-info').textContent =
      info.backend === 'webgpu'
        ? `Running on WebGPU (Burn wgpu, in a worker); model ready in ${Math.round(info.totalMs)} ms.`
        : backend === 'webgpu'
          ? `Running on the ${info.backend.toUpperCase()} — WebGPU fallback: ${info.fallbackReason ?? 'none'} (${gpu}).`
          : `Running on the ${info.backend.toUpperCase()} (Burn flex, wasm SIMD, in a worker); model ready in ${Math.round(info.totalMs)} ms.`;
    showError(null);
    return info;
  } catch (e) {
    showError('The model could not be loaded', e);
    status('The model could not be loaded.');
    return null;
  } finally {
    progress(null);
    setBusy(-1);
  }
}

/** The label drop-downs from the loaded weights' labels: `defaults[id]`, else the choice before if the weights still have it, else the first. */
function fillLabels(defaults = {}) {
  const labels = state.styles.map((s) => [s, s]);
  for (const id of ['label', 'ref-label', 'mix-a-label', 'mix-b-label', ...PARTS.map((p) => `part-${p}`)]) {
    const before = el(id).value;
    // The reference's label may also be left to the package to infer ('').
    const options = id === 'ref-label' ? [['', 'infer from the reference'], ...labels] : id.startsWith('part-') ? partOptions(state.styles) : labels;
    const keep = [defaults[id], before].find((v) => v != null && options.some(([o]) => o === v));
    fillSelect(el(id), options, keep);
  }
  syncControls();
}

/** Loads a user's weights folder (read by `read`, named `what`) in place of the current weights. */
async function useWeights(read, what) {
  let custom;
  try {
    custom = await read();
  } catch (e) {
    showError(`Could not use ${what} as weights`, e);
    return;
  }
  const info = await loadEngine(el('webgpu').checked ? 'webgpu' : 'cpu', { weights: custom.bytes, settings: custom.settings });
  if (!info) return;
  state.custom = { name: what, settings: custom.settings };
  fillLabels();
  el('weights-info').textContent = `Your weights: ${what} (id ${info.weightsId}) · ${info.styles.length} labels · ${custom.settings.join(' and ')} model${custom.settings.length > 1 ? 's' : ''}.`;
  el('weights-shipped').hidden = false;
  status(`Loaded the weights ${what}.`);
}

el('weights-zip').addEventListener('change', (e) => {
  const file = e.target.files?.[0];
  e.target.value = '';
  if (file) useWeights(() => fromZip(file), file.name);
});
el('weights-folder').addEventListener('change', (e) => {
  const files = [...(e.target.files ?? [])];
  e.target.value = '';
  if (files.length) useWeights(() => fromFolder(files), files[0].webkitRelativePath?.split('/')[0] || 'the folder');
});
el('weights-shipped').addEventListener('click', async () => {
  const info = await loadEngine(el('webgpu').checked ? 'webgpu' : 'cpu', { shipped: true });
  if (!info) return;
  state.custom = null;
  fillLabels();
  el('weights-info').textContent = '';
  el('weights-shipped').hidden = true;
  status('Back on the shipped weights.');
});

el('webgpu').addEventListener('change', async (e) => {
  await loadEngine(e.target.checked ? 'webgpu' : 'cpu');
  status('Ready.');
});

async function boot() {
  const samples = SAMPLES.map((s) => [s.id, s.title]);
  fillSelect(el('content-sample'), samples, DEFAULT.content);
  fillSelect(el('ref-sample'), samples, DEFAULT.ref);
  syncControls();
  showMotions(viewOptions());
  const shared = hasState(location.hash);
  // The default clips' text is fetched while the engine loads (loadSample reports a failure).
  const prefetch = (id) => {
    const text = fetchSample(sampleById(id));
    text.catch(() => {});
    return text;
  };
  const texts = shared ? {} : { content: prefetch(DEFAULT.content), ref: prefetch(DEFAULT.ref) };
  if (!(await loadEngine('cpu', undefined, firstLoad))) return startView3D();
  mark('engine');
  // The worker's own steps, on this page's clock.
  const clock = state.timings.load.clock ?? {};
  for (const [name, at] of Object.entries(clock)) marks[name] = Math.round(at - performance.timeOrigin);
  fillLabels({ label: DEFAULT.label, 'mix-a-label': DEFAULT.label, 'ref-label': 'old' });
  if (shared && (await openShared(location.hash))) {
    await startView3D();
    return finishBoot();
  }
  await loadSample('content', DEFAULT.content, texts.content);
  mark('content');
  // The first result needs only the content (a label); the 3D view and the reference follow it.
  await stylize();
  await startView3D();
  const said = el('status').textContent; // the result's line stays (an error shows in its own box)
  await loadSample('ref', DEFAULT.ref, texts.ref);
  status(said);
  mark('ref');
  // A link that could not be opened stays reported above the defaults loaded instead.
  if (linkError) showError('This share link cannot be opened', linkError);
  finishBoot();
}

function finishBoot() {
  const t = state.timings;
  if (t.firstResultMs) t.firstResultMs = Math.round(t.firstResultMs);
  document.body.dataset.ready = 'true';
}

boot();
