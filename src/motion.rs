//! [`Motion`]: a motion on the canonical rig at 30 fps — the type every later stage works on.
//!
//! It can only be built from finite values with at least one frame, so code downstream never checks.
//! Rotations are local (relative to the parent) and relative to the canonical T-pose; joint 0's is the
//! Hips' global rotation.

use crate::bvh::{Axis, Bvh, BvhJoint, Channel};
use crate::skeleton::canonical::{self, FPS, JOINT_NAMES, MIRROR, NUM_JOINTS, PARENTS};
use crate::skeleton::fk;
use glam::{DQuat, DVec3, EulerRot};
use thiserror::Error;

/// One frame's local joint rotations.
pub type Pose = [DQuat; NUM_JOINTS];

#[derive(Debug, Error, Clone, PartialEq)]
pub enum MotionError {
    #[error("a motion needs at least one frame")]
    Empty,
    #[error("{roots} root positions but {poses} poses")]
    LengthMismatch { roots: usize, poses: usize },
    #[error("frame {frame}: non-finite value")]
    NonFinite { frame: usize },
}

/// A motion on the canonical rig at [`FPS`] frames per second.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    root: Vec<DVec3>,
    rotations: Vec<Pose>,
}

impl Motion {
    /// Builds a motion from Hips positions (cm) and local rotations, one per frame. Quaternions are
    /// normalised; they must be finite and non-zero.
    pub fn new(root: Vec<DVec3>, mut rotations: Vec<Pose>) -> Result<Motion, MotionError> {
        if root.len() != rotations.len() {
            return Err(MotionError::LengthMismatch { roots: root.len(), poses: rotations.len() });
        }
        if root.is_empty() {
            return Err(MotionError::Empty);
        }
        for (f, (p, pose)) in root.iter().zip(rotations.iter_mut()).enumerate() {
            if !p.is_finite() {
                return Err(MotionError::NonFinite { frame: f });
            }
            for q in pose.iter_mut() {
                let len = q.length();
                if !q.is_finite() || !(len > 1e-12) {
                    return Err(MotionError::NonFinite { frame: f });
                }
                *q = *q / len;
            }
        }
        Ok(Motion { root, rotations })
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.root.len()
    }

    /// Duration from first to last frame, seconds.
    pub fn duration(&self) -> f64 {
        (self.frames() - 1) as f64 / FPS
    }

    /// Hips position of every frame (cm).
    pub fn root_positions(&self) -> &[DVec3] {
        &self.root
    }

    /// Local rotations of every frame.
    pub fn rotations(&self) -> &[Pose] {
        &self.rotations
    }

    /// Global joint positions and rotations at `frame` (forward kinematics on the canonical rig).
    pub fn global_pose(&self, frame: usize) -> ([DVec3; NUM_JOINTS], [DQuat; NUM_JOINTS]) {
        forward_kinematics(self.root[frame], &self.rotations[frame])
    }

    /// Global joint positions of every frame.
    pub fn global_positions(&self) -> Vec<[DVec3; NUM_JOINTS]> {
        (0..self.frames()).map(|f| self.global_pose(f).0).collect()
    }

    /// Frames `range` of this motion (clamped to the motion; at least one frame is kept).
    pub fn slice(&self, start: usize, end: usize) -> Motion {
        let end = end.clamp(1, self.frames());
        let start = start.min(end - 1);
        Motion { root: self.root[start..end].to_vec(), rotations: self.rotations[start..end].to_vec() }
    }

    /// This motion with the local rotations of `joints` taken from `other` in every frame (the
    /// same number of frames, else `None`). Both rotations are unit already, so nothing is
    /// renormalised: every other value keeps its exact bits.
    pub fn with_joints_from(&self, other: &Motion, joints: &[usize]) -> Option<Motion> {
        if other.frames() != self.frames() || joints.iter().any(|&j| j >= NUM_JOINTS) {
            return None;
        }
        let mut rotations = self.rotations.clone();
        for (pose, source) in rotations.iter_mut().zip(&other.rotations) {
            for &j in joints {
                pose[j] = source[j];
            }
        }
        Some(Motion { root: self.root.clone(), rotations })
    }

    /// The left/right mirror image: reflect X, swap left and right joints.
    pub fn mirrored(&self) -> Motion {
        // A reflection x → -x turns a rotation q = (w, x, y, z) into (w, x, -y, -z).
        let reflect = |q: DQuat| DQuat::from_xyzw(q.x, -q.y, -q.z, q.w);
        let root = self.root.iter().map(|p| DVec3::new(-p.x, p.y, p.z)).collect();
        let rotations = self.rotations.iter().map(|pose| std::array::from_fn(|j| reflect(pose[MIRROR[j]]))).collect();
        Motion { root, rotations }
    }

