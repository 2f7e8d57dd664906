// The canonical rig (src/skeleton/canonical.rs) on the page's side: its joints' names and parents,
// and where they are among a user's joints. Kept apart from view3d.js so that the page can map a
// motion before three.js has loaded (the 3D view starts after the first result).

export const CANONICAL = ['Hips', 'Spine', 'Chest', 'Neck', 'Head', 'Shoulder_L', 'UpperArm_L', 'LowerArm_L', 'Hand_L',
  'Shoulder_R', 'UpperArm_R', 'LowerArm_R', 'Hand_R', 'UpperLeg_L', 'LowerLeg_L', 'Foot_L', 'Toes_L',
  'UpperLeg_R', 'LowerLeg_R', 'Foot_R', 'Toes_R'];
export const PARENTS = [-1, 0, 1, 2, 3, 2, 5, 6, 7, 2, 9, 10, 11, 0, 13, 14, 15, 0, 17, 18, 19];

/**
 * For each canonical joint, the index of its user joint among `names` (−1 where none matched): the
 * importer's matches (canonical name → user joint name), else a joint of the canonical name.
 */
export function canonicalIndices(names, matched) {
  const user = new Map(matched ?? []);
  return CANONICAL.map((c) => names.indexOf(user.get(c) ?? c));
}
