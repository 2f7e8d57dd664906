//! Retargeting between a user's rig and the canonical rig.
//!
//! # Method
//!
//! * **Matching** ([`super::rigs`]): the naming scheme with the essential joints (Hips, legs to the
//!   foot, arms to the hand) and the most joints wins; else the structure (`structure.rs`); or a
//!   [`ManualMap`]. Canonical joints left unmatched are synthesised: identity local rotations, so
//!   they turn with their parents ([`UserRig::synthesised`]).
//! * **Plausibility**: one or two chains, or a reference pose whose legs do not point down from the
//!   hips or whose hands are on the floor, is no human ([`ImportError::NotHuman`]).
//! * **World basis** `R_w` (user world → canonical world): from the rig's base pose, up = Hips → Head
//!   and left = left hip − right hip, each snapped to the nearest coordinate axis, mapped onto +Y and
//!   +X (forward = left × up onto +Z). Handles Z-up rigs and rigs facing −Z. Snapping keeps the floor
//!   level: the lean of a standing base pose would otherwise tilt the whole world by a few degrees.
//! * **Base pose**: the zero-rotation rest pose, unless it is degenerate or needs a bone swung by
//!   more than 120° (twist undefined near 180°): then Bandai (all bones along +X at rest) and CC_Base
//!   (legs and arms up) use a table ([`super::rigs`]) and other rigs the clip frame needing the
//!   smallest swings (said in [`UserRig::notes`]). (The rest
//!   pose comes first so that a canonical BVH, Bandai names on a T-pose rest, imports as itself.)
//! * **T-pose** `G_T[u]` (user world global rotations of the user skeleton posed like the canonical
//!   T-pose), root to leaves: `G_base[u] = G_T[parent] · L_base[u]`; a matched joint then turns by the
//!   rotation taking its bone, mapped by `R_w`, onto the canonical T-pose bone. Bones end at the first
//!   matched canonical descendant whose user joint is not at the same place (CMU's `Spine1 → Neck` has
//!   length zero). Hips and the arms' root (Chest) align two vectors, up (towards the spine / neck)
//!   and across (left minus right hip / shoulder), so their twist is defined; the others swing
//!   minimally; leaves (Head, Hands, Toes) and unmatched joints inherit.
//! * **Transfer** (canonical T-pose frames are identity): `G_can[j] = R_w · G_user[u] · G_T[u]⁻¹ · R_w⁻¹`
//!   for matched joints, unmatched canonical joints get identity local rotations. Back:
//!   `G_user[u] = R_w⁻¹ · G_can[j] · R_w · G_T[u]`; unmatched user joints keep their base local
//!   rotation. Hips position: `scale · R_w · p` horizontally, with `scale` = canonical leg length /
//!   user leg length (Hips height above the toes, or ankles, in the two T-poses; converts units too).
//! * **Height and floor**: the Hips height is set per frame so that the lowest matched foot/toe joint
//!   is where the source's is, scaled: `scale · (low_user(t) − floor_clip) + foot_rest`, where
//!   `floor_clip` is the [`FLOOR_PERCENTILE`] (5th) over the clip's frames of `low_user` measured along
//!   the user's up axis, and `foot_rest` is 0 (or the canonical ankle height for rigs without toes). So
//!   the canonical floor is at 0 (the percentile lands there) and feet in contact stay in contact even
//!   when leg proportions differ (scaling the Hips height instead floats or sinks the feet in squats).
//!   Back, the user's lowest foot joint goes to `(low_can(t) − foot_rest) / scale + floor`, `floor`
//!   being the level of the clip the rig was built from ([`RigReport::floor`]). Both directions use
//!   the same rule: canonical → user → canonical is exact for canonical motions whose floor percentile
//!   is at 0 (every imported motion), user → canonical → user for the rig's own clip wherever the
//!   matched joints carry the motion (unmatched joints between matched ones come back at rest).
//! * **Frame rate**: the canonical motion is resampled to 30 fps after the transfer
//!   ([`super::resample`]).

use super::ImportError;
use super::canonical::{self, NUM_JOINTS, PARENTS, joint::*};
use super::resample;
use super::rigs::JointMap;
use super::rotation::decompose;
use super::tpose::degenerate;
use crate::bvh::{Axis, Bvh, BvhJoint, Channel};
use crate::motion::{Motion, Pose, forward_kinematics};
use glam::{DQuat, DVec3};

/// Building a [`UserRig`] from a BVH: matching, plausibility, world basis, base pose, T-pose.
mod build;

/// Percentile of the per-frame lowest foot height that defines the floor.
pub const FLOOR_PERCENTILE: f64 = 0.05;

