//! The canonical rig: the Bandai-Namco 21 moving joints (`joint_Root` dropped), Y up, centimetres,
//! 30 fps, facing +Z with the character's left on +X.
//!
//! Its rest pose is a symmetric T-pose with identity joint frames: every local rotation of a
//! [`crate::Motion`] is relative to this pose, so a standing motion has near-identity rotations and
//! mirroring is a reflection of X. Bone lengths are those of the Bandai skeleton
//! (`dataset-2_walk_normal_001`, averaged left/right); `tools/bandai_reference.py` derives them.

use glam::DVec3;

/// Number of joints of the canonical rig.
pub const NUM_JOINTS: usize = 21;

/// Frame rate of every [`crate::Motion`].
pub const FPS: f64 = 30.0;

/// Joint names, in hierarchy (depth-first) order; a parent always precedes its children.
pub const JOINT_NAMES: [&str; NUM_JOINTS] = [
    "Hips",
    "Spine",
    "Chest",
    "Neck",
    "Head",
    "Shoulder_L",
    "UpperArm_L",
    "LowerArm_L",
    "Hand_L",
    "Shoulder_R",
    "UpperArm_R",
    "LowerArm_R",
    "Hand_R",
    "UpperLeg_L",
    "LowerLeg_L",
    "Foot_L",
    "Toes_L",
    "UpperLeg_R",
    "LowerLeg_R",
    "Foot_R",
    "Toes_R",
];

/// Named joint indices.
pub mod joint {
    pub const HIPS: usize = 0;
    pub const SPINE: usize = 1;
    pub const CHEST: usize = 2;
    pub const NECK: usize = 3;
    pub const HEAD: usize = 4;
    pub const SHOULDER_L: usize = 5;
    pub const UPPER_ARM_L: usize = 6;
    pub const LOWER_ARM_L: usize = 7;
    pub const HAND_L: usize = 8;
    pub const SHOULDER_R: usize = 9;
    pub const UPPER_ARM_R: usize = 10;
    pub const LOWER_ARM_R: usize = 11;
    pub const HAND_R: usize = 12;
    pub const UPPER_LEG_L: usize = 13;
    pub const LOWER_LEG_L: usize = 14;
    pub const FOOT_L: usize = 15;
    pub const TOES_L: usize = 16;
    pub const UPPER_LEG_R: usize = 17;
    pub const LOWER_LEG_R: usize = 18;
    pub const FOOT_R: usize = 19;
    pub const TOES_R: usize = 20;
}

/// Parent of each joint (`None` for Hips).
pub const PARENTS: [Option<usize>; NUM_JOINTS] = [
    None,
    Some(0),
    Some(1),
    Some(2),
    Some(3),
    Some(2),
    Some(5),
    Some(6),
    Some(7),
    Some(2),
    Some(9),
    Some(10),
    Some(11),
    Some(0),
    Some(13),
    Some(14),
    Some(15),
    Some(0),
    Some(17),
    Some(18),
    Some(19),
];

/// The mirror image of each joint (left ↔ right; spine joints map to themselves).
pub const MIRROR: [usize; NUM_JOINTS] = [0, 1, 2, 3, 4, 9, 10, 11, 12, 5, 6, 7, 8, 17, 18, 19, 20, 13, 14, 15, 16];

const TOE_DOWN: f64 = -7.566;
const TOE_FWD: f64 = 8.995;

/// Offset of each joint from its parent in the T-pose, centimetres (Hips: zero).
pub const OFFSETS: [[f64; 3]; NUM_JOINTS] = [
    [0.0, 0.0, 0.0],
    [0.0, 15.7357, 0.0],
    [0.0, 8.9937, 0.0],
    [0.0, 16.3773, 0.0],
    [0.0, 6.4567, 0.0],
    [4.9804, 12.9942, 0.0],
    [5.3481, 0.0, 0.0],
    [24.3288, 0.0, 0.0],
    [22.2916, 0.0, 0.0],
    [-4.9804, 12.9942, 0.0],
    [-5.3481, 0.0, 0.0],
    [-24.3288, 0.0, 0.0],
    [-22.2916, 0.0, 0.0],
    [6.4694, -2.1925, 0.0],
    [0.0, -39.0811, 0.0],
    [0.0, -40.9854, 0.0],
    [0.0, TOE_DOWN, TOE_FWD],
    [-6.4694, -2.1925, 0.0],
    [0.0, -39.0811, 0.0],
    [0.0, -40.9854, 0.0],
    [0.0, TOE_DOWN, TOE_FWD],
];

/// Offset of joint `j` as a vector.
pub fn offset(j: usize) -> DVec3 {
    DVec3::from_array(OFFSETS[j])
}

/// Height of the Hips above the toe joints in the T-pose (cm): the rig's leg length.
pub fn leg_length() -> f64 {
    use joint::*;
    -(offset(UPPER_LEG_L).y + offset(LOWER_LEG_L).y + offset(FOOT_L).y + offset(TOES_L).y)
}

/// Index of the joint called `name` on the canonical rig.
pub fn joint_index(name: &str) -> Option<usize> {
    JOINT_NAMES.iter().position(|n| *n == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parents_precede_children_and_mirror_is_an_involution() {
        for (j, p) in PARENTS.iter().enumerate() {
            if let Some(p) = p {
                assert!(*p < j);
                assert_eq!(PARENTS[MIRROR[j]], Some(MIRROR[*p]));
            }
            assert_eq!(MIRROR[MIRROR[j]], j);
            let (o, m) = (offset(j), offset(MIRROR[j]));
            assert_eq!(o, DVec3::new(-m.x, m.y, m.z), "T-pose must be symmetric: {}", JOINT_NAMES[j]);
        }
        assert!((leg_length() - 89.825).abs() < 1e-3);
    }
}
