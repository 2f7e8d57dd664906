//! The body's facing direction over time, the clip's floor, and [`Placement`]: the map from a
//! motion's world to the normalised start (floor at y = 0, start at the origin, facing +Z).

use crate::skeleton::canonical::{NUM_JOINTS, joint};
use crate::{Motion, MotionError};
use glam::{DQuat, DVec3};

/// Standard deviation (frames) of the Gaussian that smooths the across vector over time.
///
/// At 30 fps this removes most of a walk's per-step sway of the hips and shoulders (Bandai walks:
/// frame-to-frame yaw change std 0.0088 rad raw, about 0.004 at σ = 6) and still follows a turn.
pub const FACING_SIGMA: f64 = 6.0;

/// Height (cm) at which the lowest joint of a clip is put above the floor: the height of the canonical
/// rig's toe joints in the Bandai reference T-pose (Hips at 93.3139 cm, Hips-to-toe 89.825 cm).
/// Bandai walks keep their toe joints 4.2-4.3 cm above their floor; this puts a normalised foot flat
/// on y = 0 rather than 3.5 cm into it.
pub const FLOOR_CLEARANCE: f64 = 3.489;

/// Rotation by `yaw` about +Y, applied to `v` (takes +Z to `(sin yaw, 0, cos yaw)`).
#[inline]
pub(crate) fn rotate_y(sin: f64, cos: f64, v: DVec3) -> DVec3 {
    DVec3::new(cos * v.x + sin * v.z, v.y, -sin * v.x + cos * v.z)
}

/// Wraps an angle into (−π, π].
#[inline]
pub(crate) fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let w = (a + PI).rem_euclid(TAU) - PI; // [−π, π)
    if w <= -PI { w + TAU } else { w }
}

/// The floor of a clip: the lowest height reached by any joint, less [`FLOOR_CLEARANCE`].
pub(crate) fn floor_height(positions: &[[DVec3; NUM_JOINTS]]) -> f64 {
    let lowest = positions.iter().flatten().fold(f64::INFINITY, |m, p| m.min(p.y));
    lowest - FLOOR_CLEARANCE
}

/// Unsmoothed across vector on the ground: (right hip − left hip) + (right shoulder − left shoulder),
/// y dropped. It points to the character's right, so forward = up × across.
fn across(p: &[DVec3; NUM_JOINTS]) -> (f64, f64) {
    use joint::*;
    let a = (p[UPPER_LEG_R] - p[UPPER_LEG_L]) + (p[UPPER_ARM_R] - p[UPPER_ARM_L]);
    (a.x, a.z)
}

/// Yaw (radians, about +Y, 0 = facing +Z) of every frame, from the Gaussian-smoothed across vector
/// (edges clamped). Frames where the smoothed vector vanishes take the nearest earlier valid yaw (or the
/// first valid one; 0 if none). Angles are unwrapped: consecutive frames differ by at most π.
pub(crate) fn facing_yaws(positions: &[[DVec3; NUM_JOINTS]]) -> Vec<f64> {
    let n = positions.len();
    let raw: Vec<(f64, f64)> = positions.iter().map(across).collect();
    let radius = (4.0 * FACING_SIGMA).ceil() as usize;
    let kernel: Vec<f64> = (0..=radius).map(|k| (-0.5 * (k as f64 / FACING_SIGMA).powi(2)).exp()).collect();
    let mut yaws: Vec<Option<f64>> = Vec::with_capacity(n);
    let last = n as isize - 1;
    for t in 0..n {
        let (mut ax, mut az) = (kernel[0] * raw[t].0, kernel[0] * raw[t].1);
        for (k, w) in kernel.iter().enumerate().skip(1) {
            let lo = (t as isize - k as isize).max(0) as usize;
            let hi = (t as isize + k as isize).min(last) as usize;
            ax += w * (raw[lo].0 + raw[hi].0);
            az += w * (raw[lo].1 + raw[hi].1);
        }
        // forward = up × across = (a.z, 0, −a.x); yaw = atan2(forward.x, forward.z).
        let ok = ax * ax + az * az > 1e-12;
        yaws.push(ok.then(|| az.atan2(-ax)));
    }
    let first_valid = yaws.iter().flatten().next().copied().unwrap_or(0.0);
    let mut out = Vec::with_capacity(n);
    let mut prev = first_valid;
    for y in yaws {
        let y = y.unwrap_or(prev);
        // Unwrap relative to the previous frame.
        let y = if out.is_empty() { y } else { prev + wrap_angle(y - prev) };
        out.push(y);
        prev = y;
    }
    out
}