/// What was detected and derived, for display.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RigReport {
    /// `"bandai"`, `"cmu31"`, `"m21"`, `"cc_base"`, `"mixamo"` or `"generic"`.
    pub rig: String,
    /// Canonical joint name → user joint name, canonical order.
    pub matched: Vec<(String, String)>,
    /// Canonical joints the rig lacks (optional ones: synthesised, they get identity local rotations).
    pub missing: Vec<String>,
    /// Canonical centimetres per user unit.
    pub scale: f64,
    /// User axis pointing up, e.g. `"+Y"`, and forward (the character's facing in the base pose).
    pub up_axis: String,
    pub forward_axis: String,
    /// Floor level in user units along the up axis (see the module docs).
    pub floor: f64,
    /// Where the base pose came from: `"rest"`, `"table"` or `"frame N"`.
    pub base_pose: String,
}

/// A user's rig and everything needed to retarget to and from the canonical rig.
#[derive(Clone, Debug)]
pub struct UserRig {
    joints: Vec<BvhJoint>,
    /// Rest translation of each joint: its OFFSET, position-channel components from the first frame
    /// (writers may zero the OFFSET components that channels replace).
    rest_t: Vec<DVec3>,
    map: JointMap,
    inverse: Vec<Option<usize>>,
    base_local: Vec<DQuat>,
    t_global: Vec<DQuat>,
    world: DQuat,
    scale: f64,
    floor: f64,
    /// Root … Hips, in order.
    hips_chain: Vec<usize>,
    /// The joint of `hips_chain` whose position channels carry the Hips translation.
    carrier: Option<usize>,
    /// Matched foot/toe joints: canonical indices and their user joints.
    feet_can: Vec<usize>,
    feet_user: Vec<usize>,
    /// Canonical T-pose height of the lowest matched foot joint above the lowest foot joint (0 when
    /// toes are matched, the ankle height when not).
    foot_rest: f64,
    report: RigReport,
    /// Canonical joints the rig lacks, each with how the canonical rig makes it up.
    synthesised: Vec<(String, String)>,
    /// What the importer had to decide, in words.
    notes: Vec<String>,
}

/// What [`Bvh::parse`] guarantees, checked for hand-built values: a root first, parents before
/// children, channel offsets in order, `frames × channels` values, a positive frame time.
fn well_formed(bvh: &Bvh) -> Result<(), ImportError> {
    let mut offset = 0;
    for (i, j) in bvh.joints.iter().enumerate() {
        let parent_ok = match j.parent {
            None => i == 0,
            Some(p) => p < i,
        };
        if !parent_ok || j.channel_offset != offset {
            return Err(degenerate(format!("malformed hierarchy at joint {:?}", j.name)));
        }
        offset += j.channels.len();
    }
    if bvh.joints.is_empty() || bvh.frames == 0 || bvh.values.len() != bvh.frames * offset {
        return Err(degenerate("no joints, no frames, or not frames × channels values"));
    }
    if !(bvh.frame_time.is_finite() && bvh.frame_time > 0.0) {
        return Err(degenerate("the frame time must be positive"));
    }
    Ok(())
}

/// Linear-interpolated percentile (`p` in [0, 1]) of `v`; NaN sorts last.
fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let x = p * (v.len() - 1) as f64;
    let (lo, t) = (x.floor() as usize, x - x.floor());
    if lo + 1 < v.len() { v[lo] * (1.0 - t) + v[lo + 1] * t } else { v[lo] }
}

/// Name of a rig matched through a manual mapping ([`ManualMap`](super::ManualMap)).
pub const MANUAL: &str = "manual";

/// Name of the rig found by its structure alone (`structure.rs`).
pub const STRUCTURAL: &str = "structural";

impl UserRig {
    /// What was detected and derived.
    pub fn report(&self) -> &RigReport {
        &self.report
    }

    /// The canonical joints the rig lacks (those of [`RigReport::missing`]), each with how the
    /// canonical rig makes it up: it turns with its parent (identity local rotation), so a head
    /// turns with the neck, toes lie along the foot, a missing spine or chest joint follows the one
    /// below it.
    pub fn synthesised(&self) -> &[(String, String)] {
        &self.synthesised
    }

    /// What the importer had to decide, in words: a reference pose taken from the motion (and why),
    /// joints synthesised.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The user's skeleton (hierarchy and channels).
    pub fn joints(&self) -> &[BvhJoint] {
        &self.joints
    }

    /// Canonical joint → user joint index.
    pub fn joint_map(&self) -> &JointMap {
        &self.map
    }

    /// The user's up direction (user world).
    pub fn up(&self) -> DVec3 {
        self.world.inverse() * DVec3::Y
    }

    /// Canonical centimetres per user unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// User world → canonical world rotation.
    pub fn world_rotation(&self) -> DQuat {
        self.world
    }

