//! Planted ankles held in place by two-bone leg IK — the second half of the foot cleanup.
//!
//! [`pin_feet`](super::feet::pin_feet) moves the root so planted joints slide as little as one
//! ground path allows; it cannot hold both feet, nor a foot whose leg the decoder moved. Here,
//! per leg, every run of frames in which the decoder marks the ankle as in contact gets one ground
//! spot (the mean of the ankle's horizontal positions over the run; heights stay per frame), and
//! hip and knee are rotated analytically (two-bone IK in the plane of the leg) so the ankle lands
//! there. The foot keeps its global orientation, so toes point where the decoder put them. The
//! correction fades in and out over [`BLEND_FRAMES`] frames around each run so the leg does not
//! pop. Nothing else changes: root, spine, arms, unplanted frames.
//!
//! Hand-written: a few lines of kinematics on our own [`Motion`] type (Holden's formulation of
//! the two-bone solve); IK crates target game-engine scene graphs, not this rig.

use glam::{DQuat, DVec3};

use crate::motion::{Motion, MotionError, Pose};
use crate::skeleton::canonical::{NUM_JOINTS, joint};

/// Frames over which the IK correction fades in before and out after a contact run.
pub const BLEND_FRAMES: usize = 4;

/// How far (fraction of hip-to-knee plus knee-to-ankle) IK may stretch a leg: about 16° of knee
/// bend left with equal bones.
pub const REACH: f64 = 0.99;

/// Shortest contact run (frames) that is held in place.
const MIN_RUN: usize = 2;

/// One leg: the joint it hangs from, hip (upper leg), knee (lower leg), ankle (foot), toes, and
/// its ankle's index in the four contact channels.
struct Leg {
    pelvis: usize,
    hip: usize,
    knee: usize,
    ankle: usize,
    toes: usize,
    contact: usize,
}

const LEGS: [Leg; 2] = [
    Leg {
        pelvis: joint::HIPS,
        hip: joint::UPPER_LEG_L,
        knee: joint::LOWER_LEG_L,
        ankle: joint::FOOT_L,
        toes: joint::TOES_L,
        contact: 0,
    },
    Leg {
        pelvis: joint::HIPS,
        hip: joint::UPPER_LEG_R,
        knee: joint::LOWER_LEG_R,
        ankle: joint::FOOT_R,
        toes: joint::TOES_R,
        contact: 2,
    },
];

/// `motion` with each leg's ankle held on one spot through each of its contact runs
/// (`contacts[t]`: the four contact channels of frame `t`, see [`super::feet::contacts`]; missing
/// entries count as no contact).
pub fn lock_legs(motion: &Motion, contacts: &[[bool; 4]]) -> Result<Motion, MotionError> {
    let frames = motion.frames();
    let root = motion.root_positions().to_vec();
    let mut rotations = motion.rotations().to_vec();
    // One forward kinematics pass serves both legs: solving one changes only its own joints, and
    // no joint of the other leg's chain hangs from them.
    let globals: Vec<_> = (0..frames).map(|t| motion.global_pose(t)).collect();
    for leg in &LEGS {
        let planted: Vec<bool> = (0..frames).map(|t| contacts.get(t).is_some_and(|c| c[leg.contact])).collect();
        let runs = runs(&planted);
        if runs.is_empty() {
            continue;
        }
        let ankles: Vec<DVec3> = globals.iter().map(|(pos, _)| pos[leg.ankle]).collect();
        let spots: Vec<DVec3> =
            runs.iter().map(|&(a, b)| ankles[a..b].iter().fold(DVec3::ZERO, |s, p| s + *p) / (b - a) as f64).collect();
        for (t, pose) in rotations.iter_mut().enumerate() {
            let Some((spot, weight)) = nearest_spot(t, &runs, &spots) else { continue };
            let now = ankles[t];
            let held = DVec3::new(spot.x, now.y, spot.z);
            let target = now.lerp(held, weight);
            if (target - now).length() > 1e-9 {
                let (pos, rot) = &globals[t];
                solve(leg, pos, rot, pose, target);
            }
        }
    }
    Motion::new(root, rotations)
}

