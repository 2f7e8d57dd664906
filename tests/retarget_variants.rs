//! Variants of the fixtures: other worlds (Z up, facing −Z), units, channel orders, naming schemes,
//! missing and degenerate joints, hostile input.

mod support;

use glam::{DQuat, DVec3};
use motion_stylizer::bvh::{Axis, Bvh, Channel};
use motion_stylizer::skeleton::{ImportError, UserRig, import, import_bvh};
use support::*;

fn assert_same_motion(a: &motion_stylizer::Motion, b: &motion_stylizer::Motion, tol: f64, what: &str) {
    let e = max_position_error(a, b);
    assert!(e < tol, "{what}: {e:e} cm");
}

#[test]
fn z_up_and_backwards_worlds_import_to_the_same_motion() {
    let quarter_x = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2); // Y up → Z up (facing -Y)
    let half_y = DQuat::from_rotation_y(std::f64::consts::PI); // facing -Z
    let odd = DQuat::from_rotation_z(-std::f64::consts::FRAC_PI_2) * quarter_x; // Z up, facing -X
    for name in ["m21_walk", "cmu31_xia_neutral_16_000", "cmu31_rest"] {
        let bvh = fixture("foreign", name);
        let original = import(&bvh).unwrap().motion;
        for (q, up, fwd) in [(quarter_x, "+Z", "-Y"), (half_y, "+Y", "-Z"), (odd, "+Z", "-X")] {
            let variant = transform_world(&bvh, q, 1.0);
            let imp = import(&variant).unwrap();
            assert_eq!((imp.rig.report().up_axis.as_str(), imp.rig.report().forward_axis.as_str()), (up, fwd));
            assert_same_motion(&original, &imp.motion, 1e-6, &format!("{name} {up} {fwd}"));
            // And back into that world.
            let back = imp.rig.from_canonical(&imp.motion);
            assert_same_motion(&imp.motion, &imp.rig.to_canonical(&back).unwrap(), 1e-6, name);
        }
    }
}

#[test]
fn units_do_not_matter() {
    for (dir, name) in
        [("bandai", "dataset-2_walk_normal_001_f120"), ("foreign", "m21_walk"), ("foreign", "iclone100_cmu_002_04")]
    {
        let bvh = fixture(dir, name);
        let imp = import(&bvh).unwrap();
        for s in [0.01, 1.0 / 2.54] {
            let variant = transform_world(&bvh, DQuat::IDENTITY, s);
            let v = import(&variant).unwrap();
            assert!((v.rig.report().scale - imp.rig.report().scale / s).abs() < 1e-9 * v.rig.report().scale);
            assert_same_motion(&imp.motion, &v.motion, 1e-6, &format!("{name} ×{s}"));
        }
    }
}

#[test]
fn every_rotation_order_imports_to_the_same_motion() {
    let bvh = fixture("foreign", "m21_walk");
    let original = import(&bvh).unwrap().motion;
    let orders = [
        [Axis::X, Axis::Y, Axis::Z],
        [Axis::Y, Axis::Z, Axis::X],
        [Axis::Z, Axis::X, Axis::Y],
        [Axis::Y, Axis::X, Axis::Z],
    ];
    for order in orders {
        let variant = relayout(&bvh, |j| {
            let mut c: Vec<Channel> =
                j.channels.iter().copied().filter(|c| matches!(c, Channel::Position(_))).collect();
            c.extend(order.map(Channel::Rotation));
            c
        });
        let imp = import(&variant).unwrap();
        assert_same_motion(&original, &imp.motion, 1e-6, &format!("{order:?}"));
        // from_canonical writes in that order, and reads back the same.
        let back = imp.rig.from_canonical(&imp.motion);
        assert!(back.joints.iter().all(|j| j.channels.ends_with(&order.map(Channel::Rotation))));
        assert_same_motion(&imp.motion, &imp.rig.to_canonical(&back).unwrap(), 1e-6, "written back");
    }
}

