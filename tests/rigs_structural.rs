//! Any human rig in (issue 15): one small synthetic fixture per naming family
//! (`tests/fixtures/rigs/`, made from the m21 walk by [`regenerate_rig_fixtures`]), each matched,
//! retargeted and moving like its source; feet on the floor.

mod support;

use glam::{DQuat, DVec3};
use motion_stylizer::Motion;
use motion_stylizer::bvh::{Axis, Bvh, BvhJoint, Channel};
use motion_stylizer::skeleton::canonical::joint::*;
use motion_stylizer::skeleton::rotation::{decompose, swing};
use motion_stylizer::skeleton::{JOINT_NAMES, import, import_bvh};
use support::*;

// ---------------------------------------------------------------------------------------------
// The fixture generator: the m21 walk on another skeleton.

/// How a family's skeleton is made from the m21 rig (joint names as m21's unless renamed).
struct Spec {
    file: &'static str,
    /// m21 name → the family's name (joints not listed keep theirs).
    names: &'static [(&'static str, &'static str)],
    /// A new root above the Hips (carrying the translation), e.g. `Bip01`.
    root: Option<&'static str>,
    /// (new joint, child, t): a joint without motion of its own inserted between `child` (new name)
    /// and its parent, at fraction `t` of the way from the parent.
    inserts: &'static [(&'static str, &'static str, f64)],
    /// (joint, new parent), new names: the joint hangs elsewhere (its rest position kept).
    reparent: &'static [(&'static str, &'static str)],
    /// Joints spliced out (their children hang from their parent).
    splice: &'static [&'static str],
    /// Joints dropped with their descendants (m21 names).
    drop: &'static [&'static str],
    order: [Axis; 3],
    end_sites: bool,
    /// Every joint's frame turned so that its first child lies along its +X at rest (the rest pose
    /// is then no pose at all, as in Rokoko's and Bandai's files).
    along_x: bool,
    /// Z up instead of Y up.
    z_up: bool,
    /// File units per centimetre.
    scale: f64,
    frames: usize,
}

const BASE: Spec = Spec {
    file: "",
    names: &[],
    root: None,
    inserts: &[],
    reparent: &[],
    splice: &[],
    drop: &[],
    order: [Axis::Z, Axis::Y, Axis::X],
    end_sites: true,
    along_x: false,
    z_up: false,
    scale: 1.0,
    frames: 48,
};

struct Node {
    name: String,
    parent: Option<usize>,
    src: Option<usize>,
    x: DVec3,
}

