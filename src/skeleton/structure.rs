//! Structural matching (issue 15, point 1): when no naming scheme finds the essential joints, the
//! canonical joints are found from the hierarchy's topology and its geometry in a few poses.
//!
//! * **Limbs**: below every branching joint, each child starts a *segment* that runs down while a
//!   joint has one child; a segment is a limb when it has at least three joints, reaches at least a
//!   quarter of the skeleton's size, and what hangs below its end (fingers, toes) is short.
//! * **Pairs**: a human has two pairs of limbs branching from one joint each, of similar lengths
//!   (within 25 %). The legs are the pair whose branching joint is an ancestor of the other's (else
//!   the longer pair). Hips: where the legs and the arms' branches meet; Chest: where the arms branch
//!   (the neck's parent when they hang from the neck); Head: the end of the other branch there.
//! * **Within a limb**: a leg's foot is the first joint from which the limb turns horizontal (up
//!   being the spine's direction), the next joint the toes; an arm's hand is the segment's end.
//!   Upper leg and knee (upper arm and elbow) split the limb above the foot (hand) into the two most
//!   equal long bones, so hip links and clavicles are skipped; joints the limb runs straight through
//!   in every pose (roll and twist bones) are never chosen. An arm's shoulder is the joint before
//!   the upper arm.
//! * **Left and right**: forward is where the toes point (or the feet's End Sites), else where the
//!   knees bend, over the poses given; left = up × forward.

use super::canonical::{NUM_JOINTS, joint::*};
use super::rigs::JointMap;
use crate::bvh::BvhJoint;
use glam::DVec3;

/// One segment: joints from a branching joint's child down to a leaf or the next branching joint.
struct Segment {
    /// The branching joint it hangs from.
    from: usize,
    joints: Vec<usize>,
    length: f64,
}

fn ancestors_or_self(joints: &[BvhJoint], mut u: usize) -> Vec<usize> {
    let mut out = vec![u];
    while let Some(p) = joints.get(u).and_then(|j| j.parent) {
        if out.len() > joints.len() {
            break;
        }
        out.push(p);
        u = p;
    }
    out
}

fn lca(joints: &[BvhJoint], a: usize, b: usize) -> Option<usize> {
    let pa = ancestors_or_self(joints, a);
    ancestors_or_self(joints, b).into_iter().find(|x| pa.contains(x))
}

fn is_ancestor(joints: &[BvhJoint], a: usize, d: usize) -> bool {
    a != d && ancestors_or_self(joints, d).contains(&a)
}

