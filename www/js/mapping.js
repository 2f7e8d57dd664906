// The joint-mapping panel: a file whose rig the importer cannot match opens it instead of a dead
// end. Each canonical joint gets a drop-down of the file's joints, prefilled with the importer's
// best guesses (the package's inspectBvh `map`); "Import" retries with the mapping chosen.

const el = (id) => document.getElementById(id);

/** The canonical joints in the package's order, with a readable name. */
const JOINTS = [
  ['Hips', 'hips'],
  ['Spine', 'spine'],
  ['Chest', 'chest'],
  ['Neck', 'neck'],
  ['Head', 'head'],
  ['Shoulder_L', 'left shoulder (collar)'],
  ['UpperArm_L', 'left upper arm'],
  ['LowerArm_L', 'left forearm'],
  ['Hand_L', 'left hand'],
  ['Shoulder_R', 'right shoulder (collar)'],
  ['UpperArm_R', 'right upper arm'],
  ['LowerArm_R', 'right forearm'],
  ['Hand_R', 'right hand'],
  ['UpperLeg_L', 'left thigh'],
  ['LowerLeg_L', 'left shin'],
  ['Foot_L', 'left foot'],
  ['Toes_L', 'left toes'],
  ['UpperLeg_R', 'right thigh'],
  ['LowerLeg_R', 'right shin'],
  ['Foot_R', 'right foot'],
  ['Toes_R', 'right toes'],
];

/** Canonical joints without which nothing can be imported (the others are synthesised). */
const ESSENTIAL = new Set(['Hips', 'UpperArm_L', 'LowerArm_L', 'Hand_L', 'UpperArm_R', 'LowerArm_R', 'Hand_R', 'UpperLeg_L', 'LowerLeg_L', 'Foot_L', 'UpperLeg_R', 'LowerLeg_R', 'Foot_R']);

let pending = null;

/**
 * Opens the panel for `info` (inspectBvh's result) of the file `name`; resolves to the mapping
 * chosen ({canonical: fileJoint | null}) or null when cancelled. A panel already open is
 * cancelled first.
 */
export function askMapping(name, info) {
  pending?.(null);
  const panel = el('map-panel');
  el('map-title').textContent = `Match the joints of ${name}`;
  el('map-reason').textContent = info.error ? `${info.error.code}: ${info.error.message}` : '';
  const rows = el('map-rows');
  rows.replaceChildren();
  for (const [joint, label] of JOINTS) {
    const row = document.createElement('label');
    row.className = 'map-row';
    const caption = document.createElement('span');
    caption.textContent = ESSENTIAL.has(joint) ? label : `${label} (optional)`;
    const select = document.createElement('select');
    select.dataset.joint = joint;
    select.setAttribute('aria-label', `File joint for the ${label}`);
    const none = new Option(ESSENTIAL.has(joint) ? '— choose —' : '— none: synthesise —', '');
    select.append(none, ...info.joint_names.map((n) => new Option(n, n)));
    select.value = info.map?.[joint] ?? '';
    row.append(caption, select);
    rows.append(row);
  }
  panel.hidden = false;
  panel.scrollIntoView?.({ block: 'nearest' });
  rows.querySelector('select')?.focus();
  return new Promise((resolve) => {
    pending = (value) => {
      pending = null;
      panel.hidden = true;
      resolve(value);
    };
  });
}

/** The mapping the panel's drop-downs say now. */
function chosen() {
  const map = {};
  for (const select of el('map-rows').querySelectorAll('select')) map[select.dataset.joint] = select.value || null;
  return map;
}

export function initMapping() {
  el('map-apply').addEventListener('click', () => pending?.(chosen()));
  el('map-cancel').addEventListener('click', () => pending?.(null));
  el('map-panel').addEventListener('keydown', (e) => {
    if (e.key === 'Escape') pending?.(null);
  });
}

/** Error codes a mapping by hand can cure (the others are about the file itself). */
export const MAPPABLE = new Set(['RIG_UNMATCHED', 'RIG_DEGENERATE', 'NOT_HUMAN', 'BAD_MAP']);
