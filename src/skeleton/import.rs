//! Entry points: BVH text or [`Bvh`] on any rig → [`Motion`] on the canonical rig, plus the
//! [`UserRig`] that takes motions back to the user's skeleton.

use super::ManualMap;
use super::resample;
use super::retarget::UserRig;
use crate::bvh::{Bvh, BvhError};
use crate::motion::{Motion, MotionError};
use thiserror::Error;

/// Why a BVH could not be brought onto the canonical rig.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ImportError {
    #[error(transparent)]
    Bvh(#[from] BvhError),
    /// No naming scheme finds these required canonical joints; `rig` is the closest scheme.
    #[error("rig {rig:?}: cannot find the joints {}", missing.join(", "))]
    MissingJoints { missing: Vec<String>, rig: String },
    /// The skeleton gives no usable geometry (zero-length bones, coincident hips, no leg height, …).
    #[error("degenerate rig: {reason}")]
    Degenerate { reason: String },
    /// The matched skeleton cannot be a human body: a single chain, a quadruped, limbs the wrong way
    /// ([`super::retarget`] documents the checks).
    #[error("not a human skeleton: {reason}")]
    NotHuman { reason: String },
    /// A manual joint mapping ([`super::ManualMap`]) that cannot be used: not JSON, an unknown
    /// canonical joint, a joint the file lacks, one joint for two canonical joints.
    #[error("joint mapping: {reason}")]
    BadMap { reason: String },
    /// [`UserRig::to_canonical`] was given a BVH whose hierarchy is not the rig's.
    #[error("the BVH's hierarchy is not the rig's: {reason}")]
    RigMismatch { reason: String },
    /// The clip is too long to resample (or its frame time absurd).
    #[error("the clip lasts {seconds} s: more than {limit} frames at 30 fps")]
    TooLong { seconds: f64, limit: usize },
    /// The clip would make the importer hold more frames than its data justify
    /// ([`super::resample::check_budget`]): `frames` source frames of `channels` channels at `fps`
    /// resample to `resampled` frames at 30 fps, and `frames + resampled` exceeds `limit`.
    #[error(
        "{frames} frames of {channels} channels at {fps} fps would resample to {resampled} frames at 30 fps: \
         more than the {limit} frames this much data may take"
    )]
    OverBudget { frames: usize, channels: usize, fps: f64, resampled: usize, limit: usize },
    /// The retargeted motion is not finite (values too large for the arithmetic).
    #[error(transparent)]
    Motion(#[from] MotionError),
}

impl ImportError {
    /// A stable, machine-readable name of the failure class (the npm package's `error.code`).
    pub fn code(&self) -> &'static str {
        match self {
            ImportError::Bvh(_) => "BVH_PARSE",
            ImportError::MissingJoints { .. } => "RIG_UNMATCHED",
            ImportError::Degenerate { .. } => "RIG_DEGENERATE",
            ImportError::NotHuman { .. } => "NOT_HUMAN",
            ImportError::BadMap { .. } => "BAD_MAP",
            ImportError::RigMismatch { .. } => "RIG_MISMATCH",
            ImportError::TooLong { .. } | ImportError::OverBudget { .. } => "TOO_LONG",
            ImportError::Motion(_) => "BAD_MOTION",
        }
    }
}

/// A BVH brought onto the canonical rig, with the rig to take motions back.
#[derive(Clone, Debug)]
pub struct Imported {
    pub motion: Motion,
    pub rig: UserRig,
}

/// Parses BVH text, detects its rig, retargets to the canonical rig and resamples to 30 fps. The
/// header is read first and the work bounded from it ([`resample::check_budget`]) before the frame
/// rows are parsed.
pub fn import_bvh(text: &str) -> Result<Imported, ImportError> {
    import_bvh_with(text, None)
}

/// [`import_bvh`] with a manual joint mapping (see [`ManualMap`]).
pub fn import_bvh_with(text: &str, map: Option<&ManualMap>) -> Result<Imported, ImportError> {
    let h = Bvh::parse_header(text)?;
    resample::check_budget(h.frames, h.channels, h.frame_time)?;
    import_with(&Bvh::parse(text)?, map)
}

/// Detects the rig of `bvh`, retargets its motion to the canonical rig and resamples it to 30 fps.
pub fn import(bvh: &Bvh) -> Result<Imported, ImportError> {
    import_with(bvh, None)
}

/// [`import`] with a manual joint mapping (see [`ManualMap`]).
pub fn import_with(bvh: &Bvh, map: Option<&ManualMap>) -> Result<Imported, ImportError> {
    let rig = UserRig::from_bvh_with(bvh, map)?;
    let motion = rig.to_canonical(bvh)?;
    Ok(Imported { motion, rig })
}

/// The motion on the canonical rig as a BVH (what [`Motion::to_bvh`] writes).
pub fn canonical_bvh(m: &Motion) -> Bvh {
    m.to_bvh()
}
