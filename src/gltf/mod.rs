//! glTF 2.0 export: a [`Bvh`] (the canonical rig or a user's own) as a binary `.glb` with its
//! skeleton as nodes, a skin and a small mesh of bone shapes, and one animation over the whole clip.
//!
//! **Space.** glTF is in metres, Y up, the model facing +Z. [`GltfOptions`] gives the rig's metres
//! per unit and the rotation that takes its axes there; both are applied at the root (its
//! translation is rotated and every translation scaled, the root's rotation is premultiplied by
//! the turn), so that every joint's world position is exactly `orientation · (metres_per_unit ·
//! p)` with `p` its BVH world position ([`Bvh::global_pose`]), and every other joint's local
//! rotation is the BVH's own. The scene's `extras` record both (`metresPerUnit`, `orientation` as
//! `[x, y, z, w]`) and the source frame time.
//!
//! **Nodes.** One node per BVH joint, in BVH order (node `i` is joint `i`), named as in the BVH;
//! its rest transform is the joint's OFFSET (position-channel components from the first frame, as
//! the retargeter reads rest poses) with no rotation. The skin lists every joint; its mesh (a root
//! node, as glTF asks of skinned meshes) is one octahedral bone per parent → child link and per End
//! Site, each bound rigidly to the bone's parent joint, so viewers that draw meshes only (and
//! Blender, which builds an armature from the skin) show the skeleton.
//!
//! **Animation.** One animation, one keyframe per BVH frame at `f · frame_time`, `LINEAR`: a
//! `rotation` channel for every joint with rotation channels and a `translation` channel for every
//! joint with position channels. Quaternions are kept on one hemisphere from frame to frame so that
//! interpolation takes the short way.

mod error;
mod glb;

pub use error::GltfError;

use crate::bvh::{Bvh, Channel};
use crate::skeleton::RigReport;
use glam::{DMat3, DQuat, DVec3};

/// How a BVH's space maps onto glTF's (metres, Y up, facing +Z).
#[derive(Clone, Debug, PartialEq)]
pub struct GltfOptions {
    /// Metres per BVH unit (the canonical rig: 0.01, it is in centimetres).
    pub metres_per_unit: f64,
    /// The rotation from the BVH's world axes to glTF's (identity for the canonical rig).
    pub orientation: DQuat,
    /// The animation's name.
    pub animation_name: String,
}

impl GltfOptions {
    /// The canonical rig's: centimetres, Y up, facing +Z.
    pub fn canonical() -> GltfOptions {
        GltfOptions { metres_per_unit: 0.01, orientation: DQuat::IDENTITY, animation_name: "motion".to_string() }
    }

    /// A user rig's, from what the importer detected: its scale (canonical centimetres per unit)
    /// and its up and forward axes, turned onto +Y and +Z. Axes that do not make a frame (the same
    /// axis twice, unreadable names) leave the orientation to the up axis alone, or to identity.
    pub fn for_rig(report: &RigReport) -> GltfOptions {
        let metres_per_unit = if report.scale.is_finite() && report.scale > 0.0 { report.scale / 100.0 } else { 0.01 };
        let up = signed_axis(&report.up_axis);
        let forward = signed_axis(&report.forward_axis);
        let orientation = match (up, forward) {
            (Some(u), Some(f)) if u.dot(f).abs() < 0.5 => {
                // The rows of the rotation are the rig's left, up and forward: they go to X, Y, Z.
                let left = u.cross(f);
                DQuat::from_mat3(&DMat3::from_cols(left, u, f).transpose())
            }
            (Some(u), _) => DQuat::from_rotation_arc(u, DVec3::Y),
            _ => DQuat::IDENTITY,
        };
        GltfOptions { metres_per_unit, orientation, animation_name: "motion".to_string() }
    }
}

/// `"+Y"`, `"-Z"`, … as a unit vector.
fn signed_axis(name: &str) -> Option<DVec3> {
    let (sign, axis) = match name.trim().as_bytes() {
        [b'+', a] => (1.0, *a),
        [b'-', a] => (-1.0, *a),
        [a] => (1.0, *a),
        _ => return None,
    };
    let v = match axis.to_ascii_uppercase() {
        b'X' => DVec3::X,
        b'Y' => DVec3::Y,
        b'Z' => DVec3::Z,
        _ => return None,
    };
    Some(v * sign)
}

