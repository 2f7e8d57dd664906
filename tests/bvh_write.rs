//! The BVH writer: parse → write → parse keeps every fixture's pose.
use glam::{DQuat, DVec3, EulerRot};
use motion_stylizer::Motion;
use motion_stylizer::bvh::{Axis, Bvh, BvhJoint, Channel};
use motion_stylizer::skeleton::canonical::NUM_JOINTS;
use std::path::{Path, PathBuf};

fn all_fixtures() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let mut files = Vec::new();
    for dir in ["bandai", "foreign"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "bvh") {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(files.len() >= 8, "fixtures missing");
    files
}

/// Largest distance between the world positions of same-named joints (and their End Sites), all frames.
fn max_world_error(a: &Bvh, b: &Bvh) -> f64 {
    assert_eq!(a.frames, b.frames);
    assert_eq!(a.joints.len(), b.joints.len());
    let mut worst: f64 = 0.0;
    for f in 0..a.frames {
        let (pa, ra) = a.global_pose(f);
        let (pb, rb) = b.global_pose(f);
        for (i, j) in a.joints.iter().enumerate() {
            let k = b.joint_index(&j.name).unwrap_or_else(|| panic!("{} lost", j.name));
            worst = worst.max((pa[i] - pb[k]).length());
            if let (Some(sa), Some(sb)) = (j.end_site, b.joints[k].end_site) {
                worst = worst.max(((pa[i] + ra[i] * sa) - (pb[k] + rb[k] * sb)).length());
            }
        }
    }
    worst
}

#[test]
fn round_trip_every_fixture() {
    for path in all_fixtures() {
        let name = path.display();
        let text = std::fs::read_to_string(&path).unwrap();
        let a = Bvh::parse(&text).unwrap();
        let written = a.to_bvh_string();
        let b = Bvh::parse(&written).unwrap_or_else(|e| panic!("{name}: our output does not parse: {e}"));

        assert_eq!(b.frames, a.frames, "{name}");
        assert_eq!(b.frame_time, a.frame_time, "{name}");
        // Numbers are written in shortest round-trip form: the values come back bit for bit.
        assert_eq!(b.values.len(), a.values.len());
        assert!(a.values.iter().zip(&b.values).all(|(x, y)| x.to_bits() == y.to_bits()), "{name}");
        for (ja, jb) in a.joints.iter().zip(&b.joints) {
            assert_eq!(
                (&ja.name, ja.parent, &ja.channels, ja.channel_offset, ja.end_site),
                (&jb.name, jb.parent, &jb.channels, jb.channel_offset, jb.end_site),
                "{name}"
            );
            // OFFSET components replaced by a position channel are written as 0.
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                let want = if ja.channels.contains(&Channel::Position(axis)) { 0.0 } else { ja.offset[axis.index()] };
                assert_eq!(jb.offset[axis.index()], want, "{name} {}", ja.name);
            }
        }
        let err = max_world_error(&a, &b);
        assert!(err <= 1e-4, "{name}: world positions differ by {err} cm");
        assert_eq!(err, 0.0, "{name}");
        // Writing is a fixed point after one round.
        assert_eq!(b.to_bvh_string(), written, "{name}");
    }
}

#[test]
fn standard_layout() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/foreign/cmu31_xia_neutral_16_000.bvh"),
    )
    .unwrap();
    let bvh = Bvh::parse(&text).unwrap();
    let out = bvh.to_bvh_string();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        &lines[..6],
        [
            "HIERARCHY",
            "ROOT Hips",
            "{",
            "\tOFFSET 0 0 0",
            "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation",
            "\tJOINT LHipJoint",
        ]
    );
    assert!(out.contains("\t\t\t\t\t\tEnd Site\n\t\t\t\t\t\t{\n\t\t\t\t\t\t\tOFFSET 0 0 0\n\t\t\t\t\t\t}\n"));
    let motion = lines.iter().position(|l| *l == "MOTION").unwrap();
    assert_eq!(lines[motion - 1], "}");
    assert_eq!(lines[motion + 1], "Frames: 150");
    assert_eq!(lines[motion + 2], "Frame Time: 0.008333");
    assert_eq!(lines.len(), motion + 3 + 150);
    assert!(lines[motion + 3].starts_with("19.939872 16.850014 1.430627 162.659769 "));
    assert!(out.ends_with('\n') && !out.ends_with("\n\n"));
    assert_eq!(out.matches('{').count(), out.matches('}').count());
}