/// The m21 walk (first `spec.frames` frames) on the skeleton `spec` describes.
fn rerig(spec: &Spec) -> Bvh {
    let full = fixture("foreign", "m21_walk");
    let src = drop_joints(&full, |n| spec.drop.contains(&n));
    let frames = spec.frames.min(src.frames);
    let rename = |n: &str| spec.names.iter().find(|(a, _)| *a == n).map(|(_, b)| b.to_string()).unwrap_or(n.into());
    // Rest positions of the source (zero rotations).
    let mut xs: Vec<DVec3> = Vec::new();
    for (u, j) in src.joints.iter().enumerate() {
        let t = src.local_transform(0, u).0;
        xs.push(j.parent.map_or(t, |p| xs[p] + t));
    }
    let mut nodes: Vec<Node> = src
        .joints
        .iter()
        .enumerate()
        .map(|(u, j)| Node { name: rename(&j.name), parent: j.parent, src: Some(u), x: xs[u] })
        .collect();
    let find = |nodes: &[Node], n: &str| nodes.iter().position(|x| x.name == n).unwrap_or_else(|| panic!("{n}"));
    if let Some(r) = spec.root {
        nodes.push(Node { name: r.into(), parent: None, src: None, x: xs[0] });
        let last = nodes.len() - 1;
        nodes[0].parent = Some(last);
    }
    for (name, child, t) in spec.inserts {
        let c = find(&nodes, child);
        let p = nodes[c].parent.expect("not the root");
        let x = nodes[p].x.lerp(nodes[c].x, *t);
        nodes.push(Node { name: name.to_string(), parent: Some(p), src: None, x });
        let last = nodes.len() - 1;
        nodes[c].parent = Some(last);
    }
    for (child, parent) in spec.reparent {
        let (c, p) = (find(&nodes, child), find(&nodes, parent));
        nodes[c].parent = Some(p);
    }
    for name in spec.splice {
        let s = find(&nodes, name);
        let p = nodes[s].parent;
        for n in nodes.iter_mut() {
            if n.parent == Some(s) {
                n.parent = p;
            }
        }
        nodes[s].parent = Some(usize::MAX); // detached
    }
    // Depth-first order.
    let root = nodes.iter().position(|n| n.parent.is_none()).unwrap();
    let mut order = Vec::new();
    let mut stack = vec![root];
    while let Some(n) = stack.pop() {
        order.push(n);
        let kids: Vec<usize> = (0..nodes.len()).filter(|&k| nodes[k].parent == Some(n)).collect();
        stack.extend(kids.into_iter().rev());
    }
    let new_index = |n: usize| order.iter().position(|&k| k == n).unwrap();
    // Frame changes.
    let q: Vec<DQuat> = order
        .iter()
        .map(|&n| {
            let child =
                order.iter().find(|&&k| nodes[k].parent == Some(n) && (nodes[k].x - nodes[n].x).length() > 1e-6);
            match child {
                Some(&c) if spec.along_x => swing(nodes[c].x - nodes[n].x, DVec3::X, DVec3::Z).unwrap(),
                _ => DQuat::IDENTITY,
            }
        })
        .collect();
    let mut joints = Vec::new();
    let mut offset = 0;
    for (i, &n) in order.iter().enumerate() {
        let parent = nodes[n].parent.map(new_index);
        let mut channels: Vec<Channel> = Vec::new();
        if parent.is_none() {
            channels.extend([Axis::X, Axis::Y, Axis::Z].map(Channel::Position));
        }
        channels.extend(spec.order.map(Channel::Rotation));
        let off = match parent {
            Some(p) => q[p] * (nodes[n].x - nodes[order[p]].x),
            None => nodes[n].x,
        };
        let leaf = !order.iter().any(|&k| nodes[k].parent == Some(n));
        let end_site = match nodes[n].src {
            Some(u) if spec.end_sites && leaf => src.joints[u].end_site.map(|e| q[i] * e),
            _ => None,
        };
        let nch = channels.len();
        joints.push(BvhJoint {
            name: nodes[n].name.clone(),
            parent,
            offset: off,
            channels,
            end_site,
            channel_offset: offset,
        });
        offset += nch;
    }
    let mut values = Vec::with_capacity(frames * offset);
    for f in 0..frames {
        let (pos, rot) = src.global_pose(f);
        // The global rotation of each new joint: its source joint's (frame changed), or its parent's.
        let mut g = vec![DQuat::IDENTITY; order.len()];
        for (i, &n) in order.iter().enumerate() {
            let truth = match (nodes[n].src, joints[i].parent) {
                (Some(u), _) => rot[u],
                (None, Some(p)) => g[p] * q[p],
                (None, None) => DQuat::IDENTITY,
            };
            g[i] = truth * q[i].inverse();
        }
        for (i, j) in joints.iter().enumerate() {
            let local = match j.parent {
                Some(p) => g[p].inverse() * g[i],
                None => g[i],
            };
            if j.parent.is_none() {
                values.extend_from_slice(&pos[0].to_array());
            }
            values.extend(decompose(local.normalize(), &spec.order));
        }
    }
    let mut bvh = Bvh { joints, frame_time: src.frame_time, frames, values };
    let world = if spec.z_up { DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2) } else { DQuat::IDENTITY };
    if spec.z_up || spec.scale != 1.0 {
        bvh = transform_world(&bvh, world, spec.scale);
    }
    // Five decimals (degrees, file units) keep the files small.
    for v in &mut bvh.values {
        *v = (*v * 1e5).round() / 1e5 + 0.0;
    }
    bvh
}

const SIDES: [(&str, &str); 2] = [("Left", "l"), ("Right", "r")];

fn sided(m21: &str) -> (&'static str, &'static str) {
    let i = if m21.starts_with("Left") { 0 } else { 1 };
    SIDES[i]
}

