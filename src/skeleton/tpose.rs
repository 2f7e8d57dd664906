//! The geometry of a user rig in a base pose: its T-pose (the global rotations that pose it like the
//! canonical T-pose), world basis and scale — step 2 of the method in [`super::retarget`].

use super::ImportError;
use super::canonical::{JOINT_NAMES, NUM_JOINTS, PARENTS, joint::*};
use super::rigs::JointMap;
use super::rotation::{align_two, angle, swing, world_basis};
use crate::bvh::BvhJoint;
use crate::motion::forward_kinematics;
use glam::{DQuat, DVec3};

/// Geometry derived from a base pose.
pub(super) struct Core {
    pub t_global: Vec<DQuat>,
    pub world: DQuat,
    pub scale: f64,
    /// The largest swing (radians) a matched bone needed.
    pub max_swing: f64,
}

/// A degenerate-rig error.
pub(super) fn degenerate(reason: impl Into<String>) -> ImportError {
    ImportError::Degenerate { reason: reason.into() }
}

/// Canonical T-pose global positions (Hips at the origin).
pub(super) fn canonical_tpose() -> [DVec3; NUM_JOINTS] {
    forward_kinematics(DVec3::ZERO, &[DQuat::IDENTITY; NUM_JOINTS]).0
}

const CENTRE: [usize; 4] = [SPINE, CHEST, NECK, HEAD];
const ARM_L: [usize; 4] = [SHOULDER_L, UPPER_ARM_L, LOWER_ARM_L, HAND_L];
const ARM_R: [usize; 4] = [SHOULDER_R, UPPER_ARM_R, LOWER_ARM_R, HAND_R];
const LEG_L: [usize; 4] = [UPPER_LEG_L, LOWER_LEG_L, FOOT_L, TOES_L];
const LEG_R: [usize; 4] = [UPPER_LEG_R, LOWER_LEG_R, FOOT_R, TOES_R];

/// Where a bone points: a canonical joint, or the midpoint of the two upper arms (the top of the
/// torso of a rig without a matched joint above: no spine, or no neck and head).
#[derive(Clone, Copy)]
enum Target {
    Joint(usize),
    ArmsMid,
}

/// How a matched joint's T-pose rotation is found.
enum Aim {
    /// Leaf: inherit.
    None,
    /// Swing the bone towards canonical joint `to`.
    Swing(Target),
    /// Align up (towards `up`) and across (left joint minus right joint).
    Two { up: Target, left: usize, right: usize },
}