/// m21's joints under Mixamo names (Spine, Spine1 → Spine1, Spine2; any `mixamorigN:` prefix) and
/// under SMPL-like generic names: the same joints match, so the motion is the same.
#[test]
fn mixamo_and_generic_names() {
    let bvh = fixture("foreign", "m21_walk");
    let original = import(&bvh).unwrap().motion;
    for prefix in ["mixamorig:", "mixamorig1:", ""] {
        let mixamo = rename(&bvh, |n| {
            let n = match n {
                "Spine" => "Spine1",
                "Spine1" => "Spine2",
                "Neck1" => "Neck",
                other => other,
            };
            Some(format!("{prefix}{n}"))
        });
        let imp = import(&mixamo).unwrap();
        assert_eq!(imp.rig.report().rig, "mixamo", "prefix {prefix:?}");
        assert_same_motion(&original, &imp.motion, 1e-9, prefix);
    }
    let smpl = rename(&bvh, |n| {
        let side = if n.starts_with("Left") {
            "left_"
        } else if n.starts_with("Right") {
            "right_"
        } else {
            ""
        };
        let base = n.trim_start_matches("Left").trim_start_matches("Right");
        let s = match base {
            "Hips" => "pelvis",
            "Spine" => "spine",
            "Spine1" => "chest",
            "Neck1" => "neck",
            "Head" => "head",
            "Shoulder" => "collar",
            "Arm" => "shoulder",
            "ForeArm" => "elbow",
            "Hand" => "wrist",
            "UpLeg" => "hip",
            "Leg" => "knee",
            "Foot" => "ankle",
            "ToeBase" => "foot",
            other => other,
        };
        Some(format!("{side}{s}"))
    });
    let imp = import(&smpl).unwrap();
    assert_eq!(imp.rig.report().rig, "smpl");
    assert_eq!(imp.rig.report().matched.len(), 21);
    assert_same_motion(&original, &imp.motion, 1e-9, "smpl names");
}

/// Bandai joints under names no table knows: the generic matcher finds them, the rest pose (all bones
/// along +X) is no use, so a clip frame becomes the base pose. Not the same motion as with the Bandai
/// table (another twist reference), but it moves like the source, and round trips stay exact.
#[test]
fn generic_rig_with_unusable_rest_pose_uses_a_clip_frame() {
    let bvh = fixture("bandai", "dataset-2_walk_normal_001_f120");
    let renamed = rename(&bvh, |n| Some(format!("J_{n}")));
    let imp = import(&renamed).unwrap();
    let report = imp.rig.report();
    assert_eq!(report.rig, "generic");
    assert!(report.base_pose.starts_with("frame "), "{}", report.base_pose);
    assert_eq!(report.up_axis, "+Y");
    for (pair, r, std) in effector_correlations(&renamed, &imp.rig, &imp.motion) {
        assert!(std < 0.01 || r > 0.99, "{pair}: {r}");
    }
    let walk = import(&bvh).unwrap().motion;
    let back = imp.rig.to_canonical(&imp.rig.from_canonical(&walk)).unwrap();
    assert_same_motion(&walk, &back, 1e-6, "canonical → generic Bandai → canonical");
}

/// Optional joints may be missing: here m21's shoulders and toes carry unknown names.
#[test]
fn optional_joints_may_be_missing() {
    let bvh = fixture("foreign", "m21_walk");
    let renamed = rename(&bvh, |n| {
        n.ends_with("Shoulder")
            .then(|| format!("{n}Blade"))
            .or_else(|| n.ends_with("ToeBase").then(|| format!("{n}Tip")))
    });
    let imp = import(&renamed).unwrap();
    assert_eq!(imp.rig.report().rig, "m21");
    assert_eq!(imp.rig.report().missing, ["Shoulder_L", "Shoulder_R", "Toes_L", "Toes_R"]);
    let r = effector_correlations(&renamed, &imp.rig, &imp.motion);
    assert!(r.iter().all(|(_, c, s)| *s < 0.01 || *c > 0.9), "{r:.3?}");
    // Unmatched canonical joints rest at identity.
    for pose in imp.motion.rotations() {
        for j in [5, 9, 16, 20] {
            assert!(pose[j].dot(DQuat::IDENTITY).abs() > 1.0 - 1e-12);
        }
    }
    // Without toes the canonical ankles stand at ankle height: toes near the floor still.
    let lows: Vec<f64> = imp.motion.global_positions().iter().map(|p| p[16].y.min(p[20].y)).collect();
    let mut sorted = lows.clone();
    sorted.sort_by(f64::total_cmp);
    assert!(sorted[sorted.len() / 20].abs() < 3.0, "toes' 5th percentile {}", sorted[sorted.len() / 20]);
}

