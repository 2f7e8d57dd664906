// Joint positions of two BVH texts compared numerically, by the demo page's forward kinematics
// (www/js/bvh-fk.js, the reader's conventions) in float64 and without dropping frames.
import { bvhPositions } from '../../www/js/bvh-fk.js';

const positions = (text) => bvhPositions(text, Infinity, Float64Array).positions;

/**
 * Largest joint-position difference between two BVH texts of the same skeleton, relative to the
 * size of the motion (the largest extent of the second one's positions along any axis).
 */
export function positionDifference(a, b) {
  const x = positions(a);
  const y = positions(b);
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