/// Maximal runs `[start, end)` of `true` of at least [`MIN_RUN`] frames.
fn runs(planted: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (t, &p) in planted.iter().chain(std::iter::once(&false)).enumerate() {
        match (p, start) {
            (true, None) => start = Some(t),
            (false, Some(s)) => {
                if t - s >= MIN_RUN {
                    out.push((s, t));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The spot of the run nearest frame `t` and the weight of the correction there: 1 inside a run,
/// fading linearly to 0 over [`BLEND_FRAMES`] frames outside it; `None` beyond.
fn nearest_spot(t: usize, runs: &[(usize, usize)], spots: &[DVec3]) -> Option<(DVec3, f64)> {
    runs.iter()
        .zip(spots)
        .map(|(&(a, b), &spot)| {
            let distance = if t < a {
                a - t
            } else if t >= b {
                t + 1 - b
            } else {
                0
            };
            (distance, spot)
        })
        .filter(|&(d, _)| d <= BLEND_FRAMES)
        .min_by_key(|&(d, _)| d)
        .map(|(d, spot)| (spot, 1.0 - d as f64 / (BLEND_FRAMES + 1) as f64))
}

/// Rotates `leg`'s hip and knee in `pose` so its ankle reaches `target` (as near as the bone
/// lengths allow), keeping the foot's global rotation. `pos` and `rot`: the global joint positions
/// and rotations of `pose` as given.
fn solve(leg: &Leg, pos: &[DVec3; NUM_JOINTS], rot: &[DQuat; NUM_JOINTS], pose: &mut Pose, target: DVec3) {
    let (a, b, c) = (pos[leg.hip], pos[leg.knee], pos[leg.ankle]);
    let foot_global = rot[leg.ankle];
    let (lab, lcb) = ((b - a).length(), (b - c).length());
    if lab < 1e-6 || lcb < 1e-6 {
        return;
    }
    // Never straighten the leg past REACH of its length (or past how straight it already is): a
    // target out of reach would snap the knee straight; better a little slide than a pop.
    let reach = (REACH * (lab + lcb)).max((c - a).length());
    let eps: f64 = 1e-3;
    let lat = (target - a).length().clamp(eps.max((lab - lcb).abs() + eps), reach.min(lab + lcb - eps));
    let angle = |u: DVec3, v: DVec3| u.normalize_or_zero().dot(v.normalize_or_zero()).clamp(-1.0, 1.0).acos();
    let ac_ab_0 = angle(c - a, b - a);
    let ba_bc_0 = angle(a - b, c - b);
    let ac_at_0 = angle(c - a, target - a);
    let ac_ab_1 = ((lcb * lcb - lab * lab - lat * lat) / (-2.0 * lab * lat)).clamp(-1.0, 1.0).acos();
    let ba_bc_1 = ((lat * lat - lab * lab - lcb * lcb) / (-2.0 * lab * lcb)).clamp(-1.0, 1.0).acos();
    // The leg's bending axis; a straight leg has none, so take the one across the foot.
    let mut axis0 = (c - a).cross(b - a);
    if axis0.length() < 1e-6 {
        axis0 = (c - a).cross(pos[leg.toes] - c);
    }
    let Some(axis0) = axis0.try_normalize() else { return };
    let axis1 = (c - a).cross(target - a).try_normalize();
    let (a_global, b_global) = (rot[leg.hip], rot[leg.knee]);
    let r0 = DQuat::from_axis_angle(a_global.inverse() * axis0, ac_ab_1 - ac_ab_0);
    let r1 = DQuat::from_axis_angle(b_global.inverse() * axis0, ba_bc_1 - ba_bc_0);
    let r2 = axis1.map_or(DQuat::IDENTITY, |axis1| DQuat::from_axis_angle(a_global.inverse() * axis1, ac_at_0));
    pose[leg.hip] = (pose[leg.hip] * r0 * r2).normalize();
    pose[leg.knee] = (pose[leg.knee] * r1).normalize();
    // The knee's new global rotation, as forward kinematics composes it (the pelvis is unchanged).
    let knee_global = rot[leg.pelvis] * pose[leg.hip] * pose[leg.knee];
    pose[leg.ankle] = (knee_global.inverse() * foot_global).normalize();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::forward_kinematics;
    use crate::skeleton::canonical::PARENTS;

    /// A standing pose whose left leg swings forward and back (hip rotation about X), root fixed.
    fn swinging(frames: usize) -> Motion {
        let root = vec![DVec3::new(0.0, 90.0, 0.0); frames];
        let rotations = (0..frames)
            .map(|t| {
                let mut pose = [DQuat::IDENTITY; NUM_JOINTS];
                pose[joint::UPPER_LEG_L] = DQuat::from_rotation_x(0.3 * (t as f64 * 0.4).sin());
                pose[joint::LOWER_LEG_L] = DQuat::from_rotation_x(1.0 + 0.1 * (t as f64 * 0.3).cos());
                pose
            })
            .collect();
        Motion::new(root, rotations).unwrap()
    }

    #[test]
    fn a_planted_ankle_stays_on_one_spot_and_keeps_its_orientation() {
        let m = swinging(30);
        let mut c = vec![[false; 4]; 30];
        for row in &mut c[10..20] {
            row[0] = true;
        }
        let locked = lock_legs(&m, &c).unwrap();
        let p = locked.global_positions();
        for t in 11..20 {
            let d = p[t][joint::FOOT_L] - p[10][joint::FOOT_L];
            assert!(DVec3::new(d.x, 0.0, d.z).length() < 1e-6, "frame {t}: slides {d}");
        }
        // The foot's global rotation, the right leg and frames far from the run are unchanged.
        let (before, after) = (m.global_pose(15).1, locked.global_pose(15).1);
        assert!(before[joint::FOOT_L].angle_between(after[joint::FOOT_L]) < 1e-9);
        assert_eq!(m.rotations()[15][joint::UPPER_LEG_R], locked.rotations()[15][joint::UPPER_LEG_R]);
        for t in (0..5).chain(25..30) {
            assert_eq!(m.rotations()[t], locked.rotations()[t], "frame {t}");
        }
        // The fade: frames 6..10 and 20..24 (within BLEND_FRAMES of the run) are corrected too.
        for t in (6..10).chain(20..24) {
            assert_ne!(m.rotations()[t][joint::UPPER_LEG_L], locked.rotations()[t][joint::UPPER_LEG_L], "frame {t}");
        }
    }

    /// A target beyond reach bends the knee no straighter than [`REACH`]: the ankle stops short.
    #[test]
    fn an_out_of_reach_target_leaves_the_knee_bent() {
        let m = swinging(1);
        let mut pose = m.rotations()[0];
        let root = m.root_positions()[0];
        let (pos, rot) = m.global_pose(0);
        let leg = &LEGS[0];
        let length = (pos[leg.knee] - pos[leg.hip]).length() + (pos[leg.ankle] - pos[leg.knee]).length();
        let far = pos[leg.hip] + (pos[leg.ankle] - pos[leg.hip]).normalize() * (2.0 * length);
        solve(leg, &pos, &rot, &mut pose, far);
        let (pos, _) = forward_kinematics(root, &pose);
        let stretch = (pos[leg.ankle] - pos[leg.hip]).length() / length;
        assert!((stretch - REACH).abs() < 1e-6, "stretched to {stretch}");
    }

    #[test]
    fn each_leg_hangs_from_its_pelvis() {
        for leg in &LEGS {
            assert_eq!(PARENTS[leg.hip], Some(leg.pelvis));
            assert_eq!(PARENTS[leg.knee], Some(leg.hip));
            assert_eq!(PARENTS[leg.ankle], Some(leg.knee));
            assert_eq!(PARENTS[leg.toes], Some(leg.ankle));
        }
    }

    #[test]
    fn without_contacts_nothing_changes() {
        let m = swinging(12);
        assert_eq!(lock_legs(&m, &[[false; 4]; 12]).unwrap(), m);
        assert_eq!(lock_legs(&m, &[]).unwrap(), m);
        // A one-frame contact is no run.
        let mut c = vec![[false; 4]; 12];
        c[5][0] = true;
        assert_eq!(lock_legs(&m, &c).unwrap(), m);
    }
}