/// The families: (spec, expected scheme).
fn families() -> Vec<(Spec, &'static str)> {
    vec![
        (
            Spec {
                file: "daz_poser",
                names: &[
                    ("Hips", "hip"),
                    ("Spine", "abdomen"),
                    ("Spine1", "chest"),
                    ("Neck1", "neck"),
                    ("Head", "head"),
                    ("LeftShoulder", "lCollar"),
                    ("LeftArm", "lShldr"),
                    ("LeftForeArm", "lForeArm"),
                    ("LeftHand", "lHand"),
                    ("RightShoulder", "rCollar"),
                    ("RightArm", "rShldr"),
                    ("RightForeArm", "rForeArm"),
                    ("RightHand", "rHand"),
                    ("LeftUpLeg", "lThigh"),
                    ("LeftLeg", "lShin"),
                    ("LeftFoot", "lFoot"),
                    ("LeftToeBase", "lToe"),
                    ("RightUpLeg", "rThigh"),
                    ("RightLeg", "rShin"),
                    ("RightFoot", "rFoot"),
                    ("RightToeBase", "rToe"),
                ],
                inserts: &[("lButtock", "lThigh", 0.6), ("rButtock", "rThigh", 0.6)],
                order: [Axis::Z, Axis::X, Axis::Y],
                ..BASE
            },
            "daz_poser",
        ),
        (
            Spec {
                file: "second_life",
                names: &[
                    ("Hips", "mPelvis"),
                    ("Spine", "mTorso"),
                    ("Spine1", "mChest"),
                    ("Neck1", "mNeck"),
                    ("Head", "mHead"),
                    ("LeftShoulder", "mCollarLeft"),
                    ("LeftArm", "mShoulderLeft"),
                    ("LeftForeArm", "mElbowLeft"),
                    ("LeftHand", "mWristLeft"),
                    ("RightShoulder", "mCollarRight"),
                    ("RightArm", "mShoulderRight"),
                    ("RightForeArm", "mElbowRight"),
                    ("RightHand", "mWristRight"),
                    ("LeftUpLeg", "mHipLeft"),
                    ("LeftLeg", "mKneeLeft"),
                    ("LeftFoot", "mAnkleLeft"),
                    ("LeftToeBase", "mFootLeft"),
                    ("RightUpLeg", "mHipRight"),
                    ("RightLeg", "mKneeRight"),
                    ("RightFoot", "mAnkleRight"),
                    ("RightToeBase", "mFootRight"),
                ],
                order: [Axis::X, Axis::Z, Axis::Y],
                ..BASE
            },
            "second_life",
        ),
        (Spec { file: "acclaim_zup", ..acclaim(None) }, "acclaim"),
        (Spec { file: "acclaim_zup_root", ..acclaim(Some("root")) }, "acclaim"),
        (
            Spec {
                file: "humanik",
                names: &[
                    ("Hips", "Character1:Hips"),
                    ("Spine", "Character1:Spine"),
                    ("Spine1", "Character1:Spine3"),
                    ("Neck1", "Character1:Neck"),
                    ("Head", "Character1:Head"),
                    ("LeftShoulder", "Character1:LeftShoulder"),
                    ("LeftArm", "Character1:LeftArm"),
                    ("LeftForeArm", "Character1:LeftForeArm"),
                    ("LeftHand", "Character1:LeftHand"),
                    ("RightShoulder", "Character1:RightShoulder"),
                    ("RightArm", "Character1:RightArm"),
                    ("RightForeArm", "Character1:RightForeArm"),
                    ("RightHand", "Character1:RightHand"),
                    ("LeftUpLeg", "Character1:LeftUpLeg"),
                    ("LeftLeg", "Character1:LeftLeg"),
                    ("LeftFoot", "Character1:LeftFoot"),
                    ("LeftToeBase", "Character1:LeftToeBase"),
                    ("RightUpLeg", "Character1:RightUpLeg"),
                    ("RightLeg", "Character1:RightLeg"),
                    ("RightFoot", "Character1:RightFoot"),
                    ("RightToeBase", "Character1:RightToeBase"),
                ],
                inserts: &[
                    ("Character1:Spine1", "Character1:Spine3", 0.33),
                    ("Character1:Spine2", "Character1:Spine3", 0.5),
                    ("Character1:LeftArmRoll", "Character1:LeftForeArm", 0.5),
                    ("Character1:RightArmRoll", "Character1:RightForeArm", 0.5),
                    ("Character1:LeftUpLegRoll", "Character1:LeftLeg", 0.5),
                    ("Character1:RightUpLegRoll", "Character1:RightLeg", 0.5),
                ],
                ..BASE
            },
            "humanik",
        ),
        (
            Spec {
                file: "rokoko",
                names: &[
                    ("Spine", "Spine1"),
                    ("Spine1", "Spine4"),
                    ("Neck1", "Neck"),
                    ("LeftUpLeg", "LeftThigh"),
                    ("LeftLeg", "LeftShin"),
                    ("LeftToeBase", "LeftToe"),
                    ("RightUpLeg", "RightThigh"),
                    ("RightLeg", "RightShin"),
                    ("RightToeBase", "RightToe"),
                ],
                inserts: &[("Spine2", "Spine4", 0.33), ("Spine3", "Spine4", 0.5)],
                along_x: true,
                order: [Axis::Y, Axis::X, Axis::Z],
                ..BASE
            },
            "humanik",
        ),
        (
            Spec {
                file: "biped",
                names: &[
                    ("Hips", "Bip01_Pelvis"),
                    ("Spine", "Bip01_Spine"),
                    ("Spine1", "Bip01_Spine1"),
                    ("Neck1", "Bip01_Neck"),
                    ("Head", "Bip01_Head"),
                    ("LeftShoulder", "Bip01_L_Clavicle"),
                    ("LeftArm", "Bip01_L_UpperArm"),
                    ("LeftForeArm", "Bip01_L_Forearm"),
                    ("LeftHand", "Bip01_L_Hand"),
                    ("RightShoulder", "Bip01_R_Clavicle"),
                    ("RightArm", "Bip01_R_UpperArm"),
                    ("RightForeArm", "Bip01_R_Forearm"),
                    ("RightHand", "Bip01_R_Hand"),
                    ("LeftUpLeg", "Bip01_L_Thigh"),
                    ("LeftLeg", "Bip01_L_Calf"),
                    ("LeftFoot", "Bip01_L_Foot"),
                    ("LeftToeBase", "Bip01_L_Toe0"),
                    ("RightUpLeg", "Bip01_R_Thigh"),
                    ("RightLeg", "Bip01_R_Calf"),
                    ("RightFoot", "Bip01_R_Foot"),
                    ("RightToeBase", "Bip01_R_Toe0"),
                ],
                root: Some("Bip01"),
                // The clavicles hang from the neck; the thighs from the pelvis ("triangle pelvis").
                reparent: &[("Bip01_L_Clavicle", "Bip01_Neck"), ("Bip01_R_Clavicle", "Bip01_Neck")],
                order: [Axis::Y, Axis::Z, Axis::X],
                z_up: true,
                scale: 1.0 / 2.54,
                ..BASE
            },
            "biped",
        ),
        (
            Spec {
                file: "smpl",
                names: &[
                    ("Hips", "Pelvis"),
                    ("Spine", "Spine1"),
                    ("Spine1", "Spine3"),
                    ("Neck1", "Neck"),
                    ("LeftShoulder", "L_Collar"),
                    ("LeftArm", "L_Shoulder"),
                    ("LeftForeArm", "L_Elbow"),
                    ("LeftHand", "L_Wrist"),
                    ("RightShoulder", "R_Collar"),
                    ("RightArm", "R_Shoulder"),
                    ("RightForeArm", "R_Elbow"),
                    ("RightHand", "R_Wrist"),
                    ("LeftUpLeg", "L_Hip"),
                    ("LeftLeg", "L_Knee"),
                    ("LeftFoot", "L_Ankle"),
                    ("LeftToeBase", "L_Foot"),
                    ("RightUpLeg", "R_Hip"),
                    ("RightLeg", "R_Knee"),
                    ("RightFoot", "R_Ankle"),
                    ("RightToeBase", "R_Foot"),
                ],
                inserts: &[("Spine2", "Spine3", 0.5)],
                order: [Axis::X, Axis::Y, Axis::Z],
                scale: 0.01,
                ..BASE
            },
            "smpl",
        ),
        (
            Spec {
                file: "unreal",
                names: &[
                    ("Hips", "pelvis"),
                    ("Spine", "spine_01"),
                    ("Spine1", "spine_03"),
                    ("Neck1", "neck_01"),
                    ("Head", "head"),
                    ("LeftShoulder", "clavicle_l"),
                    ("LeftArm", "upperarm_l"),
                    ("LeftForeArm", "lowerarm_l"),
                    ("LeftHand", "hand_l"),
                    ("RightShoulder", "clavicle_r"),
                    ("RightArm", "upperarm_r"),
                    ("RightForeArm", "lowerarm_r"),
                    ("RightHand", "hand_r"),
                    ("LeftUpLeg", "thigh_l"),
                    ("LeftLeg", "calf_l"),
                    ("LeftFoot", "foot_l"),
                    ("LeftToeBase", "ball_l"),
                    ("RightUpLeg", "thigh_r"),
                    ("RightLeg", "calf_r"),
                    ("RightFoot", "foot_r"),
                    ("RightToeBase", "ball_r"),
                ],
                root: Some("root"),
                inserts: &[("spine_02", "spine_03", 0.5)],
                z_up: true,
                ..BASE
            },
            "unreal",
        ),
    ]
}

