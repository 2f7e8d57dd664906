// World joint positions of BVH text by forward kinematics, for drawing the content motion as it
// was uploaded (the package imports it for the model; this only draws it). Same conventions as the
// package's reader: a position channel replaces its OFFSET component, rotation channels compose
// in file order (degrees). Only called on text the package has already accepted.

function axisRotation(axis, degrees) {
  const a = (degrees * Math.PI) / 180;
  const c = Math.cos(a);
  const s = Math.sin(a);
  if (axis === 'X') return [1, 0, 0, 0, c, -s, 0, s, c];
  if (axis === 'Y') return [c, 0, s, 0, 1, 0, -s, 0, c];
  return [c, -s, 0, s, c, 0, 0, 0, 1];
}

function mul(a, b) {
  const m = new Array(9);
  for (let i = 0; i < 3; i++)
    for (let j = 0; j < 3; j++) m[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
  return m;
}

/** { names, parents, offsets, channels, frameTime, rows } of a BVH text. */
export function parseBvh(text) {
  const split = text.search(/^\s*MOTION\s*$/m);
  const hierarchy = text.slice(0, split);
  const motion = text.slice(split).split(/\r\n|\r|\n/).slice(1);
  const tokens = hierarchy.split(/\s+/).filter(Boolean);
  const names = [];
  const parents = [];
  const offsets = [];
  const channels = [];
  const stack = [];
  let endSite = false;
  for (let i = 0; i < tokens.length; i++) {
    const t = tokens[i];
    if (t === 'ROOT' || t === 'JOINT') {
      names.push(tokens[++i]);
      parents.push(stack.length ? stack[stack.length - 1] : -1);
      offsets.push([0, 0, 0]);
      channels.push([]);
    } else if (t === 'End') {
      endSite = true;
      i++;
    } else if (t === '{') {
      stack.push(endSite ? -2 : names.length - 1);
    } else if (t === '}') {
      if (stack.pop() === -2) endSite = false;
    } else if (t === 'OFFSET') {
      const v = [Number(tokens[i + 1]), Number(tokens[i + 2]), Number(tokens[i + 3])];
      i += 3;
      if (!endSite) offsets[offsets.length - 1] = v;
    } else if (t === 'CHANNELS') {
      const n = Number(tokens[++i]);
      channels[channels.length - 1] = tokens.slice(i + 1, i + 1 + n);
      i += n;
    }
  }
  let frameTime = 1 / 30;
  const rows = [];
  for (const line of motion) {
    const l = line.trim();
    if (l === '' || l.startsWith('Frames')) continue;
    if (l.startsWith('Frame Time')) {
      frameTime = Number(l.split(':')[1]);
      continue;
    }
    rows.push(l.split(/\s+/).map(Number));
  }
  return { names, parents, offsets, channels, frameTime, rows };
}

/**
 * {names, parents, fps, frames, positions: Float32Array frames × joints × 3}. Only every step-th
 * frame is kept where the clip is faster than 60 fps or larger than `maxValues` positions (drawing
 * needs no more; the model gets the whole clip). `Float`: the positions' array type (the npm
 * package's tests compare outputs in Float64Array, with `maxValues = Infinity`).
 */
export function bvhPositions(text, maxValues = 6_000_000, Float = Float32Array) {
  const parsed = parseBvh(text);
  const { names, parents, offsets, channels } = parsed;
  const n = names.length;
  const step = Math.max(1, Math.floor(parsed.frameTime > 0 ? 1 / (60 * parsed.frameTime) : 1), Math.ceil((parsed.rows.length * n * 3) / maxValues));
  const rows = step === 1 ? parsed.rows : parsed.rows.filter((_, i) => i % step === 0);
  const frameTime = parsed.frameTime * step;
  const positions = new Float(rows.length * n * 3);
  const pos = new Array(n);
  const rot = new Array(n);
  rows.forEach((row, f) => {
    let k = 0;
    for (let i = 0; i < n; i++) {
      const t = [...offsets[i]];
      let r = [1, 0, 0, 0, 1, 0, 0, 0, 1];
      for (const ch of channels[i]) {
        const v = row[k++];
        const axis = ch[0].toUpperCase();
        if (ch.toLowerCase().endsWith('position')) t['XYZ'.indexOf(axis)] = v;
        else r = mul(r, axisRotation(axis, v));
      }
      const p = parents[i];
      if (p < 0) {
        pos[i] = t;
        rot[i] = r;
      } else {
        const m = rot[p];
        pos[i] = [0, 1, 2].map((c) => pos[p][c] + m[c * 3] * t[0] + m[c * 3 + 1] * t[1] + m[c * 3 + 2] * t[2]);
        rot[i] = mul(m, r);
      }
      positions.set(pos[i], (f * n + i) * 3);
    }
  });
  return { names, parents, fps: 1 / frameTime, frames: rows.length, positions, file: { frames: parsed.rows.length, fps: 1 / parsed.frameTime } };
}
