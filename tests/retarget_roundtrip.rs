//! Round trips: canonical → user rig → canonical (exact), user → canonical → user (exact where the
//! matched joints carry the motion), and the shape of what `from_canonical` writes.

mod support;

use motion_stylizer::bvh::Channel;
use motion_stylizer::skeleton::resample::source_fps;
use motion_stylizer::skeleton::{canonical_bvh, import};
use support::*;

/// Canonical motions used as inputs: a Bandai walk, and a CMU jump (airborne frames, deep squat).
fn canonical_inputs() -> Vec<(&'static str, motion_stylizer::Motion)> {
    vec![
        ("bandai walk", import(&fixture("bandai", "dataset-2_walk_normal_001_f120")).unwrap().motion),
        ("cmu jump", import(&fixture("foreign", "cmu31_xia_neutral_16_000")).unwrap().motion),
    ]
}

#[test]
fn canonical_to_every_rig_and_back_is_exact() {
    let inputs = canonical_inputs();
    for (dir, name) in all_fixtures() {
        let rig = import(&fixture(dir, name)).unwrap().rig;
        for (what, m) in &inputs {
            let user = rig.from_canonical(m);
            let back = rig.to_canonical(&user).unwrap();
            let e = max_position_error(m, &back);
            assert!(e < 1e-6, "{what} through {name}: {e:e} cm");
            for (a, b) in m.rotations().iter().flatten().zip(back.rotations().iter().flatten()) {
                assert!(a.dot(*b).abs() > 1.0 - 1e-12, "{what} through {name}: rotation differs");
            }
        }
    }
}

/// Matched-joint world positions after user → canonical → user, at the source's frames at the 30-fps
/// times (every fixture's rate is a multiple of 30, or it has one frame). Tolerances, user units:
/// 1e-9 where every joint between matched ones is matched or still (Bandai, m21, the CMU rest pose;
/// measured ≤ 1e-11). CMU-31's LHipJoint/RHipJoint, LowerBack and Neck and CC_Base's Waist and
/// NeckTwist01 move in these clips but have no canonical counterpart: they come back at rest, which
/// moves the joints after them by up to 0.73 units (3.6 cm) and 2.7 cm (measured).
#[test]
fn user_to_canonical_to_user_keeps_the_matched_joints() {
    let tolerance = |name: &str| match name {
        "cmu31_xia_neutral_16_000" => 0.8,
        "iclone100_cmu_002_04" => 3.0,
        _ => 1e-9,
    };
    for (dir, name) in all_fixtures() {
        let bvh = fixture(dir, name);
        let imp = import(&bvh).unwrap();
        let back = imp.rig.from_canonical(&imp.motion);
        let ratio = source_fps(bvh.frame_time) / 30.0;
        let mut e = 0.0f64;
        for k in 0..back.frames {
            let f = k as f64 * ratio;
            assert!(f.fract() == 0.0);
            let (a, _) = bvh.global_pose(f as usize);
            let (b, _) = back.global_pose(k);
            for u in imp.rig.joint_map().iter().flatten() {
                e = e.max((a[*u] - b[*u]).length());
            }
        }
        assert!(e <= tolerance(name), "{name}: {e:e}");
        eprintln!("{name}: user → canonical → user, matched joints within {e:.3e} user units");
    }
}

#[test]
fn from_canonical_writes_the_users_skeleton_at_30_fps() {
    let walk = canonical_inputs().remove(0).1;
    for (dir, name) in all_fixtures() {
        let bvh = fixture(dir, name);
        let rig = import(&bvh).unwrap().rig;
        let out = rig.from_canonical(&walk);
        assert_eq!(out.joints, bvh.joints, "{name}: same hierarchy, channels, offsets");
        assert_eq!(out.frames, walk.frames());
        assert!((out.frame_time - 1.0 / 30.0).abs() < 1e-15);
        assert_eq!(out.values.len(), out.frames * out.num_channels());
        assert!(out.values.iter().all(|v| v.is_finite()));
        // Position channels of joints other than the one carrying the Hips translation: constant, the
        // source's first-frame values (Bandai: its OFFSETs up to 2e-5).
        let carrier = if dir == "bandai" { "Hips" } else { bvh.joints[0].name.as_str() };
        for f in [0, out.frames - 1] {
            for (u, j) in out.joints.iter().enumerate() {
                for (k, c) in j.channels.iter().enumerate() {
                    if let Channel::Position(a) = c
                        && j.name != carrier
                    {
                        assert_eq!(
                            out.frame(f)[j.channel_offset + k],
                            bvh.frame(0)[j.channel_offset + k],
                            "{name} {u}"
                        );
                        assert!((out.frame(f)[j.channel_offset + k] - j.offset[a.index()]).abs() < 1e-4);
                    }
                }
            }
        }
    }
    // Bandai: joint_Root stays at rest; the Hips carry the motion.
    let rig = import(&fixture("bandai", "dataset-2_walk_normal_001_f120")).unwrap().rig;
    let out = rig.from_canonical(&walk);
    assert!(out.values.chunks(out.num_channels()).all(|row| row[..6].iter().all(|v| *v == 0.0)));
}

#[test]
fn canonical_bvh_is_the_motions_bvh() {
    let walk = canonical_inputs().remove(0).1;
    let b = canonical_bvh(&walk);
    assert_eq!(b, walk.to_bvh());
    // It imports as itself: Bandai names, but a usable (T-pose) rest pose, so no Bandai table.
    let back = import(&b).unwrap();
    assert_eq!(back.rig.report().base_pose, "rest");
    assert!((back.rig.report().scale - 1.0).abs() < 1e-12);
    let e = max_position_error(&walk, &back.motion);
    assert!(e < 1e-9, "{e:e}");
}

/// What `from_canonical` writes survives BVH text (whose writer zeroes the OFFSET components position
/// channels replace): the rig reads it back, and so does a fresh import.
#[test]
fn exported_text_reads_back() {
    let walk = canonical_inputs().remove(0).1;
    for (dir, name) in all_fixtures() {
        let rig = import(&fixture(dir, name)).unwrap().rig;
        let text = rig.from_canonical(&walk).to_bvh_string();
        let reparsed = motion_stylizer::bvh::Bvh::parse(&text).unwrap();
        let e = max_position_error(&walk, &rig.to_canonical(&reparsed).unwrap());
        assert!(e < 1e-6, "{name}: same rig, {e:e} cm");
        let fresh = import(&reparsed).unwrap();
        assert_eq!(fresh.rig.report().rig, rig.report().rig);
        assert!((fresh.rig.report().scale / rig.report().scale - 1.0).abs() < 1e-6, "{name}");
        let e = max_position_error(&walk, &fresh.motion);
        // A fresh rig measures its floor on this clip and takes its rest pose from it where needed.
        assert!(e < 1e-6, "{name}: fresh import, {e:e} cm");
    }
}