/// Acclaim ASF names, Z up, no End Sites; `root` above the pelvis or not.
fn acclaim(root: Option<&'static str>) -> Spec {
    Spec {
        names: &[
            ("Hips", "pelvis"),
            ("Spine", "lowerback"),
            ("Spine1", "thorax"),
            ("Neck1", "lowerneck"),
            ("Head", "head"),
            ("LeftShoulder", "lclavicle"),
            ("LeftArm", "lhumerus"),
            ("LeftForeArm", "lradius"),
            ("LeftHand", "lhand"),
            ("RightShoulder", "rclavicle"),
            ("RightArm", "rhumerus"),
            ("RightForeArm", "rradius"),
            ("RightHand", "rhand"),
            ("LeftUpLeg", "lfemur"),
            ("LeftLeg", "ltibia"),
            ("LeftFoot", "lfoot"),
            ("LeftToeBase", "ltoes"),
            ("RightUpLeg", "rfemur"),
            ("RightLeg", "rtibia"),
            ("RightFoot", "rfoot"),
            ("RightToeBase", "rtoes"),
        ],
        root,
        inserts: &[
            ("lhipjoint", "lfemur", 0.7),
            ("rhipjoint", "rfemur", 0.7),
            ("upperback", "thorax", 0.5),
            ("upperneck", "head", 0.5),
        ],
        end_sites: false,
        z_up: true,
        ..BASE
    }
}

fn rigs_dir() -> String {
    format!("{}/tests/fixtures/rigs", env!("CARGO_MANIFEST_DIR"))
}

fn rig_fixture(name: &str) -> (String, Bvh) {
    let path = format!("{}/{name}.bvh", rigs_dir());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e} (regenerate_rig_fixtures)"));
    let bvh = Bvh::parse(&text).unwrap();
    (text, bvh)
}

fn all_specs() -> Vec<Spec> {
    families().into_iter().map(|(s, _)| s).chain(extra_specs()).collect()
}

/// Writes `tests/fixtures/rigs/*.bvh`: `cargo test --release --test rigs_structural -- --ignored`.
#[test]
#[ignore]
fn regenerate_rig_fixtures() {
    std::fs::create_dir_all(rigs_dir()).unwrap();
    for spec in &all_specs() {
        let bvh = rerig(spec);
        std::fs::write(format!("{}/{}.bvh", rigs_dir(), spec.file), bvh.to_bvh_string()).unwrap();
    }
    std::fs::write(format!("{}/quadruped_bip01.bvh", rigs_dir()), quadruped().to_bvh_string()).unwrap();
}