/// Skins address their joints with 16-bit indices here.
pub const MAX_JOINTS: usize = u16::MAX as usize;

/// At most this many joint keyframes (frames × joints): ~450 MB of pose in memory, ~220 MB of
/// `.glb` (e.g. 9,000 frames of a 900-joint rig, or 3.5 hours of a 21-joint one at 30 fps).
pub const MAX_KEYS: usize = 8_000_000;

/// A BVH's skeleton and motion in glTF space: what the `.glb` holds, and what the npm package's
/// three.js helper builds its `Skeleton` and `AnimationClip` from.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    pub names: Vec<String>,
    pub parents: Vec<Option<usize>>,
    pub frames: usize,
    /// Seconds per frame.
    pub frame_time: f64,
    /// Each joint's rest translation and rotation (the rotation is identity but at the roots).
    pub rest_translation: Vec<DVec3>,
    pub rest_rotation: Vec<DQuat>,
    /// Whether each joint's translation / rotation is animated (it has position / rotation channels).
    pub animated_translation: Vec<bool>,
    pub animated_rotation: Vec<bool>,
    /// Local translations and rotations, `frames × joints`, row-major (every joint, animated or not).
    pub translation: Vec<DVec3>,
    pub rotation: Vec<DQuat>,
    /// The End Sites' offsets in glTF space (relative to their joint, scaled).
    pub end_sites: Vec<Option<DVec3>>,
    /// The options it was made with.
    pub options: GltfOptions,
}

impl Animation {
    /// The skeleton and motion of `bvh` in glTF space. Errors: an empty, malformed or non-finite
    /// BVH or options, more than [`MAX_JOINTS`] joints.
    pub fn from_bvh(bvh: &Bvh, options: &GltfOptions) -> Result<Animation, GltfError> {
        check(bvh, options)?;
        let n = bvh.joints.len();
        let s = options.metres_per_unit;
        let turn = options.orientation.normalize();
        let is_root: Vec<bool> = bvh.joints.iter().map(|j| j.parent.is_none()).collect();
        let local = |t: DVec3, r: DQuat, j: usize| {
            if is_root[j] { (turn * (t * s), turn * r) } else { (t * s, r) }
        };
        let mut translation = Vec::with_capacity(bvh.frames * n);
        let mut rotation: Vec<DQuat> = Vec::with_capacity(bvh.frames * n);
        for f in 0..bvh.frames {
            for j in 0..n {
                let (t, r) = bvh.local_transform(f, j);
                let (t, mut r) = local(t, r.normalize(), j);
                if f > 0 && rotation[(f - 1) * n + j].dot(r) < 0.0 {
                    r = -r;
                }
                translation.push(t);
                rotation.push(r);
            }
        }
        let has = |j: usize, position: bool| {
            bvh.joints[j].channels.iter().any(|c| matches!(c, Channel::Position(_)) == position)
        };
        // The rest pose: the OFFSETs, with position-channel components from the first frame.
        let rest_translation = (0..n)
            .map(|j| if has(j, true) { translation[j] } else { local(bvh.joints[j].offset, DQuat::IDENTITY, j).0 })
            .collect();
        Ok(Animation {
            names: bvh.joints.iter().map(|j| j.name.clone()).collect(),
            parents: bvh.joints.iter().map(|j| j.parent).collect(),
            frames: bvh.frames,
            frame_time: bvh.frame_time,
            rest_translation,
            rest_rotation: (0..n).map(|j| if is_root[j] { turn } else { DQuat::IDENTITY }).collect(),
            animated_translation: (0..n).map(|j| has(j, true)).collect(),
            animated_rotation: (0..n).map(|j| has(j, false)).collect(),
            translation,
            rotation,
            end_sites: bvh.joints.iter().map(|j| j.end_site.map(|e| e * s)).collect(),
            options: options.clone(),
        })
    }

    /// Number of joints.
    pub fn joints(&self) -> usize {
        self.names.len()
    }

