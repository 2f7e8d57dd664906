// Joint positions of two BVH texts compared numerically, by the package's own forward kinematics
// (Motion.source(): the file as given, every frame of it; float32).

/** Every frame's joint positions of `text` (imported with `stylizer`). */
function positions(stylizer, text) {
  const source = stylizer.importBvh(text).source();
  if (source.frames !== source.file.frames) throw new Error(`source() dropped frames: ${source.frames} of ${source.file.frames}`);
  return source.positions;
}

/**
 * Largest joint-position difference between two BVH texts of the same skeleton, relative to the
 * size of the motion (the largest extent of the second one's positions along any axis).
 */
export function positionDifference(stylizer, a, b) {
  const x = positions(stylizer, a);
  const y = positions(stylizer, b);
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
