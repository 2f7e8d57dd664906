// Three orthographic views (front, side, top) of one or two skeleton motions on 2D canvases (the
// perspective view is view3d.js):
// bones as lines, joints as dots, a ground grid, the root's trail. Motions are first brought into
// display space (Y up, Z the character's forward, centimetres) by toDisplay.

export const COLORS = { content: '#7fa7d9', result: '#ff8a4c', grid: '#2b323c', ground: '#56606e', text: '#9aa4b2' };

function axisVector(spec) {
  const m = /^([+-])?([XYZ])$/i.exec(String(spec ?? '').trim());
  if (!m) return null;
  const v = [0, 0, 0];
  v['XYZ'.indexOf(m[2].toUpperCase())] = m[1] === '-' ? -1 : 1;
  return v;
}

const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];

/**
 * The turn about the up axis (cos, sin) that makes the character face +Z: its left side (from the
 * right to the left hip and shoulder, `pairs` of joint indices) along +X, on average over the clip
 * (or in the first frame when the clip turns around and the average vanishes). Null without pairs.
 */
function facing(out, joints, frames, pairs) {
  if (!pairs?.length) return null;
  const across = (f) => {
    let x = 0;
    let z = 0;
    for (const [l, r] of pairs) {
      x += out[(f * joints + l) * 3] - out[(f * joints + r) * 3];
      z += out[(f * joints + l) * 3 + 2] - out[(f * joints + r) * 3 + 2];
    }
    return [x, z];
  };
  let [ax, az] = [0, 0];
  let size = 0;
  for (let f = 0; f < frames; f++) {
    const [x, z] = across(f);
    ax += x;
    az += z;
    size += Math.hypot(x, z);
  }
  if (Math.hypot(ax, az) < 0.3 * size) [ax, az] = across(0);
  const n = Math.hypot(ax, az);
  return n > 1e-9 ? [ax / n, az / n] : null;
}

/**
 * A motion in display space: positions rotated so that the rig's up axis is +Y and the character
 * faces +Z (its left along +X), scaled to centimetres. `report` is {up, forward, scale, pairs}
 * from the importer (pairs: left/right joint indices; the rig's forward axis is used without them).
 * Pass the content's `turn` (returned here) for the result so that both share the same views.
 */
export function toDisplay({ positions, parents, fps, frames }, report, turn) {
  let up = axisVector(report?.up) ?? [0, 1, 0];
  let forward = axisVector(report?.forward) ?? [0, 0, 1];
  if (up.every((c, i) => Math.abs(c) === Math.abs(forward[i]))) [up, forward] = [[0, 1, 0], [0, 0, 1]];
  const left = cross(up, forward);
  const scale = Number.isFinite(report?.scale) && report.scale > 0 ? report.scale : 1;
  const joints = parents.length;
  const out = new Float32Array(positions.length);
  for (let i = 0; i < positions.length; i += 3) {
    const p = [positions[i], positions[i + 1], positions[i + 2]];
    const dot = (v) => (v[0] * p[0] + v[1] * p[1] + v[2] * p[2]) * scale;
    out[i] = dot(left);
    out[i + 1] = dot(up);
    out[i + 2] = dot(forward);
  }
  turn ??= facing(out, joints, frames, report?.pairs) ?? [1, 0];
  const [c, s] = turn;
  for (let i = 0; i < out.length; i += 3) {
    const [x, z] = [out[i], out[i + 2]];
    out[i] = x * c + z * s;
    out[i + 2] = -x * s + z * c;
  }
  // The joint whose path is drawn as the trail: the root, or its first child when the root never moves (Bandai's joint_Root).
  let trail = 0;
  let still = true;
  for (let f = 1; f < frames && still; f++) for (let c = 0; c < 3; c++) if (out[f * joints * 3 + c] !== out[c]) still = false;
  if (still && frames > 1) trail = Math.max(0, parents.indexOf(0));
  let floor = Infinity;
  for (let i = 1; i < out.length; i += 3) floor = Math.min(floor, out[i]);
  return { positions: out, parents, fps, frames, joints, trail, still: still && trail !== 0, floor, turn };
}

