//! Forward kinematics: the one implementation every caller uses (a BVH's joints, the canonical rig,
//! a user rig in its base pose).
//!
//! A skeleton here is a list of joints in an order where every parent precedes its children (BVH
//! file order, the canonical order). Each joint has a local transform: a translation from its
//! parent (the root's: its position) and a rotation relative to the parent's frame. Global
//! transforms follow, root to leaves: `p[j] = p[parent] + R[parent] · t[j]`, `R[j] = R[parent] ·
//! r[j]`.

use glam::{DQuat, DVec3};

/// Global positions and rotations of the joints of a skeleton whose parents are `parent(j)` (a
/// parent index below `j`, `None` for a root), from each joint's local translation and rotation
/// `local(j)`, written into `pos` and `rot` (as many joints as those slices hold).
///
/// Panics if a parent does not precede its child (the callers' hierarchies guarantee it).
pub fn forward_kinematics(
    parent: impl Fn(usize) -> Option<usize>,
    mut local: impl FnMut(usize) -> (DVec3, DQuat),
    pos: &mut [DVec3],
    rot: &mut [DQuat],
) {
    debug_assert_eq!(pos.len(), rot.len());
    for j in 0..pos.len().min(rot.len()) {
        let (t, r) = local(j);
        match parent(j) {
            None => {
                pos[j] = t;
                rot[j] = r;
            }
            Some(p) => {
                assert!(p < j, "joint {j}: its parent {p} does not precede it");
                pos[j] = pos[p] + rot[p] * t;
                rot[j] = rot[p] * r;
            }
        }
    }
}

/// [`forward_kinematics`] into new vectors of `joints` joints.
pub fn forward_kinematics_vec(
    joints: usize,
    parent: impl Fn(usize) -> Option<usize>,
    local: impl FnMut(usize) -> (DVec3, DQuat),
) -> (Vec<DVec3>, Vec<DQuat>) {
    let mut pos = vec![DVec3::ZERO; joints];
    let mut rot = vec![DQuat::IDENTITY; joints];
    forward_kinematics(parent, local, &mut pos, &mut rot);
    (pos, rot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_translations_and_rotations() {
        // Root at (1, 0, 0) turned 90° about +Z; a child 1 along its parent's +X; a grandchild 1
        // along +X again with no turn of its own.
        let parents = [None, Some(0), Some(1)];
        let turn = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
        let local = |j: usize| match j {
            0 => (DVec3::new(1.0, 0.0, 0.0), turn),
            _ => (DVec3::X, DQuat::IDENTITY),
        };
        let (pos, rot) = forward_kinematics_vec(3, |j| parents[j], local);
        assert!((pos[1] - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12);
        assert!((pos[2] - DVec3::new(1.0, 2.0, 0.0)).length() < 1e-12);
        assert!(rot[2].abs_diff_eq(turn, 1e-12));
    }
}
