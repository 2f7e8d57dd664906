// World joint positions of a BVH text by forward kinematics (float64), the reader's conventions:
// a position channel replaces its OFFSET component; rotation channels compose in file order
// (R = R_c1 · R_c2 · R_c3, degrees). For comparing outputs numerically.

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

const apply = (m, v) => [0, 1, 2].map((i) => m[i * 3] * v[0] + m[i * 3 + 1] * v[1] + m[i * 3 + 2] * v[2]);

/** { joints: [{name, parent, offset, channels}], frames: number[][] (rows of channel values) }. */
export function parseBvh(text) {
  const [hierarchy, motion] = text.split(/^MOTION\r?$/m);
  const tokens = hierarchy.split(/\s+/).filter(Boolean);
  const joints = [];
  const stack = [];
  let inEndSite = false;
  for (let i = 0; i < tokens.length; i++) {
    const t = tokens[i];
    if (t === 'ROOT' || t === 'JOINT') {
      joints.push({ name: tokens[++i], parent: stack.length ? stack[stack.length - 1] : -1, offset: [0, 0, 0], channels: [] });
    } else if (t === 'End') {
      inEndSite = true;
      i++;
    } else if (t === '{') {
      stack.push(inEndSite ? -2 : joints.length - 1);
    } else if (t === '}') {
      if (stack.pop() === -2) inEndSite = false;
    } else if (t === 'OFFSET') {
      const v = [Number(tokens[i + 1]), Number(tokens[i + 2]), Number(tokens[i + 3])];
      i += 3;
      if (!inEndSite) joints[joints.length - 1].offset = v;
    } else if (t === 'CHANNELS') {
      const n = Number(tokens[++i]);
      joints[joints.length - 1].channels = tokens.slice(i + 1, i + 1 + n);
      i += n;
    }
  }
  const frames = motion
    .split(/\r?\n/)
    .filter((l) => l.trim() !== '' && !/^(Frames|Frame Time)/.test(l))
    .map((l) => l.trim().split(/\s+/).map(Number));
  return { joints, frames };
}

/** Float64Array of frames × joints × 3. */
export function bvhPositions(text) {
  const { joints, frames } = parseBvh(text);
  const out = new Float64Array(frames.length * joints.length * 3);
  frames.forEach((row, f) => {
    let k = 0;
    const pos = [];
    const rot = [];
    joints.forEach((j, i) => {
      const t = [...j.offset];
      let r = [1, 0, 0, 0, 1, 0, 0, 0, 1];
      for (const ch of j.channels) {
        const v = row[k++];
        const axis = ch[0].toUpperCase();
        if (ch.endsWith('position')) t['XYZ'.indexOf(axis)] = v;
        else r = mul(r, axisRotation(axis, v));
      }
      if (j.parent < 0) {
        pos.push(t);
        rot.push(r);
      } else {
        const p = apply(rot[j.parent], t);
        pos.push([0, 1, 2].map((c) => pos[j.parent][c] + p[c]));
        rot.push(mul(rot[j.parent], r));
      }
      out.set(pos[i], (f * joints.length + i) * 3);
    });
  });
  return out;
}

/**
 * Largest joint-position difference between two BVH texts of the same skeleton, relative to the
 * size of the motion (the largest extent of the second one's positions along any axis).
 */
export function positionDifference(a, b) {
  const x = bvhPositions(a);
  const y = bvhPositions(b);
  if (x.length !== y.length) throw new Error(`position counts differ: ${x.length} vs ${y.length}`);
  let worst = 0;
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < x.length; i++) {
    worst = Math.max(worst, Math.abs(x[i] - y[i]));
    lo[i % 3] = Math.min(lo[i % 3], y[i]);
    hi[i % 3] = Math.max(hi[i % 3], y[i]);
  }
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  return { absolute: worst, relative: worst / size, size };
}