/// Where a clip sits in the world, as the feature extractor sees it: its floor height, the ground
/// position of its first frame's Hips, and its initial facing. [`Placement::to_canonical`] maps the
/// world into the normalised frame in which [`crate::features::reconstruct`] rebuilds the clip (floor
/// at y = 0, first Hips above the origin, facing +Z); [`Placement::from_canonical`] maps back, e.g.
/// to put a stylised clip where its input was.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Placement {
    /// World height of the normalised floor, cm.
    pub floor: f64,
    /// World x of the first frame's Hips, cm.
    pub origin_x: f64,
    /// World z of the first frame's Hips, cm.
    pub origin_z: f64,
    /// Facing yaw of the first frame in the world, radians (0 = facing +Z).
    pub yaw: f64,
}

impl Placement {
    /// The placement [`crate::features::extract`] uses for `m`.
    pub fn of(m: &Motion) -> Placement {
        let positions = m.global_positions();
        Placement::from_parts(&positions, &facing_yaws(&positions))
    }

    /// From a clip's global positions and [`facing_yaws`].
    pub(crate) fn from_parts(positions: &[[DVec3; NUM_JOINTS]], yaws: &[f64]) -> Placement {
        let floor = floor_height(positions);
        let yaw = yaws.first().copied().unwrap_or(0.0);
        let o = positions.first().map(|p| p[joint::HIPS]).unwrap_or(DVec3::ZERO);
        Placement { floor, origin_x: o.x, origin_z: o.z, yaw }
    }

    /// World point → normalised frame.
    pub fn to_canonical(&self, p: DVec3) -> DVec3 {
        let (s, c) = self.yaw.sin_cos();
        rotate_y(-s, c, DVec3::new(p.x - self.origin_x, p.y - self.floor, p.z - self.origin_z))
    }

    /// Normalised frame → world point.
    pub fn from_canonical(&self, p: DVec3) -> DVec3 {
        let (s, c) = self.yaw.sin_cos();
        rotate_y(s, c, p) + DVec3::new(self.origin_x, self.floor, self.origin_z)
    }

    /// `m` moved into the normalised frame (root positions and the Hips' global rotation).
    pub fn to_canonical_motion(&self, m: &Motion) -> Result<Motion, MotionError> {
        self.transform_motion(m, false)
    }

    /// `m` moved from the normalised frame into the world.
    pub fn from_canonical_motion(&self, m: &Motion) -> Result<Motion, MotionError> {
        self.transform_motion(m, true)
    }

    fn transform_motion(&self, m: &Motion, inverse: bool) -> Result<Motion, MotionError> {
        let turn = DQuat::from_rotation_y(if inverse { self.yaw } else { -self.yaw });
        let root = m
            .root_positions()
            .iter()
            .map(|&p| if inverse { self.from_canonical(p) } else { self.to_canonical(p) })
            .collect();
        let rotations = m
            .rotations()
            .iter()
            .map(|pose| {
                let mut pose = *pose;
                pose[joint::HIPS] = turn * pose[joint::HIPS];
                pose
            })
            .collect();
        // Fails only if a placement with huge values pushes a position past f64's range.
        Motion::new(root, rotations)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5 - 4.0 * PI) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(-0.5) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn rotate_y_takes_z_to_heading() {
        let yaw: f64 = 0.7;
        let (s, c) = yaw.sin_cos();
        let v = rotate_y(s, c, DVec3::Z);
        assert!((v - DVec3::new(yaw.sin(), 0.0, yaw.cos())).length() < 1e-12);
        let q = DQuat::from_rotation_y(yaw) * DVec3::new(0.3, -1.0, 2.0);
        assert!((q - rotate_y(s, c, DVec3::new(0.3, -1.0, 2.0))).length() < 1e-12);
    }
}
