//! What a viewer needs to draw a BVH: its joint names, each joint's parent and the joints' world
//! positions (by [`Bvh::global_pose`], the crate's forward kinematics). Both the stylized motions
//! and the imported motions' source files are drawn from these.

use crate::bvh::Bvh;

/// Joint names, in file order (a parent before its children).
pub(super) fn joint_names(bvh: &Bvh) -> Vec<String> {
    bvh.joints.iter().map(|j| j.name.clone()).collect()
}

/// Each joint's parent index, −1 for the root.
pub(super) fn parents(bvh: &Bvh) -> Vec<i32> {
    bvh.joints.iter().map(|j| j.parent.map_or(-1, |p| p as i32)).collect()
}

/// World joint positions of frames `0, step, 2·step, …` (a `step` of 0 is 1), `frames × joints ×
/// 3` (x, y, z in the file's units and axes).
pub(super) fn positions(bvh: &Bvh, step: usize) -> Vec<f32> {
    let frames = (0..bvh.frames).step_by(step.max(1));
    let mut out = Vec::with_capacity(frames.len() * bvh.joints.len() * 3);
    for f in frames {
        let (positions, _) = bvh.global_pose(f);
        out.extend(positions.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]));
    }
    out
}