    /// This motion as a BVH on the canonical rig: Hips with 6 channels, the others with 3 rotation
    /// channels, all in `Zrotation Yrotation Xrotation` order; frame time 1/30 s.
    pub fn to_bvh(&self) -> Bvh {
        let mut joints = Vec::with_capacity(NUM_JOINTS);
        let rot = [Channel::Rotation(Axis::Z), Channel::Rotation(Axis::Y), Channel::Rotation(Axis::X)];
        let mut channel_offset = 0;
        for j in 0..NUM_JOINTS {
            let mut channels = Vec::with_capacity(6);
            if j == 0 {
                channels.extend([Channel::Position(Axis::X), Channel::Position(Axis::Y), Channel::Position(Axis::Z)]);
            }
            channels.extend(rot);
            let is_leaf = !PARENTS.contains(&Some(j));
            joints.push(BvhJoint {
                name: JOINT_NAMES[j].to_string(),
                parent: PARENTS[j],
                offset: canonical::offset(j),
                end_site: is_leaf.then(|| leaf_end_site(j)),
                channel_offset,
                channels,
            });
            channel_offset += joints[j].channels.len();
        }
        let mut values = Vec::with_capacity(self.frames() * channel_offset);
        for (p, pose) in self.root.iter().zip(&self.rotations) {
            values.extend([p.x, p.y, p.z]);
            for q in pose {
                let (z, y, x) = q.to_euler(EulerRot::ZYX);
                values.extend([z.to_degrees(), y.to_degrees(), x.to_degrees()]);
            }
        }
        Bvh { joints, frame_time: 1.0 / FPS, frames: self.frames(), values }
    }
}

/// End Site offsets of the canonical leaves, so that viewers draw a head, hands and toes.
fn leaf_end_site(j: usize) -> DVec3 {
    use canonical::joint::*;
    match j {
        HEAD => DVec3::new(0.0, 12.0, 0.0),
        HAND_L => DVec3::new(8.0, 0.0, 0.0),
        HAND_R => DVec3::new(-8.0, 0.0, 0.0),
        _ => DVec3::new(0.0, 0.0, 5.0), // toes
    }
}

/// Forward kinematics on the canonical rig: global positions and rotations from the Hips position
/// and the local rotations ([`crate::skeleton::fk`]).
pub fn forward_kinematics(root: DVec3, local: &Pose) -> ([DVec3; NUM_JOINTS], [DQuat; NUM_JOINTS]) {
    let mut pos = [DVec3::ZERO; NUM_JOINTS];
    let mut rot = [DQuat::IDENTITY; NUM_JOINTS];
    let translation = |j: usize| if j == 0 { root } else { canonical::offset(j) };
    fk::forward_kinematics(|j| PARENTS[j], |j| (translation(j), local[j]), &mut pos, &mut rot);
    (pos, rot)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wobbly(frames: usize) -> Motion {
        let root = (0..frames).map(|f| DVec3::new(f as f64, 90.0, 2.0 * f as f64)).collect();
        let rotations = (0..frames)
            .map(|f| {
                std::array::from_fn(|j| {
                    DQuat::from_euler(EulerRot::YXZ, 0.1 * j as f64 + 0.05 * f as f64, 0.3 - 0.02 * j as f64, 0.2)
                })
            })
            .collect();
        Motion::new(root, rotations).unwrap()
    }

    #[test]
    fn rejects_invalid_input() {
        assert_eq!(Motion::new(vec![], vec![]), Err(MotionError::Empty));
        assert!(matches!(
            Motion::new(vec![DVec3::ZERO], vec![]),
            Err(MotionError::LengthMismatch { roots: 1, poses: 0 })
        ));
        assert_eq!(
            Motion::new(vec![DVec3::new(f64::NAN, 0.0, 0.0)], vec![[DQuat::IDENTITY; NUM_JOINTS]]),
            Err(MotionError::NonFinite { frame: 0 })
        );
        let mut zero = [DQuat::IDENTITY; NUM_JOINTS];
        zero[3] = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
        assert_eq!(Motion::new(vec![DVec3::ZERO], vec![zero]), Err(MotionError::NonFinite { frame: 0 }));
    }

    #[test]
    fn to_bvh_reproduces_global_positions() {
        let m = wobbly(5);
        let bvh = m.to_bvh();
        assert_eq!(bvh.num_channels(), 6 + 3 * 20);
        for f in 0..m.frames() {
            let (want, _) = m.global_pose(f);
            let (got, _) = bvh.global_pose(f);
            for j in 0..NUM_JOINTS {
                assert!((want[j] - got[j]).length() < 1e-9, "frame {f} joint {j}");
            }
        }
    }

    #[test]
    fn mirroring_reflects_positions_and_is_an_involution() {
        let m = wobbly(4);
        let mm = m.mirrored();
        for f in 0..m.frames() {
            let (p, _) = m.global_pose(f);
            let (q, _) = mm.global_pose(f);
            for j in 0..NUM_JOINTS {
                let r = q[MIRROR[j]];
                assert!((DVec3::new(-r.x, r.y, r.z) - p[j]).length() < 1e-9);
            }
        }
        let back = mm.mirrored();
        for (a, b) in back.rotations().iter().flatten().zip(m.rotations().iter().flatten()) {
            assert!(a.abs_diff_eq(*b, 1e-12));
        }
    }
}
