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

/// Canonical joints every rig must provide: the essential parts, Hips, both legs down to the foot and
/// both arms down to the hand. The others (Spine, Chest, Neck, Head, Shoulders, Toes) are
/// synthesised on the canonical rig when missing (see [`super::retarget`]).
pub const REQUIRED: [usize; 13] = [
    HIPS,
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
    /// Whether Spine and Chest come from the structure ([`spine_from_structure`]): rigs with a
    /// variable number of spine joints.
    structural_spine: bool,
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
    /// That scheme's (partial) match: the best guesses.
    pub map: Box<JointMap>,
}

/// The name a table entry is compared by: the part after any `namespace:` (or `a|b:`) prefix,
/// lower-case, without separators (`_`, `-`, `.`, spaces), without a `mixamorigN` prefix and without a
/// 3ds Max `BipNN` prefix (`Bip01_L_Thigh` → `lthigh`; the `Bip01` root itself stays `bip01`).
pub fn normalise(name: &str) -> String {
    let tail = name.rsplit([':', '|']).next().unwrap_or(name);
    let s: String =
        tail.chars().filter(|c| !matches!(c, '_' | '-' | '.' | ' ')).map(|c| c.to_ascii_lowercase()).collect();
    let digits = |c: char| c.is_ascii_digit();
    if let Some(rest) = s.strip_prefix("mixamorig") {
        return rest.trim_start_matches(digits).to_string();
    }
    if let Some(rest) = s.strip_prefix("bip") {
        let r = rest.trim_start_matches(digits);
        if r.len() < rest.len() && !r.is_empty() {
            return r.to_string();
        }
    }
    s
}

fn always(_: &[BvhJoint], _: &[String]) -> bool {
    true
}

fn has(names: &[String], n: &str) -> bool {
    names.iter().any(|x| x == n)
}

fn any(names: &[String], f: impl Fn(&str) -> bool) -> bool {
    names.iter().any(|x| f(x))
}