/// The generated files are what the generator makes now.
#[test]
fn fixtures_are_up_to_date() {
    for spec in &all_specs() {
        let (_, bvh) = rig_fixture(spec.file);
        let made = rerig(spec);
        assert_eq!(bvh.joints.len(), made.joints.len(), "{}", spec.file);
        assert_eq!(bvh.frames, made.frames);
        let same = bvh.values.iter().zip(&made.values).all(|(a, b)| (a - b).abs() < 1e-9 * (1.0 + b.abs()));
        assert!(same, "{}: rerun regenerate_rig_fixtures", spec.file);
    }
    let (file, made) = (rig_fixture("quadruped_bip01").1, quadruped());
    assert!(file.values == made.values && file.global_pose(3) == made.global_pose(3), "quadruped_bip01: regenerate");
}

/// Fixtures of the other points: joints missing, a rest pose along +X.
fn extra_specs() -> Vec<Spec> {
    vec![
        // Video-to-BVH: CMU-like names, no head, millimetres.
        Spec { file: "video_nohead_mm", drop: &["Head"], scale: 10.0, ..BASE },
        // No chest and no neck: the arms and the head hang from the spine.
        Spec { file: "no_chest_neck", splice: &["Spine1", "Neck1"], ..BASE },
        // No spine joint at all and no toes: arms and head on the hips.
        Spec { file: "no_spine_toes", splice: &["Spine", "Spine1"], drop: &["LeftToeBase", "RightToeBase"], ..BASE },
    ]
}

/// A quadruped under 3ds Max Biped names (an elephant-like body, Y up, facing +Z): the spine runs
/// forward, the "arms" are front legs standing on the floor. Its legs swing a little over 10 frames.
fn quadruped() -> Bvh {
    let j = |name: &str, parent: Option<usize>, o: [f64; 3]| BvhJoint {
        name: name.into(),
        parent,
        offset: DVec3::from_array(o),
        channels: if parent.is_none() {
            vec![
                Channel::Position(Axis::X),
                Channel::Position(Axis::Y),
                Channel::Position(Axis::Z),
                Channel::Rotation(Axis::Z),
                Channel::Rotation(Axis::X),
                Channel::Rotation(Axis::Y),
            ]
        } else {
            vec![Channel::Rotation(Axis::Z), Channel::Rotation(Axis::X), Channel::Rotation(Axis::Y)]
        },
        end_site: None,
        channel_offset: 0,
    };
    let mut joints = vec![
        j("Bip01", None, [0.0, 180.0, 0.0]),
        j("Bip01_Pelvis", Some(0), [0.0, 0.0, 0.0]),
        j("Bip01_Spine", Some(1), [0.0, 5.0, 40.0]),
        j("Bip01_Spine1", Some(2), [0.0, 0.0, 60.0]),
        j("Bip01_Neck", Some(3), [0.0, 10.0, 50.0]),
        j("Bip01_Head", Some(4), [0.0, 10.0, 40.0]),
        j("Bip01_L_Clavicle", Some(3), [25.0, -10.0, 30.0]),
        j("Bip01_L_UpperArm", Some(6), [5.0, -20.0, 0.0]),
        j("Bip01_L_Forearm", Some(7), [0.0, -70.0, 0.0]),
        j("Bip01_L_Hand", Some(8), [0.0, -70.0, 0.0]),
        j("Bip01_R_Clavicle", Some(3), [-25.0, -10.0, 30.0]),
        j("Bip01_R_UpperArm", Some(10), [-5.0, -20.0, 0.0]),
        j("Bip01_R_Forearm", Some(11), [0.0, -70.0, 0.0]),
        j("Bip01_R_Hand", Some(12), [0.0, -70.0, 0.0]),
        j("Bip01_L_Thigh", Some(1), [28.0, -15.0, -10.0]),
        j("Bip01_L_Calf", Some(14), [0.0, -75.0, 0.0]),
        j("Bip01_L_Foot", Some(15), [0.0, -80.0, 0.0]),
        j("Bip01_R_Thigh", Some(1), [-28.0, -15.0, -10.0]),
        j("Bip01_R_Calf", Some(17), [0.0, -75.0, 0.0]),
        j("Bip01_R_Foot", Some(18), [0.0, -80.0, 0.0]),
    ];
    let mut off = 0;
    for jt in &mut joints {
        jt.channel_offset = off;
        off += jt.channels.len();
    }
    let frames = 10;
    let mut values = Vec::new();
    for f in 0..frames {
        let swing = 15.0 * (f as f64 * 0.6).sin();
        for (u, jt) in joints.iter().enumerate() {
            if jt.parent.is_none() {
                values.extend([0.0, 180.0, 3.0 * f as f64]);
            }
            // Z, X, Y rotations: legs swing about X, opposite pairs in phase.
            let x = match jt.name.as_str() {
                "Bip01_L_UpperArm" | "Bip01_R_Thigh" => swing,
                "Bip01_R_UpperArm" | "Bip01_L_Thigh" => -swing,
                _ => 0.0,
            };
            let _ = u;
            values.extend([0.0, x, 0.0]);
        }
    }
    Bvh { joints, frame_time: 1.0 / 30.0, frames, values }
}

