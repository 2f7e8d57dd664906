//! BVH text ↔ [`Bvh`]: a faithful, validated in-memory copy of a BVH file (any rig, any frame rate).
//!
//! The reader ([`Bvh::parse`]) never panics and bounds its work ([`Limits`]); the writer
//! ([`Bvh::to_bvh_string`]) emits text that three.js's `BVHLoader` and our reader load back with the
//! same pose. Local transforms (offsets, channels → translation and rotation) live here too because they are
//! what the channels *mean*; forward kinematics ([`crate::skeleton::fk`]) and rig semantics live in
//! [`crate::skeleton`].

mod error;
mod lex;
mod parse;
mod write;

pub use error::BvhError;
pub use parse::{Header, Limits, MAX_CHANNELS_PER_JOINT};

use crate::skeleton::fk;
use glam::{DQuat, DVec3};

/// A coordinate axis, as named in a `CHANNELS` line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// Unit vector along this axis.
    pub fn unit(self) -> DVec3 {
        match self {
            Axis::X => DVec3::X,
            Axis::Y => DVec3::Y,
            Axis::Z => DVec3::Z,
        }
    }
    pub fn index(self) -> usize {
        self as usize
    }
}

/// One channel of a joint: a translation or a rotation (degrees) about one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Channel {
    Position(Axis),
    Rotation(Axis),
}

/// A joint of the hierarchy. Joints are stored in file order, so a parent always precedes its children.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhJoint {
    pub name: String,
    /// Index of the parent joint; `None` for the root (the first joint).
    pub parent: Option<usize>,
    /// OFFSET from the parent, in file units.
    pub offset: DVec3,
    /// Channels in file order. A position channel replaces the matching OFFSET component.
    pub channels: Vec<Channel>,
    /// OFFSET of the joint's `End Site`, if it has one.
    pub end_site: Option<DVec3>,
    /// Index of this joint's first channel within a frame row.
    pub channel_offset: usize,
}

/// A parsed BVH file: hierarchy plus `frames × num_channels` values (row-major).
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame (> 0).
    pub frame_time: f64,
    /// Number of frames (≥ 1).
    pub frames: usize,
    /// `frames × num_channels` channel values, row-major; rotations in degrees.
    pub values: Vec<f64>,
}

impl Bvh {
    /// Total channels per frame.
    pub fn num_channels(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// The channel values of frame `f`. Panics if `f >= self.frames` (caller's bug, not user input).
    pub fn frame(&self, f: usize) -> &[f64] {
        let n = self.num_channels();
        &self.values[f * n..(f + 1) * n]
    }

    /// Frames per second (1 / frame_time).
    pub fn fps(&self) -> f64 {
        1.0 / self.frame_time
    }

    /// Duration in seconds from first to last frame: `(frames - 1) × frame_time`.
    pub fn duration(&self) -> f64 {
        (self.frames.saturating_sub(1)) as f64 * self.frame_time
    }

    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Local transform of `joint` at `frame`: translation relative to the parent (OFFSET with any
    /// position channels substituted component-wise) and rotation (rotation channels composed in file
    /// order, intrinsic: `R = R_c1 · R_c2 · R_c3`).
    pub fn local_transform(&self, frame: usize, joint: usize) -> (DVec3, DQuat) {
        self.local_transform_in(self.frame(frame), joint)
    }

    /// [`Bvh::local_transform`] on a frame row already looked up (`row = self.frame(f)`).
    fn local_transform_in(&self, row: &[f64], joint: usize) -> (DVec3, DQuat) {
        let j = &self.joints[joint];
        let mut t = j.offset;
        let mut r = DQuat::IDENTITY;
        for (k, ch) in j.channels.iter().enumerate() {
            let v = row[j.channel_offset + k];
            match *ch {
                Channel::Position(a) => t[a.index()] = v,
                Channel::Rotation(a) => r *= DQuat::from_axis_angle(a.unit(), v.to_radians()),
            }
        }
        (t, r)
    }

    /// Global joint positions and rotations at `frame` by forward kinematics
    /// ([`crate::skeleton::fk`]).
    pub fn global_pose(&self, frame: usize) -> (Vec<DVec3>, Vec<DQuat>) {
        let row = self.frame(frame);
        fk::forward_kinematics_vec(self.joints.len(), |j| self.joints[j].parent, |j| self.local_transform_in(row, j))
    }
}
