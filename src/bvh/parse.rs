//! BVH reader. (Being written: see the helper brief.)
use super::{Bvh, BvhError};

/// Bounds on the work the reader does; input beyond them is rejected with [`BvhError::LimitExceeded`].
#[derive(Clone, Debug)]
pub struct Limits {
    pub max_bytes: usize,
    pub max_joints: usize,
    pub max_frames: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { max_bytes: 256 << 20, max_joints: 1024, max_frames: 1 << 20 }
    }
}

impl Bvh {
    pub fn parse(text: &str) -> Result<Bvh, BvhError> {
        Self::parse_with_limits(text, &Limits::default())
    }
    pub fn parse_with_limits(_text: &str, _limits: &Limits) -> Result<Bvh, BvhError> {
        unimplemented!("BVH reader")
    }
}