    /// Per output (30-fps) frame of a clip on this rig, the height along up of its lowest matched
    /// foot/toe joint (feet positions interpolated linearly between source frames).
    fn user_lows(&self, bvh: &Bvh, plan: &[resample::Sample]) -> Vec<f64> {
        let up = self.up();
        let at = |f: usize| -> Vec<DVec3> {
            let (pos, _) = bvh.global_pose(f);
            self.feet_user.iter().map(|&u| pos[u]).collect()
        };
        let mut memo: Vec<Option<Vec<DVec3>>> = vec![None; bvh.frames];
        let mut lows = Vec::with_capacity(plan.len());
        for s in plan {
            let next = (s.i + 1).min(bvh.frames - 1);
            for f in [s.i, next] {
                if memo[f].is_none() {
                    memo[f] = Some(at(f));
                }
            }
            let (a, b) = (memo[s.i].as_deref().unwrap_or_default(), memo[next].as_deref().unwrap_or_default());
            let low = a
                .iter()
                .zip(b)
                .map(|(a, b)| up.dot(if s.t > 0.0 { a.lerp(*b, s.t) } else { *a }))
                .fold(f64::INFINITY, f64::min);
            lows.push(low);
        }
        lows
    }

    /// Lowest matched foot/toe joint height of a canonical pose.
    fn canonical_low(&self, pos: &[DVec3; NUM_JOINTS]) -> f64 {
        self.feet_can.iter().map(|&j| pos[j].y).fold(f64::INFINITY, f64::min)
    }

    fn check_hierarchy(&self, bvh: &Bvh) -> Result<(), ImportError> {
        let mismatch = |reason: String| Err(ImportError::RigMismatch { reason });
        if bvh.joints.len() != self.joints.len() {
            return mismatch(format!("{} joints, the rig has {}", bvh.joints.len(), self.joints.len()));
        }
        for (a, b) in bvh.joints.iter().zip(&self.joints) {
            if a.name != b.name || a.parent != b.parent || a.channels != b.channels {
                return mismatch(format!("joint {:?} differs", a.name));
            }
            // Components a position channel replaces do not count (writers often zero them).
            let free = |v: DVec3| {
                let mut v = v;
                for c in &b.channels {
                    if let Channel::Position(x) = c {
                        v[x.index()] = 0.0;
                    }
                }
                v
            };
            let tol = 1e-6 * (1.0 + b.offset.length());
            if (free(a.offset) - free(b.offset)).length() > tol {
                return mismatch(format!("joint {:?} has another OFFSET", a.name));
            }
        }
        well_formed(bvh)
    }

    /// The motion of `bvh` (this rig's hierarchy, any frame rate) on the canonical rig at 30 fps.
    pub fn to_canonical(&self, bvh: &Bvh) -> Result<Motion, ImportError> {
        self.check_hierarchy(bvh)?;
        resample::check_budget(bvh.frames, bvh.num_channels(), bvh.frame_time)?;
        let plan = resample::plan(bvh.frames, resample::source_fps(bvh.frame_time))?;
        let (w, wi) = (self.world, self.world.inverse());
        let t_inv: Vec<DQuat> = self.t_global.iter().map(|q| q.inverse()).collect();
        let hips = self.map[HIPS].expect("required");
        let mut roots = Vec::with_capacity(bvh.frames);
        let mut poses: Vec<Pose> = Vec::with_capacity(bvh.frames);
        for f in 0..bvh.frames {
            let (pos, rot) = bvh.global_pose(f);
            let mut g = [DQuat::IDENTITY; NUM_JOINTS];
            let mut local = [DQuat::IDENTITY; NUM_JOINTS];
            for j in 0..NUM_JOINTS {
                let parent = PARENTS[j].map(|p| g[p]).unwrap_or(DQuat::IDENTITY);
                g[j] = match self.map[j] {
                    Some(u) => (w * rot[u] * t_inv[u] * wi).normalize(),
                    None => parent,
                };
                local[j] = (parent.inverse() * g[j]).normalize();
            }
            roots.push(self.scale * (w * pos[hips]));
            poses.push(local);
        }
        let (mut roots, poses) = resample::apply(&plan, &roots, &poses);
        // Height: the lowest foot joint at the source's (scaled, relative to the clip's floor).
        let mut lows = self.user_lows(bvh, &plan);
        let src_floor = percentile(&mut lows.clone(), FLOOR_PERCENTILE);
        for ((r, p), low) in roots.iter_mut().zip(&poses).zip(&mut lows) {
            let target = self.scale * (*low - src_floor) + self.foot_rest;
            r.y += target - self.canonical_low(&forward_kinematics(*r, p).0);
        }
        Ok(Motion::new(roots, poses)?)
    }