/** The frame shown at `time` seconds. */
export const frameAt = (m, time) => Math.max(0, Math.min(m.frames - 1, Math.floor(time * m.fps + 1e-6)));

const VIEWS = {
  front: (p) => [p[0], p[1]],
  side: (p) => [-p[2], p[1]],
  top: (p) => [p[0], -p[2]],
};

function bounds(items, project) {
  const lo = [Infinity, Infinity];
  const hi = [-Infinity, -Infinity];
  for (const { m, shift } of items) {
    const x = m.positions;
    for (let i = 0; i < x.length; i += 3) {
      const [a, b] = project([x[i] + shift, x[i + 1], x[i + 2]]);
      if (a < lo[0]) lo[0] = a;
      if (a > hi[0]) hi[0] = a;
      if (b < lo[1]) lo[1] = b;
      if (b > hi[1]) hi[1] = b;
    }
  }
  return { lo, hi };
}

/** Draws one view of `items` ([{m, shift, color}]) at `time` onto `canvas`. */
function drawView(canvas, view, items, time, fit, options = {}) {
  const ctx = canvas.getContext('2d');
  const { width: w, height: h } = canvas;
  const dpr = options.dpr ?? 1;
  ctx.clearRect(0, 0, w, h);
  if (!fit) return;
  const project = VIEWS[view];
  const toScreen = ([a, b]) => [w / 2 + (a - fit.cx) * fit.s, h / 2 - (b - fit.cy) * fit.s];
  const floor = fit.floor;

  // Grid: 50 cm squares (in the top view the ground plane; in the others a measuring grid and the ground line).
  ctx.lineWidth = 1;
  ctx.strokeStyle = COLORS.grid;
  const step = 50;
  const [a0, b0] = [fit.cx - w / 2 / fit.s, fit.cy - h / 2 / fit.s];
  const [a1, b1] = [fit.cx + w / 2 / fit.s, fit.cy + h / 2 / fit.s];
  ctx.beginPath();
  for (let a = Math.ceil(a0 / step) * step; a <= a1; a += step) {
    const [x] = toScreen([a, 0]);
    ctx.moveTo(Math.round(x) + 0.5, 0);
    ctx.lineTo(Math.round(x) + 0.5, h);
  }
  const base = view === 'top' ? 0 : floor;
  for (let b = base + Math.ceil((b0 - base) / step) * step; b <= b1; b += step) {
    const [, y] = toScreen([0, b]);
    ctx.moveTo(0, Math.round(y) + 0.5);
    ctx.lineTo(w, Math.round(y) + 0.5);
  }
  ctx.stroke();
  if (view !== 'top') {
    const [, y] = toScreen([0, floor]);
    ctx.strokeStyle = COLORS.ground;
    ctx.lineWidth = 2 * dpr;
    ctx.beginPath();
    ctx.moveTo(0, y);
    ctx.lineTo(w, y);
    ctx.stroke();
  }

  for (const { m, shift, color } of items) {
    const f = frameAt(m, time);
    const x = m.positions;
    const at = (frame, j) => {
      const i = (frame * m.joints + j) * 3;
      return toScreen(project([x[i] + shift, x[i + 1], x[i + 2]]));
    };
    // Trail: the root's path so far.
    if (!options.noTrail && f > 0) {
      ctx.strokeStyle = color;
      ctx.globalAlpha = 0.35;
      ctx.lineWidth = 1.5 * dpr;
      ctx.beginPath();
      for (let k = 0; k <= f; k++) {
        const [px, py] = at(k, m.trail);
        if (k === 0) ctx.moveTo(px, py);
        else ctx.lineTo(px, py);
      }
      ctx.stroke();
      ctx.globalAlpha = 1;
    }
    // Bones, then joints.
    const points = [];
    for (let j = 0; j < m.joints; j++) points.push(at(f, j));
    ctx.strokeStyle = color;
    ctx.lineWidth = (options.thin ? 1.5 : 2.5) * dpr;
    ctx.lineCap = 'round';
    ctx.beginPath();
    for (let j = 0; j < m.joints; j++) {
      const p = m.parents[j];
      if (p < 0 || (m.still && p === 0)) continue;
      ctx.moveTo(points[p][0], points[p][1]);
      ctx.lineTo(points[j][0], points[j][1]);
    }
    ctx.stroke();
    if (!options.thin) {
      ctx.fillStyle = color;
      const r = (m.joints > 40 ? 1.6 : 2.6) * dpr;
      for (let j = 0; j < m.joints; j++) {
        if (m.still && j === 0) continue;
        ctx.beginPath();
        ctx.arc(points[j][0], points[j][1], r, 0, Math.PI * 2);
        ctx.fill();
      }
    }
  }
}

