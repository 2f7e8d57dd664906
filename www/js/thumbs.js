// "Sample N": the N stylized results as small animated front views; one is picked for the main views.

import { Thumb } from './views.js';

export class Thumbs {
  constructor(box, container, onPick) {
    this.box = box;
    this.container = container;
    this.onPick = onPick;
    this.thumbs = [];
  }

  /** Shows `results` (display motions); hidden when there is only one. */
  show(results, content, pick) {
    this.container.replaceChildren();
    this.thumbs = [];
    this.box.hidden = results.length < 2;
    if (results.length < 2) return;
    results.forEach((m, i) => {
      const button = document.createElement('button');
      button.type = 'button';
      button.setAttribute('aria-label', `Sample ${i + 1}`);
      button.setAttribute('aria-pressed', String(i === pick));
      const canvas = document.createElement('canvas');
      const caption = document.createElement('span');
      caption.textContent = `#${i + 1}`;
      button.append(canvas, caption);
      button.addEventListener('click', () => this.onPick(i));
      this.container.append(button);
      this.thumbs.push({ button, canvas, motion: m, thumb: null });
    });
    // Canvases get their size from the layout: create the drawers after it.
    for (const t of this.thumbs) t.thumb = new Thumb(t.canvas, t.motion, content);
  }

  select(pick) {
    this.thumbs.forEach((t, i) => t.button.setAttribute('aria-pressed', String(i === pick)));
  }

  draw(time) {
    for (const t of this.thumbs) t.thumb?.draw(time);
  }
}