// ---------------------------------------------------------------------------------------------
// Checks.

/// The effector correlations of m21's own import of the frames the fixtures hold: what a faithful
/// retarget of this clip reaches (the canonical rig's proportions are not m21's).
fn reference_correlations() -> Vec<(String, f64, f64)> {
    let m21 = fixture("foreign", "m21_walk");
    let cut = Bvh { values: m21.values[..48 * m21.num_channels()].to_vec(), frames: 48, ..m21 };
    let imp = import(&cut).unwrap();
    effector_correlations(&cut, &imp.rig, &imp.motion)
}

/// The imported motion moves like the source (effector distance series: every pair that moves
/// correlates within `slack` of m21's own import, and at least 0.9 on average), stands on the floor
/// and is upright.
fn assert_faithful(bvh: &Bvh, name: &str, slack: f64) {
    let imp = import(bvh).unwrap_or_else(|e| panic!("{name}: {e}"));
    let r = effector_correlations(bvh, &imp.rig, &imp.motion);
    let reference = reference_correlations();
    let mut moving = Vec::new();
    for ((pair, c, std), (_, c0, _)) in r.iter().zip(&reference) {
        if *std >= 0.01 {
            assert!(*c > c0 - slack, "{name}: {pair} r = {c:.3} (m21: {c0:.3}, std {std:.3})");
            moving.push(*c);
        }
    }
    let mean = moving.iter().sum::<f64>() / moving.len() as f64;
    assert!(moving.len() >= 6 && mean > 0.9, "{name}: mean r {mean:.3} over {} pairs", moving.len());
    assert_on_floor_and_upright(&imp.motion, name);
}

fn assert_on_floor_and_upright(m: &Motion, name: &str) {
    let pos = m.global_positions();
    let mut lows: Vec<f64> = pos
        .iter()
        .map(|p| [FOOT_L, TOES_L, FOOT_R, TOES_R].map(|j| p[j].y).into_iter().fold(f64::INFINITY, f64::min))
        .collect();
    lows.sort_by(f64::total_cmp);
    let p5 = lows[lows.len() / 20];
    assert!(p5.abs() < 3.0, "{name}: the feet's 5th percentile is {p5:.2} cm off the floor");
    for (f, p) in pos.iter().enumerate() {
        assert!(p[HEAD].y - p[HIPS].y > 40.0, "{name} frame {f}: the head is not above the hips");
        assert!(p[HIPS].y > 60.0 && p[HIPS].y < 120.0, "{name} frame {f}: hips at {:.1} cm", p[HIPS].y);
    }
}

#[test]
fn every_family_is_matched_by_name_and_moves_like_its_source() {
    for (spec, scheme) in families() {
        let (text, bvh) = rig_fixture(spec.file);
        let imp = import_bvh(&text).unwrap_or_else(|e| panic!("{}: {e}", spec.file));
        let report = imp.rig.report();
        assert_eq!(report.rig, scheme, "{}", spec.file);
        assert_eq!(report.matched.len(), 21, "{}: missing {:?}", spec.file, report.missing);
        assert_eq!(report.up_axis, if spec.z_up { "+Z" } else { "+Y" }, "{}", spec.file);
        assert_faithful(&bvh, spec.file, 0.05);
    }
}

/// Where the names leave a choice, the structure decides: the chest is where the arms branch off.
#[test]
fn spine_and_chest_follow_the_structure() {
    let expect = [
        ("humanik", "Character1:Spine2", "Character1:Spine3", "Character1:Neck"),
        ("rokoko", "Spine3", "Spine4", "Neck"),
        ("biped", "Bip01_Spine", "Bip01_Spine1", "Bip01_Neck"),
        ("smpl", "Spine2", "Spine3", "Neck"),
        ("unreal", "spine_02", "spine_03", "neck_01"),
        ("acclaim_zup", "upperback", "thorax", "upperneck"),
    ];
    for (file, spine, chest, neck) in expect {
        let (_, bvh) = rig_fixture(file);
        let imp = import(&bvh).unwrap_or_else(|e| panic!("{file}: {e}"));
        let m = &imp.rig.report().matched;
        let get = |c: &str| m.iter().find(|(k, _)| k == c).map(|(_, v)| v.as_str());
        assert_eq!((get("Spine"), get("Chest"), get("Neck")), (Some(spine), Some(chest), Some(neck)), "{file}");
    }
    // Acclaim: the hips are the pelvis, with or without a root above it.
    for file in ["acclaim_zup", "acclaim_zup_root"] {
        let imp = import(&rig_fixture(file).1).unwrap();
        assert_eq!(imp.rig.report().matched[0], ("Hips".to_string(), "pelvis".to_string()));
    }
}

/// Renamed families that keep m21's geometry retarget to nearly m21's own canonical motion.
#[test]
fn renamed_families_retarget_like_the_original() {
    let m21 = fixture("foreign", "m21_walk");
    let cut = Bvh { values: m21.values[..48 * m21.num_channels()].to_vec(), frames: 48, ..m21.clone() };
    let original = import(&cut).unwrap().motion;
    for file in ["daz_poser", "second_life"] {
        let imp = import(&rig_fixture(file).1).unwrap();
        let e = max_position_error(&original, &imp.motion);
        assert!(e < 1e-3, "{file}: {e:e} cm from m21's own import (the files keep five decimals)");
    }
}

