// Your own weights in the demo: a weights folder (`motion-stylizer train all` writes RUN/weights/,
// `export -o DIR` any) chosen as a folder or as a .zip of it, read into the bytes the package's
// Stylizer.load({ weights: { manifest, norm, shared, supervised?, unsupervised?, supervisedStyle?,
// unsupervisedStyle? } }) takes (format 3 keeps each setting's style encoder in <setting>-style.bin).

const FILES = {
  manifest: 'manifest.json',
  norm: 'norm.json',
  shared: 'shared.bin',
  supervised: 'supervised.bin',
  unsupervised: 'unsupervised.bin',
  supervisedStyle: 'supervised-style.bin',
  unsupervisedStyle: 'unsupervised-style.bin',
};
const MAX_BYTES = 256 * 1024 * 1024;

const coded = (code, message) => Object.assign(new Error(message), { code });
const basename = (path) => path.split('/').filter(Boolean).pop() ?? '';

/** {name: bytes} of the weights files among `entries` ([path, () => Promise<Uint8Array>, size]). */
async function pick(entries, what) {
  const found = {};
  for (const [key, name] of Object.entries(FILES)) {
    // The shallowest file of that name: a folder (or zip) may hold the weights in a subfolder.
    const hits = entries.filter(([path]) => basename(path) === name).sort((a, b) => a[0].split('/').length - b[0].split('/').length);
    if (hits.length) found[key] = hits[0];
  }
  const missing = ['manifest', 'norm', 'shared'].filter((k) => !found[k]);
  if (missing.length) throw coded('BAD_WEIGHTS', `${what} has no ${missing.map((k) => FILES[k]).join(', ')} (a weights folder, as motion-stylizer export writes it)`);
  const settings = ['supervised', 'unsupervised'].filter((k) => found[k]);
  if (!settings.length) throw coded('BAD_WEIGHTS', `${what} has neither supervised.bin nor unsupervised.bin`);
  const total = Object.values(found).reduce((n, [, , size]) => n + size, 0);
  if (total > MAX_BYTES) throw coded('BAD_WEIGHTS', `${what} holds ${(total / 1048576).toFixed(0)} MB of weights; this page takes up to ${MAX_BYTES / 1048576} MB`);
  const bytes = {};
  for (const [key, [, read]] of Object.entries(found)) bytes[key] = await read();
  return { bytes, settings };
}

/** The weights in the files of a folder chosen with <input webkitdirectory>. */
export function fromFolder(files) {
  const list = [...files];
  const what = list[0]?.webkitRelativePath?.split('/')[0] || 'the folder';
  return pick(
    list.map((f) => [f.webkitRelativePath || f.name, async () => new Uint8Array(await f.arrayBuffer()), f.size]),
    what,
  );
}

/** The weights in a .zip of a weights folder (fflate, loaded only now). */
export async function fromZip(file) {
  const { unzipSync } = await import('../vendor/fflate/browser.js');
  let entries;
  try {
    // Only the weights files are inflated.
    entries = unzipSync(new Uint8Array(await file.arrayBuffer()), { filter: (f) => Object.values(FILES).includes(basename(f.name)) });
  } catch (e) {
    throw coded('BAD_WEIGHTS', `${file.name} is not a readable .zip (${e.message})`);
  }
  return pick(
    Object.entries(entries).map(([path, data]) => [path, async () => data, data.length]),
    file.name,
  );
}
