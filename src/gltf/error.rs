//! [`GltfError`]: why a [`Bvh`](crate::bvh::Bvh) cannot be written as glTF, typed.

/// Why a motion could not be written as a `.glb`.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum GltfError {
    /// A BVH with no joints or no frames.
    #[error("the motion has no {what}")]
    Empty { what: &'static str },
    /// A `Bvh` that breaks its own invariants (only hand-built ones can: parsed files never do).
    #[error("malformed motion: {reason}")]
    Malformed { reason: String },
    /// A non-finite channel value, frame time or option.
    #[error("non-finite value: {what}")]
    NonFinite { what: String },
    /// More joints than a skin's 16-bit joint indices can address.
    #[error("{joints} joints: a glTF skin here holds at most {max}")]
    TooManyJoints { joints: usize, max: usize },
    /// More joint keyframes than [`MAX_KEYS`](super::MAX_KEYS), keyframe times that collapse in
    /// 32-bit floats, or a binary chunk beyond 4 GiB.
    #[error("the motion is too long for glTF: {reason}")]
    TooLarge { reason: String },
}

impl GltfError {
    /// A stable, machine-readable name of the failure class (the npm package's `error.code`):
    /// `BAD_MOTION` (empty, malformed or non-finite) or `TOO_LONG` (too many joints, frames or bytes).
    pub fn code(&self) -> &'static str {
        match self {
            GltfError::Empty { .. } | GltfError::Malformed { .. } | GltfError::NonFinite { .. } => "BAD_MOTION",
            GltfError::TooManyJoints { .. } | GltfError::TooLarge { .. } => "TOO_LONG",
        }
    }
}