/// T-pose, world basis and scale of a rig in base pose `base_local`.
pub(super) fn build(
    joints: &[BvhJoint],
    rest_t: &[DVec3],
    map: &JointMap,
    inverse: &[Option<usize>],
    base_local: &[DQuat],
) -> Result<Core, ImportError> {
    let (pos0, g0) =
        super::fk::forward_kinematics_vec(joints.len(), |u| joints[u].parent, |u| (rest_t[u], base_local[u]));
    let matched_pos: Vec<DVec3> = map.iter().flatten().map(|&u| pos0[u]).collect();
    let hips = map[HIPS].expect("required");
    let size = matched_pos.iter().map(|p| (*p - pos0[hips]).length()).fold(0.0, f64::max);
    if !(size.is_finite() && size > 0.0) || g0.iter().any(|q| !q.is_finite()) {
        return Err(degenerate("the skeleton has no extent"));
    }
    let eps = 1e-6 * size;
    let p = |j: usize| map[j].map(|u| pos0[u]);
    let distinct = |a: usize, b: usize| match (p(a), p(b)) {
        (Some(x), Some(y)) => (x - y).length() > eps,
        _ => false,
    };
    let first_pair =
        |pairs: (&[usize], &[usize])| pairs.0.iter().zip(pairs.1).map(|(&l, &r)| (l, r)).find(|&(l, r)| distinct(l, r));

    let arms_mid = |pos: &[DVec3]| -> DVec3 {
        let (l, r) = (map[UPPER_ARM_L].expect("required"), map[UPPER_ARM_R].expect("required"));
        (pos[l] + pos[r]) / 2.0
    };
    // World basis: up towards the Head, or the highest matched joint of the spine, or the arms.
    let top = [HEAD, NECK, CHEST, SPINE].into_iter().find_map(|j| p(j).filter(|x| (*x - pos0[hips]).length() > eps));
    let up = top.unwrap_or_else(|| arms_mid(&pos0)) - pos0[hips];
    let (l, r) = first_pair((&LEG_L, &LEG_R)).ok_or_else(|| degenerate("the left and right legs coincide"))?;
    if up.length() <= eps {
        return Err(degenerate("the upper body is at the Hips"));
    }
    let world = world_basis(up, p(l).expect("matched") - p(r).expect("matched"))
        .ok_or_else(|| degenerate("cannot tell up from left: the hips line up with the Head"))?;
    let wi = world.inverse();

    // Aims.
    let arm_root = {
        let first = if map[SHOULDER_L].is_some() { SHOULDER_L } else { UPPER_ARM_L };
        let mut a = PARENTS[first];
        while let Some(x) = a {
            if map[x].is_some() {
                break;
            }
            a = PARENTS[x];
        }
        a.unwrap_or(HIPS)
    };
    let first_after = |j: usize, list: &[usize]| -> Option<usize> {
        let start = list.iter().position(|&x| x == j).map(|i| i + 1).unwrap_or(0);
        list[start..].iter().copied().find(|&x| map[x].is_some() && distinct(j, x))
    };
    // Up from `j`: the next matched spine joint, else the arms' midpoint (when it is above `j`).
    let up_from = |j: usize| -> Option<Target> {
        if let Some(x) = first_after(j, &CENTRE) {
            return Some(Target::Joint(x));
        }
        let u = map[j]?;
        // Above `j` along the rig's up, not merely elsewhere: a head (the top of the chain) has the
        // arms below it and keeps inheriting its parent's rotation.
        ((arms_mid(&pos0) - pos0[u]).dot(up.normalize()) > eps).then_some(Target::ArmsMid)
    };
    let aim = |j: usize| -> Result<Aim, ImportError> {
        if j == HIPS || j == arm_root {
            let up = up_from(j).ok_or_else(|| degenerate("the spine has no length"))?;
            let pairs = if j == HIPS { (&LEG_L, &LEG_R) } else { (&ARM_L, &ARM_R) };
            return match first_pair((pairs.0, pairs.1)) {
                Some((left, right)) => Ok(Aim::Two { up, left, right }),
                None if j == HIPS => Err(degenerate("the left and right legs coincide")),
                None => Ok(Aim::Swing(up)),
            };
        }
        let chain: &[usize] = [&CENTRE, &ARM_L, &ARM_R, &LEG_L, &LEG_R]
            .into_iter()
            .find(|c| c.contains(&j))
            .map(|c| c.as_slice())
            .unwrap_or(&[]);
        let next = first_after(j, chain).map(Target::Joint);
        // The top of a spine without neck and head points at the arms.
        let next = next.or_else(|| if CENTRE.contains(&j) { up_from(j) } else { None });
        Ok(next.map(Aim::Swing).unwrap_or(Aim::None))
    };
    let can = canonical_tpose();
    let can_at = |t: Target| match t {
        Target::Joint(x) => can[x],
        Target::ArmsMid => (can[UPPER_ARM_L] + can[UPPER_ARM_R]) / 2.0,
    };

    let mut t_global = vec![DQuat::IDENTITY; joints.len()];
    let mut max_swing = 0.0f64;
    for (u, joint) in joints.iter().enumerate() {
        let cur = match joint.parent {
            Some(q) => t_global[q] * base_local[u],
            None => base_local[u],
        };
        t_global[u] = cur;
        let Some(j) = inverse[u] else { continue };
        // Vector from u to a user joint, in the current (partly corrected) pose, canonical world.
        let g0_inv = g0[u].inverse();
        let vec_to_pos = |x: DVec3| world * (cur * (g0_inv * (x - pos0[u])));
        let vec_to = |x: usize| vec_to_pos(pos0[map[x].expect("matched")]);
        let target = |t: Target| match t {
            Target::Joint(x) => vec_to(x),
            Target::ArmsMid => vec_to_pos(arms_mid(&pos0)),
        };
        let s = match aim(j)? {
            Aim::None => DQuat::IDENTITY,
            Aim::Swing(x) => swing(target(x), can_at(x) - can[j], DVec3::Z)
                .ok_or_else(|| degenerate(format!("bone {} has no direction", JOINT_NAMES[j])))?,
            Aim::Two { up, left, right } => {
                align_two(target(up), vec_to(left) - vec_to(right), can_at(up) - can[j], can[left] - can[right])
                    .ok_or_else(|| degenerate(format!("{}: up and across are parallel", JOINT_NAMES[j])))?
            }
        };
        max_swing = max_swing.max(angle(s));
        t_global[u] = (wi * s * world * cur).normalize();
    }

    // Scale: Hips height above the toes (ankles if a side lacks toes) in both T-poses.
    let mut pos_t = vec![DVec3::ZERO; joints.len()];
    for (u, joint) in joints.iter().enumerate() {
        pos_t[u] = match joint.parent {
            Some(q) => pos_t[q] + t_global[q] * rest_t[u],
            None => rest_t[u],
        };
    }
    let ends = if map[TOES_L].is_some() && map[TOES_R].is_some() { [TOES_L, TOES_R] } else { [FOOT_L, FOOT_R] };
    let h_user: f64 =
        ends.iter().map(|&e| (world * (pos_t[hips] - pos_t[map[e].expect("matched")])).y).sum::<f64>() / 2.0;
    let h_can: f64 = ends.iter().map(|&e| can[HIPS].y - can[e].y).sum::<f64>() / 2.0;
    let scale = h_can / h_user;
    if !(h_user > eps && scale.is_finite() && scale > 0.0) {
        return Err(degenerate("the legs have no height"));
    }
    Ok(Core { t_global, world, scale, max_swing })
}

