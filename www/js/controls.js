// The style form: read and write its values as one plain object (what share links store), and turn
// them into a worker request.

const el = (id) => document.getElementById(id);
const radio = (name) => document.querySelector(`input[name=${name}]:checked`)?.value;
const setRadio = (name, value) => {
  const input = document.querySelector(`input[name=${name}][value="${CSS.escape(value)}"]`);
  if (input) input.checked = true;
};

/** Fills a <select> with options (value, text) without HTML parsing. */
export function fillSelect(select, options, selected) {
  select.replaceChildren(
    ...options.map(([value, label]) => {
      const o = document.createElement('option');
      o.value = value;
      o.textContent = label;
      return o;
    }),
  );
  if (selected != null && options.some(([v]) => v === selected)) select.value = selected;
}

export function readControls() {
  return {
    model: radio('model'),
    mode: radio('mode'),
    label: el('label').value,
    refLabel: el('ref-label').value,
    mixA: { kind: el('mix-a-kind').value, label: el('mix-a-label').value },
    mixB: { kind: el('mix-b-kind').value, label: el('mix-b-label').value },
    t: Number(el('mix-t').value),
    seed: Math.max(0, Math.min(4294967295, Math.floor(Number(el('seed').value) || 0))),
    samples: Math.max(1, Math.min(8, Math.floor(Number(el('samples').value) || 1))),
    temperature: Number(el('temperature').value),
    strength: Number(el('strength').value),
    guidance: Number(el('guidance').value),
    rig: el('rig').value,
    parts: Object.fromEntries(PARTS.map((p) => [p, el(`part-${p}`).value])),
  };
}

/** The body parts with a style of their own (`parts` of the package's stylize). */
export const PARTS = ['lower', 'upper', 'head'];

/**
 * A part's choices: '' (the style above), 'content' (unchanged), 'motion' (the reference motion),
 * 'label:NAME' (a label; supervised only).
 */
export function partOptions(styles) {
  return [['', 'the style above'], ['content', 'unchanged (the content)'], ['motion', 'the reference motion'], ...styles.map((s) => [`label:${s}`, `label: ${s}`])];
}

export function writeControls(c) {
  setRadio('model', c.model);
  setRadio('mode', c.mode);
  const setSelect = (id, value) => {
    const s = el(id);
    if ([...s.options].some((o) => o.value === value)) s.value = value;
  };
  setSelect('label', c.label);
  setSelect('ref-label', c.refLabel);
  setSelect('mix-a-kind', c.mixA.kind);
  setSelect('mix-a-label', c.mixA.label);
  setSelect('mix-b-kind', c.mixB.kind);
  setSelect('mix-b-label', c.mixB.label);
  setSelect('rig', c.rig);
  for (const p of PARTS) setSelect(`part-${p}`, c.parts?.[p] ?? '');
  el('mix-t').value = String(c.t);
  el('seed').value = String(c.seed);
  el('samples').value = String(c.samples);
  el('temperature').value = String(c.temperature);
  el('strength').value = String(c.strength);
  el('guidance').value = String(c.guidance);
  syncControls();
}

/** Shows the inputs the chosen mode uses; the unsupervised model takes no labels. */
export function syncControls() {
  const c = readControls();
  const unsupervised = c.model === 'unsupervised';
  const labelRadio = document.querySelector('input[name=mode][value=label]');
  labelRadio.disabled = unsupervised;
  labelRadio.parentElement.title = unsupervised ? 'label-based styles need the supervised model' : '';
  if (unsupervised && c.mode === 'label') setRadio('mode', 'motion');
  const mode = radio('mode');
  for (const m of ['label', 'motion', 'mix']) el(`mode-${m}`).hidden = !(m === mode || (m === 'motion' && mode === 'mix'));
  el('ref-label').parentElement.hidden = unsupervised;
  for (const side of ['a', 'b']) {
    const kind = el(`mix-${side}-kind`);
    kind.querySelector('option[value=label]').disabled = unsupervised;
    if (unsupervised && kind.value === 'label') kind.value = 'prior';
    el(`mix-${side}-label`).hidden = kind.value !== 'label';
  }
  for (const p of PARTS) {
    const select = el(`part-${p}`);
    for (const o of select.options) o.disabled = unsupervised && o.value.startsWith('label:');
    if (unsupervised && select.value.startsWith('label:')) select.value = '';
  }
  el('mix-t-label').textContent = Number(el('mix-t').value).toFixed(2);
  el('temperature-label').textContent = Number(el('temperature').value).toFixed(2);
  el('strength-label').textContent = Number(el('strength').value).toFixed(2);
  el('guidance-label').textContent = Number(el('guidance').value).toFixed(2);
}

/** Whether the controls use the reference motion. */
export const usesReference = (c) =>
  c.mode === 'motion' || (c.mode === 'mix' && (c.mixA.kind === 'motion' || c.mixB.kind === 'motion')) || PARTS.some((p) => c.parts?.[p] === 'motion');

/** The worker's stylize request for the controls (on the content's rig). */
export function requestOf(c) {
  const unsupervised = c.model === 'unsupervised';
  const part = (p) => {
    // An empty reference label: the package infers it (supervised).
    if (p.kind === 'motion') return { kind: 'motion', label: unsupervised || !c.refLabel ? undefined : c.refLabel };
    if (p.kind === 'prior') return { kind: 'prior' };
    return { kind: 'label', label: p.label };
  };
  let source;
  if (c.mode === 'mix') source = { kind: 'mix', a: part(c.mixA), b: part(c.mixB), t: c.t };
  else source = part({ kind: c.mode, label: c.label });
  // Parts with a choice of their own: 'content', or a source as above.
  const chosen = PARTS.filter((p) => c.parts?.[p]);
  const parts = chosen.length
    ? Object.fromEntries(chosen.map((p) => {
        const v = c.parts[p];
        return [p, v === 'content' ? 'content' : v === 'motion' ? part({ kind: 'motion' }) : part({ kind: 'label', label: v.slice('label:'.length) })];
      }))
    : undefined;
  return { source, parts, unsupervised, samples: c.samples, seed: c.seed, temperature: c.temperature, strength: c.strength, guidance: c.guidance, rig: 'content' };
}

/** A short name of the style (file names, captions). */
export function styleName(c) {
  const unsupervised = c.model === 'unsupervised';
  const part = (p) => (p.kind === 'label' ? p.label : p.kind === 'prior' ? 'prior' : unsupervised || !c.refLabel ? 'ref' : c.refLabel);
  const main = c.mode === 'mix' ? `${part(c.mixA)}-${part(c.mixB)}-${c.t.toFixed(2)}` : part({ kind: c.mode, label: c.label });
  const own = PARTS.filter((p) => c.parts?.[p]).map((p) => {
    const v = c.parts[p];
    return `${p}-${v === 'motion' ? part({ kind: 'motion' }) : v.replace('label:', '')}`;
  });
  return [main, ...own].join('+');
}
