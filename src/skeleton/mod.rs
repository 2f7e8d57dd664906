//! Kinematics and rigs: the canonical skeleton, forward kinematics, and retargeting between a user's
//! rig and the canonical one.
//!
//! [`import_bvh`] / [`import`] bring a BVH on any supported human rig onto the canonical rig at
//! 30 fps: matched by name ([`rigs`]: Bandai, CMU-31, m21, CC_Base, Mixamo, Daz/Poser, Second Life,
//! Acclaim, HumanIK/Rokoko/Neuron, Biped, SMPL, Unreal, generic synonyms), else by structure
//! (`structure.rs`), or by a manual mapping ([`ManualMap`], [`import_with`]). The returned
//! [`UserRig`] takes canonical motions back to the user's skeleton ([`UserRig::from_canonical`]).
//! See [`retarget`] for the method; the work is bounded from the header ([`resample::check_budget`]).

pub mod canonical;
pub mod fk;
mod import;
mod inspect;
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
pub use inspect::{Inspection, inspect};
pub use manual::{ManualMap, map_json};
pub use retarget::{RigReport, UserRig};