/// Pearson correlations of the distance series of hands and feet (the head may be missing): source
/// joints against the canonical motion.
fn limb_correlations(bvh: &Bvh, imp: &motion_stylizer::skeleton::Imported) -> Vec<(f64, f64)> {
    let ends = [HAND_L, HAND_R, FOOT_L, FOOT_R];
    let map = imp.rig.joint_map();
    let fps = motion_stylizer::skeleton::resample::source_fps(bvh.frame_time);
    let can = imp.motion.global_positions();
    let src: Vec<Vec<DVec3>> = (0..can.len())
        .map(|k| {
            let i = ((k as f64 * fps / 30.0).round() as usize).min(bvh.frames - 1);
            let pos = bvh.global_pose(i).0;
            ends.iter().map(|&e| pos[map[e].unwrap()]).collect()
        })
        .collect();
    let mut out = Vec::new();
    for a in 0..4 {
        for b in a + 1..4 {
            let x: Vec<f64> = src.iter().map(|p| (p[a] - p[b]).length()).collect();
            let y: Vec<f64> = can.iter().map(|p| (p[ends[a]] - p[ends[b]]).length()).collect();
            let scale = x.iter().sum::<f64>() / x.len() as f64;
            out.push((pearson(&x, &y), std_dev(&x) / scale));
        }
    }
    out
}

/// Point 3: non-essential joints missing are synthesised, and the motion still moves like its source.
#[test]
fn missing_non_essential_joints_are_synthesised() {
    let cases: [(&str, &[&str]); 3] = [
        ("video_nohead_mm", &["Head"]),
        ("no_chest_neck", &["Chest", "Neck"]),
        ("no_spine_toes", &["Spine", "Chest", "Toes_L", "Toes_R"]),
    ];
    // m21's own joints (the daz_poser fixture is m21 renamed): what these pairs reach.
    let daz = rig_fixture("daz_poser").1;
    let reference = limb_correlations(&daz, &import(&daz).unwrap());
    for (file, missing) in cases {
        let (text, bvh) = rig_fixture(file);
        let imp = import_bvh(&text).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(imp.rig.report().missing, missing, "{file}");
        let synth: Vec<&str> = imp.rig.synthesised().iter().map(|(j, _)| j.as_str()).collect();
        assert_eq!(synth, missing, "{file}");
        assert!(imp.rig.notes().iter().any(|n| n.contains("synthesised")), "{file}: {:?}", imp.rig.notes());
        // Synthesised joints turn with their parents.
        for pose in imp.motion.rotations() {
            for m in missing {
                let j = JOINT_NAMES.iter().position(|n| n == m).unwrap();
                assert!(pose[j].dot(DQuat::IDENTITY).abs() > 1.0 - 1e-12, "{file}: {m}");
            }
        }
        for ((r, std), (r0, _)) in limb_correlations(&bvh, &imp).into_iter().zip(&reference) {
            assert!(std < 0.02 || r > r0 - 0.05, "{file}: r = {r:.3} (m21: {r0:.3}, std {std:.3})");
        }
        assert_on_floor_and_upright(&imp.motion, file);
        // And back onto the rig.
        let back = imp.rig.from_canonical(&imp.motion);
        let again = imp.rig.to_canonical(&back).unwrap();
        assert!(max_position_error(&imp.motion, &again) < 1e-6, "{file}: round trip");
    }
    // Millimetres: the scale converts them.
    let imp = import(&rig_fixture("video_nohead_mm").1).unwrap();
    assert!(
        (imp.rig.report().scale - 0.1 * import(&rig_fixture("daz_poser").1).unwrap().rig.report().scale).abs() < 1e-6
    );
    let _ = sided("Left");
}

/// Point 2: a rest pose that is no pose (every bone along its parent's +X) gives way to a frame of
/// the motion, and the report says so.
#[test]
fn unusable_rest_pose_is_taken_from_the_motion() {
    let (_, bvh) = rig_fixture("rokoko");
    let imp = import(&bvh).unwrap();
    let r = imp.rig.report();
    assert!(r.base_pose.starts_with("frame "), "{}", r.base_pose);
    assert!(imp.rig.notes().iter().any(|n| n.contains("rest pose") && n.contains("frame")), "{:?}", imp.rig.notes());
    assert_eq!(r.up_axis, "+Y");
    // The same motion as the rig whose rest pose is a T-pose (the humanik fixture's joints but
    // the spine inserts), within the difference of reference poses.
    assert_faithful(&bvh, "rokoko", 0.05);
}