/// The canonical joints of `joints` from their structure, with `poses[0]` (global positions, one per
/// joint) for the geometry and every pose for the facing direction; `None` when the skeleton does
/// not have the shape of a human body.
pub(super) fn match_structure(joints: &[BvhJoint], poses: &[Vec<DVec3>]) -> Option<JointMap> {
    let n = joints.len();
    let pos = poses.first()?;
    if pos.len() != n || n < 9 || pos.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (u, j) in joints.iter().enumerate() {
        if let Some(p) = j.parent.filter(|&p| p < u) {
            children[p].push(u);
        }
    }
    // Size: the largest distance from the middle of the bounding box (not from the root, which may
    // stay at the origin while the body walks away).
    // A root with one child (`joint_Root`, `Bip01`, `root`) may sit anywhere: left out.
    let body: Vec<DVec3> =
        pos.iter().enumerate().filter(|&(u, _)| !(u == 0 && children[0].len() == 1)).map(|(_, p)| *p).collect();
    let first = *body.first()?;
    let (lo, hi) = body.iter().fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let mid = (lo + hi) / 2.0;
    let size = body.iter().map(|p| (*p - mid).length()).fold(0.0, f64::max);
    if size.is_nan() || size <= 0.0 {
        return None;
    }
    // Largest distance from `u` to a joint below it.
    let reach_below = |u: usize| -> f64 {
        let mut stack = children[u].clone();
        let mut r = 0.0f64;
        while let Some(x) = stack.pop() {
            r = r.max((pos[x] - pos[u]).length());
            stack.extend_from_slice(&children[x]);
        }
        r
    };
    // Segments below every branching joint (and the root).
    let mut limbs: Vec<Segment> = Vec::new();
    for b in 0..n {
        if children[b].len() < 2 && joints[b].parent.is_some() {
            continue;
        }
        for &c in &children[b] {
            let mut seg = vec![c];
            let mut cur = c;
            while children[cur].len() == 1 {
                cur = children[cur][0];
                seg.push(cur);
            }
            let length: f64 = std::iter::once(b).chain(seg.iter().copied()).collect::<Vec<_>>()[..]
                .windows(2)
                .skip(1)
                .map(|w| (pos[w[1]] - pos[w[0]]).length())
                .sum();
            if seg.len() >= 3 && length >= 0.25 * size && reach_below(cur) < 0.15 * size {
                limbs.push(Segment { from: b, joints: seg, length });
            }
        }
    }
    // Pairs: two limbs from one joint, similar lengths.
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for a in 0..limbs.len() {
        for b in a + 1..limbs.len() {
            let (la, lb) = (limbs[a].length, limbs[b].length);
            if limbs[a].from == limbs[b].from && la.min(lb) >= 0.8 * la.max(lb) {
                pairs.push((a, b));
            }
        }
    }
    if pairs.len() != 2 || limbs.len() != 4 {
        return None;
    }
    let (p, q) = (pairs[0], pairs[1]);
    let (bp, bq) = (limbs[p.0].from, limbs[q.0].from);
    let longer = |x: (usize, usize)| limbs[x.0].length + limbs[x.1].length;
    let (legs, arms) = if is_ancestor(joints, bp, bq) {
        (p, q)
    } else if is_ancestor(joints, bq, bp) {
        (q, p)
    } else if longer(p) >= longer(q) {
        (p, q)
    } else {
        (q, p)
    };
    let (leg_root, arm_root) = (limbs[legs.0].from, limbs[arms.0].from);
    let hips = lca(joints, leg_root, arm_root)?;
    if hips == arm_root {
        return None; // the arms would hang from the hips
    }
    let up = (pos[arm_root] - pos[hips]).try_normalize()?;

    // Head: the end of the branch at the arms' root that is no arm.
    let arm_starts = [limbs[arms.0].joints[0], limbs[arms.1].joints[0]];
    let head_branch: Vec<usize> = {
        let c = children[arm_root].iter().copied().find(|c| !arm_starts.contains(c));
        let mut path = Vec::new();
        let mut cur = c;
        while let Some(x) = cur {
            path.push(x);
            cur = children[x].iter().copied().max_by(|&a, &b| {
                let (da, db) = ((pos[a] - pos[arm_root]).dot(up), (pos[b] - pos[arm_root]).dot(up));
                da.total_cmp(&db)
            });
        }
        path
    };

    let mut map: JointMap = [None; NUM_JOINTS];
    map[HIPS] = Some(hips);
    match head_branch.len() {
        0 => {}
        1 => map[HEAD] = Some(head_branch[0]),
        k => {
            // A last joint named like an end marker (`HeadTop_End`, `Head_Nub`) is no head: a hint.
            let last = head_branch[k - 1];
            let name = super::rigs::normalise(&joints[last].name);
            let marker = ["end", "top", "nub", "tip"].iter().any(|m| name.ends_with(m));
            let head = if marker { head_branch[k - 2] } else { last };
            map[HEAD] = Some(head);
            if head != head_branch[0] {
                map[NECK] = Some(head_branch[0]);
            }
        }
    }

    // Within the limbs.
    // Joints a segment runs straight through in every pose (roll and twist bones): no limb joints.
    let straight = |seg: &Segment| -> Vec<bool> {
        let s = &seg.joints;
        (0..s.len())
            .map(|i| {
                let prev = if i == 0 { seg.from } else { s[i - 1] };
                let Some(&next) = s.get(i + 1) else { return false };
                let mut seen = false;
                for pose in poses.iter().filter(|p| p.len() == n) {
                    let (a, b) = (pose[s[i]] - pose[prev], pose[next] - pose[s[i]]);
                    if a.length() <= 1e-6 * size || b.length() <= 1e-6 * size {
                        continue;
                    }
                    if a.angle_between(b) > 1f64.to_radians() {
                        return false;
                    }
                    seen = true;
                }
                seen
            })
            .collect()
    };
    let leg_parts = |seg: &Segment| -> Option<[Option<usize>; 4]> {
        let s = &seg.joints;
        let foot_i = (2..s.len())
            .find(|&i| {
                i + 1 < s.len() && (pos[s[i + 1]] - pos[s[i]]).try_normalize().is_some_and(|d| d.dot(up).abs() < 0.8)
            })
            .unwrap_or(s.len() - 1);
        let foot = s[foot_i];
        let (upper_i, knee_i) = split(pos, s, foot_i, &straight(seg))?;
        let toes = s.get(foot_i + 1).copied();
        Some([Some(s[upper_i]), Some(s[knee_i]), Some(foot), toes])
    };
    let arm_parts = |seg: &Segment| -> Option<[Option<usize>; 4]> {
        let s = &seg.joints;
        let hand_i = s.len() - 1;
        let hand = s[hand_i];
        let (upper_i, elbow_i) = split(pos, s, hand_i, &straight(seg))?;
        let shoulder = upper_i.checked_sub(1).map(|i| s[i]);
        Some([shoulder, Some(s[upper_i]), Some(s[elbow_i]), Some(hand)])
    };
    let leg_a = leg_parts(&limbs[legs.0])?;
    let leg_b = leg_parts(&limbs[legs.1])?;
    // In this pose the legs must hang from the hips, against the spine's direction (a rest pose
    // with every bone along one axis does not tell: the caller tries a frame of the motion).
    for leg in [leg_a, leg_b] {
        let (u, f) = (pos[leg[0]?], pos[leg[2]?]);
        if (f - u).dot(up) > -0.5 * (f - u).length() {
            return None;
        }
    }
    let arm_a = arm_parts(&limbs[arms.0])?;
    let arm_b = arm_parts(&limbs[arms.1])?;

    // Facing: toes (or the feet's End Sites), else the knees' bend, over the poses.
    let mut fwd = DVec3::ZERO;
    for leg in [leg_a, leg_b] {
        let (Some(knee), Some(foot)) = (leg[1], leg[2]) else { continue };
        for pose in poses.iter().filter(|p| p.len() == n) {
            let toe = match leg[3] {
                Some(t) => Some(pose[t] - pose[foot]),
                None => joints[foot].end_site.map(|_| DVec3::ZERO),
            };
            if let Some(v) = toe.filter(|v| v.length() > 0.0) {
                fwd += v - up * v.dot(up);
            }
        }
        if fwd.length() <= 1e-6 * size {
            for pose in poses.iter().filter(|p| p.len() == n) {
                let hip = pose[leg[0]?];
                let bend = pose[knee] - (hip + pose[foot]) / 2.0;
                fwd += bend - up * bend.dot(up);
            }
        }
    }
    let fwd = fwd.try_normalize()?;
    let left = up.cross(fwd);
    let side = |x: Option<usize>| x.map(|u| (pos[u] - pos[hips]).dot(left)).unwrap_or(0.0);
    let (leg_l, leg_r) = if side(leg_a[0]) >= side(leg_b[0]) { (leg_a, leg_b) } else { (leg_b, leg_a) };
    let (arm_l, arm_r) = if side(arm_a[1]) >= side(arm_b[1]) { (arm_a, arm_b) } else { (arm_b, arm_a) };
    for (k, j) in [UPPER_LEG_L, LOWER_LEG_L, FOOT_L, TOES_L].into_iter().enumerate() {
        map[j] = leg_l[k];
    }
    for (k, j) in [UPPER_LEG_R, LOWER_LEG_R, FOOT_R, TOES_R].into_iter().enumerate() {
        map[j] = leg_r[k];
    }
    for (k, j) in [SHOULDER_L, UPPER_ARM_L, LOWER_ARM_L, HAND_L].into_iter().enumerate() {
        map[j] = arm_l[k];
    }
    for (k, j) in [SHOULDER_R, UPPER_ARM_R, LOWER_ARM_R, HAND_R].into_iter().enumerate() {
        map[j] = arm_r[k];
    }
    // A shoulder that is the arms' root itself is no shoulder.
    for j in [SHOULDER_L, SHOULDER_R] {
        if map[j] == Some(arm_root) {
            map[j] = None;
        }
    }
    Some(map)
}

/// The limb's root and middle joint (indices into `s`, before `end`): the split of the limb into the
/// two most equal long bones, `root → middle` and `middle → end`; so links before the limb
/// (clavicles, hip links) and twist or roll bones inside it are skipped.
fn split(pos: &[DVec3], s: &[usize], end: usize, straight: &[bool]) -> Option<(usize, usize)> {
    let dist = |a: usize, b: usize| (pos[s[a]] - pos[s[b]]).length();
    let mut best: Option<(f64, usize, usize)> = None;
    for u in (0..end).filter(|&u| !straight[u]) {
        for m in (u + 1..end).filter(|&m| !straight[m]) {
            let (x, y) = (dist(u, m), dist(m, end));
            let balance = x.min(y) / x.max(y).max(f64::MIN_POSITIVE);
            if best.is_none_or(|b| balance > b.0 + 1e-9) {
                best = Some((balance, u, m));
            }
        }
    }
    best.map(|(_, u, m)| (u, m))
}