/// A scheme of `table` with a fixed name and eligibility.
const fn scheme(
    name: &'static str,
    table: &'static [(usize, &'static [&'static str])],
    eligible: fn(&[BvhJoint], &[String]) -> bool,
    structural_spine: bool,
) -> Scheme {
    Scheme { name, table, eligible, base_pose: None, structural_spine }
}

/// The naming schemes, in tie-breaking order.
pub static SCHEMES: [Scheme; 12] = [
    Scheme {
        name: "bandai",
        table: BANDAI_TABLE,
        eligible: always,
        base_pose: Some(BANDAI_BASE_POSE),
        structural_spine: false,
    },
    scheme("cmu31", CMU31_TABLE, |_, n| has(n, "lhipjoint") || has(n, "lowerback"), false),
    scheme("m21", CMU31_TABLE, |_, n| has(n, "neck1"), false),
    Scheme {
        name: "cc_base",
        table: CC_BASE_TABLE,
        eligible: always,
        base_pose: Some(CC_BASE_POSE),
        structural_spine: false,
    },
    scheme(
        "daz_poser",
        DAZ_POSER_TABLE,
        |_, n| has(n, "abdomen") || has(n, "abdomenlower") || has(n, "lshldr") || has(n, "lshldrbend"),
        false,
    ),
    scheme("second_life", SECOND_LIFE_TABLE, |_, n| has(n, "mpelvis") || has(n, "mtorso"), false),
    scheme("acclaim", ACCLAIM_TABLE, |_, n| has(n, "lfemur") || has(n, "lhumerus"), false),
    scheme(
        "humanik",
        HUMANIK_TABLE,
        |_, n| {
            any(n, |x| x.ends_with("roll") || x.starts_with("lefthandthumb") || x.starts_with("leftinhand"))
                || has(n, "spine3")
                || has(n, "leftthigh")
        },
        true,
    ),
    scheme(
        "mixamo",
        MIXAMO_TABLE,
        |j, n| has(n, "spine2") || j.iter().any(|j| j.name.to_ascii_lowercase().contains("mixamorig")),
        false,
    ),
    scheme(
        "biped",
        BIPED_TABLE,
        |j, _| {
            j.iter().any(|j| {
                let l = j.name.to_ascii_lowercase();
                l.strip_prefix("bip").is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
            })
        },
        true,
    ),
    scheme(
        "smpl",
        SMPL_TABLE,
        |_, n| has(n, "lknee") || has(n, "leftknee") || has(n, "lelbow") || has(n, "leftelbow"),
        true,
    ),
    scheme("unreal", UNREAL_TABLE, |_, n| has(n, "spine01") || has(n, "claviclel") || has(n, "thighl"), true),
];

/// Name of the generic fallback.
pub const GENERIC: &str = "generic";

/// Detects the rig of `joints` and maps the canonical joints onto it.
pub fn detect(joints: &[BvhJoint]) -> Result<Detection, Unmatched> {
    let normalised: Vec<String> = joints.iter().map(|j| normalise(&j.name)).collect();
    let mut candidates: Vec<(&'static str, JointMap, Option<BasePose>)> = Vec::new();
    for s in &SCHEMES {
        if (s.eligible)(joints, &normalised) {
            let mut map = validate(joints, match_table(&normalised, s.table));
            if s.structural_spine {
                map = validate(joints, spine_from_structure(joints, map));
            }
            candidates.push((s.name, map, s.base_pose));
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
    Err(Unmatched { rig, missing: missing_required(map), map: Box::new(*map) })
}

/// Names of the required canonical joints `map` lacks.
pub fn missing_required(map: &JointMap) -> Vec<String> {
    (0..NUM_JOINTS).filter(|&j| map[j].is_none() && REQUIRED.contains(&j)).map(|j| JOINT_NAMES[j].to_string()).collect()
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

/// The user joints from the root down to `u` (root first); empty if the hierarchy loops.
pub(super) fn path_to(joints: &[BvhJoint], u: usize) -> Vec<usize> {
    let mut path = vec![u];
    let mut cur = u;
    while let Some(p) = joints.get(cur).and_then(|j| j.parent) {
        if path.len() > joints.len() {
            return Vec::new();
        }
        path.push(p);
        cur = p;
    }
    path.reverse();
    path
}

/// Spine and Chest from the structure: on the chain from the Hips up to the Head, the Chest is the
/// joint the two upper arms branch from (the one below it where that is the Neck, as in 3ds Max
/// Biped, whose clavicles hang from the neck), the Spine the joint below the Chest (none when the
/// Chest sits on the Hips), the Neck the joint above the Chest when no name gave one. Unchanged when
/// the arms do not branch from that chain.
pub(super) fn spine_from_structure(joints: &[BvhJoint], mut map: JointMap) -> JointMap {
    let (Some(hips), Some(head), Some(al), Some(ar)) = (map[HIPS], map[HEAD], map[UPPER_ARM_L], map[UPPER_ARM_R])
    else {
        return map;
    };
    let chain = path_to(joints, head);
    let Some(h) = chain.iter().position(|&u| u == hips) else { return map };
    let chain = &chain[h..]; // Hips … Head
    let (pl, pr) = (path_to(joints, al), path_to(joints, ar));
    let branch = pl.iter().zip(&pr).take_while(|(a, b)| a == b).map(|(a, _)| *a).last();
    let Some(mut k) = branch.and_then(|b| chain.iter().position(|&u| u == b)) else { return map };
    if k + 1 >= chain.len() {
        return map; // the arms branch from the Head
    }
    if map[NECK] == Some(chain[k]) && k >= 2 {
        k -= 1;
    }
    if k == 0 {
        return map; // the arms hang from the Hips: leave the names' guess
    }
    map[CHEST] = Some(chain[k]);
    map[SPINE] = (k >= 2).then(|| chain[k - 1]);
    if map[NECK].is_none_or(|n| !chain[k + 1..chain.len() - 1].contains(&n)) {
        map[NECK] = (k + 2 < chain.len()).then(|| chain[k + 1]);
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
pub(super) fn validate(joints: &[BvhJoint], mut map: JointMap) -> JointMap {
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
        assert_eq!(normalise("CC_Base_L_Thigh"), "ccbaselthigh");
        assert_eq!(normalise("Bip01_L_Thigh"), "lthigh");
        assert_eq!(normalise("Bip001_Spine1"), "spine1");
        assert_eq!(normalise("Bip01"), "bip01");
        assert_eq!(normalise("Character1:Left-Up_Leg"), "leftupleg");
        assert_eq!(normalise("spine_01"), normalise("Spine01"));
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
        assert_eq!(d.rig, "smpl");
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
        // The collars hang from spine3: the chest, from the structure.
        assert_eq!(name(CHEST), Some("spine3"));
        assert_eq!(name(SPINE), Some("spine2"));
        assert_eq!(name(NECK), Some("neck"));
        // The generic matcher alone reads the same names.
        let g = validate(&j, match_generic(&j));
        assert_eq!(g[HAND_R].map(|u| j[u].name.as_str()), Some("right_wrist"));
        assert_eq!(g[TOES_L].map(|u| j[u].name.as_str()), Some("left_foot"));
    }

    #[test]
    fn structure_sets_spine_and_chest() {
        // Biped: clavicles under the neck; the chest is the spine joint below it.
        let j = rig(&[
            ("Bip01", None),
            ("Bip01_Pelvis", Some(0)),
            ("Bip01_Spine", Some(1)),
            ("Bip01_L_Thigh", Some(2)),
            ("Bip01_L_Calf", Some(3)),
            ("Bip01_L_Foot", Some(4)),
            ("Bip01_R_Thigh", Some(2)),
            ("Bip01_R_Calf", Some(6)),
            ("Bip01_R_Foot", Some(7)),
            ("Bip01_Spine1", Some(2)),
            ("Bip01_Spine2", Some(9)),
            ("Bip01_Spine3", Some(10)),
            ("Bip01_Neck", Some(11)),
            ("Bip01_Head", Some(12)),
            ("Bip01_L_Clavicle", Some(12)),
            ("Bip01_L_UpperArm", Some(14)),
            ("Bip01_L_Forearm", Some(15)),
            ("Bip01_L_Hand", Some(16)),
            ("Bip01_R_Clavicle", Some(12)),
            ("Bip01_R_UpperArm", Some(18)),
            ("Bip01_R_Forearm", Some(19)),
            ("Bip01_R_Hand", Some(20)),
        ]);
        let d = detect(&j).unwrap();
        assert_eq!(d.rig, "biped");
        let name = |c: usize| d.map[c].map(|u| j[u].name.as_str());
        assert_eq!(
            (name(HIPS), name(SPINE), name(CHEST), name(NECK)),
            (Some("Bip01_Pelvis"), Some("Bip01_Spine2"), Some("Bip01_Spine3"), Some("Bip01_Neck"))
        );
        assert_eq!((name(UPPER_LEG_R), name(SHOULDER_L)), (Some("Bip01_R_Thigh"), Some("Bip01_L_Clavicle")));
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
