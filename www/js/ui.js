// Small page helpers: the status line, the progress bar, the error box (text only, never HTML),
// and whole-page drag and drop of a file.

const el = (id) => document.getElementById(id);

export function status(text) {
  el('status').textContent = text;
}

/** A fraction 0-1 (determinate), 'busy' (indeterminate), or null (hidden). */
export function progress(fraction) {
  const box = el('progress');
  box.hidden = fraction == null;
  box.classList.toggle('busy', fraction === 'busy');
  box.querySelector('.bar').style.width = typeof fraction === 'number' ? `${Math.round(fraction * 100)}%` : '';
}

/** Shows "what — CODE: message (line N)"; hides the box without an error. */
export function showError(what, e) {
  const box = el('error');
  if (!e) {
    box.hidden = true;
    box.textContent = '';
    return;
  }
  const code = e.code ? `${e.code}: ` : '';
  const line = e.line ? ` (line ${e.line})` : '';
  box.textContent = `${what} — ${code}${e.message}${line}`;
  box.hidden = false;
}

/** Calls onFile with the first file dropped anywhere on the page (the body shows a drop hint meanwhile). */
export function onFileDrop(onFile) {
  let depth = 0;
  const clear = () => {
    depth = 0;
    document.body.classList.remove('dragging');
  };
  document.addEventListener('dragenter', (e) => {
    if (![...(e.dataTransfer?.types ?? [])].includes('Files')) return;
    depth++;
    document.body.classList.add('dragging');
  });
  document.addEventListener('dragleave', () => {
    if (--depth <= 0) clear();
  });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    clear();
    const file = e.dataTransfer?.files?.[0];
    if (file) onFile(file);
  });
}
