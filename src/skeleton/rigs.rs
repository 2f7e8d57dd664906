//! Rig detection: which naming scheme a user's BVH follows, which of its joints play the canonical
//! joints' parts, and the base (reference) pose of the rigs whose zero-rotation rest pose is no use.
//!
//! One table per scheme (the tables are in `rig_names.rs`) maps each canonical joint to candidate
//! user joint names (compared case-insensitively after dropping any `namespace:` and `mixamorig*`
//! prefix); a generic fallback understands side markers (`Left…`, `…_L`, `L_…`, `l…`, `LThigh`) and
//! common synonyms. The scheme that matches the required joints and the most joints in all wins; ties go to the earlier scheme in
//! [`SCHEMES`] order. A match is kept only if the user hierarchy agrees with the canonical one (the
//! user joint of a canonical joint's nearest matched canonical ancestor is one of its ancestors).

use super::canonical::{JOINT_NAMES, NUM_JOINTS, PARENTS, joint::*};
use super::rig_names::*;
use crate::bvh::BvhJoint;

/// Canonical joints every rig must provide (plus at least one of Spine and Chest).
pub const REQUIRED: [usize; 14] = [
    HIPS,
    HEAD,
    UPPER_ARM_L,
    LOWER_ARM_L,
    HAND_L,
    UPPER_ARM_R,
    LOWER_ARM_R,
    HAND_R,
    UPPER_LEG_L,
    LOWER_LEG_L,
    FOOT_L,
    UPPER_LEG_R,
    LOWER_LEG_R,
    FOOT_R,
];

/// Canonical joint → user joint index.
pub type JointMap = [Option<usize>; NUM_JOINTS];

/// Local rotations (x, y, z, w) of a rig's base pose, by user joint name; joints not listed rest at
/// zero rotation.
pub type BasePose = &'static [(&'static str, [f64; 4])];

/// A naming scheme.
pub struct Scheme {
    /// Reported rig name.
    pub name: &'static str,
    /// Candidate user names for canonical joints, in priority order; a user joint is used once.
    table: &'static [(usize, &'static [&'static str])],
    /// Whether the scheme applies at all, from the normalised user joint names.
    eligible: fn(&[BvhJoint], &[String]) -> bool,
    /// Base pose to use instead of the zero-rotation rest pose.
    pub base_pose: Option<BasePose>,
}

/// Result of [`detect`].
#[derive(Clone, Debug)]
pub struct Detection {
    pub rig: &'static str,
    pub map: JointMap,
    pub base_pose: Option<BasePose>,
}

/// Why no scheme fits: the best candidate's name and the required canonical joints it lacks.
#[derive(Clone, Debug, PartialEq)]
pub struct Unmatched {
    pub rig: &'static str,
    pub missing: Vec<String>,
}

/// Lower-case name without any `namespace:` (or `a|b:`) prefix and without a `mixamorigN_` prefix.
pub fn normalise(name: &str) -> String {
    let tail = name.rsplit([':', '|']).next().unwrap_or(name).to_ascii_lowercase();
    match tail.strip_prefix("mixamorig") {
        Some(rest) => {
            let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit());
            rest.strip_prefix('_').unwrap_or(rest).to_string()
        }
        None => tail,
    }
}

fn always(_: &[BvhJoint], _: &[String]) -> bool {
    true
}

fn has(names: &[String], n: &str) -> bool {
    names.iter().any(|x| x == n)
}

/// The naming schemes, in tie-breaking order.
pub static SCHEMES: [Scheme; 5] = [
    Scheme { name: "bandai", table: BANDAI_TABLE, eligible: always, base_pose: Some(BANDAI_BASE_POSE) },
    Scheme {
        name: "cmu31",
        table: CMU31_TABLE,
        eligible: |_, n| has(n, "lhipjoint") || has(n, "lowerback"),
        base_pose: None,
    },
    Scheme { name: "m21", table: CMU31_TABLE, eligible: |_, n| has(n, "neck1"), base_pose: None },
    Scheme { name: "cc_base", table: CC_BASE_TABLE, eligible: always, base_pose: Some(CC_BASE_POSE) },
    Scheme {
        name: "mixamo",
        table: MIXAMO_TABLE,
        eligible: |j, n| has(n, "spine2") || j.iter().any(|j| j.name.to_ascii_lowercase().contains("mixamorig")),
        base_pose: None,
    },
];

/// Name of the generic fallback.
pub const GENERIC: &str = "generic";