fn joint(name: &str, parent: Option<usize>, offset: [f64; 3], channels: &[Channel], channel_offset: usize) -> BvhJoint {
    BvhJoint {
        name: name.into(),
        parent,
        offset: DVec3::from_array(offset),
        channels: channels.to_vec(),
        end_site: None,
        channel_offset,
    }
}

/// A hand-built `Bvh` whose joints are not in depth-first order, with leaves without End Sites and a
/// joint without channels: written depth-first with channels regrouped, same pose by name.
#[test]
fn any_joint_order_writes_the_same_pose() {
    use Channel::*;
    let rot = [Rotation(Axis::Y), Rotation(Axis::X), Rotation(Axis::Z)];
    let mut root = joint("root", None, [1.0, 2.0, 3.0], &[Position(Axis::Y), Rotation(Axis::Z)], 0);
    root.end_site = Some(DVec3::new(0.0, 0.0, 4.0));
    let joints = vec![
        root,
        joint("a", Some(0), [0.0, 5.0, 0.0], &rot, 2),
        joint("b", Some(0), [3.0, 0.0, 0.0], &[], 5),
        joint("a1", Some(1), [0.0, 7.0, 1.0], &rot, 5),
        joint("b1", Some(2), [2.0, 0.0, 0.0], &[Rotation(Axis::X)], 8),
    ];
    let frames = 3;
    let values: Vec<f64> = (0..frames * 9).map(|i| (i as f64 * 37.3).sin() * 90.0 + 0.1).collect();
    let a = Bvh { joints, frame_time: 1.0 / 24.0, frames, values };
    let out = a.to_bvh_string();
    let b = Bvh::parse(&out).unwrap();
    let names: Vec<&str> = b.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["root", "a", "a1", "b", "b1"]);
    assert_eq!(b.joints[0].offset.to_array(), [1.0, 0.0, 3.0]);
    assert_eq!(b.frame_time, 1.0 / 24.0);
    let err = max_world_error(&a, &b);
    assert!(err < 1e-12, "{err}");
}

/// The canonical-rig output of [`Motion::to_bvh`] (computed, full-precision values) survives the text.
#[test]
fn motion_to_bvh_round_trip() {
    let frames = 20;
    let root = (0..frames).map(|f| DVec3::new(f as f64 * 1.3, 90.0 + (f as f64).sin(), -2.0 * f as f64)).collect();
    let rotations = (0..frames)
        .map(|f| {
            std::array::from_fn(|j| {
                DQuat::from_euler(EulerRot::YXZ, 0.11 * j as f64 + 0.05 * f as f64, 0.3 - 0.02 * j as f64, 0.2)
            })
        })
        .collect::<Vec<[DQuat; NUM_JOINTS]>>();
    let m = Motion::new(root, rotations).unwrap();
    let a = m.to_bvh();
    let b = Bvh::parse(&a.to_bvh_string()).unwrap();
    assert_eq!(b.joints.len(), NUM_JOINTS);
    assert_eq!(b.frame_time, a.frame_time);
    let err = max_world_error(&a, &b);
    assert!(err <= 1e-4, "{err}");
    for f in 0..frames {
        let (want, _) = m.global_pose(f);
        let (got, _) = b.global_pose(f);
        for j in 0..NUM_JOINTS {
            assert!((want[j] - got[j]).length() < 1e-9);
        }
    }
}

#[test]
fn number_formatting() {
    let mut a = Bvh {
        joints: vec![joint("r", None, [0.0, -0.0, 1e-7], &[Channel::Rotation(Axis::X)], 0)],
        frame_time: 0.0333333,
        frames: 4,
        values: vec![90.0, -0.0, 1.5e-5, 123456789.125],
    };
    let out = a.to_bvh_string();
    assert!(out.contains("\tOFFSET 0 -0 1e-7\n"), "{out}");
    assert!(out.ends_with("MOTION\nFrames: 4\nFrame Time: 0.0333333\n90\n-0\n0.000015\n123456789.125\n"), "{out}");
    // Zero channels: no rows at all, and it reads back.
    a.joints[0].channels.clear();
    a.values.clear();
    let out = a.to_bvh_string();
    assert!(out.ends_with("Frame Time: 0.0333333\n"));
    assert_eq!(Bvh::parse(&out).unwrap().frames, 4);
}