/// Point 4: non-humans are refused with their error.
#[test]
fn non_humans_are_refused() {
    let (text, _) = rig_fixture("quadruped_bip01");
    let err = import_bvh(&text).unwrap_err();
    assert_eq!(err.code(), "NOT_HUMAN", "{err}");
    assert!(err.to_string().contains("quadruped"), "{err}");
    // A single chain, with human names or none.
    let chain = |names: &[&str]| {
        let mut s = String::from("HIERARCHY\n");
        for (k, n) in names.iter().enumerate() {
            let kw = if k == 0 { "ROOT" } else { "JOINT" };
            let ch = if k == 0 {
                "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
            } else {
                "CHANNELS 3 Zrotation Xrotation Yrotation"
            };
            s += &format!("{kw} {n}\n{{\nOFFSET 0 10 0\n{ch}\n");
        }
        s += "End Site\n{\nOFFSET 0 10 0\n}\n";
        s += &"}\n".repeat(names.len());
        let nch = 6 + 3 * (names.len() - 1);
        s += &format!(
            "MOTION\nFrames: 2\nFrame Time: 0.0333333\n{}\n{}\n",
            vec!["0"; nch].join(" "),
            vec!["1"; nch].join(" ")
        );
        s
    };
    for names in [&["Hips", "Spine", "Chest", "Neck", "Head"][..], &["Bone0", "Bone1", "Bone2", "Bone3"]] {
        let err = import_bvh(&chain(names)).unwrap_err();
        assert_eq!(err.code(), "NOT_HUMAN", "{names:?}: {err}");
    }
    // A file of two joints is no skeleton to judge: its error names the joints it lacks.
    let small = std::fs::read_to_string(format!("{}/tests/fixtures/small.bvh", env!("CARGO_MANIFEST_DIR"))).unwrap();
    assert_eq!(import_bvh(&small).unwrap_err().code(), "RIG_UNMATCHED");
    // Legs pointing up from the hips in every frame.
    let m21 = fixture("foreign", "m21_walk");
    let mut upside = m21.clone();
    for j in &mut upside.joints {
        if ["LeftUpLeg", "RightUpLeg", "LeftLeg", "RightLeg", "LeftFoot", "RightFoot"].contains(&j.name.as_str()) {
            j.offset.y = -j.offset.y;
        }
    }
    let upside = relayout(&upside, |j| j.channels.clone());
    let flipped = Bvh { values: upside.values.iter().zip(&m21.values).map(|(_, b)| *b).collect(), ..upside };
    let err = import(&flipped).unwrap_err();
    assert_eq!(err.code(), "NOT_HUMAN", "{err}");
    // A body with nonsense names and one arm missing: no scheme and no structure; the error names
    // what the closest scheme lacks.
    let one_armed = anonymise(&drop_joints(&m21, |n| n == "LeftArm"));
    let err = import(&one_armed).unwrap_err();
    assert_eq!(err.code(), "RIG_UNMATCHED", "{err}");
    assert!(err.to_string().contains("Hips"), "{err}");
}

/// Every joint renamed `j0`, `j1`, …: only the structure is left.
fn anonymise(bvh: &Bvh) -> Bvh {
    let mut out = bvh.clone();
    for (k, j) in out.joints.iter_mut().enumerate() {
        j.name = format!("j{k}");
    }
    out
}

/// Point 1, structure: the same skeletons with meaningless names are matched from their topology
/// and geometry, the same joints as by name (so the same motion), twist/roll bones and hip links
/// skipped, the arms hanging from the neck (Biped), Z up, a rest pose along +X (Bandai).
#[test]
fn structure_alone_matches_the_same_joints() {
    let m21 = fixture("foreign", "m21_walk");
    let cases: Vec<(&str, Bvh)> = vec![
        ("m21", m21.clone()),
        ("cmu31", fixture("foreign", "cmu31_xia_neutral_16_000")),
        ("humanik", rig_fixture("humanik").1),
        ("acclaim_zup_root", rig_fixture("acclaim_zup_root").1),
        ("biped", rig_fixture("biped").1),
        ("daz_poser", rig_fixture("daz_poser").1),
        ("unreal", rig_fixture("unreal").1),
        ("bandai", fixture("bandai", "dataset-2_walk_normal_001_f120")),
    ];
    for (name, bvh) in cases {
        let by_name = import(&bvh).unwrap();
        let anon = anonymise(&bvh);
        let imp = import(&anon).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(imp.rig.report().rig, "structural", "{name}");
        let essential = [
            HIPS,
            UPPER_LEG_L,
            LOWER_LEG_L,
            FOOT_L,
            UPPER_LEG_R,
            LOWER_LEG_R,
            FOOT_R,
            UPPER_ARM_L,
            LOWER_ARM_L,
            HAND_L,
            UPPER_ARM_R,
            LOWER_ARM_R,
            HAND_R,
            HEAD,
        ];
        for j in essential {
            assert_eq!(imp.rig.joint_map()[j], by_name.rig.joint_map()[j], "{name}: {}", JOINT_NAMES[j]);
        }
        if name == "bandai" {
            // Bandai by name uses its base-pose table; by structure a frame of the clip.
            for (pair, r, std) in effector_correlations(&anon, &imp.rig, &imp.motion) {
                assert!(std < 0.01 || r > 0.95, "{name}: {pair} {r}");
            }
        } else if name != "cmu31" {
            assert_faithful(&anon, name, 0.05);
        }
        if ["m21", "daz_poser"].contains(&name) {
            assert!(max_position_error(&by_name.motion, &imp.motion) < 1e-6, "{name}");
        }
    }
}