    /// World positions and rotations of the rest pose (glTF space).
    pub fn rest_world(&self) -> (Vec<DVec3>, Vec<DQuat>) {
        crate::skeleton::fk::forward_kinematics_vec(
            self.joints(),
            |j| self.parents[j],
            |j| (self.rest_translation[j], self.rest_rotation[j]),
        )
    }

    /// World joint positions of frame `f` (glTF space).
    pub fn world_positions(&self, f: usize) -> Vec<DVec3> {
        let n = self.joints();
        crate::skeleton::fk::forward_kinematics_vec(
            n,
            |j| self.parents[j],
            |j| (self.translation[f * n + j], self.rotation[f * n + j]),
        )
        .0
    }

    /// The `.glb` bytes (see the module docs).
    pub fn to_glb(&self) -> Result<Vec<u8>, GltfError> {
        glb::write(self)
    }
}

/// `bvh` as `.glb` bytes (see the module docs): [`Animation::from_bvh`] then [`Animation::to_glb`].
pub fn to_glb(bvh: &Bvh, options: &GltfOptions) -> Result<Vec<u8>, GltfError> {
    Animation::from_bvh(bvh, options)?.to_glb()
}

/// The invariants [`Animation::from_bvh`] relies on, as errors rather than panics.
fn check(bvh: &Bvh, options: &GltfOptions) -> Result<(), GltfError> {
    let n = bvh.joints.len();
    if n == 0 {
        return Err(GltfError::Empty { what: "joints" });
    }
    if bvh.frames == 0 {
        return Err(GltfError::Empty { what: "frames" });
    }
    if n > MAX_JOINTS {
        return Err(GltfError::TooManyJoints { joints: n, max: MAX_JOINTS });
    }
    if bvh.frames.checked_mul(n).is_none_or(|keys| keys > MAX_KEYS) {
        let reason = format!("{} frames of {n} joints: more than {MAX_KEYS} joint keyframes", bvh.frames);
        return Err(GltfError::TooLarge { reason });
    }
    let malformed = |reason: String| Err(GltfError::Malformed { reason });
    let mut channel_offset = 0;
    for (i, j) in bvh.joints.iter().enumerate() {
        if let Some(p) = j.parent
            && p >= i
        {
            return malformed(format!("joint {i} ({}): its parent {p} does not precede it", j.name));
        }
        if j.channel_offset != channel_offset {
            return malformed(format!(
                "joint {i} ({}): channel offset {} is not {channel_offset}",
                j.name, j.channel_offset
            ));
        }
        channel_offset += j.channels.len();
        if !j.offset.is_finite() || !j.end_site.is_none_or(|e| e.is_finite()) {
            return Err(GltfError::NonFinite { what: format!("the offset of joint {i} ({})", j.name) });
        }
    }
    match bvh.frames.checked_mul(channel_offset) {
        Some(len) if len == bvh.values.len() => {}
        _ => {
            return malformed(format!(
                "{} values for {} frames of {channel_offset} channels",
                bvh.values.len(),
                bvh.frames
            ));
        }
    }
    if let Some(k) = bvh.values.iter().position(|v| !v.is_finite()) {
        let frame = k / channel_offset.max(1);
        return Err(GltfError::NonFinite { what: format!("frame {frame}, channel {}", k % channel_offset.max(1)) });
    }
    if !(bvh.frame_time.is_finite() && bvh.frame_time > 0.0) {
        return Err(GltfError::NonFinite { what: format!("frame time {}", bvh.frame_time) });
    }
    let s = options.metres_per_unit;
    if !(s.is_finite() && s > 0.0) {
        return Err(GltfError::NonFinite { what: format!("metres per unit {s}") });
    }
    let q = options.orientation;
    if !q.is_finite() || q.length() < 1e-9 {
        return Err(GltfError::NonFinite { what: format!("orientation {q:?}") });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::Bvh;

    const TWO_JOINTS: &str = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT Spine\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 5 0\n  }\n }\n}\nMOTION\nFrames: 3\nFrame Time: 0.04\n1 90 2 0 0 0 0 0 0\n2 91 3 10 20 30 -170 5 0\n3 92 4 -20 30 179 175 -5 10\n";

    fn two_joints() -> Bvh {
        Bvh::parse(TWO_JOINTS).unwrap()
    }

    #[test]
    fn world_positions_are_the_bvh_ones_scaled_and_turned() {
        let bvh = two_joints();
        let turn = DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        let options = GltfOptions { metres_per_unit: 0.025, orientation: turn, animation_name: "a".into() };
        let a = Animation::from_bvh(&bvh, &options).unwrap();
        for f in 0..bvh.frames {
            let (want, _) = bvh.global_pose(f);
            for (j, got) in a.world_positions(f).into_iter().enumerate() {
                let want = turn * (want[j] * 0.025);
                assert!((got - want).length() < 1e-12, "frame {f} joint {j}: {got} vs {want}");
            }
        }
        assert!(a.animated_translation[0] && !a.animated_translation[1]);
        assert!(a.animated_rotation.iter().all(|&r| r));
    }

    #[test]
    fn quaternions_stay_on_one_hemisphere() {
        let a = Animation::from_bvh(&two_joints(), &GltfOptions::canonical()).unwrap();
        for f in 1..a.frames {
            for j in 0..2 {
                assert!(a.rotation[(f - 1) * 2 + j].dot(a.rotation[f * 2 + j]) >= 0.0, "frame {f} joint {j}");
            }
        }
    }

    #[test]
    fn rig_orientation_takes_up_to_y_and_forward_to_z() {
        let report = RigReport {
            rig: "generic".into(),
            matched: vec![],
            missing: vec![],
            scale: 2.54,
            up_axis: "+Z".into(),
            forward_axis: "-Y".into(),
            floor: 0.0,
            base_pose: "rest".into(),
        };
        let o = GltfOptions::for_rig(&report);
        assert!((o.metres_per_unit - 0.0254).abs() < 1e-15);
        assert!((o.orientation * DVec3::Z - DVec3::Y).length() < 1e-12);
        assert!((o.orientation * -DVec3::Y - DVec3::Z).length() < 1e-12);
        let same = RigReport { forward_axis: "+Z".into(), ..report.clone() };
        assert!((GltfOptions::for_rig(&same).orientation * DVec3::Z - DVec3::Y).length() < 1e-12);
        let unreadable = RigReport { up_axis: "up".into(), ..report };
        assert_eq!(GltfOptions::for_rig(&unreadable).orientation, DQuat::IDENTITY);
    }

    #[test]
    fn bad_motions_are_errors_not_panics() {
        let good = two_joints();
        let mut b = good.clone();
        b.values[4] = f64::NAN;
        assert_eq!(to_glb(&b, &GltfOptions::canonical()).unwrap_err().code(), "BAD_MOTION");
        let mut b = good.clone();
        b.values.pop();
        assert!(matches!(to_glb(&b, &GltfOptions::canonical()), Err(GltfError::Malformed { .. })));
        let mut b = good.clone();
        b.joints[1].parent = Some(1);
        assert!(matches!(to_glb(&b, &GltfOptions::canonical()), Err(GltfError::Malformed { .. })));
        let mut b = good.clone();
        b.joints.clear();
        assert_eq!(to_glb(&b, &GltfOptions::canonical()), Err(GltfError::Empty { what: "joints" }));
        let mut b = good.clone();
        b.frames = 0;
        b.values.clear();
        assert_eq!(to_glb(&b, &GltfOptions::canonical()), Err(GltfError::Empty { what: "frames" }));
        let mut b = good.clone();
        b.frame_time = 0.0;
        assert!(matches!(to_glb(&b, &GltfOptions::canonical()), Err(GltfError::NonFinite { .. })));
        // Too many keyframes: refused before anything proportional to them is allocated.
        let mut b = good.clone();
        b.joints.truncate(1);
        b.joints[0].channels.clear();
        b.frames = MAX_KEYS + 1;
        b.values.clear();
        assert_eq!(to_glb(&b, &GltfOptions::canonical()).unwrap_err().code(), "TOO_LONG");
        let zero = GltfOptions { metres_per_unit: 0.0, ..GltfOptions::canonical() };
        assert!(matches!(to_glb(&good, &zero), Err(GltfError::NonFinite { .. })));
    }
}