#[test]
fn missing_required_joints_are_named() {
    let m21 = fixture("foreign", "m21_walk");
    let upper_body = drop_joints(&m21, |n| n.ends_with("UpLeg"));
    match import(&upper_body) {
        Err(ImportError::MissingJoints { missing, rig }) => {
            assert_eq!(rig, "m21");
            assert_eq!(missing, ["UpperLeg_L", "LowerLeg_L", "Foot_L", "UpperLeg_R", "LowerLeg_R", "Foot_R"]);
        }
        other => panic!("{other:?}"),
    }
    // A hand no table knows: the structure finds it (issue 15).
    let pawed = rename(&m21, |n| (n == "LeftHand").then(|| "LeftPaw".to_string()));
    let imp = import(&pawed).unwrap();
    assert_eq!(imp.rig.report().rig, "structural");
    assert!(imp.rig.report().matched.contains(&("Hand_L".to_string(), "LeftPaw".to_string())));
    // Without its left arm, neither names nor structure: the error names what is missing.
    let one_armed = drop_joints(&m21, |n| n == "LeftArm");
    let err = import(&one_armed).unwrap_err();
    match &err {
        ImportError::MissingJoints { missing, .. } => {
            assert!(missing.ends_with(&["LowerArm_L".into(), "Hand_L".into()]))
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().contains("Hand_L"), "{err}");
    // Head, Spine and Chest are not essential (issue 15): synthesised, not missing.
    let headless = drop_joints(&fixture("bandai", "dataset-2_walk_normal_001_f120"), |n| n == "Head");
    let imp = import(&headless).unwrap();
    assert_eq!(imp.rig.report().missing, ["Head"]);
    assert_eq!(imp.rig.synthesised()[0].0, "Head");
    let spineless = rename(&m21, |n| n.starts_with("Spine").then(|| format!("Back{n}")));
    assert_eq!(import(&spineless).unwrap().rig.report().missing, ["Spine", "Chest"]);
    // A BVH error passes through.
    assert!(matches!(import_bvh("HIERARCHY\nROOT"), Err(ImportError::Bvh(_))));
}

#[test]
fn degenerate_rigs_are_errors() {
    let m21 = fixture("foreign", "m21_walk");
    let mut flat = m21.clone();
    for j in &mut flat.joints {
        j.offset = DVec3::ZERO;
    }
    assert!(matches!(import(&flat), Err(ImportError::Degenerate { .. })), "{:?}", import(&flat).err());
    // The right leg where the left one is: the hips coincide all the way down.
    let mut merged = m21.clone();
    for side in ["UpLeg", "Leg", "Foot", "ToeBase"] {
        let l = merged.joint_index(&format!("Left{side}")).unwrap();
        let r = merged.joint_index(&format!("Right{side}")).unwrap();
        merged.joints[r].offset = merged.joints[l].offset;
    }
    assert!(matches!(import(&merged), Err(ImportError::Degenerate { .. })), "{:?}", import(&merged).err());
    // Hand-built values the parser would never produce: errors, not panics.
    let mut backwards = m21.clone();
    backwards.joints[1].parent = Some(5);
    assert!(matches!(import(&backwards), Err(ImportError::Degenerate { .. })));
    let mut short = m21.clone();
    short.values.pop();
    assert!(matches!(import(&short), Err(ImportError::Degenerate { .. })));
    let mut timeless = m21.clone();
    timeless.frame_time = f64::NAN;
    assert!(matches!(import(&timeless), Err(ImportError::Degenerate { .. })));
    // Absurd frame time.
    let mut slow = m21.clone();
    slow.frame_time = 1e9;
    assert!(matches!(import(&slow), Err(ImportError::TooLong { .. })));
    // Values too large for the arithmetic: an error, not a NaN motion.
    let mut huge = m21.clone();
    huge.values[1] = 1e308;
    huge.values[0] = -1e308;
    assert!(import(&huge).is_err() || import(&huge).unwrap().motion.root_positions().iter().all(|p| p.is_finite()));
}

#[test]
fn another_rigs_clip_is_refused() {
    let rig = UserRig::from_bvh(&fixture("foreign", "m21_walk")).unwrap();
    assert!(matches!(rig.to_canonical(&fixture("foreign", "cmu31_rest")), Err(ImportError::RigMismatch { .. })));
    let mut moved = fixture("foreign", "m21_walk");
    moved.joints[3].offset.x += 1.0;
    assert!(matches!(rig.to_canonical(&moved), Err(ImportError::RigMismatch { .. })));
}

/// Deterministic pseudo-random numbers in [0, 1).
fn rng(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// Random mutations of the fixtures (dropped and renamed joints, zeroed or scaled offsets, fewer
/// rotation channels, extreme values and frame times): never a panic, and whatever imports writes back
/// finite values.
#[test]
fn hostile_variants_never_panic() {
    let bases: Vec<Bvh> =
        [("foreign", "m21_walk"), ("foreign", "cmu31_rest"), ("bandai", "dataset-2_raise-up-both-hands_active_001")]
            .iter()
            .map(|(d, n)| {
                let b = fixture(d, n);
                let frames = b.frames.min(12);
                Bvh { values: b.values[..frames * b.num_channels()].to_vec(), frames, ..b }
            })
            .collect();
    let mut seed = 42;
    let (mut ok, mut err) = (0, 0);
    for it in 0..400 {
        let mut b = bases[it % bases.len()].clone();
        let n = b.joints.len();
        match it % 8 {
            0 => {
                let k = (rng(&mut seed) * n as f64) as usize;
                let name = b.joints[k].name.clone();
                b = drop_joints(&b, |x| x == name && k > 0);
            }
            1 => {
                for j in &mut b.joints {
                    if rng(&mut seed) < 0.3 {
                        j.offset *= [0.0, 1e-12, 1e6, -1.0][(rng(&mut seed) * 4.0) as usize];
                    }
                }
            }
            2 => {
                for v in &mut b.values {
                    if rng(&mut seed) < 0.1 {
                        *v = [1e300, -1e300, 1e12, 0.0, 720.0][(rng(&mut seed) * 5.0) as usize];
                    }
                }
            }
            3 => {
                let keep = (rng(&mut seed) * 3.0) as usize;
                b = relayout(&b, |j| {
                    let mut c: Vec<Channel> =
                        j.channels.iter().copied().filter(|c| matches!(c, Channel::Position(_))).collect();
                    c.extend(
                        [Channel::Rotation(Axis::Y), Channel::Rotation(Axis::X), Channel::Rotation(Axis::Z)]
                            .into_iter()
                            .take(keep),
                    );
                    c
                });
            }
            4 => b.frame_time = [1e-300, 1e-9, 1e300, 7.0][(rng(&mut seed) * 4.0) as usize],
            5 => {
                let k = (rng(&mut seed) * n as f64) as usize;
                b.joints[k].name = format!("x{}", b.joints[k].name);
            }
            6 => {
                for j in &mut b.joints {
                    j.offset = DVec3::new(rng(&mut seed) - 0.5, rng(&mut seed) - 0.5, rng(&mut seed) - 0.5);
                }
            }
            _ => {
                // Everything at one point but the head.
                for j in &mut b.joints {
                    if !j.name.contains("Head") {
                        j.offset = DVec3::ZERO;
                    }
                }
            }
        }
        match import(&b) {
            Ok(imp) => {
                ok += 1;
                let back = imp.rig.from_canonical(&imp.motion);
                assert!(back.values.iter().all(|v| v.is_finite()), "iteration {it}");
                let _ = imp.rig.to_canonical(&back);
            }
            Err(_) => err += 1,
        }
    }
    eprintln!("hostile variants: {ok} imported, {err} refused");
    assert!(ok > 50 && err > 50, "{ok} / {err}");
}
