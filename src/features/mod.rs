//! The 260-D per-frame pose features (the model's representation of a [`crate::Motion`]) and their
//! inverse, normalisation and mirroring.
//!
//! # Layout (per frame `t`, f32; see the constants in this module)
//!
//! | dims | const | meaning |
//! |---|---|---|
//! | 0 | [`ROOT_ANG_VEL`] | yaw(t+1) − yaw(t), radians, wrapped to (−π, π] |
//! | 1..3 | [`ROOT_LIN_VEL`] | Hips ground displacement p(t+1) − p(t), (x, z), cm, in the facing frame of t |
//! | 3 | [`ROOT_HEIGHT`] | Hips height above the floor, cm |
//! | 4..67 | [`POSITIONS`] | per joint (x, y, z), cm: x, z relative to the Hips' ground projection and rotated into the facing frame of t; y the height above the floor (absolute). Hips itself is (0, height, 0). |
//! | 67..193 | [`ROTATIONS`] | per joint 6 numbers, first then second column of the rotation matrix: Hips relative to the facing frame (R_y(−yaw(t))·G_hips), the others local (as in [`crate::Motion`], relative to the canonical T-pose) |
//! | 193..256 | [`VELOCITIES`] | per joint P(t+1) − P(t), cm, in the facing frame of t |
//! | 256..260 | [`CONTACTS`] | 1.0 / 0.0 for `Foot_L`, `Toes_L`, `Foot_R`, `Toes_R` |
//!
//! Joints are in the canonical order ([`crate::skeleton::JOINT_NAMES`]). The facing frame of t is the
//! rotation by yaw(t) about +Y; "rotated into" it means multiplied by R_y(−yaw(t)), so a body facing
//! its own forward direction sees forward as +Z and its left as +X.
//!
//! # Conventions
//!
//! - **Floor**: per clip, the lowest height any joint reaches, less [`FLOOR_CLEARANCE`] (3.49 cm, the
//!   canonical toe joint's height when standing): the lowest joint of a clip sits 3.49 cm above y = 0,
//!   where a flat foot's toe joint is. The floor found by import is not trusted (foreign rigs).
//! - **Facing**: across = (UpperLeg_R − UpperLeg_L) + (UpperArm_R − UpperArm_L) with y dropped,
//!   Gaussian-smoothed over time (σ = [`FACING_SIGMA`] frames, edges clamped); forward = up × across;
//!   yaw = atan2(forward.x, forward.z). If the smoothed vector vanishes the previous frame's yaw is kept.
//! - **Start**: the rebuilt clip starts with its Hips above the origin, facing +Z (yaw 0). The features
//!   themselves do not depend on where the clip is or which way it faces (only the floor), so a window
//!   cut out of a clip's features equals the features of that window of the clip (up to the floor
//!   and the smoothing at its edges). [`Placement`] maps the world to this normalised frame and back.
//! - **Last frame**: it has no successor, so dims 0..3 and 193..256 repeat the previous frame's
//!   (a one-frame clip has zeros there). The inverse never uses the last frame's velocities.
//! - **Contacts**: speed |P(t+1) − P(t)| < [`CONTACT_SPEED`] (2 cm/frame = 60 cm/s) and height below
//!   [`CONTACT_HEIGHT`] (17 cm for the ankles, 9.5 cm for the toes). On Bandai walks planted feet
//!   move under 0.5 cm/frame and swinging ones 5-14; each foot is down 50-60 % of a walk, 10-20 % of a
//!   run.
//!
//! # Inverse
//!
//! [`reconstruct`] integrates the yaw from 0 and the rotated root velocity from the origin (f64),
//! takes the height as is, the Hips' rotation as yaw · its 6D and the others' local rotations from their
//! 6D by Gram-Schmidt (any finite 6D gives a rotation). Position and velocity dims are redundant and
//! unused; [`reconstruct_positions`] rebuilds joint positions from the position dims instead, to judge a
//! network's output. On real clips the round trip is exact up to f32 rounding (well under 0.01 mm).
//!
//! # Model views
//!
//! The autoencoder sees [`View::Model`] ([`MODEL_DIM`] = 256 dims: contacts dropped), the global motion
//! regressor [`View::Regressor`] ([`REGRESSOR_DIM`] = 254: also without [`ROOT_LIN_VEL`]). See
//! [`Features::view`], [`Features::view_channels_first`], [`Features::write_view`].

mod extract;
mod facing;
mod layout;
mod mirror;
mod normalize;
mod reconstruct;
mod rot6d;

pub use extract::{CONTACT_HEIGHT, CONTACT_JOINTS, CONTACT_SPEED, extract, extract_placed};
pub use facing::{FACING_SIGMA, FLOOR_CLEARANCE, Placement};
pub use layout::{
    CONTACTS, DIM, FeatureError, Features, GROUPS, MODEL_DIM, POSITIONS, REGRESSOR_DIM, ROOT_ANG_VEL, ROOT_HEIGHT,
    ROOT_LIN_VEL, ROTATIONS, VELOCITIES, View, position_dim, rotation_dim, velocity_dim,
};
pub use mirror::mirror;
pub use normalize::{NormAccumulator, NormStats, STD_FLOOR};
pub use reconstruct::{reconstruct, reconstruct_positions};
pub use rot6d::{quat_from_6d, quat_to_6d};