/** Scale and centre that fit every frame of `items` into a w × h canvas. */
function fitView(view, items, w, h, floor) {
  if (!items.length) return null;
  const { lo, hi } = bounds(items, VIEWS[view]);
  const minExtent = 120;
  const ew = Math.max(hi[0] - lo[0], minExtent);
  const eh = Math.max(hi[1] - lo[1], minExtent);
  const s = Math.min(w / (ew * 1.15), h / (eh * 1.15));
  return { s, cx: (lo[0] + hi[0]) / 2, cy: (lo[1] + hi[1]) / 2, floor };
}

/** Items to draw: the content and the result, shifted apart in the side-by-side layout. */
export function layoutItems(content, result, { layout = 'overlay', showContent = true, showResult = true } = {}) {
  const items = [];
  let shift = 0;
  if (layout === 'side' && content && result) {
    let lo = Infinity;
    let hi = -Infinity;
    for (let i = 0; i < content.positions.length; i += 3) {
      lo = Math.min(lo, content.positions[i]);
      hi = Math.max(hi, content.positions[i]);
    }
    shift = Math.max(hi - lo, 60) + 40;
  }
  if (content && showContent) items.push({ m: content, shift: layout === 'side' && result ? -shift / 2 : 0, color: COLORS.content });
  if (result && showResult) items.push({ m: result, shift: layout === 'side' && content ? shift / 2 : 0, color: COLORS.result });
  return items;
}

/** The three synchronized views of the page. */
export class Views {
  constructor(canvases) {
    this.canvases = canvases;
    this.content = null;
    this.result = null;
    this.options = {};
    this.time = 0;
    this.observer = new ResizeObserver(() => this.resize());
    for (const c of Object.values(canvases)) this.observer.observe(c);
  }

  set({ content = this.content, result = this.result, ...options }) {
    this.content = content;
    this.result = result;
    this.options = { ...this.options, ...options };
    this.refit();
  }

  resize() {
    const dpr = window.devicePixelRatio || 1;
    for (const c of Object.values(this.canvases)) {
      const w = Math.max(1, Math.round(c.clientWidth * dpr));
      const h = Math.max(1, Math.round(c.clientHeight * dpr));
      if (c.width !== w || c.height !== h) {
        c.width = w;
        c.height = h;
      }
    }
    this.refit();
  }

  refit() {
    this.items = layoutItems(this.content, this.result, this.options);
    const floor = this.content?.floor ?? this.result?.floor ?? 0;
    this.fits = {};
    for (const [view, c] of Object.entries(this.canvases)) this.fits[view] = fitView(view, this.items, c.width, c.height, floor);
    this.draw(this.time);
  }

  draw(time) {
    this.time = time;
    const dpr = window.devicePixelRatio || 1;
    for (const [view, c] of Object.entries(this.canvases)) drawView(c, view, this.items ?? [], time, this.fits?.[view], { dpr });
  }
}

/** A small front view of one motion (the sample thumbnails). */
export class Thumb {
  constructor(canvas, motion, content) {
    this.canvas = canvas;
    const dpr = window.devicePixelRatio || 1;
    canvas.width = Math.round((canvas.clientWidth || 110) * dpr);
    canvas.height = canvas.width;
    this.items = [{ m: motion, shift: 0, color: COLORS.result }];
    this.fit = fitView('front', [{ m: content ?? motion, shift: 0 }, ...this.items], canvas.width, canvas.height, motion.floor);
    this.dpr = dpr;
  }

  draw(time) {
    drawView(this.canvas, 'front', this.items, time, this.fit, { dpr: this.dpr, noTrail: true });
  }
}
