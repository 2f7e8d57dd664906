//! Foot-contact cleanup of generated motions: no sliding of a planted foot.
//!
//! The root's ground velocity comes from the global motion regressor and the legs from the
//! decoder; where the two disagree, a planted foot slides. The decoder also predicts the four
//! foot-contact channels (ankles and toes, [`CONTACTS`](crate::features::CONTACTS)): for every
//! pair of frames in which some foot joints are in contact in both, the root's ground translation
//! is corrected by minus those joints' mean horizontal displacement, so a single planted joint
//! stays exactly in place and two planted joints on average. The correction accumulates over the
//! clip (later frames move with the root); heights, rotations and the pose are untouched.
//!
//! Hand-written: a few lines of kinematics on our own [`Motion`] type; no library does this.

use glam::DVec3;

use crate::features::{CONTACT_JOINTS, CONTACTS, Features};
use crate::motion::{Motion, MotionError};

/// Contact threshold on the decoded (denormalised) contact channels, which are 0/1 in the data.
pub const CONTACT_THRESHOLD: f32 = 0.5;

/// Per frame, which of [`CONTACT_JOINTS`] the features mark as in contact.
pub fn contacts(features: &Features) -> Vec<[bool; 4]> {
    features.rows().map(|row| std::array::from_fn(|k| row[CONTACTS.start + k] > CONTACT_THRESHOLD)).collect()
}

/// `motion` with its root shifted on the ground so that joints in contact (`contacts[t]`, one
/// entry per frame; missing entries count as no contact) do not slide (see the module docs).
pub fn pin_feet(motion: &Motion, contacts: &[[bool; 4]]) -> Result<Motion, MotionError> {
    let positions = motion.global_positions();
    let mut root = motion.root_positions().to_vec();
    let mut offset = DVec3::ZERO;
    for t in 1..positions.len() {
        let (Some(before), Some(now)) = (contacts.get(t - 1), contacts.get(t)) else { break };
        let mut slide = DVec3::ZERO;
        let mut planted = 0;
        for (k, &j) in CONTACT_JOINTS.iter().enumerate() {
            if before[k] && now[k] {
                let d = positions[t][j] - positions[t - 1][j];
                slide += DVec3::new(d.x, 0.0, d.z);
                planted += 1;
            }
        }
        if planted > 0 {
            offset -= slide / f64::from(planted);
        }
        root[t] += offset;
    }
    Motion::new(root, motion.rotations().to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::canonical::{NUM_JOINTS, joint};
    use glam::DQuat;

    /// A T-pose gliding along +X at 2 cm per frame.
    fn gliding(frames: usize) -> Motion {
        let root = (0..frames).map(|t| DVec3::new(2.0 * t as f64, 90.0, 0.0)).collect();
        Motion::new(root, vec![[DQuat::IDENTITY; NUM_JOINTS]; frames]).unwrap()
    }

    #[test]
    fn a_planted_foot_stops_sliding_and_a_free_one_is_left_alone() {
        let m = gliding(10);
        let planted = pin_feet(&m, &vec![[true, false, false, false]; 10]).unwrap();
        let p = planted.global_positions();
        for t in 1..10 {
            assert!((p[t][joint::FOOT_L] - p[0][joint::FOOT_L]).length() < 1e-9, "frame {t}");
        }
        let free = pin_feet(&m, &vec![[false; 4]; 10]).unwrap();
        assert_eq!(free, m);
        // Contact only in frames 3..6: the root stops there and glides again afterwards.
        let mut c = vec![[false; 4]; 10];
        for row in &mut c[3..6] {
            row[2] = true;
        }
        let r = pin_feet(&m, &c).unwrap();
        let x: Vec<f64> = r.root_positions().iter().map(|p| p.x).collect();
        assert_eq!(x, vec![0.0, 2.0, 4.0, 6.0, 6.0, 6.0, 8.0, 10.0, 12.0, 14.0]);
    }
}