/// Whether the matched skeleton in its base pose `base_local` (world basis `world`) can be a standing
/// human: both legs point down from the hips (their ends at least 40 % of the leg's length below),
/// the top of the torso (the upper arms' midpoint) is above the hips, the hands are off the floor
/// (a quarter of the hips' height up: not front paws) and the hips are apart.
pub(super) fn check_human(
    joints: &[BvhJoint],
    rest_t: &[DVec3],
    map: &JointMap,
    base_local: &[DQuat],
    world: DQuat,
) -> Result<(), ImportError> {
    let (pos, _) =
        super::fk::forward_kinematics_vec(joints.len(), |u| joints[u].parent, |u| (rest_t[u], base_local[u]));
    let at = |j: usize| map[j].map(|u| pos[u]);
    let (Some(hips), Some(al), Some(ar)) = (at(HIPS), at(UPPER_ARM_L), at(UPPER_ARM_R)) else {
        return Err(degenerate("the hips or an arm is missing"));
    };
    let up = world.inverse() * DVec3::Y;
    let not_human = |reason: String| Err(ImportError::NotHuman { reason });
    let mut lowest = f64::INFINITY;
    let mut leg_sum = 0.0;
    for (side, leg) in [("left", LEG_L), ("right", LEG_R)] {
        let pts: Vec<DVec3> = leg.iter().filter_map(|&j| at(j)).collect();
        let len: f64 = std::iter::once(hips)
            .chain(pts.iter().copied())
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| (w[1] - w[0]).length())
            .sum();
        let end = *pts.last().unwrap_or(&hips);
        let drop = up.dot(hips - end);
        if !(len > 0.0 && drop >= 0.4 * len) {
            return not_human(format!(
                "the {side} leg does not point down from the hips ({:.0} % of its length below them): \
                 not a standing human (a quadruped, or limbs the wrong way)",
                100.0 * drop / len.max(f64::MIN_POSITIVE)
            ));
        }
        lowest = lowest.min(pts.iter().map(|p| up.dot(*p)).fold(f64::INFINITY, f64::min));
        leg_sum += len;
    }
    let leg = leg_sum / 2.0;
    let torso = up.dot((al + ar) / 2.0 - hips);
    if torso < 0.15 * leg {
        return not_human(format!(
            "the arms are not above the hips (torso {:.0} % of the leg length): not an upright human",
            100.0 * torso / leg
        ));
    }
    let height = up.dot(hips) - lowest;
    for (side, j) in [("left", HAND_L), ("right", HAND_R)] {
        let hand = at(j).map(|h| up.dot(h) - lowest).unwrap_or(0.0);
        if hand < 0.25 * height {
            return not_human(format!(
                "the {side} hand is on the floor in the reference pose: front legs, not arms (a quadruped?)"
            ));
        }
    }
    let (Some(l), Some(r)) = (at(UPPER_LEG_L), at(UPPER_LEG_R)) else {
        return Err(degenerate("a leg is missing"));
    };
    if (l - r).length() < 0.02 * leg {
        return Err(degenerate("the left and right hips coincide"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::canonical;

    #[test]
    fn canonical_tpose_leg_height_is_leg_length() {
        let c = canonical_tpose();
        assert!((c[HIPS].y - c[TOES_L].y - canonical::leg_length()).abs() < 1e-9);
    }
}