/// Detects the rig of `joints` and maps the canonical joints onto it.
pub fn detect(joints: &[BvhJoint]) -> Result<Detection, Unmatched> {
    let normalised: Vec<String> = joints.iter().map(|j| normalise(&j.name)).collect();
    let mut candidates: Vec<(&'static str, JointMap, Option<BasePose>)> = Vec::new();
    for s in &SCHEMES {
        if (s.eligible)(joints, &normalised) {
            candidates.push((s.name, validate(joints, match_table(&normalised, s.table)), s.base_pose));
        }
    }
    candidates.push((GENERIC, validate(joints, match_generic(joints)), None));
    let score = |m: &JointMap| m.iter().filter(|x| x.is_some()).count();
    let mut best: Option<&(&'static str, JointMap, Option<BasePose>)> = None;
    for c in &candidates {
        if missing_required(&c.1).is_empty() && best.is_none_or(|b| score(&c.1) > score(&b.1)) {
            best = Some(c);
        }
    }
    if let Some((rig, map, base_pose)) = best {
        return Ok(Detection { rig, map: *map, base_pose: *base_pose });
    }
    // No scheme has every required joint: report the one closest to it.
    let (rig, map, _) = candidates
        .iter()
        .min_by_key(|c| (missing_required(&c.1).len(), usize::MAX - score(&c.1)))
        .expect("the generic candidate is always there");
    Err(Unmatched { rig, missing: missing_required(map) })
}

/// Names of the required canonical joints `map` lacks (`Spine` and `Chest` when both are missing).
pub fn missing_required(map: &JointMap) -> Vec<String> {
    let no_spine = map[SPINE].is_none() && map[CHEST].is_none();
    (0..NUM_JOINTS)
        .filter(|&j| map[j].is_none() && (REQUIRED.contains(&j) || (no_spine && (j == SPINE || j == CHEST))))
        .map(|j| JOINT_NAMES[j].to_string())
        .collect()
}

fn match_table(normalised: &[String], table: &[(usize, &[&str])]) -> JointMap {
    let mut map: JointMap = [None; NUM_JOINTS];
    let mut used = vec![false; normalised.len()];
    for (j, names) in table {
        for want in names.iter().map(|n| normalise(n)) {
            if let Some(u) = normalised.iter().position(|n| *n == want)
                && !used[u]
            {
                map[*j] = Some(u);
                used[u] = true;
                break;
            }
        }
    }
    map
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Side {
    Left,
    Right,
}

/// Side marker and compact (separator-free, lower-case) base name of a joint name.
fn side_and_base(name: &str) -> (Option<Side>, String) {
    let raw = name.rsplit([':', '|']).next().unwrap_or(name);
    let mut raw = raw.to_string();
    let lower = raw.to_ascii_lowercase();
    if lower.starts_with("mixamorig") {
        raw = normalise(&raw);
    }
    for p in GENERIC_PREFIXES {
        if raw.to_ascii_lowercase().starts_with(p) {
            raw = raw[p.len()..].to_string();
            break;
        }
    }
    let lower = raw.to_ascii_lowercase();
    let tokens: Vec<&str> = lower.split(['_', '.', '-', ' ']).filter(|t| !t.is_empty()).collect();
    let compact: String = tokens.concat();
    let side_of = |t: &str| match t {
        "l" | "left" => Some(Side::Left),
        "r" | "right" => Some(Side::Right),
        _ => None,
    };
    if tokens.len() > 1 {
        if let Some(s) = side_of(tokens[0]) {
            return (Some(s), tokens[1..].concat());
        }
        if let Some(s) = side_of(tokens[tokens.len() - 1]) {
            return (Some(s), tokens[..tokens.len() - 1].concat());
        }
    }
    for (word, side) in [("left", Side::Left), ("right", Side::Right)] {
        if let Some(rest) = compact.strip_prefix(word) {
            return (Some(side), rest.to_string());
        }
        if let Some(rest) = compact.strip_suffix(word) {
            return (Some(side), rest.to_string());
        }
    }
    // CamelCase "LThigh", "RHipJoint".
    let b = raw.as_bytes();
    if b.len() > 2 && (b[0] == b'L' || b[0] == b'R') && b[1].is_ascii_uppercase() && b[2].is_ascii_lowercase() {
        let side = if b[0] == b'L' { Side::Left } else { Side::Right };
        return (Some(side), compact[1..].to_string());
    }
    (None, compact)
}

fn match_generic(joints: &[BvhJoint]) -> JointMap {
    let parsed: Vec<(Option<Side>, String)> = joints.iter().map(|j| side_and_base(&j.name)).collect();
    let mut map: JointMap = [None; NUM_JOINTS];
    let mut used = vec![false; joints.len()];
    let take = |side: Option<Side>, names: &[&str], used: &mut Vec<bool>| -> Option<usize> {
        for want in names {
            if let Some(u) = parsed.iter().enumerate().position(|(u, (s, b))| !used[u] && *s == side && b == want) {
                used[u] = true;
                return Some(u);
            }
        }
        None
    };
    for (j, names) in GENERIC_CENTRE {
        map[*j] = take(None, names, &mut used);
    }
    for (js, names) in GENERIC_SIDED {
        map[js[0]] = take(Some(Side::Left), names, &mut used);
        map[js[1]] = take(Some(Side::Right), names, &mut used);
    }
    map
}

/// Drops matches that contradict the hierarchy: the user joint of a canonical joint's nearest matched
/// canonical ancestor must be a proper ancestor of its own user joint.
fn validate(joints: &[BvhJoint], mut map: JointMap) -> JointMap {
    let is_ancestor = |a: usize, mut d: usize| {
        let mut steps = 0;
        while let Some(p) = joints.get(d).and_then(|j| j.parent) {
            if p == a {
                return true;
            }
            d = p;
            steps += 1;
            if steps > joints.len() {
                break;
            }
        }
        false
    };
    for j in 0..NUM_JOINTS {
        let Some(u) = map[j] else { continue };
        let mut a = PARENTS[j];
        while let Some(p) = a {
            if map[p].is_some() {
                break;
            }
            a = PARENTS[p];
        }
        if let Some(p) = a
            && !is_ancestor(map[p].unwrap_or(usize::MAX), u)
        {
            map[j] = None;
        }
    }
    map
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn rig(names: &[(&str, Option<usize>)]) -> Vec<BvhJoint> {
        names
            .iter()
            .map(|(n, p)| BvhJoint {
                name: n.to_string(),
                parent: *p,
                offset: DVec3::ZERO,
                channels: vec![],
                end_site: None,
                channel_offset: 0,
            })
            .collect()
    }

    #[test]
    fn normalises_prefixes() {
        assert_eq!(normalise("mixamorig:LeftArm"), "leftarm");
        assert_eq!(normalise("mixamorig1:LeftArm"), "leftarm");
        assert_eq!(normalise("mixamorig_LeftArm"), "leftarm");
        assert_eq!(normalise("Armature|Hips"), "hips");
        assert_eq!(normalise("CC_Base_L_Thigh"), "cc_base_l_thigh");
    }

    #[test]
    fn generic_side_markers() {
        assert_eq!(side_and_base("LeftUpLeg"), (Some(Side::Left), "upleg".into()));
        assert_eq!(side_and_base("upperarm_r"), (Some(Side::Right), "upperarm".into()));
        assert_eq!(side_and_base("L_Thigh"), (Some(Side::Left), "thigh".into()));
        assert_eq!(side_and_base("LThigh"), (Some(Side::Left), "thigh".into()));
        assert_eq!(side_and_base("Foot.L"), (Some(Side::Left), "foot".into()));
        assert_eq!(side_and_base("hand_right"), (Some(Side::Right), "hand".into()));
        assert_eq!(side_and_base("Bip01_R_Calf"), (Some(Side::Right), "calf".into()));
        assert_eq!(side_and_base("Head"), (None, "head".into()));
        assert_eq!(side_and_base("Spine_01"), (None, "spine01".into()));
    }

    #[test]
    fn generic_rig_with_smpl_like_names() {
        // pelvis, spine1..3, neck, head, collars, shoulders (= upper arms), elbows, wrists, hips, knees…
        let j = rig(&[
            ("pelvis", None),
            ("left_hip", Some(0)),
            ("left_knee", Some(1)),
            ("left_ankle", Some(2)),
            ("left_foot", Some(3)),
            ("right_hip", Some(0)),
            ("right_knee", Some(5)),
            ("right_ankle", Some(6)),
            ("right_foot", Some(7)),
            ("spine1", Some(0)),
            ("spine2", Some(9)),
            ("spine3", Some(10)),
            ("neck", Some(11)),
            ("head", Some(12)),
            ("left_collar", Some(11)),
            ("left_shoulder", Some(14)),
            ("left_elbow", Some(15)),
            ("left_wrist", Some(16)),
            ("right_collar", Some(11)),
            ("right_shoulder", Some(18)),
            ("right_elbow", Some(19)),
            ("right_wrist", Some(20)),
        ]);
        let d = detect(&j).unwrap();
        assert_eq!(d.rig, GENERIC);
        let name = |c: usize| d.map[c].map(|u| j[u].name.as_str());
        assert_eq!(name(HIPS), Some("pelvis"));
        assert_eq!(name(UPPER_LEG_L), Some("left_hip"));
        assert_eq!(name(LOWER_LEG_L), Some("left_knee"));
        // SMPL's "ankle" is the foot joint and its "foot" the ball of the foot.
        assert_eq!(name(FOOT_L), Some("left_ankle"));
        assert_eq!(name(TOES_L), Some("left_foot"));
        assert_eq!(name(SHOULDER_R), Some("right_collar"));
        assert_eq!(name(UPPER_ARM_R), Some("right_shoulder"));
        assert_eq!(name(HAND_R), Some("right_wrist"));
        assert_eq!(name(CHEST), Some("spine2"));
        assert_eq!(name(SPINE), Some("spine1"));
    }

    #[test]
    fn mixamo_three_spines() {
        let names = [
            ("mixamorig:Hips", None),
            ("mixamorig:Spine", Some(0)),
            ("mixamorig:Spine1", Some(1)),
            ("mixamorig:Spine2", Some(2)),
            ("mixamorig:Neck", Some(3)),
            ("mixamorig:Head", Some(4)),
            ("mixamorig:LeftShoulder", Some(3)),
            ("mixamorig:LeftArm", Some(6)),
            ("mixamorig:LeftForeArm", Some(7)),
            ("mixamorig:LeftHand", Some(8)),
            ("mixamorig:RightShoulder", Some(3)),
            ("mixamorig:RightArm", Some(10)),
            ("mixamorig:RightForeArm", Some(11)),
            ("mixamorig:RightHand", Some(12)),
            ("mixamorig:LeftUpLeg", Some(0)),
            ("mixamorig:LeftLeg", Some(14)),
            ("mixamorig:LeftFoot", Some(15)),
            ("mixamorig:LeftToeBase", Some(16)),
            ("mixamorig:RightUpLeg", Some(0)),
            ("mixamorig:RightLeg", Some(18)),
            ("mixamorig:RightFoot", Some(19)),
            ("mixamorig:RightToeBase", Some(20)),
        ];
        let d = detect(&rig(&names)).unwrap();
        assert_eq!(d.rig, "mixamo");
        assert_eq!((d.map[SPINE], d.map[CHEST], d.map[NECK]), (Some(2), Some(3), Some(4)));
        assert!(d.map.iter().all(|m| m.is_some()));
        // The same without prefix, and with a numbered one.
        let bare: Vec<(String, Option<usize>)> = names.iter().map(|(n, p)| (n[10..].to_string(), *p)).collect();
        let bare: Vec<(&str, Option<usize>)> = bare.iter().map(|(n, p)| (n.as_str(), *p)).collect();
        assert_eq!(detect(&rig(&bare)).unwrap().rig, "mixamo");
        let two: Vec<(String, Option<usize>)> = names.iter().map(|(n, p)| (n.replace(':', "2:"), *p)).collect();
        let two: Vec<(&str, Option<usize>)> = two.iter().map(|(n, p)| (n.as_str(), *p)).collect();
        assert_eq!(detect(&rig(&two)).unwrap().map, d.map);
    }

    #[test]
    fn hierarchy_contradictions_are_dropped() {
        // "LeftHand" under the right arm: not a descendant of the left forearm.
        let j = rig(&[
            ("Hips", None),
            ("Spine", Some(0)),
            ("Head", Some(1)),
            ("LeftArm", Some(1)),
            ("LeftForeArm", Some(3)),
            ("RightArm", Some(1)),
            ("RightForeArm", Some(5)),
            ("LeftHand", Some(6)),
            ("RightHand", Some(6)),
        ]);
        let map = validate(&j, match_generic(&j));
        assert_eq!(map[HAND_L], None);
        assert_eq!(map[HAND_R], Some(8));
        let err = detect(&j).unwrap_err();
        assert!(err.missing.contains(&"Hand_L".to_string()));
        assert!(err.missing.contains(&"UpperLeg_L".to_string()));
    }
}