    /// The canonical motion `m` on this rig: a BVH with the rig's hierarchy and channels at 30 fps.
    pub fn from_canonical(&self, m: &Motion) -> Bvh {
        let n = self.joints.iter().map(|j| j.channels.len()).sum::<usize>();
        let (wi, up) = (self.world.inverse(), self.up());
        let mut values = vec![0.0; n * m.frames()];
        for (f, row) in values.chunks_exact_mut(n.max(1)).enumerate().take(m.frames()) {
            let (pos, g) = m.global_pose(f);
            let p = wi * m.root_positions()[f] / self.scale;
            let target = (self.canonical_low(&pos) - self.foot_rest) / self.scale + self.floor;
            let mut posed = self.user_pose(&g, p);
            let low = self.feet_user.iter().map(|&u| up.dot(posed.2[u])).fold(f64::INFINITY, f64::min);
            let delta = target - low;
            if delta.is_finite() && delta != 0.0 {
                posed = self.user_pose(&g, p + up * delta);
            }
            self.fill_row(&posed.0, posed.1, row);
        }
        Bvh { joints: self.joints.clone(), frame_time: 1.0 / canonical::FPS, frames: m.frames(), values }
    }

    /// One frame on the user rig from canonical global rotations `g_can` and the Hips position `p`
    /// (user world): local rotations, the translation carried by the carrier joint, positions.
    fn user_pose(&self, g_can: &[DQuat; NUM_JOINTS], p: DVec3) -> (Vec<DQuat>, Option<(usize, DVec3)>, Vec<DVec3>) {
        let (w, wi) = (self.world, self.world.inverse());
        let nj = self.joints.len();
        let mut g = vec![DQuat::IDENTITY; nj];
        let mut local = vec![DQuat::IDENTITY; nj];
        for (u, joint) in self.joints.iter().enumerate() {
            let parent = joint.parent.map(|q| g[q]).unwrap_or(DQuat::IDENTITY);
            g[u] = match self.inverse[u] {
                Some(j) => (wi * g_can[j] * w * self.t_global[u]).normalize(),
                None => (parent * self.base_local[u]).normalize(),
            };
            local[u] = (parent.inverse() * g[u]).normalize();
        }
        // Translation of the carrier so that the Hips land on `p` (joints between keep their OFFSETs).
        let mut carried = None;
        if let Some(c) = self.carrier {
            let k = self.hips_chain.iter().position(|&u| u == c).expect("carrier is on the chain");
            let mut above = DVec3::ZERO; // position of the carrier's parent
            for &u in &self.hips_chain[..k] {
                above = match self.joints[u].parent {
                    Some(q) => above + g[q] * self.rest_t[u],
                    None => self.rest_t[u],
                };
            }
            let mut below = DVec3::ZERO; // carrier → Hips
            for &u in &self.hips_chain[k + 1..] {
                below += g[self.joints[u].parent.expect("below the carrier")] * self.rest_t[u];
            }
            let t = match self.joints[c].parent {
                Some(q) => g[q].inverse() * (p - below - above),
                None => p - below,
            };
            carried = Some((c, t));
        }
        let mut pos = vec![DVec3::ZERO; nj];
        for (u, joint) in self.joints.iter().enumerate() {
            let mut t = self.rest_t[u];
            if let Some((c, tc)) = carried
                && c == u
            {
                for ch in &joint.channels {
                    if let Channel::Position(a) = ch {
                        t[a.index()] = tc[a.index()];
                    }
                }
            }
            pos[u] = match joint.parent {
                Some(q) => pos[q] + g[q] * t,
                None => t,
            };
        }
        (local, carried, pos)
    }

    /// Channel values of one frame: rotations in each joint's channel order, position channels the
    /// rest translation (the carrier: its translation).
    fn fill_row(&self, local: &[DQuat], carried: Option<(usize, DVec3)>, row: &mut [f64]) {
        let mut k = 0;
        for (u, joint) in self.joints.iter().enumerate() {
            let t = match carried {
                Some((c, t)) if c == u => t,
                _ => self.rest_t[u],
            };
            let axes: Vec<Axis> = joint
                .channels
                .iter()
                .filter_map(|c| match c {
                    Channel::Rotation(a) => Some(*a),
                    Channel::Position(_) => None,
                })
                .collect();
            let mut angles = decompose(local[u], &axes).into_iter();
            for ch in &joint.channels {
                let v = match ch {
                    Channel::Position(a) => t[a.index()],
                    Channel::Rotation(_) => angles.next().unwrap_or(0.0),
                };
                row[k] = if v.is_finite() { v } else { 0.0 };
                k += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_interpolates() {
        let mut v = vec![4.0, 1.0, 3.0, 2.0, 5.0];
        assert_eq!(percentile(&mut v, 0.0), 1.0);
        assert_eq!(percentile(&mut v, 0.5), 3.0);
        assert!((percentile(&mut v, 0.05) - 1.2).abs() < 1e-12);
        assert_eq!(percentile(&mut [7.0], 0.05), 7.0);
    }
}
