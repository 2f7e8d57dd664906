//! Kinematics and rigs: the canonical skeleton, forward kinematics, and retargeting between a user's
//! rig and the canonical one.

pub mod canonical;

pub use canonical::{FPS, JOINT_NAMES, NUM_JOINTS};
