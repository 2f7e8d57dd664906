//! Kinematics and rigs: the canonical skeleton, forward kinematics, and retargeting between a user's
//! rig and the canonical one.
//!
//! [`import_bvh`] / [`import`] bring a BVH on any supported rig (Bandai, CMU-31, the 21-joint m21 rig,
//! Reallusion CC_Base, Mixamo, or anything the generic matcher understands) onto the canonical rig at
//! 30 fps; the returned [`UserRig`] takes canonical motions back to the user's skeleton
//! ([`UserRig::from_canonical`]). See [`retarget`] for the method.

pub mod canonical;
pub mod fk;
mod import;
mod manual;
pub mod resample;
pub mod retarget;
mod rig_names;
pub mod rigs;
pub mod rotation;
mod structure;
mod tpose;

pub use canonical::{FPS, JOINT_NAMES, NUM_JOINTS};
pub use import::{ImportError, Imported, canonical_bvh, import, import_bvh, import_bvh_with, import_with};
pub use manual::{ManualMap, map_json};
pub use retarget::{RigReport, UserRig};
