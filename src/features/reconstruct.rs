//! Features → motion (and, for evaluating a network's output, features → joint positions).

use super::facing::{rotate_y, wrap_angle};
use super::layout::{FeatureError, Features, ROOT_ANG_VEL, ROOT_HEIGHT, ROOT_LIN_VEL, position_dim, rotation_dim};
use super::rot6d::quat_from_6d;
use crate::Motion;
use crate::motion::Pose;
use crate::skeleton::canonical::{NUM_JOINTS, joint};
use glam::{DQuat, DVec3};

/// Rebuilds a motion from its features, in the normalised frame: yaw integrated from 0 (facing +Z at
/// the first frame), the root's ground velocity rotated back and integrated from the origin, the
/// height as is; the Hips' rotation is yaw · (its 6D), the other joints' local rotations their 6D
/// (Gram-Schmidt, so a network's non-orthonormal output is fine). Integration is in f64. The
/// position, velocity and contact dims are not used.
///
/// Errors: a non-finite value ([`FeatureError::NonFinite`]); nothing panics on finite input.
pub fn reconstruct(f: &Features) -> Result<Motion, FeatureError> {
    check_finite(f)?;
    let n = f.frames();
    let mut root = Vec::with_capacity(n);
    let mut rotations: Vec<Pose> = Vec::with_capacity(n);
    let mut path = Path::default();
    for row in f.rows() {
        let (yaw, x, z) = path.current();
        root.push(DVec3::new(x, row[ROOT_HEIGHT.start] as f64, z));
        let mut pose = [DQuat::IDENTITY; NUM_JOINTS];
        for (j, q) in pose.iter_mut().enumerate() {
            let d = rotation_dim(j);
            let v = std::array::from_fn(|k| row[d + k] as f64);
            *q = quat_from_6d(v);
        }
        pose[joint::HIPS] = DQuat::from_rotation_y(yaw) * pose[joint::HIPS];
        rotations.push(pose);
        path.advance(row);
    }
    Ok(Motion::new(root, rotations)?)
}

/// Global joint positions (cm, normalised frame) from the root dims and the position dims alone, with
/// the same root integration as [`reconstruct`]. For a motion's own features it matches the
/// positions of the reconstructed motion; for a network's output it shows what the position dims
/// say, independently of the rotations.
pub fn reconstruct_positions(f: &Features) -> Result<Vec<[DVec3; NUM_JOINTS]>, FeatureError> {
    check_finite(f)?;
    let mut out = Vec::with_capacity(f.frames());
    let mut path = Path::default();
    for row in f.rows() {
        let (yaw, x, z) = path.current();
        let (s, c) = yaw.sin_cos();
        let frame = std::array::from_fn(|j| {
            let d = position_dim(j);
            let rel = rotate_y(s, c, DVec3::new(row[d] as f64, 0.0, row[d + 2] as f64));
            DVec3::new(x + rel.x, row[d + 1] as f64, z + rel.z)
        });
        out.push(frame);
        path.advance(row);
    }
    Ok(out)
}

fn check_finite(f: &Features) -> Result<(), FeatureError> {
    match f.first_non_finite() {
        Some((frame, dim)) => Err(FeatureError::NonFinite { frame, dim }),
        None => Ok(()),
    }
}

/// The integrated root path: yaw (kept in (−π, π]) and ground position, f64.
#[derive(Default)]
struct Path {
    yaw: f64,
    x: f64,
    z: f64,
}

impl Path {
    fn current(&self) -> (f64, f64, f64) {
        (self.yaw, self.x, self.z)
    }

    fn advance(&mut self, row: &[f32]) {
        let (s, c) = self.yaw.sin_cos();
        let v = rotate_y(s, c, DVec3::new(row[ROOT_LIN_VEL.start] as f64, 0.0, row[ROOT_LIN_VEL.start + 1] as f64));
        self.x += v.x;
        self.z += v.z;
        self.yaw = wrap_angle(self.yaw + row[ROOT_ANG_VEL.start] as f64);
    }
}
